"""Run every example of every help text, each help text's in a new empty folder, and time them.

    python scripts/check_help_examples.py            # all of them (the benchmarks take ~25 min)
    python scripts/check_help_examples.py --quick    # skip what the test suite skips (minutes-long benchmarks)

The test suite runs the same examples (tests/test_help_examples.py) except the long
benchmarks listed in LONG; this script is the complete check. Exit status 1 if any
example fails.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time

from wobble.cli._examples import help_examples

# Examples the test suite does not run (this script does): the benchmarks take minutes (and need a
# source checkout); the inversions at their default length take 25-60 s each, and the suite runs
# the same command lines with fewer steps (the other invert examples and tests/test_inversion_api.py).
LONG = {
    ("invert", "mars"),
    ("invert", "earth", "--json"),
    ("invert", "mars", "--plot", "corner.png"),
    ("bench", "--quick"),
    ("bench", "--case", "free_generic", "--plot", "figs"),
    ("bench", "--case", "user_top"),
    ("bench", "-o", "performance.md", "--plot", "figures", "--overwrite"),
}


def _scheduler():
    """A local dask.distributed cluster where the sweep's help example expects one."""
    from distributed import LocalCluster

    return LocalCluster(
        host="127.0.0.1",
        scheduler_port=8786,
        n_workers=1,
        threads_per_worker=2,
        processes=False,
        dashboard_address=None,
    )


def run_examples(quick: bool) -> int:
    cluster = _scheduler()
    try:
        return _run_all(quick)
    finally:
        cluster.close()


def _run_all(quick: bool) -> int:
    failed = 0
    for name, examples in help_examples().items():
        with tempfile.TemporaryDirectory() as folder:
            for argv in examples:
                if quick and tuple(argv) in LONG:
                    print(f"skip  {' '.join(argv)}")
                    continue
                t0 = time.perf_counter()
                done = subprocess.run(
                    [sys.executable, "-m", "wobble", *argv], cwd=folder, capture_output=True, text=True
                )
                dt = time.perf_counter() - t0
                ok = done.returncode == 0
                failed += not ok
                print(f"{'ok' if ok else 'FAIL':<5} {dt:6.1f} s  [{name}] wobble {' '.join(argv)}")
                if not ok:
                    print("      " + (done.stderr.strip().splitlines() or ["(no message)"])[-1])
    return 1 if failed else 0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="skip the minutes-long benchmarks, as the tests do")
    return run_examples(p.parse_args().quick)


if __name__ == "__main__":
    raise SystemExit(main())
