"""``wobble precession``: forced precession budgets and the principal nutation, as a table, JSON or netCDF."""

from __future__ import annotations

import argparse

from wobble.errors import InputError

EPILOG = """\
examples:
  wobble precession earth mars
  wobble precession mars --json
  wobble precession earth mars -o precession.nc --overwrite
  wobble precession earth mars --plot precession.png
  wobble precession --body-file my_planet.toml    (the shipped example planet, or your own file)

Rates are of the node longitude of the equator on the orbit plane, in arcsec per
Julian century, negative when retrograde (IAU's psi_A and p_A count the other way:
Earth's -5040.69 here is IAU's +5040.69). The Sun perturbs every planet on the
planet's own orbit (obliquity, orbit_semi_major_axis, orbit_eccentricity in the
planet file); satellites come from the perturber catalogue (the Moon for Earth).
The observed rate is never an input; it is shown for comparison.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "precession",
        help="forced precession of the spin axis by the Sun and moons, term by term",
        description="The precession rate of a planet's spin axis from its dynamical flattening, spin, obliquity "
        "and its perturbers' orbits, each term shown (Sun, Moon, eccentricity, inclination, the Sun's perturbation "
        "of the lunar orbit, geodesic precession), the published steps to IAU 2006 for Earth, and the rigid-body "
        "principal nutation from the Moon's node beside the rigid-Earth series REN-2000 (Souchay et al. 1999) and "
        "the non-rigid IAU 2000A.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("bodies", nargs="*", metavar="BODY", help="catalogued planets (default: all of them)")
    p.add_argument("--body-file", action="append", default=[], metavar="FILE", help="a planet file in the wobble/1 schema (repeatable)")
    p.add_argument(
        "--perturber",
        action="append",
        default=None,
        metavar="NAME_OR_FILE",
        help="a satellite to include (catalogue name or perturber file; repeatable); default: the catalogue's satellites of the body",
    )
    p.add_argument("--json", action="store_true", help="print a JSON list, one object per body")
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write a CF-1.10 netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--plot", metavar="FILE.png", help="draw each budget, term by term, against the observed rate")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.chandler import known_planets
    from wobble.api.precession import precession_dataset, precession_rate
    from wobble.cli._output import check_outputs, print_json, wrote

    from wobble.io.shipped import resolve

    for name in args.bodies:
        if name.lower() not in known_planets():
            raise InputError("BODY", name, f"one of {', '.join(known_planets())} (files go with --body-file)")
    check_outputs(args)
    bodies = list(args.bodies) + [resolve(f, ("examples", "bodies"), "--body-file", (".toml",)) for f in args.body_file]
    if not bodies:
        bodies = known_planets()
    budgets = [precession_rate(b, args.perturber) for b in bodies]
    if args.output:
        from wobble.io.netcdf import write_netcdf

        write_netcdf(precession_dataset(budgets), args.output, overwrite=args.overwrite, command=args.command_line)
    if args.plot:
        from wobble.plot.precession import budget_figure

        budget_figure(budgets, args.plot, overwrite=args.overwrite)
    if args.json:
        print_json([b.to_dict() for b in budgets])
    else:
        print("\n\n".join(b.summary() for b in budgets))
    for path in (args.output, args.plot):
        if path:
            wrote(path, json_mode=args.json)
    return 0
