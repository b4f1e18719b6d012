"""``wobble free``: exact torque-free rotation to a CF netCDF file and a summary."""

from __future__ import annotations

import argparse
import json

from wobble.cli._table import print_rows
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble free --inertia 1 2 3 --omega 1 0.1 1 --t-end 1000 --samples 10001 -o free.nc
  wobble free --inertia 1 2 3 --omega 1e-6 1 1e-6 --t-end 200 --json     tennis-racket flips
  wobble free --inertia "8.01012e37 kg m2" 8.01032e37 8.03652e37 \\
              --omega 7.292115e-11 0 7.292115e-5 --t-end "100 yr" --samples 36526 -o earth.nc

Numbers without units are SI (kg m2, rad/s, s); a value may carry its unit in
quotes ("2 d", "360 deg/d"). --json prints the regime, the elliptic parameter m
and 1 - m, the period and the time between flips (where they apply).
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "free",
        help="exact torque-free rotation (symmetric, asymmetric, separatrix) with attitude",
        description="Exact torque-free motion of a rigid body: omega(t) in the body frame and the "
        "attitude quaternion, from the principal moments and the initial angular velocity.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--inertia", nargs=3, required=True, metavar=("I1", "I2", "I3"), help="principal moments (kg m2), any order")
    p.add_argument("--omega", nargs=3, required=True, metavar=("W1", "W2", "W3"), help="initial body-frame angular velocity (rad/s)")
    p.add_argument("--t-end", default="0", help="end of the output span (s unless a unit is given)")
    p.add_argument("--samples", type=int, default=1001, help="number of output times from 0 to --t-end (default 1001)")
    p.add_argument("-o", "--output", help="write the time series to this netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def _quantity(values, name, unit):
    from astropy import units as u

    from wobble.api._units import parse_quantity

    qs = [parse_quantity(v, name, unit) for v in values]
    return u.Quantity([q.to_value(unit) for q in qs], unit)


def run(args) -> int:
    from astropy import units as u

    from wobble.api._units import parse_quantity
    from wobble.api.free import FreeRotation
    from wobble.io.netcdf import write_netcdf

    moments = _quantity(args.inertia, "--inertia", u.kg * u.m**2)
    omega = _quantity(args.omega, "--omega", u.rad / u.s)
    t_end = parse_quantity(args.t_end, "--t-end", u.s)
    if args.samples < 1:
        raise InputError("--samples", args.samples, "a whole number >= 1")
    body = FreeRotation(moments, omega)
    summary = body.summary()
    t1 = t_end.to_value(u.s)
    if not t1 >= 0:
        raise InputError("--t-end", args.t_end, "a non-negative, finite time (e.g. 100 s, 2 d)")
    summary["t_end_s"] = t1
    if body.time_between_flips is not None or body.regime == "separatrix":
        summary["flip_times_s"] = body.flip_times(t_end).to_value(u.s).tolist()[:1000]
    if args.output:
        ds = body.evaluate(t_end=t_end, samples=args.samples)
        path = write_netcdf(ds, args.output, overwrite=args.overwrite, command=args.command_line)
        summary["output"] = str(path)
        summary["samples"] = args.samples
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        _print_table(summary)
    return 0


def _print_table(summary: dict) -> None:
    rows = [
        ("regime", summary["regime"]),
        ("elliptic parameter m", summary["parameter_m"]),
        ("1 - m", summary["complementary_parameter_1_minus_m"]),
        ("period (s)", summary["period_s"]),
        ("time between flips (s)", summary["time_between_flips_s"]),
        ("kinetic energy (J)", summary["energy_J"]),
        ("|L| (kg m2/s)", summary["angular_momentum_kg_m2_s"]),
    ]
    if "flip_times_s" in summary:
        rows.append(("flip times (s)", summary["flip_times_s"]))
    if "output" in summary:
        rows.append(("written", summary["output"]))
    print_rows(rows)
