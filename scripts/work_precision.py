"""Work-precision benchmark of every solver; writes docs/performance.md and its figures.

Usage: python scripts/work_precision.py [--quick] [--json] [--case NAME ...]

A thin wrapper around the harness in benchmarks/ (also ``wobble bench``). Without
-o/--plot it writes docs/performance.md (replacing it) and docs/figures/work_precision_<case>.png.
Re-runnable at any time; the report records the machine's load average at the start and
the end of the run (the timings of a shared machine are noisy; ratios within one run are
what the targets compare).
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # benchmarks/ is a folder of the checkout, not installed

from benchmarks.harness import main  # noqa: E402 - after sys.path.insert(0, ROOT)

if __name__ == "__main__":
    argv = sys.argv[1:]
    shown = list(argv)  # the report records what was typed, not the defaults added here
    if not any(a in ("-o", "--output") or a.startswith("--output=") for a in argv):
        argv += ["-o", str(ROOT / "docs" / "performance.md"), "--overwrite"]
    if not any(a == "--plot" or a.startswith("--plot=") for a in argv):
        argv += ["--plot", str(ROOT / "docs" / "figures")]
    sys.exit(main(argv, prog="python scripts/work_precision.py", shown=shown))
