"""Perturbers of spin axes (``data/precession/*.toml``) and the published precession steps.

A perturber file (``kind = "perturber"``) gives a body's mass and its mean
orbit about the body it perturbs, named by the top-level key ``primary``
(``"earth"`` for the Moon; ``"*"`` for the Sun, whose orbit relative to each
planet is that planet's own heliocentric orbit, catalogued in
``data/bodies/<planet>.toml``). The Sun is always a perturber of a planet;
its satellites are the perturbers whose ``primary`` is the planet's name, and
the planets (below) those apart from its orbit (:func:`default_perturbers`).

The top-level key ``coupling`` says how a satellite acts: ``"tidal"`` (the
default; the Moon) is a point mass on an orbit whose plane the Sun holds,
whose torque on the bulge is averaged over the orbit; ``"ring"`` (Phobos,
Deimos) is a satellite close enough for the planet's J2 to hold its orbit
near the equator, a ring in its Laplace plane that precesses with the planet
(:mod:`wobble.models.precession`, equations (5) and (6)); ``"planet"`` (Venus,
Jupiter, ...; ``primary = "*"``) is a planet on its own heliocentric orbit,
``semi_major_axis`` about the Sun, which torques every other planet's bulge
(equation (7): circular orbits in one plane, so a planet file gives only ``gm``
and ``semi_major_axis``).

``data/precession/iau2006.toml`` (``kind = "precession_reference"``) holds
the published steps from the first-order lunisolar rate to IAU 2006's psi_A
and p_A, shown next to Earth's budget.

``data/precession/rigid_earth_nutation.toml`` (``kind = "nutation_reference"``)
holds a rigid-Earth series' 18.6-year term (REN-2000, Souchay et al. 1999) and
the dynamical flattening it was computed with, shown next to the model's
principal nutation.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from importlib import resources
from pathlib import Path

from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.parameter_file import ParameterFile, read_parameter_file, wrong_unit
from wobble.io.shipped import not_a_file
from wobble.models.planet import Measured
from wobble.models.precession import PerturberOrbit

__all__ = [
    "PERTURBER_UNITS",
    "REFERENCE_UNITS",
    "perturber_names",
    "load_perturber",
    "perturbers_of",
    "load_precession_reference",
    "NUTATION_REFERENCE_UNITS",
    "load_nutation_reference",
    "measured",
    "COUPLINGS",
    "is_ring",
    "is_planet",
    "planet_perturbers",
    "MIN_SEPARATION",
    "too_close",
    "default_perturbers",
    "too_close_note",
    "perturber_values",
    "perturber_orbit",
]

_ONE = u.dimensionless_unscaled
PERTURBER_UNITS: dict[str, u.UnitBase] = {
    "gm": u.m**3 / u.s**2,
    "semi_major_axis": u.m,
    "eccentricity": _ONE,
    "inclination": u.rad,
    "node_rate": u.rad / u.s,
    "solar_perturbation_factor": _ONE,
}
REFERENCE_UNITS: dict[str, u.UnitBase] = {
    "dynamical_flattening": _ONE,
    "obliquity": u.rad,
    "first_order_lunisolar_coefficient": u.rad / u.s,
    "planetary_first_order": u.rad / u.s,
    "lunisolar_second_order": u.rad / u.s,
    "j4_term": u.rad / u.s,
    "j2_planetary_tilt": u.rad / u.s,
    "nonlinear_term": u.rad / u.s,
    "geodesic_precession": u.rad / u.s,
    "psi_rate": u.rad / u.s,
    "chi_rate": u.rad / u.s,
    "general_precession": u.rad / u.s,
    "nutation_longitude_iau2000a": u.rad,
    "nutation_obliquity_iau2000a": u.rad,
}
NUTATION_REFERENCE_UNITS: dict[str, u.UnitBase] = {
    "retrograde_amplitude": u.rad,
    "prograde_amplitude": u.rad,
    "conversion_obliquity": u.rad,
    "nutation_longitude": u.rad,
    "nutation_obliquity": u.rad,
    "dynamical_flattening": _ONE,
    "general_precession": u.rad / u.s,
}


#: The values of a perturber file's ``coupling`` key (the first is the default).
COUPLINGS = ("tidal", "ring", "planet")
# What equation (7) leaves out: a planet file giving one of these would be silently ignored, so it is refused.
_NOT_FOR_PLANETS = ("eccentricity", "inclination", "node_rate", "solar_perturbation_factor")


def is_ring(pf: ParameterFile) -> bool:
    """True when the perturber file is a ring satellite (``coupling = "ring"``)."""
    return pf.extra.get("coupling", COUPLINGS[0]) == "ring"


def is_planet(pf: ParameterFile) -> bool:
    """True when the perturber file is a planet on its own heliocentric orbit (``coupling = "planet"``)."""
    return pf.extra.get("coupling", COUPLINGS[0]) == "planet"


def _dir():
    return resources.files("wobble._data") / "precession"


def _read(path, kind, known):
    return read_parameter_file(path, kind=kind, known=set(known))


def perturber_names() -> list[str]:
    """Names of the catalogued perturbers (``moon``, ``sun``, ``jupiter``, ...), sorted."""
    return list(_catalogue_names())


# The shipped catalogue is package data: listed and parsed once per process. Every budget lists it
# (the satellites and the planets of the body); reading each of its 14 files for every lookup took
# 105 ms of a Mars budget's 120 ms.
@functools.lru_cache(maxsize=1)
def _catalogue_names() -> tuple[str, ...]:
    out = []
    for entry in _dir().iterdir():
        if entry.name.endswith(".toml"):
            with resources.as_file(entry) as path:
                if _read_kind(path) == "perturber":
                    out.append(entry.name[:-5])
    return tuple(sorted(out))


@functools.cache
def _parsed(key: str) -> ParameterFile:
    with resources.as_file(_dir() / f"{key}.toml") as path:
        return _check(_read(path, "perturber", PERTURBER_UNITS))


def _catalogued(key: str) -> ParameterFile:
    """A shipped perturber file, parsed once; each caller gets its own dicts, so that a change to one (none is
    made in wobble) cannot reach the cache. The Parameters in them are frozen."""
    pf = _parsed(key)
    return dataclasses.replace(pf, parameters=dict(pf.parameters), extra=dict(pf.extra))


def _read_kind(path) -> str:
    from wobble.io.parameter_file import read_toml

    return str(read_toml(path).get("kind", ""))


def measured(pf: ParameterFile, key: str, unit: u.UnitBase) -> Measured | None:
    """Parameter ``key`` of ``pf`` as a :class:`Measured` in ``unit`` (None when absent)."""
    param = pf.get(key)
    if param is None:
        return None
    where = f"parameters.{key}"
    if param.value.size != 1:
        raise FileFormatError(pf.path, f"{where}.value", "must be a single number")
    try:
        return Measured(float(param.value.to_value(unit)), float(param.uncertainty.to_value(unit)))
    except u.UnitConversionError:
        raise wrong_unit(pf, key, unit) from None


def _check(pf: ParameterFile) -> ParameterFile:
    """Physical ranges of a perturber: positive mass and distance, bound orbit, inclination in [0, 180] deg."""
    pf.require("gm", "a perturber's tidal torque")
    if pf.extra.get("primary") != "*":
        pf.require("semi_major_axis", "a perturber's tidal torque")
    gm = measured(pf, "gm", PERTURBER_UNITS["gm"])
    if gm is not None and not gm.value > 0:
        raise FileFormatError(
            pf.path, "parameters.gm.value", f"got {gm.value!r}; allowed: a positive G M (a negative mass is unphysical)"
        )
    a = measured(pf, "semi_major_axis", u.m)
    if a is not None and not a.value > 0:
        raise FileFormatError(
            pf.path, "parameters.semi_major_axis.value", f"got {a.value!r}; allowed: a positive length"
        )
    e = measured(pf, "eccentricity", _ONE)
    if e is not None and not 0 <= e.value < 1:
        raise FileFormatError(
            pf.path,
            "parameters.eccentricity.value",
            f"got {e.value!r}; allowed: 0 <= e < 1 (a bound orbit; e >= 1 is hyperbolic)",
        )
    i = measured(pf, "inclination", u.rad)
    if i is not None and not 0 <= i.value <= math.pi:
        raise FileFormatError(
            pf.path, "parameters.inclination.value", f"got {math.degrees(i.value):.6g} deg; allowed: 0 to 180 deg"
        )
    if not isinstance(pf.extra.get("primary", ""), str) or not pf.extra.get("primary"):
        raise FileFormatError(
            pf.path, "primary", 'missing; the name of the body this perturber orbits (or "*" for every planet)'
        )
    coupling = pf.extra.get("coupling", COUPLINGS[0])
    if coupling not in COUPLINGS:
        raise FileFormatError(
            pf.path, "coupling", f"got {coupling!r}; allowed: {' or '.join(repr(c) for c in COUPLINGS)}"
        )
    if coupling == "ring" and pf.extra.get("primary") == "*":
        raise FileFormatError(pf.path, "coupling", "got 'ring' for a perturber of every planet; allowed: 'tidal'")
    if coupling == "planet":
        _check_planet(pf)
    if coupling == "ring" and pf.get("node_rate") is not None:
        raise FileFormatError(
            pf.path,
            "parameters.node_rate",
            "given for a ring satellite; allowed: none (its node turns about its Laplace plane, not the orbit plane)",
        )
    return pf


def _check_planet(pf: ParameterFile) -> None:
    pf.require("semi_major_axis", "a planet's distance from the Sun (equation (7))")
    if pf.extra.get("primary") != "*":
        raise FileFormatError(
            pf.path,
            "primary",
            f"got {pf.extra.get('primary')!r} for a planet; allowed: '*' (a planet perturbs every other planet)",
        )
    for key in _NOT_FOR_PLANETS:
        if pf.get(key) is not None:
            raise FileFormatError(
                pf.path,
                f"parameters.{key}",
                "given for a planet; allowed: none (its term takes circular orbits in the body's orbit plane)",
            )


def load_perturber(name: str | os.PathLike) -> ParameterFile:
    """A catalogued perturber by name (``"moon"``) or a perturber file by path."""
    text = os.fspath(name)
    key = text.strip().lower()
    if key in _catalogue_names():
        return _catalogued(key)
    if Path(text).is_file():
        return _check(_read(text, "perturber", PERTURBER_UNITS))
    # Why the path is not read (missing, a folder, empty), in the words every file option uses.
    raise InputError(
        "perturber",
        text,
        f"one of {', '.join(perturber_names())}, or the path of a perturber file ({not_a_file(text)})",
    )


def perturbers_of(body: str) -> list[ParameterFile]:
    """The catalogued perturbers whose ``primary`` is ``body`` (the Sun's and the planets' ``*`` excluded), by name."""
    out = []
    for name in perturber_names():
        pf = load_perturber(name)
        if str(pf.extra.get("primary", "")).lower() == body.strip().lower():
            out.append(pf)
    return out


def planet_perturbers() -> list[ParameterFile]:
    """The catalogued planets (``coupling = "planet"``), innermost first."""
    out = [pf for pf in map(load_perturber, perturber_names()) if is_planet(pf)]
    return sorted(out, key=lambda pf: measured(pf, "semi_major_axis", u.m).value)


#: A planet is kept only while its orbit stays this far, relative, from the body's range of distance from the Sun,
#: a(1 +- e). Closer, the planets' own eccentricities (up to Mercury's 0.21) and resonances matter, which
#: equation (7)'s circular orbits leave out, and (7) grows without bound as the orbits meet. The closest
#: catalogued pair, Venus and the Earth-Moon system, are 28 % apart.
MIN_SEPARATION = 0.1


def too_close(pf: ParameterFile, semi_major_axis: float, eccentricity: float) -> bool:
    """Whether a planet's orbit comes within :data:`MIN_SEPARATION` of a body's range of distance from the Sun,
    a(1 +- e) (SI), where equation (7)'s average over two separate circular orbits does not hold (the body's own
    planet file, or a planet near its orbit)."""
    a_k = measured(pf, "semi_major_axis", u.m).value
    low = semi_major_axis * (1 - eccentricity) * (1 - MIN_SEPARATION)
    return low < a_k < semi_major_axis * (1 + eccentricity) / (1 - MIN_SEPARATION)


def default_perturbers(body: str, semi_major_axis: float, eccentricity: float):
    """A body's perturbers besides the Sun: its catalogued satellites, then the planets apart from its orbit.

    Parameters
    ----------
    body : str
        The body's name.
    semi_major_axis, eccentricity : float
        The body's heliocentric orbit (m; 1).

    Returns
    -------
    files : list of ParameterFile
    too_close_names : list of str
        Planets left out because their orbit comes too close to the body's (:func:`too_close`), the body's own
        planet file (its name, near its orbit: Earth's is the Earth-Moon system) excepted, which is no news.
    """
    key = body.strip().lower()
    files, close = perturbers_of(key), []
    for pf in planet_perturbers():
        if not too_close(pf, semi_major_axis, eccentricity):
            files.append(pf)
        elif pf.name != key:
            close.append(pf.name)
    return files, close


def perturber_values(pf: ParameterFile, values: dict, sigmas: dict | None = None) -> None:
    """Put the file's orbit and mass into ``values`` (and their sigmas into ``sigmas``), SI, as ``"<name>.<key>"``:
    the scalars an uncertainty budget perturbs one at a time before :func:`perturber_orbit` reads them."""
    for key, unit in PERTURBER_UNITS.items():
        m = measured(pf, key, unit)
        if m is not None:
            values[f"{pf.name}.{key}"] = m.value
            if sigmas is not None:
                sigmas[f"{pf.name}.{key}"] = m.sigma


def perturber_orbit(pf: ParameterFile, values, body_semi_major_axis: float) -> PerturberOrbit:
    """The model's orbit of perturber ``pf`` from the scalars :func:`perturber_values` put in ``values``: a ring
    satellite or a planet as its ``coupling`` says (a planet's strength needs the body's heliocentric
    ``body_semi_major_axis``, m); the file's keys with their defaults (e = i = 0, no solar perturbation)."""

    def get(key, default=None):
        return values.get(f"{pf.name}.{key}", default)

    return PerturberOrbit(
        name=pf.name,
        gm=get("gm"),
        semi_major_axis=get("semi_major_axis"),
        eccentricity=get("eccentricity", 0.0),
        inclination=get("inclination", 0.0),
        perturbation_factor=get("solar_perturbation_factor", 1.0),
        node_rate=get("node_rate"),
        ring=is_ring(pf),
        body_semi_major_axis=body_semi_major_axis if is_planet(pf) else None,
    )


def too_close_note(names: list[str]) -> str:
    """The note that names the planets :func:`default_perturbers` left out for coming too close."""
    return (
        f"left out: {', '.join(names)} (a planet whose orbit comes within {MIN_SEPARATION:.0%} of the body's range "
        "of distance from the Sun, where the torque averaged over both circular orbits does not hold)"
    )


def load_precession_reference(name: str = "iau2006") -> ParameterFile:
    """The published precession steps (``iau2006``)."""
    with resources.as_file(_dir() / f"{name}.toml") as path:
        return _read(path, "precession_reference", REFERENCE_UNITS)


def load_nutation_reference(name: str | os.PathLike = "rigid_earth_nutation") -> ParameterFile:
    """A published rigid-Earth principal nutation: ``rigid_earth_nutation`` (REN-2000's 18.6-year term) or a file.

    Its ``nutation_longitude``, ``nutation_obliquity`` and ``dynamical_flattening``
    are required; a file without them, or with a flattening outside (0, 1), is a
    FileFormatError naming the key.
    """
    text = os.fspath(name)
    if Path(text).is_file():
        pf = _read(text, "nutation_reference", NUTATION_REFERENCE_UNITS)
    else:
        entry = _dir() / f"{text.strip().lower()}.toml"
        if not entry.is_file():
            raise InputError(
                "nutation reference", text, "rigid_earth_nutation, or the path of a nutation_reference file"
            )
        with resources.as_file(entry) as path:
            pf = _read(path, "nutation_reference", NUTATION_REFERENCE_UNITS)
    for key in ("nutation_longitude", "nutation_obliquity", "dynamical_flattening"):
        pf.require(key, "the comparison of the principal nutation with a rigid-Earth series")
    h = measured(pf, "dynamical_flattening", _ONE)
    if not 0.0 < h.value < 1.0:
        raise FileFormatError(pf.path, "parameters.dynamical_flattening.value", f"got {h.value!r}; allowed: 0 < H < 1")
    return pf
