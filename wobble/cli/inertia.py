"""``wobble inertia``: inertia tensor, principal axes and classification of a body.

For people with data rather than code: point masses from a CSV file, a density
grid from a netCDF file, or a standard solid with its dimensions.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from wobble.cli._types import real_number
from wobble.errors import InputError

if TYPE_CHECKING:  # annotations only: run() imports astropy and the API when it runs
    from astropy import units as u

    from wobble.api.bodies import RigidBody

__all__ = ["register", "run", "SOLIDS"]

EPILOG = """\
examples:
  wobble inertia --solid ellipsoid --mass 2 --axes 3 2 1
  wobble inertia --solid cone --mass "250 g" --radius "3 cm" --height "8 cm" --about 0 0 -0.06
  wobble inertia --solid top --disc-mass 0.1 --disc-radius 0.03 --axle-mass 0.01 \\
                 --axle-length 0.08 --disc-height 0.05 --about origin --json
  wobble inertia --points dumbbell.csv --length-unit cm --json
  wobble inertia --density planet.nc --var rho --rule simpson -o inertia.nc

dumbbell.csv and planet.nc are shipped examples, found by name from any folder
(wobble example dumbbell.csv copies one to edit; a file of yours of the same name wins).

--points FILE.csv has columns m, x, y, z; units may follow the names in the header
(e.g. "m [g], x [cm], y [cm], z [cm]"), otherwise --mass-unit/--length-unit or SI.
--density FILE.nc needs a variable on x, y, z with mass/volume units and length
coordinates. Numbers without units are SI (kg, m), or the --mass-unit/--length-unit;
a unit on the first of three values applies to the other two when they are bare
numbers (--about "1 cm" 2 3 is (1, 2, 3) cm), otherwise each value has its own.
--about com (default: the centre of mass), origin, or X Y Z.
Solids (centre of mass at the origin, symmetry axis along z):
  sphere (--mass --radius)        hollow-sphere (--mass --radius [--inner-radius])
  ellipsoid (--mass --axes A B C, semi-axes)   box (--mass --edges A B C)
  cylinder (--mass --radius --height [--inner-radius])   cone (--mass --radius --height)
  disc (--mass --radius)          rod (--mass --length)
  top (--disc-mass --disc-radius --axle-mass --axle-length --disc-height [--axle-radius]);
      the tip of the axle is at the origin.
"""

# name: (RigidBody constructor, required options, optional options); options are argparse dests.
# Constructors are named, not imported: `wobble --help` must not load the API.
SOLIDS = {
    "sphere": ("solid_sphere", ("mass", "radius"), ()),
    "hollow-sphere": ("hollow_sphere", ("mass", "radius"), ("inner_radius",)),
    "ellipsoid": ("ellipsoid", ("mass", "axes"), ()),
    "box": ("box", ("mass", "edges"), ()),
    "cylinder": ("cylinder", ("mass", "radius", "height"), ("inner_radius",)),
    "cone": ("cone", ("mass", "radius", "height"), ()),
    "disc": ("thin_disc", ("mass", "radius"), ()),
    "rod": ("thin_rod", ("mass", "length"), ()),
    "top": (
        "spinning_top",
        ("disc_mass", "disc_radius", "axle_mass", "axle_length", "disc_height"),
        ("axle_radius",),
    ),
}
# The models' constructors (the parts of a top among them), as a refusal of their sizes names them.
_CONSTRUCTORS = frozenset(name for name, _, _ in SOLIDS.values())
# Relative tolerance for equal principal moments (wobble.api.bodies.DEFAULT_RTOL; tested equal).
DEFAULT_RTOL = 1e-9
_MASS_OPTIONS = ("mass", "disc_mass", "axle_mass")
_TRIPLE_OPTIONS = ("axes", "edges")
_SOLID_OPTIONS = (
    "mass", "radius", "inner_radius", "height", "length", "axes", "edges",
    "disc_mass", "disc_radius", "axle_mass", "axle_length", "disc_height", "axle_radius",
)  # fmt: skip
# Keyword the constructor uses for an option, where it differs.
_KEYWORD = {"axes": "semi_axes"}


def register(subparsers) -> None:
    """Add the ``inertia`` subcommand."""
    p = subparsers.add_parser(
        "inertia",
        help="inertia tensor, principal moments and axes of masses, a density grid or a solid",
        description="Inertia tensor I_jk = sum m (r^2 delta_jk - x_j x_k) about the centre of mass "
        "(or --about), principal moments (ascending) and axes (right-handed), and the shape class.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--points", metavar="FILE.csv", help="point masses: CSV with columns m, x, y, z")
    src.add_argument("--density", metavar="FILE.nc", help="density grid: netCDF variable on x, y, z")
    src.add_argument("--solid", choices=tuple(SOLIDS), metavar="NAME", help=f"a solid: {', '.join(SOLIDS)}")
    p.add_argument("--var", metavar="NAME", help="density variable in --density (default: the only one on x, y, z)")
    p.add_argument("--rule", choices=("trapezoid", "simpson", "voxel"), help="grid quadrature (default trapezoid)")
    p.add_argument("--mass-unit", metavar="UNIT", help="unit of masses given without one (default kg)")
    p.add_argument("--length-unit", metavar="UNIT", help="unit of lengths given without one (default m)")
    for dest in _SOLID_OPTIONS:
        flag = "--" + dest.replace("_", "-")
        if dest in _TRIPLE_OPTIONS:
            p.add_argument(flag, nargs=3, metavar=("A", "B", "C"), help="three lengths along x, y, z")
        else:
            p.add_argument(flag, metavar="Q", help="mass" if dest in _MASS_OPTIONS else "length")
    p.add_argument("--about", nargs="+", metavar="POINT", default=["com"], help="com (default), origin, or X Y Z")
    p.add_argument("--tolerance", type=real_number, default=DEFAULT_RTOL, metavar="RTOL",
                   help=f"relative tolerance for equal moments (default {DEFAULT_RTOL:g})")  # fmt: skip
    p.add_argument("--json", action="store_true", help="machine-readable output on stdout")
    p.add_argument("-o", "--output", metavar="FILE.nc", help="also write a CF netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --output file")
    p.set_defaults(func=run)


def _unit_option(text: str | None, option: str, kind: u.UnitBase) -> u.UnitBase | None:
    from astropy import units as u

    if text is None:
        return None
    try:
        unit = u.Unit(text, parse_strict="raise")
    except ValueError:
        raise InputError(
            option, text, f"a unit astropy can parse (e.g. {'g, kg, Msun' if kind == u.kg else 'cm, m, au'})"
        ) from None
    if not unit.is_equivalent(kind, equivalencies=None):
        raise InputError(option, text, f"a unit of {kind.physical_type}")
    return unit


def _refuse_unused(args, allowed: set[str], what: str) -> None:
    for dest in ("var", "rule", "mass_unit", "length_unit", *_SOLID_OPTIONS):
        value = getattr(args, dest)
        if value is not None and dest not in allowed:
            shown = " ".join(value) if isinstance(value, list) else value
            raise InputError("--" + dest.replace("_", "-"), shown, f"nothing: it is not used with {what}")


def _about(args, length_unit: u.UnitBase):

    from wobble.api.units import parse_quantities

    tokens = args.about
    if len(tokens) == 1 and tokens[0].lower() in ("com", "origin"):
        return tokens[0].lower()
    if len(tokens) == 3:
        return parse_quantities(tokens, "--about", length_unit)
    raise InputError("--about", " ".join(tokens), "com, origin, or three coordinates X Y Z (e.g. --about 0 0 -0.06)")


def _solid(args, mass_unit: u.UnitBase, length_unit: u.UnitBase) -> RigidBody:

    from wobble.api.bodies import RigidBody
    from wobble.api.units import parse_quantities, parse_quantity

    constructor_name, required, optional = SOLIDS[args.solid]
    constructor = getattr(RigidBody, constructor_name)
    _refuse_unused(args, {"mass_unit", "length_unit", *required, *optional}, f"--solid {args.solid}")
    kwargs = {}
    typed = {}
    for dest in (*required, *optional):
        raw = getattr(args, dest)
        flag = "--" + dest.replace("_", "-")
        if raw is None:
            if dest in required:
                needs = ", ".join("--" + r.replace("_", "-") for r in required)
                raise InputError.missing(flag, f"a value; --solid {args.solid} needs {needs}")
            continue
        if dest in _TRIPLE_OPTIONS:
            value = parse_quantities(raw, flag, length_unit)
        else:
            value = parse_quantity(raw, flag, mass_unit if dest in _MASS_OPTIONS else length_unit)
        kwargs[_KEYWORD.get(dest, dest)] = value
        typed[flag] = " ".join(raw) if isinstance(raw, list) else raw
    try:
        return constructor(**kwargs)
    except InputError as exc:
        # Moments past the doubles (either end) are about all the sizes together: the options as typed.
        if exc.parameter not in _CONSTRUCTORS:
            raise
        raise InputError(", ".join(typed), ", ".join(typed.values()), exc.allowed) from None


def build_body(args) -> tuple[RigidBody, str]:
    """The body the arguments describe, about the requested point, and a one-line description."""
    from astropy import units as u

    from wobble.api.bodies import RigidBody
    from wobble.io.shipped import resolve

    mass_unit = _unit_option(args.mass_unit, "--mass-unit", u.kg) or u.kg
    length_unit = _unit_option(args.length_unit, "--length-unit", u.m) or u.m
    about = _about(args, length_unit)
    if args.points is not None:
        from wobble.io.point_masses import read_point_masses

        _refuse_unused(args, {"mass_unit", "length_unit"}, "--points")
        masses, positions = read_point_masses(
            resolve(args.points, "examples", "--points", (".csv",)),
            mass_unit=_unit_option(args.mass_unit, "--mass-unit", u.kg),
            length_unit=_unit_option(args.length_unit, "--length-unit", u.m),
        )  # fmt: skip
        body = RigidBody.from_point_masses(masses, positions, name=str(args.points))
        label = f"{masses.size} point mass{'' if masses.size == 1 else 'es'} from {args.points}"
    elif args.density is not None:
        from wobble.io.density_grid import open_density

        _refuse_unused(args, {"var", "rule", "length_unit"}, "--density")
        with open_density(resolve(args.density, "examples", "--density", (".nc",)), args.var) as density:
            body = RigidBody.from_density(density, rule=args.rule or "trapezoid", name=str(density.name))
            label = (
                f"density {density.name!r} from {args.density} ({'x'.join(map(str, density.shape))} grid, "
                f"{args.rule or 'trapezoid'} rule)"
            )
    else:
        body = _solid(args, mass_unit, length_unit)
        label = f"solid {args.solid}"
    from wobble.cli._record import as_typed

    with as_typed({"point": ("--about", " ".join(args.about))}):
        return body.shifted_to(about), label


# The JSON keys with their unit, as every other command writes them (README, "Commands"); inertia gave the
# units in a map beside unsuffixed keys. The old keys are aliases for one release (wobble.io.json_keys).
# The map itself, "units", also stays one release; deprecated_keys cannot list it, since no new key holds
# its value (each of its units is now in a key's name): docs/bodies.md says so.
JSON_RENAMES = {
    "mass": "mass_kg",
    "center_of_mass": "center_of_mass_m",
    "reference_point": "reference_point_m",
    "tensor": "tensor_kg_m2",
    "principal_moments": "principal_moments_kg_m2",
    "principal_moment_differences": "principal_moment_differences_kg_m2",
}


def _report(body: RigidBody, rtol: float) -> dict:
    import numpy as np
    from astropy import units as u

    from wobble.io.json_keys import deprecate

    f = body.principal("ascending", rtol)
    cls = body.classify(rtol)
    d = f.differences.to_value(u.kg * u.m**2)
    out = {
        "mass_kg": float(body.mass.to_value(u.kg)),
        "center_of_mass_m": body.center_of_mass.to_value(u.m).tolist(),
        "reference_point_m": body.reference_point.to_value(u.m).tolist(),
        "tensor_kg_m2": body.tensor.to_value(u.kg * u.m**2).tolist(),
        "principal_moments_kg_m2": f.moments.to_value(u.kg * u.m**2).tolist(),
        "principal_axes": np.asarray(f.axes).tolist(),  # unit vectors: no unit
        "principal_moment_differences_kg_m2": [float(d[1, 0]), float(d[2, 1]), float(d[2, 0])],
        "classification": cls.kind,
        "asymmetry": cls.asymmetry,
        "tolerance": cls.rtol,
        # Deprecated (one release, see JSON_RENAMES): the units of the old, unsuffixed keys.
        "units": {
            "mass": "kg",
            "center_of_mass": "m",
            "reference_point": "m",
            "tensor": "kg m2",
            "principal_moments": "kg m2",
            "principal_axes": "1",
            "principal_moment_differences": "kg m2",
        },
    }
    return deprecate(out, JSON_RENAMES)


def _vec(v, scale: float = 1.0) -> str:
    """A vector to 7 digits; components below 1e-12 of ``scale`` (the rounding of sums of terms
    of that size, such as -3.9e-19 m for a body 0.2 m across) shown as 0."""
    return "(" + ", ".join(f"{x if abs(x) > 1e-12 * scale else 0.0:.7g}" for x in v) + ")"


def _print_human(report: dict, label: str, out) -> None:
    import math

    # The body's radius of gyration: the length scale of its centre of mass's rounding.
    size = (
        math.sqrt(max(sum(report["tensor_kg_m2"][i][i] for i in range(3)), 0.0) / report["mass_kg"])
        if report["mass_kg"]
        else 0
    )
    print(f"wobble inertia: {label}", file=out)
    print(f"  mass                {report['mass_kg']:.7g} kg", file=out)
    print(f"  centre of mass      {_vec(report['center_of_mass_m'], size)} m", file=out)
    same = report["reference_point_m"] == report["center_of_mass_m"]
    print(
        f"  about               {'the centre of mass' if same else _vec(report['reference_point_m']) + ' m'}", file=out
    )
    print("  inertia tensor (kg m2, input axes x, y, z)", file=out)
    # Entries below 1e-12 of the largest are the rounding of sums of terms of that size (5161 kg m2
    # beside 8.3e37 for the shipped planet grid): shown as 0, as in _vec; --json keeps them.
    big = max((abs(x) for row in report["tensor_kg_m2"] for x in row), default=0.0)
    for row in report["tensor_kg_m2"]:
        print("    " + "  ".join(f"{x if abs(x) > 1e-12 * big else 0.0:>17.7g}" for x in row), file=out)
    print("  principal moments (kg m2, ascending)", file=out)
    for k, (m, a) in enumerate(zip(report["principal_moments_kg_m2"], report["principal_axes"]), start=1):
        print(f"    I{k} = {m:<17.7g} axis e{k} = {_vec(a)}", file=out)
    print(
        f"  classification      {report['classification']} (closest pair of moments differs by "
        f"{report['asymmetry']:.3g} relative; tolerance {report['tolerance']:g})",
        file=out,
    )


def run(args) -> int:
    """Compute and print; exit status 0."""
    from wobble.cli._output import check_outputs, print_json, wrote

    rtol = args.tolerance
    if not (0.0 <= rtol < 1.0):
        raise InputError("--tolerance", rtol, "a relative tolerance in [0, 1), e.g. 1e-9")
    check_outputs(args)
    body, label = build_body(args)
    report = _report(body, rtol)
    report["output"] = None  # the same keys whatever the options (README, "Commands")
    if args.output is not None:
        from wobble.io.netcdf import write_netcdf

        path = write_netcdf(body.to_dataset(rtol), args.output, overwrite=args.overwrite, command=args.command_line)
        report["output"] = str(path)
    if args.json:
        print_json(report)
    else:
        _print_human(report, label, sys.stdout)
    if args.output is not None:
        wrote(report["output"], json_mode=args.json)
    return 0
