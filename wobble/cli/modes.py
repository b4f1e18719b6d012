"""``wobble modes``: every free wobble of a layered planet (Chandler wobble, free core nutation)."""

from __future__ import annotations

import argparse

from wobble.errors import InputError

EPILOG = """\
examples:
  wobble modes earth mars
  wobble modes mars --json
  wobble modes earth mars -o modes.nc --overwrite
  wobble modes earth mars --plot modes.png
  wobble modes earth --mode FCN --profile prem
  wobble example bodies/mars.toml my_mars.toml    a planet file to edit (a profile too: wobble example prem.toml), then:
  wobble modes --body-file my_mars.toml

Each mode is shown in the frame where it is observed: the Chandler wobble (CW)
in the planet's frame, the free core nutation (FCN) in the planet's frame
(nearly diurnal) and in space. Periods are in days of 86400 s; negative periods
are retrograde. The FCN is predicted from the hydrostatic core flattening
(Clairaut's equation on the body's density profile: PREM for Earth); the core
flattening that the observed FCN requires is an output, never an input.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "modes",
        help="free modes of a layered planet: Chandler wobble and free core nutation",
        description="Rotational normal modes of a planet with a liquid core from the linearised Liouville "
        "equations (Sasao, Okubo & Saito 1980; Mathews et al. 1991, 2002), with the core's hydrostatic "
        "flattening from Clairaut's equation.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("bodies", nargs="*", metavar="BODY", help="catalogued planets (default: all of them)")
    p.add_argument("--body-file", action="append", default=[], metavar="FILE", help="a planet file in the wobble/1 schema (repeatable)")
    p.add_argument(
        "--profile",
        metavar="PROFILE",
        help="density profile (shipped name such as prem, or a file) for the hydrostatic core flattening "
        "(default: the catalogued body's own)",
    )
    p.add_argument("--mode", action="append", choices=("CW", "FCN"), help="modes to compute (repeatable; default: every mode the body supports)")
    p.add_argument("--json", action="store_true", help="print a JSON list, one object per body")
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write a CF-1.10 netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--plot", metavar="FILE.png", help="draw the mode periods against the core flattening")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.chandler import known_planets
    from wobble.api.modes import modes_dataset, normal_modes
    from wobble.cli._output import check_outputs, print_json, wrote

    for name in args.bodies:
        if name.lower() not in known_planets():
            raise InputError("BODY", name, f"one of {', '.join(known_planets())} (files go with --body-file)")
    from wobble.io.shipped import resolve

    check_outputs(args)
    files = [resolve(f, ("examples", "bodies"), "--body-file", (".toml",)) for f in args.body_file]
    bodies = list(args.bodies) + files or known_planets()
    modes = tuple(args.mode) if args.mode else None
    results = [normal_modes(b, profile=args.profile, modes=modes) for b in bodies]
    if args.output:
        from wobble.io.netcdf import write_netcdf

        write_netcdf(modes_dataset(results), args.output, overwrite=args.overwrite, command=args.command_line)
    if args.plot:
        from wobble.plot.modes import modes_figure

        modes_figure(results, args.plot, overwrite=args.overwrite)
    if args.json:
        print_json([r.to_dict() for r in results])
    else:
        print("\n\n".join(r.summary() for r in results))
    for path in (args.output, args.plot):
        if path:
            wrote(path, json_mode=args.json)
    return 0
