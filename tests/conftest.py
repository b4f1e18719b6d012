"""Test-wide settings: no network, no windows, reproducible property tests."""

from __future__ import annotations

import ipaddress
import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")  # no display, and no GUI warnings

# One BLAS thread per test process (and, through the environment, per process a test starts), unless the
# caller chose: the suite runs one process per core (pytest-xdist), and OpenBLAS's own pool of one thread
# per core in each of them oversubscribes the cores. Its threads then wait for one another on the many
# small products: a state-space maximum-likelihood fit took 12.7 s in the suite against 0.86 s with one
# thread, and test_forecast_models.py 33 s against 15. wobble limits the pool itself around its
# polar-motion calls (wobble.numerics.threads); the tests also call the models below those.
if "OPENBLAS_NUM_THREADS" not in os.environ:
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")  # NumPy's BLAS may be loaded already (by a plugin)

import pytest
from hypothesis import HealthCheck, settings

_APPROX = pytest.approx


def _relative_approx(expected, rel=None, abs=None, nan_ok=False):
    """pytest.approx where a relative tolerance given alone is the whole tolerance: pytest keeps its default
    absolute 1e-12 beside it, so ``approx(x, rel=1e-15)`` passed any value for |x| below about 1e-12 (nine
    assertions on moments of 1e-300 kg m2 and rates of 1e-14 rad/s checked nothing) and only 1e-12 absolute
    above. An absolute tolerance is asked for explicitly."""
    if rel is not None and abs is None:
        abs = 0.0
    return _APPROX(expected, rel=rel, abs=abs, nan_ok=nan_ok)


pytest.approx = _relative_approx

# Property tests: no deadlines (machines are shared; timing is not a test),
# derandomized so CI runs are reproducible.
settings.register_profile("wobble", deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("wobble")

_real_connect = socket.socket.connect


def _is_loopback(address) -> bool:
    if isinstance(address, (str, bytes)):  # AF_UNIX path
        return True
    host = address[0]
    if host in ("localhost", ""):
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _guarded_connect(self, address):
    if self.family == getattr(socket, "AF_UNIX", None) or _is_loopback(address):
        return _real_connect(self, address)
    raise RuntimeError(f"test tried to reach the network: {address!r} (wobble must work offline)")


@pytest.fixture(autouse=True)
def _no_network(monkeypatch):
    """Fail any test that opens a connection beyond loopback."""
    monkeypatch.setattr(socket.socket, "connect", _guarded_connect)
    yield


def cf_problems(path) -> list[str]:
    """Run the IOOS compliance checker (CF 1.10, lenient) offline; return its failures.

    Lenient criteria: only real failures are returned; the checker's own
    exceptions count as failures too, so a file that crashes it never passes.
    """
    import json
    import tempfile

    from compliance_checker.runner import CheckSuite, ComplianceChecker

    CheckSuite().load_all_available_checkers()
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "report.json")
        passed, errors = ComplianceChecker.run_checker(
            str(path), ["cf:1.10"], 0, "lenient", output_filename=report, output_format="json"
        )
        with open(report) as fh:
            result = json.load(fh)["cf:1.10"]
    problems = [
        f"{item['name']}: {'; '.join(item['msgs'])}"
        for item in result["all_priorities"]
        if item["value"][0] < item["value"][1] and item["weight"] >= 2
    ]
    if errors:
        problems.append("compliance-checker raised an exception while checking the file")
    if not passed and not problems:
        problems.append("compliance-checker did not pass the file")
    return problems


@pytest.fixture
def assert_cf_compliant():
    """Fixture: ``assert_cf_compliant(path)`` fails with the checker's messages."""

    def check(path):
        problems = cf_problems(path)
        assert not problems, "CF compliance problems:\n" + "\n".join(problems)

    return check


@pytest.fixture
def python_ctrl_c():
    """Python's own Ctrl-C handler for each test, the previous one restored after: a process started in the
    background (``&`` in a script, nohup) inherits SIGINT ignored, and these tests are about that handler
    (they failed, or were skipped, in a clean-clone CI run started in the background)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    # None: a handler not installed from Python; the default is the nearest it can be restored to.
    signal.signal(signal.SIGINT, signal.SIG_DFL if previous is None else previous)


# ---------------------------------------------------------------------------
# Numba's disk cache, written once (tests/_warm_numba.py)
# ---------------------------------------------------------------------------
_WARM_UP: subprocess.Popen | None = None


def pytest_configure(config):
    """In the process that controls the pytest-xdist workers (no work of its own while they run),
    compile wobble's Numba kernels in the background while the workers collect: on a fresh checkout
    both workers otherwise compiled the same kernels at once when their first engine test came."""
    global _WARM_UP
    if hasattr(config, "workerinput") or not getattr(config.option, "numprocesses", None):
        return
    _WARM_UP = subprocess.Popen(
        [sys.executable, str(Path(__file__).with_name("_warm_numba.py"))],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        cwd=Path(__file__).parent,
    )


def pytest_unconfigure(config):
    if _WARM_UP is not None and _WARM_UP.poll() is None:
        _WARM_UP.kill()
        _WARM_UP.wait()
