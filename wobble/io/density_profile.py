"""Radial density profiles (``data/profiles/*.toml``, ``kind = "density_profile"``).

A profile is a ``wobble/1`` parameter file (``data/README.md``) whose layers are
polynomials in r/scale, the form of PREM's Table 1 (Dziewonski & Anderson 1981):

* ``layer_top_radius``: the top of each layer, from the centre out (length);
* ``density_coefficients``: one row per layer, rho = sum_j c_j (r/scale)^j (density);
* ``normalising_radius``: the scale (length);
* optional ``fluid_core_inner_radius`` and ``fluid_core_outer_radius`` (length),
  both on layer boundaries; ``mass_tolerance`` (relative, allowed mismatch with
  the body's GM/G); anchors ``observed_flattening`` and
  ``reference_hydrostatic_flattening`` that results show beside their own.

The top-level key ``body`` names the catalogued planet a shipped profile
belongs to (``prem`` is Earth's). Conversion to SI happens here, once.
"""

from __future__ import annotations

import math

import os
from importlib import resources
from pathlib import Path

import numpy as np
from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.parameter_file import ParameterFile, read_parameter_file, wrong_unit
from wobble.io.shipped import not_a_file
from wobble.models.hydrostatic import DensityProfile, check_profile

__all__ = ["PROFILE_UNITS", "profile_names", "load_profile", "profile_for_body"]

_ONE = u.dimensionless_unscaled
PROFILE_UNITS: dict[str, u.UnitBase] = {
    "layer_top_radius": u.m,
    "density_coefficients": u.kg / u.m**3,
    "normalising_radius": u.m,
    "fluid_core_inner_radius": u.m,
    "fluid_core_outer_radius": u.m,
    "mass_tolerance": _ONE,
    "observed_flattening": _ONE,
    "reference_hydrostatic_flattening": _ONE,
}
_REQUIRED = ("layer_top_radius", "density_coefficients", "normalising_radius")


def _profiles_dir():
    return resources.files("wobble._data") / "profiles"


def profile_names() -> list[str]:
    """Names of the shipped profiles, sorted."""
    return sorted(p.name[:-5] for p in _profiles_dir().iterdir() if p.name.endswith(".toml"))


def _read(path) -> ParameterFile:
    return read_parameter_file(path, kind="density_profile", known=set(PROFILE_UNITS))


def _si(pf: ParameterFile, key: str):
    param = pf.get(key)
    if param is None:
        return None
    try:
        return np.asarray(param.value.to_value(PROFILE_UNITS[key]), dtype=float)
    except u.UnitConversionError:
        raise wrong_unit(pf, key, PROFILE_UNITS[key]) from None


def profile_from_file(pf: ParameterFile) -> DensityProfile:
    """SI :class:`DensityProfile` from a parsed profile file (checked)."""
    for key in _REQUIRED:
        pf.require(key, "a density profile")
    tops = _si(pf, "layer_top_radius").ravel()
    coeffs = _si(pf, "density_coefficients")
    if coeffs.ndim == 1:
        coeffs = coeffs[:, None] if tops.size > 1 else coeffs[None, :]
    if coeffs.ndim != 2 or coeffs.shape[0] != tops.size:
        raise FileFormatError(
            pf.path, "parameters.density_coefficients.value", f"one row of coefficients per layer ({tops.size} layers)"
        )
    scale = float(_si(pf, "normalising_radius"))
    if not scale > 0:
        raise FileFormatError(pf.path, "parameters.normalising_radius.value", "must be positive")
    tolerance = _si(pf, "mass_tolerance")
    if tolerance is not None and not (tolerance.size == 1 and 0 < float(tolerance) < math.inf):
        # A negative one was read and then printed as the limit ("allowed: within -0.001").
        got = ", ".join(f"{x:g}" for x in tolerance.ravel())
        raise FileFormatError(
            pf.path,
            "parameters.mass_tolerance.value",
            f"got {got}; allowed: one positive relative tolerance (1e-3 when not given)",
        )
    inner, outer = _si(pf, "fluid_core_inner_radius"), _si(pf, "fluid_core_outer_radius")
    if (inner is None) != (outer is None):
        raise FileFormatError(
            pf.path,
            "parameters.fluid_core_outer_radius",
            "give both fluid_core_inner_radius and fluid_core_outer_radius",
        )
    core = None if inner is None else (float(inner), float(outer))
    profile = DensityProfile(
        name=pf.name,
        edges=(0.0, *map(float, tops)),
        coeffs=tuple(tuple(map(float, row)) for row in coeffs),
        scale=scale,
        fluid_core=core,
    )
    try:
        check_profile(profile)
    except InputError as exc:
        raise FileFormatError(pf.path, f"parameters ({exc.parameter})", f"{exc.value}; needs {exc.allowed}") from None
    return profile


def load_profile(profile: str | os.PathLike) -> tuple[DensityProfile, ParameterFile]:
    """A shipped profile by name (``"prem"``, ``"mars_layered"``) or a profile file by path."""
    text = os.fspath(profile)
    if text.strip().lower() in profile_names():
        with resources.as_file(_profiles_dir() / f"{text.strip().lower()}.toml") as path:
            pf = _read(path)
    elif Path(text).is_file():
        pf = _read(text)
    else:
        # Why the path is not read (missing, a folder, empty), in the words every file option uses.
        raise InputError(
            "profile",
            text,
            f"one of {', '.join(profile_names())}, or the path of a density-profile file ({not_a_file(text)})",
        )
    return profile_from_file(pf), pf


def profile_for_body(body: str) -> str | None:
    """The shipped profile whose ``body`` is ``body`` (``"earth"`` -> ``"prem"``), or None."""
    for name in profile_names():
        with resources.as_file(_profiles_dir() / f"{name}.toml") as path:
            pf = _read(path)
        if str(pf.extra.get("body", "")).lower() == body.lower():
            return name
    return None
