"""Every example of every help text runs as printed, in an empty folder (issue 15).

A new user copies an example from ``wobble --help`` or ``wobble COMMAND --help`` and runs
it from wherever they are: it must exit 0 there, with nothing but what wobble ships.
Each help text's examples run in empty temporary folders: alone until the first
``wobble example``, then in order from each copy on (a later example may use the file it
copied). The minutes-long benchmarks and the
default-length inversions (25-60 s each) are left to ``scripts/check_help_examples.py``
(which runs every example); the example that needs a
dask.distributed scheduler gets one started here first.
"""

from __future__ import annotations

try:
    import fcntl
except ImportError:  # Windows: no lock, the examples may then skip when run in parallel
    fcntl = None

import socket
import sys
import time
from pathlib import Path

import pytest

from wobble.cli import main
from wobble.cli._examples import help_examples

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from check_help_examples import LONG

EXAMPLES = help_examples()
SCHEDULER = ("127.0.0.1", 8786)


def _needs_scheduler(argv) -> bool:
    return any(a.startswith("tcp://") for a in argv)


def _listening(address) -> bool:
    with socket.socket() as probe:
        return probe.connect_ex(address) == 0


@pytest.fixture
def scheduler(tmp_path_factory):
    """A local dask.distributed cluster on the address the help text names.

    The suite runs in several processes (pytest-xdist) and two examples need this port: a lock
    file shared by the processes lets one cluster exist at a time (the other waits for it), so
    neither finds the port taken and skips. Only a cluster of someone else's skips the test.
    """
    distributed = pytest.importorskip("distributed")
    with open(tmp_path_factory.getbasetemp().parent / "port-8786.lock", "w") as lock:
        if fcntl is not None:
            fcntl.flock(lock, fcntl.LOCK_EX)
        deadline = time.monotonic() + 30.0  # a cluster closed a moment ago may still be listening
        while _listening(SCHEDULER):
            if time.monotonic() > deadline:
                pytest.skip("port 8786 is taken by another process (a cluster of someone else's)")
            time.sleep(0.5)
        cluster = distributed.LocalCluster(
            host=SCHEDULER[0],
            scheduler_port=SCHEDULER[1],
            n_workers=1,
            threads_per_worker=2,
            processes=False,
            # ":0", not None: a scheduler without a dashboard still serves HTTP on 8787 by default, and
            # warns (an error here) when another test's cluster holds it; ":0" takes any free port.
            dashboard_address=":0",
        )
        try:
            yield cluster
        finally:
            cluster.close()


def _groups(examples):
    """A help text's examples in groups that run apart. ``wobble example`` is the only command that writes a
    file a later example reads (its copy of a shipped file): each example before the first copy is a group of
    its own, and each copy starts a group that holds the examples after it, which may use the copy. The long
    examples (LONG) are left out, and groups left empty dropped. (One test per help text made
    `wobble invert`'s the suite's longest test, 40 s on one worker.)"""
    groups, copied = [], False
    for argv in examples:
        copied = copied or argv[0] == "example"
        if argv[0] == "example" or not copied or not groups:
            groups.append([])
        groups[-1].append(argv)
    return [[a for a in g if tuple(a) not in LONG] for g in groups if any(tuple(a) not in LONG for a in g)]


GROUPS = [(name, i, group) for name in sorted(EXAMPLES) for i, group in enumerate(_groups(EXAMPLES[name]))]


@pytest.mark.parametrize(("name", "index", "group"), GROUPS, ids=[f"{name}-{i}" for name, i, _ in GROUPS])
def test_every_help_example_runs_in_an_empty_folder(name, index, group, tmp_path, monkeypatch, capsys, request):
    monkeypatch.chdir(tmp_path)
    for argv in group:
        if _needs_scheduler(argv):
            request.getfixturevalue("scheduler")
        status = main(list(argv))
        err = capsys.readouterr().err
        assert status == 0, f"wobble {' '.join(argv)} (from the help of {name}) exited {status}: {err}"


def test_every_help_text_has_examples_the_tests_run():
    assert {name for name, _, _ in GROUPS} == set(EXAMPLES)


def test_the_long_examples_are_still_printed():
    """LONG must name examples that exist (a stale entry would hide nothing and mislead)."""
    printed = {tuple(argv) for examples in EXAMPLES.values() for argv in examples}
    assert set(LONG) <= printed
