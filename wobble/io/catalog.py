"""The planet catalogue (``data/bodies/*.toml``) and users' own planet files.

Reads the ``wobble/1`` schema (:mod:`wobble.io.parameter_file`) with
``kind = "planet"``, checks every parameter's unit against what it means, and
converts once to SI into :class:`wobble.models.planet.PlanetParameters`.
"""

from __future__ import annotations

import math
import os
from importlib import resources
from pathlib import Path

from astropy import constants as const
from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.parameter_file import ParameterFile, read_parameter_file, wrong_unit
from wobble.io.quantity_values import float64_value
from wobble.models.planet import POSITIVE_KEYS, Measured, PlanetParameters

__all__ = ["PLANET_UNITS", "catalogue_names", "catalogue_file", "load_planet", "planet_from_file"]

_ONE = u.dimensionless_unscaled
# Every key a planet file may hold, with the SI unit it is converted to.
PLANET_UNITS: dict[str, u.UnitBase] = {
    "gm": u.m**3 / u.s**2,
    "equatorial_radius": u.m,
    "rotation_rate": u.rad / u.s,
    "rotation_period": u.s,
    "gravitational_constant": u.m**3 / (u.kg * u.s**2),
    "dynamical_flattening": _ONE,
    "j2": _ONE,
    "c20": _ONE,
    "polar_moment_factor": _ONE,
    "c22": _ONE,
    "s22": _ONE,
    "love_number_k2": _ONE,
    "love_number_k2_period": u.s,
    "love_number_k2_imaginary": _ONE,
    "love_number_k2_imaginary_period": u.s,
    "anelastic_exponent": _ONE,
    "ocean_pole_tide_love_number": _ONE,
    "fluid_core_equatorial_moment": u.kg * u.m**2,
    "fluid_core_radius": u.m,
    "fluid_core_density": u.kg / u.m**3,
    "observed_chandler_period": u.s,
    # Forced precession (wobble precession).
    "obliquity": u.rad,
    "orbit_semi_major_axis": u.m,
    "orbit_eccentricity": _ONE,
    "observed_precession_rate": u.rad / u.s,
    "observed_precession_includes_geodesic": _ONE,
    # interior and free core nutation (wobble modes)
    "core_compliance_beta": _ONE,
    "core_compliance_gamma": _ONE,
    "observed_fcn_period": u.s,
    "core_flattening_excess": _ONE,
}


#: Upper bounds set by nature. H = (C - Abar)/C: A + B >= C for any body, so H <= 1/2. C/(M a^2): mass
#: within a of the axis gives at most 1, and a near-spherical body at most 2/3, all of it in a thin shell at the
#: surface (a uniform sphere has 0.4).
_AT_MOST = {
    "dynamical_flattening": (
        0.5,
        "at most 1/2 (the moments' triangle inequality A + B >= C; Earth's H is 3.27e-3)",
    ),
    "polar_moment_factor": (
        2.0 / 3.0,
        "at most 2/3 (all the mass in a thin shell at the surface; a uniform sphere has 0.4)",
    ),
}

#: Lower bounds set by nature: a compliance is a deformation per unit forcing, which an elastic mantle never gives
#: with the opposite sign (beta <= -1 left the FCN's e_f - beta and its messages meaningless).
_AT_LEAST = {
    "core_compliance_beta": (0.0, "at least 0 (a compliance; Mathews et al. 2002 give 6.16e-4 for Earth)"),
    "core_compliance_gamma": (0.0, "at least 0 (a compliance; Mathews et al. 2002 give 1.9662e-3 for Earth)"),
}
#: Signed values that must not be zero.
_NON_ZERO = {"observed_fcn_period": "a non-zero period, signed relative to the spin (negative: retrograde)"}


def _bodies_dir():
    return resources.files("wobble._data") / "bodies"


def catalogue_names() -> list[str]:
    """Names of the catalogued planets (``earth``, ``mars``, ...), sorted."""
    return sorted(p.name[:-5] for p in _bodies_dir().iterdir() if p.name.endswith(".toml"))


def catalogue_file(name: str):
    """Path of the catalogue file of ``name`` (case-insensitive)."""
    key = name.strip().lower()
    if key not in catalogue_names():
        raise InputError("body", name, f"one of {', '.join(catalogue_names())} (or a planet file: --body-file)")
    return _bodies_dir() / f"{key}.toml"


def _typed(param) -> str:
    """A parameter's value as the file gives it, with the file's unit."""
    return f"{param.value.value.item():g} {param.unit_text or param.value.unit.to_string()}".strip()


def _si(pf: ParameterFile, key: str) -> Measured | None:
    param = pf.get(key)
    if param is None:
        return None
    unit = PLANET_UNITS[key]
    where = f"parameters.{key}"
    if param.value.size != 1:
        raise FileFormatError(pf.path, f"{where}.value", "must be a single number")
    try:
        # float64_value: no equivalencies, and an overflow is inf (refused below) without astropy's warning first.
        value = float(float64_value(param.value, unit))
        sigma = float(float64_value(param.uncertainty, unit))
    except u.UnitConversionError:
        raise wrong_unit(pf, key, unit) from None
    typed = _typed(param)
    if not (math.isfinite(value) and math.isfinite(sigma)):  # 1e300 AU overflows in metres
        raise FileFormatError(
            pf.path, f"{where}.value", f"got {typed}; allowed: a value and uncertainty finite in SI ({unit})"
        )
    if key in (*POSITIVE_KEYS, "rotation_period") and not value > 0:
        raise FileFormatError(pf.path, f"{where}.value", f"got {typed}; allowed: a positive number")
    if key in _AT_MOST and not value <= _AT_MOST[key][0]:
        raise FileFormatError(pf.path, f"{where}.value", f"got {typed}; allowed: {_AT_MOST[key][1]}")
    if key in _AT_LEAST and not value >= _AT_LEAST[key][0]:
        raise FileFormatError(pf.path, f"{where}.value", f"got {typed}; allowed: {_AT_LEAST[key][1]}")
    if key in _NON_ZERO and value == 0:
        raise FileFormatError(pf.path, f"{where}.value", f"got {typed}; allowed: {_NON_ZERO[key]}")
    return Measured(value, sigma)


def _either(pf: ParameterFile, first: str, second: str):
    if pf.get(first) is not None and pf.get(second) is not None:
        raise FileFormatError(pf.path, f"parameters.{second}", f"give either {first} or {second}, not both")


def planet_from_file(pf: ParameterFile) -> PlanetParameters:
    """Convert a parsed planet file to SI :class:`PlanetParameters`.

    Raises
    ------
    wobble.errors.FileFormatError
        A wrong unit or value, naming the file and key.
    """
    _either(pf, "rotation_rate", "rotation_period")
    _either(pf, "j2", "c20")
    rate = _si(pf, "rotation_rate")
    if rate is None:
        period = _si(pf, "rotation_period")
        if period is None:
            raise FileFormatError(pf.path, "parameters.rotation_rate", "missing; give rotation_rate or rotation_period")
        # sigma_Omega = Omega sigma_P / P: (2 pi sigma_P) / P^2 overflowed P^2 at 1e300 s and divided by an
        # underflowed one at 1e-300 s (tracebacks).
        omega = 2 * math.pi / period.value
        if not math.isfinite(omega):
            raise FileFormatError(
                pf.path,
                "parameters.rotation_period.value",
                f"got {_typed(pf.get('rotation_period'))}; allowed: a period whose rate 2 pi / P is a finite float",
            )
        rate = Measured(omega, omega * (period.sigma / period.value))
    j2 = _si(pf, "j2")
    c20 = _si(pf, "c20")
    if c20 is not None:
        # J2 = -sqrt(5) C20 for fully normalised coefficients.
        j2 = Measured(-math.sqrt(5.0) * c20.value, math.sqrt(5.0) * c20.sigma)
    g = _si(pf, "gravitational_constant") or Measured(const.G.si.value, const.G.si.uncertainty)
    kwargs = {
        key: _si(pf, key)
        for key in PLANET_UNITS
        if key not in ("rotation_rate", "rotation_period", "j2", "c20", "gravitational_constant")
    }
    try:
        return PlanetParameters(name=pf.name, rotation_rate=rate, gravitational_constant=g, j2=j2, **kwargs)
    except InputError as exc:
        named = exc.parameter
        if pf.get("rotation_period") is not None:  # the rate was the file's period: name what the file gives
            named = named.replace("rotation_rate", "rotation_period")
        raise FileFormatError(pf.path, f"parameters ({named})", f"{exc.value}; needs {exc.allowed}") from None


def load_planet(body: str | os.PathLike) -> tuple[PlanetParameters, ParameterFile]:
    """Load a catalogued planet by name, or a planet file by path.

    Parameters
    ----------
    body : str or path-like
        ``"earth"``, ``"Mars"``, or a path to a ``wobble/1`` planet file. A path object
        (:class:`pathlib.Path`) is always a file, even one named ``earth``; a string is a
        catalogue name first.

    Returns
    -------
    (PlanetParameters, ParameterFile)
        The SI description and the parsed file (values with sources).
    """
    if not isinstance(body, (str, os.PathLike)):  # None or 3 raised a bare TypeError from os.fspath
        raise InputError("body", repr(body), f"one of {', '.join(catalogue_names())}, or the path of a planet file")
    text = os.fspath(body)
    if not isinstance(body, os.PathLike) and text.strip().lower() in catalogue_names():
        with resources.as_file(catalogue_file(text)) as path:
            pf = read_parameter_file(path, kind="planet", known=set(PLANET_UNITS))
    elif Path(text).is_file():
        pf = read_parameter_file(text, kind="planet", known=set(PLANET_UNITS))
    else:
        raise InputError("body", text, f"one of {', '.join(catalogue_names())}, or the path of a planet file")
    return planet_from_file(pf), pf
