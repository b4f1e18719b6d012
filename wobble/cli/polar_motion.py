"""``wobble polar-motion``: the Chandler wobble measured in the IERS record, beside the model."""

from __future__ import annotations

import argparse
import math

from wobble.cli._record import add_outputs, add_record, report
from wobble.cli._stages import Stages
from wobble.cli._types import whole_number
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble polar-motion                          the whole IERS 20 C04 record (1962-)
  wobble polar-motion --start 1980 --end 2010 --window 6 --json
  wobble polar-motion -o pm.nc --plot pm.png --overwrite
  wobble polar-motion --file finals2000A.all   IERS Bulletin A (finals2000A) instead of C04

--file takes a C04 or finals2000A file of your own; the names finals2000A.all and
eopc04.1962-now, when no such file is in the working folder, are the copies shipped
with the astropy-iers-data package. Dates are UTC: 2015-01-01, 2015-06, 2015 or
2015.5. The pole is p = x_p - i y_p, so the Chandler wobble (prograde) is at a
positive frequency. The period is found by nonlinear least squares and,
independently, from the peak of the two-sided spectrum; its uncertainty allows for
the strongly autocorrelated residuals (Newey & West 1987), the scatter over
sub-spans and a randomly excited wobble of Q = 100 (--excitation-q). A bare number
in --window and --step is years (Julian, 365.25 d); days are days of 86400 s;
amplitudes are in milliarcseconds (mas). Q (skipped by --no-q, and for spans under
20 years) is printed with its caveats. No network is used.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "polar-motion",
        help="measure the Chandler wobble in the IERS polar-motion record and compare with the model",
        description="The Chandler wobble (period, amplitude, phase) measured in the IERS polar-motion "
        "record by two independent methods, its changes over the decades in sliding windows, an "
        "optional Q, and the modelled period of 'wobble chandler earth' beside it.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_record(p)
    p.add_argument(
        "--window",
        metavar="T",
        help="length of the sliding windows, e.g. 8 or 2920d (a bare number is years; default: 8, or the span "
        "when shorter): longer than 2 yr, since the samples in each must span 2 yr (on daily data, at least 732.5 d)",
    )
    p.add_argument(
        "--step",
        metavar="T",
        help="spacing of the windows, at least 1 d, e.g. 1 or 26 week (a bare number is years; default: 1)",
    )
    p.add_argument(
        "--drift-degree",
        metavar="N",
        type=whole_number,
        default=2,
        help="degree of the mean-pole polynomial, 0 to 6 (default: 2)",
    )
    p.add_argument(
        "--excitation-q",
        metavar="Q",
        default="100",
        help="Q of the randomly excited wobble in the Monte-Carlo part of the uncertainty, finite and above 1, or "
        "'none' to leave that part out (default: 100)",
    )
    p.add_argument("--no-q", action="store_true", help="skip the quality-factor estimate")
    add_outputs(
        p,
        output_help="write series, model, residuals, windows and spectrum (CF-1.10 netCDF)",
        plot_help="write a figure: pole path, two-sided spectrum, windowed amplitude and period",
    )
    p.set_defaults(func=run)


def _q(text: str) -> float | None:
    allowed = "a finite quality factor above 1, e.g. 100, or 'none'"
    if text.strip().lower() == "none":
        return None
    try:
        value = float(text)
    except ValueError:
        raise InputError("--excitation-q", text, allowed) from None
    if not (math.isfinite(value) and value > 1.0):
        raise InputError("--excitation-q", text, allowed)
    return value


def run(args) -> int:
    from wobble.api.polar_motion import polar_motion_analysis
    from wobble.cli._output import check_outputs
    from wobble.cli._record import as_typed, check_file, parse_time

    window = parse_time(args.window, "--window", "yr", default="8")
    step = parse_time(args.step, "--step", "yr", default="1")
    excitation_q = _q(args.excitation_q)
    check_outputs(args)
    check_file(args)
    options = {
        "window": ("--window", window.shown),
        "step": ("--step", step.shown),
        "start/end": ("--start/--end", None),
    }
    with Stages() as progress, as_typed(options):
        analysis = polar_motion_analysis(
            args.file,
            start=args.start,
            end=args.end,
            window=None if args.window is None else window.quantity,  # None: 8 yr, or the span if shorter
            step=step.quantity,
            drift_degree=args.drift_degree,
            excitation_q=excitation_q,
            quality_factor=not args.no_q,
            progress=progress,
        )

    def show():
        from wobble.cli._polar_motion_report import report as text

        print(text(analysis))
        if args.output or args.plot:
            print()  # a blank line between the report and the "wrote" lines

    return report(args, analysis, "wobble.plot.polar_motion:save_overview", show)
