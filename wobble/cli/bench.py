"""``wobble bench``: the work-precision benchmark of every solver, from a source checkout.

The benchmark lives in the top-level ``benchmarks/`` folder of the repository, beside
``wobble/`` and ``scripts/``, with the references it reads (tests/references/ and
benchmarks/engine_reference.json) and the reports it writes (docs/): it is not installed
with the package. This module holds only what ``wobble --help`` needs (argparse: the
options and the case names); ``run`` finds ``benchmarks/`` next to the imported wobble
package and refuses in one line when wobble is an installed copy.
"""

from __future__ import annotations

import argparse

from wobble.cli._types import whole_number

__all__ = ["CASE_KEYS", "add_arguments", "register", "run", "harness"]

#: The benchmark's cases, in the order of the report.
CASE_KEYS = (
    "free_generic",
    "free_separatrix",
    "free_earth",
    "top_undulating",
    "top_cusps",
    "top_loops",
    "top_sleeping",
    "torqued_satellite",
    "torqued_asymmetric_top",
    "ensemble_satellite",
    "ensemble_free",
    "user_top",
    "user_free",
)

EPILOG = """\
examples:
  wobble bench --smoke --json                       the harness itself, as JSON: 2-3 s, or 15 to 35 s
                                                    on the first run after installing (Numba compiles
                                                    wobble's kernels once, then caches them on disk)
  wobble bench --quick                              fewer settings, ensembles up to 10^4 (5-8 minutes)
  wobble bench --case user_top                      HeavyTop(...).motion(t) against plain SciPy DOP853
  wobble bench --case free_generic --plot figs      one case, with its work-precision diagram
  wobble bench -o performance.md --plot figures --overwrite
                                                    the full run that writes the report (about 20 min;
                                                    the project's own is docs/performance.md)

For each case and method: one warm-up run (its output is checked against a reference
independent of the method), then the minimum and median of repeated runs, methods
interleaved. No timing includes Numba's loading or compiling of wobble's kernels: a
warm-up that loaded or compiled any is followed by one more run, which is timed. Runs
from a source checkout only (git clone; pip install -e .): the benchmark and its mpmath
and Radau references are in benchmarks/ and tests/references/ of the repository. MuJoCo
runs only when installed (pip install "wobble[bench]"). The diagrams put the error on x
and seconds on y.
"""


def add_arguments(p) -> None:
    """The options of ``wobble bench`` and ``python scripts/work_precision.py``."""
    mode = p.add_mutually_exclusive_group()
    mode.add_argument(
        "--quick",
        action="store_true",
        help="fewer settings and repeats (targets judged only where their methods ran as in the full "
        "run); ensembles up to 10^4 members; 5-8 minutes",
    )
    mode.add_argument(
        "--smoke",
        action="store_true",
        help="2-3 s once wobble's compiled kernels are cached on disk; the first run after installing also "
        "compiles them, 15 to 35 s in all (said on stderr; not in any timing): one setting per method on two "
        "short cases, the harness's own test (targets not judged)",
    )
    p.add_argument(
        "--case", action="append", metavar="NAME", help=f"run only this case (repeatable): {', '.join(CASE_KEYS)}"
    )
    p.add_argument(
        "--repeats", type=whole_number, help="timed runs after the warm-up (default 3; --quick 2; --smoke 1)"
    )
    p.add_argument("--json", action="store_true", help="print the results as JSON instead of a table")
    p.add_argument("--plot", metavar="DIR", help="write work_precision_<case>.png diagrams into DIR (replaced)")
    p.add_argument(
        "-o", "--output", metavar="REPORT.md", help="write the Markdown report (the project's is docs/performance.md)"
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing report")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "bench",
        help="work-precision benchmark: every solver against SciPy (and MuJoCo), speed against error",
        description="Work-precision benchmark of wobble's exact solutions and integrators against "
        "scipy.integrate.solve_ivp (RK45, DOP853, LSODA, Radau) and MuJoCo, on fixed cases with mpmath references, "
        "and of the public API against the SciPy a user would write. Needs a source checkout.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_arguments(p)
    p.set_defaults(func=run)


def harness():
    """The benchmark's harness module, imported from the checkout the running wobble comes from.

    Raises
    ------
    wobble.errors.InputError
        wobble is an installed copy (no ``benchmarks/`` beside it).
    """
    import importlib
    import sys
    from pathlib import Path

    import wobble
    from wobble.errors import InputError

    package = Path(wobble.__file__).resolve().parent
    root = package.parent
    if not (root / "benchmarks" / "harness.py").is_file() or not (root / "tests" / "references").is_dir():
        raise InputError(
            "wobble bench",
            f"wobble installed at {package}",
            "wobble run from a source checkout (git clone, then pip install -e .): the benchmark and its "
            "references are in benchmarks/ and tests/references/ of the repository, not in the package",
        )
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    return importlib.import_module("benchmarks.harness")


def run(args) -> int:
    return harness().run(args, getattr(args, "command_line", "wobble bench"))
