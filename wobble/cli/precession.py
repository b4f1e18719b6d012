"""``wobble precession``: forced precession budgets and the principal nutation, as a table, JSON or netCDF."""

from __future__ import annotations

import argparse

from wobble.cli._planets import add_bodies, add_outputs, bodies_from_args, report

EPILOG = """\
examples:
  wobble precession earth mars
  wobble precession mars --json
  wobble precession earth mars -o precession.nc --overwrite
  wobble precession earth mars --plot precession.png
  wobble precession --body-file my_planet.toml    (the shipped example planet, or your own file)

Rates are of the node longitude of the equator on the orbit plane, in arcsec per
Julian century, negative when retrograde (IAU's psi_A and p_A count the other way:
Earth's lunisolar -5040.69 here is IAU's +5040.69). The Sun perturbs every planet on the
planet's own orbit (obliquity, orbit_semi_major_axis, orbit_eccentricity in the
planet file); satellites come from the perturber catalogue (the Moon for Earth;
Phobos and Deimos for Mars, as rings that precess with the planet), and so do the
planets, each on its own orbit about the Sun (a planet whose orbit comes within 10 %
of the body's range of distance from the Sun, such as the body's own, is left out).
The observed rate is never an input; it is shown for comparison.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "precession",
        help="forced precession of the spin axis by the Sun, moons and planets, term by term",
        description="The precession rate of a planet's spin axis from its dynamical flattening, spin, obliquity "
        "and its perturbers' orbits, each term shown (Sun, Moon, eccentricity, inclination, the Sun's perturbation "
        "of the lunar orbit, the planets, Mars' moons as rings, geodesic precession), the published steps to IAU "
        "2006 for Earth, and the rigid-body principal nutation from the Moon's node beside the rigid-Earth series "
        "REN-2000 (Souchay et al. 1999) and the non-rigid IAU 2000A.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_bodies(p)
    p.add_argument(
        "--perturber",
        action="append",
        default=None,
        metavar="NAME_OR_FILE",
        help="a satellite of the body, or a planet, to include (catalogue name or perturber file; repeatable); the "
        "ones given replace the default, the catalogue's satellites of the body (the Moon for Earth, Phobos and "
        "Deimos for Mars) and the planets apart from its orbit, and the output names those left out; the Sun is "
        "always included (--perturber sun alone: the Sun only)",
    )
    add_outputs(p, "draw each budget, term by term, against the observed rate")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.precession import precession_dataset, precession_rate

    budgets = [precession_rate(b, args.perturber) for b in bodies_from_args(args)]
    return report(args, budgets, precession_dataset, "wobble.plot.precession:budget_figure")
