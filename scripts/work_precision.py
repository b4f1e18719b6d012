"""Work-precision benchmark of every solver (issue 8); writes docs/performance.md and its figures.

Usage: python scripts/work_precision.py [--quick] [--json] [--case NAME ...]

A thin wrapper: the harness is the package wobble.bench (also ``wobble bench``). Without
-o/--plot it writes docs/performance.md (replacing it) and docs/figures/work_precision_<case>.png.
"""

from __future__ import annotations

import sys
from pathlib import Path

from wobble.bench.harness import main

ROOT = Path(__file__).resolve().parents[1]

if __name__ == "__main__":
    argv = sys.argv[1:]
    shown = list(argv)  # the report records what was typed, not the defaults added here
    if not any(a in ("-o", "--output") or a.startswith("--output=") for a in argv):
        argv += ["-o", str(ROOT / "docs" / "performance.md"), "--overwrite"]
    if not any(a == "--plot" or a.startswith("--plot=") for a in argv):
        argv += ["--plot", str(ROOT / "docs" / "figures")]
    sys.exit(main(argv, prog="python scripts/work_precision.py", shown=shown))
