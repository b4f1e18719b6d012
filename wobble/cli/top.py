"""``wobble top``: the heavy symmetric top's analysis, and its exact motion to a CF netCDF file."""

from __future__ import annotations

import argparse
import json

from wobble.cli._table import fmt, print_rows
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble top --I1 1 --I3 0.5 --mgl 1 --theta0 "60 deg" --omega3 10 --json
                                  released from rest: cusps; turning points, period, mean precession
  wobble top --I1 1 --I3 0.5 --mgl 1 --theta0 "60 deg" --phidot0 -0.3 --omega3 10 \\
             -o loops.nc --t-end 20 --samples 2001
                                  loops, the motion written to a CF netCDF file
  wobble top --I1 "1 kg m2" --I3 0.5 --mgl "1 N m" --theta0 "1e-6 rad" --omega3 10
                                  a nearly sleeping top (theta0 = 0 is the sleeping top)

Numbers without units are SI (kg m2, J, rad, rad/s, s); a value may carry its
unit in quotes ("60 deg", "360 deg/s", "2 min"). Give exactly one of --omega3
(spin about the symmetry axis) and --psidot0. --json prints u1, u2, u3, the
turning angles, the nutation class (undulating, cusps, loops, regular, sleeping),
the nutation period, the mean precession rate and whether a sleeping top with
this spin would be stable (I3^2 omega3^2 > 4 I1 M g l).
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "top",
        help="the heavy symmetric top: turning points, nutation class, exact motion",
        description="The heavy symmetric top with one point fixed (course notes section 5.7): the roots "
        "of f(u), turning angles, nutation class and period, and the exact motion.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--I1", required=True, help="transverse moment of inertia about the tip (kg m2)")
    p.add_argument("--I3", required=True, help="axial moment of inertia (kg m2)")
    p.add_argument("--mgl", required=True, help="M g l: weight times tip-to-centre-of-mass distance (J)")
    p.add_argument("--theta0", required=True, help="initial tilt from the upward vertical (rad unless a unit is given)")
    p.add_argument("--thetadot0", default="0", help="initial nutation rate (rad/s; default 0)")
    p.add_argument("--phidot0", default="0", help="initial precession rate (rad/s; default 0)")
    spin = p.add_mutually_exclusive_group(required=True)
    spin.add_argument("--omega3", help="spin about the symmetry axis (rad/s)")
    spin.add_argument("--psidot0", help="initial spin rate dpsi/dt (rad/s)")
    p.add_argument("--phi0", default="0", help="initial precession angle (rad; default 0)")
    p.add_argument("--psi0", default="0", help="initial spin angle (rad; default 0)")
    p.add_argument("--t-end", default=None, help="end of the output span for -o (s unless a unit is given; default 10 nutation periods)")
    p.add_argument("--samples", type=int, default=1001, help="number of output times from 0 to --t-end (default 1001)")
    p.add_argument("-o", "--output", help="write the motion to this netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np
    from astropy import units as u

    from wobble.api._units import parse_quantity

    from wobble.api.top import HeavyTop
    from wobble.io.netcdf import write_netcdf

    rate = u.rad / u.s
    kw = dict(
        I1=parse_quantity(args.I1, "--I1", u.kg * u.m**2),
        I3=parse_quantity(args.I3, "--I3", u.kg * u.m**2),
        mgl=parse_quantity(args.mgl, "--mgl", u.J),
        theta0=parse_quantity(args.theta0, "--theta0", u.rad),
        thetadot0=parse_quantity(args.thetadot0, "--thetadot0", rate),
        phidot0=parse_quantity(args.phidot0, "--phidot0", rate),
        phi0=parse_quantity(args.phi0, "--phi0", u.rad),
        psi0=parse_quantity(args.psi0, "--psi0", u.rad),
    )
    if args.omega3 is not None:
        kw["omega3"] = parse_quantity(args.omega3, "--omega3", rate)
    else:
        kw["psidot0"] = parse_quantity(args.psidot0, "--psidot0", rate)
    try:
        top = HeavyTop(**kw)
    except InputError as exc:
        # Name the option as the user typed it.
        raise InputError(f"--{exc.parameter}", exc.value, exc.allowed) from None
    summary = top.summary()
    if args.output:
        if args.samples < 1:
            raise InputError("--samples", args.samples, "a whole number >= 1")
        if args.t_end is None:
            period = top.model.nutation_period
            t1 = 10 * period if np.isfinite(period) else 10.0
            t_end = t1 * u.s
        else:
            t_end = parse_quantity(args.t_end, "--t-end", u.s)
            t1 = t_end.to_value(u.s)
            if not (np.isfinite(t1) and t1 >= 0):
                raise InputError("--t-end", args.t_end, "a non-negative, finite time (e.g. 100 s, 2 min)")
        ds = top.to_dataset(t_end=t_end, samples=args.samples)
        path = write_netcdf(ds, args.output, overwrite=args.overwrite, command=args.command_line)
        summary.update(output=str(path), samples=args.samples, t_end_s=t1)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        _print_table(summary)
    return 0


def _print_table(summary: dict) -> None:
    rows = [
        ("nutation", summary["nutation"]),
        ("roots u1, u2, u3", ", ".join(fmt(summary[k]) for k in ("u1", "u2", "u3"))),
        ("theta min, max (deg)", f"{fmt(summary['theta_min_deg'])}, {fmt(summary['theta_max_deg'])}"),
        ("nutation period (s)", summary["nutation_period_s"]),
        ("mean precession rate (rad/s)", summary["mean_precession_rate_rad_s"]),
        ("mean spin rate (rad/s)", summary["mean_spin_rate_rad_s"]),
        ("elliptic parameter m, 1 - m", f"{fmt(summary['parameter_m'])}, {fmt(summary['complementary_parameter_1_minus_m'])}"),
        ("energy E, E' (J)", f"{fmt(summary['energy_J'])}, {fmt(summary['energy_prime_J'])}"),
        ("p_phi, p_psi (kg m2/s)", f"{fmt(summary['p_phi_kg_m2_s'])}, {fmt(summary['p_psi_kg_m2_s'])}"),
        ("sleeping top stable", summary["sleeping_stable"]),
    ]
    reg = summary.get("regular_precession_at_theta0")
    if reg:
        rows.append(("steady precession at theta0 (rad/s)", f"slow {fmt(reg['slow_rad_s'])}, fast {fmt(reg['fast_rad_s'])}"))
    if "output" in summary:
        rows.append(("written", summary["output"]))
    print_rows(rows)
