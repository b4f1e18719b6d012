"""``wobble top``: the heavy symmetric top's analysis, and its exact motion to a CF netCDF file."""

from __future__ import annotations

import argparse

from wobble.cli._table import print_rows
from wobble.cli._types import whole_number
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble top --I1 1 --I3 0.5 --mgl 1 --theta0 60 --omega3 10 --json
                                  released from rest: cusps; turning points, period, mean precession
  wobble top --I1 1 --I3 0.5 --mgl 1 --theta0 60 --phidot0 -0.3 --omega3 10 \\
             -o loops.nc --t-end 20 --samples 2001 --plot loops.png
                                  loops: the motion to a CF netCDF file, the figure axis's path drawn
  wobble top --I1 "1 kg m2" --I3 0.5 --mgl "1 N m" --theta0 "1e-6 rad" --omega3 10
                                  a nearly sleeping top (theta0 = 0 is the sleeping top)

Angles (--theta0, --phi0, --psi0) without a unit are degrees, as the JSON output's
theta_min_deg; other numbers without units are SI (kg m2, J, rad/s, s). A value may
carry its unit in quotes ("0.5 rad", "360 deg/s", "2 min"). Give exactly one of --omega3
(spin about the symmetry axis) and --psidot0. --json prints u1, u2, u3, the
turning angles, the nutation class (undulating, cusps, loops, regular, sleeping),
the nutation period, the mean precession rate and whether a sleeping top with
this spin would be stable (I3^2 omega3^2 > 4 I1 M g l).
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "top",
        help="the heavy symmetric top: turning points, nutation class, exact motion",
        description="The heavy symmetric top with one point fixed (Goldstein, Poole & Safko 2002, sec. 5.7): the roots "
        "of f(u), turning angles, nutation class and period, and the exact motion.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--I1", required=True, help="transverse moment of inertia about the tip (kg m2)")
    p.add_argument("--I3", required=True, help="axial moment of inertia (kg m2)")
    p.add_argument("--mgl", required=True, help="M g l: weight times tip-to-centre-of-mass distance (J)")
    p.add_argument(
        "--theta0", required=True, help="initial tilt from the upward vertical (degrees unless a unit is given)"
    )
    p.add_argument("--thetadot0", default="0", help="initial nutation rate (rad/s; default 0)")
    p.add_argument("--phidot0", default="0", help="initial precession rate (rad/s; default 0)")
    spin = p.add_mutually_exclusive_group(required=True)
    spin.add_argument("--omega3", help="spin about the symmetry axis (rad/s)")
    spin.add_argument("--psidot0", help="initial spin-angle rate dpsi/dt (rad/s; the axial spin is --omega3)")
    p.add_argument("--phi0", default="0", help="initial precession angle (degrees unless a unit is given; default 0)")
    p.add_argument("--psi0", default="0", help="initial spin angle (degrees unless a unit is given; default 0)")
    p.add_argument(
        "--t-end",
        default=None,
        help="end of the output span for -o and --plot (s unless a unit is given; default 10 nutation periods)",
    )
    p.add_argument(
        "--samples",
        type=whole_number,
        default=1001,
        help="number of output times from 0 to --t-end for -o (default 1001); --plot samples the path its own "
        "way (200 a nutation period)",
    )
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write the motion to this netCDF file")
    p.add_argument(
        "--plot",
        metavar="FILE.png",
        help="draw the path of the figure axis between the turning circles (undulation, cusps or loops) over the span "
        "(its first 200 nutation periods when it holds more)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace existing output files")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def run(args) -> int:
    from astropy import units as u

    from wobble.api.top import HeavyTop
    from wobble.api.units import parse_angle, parse_quantity
    from wobble.cli._output import check_outputs, finish

    check_outputs(args)
    if args.samples < 2:
        raise InputError("--samples", args.samples, "a whole number >= 2 (the times from 0 to --t-end)")
    rate = u.rad / u.s
    kw = dict(
        I1=parse_quantity(args.I1, "--I1", u.kg * u.m**2),
        I3=parse_quantity(args.I3, "--I3", u.kg * u.m**2),
        mgl=parse_quantity(args.mgl, "--mgl", u.J),
        theta0=parse_angle(args.theta0, "--theta0"),
        thetadot0=parse_quantity(args.thetadot0, "--thetadot0", rate),
        phidot0=parse_quantity(args.phidot0, "--phidot0", rate),
        phi0=parse_angle(args.phi0, "--phi0"),
        psi0=parse_angle(args.psi0, "--psi0"),
    )
    if args.omega3 is not None:
        kw["omega3"] = parse_quantity(args.omega3, "--omega3", rate)
    else:
        kw["psidot0"] = parse_quantity(args.psidot0, "--psidot0", rate)
    top = HeavyTop(**kw)  # its errors name its keywords, which are the options' dests (shown as --I1, ...)
    summary = top.to_dict()
    summary.update(samples=None, t_end_s=None, t_end_chosen_by=None)  # null without a span (the same keys always)
    written = []
    if args.output or args.plot or args.t_end is not None:  # a --t-end given is checked even when unused
        t1, chosen = _span(top, args.t_end)
        summary.update(samples=args.samples, t_end_s=t1, t_end_chosen_by=chosen)
    if args.output:
        from wobble.io.netcdf import write_netcdf

        ds = top.to_dataset(t_end=t1 * u.s, samples=args.samples)
        written.append(write_netcdf(ds, args.output, overwrite=args.overwrite, command=args.command_line))
        summary["output"] = str(written[-1])
    if args.plot:
        from wobble.plot.top import axis_locus_figure

        written.append(axis_locus_figure(top, t1 * u.s, path=args.plot, overwrite=args.overwrite))
        summary["plot"] = str(written[-1])
    return finish(args, summary, lambda: _print_table(summary, args.t_end), written)


def _span(top, text) -> tuple[float, str]:
    """(end of the output span in s, how it was chosen): --t-end, or ten nutation periods."""
    import math

    from wobble.cli._output import t_end_option

    if text is None:
        period = top.model.nutation_period
        if math.isfinite(period):
            return 10 * period, "10 nutation periods, the default; --t-end to change"
        return 10.0, "10 s, the default (the motion has no nutation period); --t-end to change"
    # within the model's own limit (HeavyTopModel.max_time)
    return t_end_option(text, top.model, "100 s, 2 min"), "--t-end"


def _print_table(summary: dict, typed: str | None = None) -> None:
    from wobble.api.top import mean_rate_text
    from wobble.cli._output import duration, number, span_text

    def pair(a, b, unit=""):
        return f"{number(a)}, {number(b)}{unit}"

    rows = [
        ("nutation", summary["nutation_class"]),
        ("roots u1, u2, u3", ", ".join(number(summary[k]) for k in ("u1", "u2", "u3"))),
        ("theta min, max", pair(summary["theta_min_deg"], summary["theta_max_deg"], " deg")),
        ("nutation period", duration(summary["nutation_period_s"])),
        (
            "mean precession rate",
            mean_rate_text(
                summary["mean_precession_rate_rad_per_s"],
                summary.get("error_estimate_mean_precession_rate_rad_per_s"),
            ),
        ),
        ("mean spin rate", f"{number(summary['mean_spin_rate_rad_per_s'])} rad/s"),
        ("elliptic parameter m, 1 - m", pair(summary["parameter_m"], summary["complementary_parameter_1_minus_m"])),
        ("energy E, E'", pair(summary["energy_J"], summary["energy_prime_J"], " J")),
        ("p_phi, p_psi", pair(summary["p_phi_kg_m2_per_s"], summary["p_psi_kg_m2_per_s"], " kg m2/s")),
        ("sleeping top stable", "yes" if summary["sleeping_stable"] else "no"),
    ]
    reg = summary.get("regular_precession_at_theta0")
    if reg:
        rows.append(
            (
                "steady precession at theta0",
                f"slow {number(reg['slow_rad_per_s'])}, fast {number(reg['fast_rad_per_s'])} rad/s"
                if reg["fast_rad_per_s"] is not None
                # A horizontal axis (cos theta0 = 0): the fast root has gone to infinity; the slow one is Mgl/(I3 w3).
                else f"slow {number(reg['slow_rad_per_s'])} rad/s (no fast one: the axis is horizontal)",
            )
        )
    if summary["t_end_s"] is not None:
        rows.append(
            (
                "span",
                f"0 to {span_text(summary['t_end_s'], typed)}, {summary['samples']} samples "
                f"({summary['t_end_chosen_by']})",
            )
        )
    print_rows(rows)
