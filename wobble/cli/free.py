"""``wobble free``: exact torque-free rotation: a summary, a CF netCDF file, a figure."""

from __future__ import annotations

import argparse

from wobble.cli._types import whole_number
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble free --inertia 1 2 3 --omega 1 0.1 1
                                  the regime, period and wobble (three periods by default)
  wobble free --inertia 1 2 3 --omega 1 0.1 1 --t-end 1000 --samples 10001 -o free.nc
  wobble free --inertia 1 2 3 --omega 1e-6 1 1e-6 --t-end 200 --json     tennis-racket flips
  wobble free --inertia 1 2 3 --omega 1e-6 1 1e-6 --t-end 200 --plot flips.png
  wobble free --inertia "8.01012e37 kg m2" 8.01032e37 8.03652e37 \\
              --omega 7.292115e-11 0 7.292115e-5 --t-end "100 yr" --samples 36526 -o earth.nc

Numbers without units are SI (kg m2, rad/s, s); a value may carry its unit in
quotes ("2 d", "360 deg/d"); a unit on the first of three values applies to the
other two when they are bare numbers. Without --t-end the span is three periods of omega.
The body flips (the tennis-racket effect) when its intermediate axis swings by more
than 90 deg; otherwise the sign changes of that axis's component are half periods of
a wobble, and no flips are reported. --json prints SI numbers (keys end in their unit;
the swing of the intermediate axis in degrees).
"""

DEFAULT_PERIODS = 3


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "free",
        help="exact torque-free rotation (symmetric, asymmetric, separatrix) with attitude",
        description="Exact torque-free motion of a rigid body: omega(t) in the body frame and the "
        "attitude quaternion, from the principal moments and the initial angular velocity.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--inertia", nargs=3, required=True, metavar=("I1", "I2", "I3"), help="principal moments (kg m2), any order"
    )
    p.add_argument(
        "--omega",
        nargs=3,
        required=True,
        metavar=("W1", "W2", "W3"),
        help="initial body-frame angular velocity (rad/s)",
    )
    p.add_argument(
        "--t-end", help=f"end of the output span (s unless a unit is given; default {DEFAULT_PERIODS} periods)"
    )
    p.add_argument(
        "--samples",
        type=whole_number,
        default=1001,
        help="number of output times from 0 to --t-end for -o (default 1001); --plot samples the motion its own "
        "way (1000 a period, the first 10 periods)",
    )
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write the time series to this netCDF file")
    p.add_argument(
        "--plot",
        metavar="FILE.png",
        help="draw omega(t) (its first 10 periods when the span holds more) and the polhode (the path of L in the "
        "body)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace existing output files")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def _quantity(values, name, unit):
    from wobble.api.units import parse_quantities

    return parse_quantities(values, name, unit)


def _typed_unit(text: str):
    """The unit --t-end was given in: seconds for a bare number (the text was parsed by _span already)."""
    from astropy import units as u

    from wobble.api.units import parse_quantity

    return parse_quantity(text, "--t-end", u.s).unit


def _span(body, text):
    """(t_end in s, how it was chosen) from --t-end, or three periods of omega."""
    import math
    from wobble.numerics.floats import HUGE

    from astropy import units as u

    from wobble.cli._output import t_end_option

    if text is not None:  # within the model's own limit (FreeRotationModel.max_time)
        return t_end_option(text, body.model, "100 s, 2 d"), "--t-end"
    period = float(body.period.to_value(u.s))
    if not math.isfinite(period):
        why = "on the separatrix the motion never repeats" if body.regime == "separatrix" else "the spin is steady"
        raise InputError.missing(
            "--t-end", f"a time span (e.g. --t-end 100): {why}, so there is no period to default to"
        )
    t_end = DEFAULT_PERIODS * period  # a Python float: inf past the largest double, without a NumPy warning
    if not math.isfinite(t_end):
        raise InputError.missing(
            "--t-end",
            f"a time span (e.g. --t-end 1e308): the default, {DEFAULT_PERIODS} periods of omega "
            f"({DEFAULT_PERIODS} x {period:.6g} s), is past the largest double ({HUGE:.4g} s)",
        )
    return t_end, f"{DEFAULT_PERIODS} periods, the default; --t-end to change"


#: Flip times listed in the JSON at most (a body may flip millions of times in its span).
MAX_LISTED_FLIPS = 1000


def run(args) -> int:
    from astropy import units as u

    from wobble.api.free import FreeRotation
    from wobble.cli._output import check_outputs, finish

    if args.samples < 2:
        raise InputError("--samples", args.samples, "a whole number >= 2 (the times from 0 to --t-end)")
    check_outputs(args)
    moments = _quantity(args.inertia, "--inertia", u.kg * u.m**2)
    omega = _quantity(args.omega, "--omega", u.rad / u.s)
    try:
        body = FreeRotation(moments, omega)
    except InputError as exc:
        # The API's names for the options (the command line then shows the values as typed).
        option = {"moments": "--inertia", "omega0": "--omega"}.get(exc.parameter, exc.parameter)
        raise InputError(option, exc.value, exc.allowed) from None
    summary = body.to_dict()
    # The same keys whatever the options (README, "Commands"): null where no span was needed.
    summary.update(t_end_s=None, t_end_chosen_by=None, samples=None, flip_times_s=[], flips_in_span=0)
    needs_span = args.output or args.plot or args.t_end is not None or body.flips
    if needs_span:
        t1, chosen = _span(body, args.t_end)
        summary.update(t_end_s=t1, t_end_chosen_by=chosen, samples=args.samples)
    if body.flips:
        # The list stops at MAX_LISTED_FLIPS, taken from a span that holds no more than two beyond them
        # (flips are a time_between_flips apart; the separatrix has one flip and no such time, None);
        # flips_in_span counts them all without listing them.
        between = body.model.time_between_flips
        listed = t1 if between is None else min(t1, (MAX_LISTED_FLIPS + 1) * between)
        flips = body.flip_times(listed * u.s).to_value(u.s)
        summary.update(flip_times_s=flips[:MAX_LISTED_FLIPS].tolist(), flips_in_span=body.flip_count(t1 * u.s))
    written = []
    if args.output:
        from wobble.io.netcdf import write_netcdf

        ds = body.to_dataset(t_end=t1 * u.s, samples=args.samples)
        written.append(write_netcdf(ds, args.output, overwrite=args.overwrite, command=args.command_line))
        summary["output"] = str(written[-1])
    if args.plot:
        from wobble.plot.free import motion_figure

        unit = None if args.t_end is None else _typed_unit(args.t_end)  # the figure's axis in the user's unit
        written.append(motion_figure(body, t1 * u.s, time_unit=unit, path=args.plot, overwrite=args.overwrite))
        summary["plot"] = str(args.plot)
    return finish(args, summary, lambda: _print_table(summary, args.t_end), written)


_REGIMES = {
    "steady": "steady spin about a principal axis",
    "symmetric": "two equal moments: uniform precession about L",
    "major-axis": "about the axis of the largest moment (L^2 > 2 E I2)",
    "minor-axis": "about the axis of the smallest moment (L^2 < 2 E I2)",
    "separatrix": "on the separatrix (L^2 = 2 E I2): one flip, never repeating",
}


def _steady_axis(summary: dict) -> str:
    """Which principal axis a steady spin is about, and whether a disturbance grows: the intermediate
    axis's spin is unstable (the tennis racket), which "steady spin about a principal axis" did not say."""
    from wobble.models.free import steady_axis

    axis, kind = steady_axis(summary["moments_kg_m2"], summary["omega0_rad_per_s"])
    if kind is None:
        return _REGIMES["steady"]
    if kind == "intermediate":
        return f"steady spin about axis {axis + 1}, the intermediate one: unstable, the least disturbance flips it"
    return f"steady spin about axis {axis + 1}, of the {kind} moment: stable"


def _print_table(summary: dict, typed: str | None = None) -> None:
    from wobble.cli._output import duration, number, span_text
    from wobble.cli._table import print_rows

    regime = summary["regime"]
    period = (
        duration(summary["period_s"])
        if summary["period_s"]
        else ("none: omega is constant" if regime == "steady" else "none: omega never repeats")
    )
    rows = [("regime", f"{regime}: {_steady_axis(summary) if regime == 'steady' else _REGIMES[regime]}")]
    rows.append(("period of omega", period))
    swing = summary.get("intermediate_axis_swing_deg")
    if regime == "steady":
        pass
    elif summary["flips"]:
        rows.append(("flips", f"yes: the intermediate axis swings by {number(swing, 4)} deg"))
        rows.append(("time between flips", duration(summary["time_between_flips_s"])))
        times = summary.get("flip_times_s", [])
        count = summary["flips_in_span"]
        shown = ", ".join(number(t) for t in times[:6]) + (f" ... ({count} in the span)" if count > 6 else "")
        rows.append(("flip times (s)", shown or "none in the span"))
    elif swing is not None:
        rows.append(("flips", f"no: the intermediate axis swings by {number(swing, 4)} deg (a wobble)"))
    rows += [
        (
            "elliptic parameter m, 1 - m",
            f"{number(summary['parameter_m'])}, {number(summary['complementary_parameter_1_minus_m'])}",
        ),
        ("kinetic energy", f"{number(summary['energy_J'])} J"),
        ("|L|", f"{number(summary['angular_momentum_kg_m2_per_s'])} kg m2/s"),
    ]
    if summary["t_end_s"] is not None:
        rows.append(
            (
                "span",
                f"0 to {span_text(summary['t_end_s'], typed)}, {summary['samples']} samples "
                f"({summary['t_end_chosen_by']})",
            )
        )
    print_rows(rows)
