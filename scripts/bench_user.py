"""Benchmark: the public API as a user meets it, against plain SciPy DOP853 (issue 15); writes docs/performance-user.md.

Usage: python scripts/bench_user.py [--quick] [--repeats N]

``HeavyTop(...).motion(t)`` for the four tops of issue 8 and ``FreeRotation(...).evaluate(t)``
for the generic free body, Quantities in and a CF Dataset out, against
``scipy.integrate.solve_ivp(method="DOP853")`` at rtol 1e-12 without events, on the
equations a user would write (benchmarks/user_level.py says exactly which, how the
tolerance is chosen and how both errors are measured). The same rows are part of the
full work-precision run (``python scripts/work_precision.py``, which rewrites this file
too and includes it in docs/performance.md); this script refreshes them alone, in about
a minute. Re-runnable at any time; the report records the machine's load average.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # benchmarks/ is a folder of the checkout, not installed

from benchmarks.harness import run_benchmark, write_user_report  # noqa: E402
from benchmarks.report import USER_REPORT  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the cusps top only, fewer repeats")
    ap.add_argument("--repeats", type=int, default=None, help="timed runs after the warm-up (default 3; --quick 2)")
    typed = sys.argv[1:] if argv is None else list(argv)
    args = ap.parse_args(typed)
    mode = "quick" if args.quick else "full"
    res = run_benchmark(mode, ["user_top", "user_free"], args.repeats,
                        progress=lambda s: print(s, file=sys.stderr, flush=True))
    res["meta"]["command"] = " ".join(["python scripts/bench_user.py", *typed])
    path = write_user_report(res, ROOT / "docs" / USER_REPORT)
    print(path.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
