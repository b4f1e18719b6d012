"""The command line under generated inputs: every subcommand, every input format (a small seeded budget).

The strategies and checks live in tests/fuzz_strategies.py; ``python scripts/fuzz_cli.py`` runs the
same at a large budget (docs/reliability.md). Here: a few dozen derandomized inputs per command
(about a minute in all), the harness's own checks shown to catch what they are meant to catch, and
a few inputs run as real processes to show the in-process view matches what a shell sees.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
import weakref

import fuzz_strategies as fz
import pytest
from hypothesis import HealthCheck, given, settings

# Inputs per command: the cheap commands get more, the slow ones enough to pass through their files.
BUDGET = {
    "chandler": 3,
    "modes": 2,
    "precession": 6,
    "polar-motion": 2,
    "excitation": 3,
    "forecast": 3,
    "inertia": 15,
    "free": 15,
    "top": 15,
    "run": 6,
    "sweep": 4,
    "invert": 1,
    "example": 10,
    "bench": 4,
}


def _fuzz(command):
    @settings(
        max_examples=BUDGET[command],
        derandomize=True,
        database=None,
        deadline=None,
        suppress_health_check=list(HealthCheck),
    )
    @given(fz.case_strategy(command, real_bench=False))
    def check(case):
        outcome = fz.run_case(case, os.environ.get("PYTEST_FUZZ_TMP"))
        assert not outcome.problems, case.show() + "\n" + "\n".join(outcome.problems) + "\n" + outcome.stderr[-1000:]

    return check


@pytest.mark.slow
@pytest.mark.parametrize("command", fz.COMMANDS)
def test_generated_inputs_keep_the_contract(command, tmp_path, monkeypatch):
    monkeypatch.setenv("PYTEST_FUZZ_TMP", str(tmp_path))
    _fuzz(command)()


# -- the harness catches what it is meant to catch ---------------------------------------------


def _patched_run(monkeypatch, body):
    """Make ``wobble free`` run ``body(args)`` instead of its own code."""
    import wobble.cli.free

    monkeypatch.setattr(wobble.cli.free, "run", body)


FREE = ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1"]


def test_harness_reports_a_crash(monkeypatch, tmp_path):
    _patched_run(monkeypatch, lambda args: 1 / 0)
    outcome = fz.run_case(fz.Case("free", FREE), tmp_path)
    assert any(p.startswith("crash: ZeroDivisionError") for p in outcome.problems), outcome.problems


def test_harness_reports_a_hang(monkeypatch, tmp_path):
    _patched_run(monkeypatch, lambda args: time.sleep(30))
    start = time.monotonic()
    outcome = fz.run_case(fz.Case("free", FREE), tmp_path, bound=0.5)
    assert time.monotonic() - start < 10
    assert outcome.problems == ["hang: still running after 0.5 s"]


def test_harness_reports_a_hang_whose_first_alarm_was_swallowed(monkeypatch, tmp_path):
    """Python swallows an exception raised in a weakref or garbage-collector callback; in CI the watchdog's
    Hang once landed in one and the run slept its full 30 s. The watchdog repeats its alarm, and a Hang
    reported as unraisable is not passed on to pytest (which would fail the test at teardown)."""

    def swallowed(args):
        class Thing:
            pass

        def callback(_):
            raise fz.Hang()

        thing = Thing()
        ref = weakref.ref(thing, callback)
        del thing  # the callback's Hang goes to sys.unraisablehook, as the collector's did
        assert ref() is None
        try:
            time.sleep(30)
        except fz.Hang:
            pass  # the first alarm taken and lost, as inside a callback
        time.sleep(30)

    _patched_run(monkeypatch, swallowed)
    start = time.monotonic()
    outcome = fz.run_case(fz.Case("free", FREE), tmp_path, bound=0.5)
    assert time.monotonic() - start < 10
    assert outcome.problems == ["hang: still running after 0.5 s"]


def test_harness_reports_lost_changed_partial_and_temporary_files(monkeypatch, tmp_path):
    def vandal(args):
        os.remove("prev.nc")
        with open("keep.nc", "wb") as fh:
            fh.write(b"changed")
        with open("out.nc", "wb") as fh:
            fh.write(b"CDF half a file")
        with open(".out.nc.1.abcdefgh.tmp", "wb") as fh:
            fh.write(b"x")
        return 0

    _patched_run(monkeypatch, vandal)
    case = fz.Case("free", [*FREE, "-o", "out.nc"], {"prev.nc": fz.PREVIOUS, "keep.nc": fz.PREVIOUS})
    problems = fz.run_case(case, tmp_path).problems
    assert "lost file: prev.nc was removed" in problems
    assert "unexpected file written: keep.nc" in problems
    assert any(p.startswith("invalid output out.nc: netCDF does not reopen") for p in problems)
    assert "temporary file left: .out.nc.1.abcdefgh.tmp" in problems


def test_harness_reports_nan_in_the_output_of_a_motion_that_succeeded(monkeypatch, tmp_path):
    """A silent NaN (as the compiled heavy-top phase once gave past 2^996 s) is a finding for the
    motion commands; a finite file passes."""
    import numpy as np
    import xarray as xr

    def writer(values):
        def run(args):
            xr.Dataset({"omega": ("time", np.asarray(values)), "note": ((), "text")}).to_netcdf("out.nc")
            return 0

        return run

    case = fz.Case("free", [*FREE, "-o", "out.nc"])
    _patched_run(monkeypatch, writer([1.0, float("nan")]))
    assert "invalid output out.nc: NaN in omega of a run that succeeded" in fz.run_case(case, tmp_path).problems
    _patched_run(monkeypatch, writer([1.0, 2.0]))
    assert fz.run_case(case, tmp_path).problems == []


def test_harness_reports_a_multi_line_failure_and_bad_json(monkeypatch, tmp_path):
    def noisy(args):
        print("{not json")
        print("first line\nsecond line", file=sys.stderr)
        return 2 if not args.json else 0

    _patched_run(monkeypatch, noisy)
    assert "failure printed 2 lines on stderr (one expected)" in fz.run_case(fz.Case("free", FREE), tmp_path).problems
    problems = fz.run_case(fz.Case("free", [*FREE, "--json"]), tmp_path).problems
    assert any(p.startswith("--json output is not one JSON document") for p in problems)


def test_a_valid_run_passes_every_check(tmp_path):
    case = fz.Case(
        "free",
        [*FREE, "-o", "sub/out.nc", "--plot", "prevfig.png", "--overwrite", "--json"],
        {"sub": None, "prevfig.png": fz.PREVIOUS},
    )
    outcome = fz.run_case(case, tmp_path)
    assert outcome.status == 0 and outcome.problems == [] and outcome.warnings == []


# -- the in-process view is what a shell sees ---------------------------------------------------

REAL = [
    (["free", "--inertia", "1", "2", "3", "--omega", "1e300", "0.1", "1", "--json"], {}),  # the overflow, now refused
    (["top", "--bogus", "--I1", "1"], {}),  # an argparse usage error
    (["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "-o", "prev.nc"], {"prev.nc": fz.PREVIOUS}),
]


@pytest.mark.slow
def test_in_process_runs_match_real_processes(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    for i, (argv, files) in enumerate(REAL):
        inside = fz.run_case(fz.Case(argv[0], argv, dict(files)), tmp_path)
        folder = tmp_path / f"real{i}"
        folder.mkdir()
        for name, data in files.items():
            (folder / name).write_bytes(data)
        real = subprocess.run(
            [sys.executable, "-m", "wobble", *argv], cwd=folder, capture_output=True, text=True, env=env, timeout=120
        )
        assert inside.problems == [], (argv, inside.problems)
        assert real.returncode == inside.status, (argv, real.stderr)
        assert "Traceback" not in real.stderr
        if real.returncode == 2:
            assert real.stderr == inside.stderr, argv
        for name, data in files.items():
            assert (folder / name).read_bytes() == data


def test_drawing_files_leaves_the_shared_edge_values_as_they_were():
    """A list or table drawn into a file's data and mutated by a later step of the same draw once
    changed the shared constant: later inputs then differed from their replays and Hypothesis
    stopped the fuzzer ("the second run stopped drawing earlier than the first run")."""
    import copy

    before = copy.deepcopy((fz.TOML_EDGES, fz._WORK_EDGES))

    @settings(max_examples=400, database=None, derandomize=True, suppress_health_check=list(HealthCheck))
    @given(fz.mutated_toml("a = 1\n[b]\nsamples = 2\n", "edge"))
    def draw(_text):
        pass

    draw()
    assert (fz.TOML_EDGES, fz._WORK_EDGES) == before


def test_a_chunk_over_its_memory_limit_reports_a_memory_error(tmp_path):
    """The fuzzer caps each chunk's address space (scripts/fuzz_cli.py --memory): an input that asks for
    more fails with a MemoryError the harness reports, instead of taking the machine (its time bound cannot
    interrupt one long compiled call). Run in a child process: the cap is for the whole process."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    code = f"""
import sys
sys.path[:0] = [{os.path.join(root, "scripts")!r}, {os.path.join(root, "tests")!r}]
import numpy as np
import fuzz_cli, fuzz_strategies as fz
import wobble.cli.free
fuzz_cli.limit_memory(2.0)
wobble.cli.free.run = lambda args: int(np.ones(2**30).sum())  # 8 GiB of float64, over the 2 GiB cap
outcome = fz.run_case(fz.Case("free", {FREE!r}), {str(tmp_path)!r})
print(outcome.problems)
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "crash: MemoryError" in proc.stdout, proc.stdout
