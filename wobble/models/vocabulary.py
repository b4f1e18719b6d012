"""One name per concept, from the models to the command line and the files.

Regimes of free rotation, nutation classes of the heavy top, frames, axis labels and the
unit suffixes of JSON keys are defined here once and used by the models, the sweeps, the
command line and the netCDF files (CF ``flag_meanings`` come from :func:`flag_meanings`).
The enumerations are ``str`` enumerations: a member compares equal to its value
(``Regime.MAJOR_AXIS == "major-axis"``) and prints and serialises as it.
"""

from __future__ import annotations

from enum import StrEnum

__all__ = [
    "Regime",
    "NutationClass",
    "Frame",
    "BODY_AXES",
    "INERTIAL_AXES",
    "QUATERNION_COMPONENTS",
    "UNIT_SUFFIXES",
    "flag_meanings",
]


class _Names(StrEnum):
    """Names that are plain strings: ``str(member)`` and f-strings give the value."""


class Regime(_Names):
    """How a torque-free body rotates (Landau & Lifshitz section 37).

    ``major-axis``: the angular velocity circulates about the axis of the largest moment
    (L^2 > 2 E I2; for a tumbling asteroid, the short-axis mode, SAM); ``minor-axis``: about
    the axis of the smallest moment (L^2 < 2 E I2; the long-axis mode, LAM).
    """

    STEADY = "steady"
    SYMMETRIC = "symmetric"
    MAJOR_AXIS = "major-axis"
    MINOR_AXIS = "minor-axis"
    SEPARATRIX = "separatrix"


class NutationClass(_Names):
    """How the heavy symmetric top's figure axis moves (Goldstein, Poole & Safko 2002, sec. 5.7)."""

    UNDULATING = "undulating"
    CUSPS = "cusps"
    LOOPS = "loops"
    REGULAR = "regular"  # regular precession: no nutation
    SLEEPING = "sleeping"


class Frame(_Names):
    """Where a vector is fixed: in the body, or in inertial space."""

    BODY = "body"
    INERTIAL = "inertial"


#: Labels of body axes (the user's body frame), inertial axes (Z up for a top under gravity)
#: and quaternion components (scalar first), as netCDF coordinates and in JSON.
BODY_AXES = ("1", "2", "3")
INERTIAL_AXES = ("X", "Y", "Z")
QUATERNION_COMPONENTS = ("w", "x", "y", "z")

#: The suffix a JSON key carries for its unit (a dimensionless number has none).
UNIT_SUFFIXES = {
    "s": "_s",
    "d": "_days",
    "yr": "_yr",
    "deg": "_deg",
    "rad": "_rad",
    "rad s-1": "_rad_per_s",
    "mas": "_mas",
    "mas yr-1": "_mas_per_yr",
    "arcsec cy-1": "_arcsec_per_century",
    "kg": "_kg",
    "m": "_m",
    "kg m2": "_kg_m2",
    "kg m2 s-1": "_kg_m2_per_s",
    "J": "_J",
    "N m": "_N_m",
}


def flag_meanings(names, invalid: str | None = None) -> str:
    """CF ``flag_meanings`` for codes 0, 1, ... (or -1 for ``invalid``, then 0, 1, ...).

    The names as they are: CF allows hyphens in flag meanings (``major-axis``), so a
    class reads the same in a file, in JSON and in the API.
    """
    return " ".join(([invalid] if invalid else []) + [str(n) for n in names])
