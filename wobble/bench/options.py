"""The options of ``wobble bench`` and their case names, importable without the benchmark itself.

``wobble --help`` builds every subcommand's parser; this module keeps that cheap
(argparse only: no NumPy, SciPy or the cases).
"""

from __future__ import annotations

__all__ = ["CASE_KEYS", "add_arguments"]

CASE_KEYS = ("free_generic", "free_separatrix", "free_earth", "top_undulating", "top_cusps", "top_loops",
             "top_sleeping", "torqued_satellite", "torqued_asymmetric_top", "ensemble_satellite", "ensemble_free")


def add_arguments(p) -> None:
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="fewer settings and repeats; ensembles up to 10^4 members")
    mode.add_argument("--smoke", action="store_true", help="a few seconds: one setting per method on three cases (tests)")
    p.add_argument("--case", action="append", metavar="NAME", help=f"run only this case (repeatable): {', '.join(CASE_KEYS)}")
    p.add_argument("--repeats", type=int, help="timed runs after the warm-up (default 3; --quick 2; --smoke 1)")
    p.add_argument("--json", action="store_true", help="print the results as JSON instead of a table")
    p.add_argument("--plot", metavar="DIR", help="write work_precision_<case>.png diagrams into DIR (replaced)")
    p.add_argument("-o", "--output", metavar="REPORT.md", help="write the Markdown report (docs/performance.md)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing report")
