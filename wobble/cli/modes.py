"""``wobble modes``: every free wobble of a layered planet (Chandler wobble, free core nutation)."""

from __future__ import annotations

import argparse

from wobble.cli._planets import add_bodies, add_outputs, bodies_from_args, report

EPILOG = """\
examples:
  wobble modes earth mars
  wobble modes mars --json
  wobble modes earth mars -o modes.nc --overwrite
  wobble modes earth mars --plot modes.png
  wobble modes earth --mode FCN --profile prem    only the FCN rows (the same numbers as the full table)
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
    add_bodies(p)
    p.add_argument(
        "--profile",
        metavar="PROFILE",
        help="density profile (shipped name such as prem, or a file) for the hydrostatic core flattening "
        "(default: the catalogued body's own)",
    )
    p.add_argument(
        "--mode",
        action="append",
        choices=("CW", "FCN"),
        help="show only this mode (repeatable; default: every mode the body supports); the numbers do not "
        "change: every supported mode is computed, the Chandler wobble coupled to the liquid core",
    )
    add_outputs(p, "draw the mode periods against the core flattening")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.modes import modes_dataset, normal_modes

    bodies = bodies_from_args(args)
    modes = tuple(args.mode) if args.mode else None
    results = [normal_modes(b, profile=args.profile, modes=modes) for b in bodies]
    return report(args, results, modes_dataset, "wobble.plot.modes:modes_figure")
