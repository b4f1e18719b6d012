"""Fuzzing the ``wobble`` command line: inputs for every subcommand and file format, and the checks.

Shared by the test suite (``tests/test_fuzz_cli.py``, a small seeded budget) and
``scripts/fuzz_cli.py`` (the same strategies at a large budget). A generated input is a
:class:`Case`: an argument list for ``wobble`` plus the files to lay out in an empty folder
first (input files, and sometimes an existing file at an output path). :func:`run_case`
runs it in-process through :func:`wobble.cli.main` with a time limit and returns every way
it broke the command line's contract (DEVELOPERS.md, "Errors"):

* exit status 0 or 2 (argparse's usage errors are 2; 130 is only for interrupts, and the
  fuzzer sends none), never an exception escaping ``main``;
* no traceback on stderr, and a failure is exactly one line there;
* a run ends within the command's time bound (:data:`BOUNDS`);
* (apart) Python warnings it printed, which are noise for a person but no broken promise;
* ``--json`` on success prints one strict JSON document;
* every file the run left is a complete, valid output named on the command line (netCDF
  that reopens, without NaN from the motion commands, :data:`NAN_FREE`; Zarr that reopens,
  a PNG with its end chunk, a PDF with its trailer, SVG that parses, a copy equal to the
  shipped file, a non-empty report);
* no temporary file (``.NAME.*.tmp``, ``.NAME.*.old``) is left in the folder;
* no file that was there before is removed, and none is changed unless it is an output
  named on the command line, ``--overwrite`` was given and the exit status is 0.

Numbers, units, angles and dates are drawn from valid values, edges (0, negatives,
1e-300, 1e300, inf, nan, unit strings right and wrong) and malformed text; files are
mutations of the shipped examples (``data/``, the IERS files of astropy-iers-data) as
well as random text. Sizes are capped (samples, members, walkers, spans) so every valid
run stays within its bound on a busy two-core machine.
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import math
import os
import shlex
import shutil
import signal
import sys
import tempfile
import threading
import time
import tomllib
import traceback
import warnings
from dataclasses import dataclass, field
from functools import cache, lru_cache
from pathlib import Path

from hypothesis import strategies as st

from wobble.cli import SUBCOMMANDS

__all__ = ["COMMANDS", "BOUNDS", "Case", "Outcome", "run_case", "case_strategy", "signature", "minimize"]

# Every subcommand, as typed: a new one fails the suite until it has a strategy (_BUILDERS).
COMMANDS = tuple(name.replace("_", "-") for name in SUBCOMMANDS)

#: Seconds one generated input may take (in-process, on a busy two-core machine); beyond it is a hang.
#: Generous: the slowest valid inputs take a few seconds on a quiet machine, ten times that on a loaded one.
BOUNDS = {
    "chandler": 30,
    "modes": 45,
    "precession": 30,
    "polar-motion": 60,
    "excitation": 60,
    "forecast": 60,
    "inertia": 30,
    "free": 30,
    "top": 30,
    "run": 60,
    "sweep": 60,
    "invert": 60,
    "example": 30,
    "bench": 180,
}

#: The contents planted at an output path before a run (a previous result the run must not lose).
PREVIOUS = b"previous result: must survive unless --overwrite and success\n"


# --------------------------------------------------------------------------------------------
# Cases and their checks
# --------------------------------------------------------------------------------------------


@dataclass
class Case:
    """One generated input: ``wobble ARGV`` run in a folder holding ``files`` (None = a folder)."""

    command: str
    argv: list[str]
    files: dict[str, bytes | None] = field(default_factory=dict)

    def show(self) -> str:
        lines = [shlex.join(["wobble", *self.argv])]
        for name, data in self.files.items():
            if data is None:
                lines.append(f"  folder {name}/")
            elif data == PREVIOUS:
                lines.append(f"  {name}: an existing file (a previous result)")
            else:
                text = data[:600].decode("utf-8", "backslashreplace")
                more = f" ... ({len(data)} bytes)" if len(data) > 600 else ""
                lines.append(f"  {name}:\n" + "\n".join("    | " + t for t in text.splitlines()) + more)
        return "\n".join(lines)


@dataclass
class Outcome:
    """What a run did: exit status, output, time, broken promises (``problems``) and warnings it printed."""

    status: int | None
    stdout: str
    stderr: str
    seconds: float
    problems: list[str]
    warnings: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems


class Hang(BaseException):
    """Raised by the watchdog when a run exceeds its bound (a BaseException: nothing in wobble swallows it)."""


_ARMED = threading.Event()  # set while a run is watched: an alarm after its end is ignored


def _alarm(signum, frame):
    if _ARMED.is_set():
        raise Hang()


def _ignore_swallowed_hang(previous):
    """A ``sys.unraisablehook`` that drops a Hang raised inside a weakref or garbage-collection callback
    (where Python swallows exceptions; the watchdog sends another alarm) and passes anything else on."""

    def hook(unraisable):
        if not isinstance(unraisable.exc_value, Hang):
            previous(unraisable)

    return hook


class _Watchdog:
    """SIGALRM to the main thread after ``bound`` seconds, by ``pthread_kill``, then again every second
    until cancelled.

    A process-wide timer (``setitimer``) may have its signal taken by another thread of the process (an
    idle pool thread), and then the main thread's sleep is not interrupted: a run meant to stop at 0.5 s
    went its full 30 s once in CI, and the late handler raised Hang in pytest's teardown. Sent to the
    main thread, the signal interrupts whatever it waits in. Once more in CI (2026-11-30) the handler ran
    inside a WeakKeyDictionary callback of the garbage collector, which swallowed the Hang, and the sleep
    went on: hence the repeats, and the unraisable hook above.
    """

    def __init__(self, bound: float):
        self._stop = threading.Event()
        _ARMED.set()
        self._thread = threading.Thread(target=self._run, args=(bound,), daemon=True)
        self._thread.start()

    def _run(self, bound: float) -> None:
        wait = bound
        while not self._stop.wait(wait):
            signal.pthread_kill(threading.main_thread().ident, signal.SIGALRM)
            wait = 1.0

    def cancel(self) -> None:
        _ARMED.clear()  # first: an alarm already on its way finds the handler disarmed
        self._stop.set()
        self._thread.join()


def output_roles(case: Case) -> dict[str, str]:
    """Paths the command line names as outputs, with what they must hold when written."""
    roles: dict[str, str] = {}
    argv = case.argv
    for i, token in enumerate(argv):
        for flag, role in (("-o", "output"), ("--output", "output"), ("--plot", "plot")):
            value = None
            if token == flag and i + 1 < len(argv):
                value = argv[i + 1]
            elif token.startswith(flag + "=") and flag.startswith("--"):
                value = token.split("=", 1)[1]
            if value:
                roles[os.path.normpath(value)] = role
    if case.command == "example":
        positional = [t for t in argv[1:] if not t.startswith("-")]
        if len(positional) >= 2:
            roles[os.path.normpath(positional[1])] = "copy"
    return roles


def _snapshot(folder: Path) -> dict[str, bytes | None]:
    out: dict[str, bytes | None] = {}
    for root, dirs, files in os.walk(folder):
        for d in dirs:
            out[os.path.relpath(os.path.join(root, d), folder)] = None
        for f in files:
            p = os.path.join(root, f)
            try:
                out[os.path.relpath(p, folder)] = Path(p).read_bytes()
            except OSError:
                out[os.path.relpath(p, folder)] = b"<unreadable>"
    return out


@lru_cache(maxsize=1)
def _shipped_contents() -> set[bytes]:
    from importlib import resources

    root = resources.files("wobble._data")
    found = set()
    for kind in root.iterdir():
        if kind.is_dir():
            for entry in kind.iterdir():
                if entry.is_file():
                    found.add(entry.read_bytes())
    return found


#: Commands whose netCDF output holds no NaN when they succeed: a motion is finite or refused (a
#: sweep marks invalid members with NaN, the polar-motion files mark what a span cannot measure).
NAN_FREE = ("top", "free", "run")


def _nan_variables(ds) -> list[str]:
    """The floating-point variables of an open netCDF4 Dataset that hold a NaN (masks off)."""
    import numpy as np

    found = []
    for name, var in ds.variables.items():
        if getattr(var.dtype, "kind", "") == "f":  # string variables have the type str
            var.set_auto_mask(False)
            if np.isnan(var[...]).any():
                found.append(name)
    return found


def _valid_file(path: Path, role: str, command: str) -> str | None:
    """None if ``path`` is a complete output of its role, else what is wrong."""
    if role == "copy" or (command == "example" and path.is_file()):
        return None if path.read_bytes() in _shipped_contents() else "not a copy of a shipped file"
    if role == "plot" and command == "bench":
        if not path.is_dir():
            return "bench --plot should be a folder"
        bad = [p.name for p in path.iterdir() if _valid_file(p, "plot", "chandler")]
        return f"invalid figures {bad}" if bad else None
    if path.is_dir():
        if not str(path).endswith(".zarr"):
            return "a folder where a file was expected"
        try:
            import xarray as xr

            with xr.open_zarr(path, decode_times=False) as ds:
                ds.load()
        except Exception as exc:  # any failure to reopen is the finding
            return f"Zarr store does not reopen: {exc!r}"
        return None
    data = path.read_bytes()
    if role == "output" and command == "bench":
        return None if data.strip() else "empty report"
    if role == "output":
        try:
            import netCDF4

            with netCDF4.Dataset(path) as ds:
                nan = _nan_variables(ds) if command in NAN_FREE else []
        except Exception as exc:
            return f"netCDF does not reopen: {exc!r}"
        return f"NaN in {', '.join(nan)} of a run that succeeded" if nan else None
    # Figures: by their content.
    if data.startswith(b"\x89PNG\r\n\x1a\n"):
        return None if data[-12:].endswith(b"IEND\xaeB`\x82") else "truncated PNG"
    if data.startswith(b"%PDF"):
        return None if b"%%EOF" in data[-1024:] else "truncated PDF"
    if b"<svg" in data[:2000]:
        import xml.etree.ElementTree as ET

        try:
            ET.fromstring(data)
        except ET.ParseError as exc:
            return f"SVG does not parse: {exc}"
        return None
    return "neither PNG, PDF nor SVG"


def _strict_json(text: str) -> None:
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    json.loads(text, parse_constant=refuse)


def lay_out(case: Case, folder: Path) -> None:
    """Write ``case.files`` into ``folder`` (a None entry is a folder)."""
    for name, data in case.files.items():
        target = folder / name
        if data is None:
            target.mkdir(parents=True, exist_ok=True)
        else:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)


def run_case(
    case: Case, base: str | os.PathLike | None = None, bound: float | None = None, keep: bool = False
) -> Outcome:
    """Run ``case`` in-process in a fresh folder under ``base``; return the outcome and every problem."""
    from wobble.cli import main

    bound = BOUNDS[case.command] if bound is None else bound
    folder = Path(tempfile.mkdtemp(prefix="fuzz-", dir=base))
    lay_out(case, folder)
    before = _snapshot(folder)
    out, err = io.StringIO(), io.StringIO()
    problems: list[str] = []
    status = None
    cwd = os.getcwd()
    previous_handler = signal.signal(signal.SIGALRM, _alarm)
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _ignore_swallowed_hang(previous_hook)
    start = time.perf_counter()
    try:
        os.chdir(folder)
        with (
            contextlib.redirect_stdout(out),
            contextlib.redirect_stderr(err),
            warnings.catch_warnings(record=True) as caught,
        ):
            warnings.simplefilter("always")
            watchdog = _Watchdog(bound)
            try:
                status = main(list(case.argv))
            except SystemExit as exc:  # argparse: --help (0), usage errors (2)
                status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            except Hang:
                problems.append(f"hang: still running after {bound} s")
            except KeyboardInterrupt:
                raise
            except BaseException as exc:  # an exception escaping main is the finding
                tb = traceback.extract_tb(exc.__traceback__)
                where = next(
                    (
                        f"{Path(f.filename).name}:{f.lineno} {f.name}"
                        for f in reversed(tb)
                        if "/wobble/" in f.filename or "/benchmarks/" in f.filename
                    ),
                    "?",
                )
                problems.append(f"crash: {type(exc).__name__} at {where}: {str(exc)[:200]}")
            finally:
                watchdog.cancel()
    finally:
        signal.signal(signal.SIGALRM, previous_handler)
        sys.unraisablehook = previous_hook
        os.chdir(cwd)
    seconds = time.perf_counter() - start
    stdout, stderr = out.getvalue(), err.getvalue()
    # Python warnings are noise on stderr, not a broken promise: reported apart (the script lists them).
    noise = [
        f"warning: {w.category.__name__} at {Path(w.filename).name}:{w.lineno}: {str(w.message)[:160]}" for w in caught
    ]
    if status is not None and status not in (0, 2):
        problems.append(f"exit status {status}")
    if "Traceback" in stderr:
        # The exception's own line (the last one of the traceback) says what went wrong.
        tail = stderr[stderr.index("Traceback") :].strip().splitlines()
        problems.append(f"traceback on stderr: {tail[-1][:160] if tail else ''}")
    if status == 2:
        lines = [line for line in stderr.splitlines() if line.strip()]
        if len(lines) != 1 and case.command != "bench":
            problems.append(f"failure printed {len(lines)} lines on stderr (one expected)")
        if lines and "error" not in lines[-1]:
            problems.append(f"failure's last stderr line is not an error: {lines[-1][:120]!r}")
    options = case.argv[: case.argv.index("--")] if "--" in case.argv else case.argv  # after "--", all positional
    if status == 0 and "--json" in options and "--help" not in options and "-h" not in options:
        try:
            _strict_json(stdout)
        except ValueError as exc:
            problems.append(f"--json output is not one JSON document: {exc}")
    problems += _file_problems(case, folder, before, status)
    if not keep:
        shutil.rmtree(folder, ignore_errors=True)
    return Outcome(status, stdout, stderr, seconds, problems, noise)


def _file_problems(case: Case, folder: Path, before: dict, status) -> list[str]:
    after = _snapshot(folder)
    roles = output_roles(case)
    overwrite = "--overwrite" in (case.argv[: case.argv.index("--")] if "--" in case.argv else case.argv)
    problems = []
    for name in before:
        if name not in after:
            problems.append(f"lost file: {name} was removed")
    for name, data in after.items():
        base = os.path.basename(name)
        if base.startswith(".") and (base.endswith(".tmp") or base.endswith(".old")):
            problems.append(f"temporary file left: {name}")
            continue
        if any(
            part.startswith(".") and (part.endswith(".tmp") or part.endswith(".old")) for part in Path(name).parts[:-1]
        ):
            continue
        old = before.get(name, "absent")
        if old == data:
            continue
        if name in before and data is None:  # a folder that existed: its content is checked entry by entry
            continue
        role = roles.get(name) or next((r for p, r in roles.items() if name.startswith(p + os.sep)), None)
        if role is None and case.command == "example":
            role = "copy"
        if role is None:
            if any(name.startswith(p + os.sep) for p in after if after[p] is None and p.endswith(".zarr")):
                continue
            problems.append(f"unexpected file written: {name}")
            continue
        if any(name.startswith(p + os.sep) for p in roles):  # inside a Zarr store or a plot folder
            continue
        if name in before:
            if not overwrite:
                problems.append(f"existing file changed without --overwrite: {name}")
            elif status != 0:
                problems.append(f"existing file changed by a failed run (exit {status}): {name}")
        elif status != 0 and old == "absent" and data is not None and not str(name).endswith(".zarr"):
            pass  # a complete output before a later failure is allowed; its validity is checked below
        why = _valid_file(folder / name, role, case.command)
        if why:
            problems.append(f"invalid output {name}: {why}")
    return problems


def signature(problem: str) -> str:
    """A failure's kind and place, without the values: distinct signatures are distinct bugs."""
    head = problem.split(": ", 1)[0]
    if head == "crash":
        return problem.split(": ", 2)[1] if problem.count(": ") >= 2 else problem
    if head in ("warning",):
        return problem.rsplit(": ", 1)[0]
    return (
        problem.split(":", 1)[0] + ": " + problem.split(":", 1)[-1].split("(")[0].strip()[:80]
        if ":" in problem
        else problem
    )


def minimize(case: Case, problem_signature: str, base=None, trials: int = 60) -> Case:
    """Drop arguments (an option with its values) while the failure with ``problem_signature`` persists.

    At most ``trials`` reruns; a hang is reported as generated (each rerun would take its whole bound).
    """
    if problem_signature.startswith("hang"):
        return case
    budget = [trials]

    def fails(c: Case) -> bool:
        if budget[0] <= 0:
            return False
        budget[0] -= 1
        outcome = run_case(c, base)
        return any(signature(p) == problem_signature for p in outcome.problems + outcome.warnings)

    argv = list(case.argv)
    i = 1
    while i < len(argv):
        for width in (2, 1, 3, 4):
            trial = argv[:i] + argv[i + width :]
            if i + width <= len(argv) and fails(Case(case.command, trial, case.files)):
                argv = trial
                break
        else:
            i += 1
    files = dict(case.files)
    for name in list(files):
        if name not in " ".join(argv):
            trial = {k: v for k, v in files.items() if k != name}
            if fails(Case(case.command, argv, trial)):
                files = trial
    return Case(case.command, argv, files)


# --------------------------------------------------------------------------------------------
# Values
# --------------------------------------------------------------------------------------------

EDGE_NUMBERS = [
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "0.5",
    "1e-300",
    "-1e-300",
    "1e300",
    "-1e300",
    "1.7e308",
    "5e-324",
    "inf",
    "-inf",
    "nan",
    "1e-12",
    "1e12",
    "3",
]
MALFORMED = ["", " ", "abc", "1,5", "1..2", "1e", "0x10", "None", "[1]", "1 2", "--", "-", "é", "1/0", "１"]


def _float_text():
    return st.floats(allow_nan=True, allow_infinity=True, width=64).map(repr)


def numbers():
    """Text for a number: edges, random floats and integers, malformed text."""
    return st.one_of(
        st.sampled_from(EDGE_NUMBERS),
        _float_text(),
        st.integers(-1000, 10**6).map(str),
        st.sampled_from(MALFORMED),
        st.text(max_size=6),
    )


def positive_numbers():
    """Ordinary positive values."""
    return st.floats(0.01, 100).map(lambda x: f"{x:.6g}")


#: Units per kind: the first three are right, the rest wrong (or odd) for that kind.
UNITS = {
    "inertia": ["kg m2", "g cm2", "kg m^2", "kg", "m", "s", "deg", "foo", "kg m2 s-1", "Msun au2"],
    "rate": ["rad/s", "deg/s", "deg/d", "1/s", "Hz", "rad", "m/s", "s", "cycle/s", "rad s-1"],
    "time": ["s", "d", "min", "yr", "h", "m", "kg", "rad", "day", "Gyr"],
    "energy": ["J", "N m", "erg", "kg m2 s-2", "W", "m", "kg", "deg", "eV", "J s"],
    "angle": ["deg", "rad", "arcsec", "degree", "m", "s", "turn", "mas", "kg", "hourangle"],
    "mass": ["kg", "g", "Msun", "lb", "m", "s", "u", "t", "Mearth", "kg m2"],
    "length": ["m", "cm", "km", "au", "pc", "kg", "s", "deg", "mm", "lyr"],
}
#: How wild a case's values are: "valid" (ordinary values, right units), "edge" (plus 0, negatives,
#: 1e-300, 1e300, inf, nan), "wild" (plus wrong units and malformed text). Drawn once per case.
MODES = ("valid", "valid", "edge", "edge", "wild")


def quantities(kind: str, typical=None, mode: str = "wild"):
    """Text for a quantity of ``kind``: a bare number (the default unit), or a number with a unit."""
    plain = typical if typical is not None else positive_numbers()
    right = st.tuples(plain, st.sampled_from(UNITS[kind][:3])).map(" ".join)
    if mode == "valid":
        return st.one_of(plain, plain, right)
    edge = st.sampled_from(EDGE_NUMBERS)
    if mode == "edge":
        return st.one_of(plain, right, edge, st.tuples(edge, st.sampled_from(UNITS[kind][:3])).map(" ".join))
    wrong = st.tuples(st.one_of(plain, numbers()), st.sampled_from(UNITS[kind])).map(" ".join)
    return st.one_of(plain, right, edge, wrong, numbers())


def angles(mode: str = "wild"):
    typical = st.floats(0, 180).map(lambda x: f"{x:.4g}")
    if mode == "valid":
        return st.one_of(
            st.sampled_from(["30", "30 deg", "1 rad", "60", "90", "0.5 rad"]), quantities("angle", typical, mode)
        )
    return st.one_of(
        st.sampled_from(
            [
                "30",
                "30 deg",
                "1 rad",
                "0",
                "180",
                "-30",
                "1e-6 rad",
                "400",
                "nan",
                "30 m",
                "90",
                "179.999",
                "0.5 rad",
                "1 arcsec",
                "pi",
                "30 degree",
                "inf deg",
                "1e-300",
                "1e300 deg",
                "-0",
            ]
        ),
        quantities("angle", typical, mode),
    )


def dates(mode: str = "wild"):
    ordinary = st.one_of(
        st.integers(1963, 2024).map(str),
        st.tuples(st.integers(1963, 2024), st.integers(1, 12), st.integers(1, 28)).map(
            lambda t: "{:04d}-{:02d}-{:02d}".format(*t)
        ),
        st.tuples(st.integers(1963, 2024), st.integers(1, 12)).map(lambda t: "{:04d}-{:02d}".format(*t)),
        st.floats(1963, 2024).map(lambda x: f"{x:.2f}"),
    )
    if mode == "valid":
        return ordinary
    return st.one_of(
        ordinary,
        st.sampled_from(
            [
                "2015-01-01",
                "2015-06",
                "2015",
                "2015.5",
                "1962-01-01",
                "1900",
                "2100-01-01",
                "2015-13-01",
                "2015-02-30",
                "0",
                "-1",
                "1e300",
                "nan",
                "inf",
                "today",
                "",
                "2015-01-01T12:00",
                "99999",
                "2019-01-01",
                "2020-06-01",
                "1980",
                "2010",
                "2016-01-01",
                "2021-01-01",
                "-4713",
                "10000-01-01",
            ]
        ),
        st.text(max_size=10),
    )


def whole_numbers(low: int, high: int, mode: str = "wild", *, huge_valid: bool = True):
    """Text for an integer option: mostly in [low, high], sometimes negative, huge or not an integer.

    ``huge_valid=False`` leaves out 10^13 where it is a valid request for unbounded work (a sweep
    of 10^13 members runs for a year, as asked): only values the command must refuse stay."""
    if mode == "valid":
        return st.integers(low, high).map(str)
    odd = ["0", "-1", "-5", "1e3", "2.5", "abc", "", "99999999999999999999"]
    return st.one_of(
        st.integers(low, high).map(str),
        st.integers(low, high).map(str),
        st.sampled_from(odd + (["10000000000000"] if huge_valid else [])),
    )


# --------------------------------------------------------------------------------------------
# Files: TOML, CSV, netCDF, EOP, and their mutations
# --------------------------------------------------------------------------------------------


def _data_root():
    from importlib import resources

    return resources.files("wobble._data")


@cache
def shipped_text(kind: str, name: str) -> str:
    return (_data_root() / kind / name).read_text(encoding="utf-8")


@cache
def shipped_names(kind: str) -> tuple[str, ...]:
    return tuple(
        sorted(
            e.name
            for e in (_data_root() / kind).iterdir()
            if e.is_file() and not e.name.startswith(("_", ".")) and not e.name.endswith(".py")
        )
    )


def _toml_key(key: str) -> str:
    return key if key and all(c.isalnum() or c in "-_" for c in key) else json.dumps(key)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return json.dumps(str(v))


def dump_toml(data: dict) -> str:
    """TOML text for a mapping: every top-level key on one line (tables inline)."""
    return "".join(f"{_toml_key(k)} = {_toml_value(v)}\n" for k, v in data.items())


TOML_EDGES = [
    0,
    -1,
    1,
    2,
    3,
    10**30,
    -(10**30),
    0.0,
    -0.0,
    1e-300,
    1e300,
    -1e300,
    float("inf"),
    float("-inf"),
    float("nan"),
    0.5,
    True,
    False,
    "",
    "x",
    "kg",
    "deg",
    "1 d",
    "earth",
    "mars",
    "nan",
    [],
    [1, 2],
    [0.0, 0.0, 0.0],
    [1e300, 1.0, 1.0],
    ["a"],
    {},
    {"value": 1.0},
    {"value": 1.0, "unit": "kg"},
    2**63,
    1e-12,
    100,
]


#: Keys whose value sets how much work a run does (time spans, sample and member counts, grid sizes).
_WORK_KEYS = {
    "start",
    "stop",
    "step",
    "samples",
    "values",
    "members",
    "num",
    "steps",
    "walkers",
    "burn",
    "prior_draws",
    "ensembles",
    "chunk_size",
    "thin",
}
_WORK_EDGES = [
    0,
    -1,
    1,
    2,
    0.0,
    -0.0,
    0.5,
    float("nan"),
    float("inf"),
    float("-inf"),
    "",
    "x",
    "kg",
    True,
    [],
    {},
    10**30,
    -(10**30),
]


def _fresh(draw, values: list):
    """One of ``values``, copied: a list or table put into a file's data and then mutated by a
    later step must not change the shared constant (it did: later draws then differed from
    their replays, and Hypothesis stopped the run, "the second run stopped drawing earlier")."""
    return copy.deepcopy(draw(st.sampled_from(values)))


def _paths(data, prefix=()):
    """Every (container, key, path) in a nested TOML mapping."""
    if isinstance(data, dict):
        items = data.items()
    elif isinstance(data, list):
        items = enumerate(data)
    else:
        return
    for k, v in items:
        yield data, k, prefix + (k,)
        yield from _paths(v, prefix + (k,))


@st.composite
def mutated_toml(draw, base_text: str, mode: str = "wild"):
    """A shipped TOML file with 0-3 structural mutations, or (wild) a textual one.

    ``mode`` "valid" only scales numbers by modest factors; "edge" also puts edge values in,
    deletes keys and adds unknown ones; "wild" also breaks units and the text itself.
    """
    data = tomllib.loads(base_text)
    if mode == "wild" and draw(st.integers(0, 5)) == 0:
        return draw(mutated_text(base_text)).encode("utf-8", "surrogatepass")
    ops = {
        "valid": ["number"],
        "edge": ["edge", "number", "delete", "unknown"],
        "wild": ["edge", "edge", "number", "delete", "unknown", "unit"],
    }[mode]
    factors = [0.5, 0.9, 1.1, 2] if mode == "valid" else [-1, 0, 1e-3, 0.5, 2, 1e3, 1e100]
    for _ in range(draw(st.integers(0, 3))):
        places = list(_paths(data))
        if not places:
            break
        container, key, _path = places[draw(st.integers(0, len(places) - 1))]
        op = draw(st.sampled_from(ops))
        if key in _WORK_KEYS:  # keep runs short: values that refuse or shorten, never lengthen
            if op in ("edge", "number"):
                container[key] = _fresh(draw, _WORK_EDGES)
                continue
        if op == "delete" and isinstance(container, dict):
            del container[key]
        elif op == "unknown" and isinstance(container, dict):
            container[draw(st.sampled_from(["bogus", "Value", "unit ", "extra"]))] = _fresh(draw, TOML_EDGES)
        elif op == "unit" and isinstance(container, dict):
            container["unit"] = draw(st.sampled_from(sum(UNITS.values(), []) + ["", "1", "???"]))
        elif op == "number":
            old = container[key]
            if isinstance(old, (int, float)) and not isinstance(old, bool):
                factor = draw(st.sampled_from(factors))
                container[key] = (
                    type(old)(old * factor)
                    if isinstance(old, float)
                    else int(old * factor)
                    if abs(factor) < 1e20
                    else float(old * factor)
                )
            elif mode != "valid":
                container[key] = _fresh(draw, TOML_EDGES)
        else:
            container[key] = _fresh(draw, TOML_EDGES)
    return dump_toml(data).encode("utf-8")


@st.composite
def mutated_text(draw, text: str):
    """``text`` cut, with a line dropped, doubled or garbled, bytes inserted; or random text."""
    lines = text.splitlines(keepends=True)
    op = draw(st.sampled_from(["truncate", "drop", "double", "garble", "insert", "random", "empty"]))
    if op == "truncate":
        return text[: draw(st.integers(0, max(0, len(text) - 1)))]
    if op == "empty":
        return ""
    if op == "random":
        return draw(st.text(max_size=200))
    if not lines:
        return text
    i = draw(st.integers(0, len(lines) - 1))
    if op == "drop":
        del lines[i]
    elif op == "double":
        lines.insert(i, lines[i])
    elif op == "garble":
        line = lines[i]
        j = draw(st.integers(0, max(0, len(line) - 1)))
        lines[i] = line[:j] + draw(st.text(min_size=1, max_size=5)) + line[j + 1 :]
    else:
        lines.insert(i, draw(st.text(max_size=40)) + "\n")
    return "".join(lines)


def toml_files(kind: str, names=None, mode: str = "wild"):
    """Mutations of the shipped TOML files of a data/ folder, and (wild) random text."""
    names = names or [n for n in shipped_names(kind) if n.endswith(".toml") and n != "index.toml"]
    choices = [
        st.sampled_from(names).flatmap(lambda n: mutated_toml(shipped_text(kind, n), mode)),
        st.sampled_from(names).map(lambda n: shipped_text(kind, n).encode()),
    ]
    if mode == "wild":
        choices.append(st.text(max_size=120).map(lambda t: t.encode("utf-8", "surrogatepass")))
    return st.one_of(*choices)


def csv_files(mode: str = "wild"):
    base = shipped_text("examples", "dumbbell.csv")
    if mode == "valid":
        row = st.lists(positive_numbers(), min_size=4, max_size=4).map(lambda r: ", ".join(r))
        return st.one_of(
            st.just(base),
            st.lists(row, min_size=1, max_size=8).map(lambda rows: "m, x, y, z\n" + "\n".join(rows) + "\n"),
        ).map(str.encode)
    row = st.lists(st.one_of(numbers(), positive_numbers()), min_size=3, max_size=5).map(lambda r: ", ".join(r))
    header = st.sampled_from(
        [
            "m, x, y, z",
            "m [kg], x, y, z",
            "m [g], x [cm], y [cm], z [cm]",
            "m [m], x, y, z",
            "m, x [kg], y, z",
            "x, y, z, m",
            "m,x,y",
            "mass, x, y, z",
            "",
            "m [foo], x, y, z",
        ]
    )
    built = st.tuples(header, st.lists(row, min_size=0, max_size=6)).map(lambda t: "\n".join([t[0], *t[1]]) + "\n")
    return st.one_of(st.just(base), mutated_text(base), built).map(lambda t: t.encode("utf-8", "surrogatepass"))


@st.composite
def density_files(draw, mode: str = "wild"):
    """A small density grid as netCDF bytes: shapes, units, values and coordinates right and wrong."""
    import numpy as np
    import xarray as xr

    if mode == "valid":
        shape = draw(st.tuples(*[st.integers(2, 5)] * 3))
        ds = xr.Dataset(
            {"rho": (("x", "y", "z"), np.full(shape, draw(st.floats(1, 1e4))), {"units": "kg m-3"})},
            coords={
                a: (a, np.linspace(-1.0, 1.0, n), {"units": draw(st.sampled_from(["m", "km", "cm"]))})
                for a, n in zip("xyz", shape)
            },
        )
        with tempfile.TemporaryDirectory() as tmp:
            ds.to_netcdf(Path(tmp) / "grid.nc", engine="netcdf4")
            return (Path(tmp) / "grid.nc").read_bytes()
    if mode == "wild" and draw(st.integers(0, 5)) == 0:
        data = (_data_root() / "examples" / "planet.nc").read_bytes()
        return data[: draw(st.integers(0, len(data) - 1))] if draw(st.booleans()) else data
    shape = draw(st.tuples(*[st.integers(1, 5)] * 3))
    coords = {}
    for axis, n in zip("xyz", shape):
        kind = draw(st.sampled_from(["even", "even", "even", "reversed", "repeated", "nan", "huge"]))
        c = np.linspace(-1.0, 1.0, n)
        if kind == "reversed":
            c = c[::-1].copy()
        elif kind == "repeated" and n > 1:
            c[1] = c[0]
        elif kind == "nan":
            c[0] = np.nan
        elif kind == "huge":
            c = c * 1e300
        coords[axis] = (axis, c, {"units": draw(st.sampled_from(["m", "km", "cm", "kg", "", "s"]))})
    fill = draw(st.sampled_from([1.0, 0.0, -1.0, 1e300, float("nan"), float("inf"), 5515.0]))
    values = np.full(shape, fill)
    if draw(st.booleans()):
        values.flat[0] = draw(st.sampled_from([0.0, -5.0, float("nan"), 1e308]))
    dims = draw(st.sampled_from([("x", "y", "z"), ("z", "y", "x"), ("x", "y", "w")]))
    if dims != ("x", "y", "z"):
        values = values.transpose(["xyz".index(d) if d in "xyz" else 2 for d in dims]) if dims[2] != "w" else values
    unit = draw(st.sampled_from(["kg m-3", "g cm-3", "kg/m3", "kg", "m", "", "foo"]))
    ds = xr.Dataset(
        {"rho": (dims, values, {"units": unit})},
        coords={k: v for k, v in coords.items() if k in dims} if dims[2] != "w" else {},
    )
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "grid.nc"
        ds.to_netcdf(path, engine="netcdf4")
        return path.read_bytes()


@cache
def _eop_lines(name: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(header lines, data lines) of a file of astropy-iers-data."""
    import astropy_iers_data

    path = Path(astropy_iers_data.__file__).parent / "data" / name
    lines = path.read_text(encoding="ascii").splitlines()
    if name.startswith("eopc04"):
        return tuple(x for x in lines if x.startswith("#")), tuple(
            x for x in lines if not x.startswith("#") and x.strip()
        )
    return (), tuple(x for x in lines if x.strip())


@st.composite
def eop_files(draw, mode: str = "wild", years=(0.01, 1, 3, 8, 11, 12, 14)):
    """A slice of the shipped C04 or finals2000A file (``years`` long: a few days to a dozen years), maybe
    damaged."""
    name = draw(st.sampled_from(["eopc04.1962-now", "finals2000A.all"]))
    header, data = _eop_lines(name)
    if name.startswith("finals"):
        observed = [i for i, x in enumerate(data) if len(x) > 16 and x[16] == "I"]
        data = data[: observed[-1] + 1 + draw(st.integers(0, 30))]
    years = draw(st.sampled_from(list(years)))
    n = max(2, int(years * 365.25))
    start = draw(st.integers(0, max(0, len(data) - n)))
    lines = list(header) + list(data[start : start + n])
    text = "\n".join(lines) + "\n"
    op = draw(
        st.sampled_from(
            {
                "valid": ["none"],
                "edge": ["none", "field", "swap", "gap"],
                "wild": ["none", "text", "field", "swap", "gap"],
            }[mode]
        )
    )
    body = len(header)
    if op == "text":
        text = draw(mutated_text(text))
    elif op in ("field", "swap", "gap") and len(lines) > body + 2:
        i = draw(st.integers(body, len(lines) - 2))
        if op == "field":
            line = lines[i]
            j = draw(st.integers(0, max(0, len(line) - 10)))
            lines[i] = (
                line[:j]
                + draw(st.sampled_from(["       nan", "  junk    ", "     1e300", "      -inf", "          "]))
                + line[j + 10 :]
            )
        elif op == "swap":
            lines[i], lines[i + 1] = lines[i + 1], lines[i]
        else:
            del lines[i : i + draw(st.integers(1, 400))]
        text = "\n".join(lines) + "\n"
    return text.encode("utf-8", "surrogatepass")


# --------------------------------------------------------------------------------------------
# Command lines
# --------------------------------------------------------------------------------------------

#: Output paths: new, in a sub-folder, in a missing folder, a folder, empty, odd suffixes, an existing file.
OUTPUT_NAMES = [
    "out.nc",
    "out.nc",
    "out.nc",
    "sub/out.nc",
    "missing/out.nc",
    ".",
    "sub",
    "",
    "out",
    "out.txt",
    "prev.nc",
    "prev.nc",
    "out.zarr",
    "sub/prev.nc",
]
PLOT_NAMES = [
    "fig.png",
    "fig.png",
    "fig.pdf",
    "fig.svg",
    "fig.jpg",
    "fig",
    "missing/fig.png",
    "sub",
    "prevfig.png",
    "prevfig.png",
    "",
]


@st.composite
def _options(draw, spec: dict, always=()):
    """Options of ``spec`` ({flag: strategy or None for a switch}), each present or not, in random order."""
    flags = list(spec)
    chosen = draw(st.lists(st.sampled_from(flags), unique=True, max_size=len(flags))) if flags else []
    chosen = list(dict.fromkeys([*always, *chosen]))
    argv: list[str] = []
    for flag in chosen:
        value = spec[flag]
        if value is None:
            argv.append(flag)
        else:
            drawn = draw(value)
            argv += [flag, *drawn] if isinstance(drawn, list) else [flag, drawn]
    return argv


def _planted(argv: list[str]) -> dict[str, bytes | None]:
    """The folder the command line expects: sub/ exists, prev*.nc/png hold a previous result."""
    files: dict[str, bytes | None] = {"sub": None}
    for token in argv:
        name = os.path.basename(token)
        if name.startswith("prev"):
            files[token] = PREVIOUS
    return files


NOISE = ["--bogus", "-x", "--json=1", "--output", "-o", "--", "--overwrite", "--help", "ünïcode", "-1", "--plot="]


@st.composite
def _finish(draw, command: str, argv: list[str], files: dict, mode: str = "wild"):
    """Shuffle in a little noise sometimes (wild cases); plant the folder."""
    argv = list(argv)
    if mode == "wild" and draw(st.integers(0, 4)) == 0:
        argv.insert(draw(st.integers(0, len(argv))), draw(st.sampled_from(NOISE)))
    if draw(st.integers(0, 3)) == 0:
        argv.append("--overwrite")
    planted = _planted(argv)
    planted.update(files)
    return Case(command, [command, *argv], planted)


def _common_outputs(mode: str = "wild"):
    if mode == "valid":
        return {
            "-o": st.sampled_from(["out.nc", "sub/out.nc", "prev.nc"]),
            "--overwrite": None,
            "--json": None,
            "--plot": st.sampled_from(["fig.png", "fig.pdf", "fig.svg", "prevfig.png"]),
        }
    return {
        "-o": st.sampled_from(OUTPUT_NAMES),
        "--overwrite": None,
        "--json": None,
        "--plot": st.sampled_from(PLOT_NAMES),
    }


BODIES = ["earth", "mars", "EARTH", "venus", "", "my_planet", "../x", "mars.toml"]


def _mode(draw) -> str:
    return draw(st.sampled_from(MODES))


@st.composite
def chandler_cases(draw, command="chandler"):
    mode = _mode(draw)
    files = {}
    argv = draw(st.lists(st.sampled_from(BODIES if mode == "wild" else ["earth", "mars"]), max_size=2))
    if draw(st.booleans()):
        files["planet.toml"] = draw(
            toml_files("bodies", None, mode)
            if draw(st.booleans())
            else toml_files("examples", ["my_planet.toml"], mode)
        )
        argv += ["--body-file", "planet.toml"]
    elif mode == "wild" and draw(st.booleans()):
        argv += ["--body-file", draw(st.sampled_from(["my_planet.toml", "missing.toml", "mars", "sub", "planet.nc"]))]
    spec = _common_outputs(mode)
    if command == "chandler":
        models = ["full", "rigid", "elastic", "fluid_core", "core", "ocean_pole_tide", "ocean", "anelastic"]
        spec.update({"--model": st.sampled_from(models + (["bogus", ""] if mode == "wild" else [])), "--sources": None})
    elif command == "modes":
        spec.update(
            {
                "--profile": st.sampled_from(
                    ["prem", "mars_layered", "profile.toml"] + (["missing", ""] if mode == "wild" else [])
                ),
                "--mode": st.sampled_from(["CW", "FCN"] + (["cw", "XX"] if mode == "wild" else [])),
            }
        )
        if draw(st.booleans()):
            files["profile.toml"] = draw(toml_files("profiles", None, mode))
    else:
        spec.update(
            {
                "--perturber": st.sampled_from(
                    ["moon", "sun", "phobos", "jupiter", "venus", "perturber.toml"]
                    + (["deimos", "", "iau2006", "mars", "earth"] if mode == "wild" else [])
                )
            }
        )
        if draw(st.booleans()):
            files["perturber.toml"] = draw(
                toml_files("precession", ["moon.toml", "sun.toml", "phobos.toml", "jupiter.toml"], mode)
            )
    argv += draw(_options(spec))
    return draw(_finish(command, argv, files, mode))


def _pick(mode, valid, edge=(), wild=()):
    """A sampled_from of the values allowed at ``mode``."""
    values = list(valid) + (list(edge) if mode != "valid" else []) + (list(wild) if mode == "wild" else [])
    return st.sampled_from(values)


@st.composite
def pole_cases(draw, command: str):
    mode = _mode(draw)
    files = {}
    argv = []
    source = draw(st.sampled_from(["slice"] * 6 + ["shipped"] + (["missing"] if mode == "wild" else [])))
    if source == "slice":
        # A calibrated Kalman forecast needs 10 years of fit, 6 of past forecasts and the horizon: 17 or more.
        long = (0.01, 3, 12, 14, 18, 20, 20) if command == "forecast" else (0.01, 1, 3, 8, 11, 12, 14)
        files["pole.txt"] = draw(eop_files(mode, long))
        argv += ["--file", "pole.txt"]
    elif source == "missing":
        argv += ["--file", draw(st.sampled_from(["missing.txt", "sub", "", "finals2000A.all"]))]
    elif command != "forecast":  # the whole shipped record, cut to a few years by dates (forecast: --issued)
        year = draw(st.integers(1975, 2012))
        argv += ["--start", str(year), "--end", str(year + draw(st.sampled_from([1, 9, 11, 12])))]
    spec = _common_outputs(mode)
    spec.update({"--start": dates(mode), "--end": dates(mode)})
    if command == "polar-motion":
        spec.update(
            {
                "--window": _pick(
                    mode, ["8", "4", "2", "6", "3.5"], ["0", "-1", "1e300", "nan", "inf", "1e-300", "20"], ["x", ""]
                ),
                "--step": _pick(mode, ["1", "0.5", "2"], ["0", "-1", "1e-300", "nan", "1e300"], ["x"]),
                "--drift-degree": whole_numbers(0, 4, mode),
                "--excitation-q": _pick(
                    mode, ["100", "none", "50"], ["0", "-1", "1", "inf", "nan", "1e300", "0.5"], ["x"]
                ),
                "--no-q": None,
            }
        )
        if source != "shipped" and draw(st.booleans()):
            argv.append("--no-q")
    elif command == "excitation":
        spec.update(
            {
                "--period": _pick(
                    mode,
                    ["433d", "433", "365 d", "1.2 yr"],
                    ["0", "-433", "nan", "inf", "1e300", "1e-300"],
                    ["433 m", "x"],
                ),
                "--q": _pick(mode, ["100", "inf", "82"], ["0", "-1", "nan", "1e300", "1e-300"], ["x"]),
            }
        )
    else:
        spec.update(
            {
                "--issued": dates(mode),
                "--horizon": _pick(
                    mode,
                    ["365d", "90", "30d", "1 yr"],
                    ["0", "-5", "1e300", "nan", "inf", "4 yr", "1e-300", "1"],
                    ["5 m", "x"],
                ),
                "--method": _pick(mode, ["kalman", "ls_ar"], ["both"], ["x", ""]),
                "--latency": _pick(mode, ["1d", "30d", "0"], ["-1", "nan", "1e300", "100 yr"], ["x"]),
                "--q": _pick(mode, ["100", "inf"], ["0", "-1", "nan"], ["x"]),
                "--scheduler": _pick(mode, ["synchronous", "threads"], [], ["bogus"]),
            }
        )
        if draw(st.booleans()):
            a = draw(dates(mode))
            b = draw(dates(mode))
            spec.pop("--issued")
            spec.pop("--scheduler")
            spec["--every"] = _pick(mode, ["7d", "30d", "100d"], ["0", "-7", "1e-300", "nan"], ["x"])
            # Valid spans only short ones: a drawn a:b reached 17 years (seed 307: a synchronous hindcast of
            # 1992-2009 ran past the 60-s bound), and the fuzzer asks only for work that is refused or short.
            span = draw(
                st.sampled_from(
                    ["2019-01-01:2019-03-01", "2010-06-01:2010-08-01", f"{a}:{a}"]
                    + ([a, f"{a}:{b}:{a}", ":"] if mode == "wild" else [])
                )
            )
            argv += ["--hindcast", span, "--scheduler", "synchronous"]
    argv += draw(_options(spec))
    return draw(_finish(command, argv, files, mode))


@st.composite
def inertia_cases(draw):
    from wobble.cli.inertia import SOLIDS

    mode = _mode(draw)
    files = {}
    source = draw(
        st.sampled_from(["points", "density", "solid", "solid", "solid"] + (["none"] if mode == "wild" else []))
    )
    argv: list[str] = []
    spec = {
        "-o": _common_outputs(mode)["-o"],
        "--overwrite": None,
        "--json": None,
        "--about": _pick(
            mode,
            [["com"], ["origin"], ["0", "0", "-0.06"]],
            [["1e300", "0", "0"], ["nan", "0", "0"], ["0", "0", "0"]],
            [["1", "2"], ["x", "y", "z"], ["1 km", "0", "0 s"]],
        ),
        "--tolerance": _pick(mode, ["1e-9", "0.5", "1e-3"], ["0", "-1", "1", "nan", "inf"], ["x"]),
    }
    if source == "points":
        files["masses.csv"] = draw(csv_files(mode))
        argv += ["--points", draw(_pick(mode, ["masses.csv", "masses.csv", "dumbbell.csv"], [], ["missing.csv"]))]
        spec.update(
            {
                "--mass-unit": _pick(mode, UNITS["mass"][:3], [], UNITS["mass"][3:] + ["", "???"]),
                "--length-unit": _pick(mode, UNITS["length"][:3], [], UNITS["length"][3:] + ["", "???"]),
            }
        )
    elif source == "density":
        files["grid.nc"] = draw(density_files(mode))
        argv += ["--density", draw(_pick(mode, ["grid.nc", "grid.nc", "planet.nc"], [], ["missing.nc"]))]
        spec.update(
            {
                "--var": _pick(mode, ["rho"], [], ["x", "missing"]),
                "--rule": _pick(mode, ["trapezoid", "simpson", "voxel"], [], ["bogus"]),
                "--length-unit": _pick(mode, UNITS["length"][:3], [], UNITS["length"][3:] + ["", "???"]),
            }
        )
    elif source == "solid":
        name = draw(st.sampled_from(list(SOLIDS) + (["bogus"] if mode == "wild" else [])))
        argv += ["--solid", name]
        required, optional = (SOLIDS[name][1], SOLIDS[name][2]) if name in SOLIDS else ((), ())
        for dest in (*required, *optional):
            if dest in required and mode == "wild" and draw(st.integers(0, 5)) == 0:
                continue  # a required option left out
            if dest in optional and draw(st.booleans()):
                continue
            flag = "--" + dest.replace("_", "-")
            kind = "mass" if "mass" in dest else "length"
            if dest in ("axes", "edges"):
                argv += [flag, *draw(st.lists(quantities(kind, mode=mode), min_size=3, max_size=3))]
            else:
                argv += [flag, draw(quantities(kind, mode=mode))]
        if mode == "wild" and draw(st.integers(0, 5)) == 0:
            argv += ["--radius", "1"]  # an option the solid may not use
        spec.update(
            {
                "--mass-unit": _pick(mode, UNITS["mass"][:3], [], UNITS["mass"][3:] + ["", "???"]),
                "--length-unit": _pick(mode, UNITS["length"][:3], [], UNITS["length"][3:] + ["", "???"]),
            }
        )
    argv += draw(_options(spec))
    return draw(_finish("inertia", argv, files, mode))


@st.composite
def free_cases(draw):
    mode = _mode(draw)

    def vec(kind, typical=None):
        return st.lists(quantities(kind, typical, mode), min_size=3, max_size=3)

    argv = [
        "--inertia",
        *draw(vec("inertia")),
        "--omega",
        *draw(vec("rate", st.floats(-10, 10).map(lambda x: f"{x:.6g}"))),
    ]
    if mode == "wild" and draw(st.integers(0, 5)) == 0:
        argv = argv[: draw(st.integers(0, len(argv)))]
    spec = _common_outputs(mode)
    spec.update(
        {
            "--t-end": quantities("time", st.floats(0, 50).map(lambda x: f"{x:.4g}"), mode),
            "--samples": whole_numbers(1, 2000, mode),
        }
    )
    argv += draw(_options(spec))
    return draw(_finish("free", argv, {}, mode))


@st.composite
def top_cases(draw):
    mode = _mode(draw)
    argv = [
        "--I1",
        draw(quantities("inertia", mode=mode)),
        "--I3",
        draw(quantities("inertia", mode=mode)),
        "--mgl",
        draw(quantities("energy", mode=mode)),
        "--theta0",
        draw(angles(mode)),
    ]
    spin = draw(st.sampled_from(["--omega3", "--psidot0"] + (["both", "neither"] if mode == "wild" else [])))
    rate = quantities("rate", st.floats(-30, 30).map(lambda x: f"{x:.4g}"), mode)
    if spin in ("--omega3", "both"):
        argv += ["--omega3", draw(rate)]
    if spin in ("--psidot0", "both"):
        argv += ["--psidot0", draw(rate)]
    if mode == "wild" and draw(st.integers(0, 5)) == 0:
        argv = argv[: draw(st.integers(0, len(argv)))]
    spec = _common_outputs(mode)
    spec.update(
        {
            "--thetadot0": rate,
            "--phidot0": rate,
            "--phi0": angles(mode),
            "--psi0": angles(mode),
            "--t-end": quantities("time", st.floats(0, 30).map(lambda x: f"{x:.4g}"), mode),
            "--samples": whole_numbers(1, 2000, mode),
        }
    )
    argv += draw(_options(spec))
    return draw(_finish("top", argv, {}, mode))


#: Shipped scenes cheap enough to run whole within the bound.
CHEAP_SCENES = [
    "tennis_racket",
    "top_cusps",
    "top_loops",
    "tossed_book",
    "tumbling_asteroid",
    "gyroscope",
    "mars_free_wobble",
    "earth_free_wobble",
]


@st.composite
def run_cases(draw):
    mode = _mode(draw)
    files = {}
    which = draw(
        st.sampled_from(["name", "mutated", "mutated", "mutated", "list"] + (["missing"] if mode == "wild" else []))
    )
    argv: list[str] = []
    if which == "name":
        argv.append(draw(_pick(mode, CHEAP_SCENES, ["tennis_racket.toml"], ["bogus"])))
    elif which == "mutated":
        files["scene.toml"] = draw(toml_files("scenes", [n + ".toml" for n in CHEAP_SCENES], mode))
        argv.append("scene.toml")
    elif which == "missing":
        argv.append(draw(st.sampled_from(["missing.toml", "sub", "", "out.nc"])))
    else:
        argv.append("--list")
    spec = _common_outputs(mode)
    spec["--model"] = _pick(
        mode, ["free-symmetric", "free-elliptic", "heavy-top", "splitting", "dop853"], [], ["bogus", ""]
    )
    argv += draw(_options(spec, always=("-o",) if which != "list" and draw(st.integers(0, 5)) else ()))
    return draw(_finish("run", argv, files, mode))


@st.composite
def sweep_cases(draw):
    mode = _mode(draw)
    files = {}
    which = draw(st.sampled_from(["name", "mutated", "mutated"] + (["missing"] if mode == "wild" else [])))
    random_sweeps = ["earth_chandler", "mars_chandler", "tumbling_asteroids"]
    argv: list[str] = []
    if which == "name":
        argv.append(draw(_pick(mode, random_sweeps, [], ["bogus"])))
    elif which == "mutated":
        files["sweep.toml"] = draw(toml_files("sweeps", [n + ".toml" for n in random_sweeps], mode))
        argv.append("sweep.toml")
    else:
        argv.append(draw(st.sampled_from(["missing.toml", "sub", ""])))
    spec = _common_outputs(mode)
    spec.update(
        {
            "--chunk-size": whole_numbers(50, 500, mode),
            "--scheduler": _pick(mode, ["threads", "synchronous", "threads", "processes"], [], ["bogus", ""]),
            "--quiet": None,
        }
    )
    argv += ["--members", draw(whole_numbers(1, 800, mode, huge_valid=False))]
    argv += draw(_options(spec))
    o = argv.index("-o") if "-o" in argv else -1
    if o >= 0 and draw(st.integers(0, 3)) == 0:
        argv[o + 1] = draw(st.sampled_from(["out.zarr", "prev.zarr", "sub/out.zarr"]))
    return draw(_finish("sweep", argv, files, mode))


@st.composite
def invert_cases(draw):
    mode = _mode(draw)
    files = {}
    which = draw(st.sampled_from(["name", "mutated", "mutated"] + (["missing"] if mode == "wild" else [])))
    argv: list[str] = []
    if which == "name":
        argv.append(draw(_pick(mode, ["mars", "earth", "mars_chandler_only", "inversions/mars"], [], ["bogus"])))
    elif which == "mutated":
        files["setup.toml"] = draw(toml_files("inversions", None, mode))
        argv.append("setup.toml")
    else:
        argv.append(draw(st.sampled_from(["missing.toml", "sub", ""])))
    argv += [
        "--steps",
        draw(_pick(mode, ["20", "30", "10"], ["0", "-1", "1"], ["x"])),
        "--burn",
        draw(_pick(mode, ["5", "10", "0"], ["-1"])),
    ]
    spec = _common_outputs(mode)
    spec.update(
        {
            "--walkers": _pick(mode, ["10", "12", "16"], ["11", "2", "0", "-2"], ["x"]),
            "--ensembles": _pick(mode, ["1", "2"], ["0", "-1"]),
            "--seed": whole_numbers(0, 2**32, mode),
            "--prior-only": None,
            "--scheduler": _pick(mode, ["synchronous", "threads"], [], ["bogus"]),
            "--quiet": None,
        }
    )
    argv += draw(_options(spec))
    return draw(_finish("invert", argv, files, mode))


@st.composite
def example_cases(draw):
    from wobble.io.shipped import shipped_files

    mode = _mode(draw)
    shipped = shipped_files()
    names = [f.qualified for f in shipped] + [f.name for f in shipped] + [f.stem for f in shipped]
    if draw(st.integers(0, 4)) == 0:
        argv = ["--list"] + (["--json"] if draw(st.booleans()) else [])
        return draw(_finish("example", argv, {}, mode))
    argv = [draw(_pick(mode, names, [], ["bogus", "", "../etc", "bodies/", "/"]))]
    if draw(st.booleans()):
        argv.append(
            draw(
                _pick(
                    mode,
                    ["copy.toml", "sub", "sub/", "prev.toml", "prev.toml", "copy.csv"],
                    ["."],
                    ["missing/copy.toml", ""],
                )
            )
        )
    argv += draw(_options({"--json": None, "--overwrite": None}))
    case = draw(_finish("example", argv, {}, mode))
    if draw(st.integers(0, 3)) == 0:  # the default destination exists already
        case.files[os.path.basename(argv[0].rstrip("/")) or "x"] = PREVIOUS
    return case


@st.composite
def bench_cases(draw, real: bool = True):
    from wobble.cli.bench import CASE_KEYS

    argv: list[str] = []
    short = real and draw(st.integers(0, 3)) == 0
    if short:  # a real (short) run
        argv += ["--smoke", "--case", draw(st.sampled_from(["free_generic", "top_cusps", "user_free"]))]
    else:  # refusals: unknown cases, bad repeats, bad outputs, conflicting modes
        argv += draw(
            st.sampled_from(
                [
                    ["--case", "bogus"],
                    ["--repeats", "0"],
                    ["--repeats", "-1"],
                    ["--repeats", "x"],
                    ["--quick", "--smoke"],
                    ["--case", ""],
                    ["--case", CASE_KEYS[0], "--repeats", "-3"],
                    ["--smoke", "-o", "missing/r.md"],
                    ["--smoke", "-o", "prev.md"],
                    ["--smoke", "--plot", "prev.md"],
                    ["--smoke", "-o", "sub"],
                ]
            )
        )
    argv += draw(
        _options(
            {
                "--json": None,
                "-o": st.sampled_from(["report.md", "prev.md", "missing/r.md", "sub"]),
                "--plot": st.sampled_from(["figs", "sub", "missing/figs", "prev.md"]),
                # A refusal stays one: a later valid --repeats would make it the full, minutes-long benchmark.
                "--repeats": st.sampled_from(["1", "0", "-1"] if short else ["0", "-1"]),
            }
        )
    )
    return draw(_finish("bench", argv, {"prev.md": PREVIOUS}, "edge"))


_BUILDERS = {
    "chandler": lambda: chandler_cases("chandler"),
    "modes": lambda: chandler_cases("modes"),
    "precession": lambda: chandler_cases("precession"),
    "polar-motion": lambda: pole_cases("polar-motion"),
    "excitation": lambda: pole_cases("excitation"),
    "forecast": lambda: pole_cases("forecast"),
    "inertia": inertia_cases,
    "free": free_cases,
    "top": top_cases,
    "run": run_cases,
    "sweep": sweep_cases,
    "invert": invert_cases,
    "example": example_cases,
    "bench": bench_cases,
}


def case_strategy(command: str, real_bench: bool = True):
    """Generated inputs for ``wobble COMMAND`` (``real_bench=False``: no benchmark runs, its refusals only)."""
    if command == "bench":
        return bench_cases(real_bench)
    return _BUILDERS[command]()
