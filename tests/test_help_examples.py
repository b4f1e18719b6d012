"""Every example of every help text runs as printed, in an empty folder (issue 15).

A new user copies an example from ``wobble --help`` or ``wobble COMMAND --help`` and runs
it from wherever they are: it must exit 0 there, with nothing but what wobble ships.
Each help text's examples run in order in their own empty temporary folder (a later
example may use a file an earlier one copied). The minutes-long benchmarks and the
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


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_every_help_example_runs_in_an_empty_folder(name, tmp_path, monkeypatch, capsys, request):
    monkeypatch.chdir(tmp_path)
    ran = 0
    for argv in EXAMPLES[name]:
        if tuple(argv) in LONG:
            continue
        if _needs_scheduler(argv):
            request.getfixturevalue("scheduler")
        status = main(list(argv))
        err = capsys.readouterr().err
        assert status == 0, f"wobble {' '.join(argv)} (from the help of {name}) exited {status}: {err}"
        ran += 1
    assert ran, f"the help of {name} has no example the tests can run"


def test_the_long_examples_are_still_printed():
    """LONG must name examples that exist (a stale entry would hide nothing and mislead)."""
    printed = {tuple(argv) for examples in EXAMPLES.values() for argv in examples}
    assert set(LONG) <= printed
