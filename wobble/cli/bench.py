"""``wobble bench``: the work-precision benchmark of every solver (issue 8)."""

from __future__ import annotations

import argparse

EPILOG = """\
examples:
  wobble bench --quick                              fewer settings, ensembles up to 10^4 (minutes)
  wobble bench --smoke --json                       a few seconds: the harness itself, as JSON
  wobble bench --case free_generic --plot figs      one case, with its work-precision diagram
  wobble bench -o docs/performance.md --plot docs/figures --overwrite
                                                    the full run that writes the report (about 20 min)

For each case and method: one warm-up run (its output is checked against a reference
independent of the method), then the minimum and median of repeated runs, methods
interleaved. Needs a source checkout (it reads the committed mpmath and Radau references
under tests/references and scripts/). MuJoCo runs only when installed
(pip install "wobble[bench]"). The diagrams put the error on x and seconds on y.
"""


def register(subparsers) -> None:
    from wobble.bench.options import add_arguments

    p = subparsers.add_parser(
        "bench",
        help="work-precision benchmark: every solver against SciPy (and MuJoCo), speed against error",
        description="Work-precision benchmark of wobble's exact solutions and integrators against "
        "scipy.integrate.solve_ivp (RK45, DOP853, LSODA, Radau) and MuJoCo, on the fixed cases of issue 8.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_arguments(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.bench.harness import run as run_bench

    return run_bench(args, getattr(args, "command_line", "wobble bench"))
