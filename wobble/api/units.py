"""Units at the boundary: the one place Quantities become SI floats.

Public functions call :func:`to_si` once per dimensional argument on the way
in and attach units once on the way out (``value << u.s``). A plain number
where a dimension is required is an :class:`~wobble.errors.InputError`,
never a guess. The command line reads its dimensional arguments with
:func:`parse_quantity` and :func:`parse_angle` (a bare number is SI, or degrees).
"""

from __future__ import annotations

import contextlib
import math

import numpy as np
from astropy import units as u

from wobble.errors import InputError
from wobble.io.quantity_values import NotReal, float64_value, quantity_from_text, real_float
from wobble.io.text import is_number
from wobble.numerics.floats import HUGE

__all__ = [
    "to_si",
    "dimensionless",
    "parse_quantity",
    "parse_quantities",
    "parse_duration",
    "parse_angle",
    "describe_unit",
    "spin_rate_si",
]

# Examples shown in error messages, by physical type.
_EXAMPLES = {
    "time": "1 d, 86164.1 s",
    "angular speed": "7.292115e-05 rad / s, 360 deg / d",
    "angular frequency": "7.292115e-05 rad / s, 360 deg / d",
    "moment of inertia": "8.0e37 kg m2, 1 g cm2",
    "mass": "5.97e24 kg",
    "length": "6378136.6 m, 1 au",
    "angle": "0.5 rad, 30 deg",
    "mass density": "5510 kg / m3, 5.5 g / cm3",
    "acceleration": "9.81 m / s2",
    "gravitational parameter": "3.986004418e14 m3 / s2",
    "torque": "1 N m",
    "the gravitational constant": "6.6743e-11 m3 / (kg s2)",
}


def describe_unit(unit: u.UnitBase) -> str:
    """Name the physical type of ``unit`` with examples, for error messages."""
    kind = str(unit.physical_type)
    if unit.is_equivalent(u.m**3 / u.s**2, equivalencies=None):
        kind = "gravitational parameter"
    if unit.is_equivalent(u.rad / u.s, equivalencies=None):
        kind = "angular speed"
    if unit.is_equivalent(u.kg * u.m**2, equivalencies=None):
        kind = "moment of inertia"
    if unit.is_equivalent(u.m**3 / u.kg / u.s**2, equivalencies=None):
        kind = "the gravitational constant"  # astropy has no name for it ("unknown")
    if kind == "unknown":
        kind = unit.to_string()
    example = _EXAMPLES.get(kind, f"1 {unit.to_string()}")
    return f"a Quantity with units of {kind} (e.g. {example})"


def _not_a_quantity(value, unit: u.UnitBase) -> tuple[object, str]:
    """The value as an error shows it and what to say about it, for a value that is not a Quantity.

    A string was told "a plain number has no unit" and shown unquoted (``got 433 d``), as if it had one.
    """
    allowed = describe_unit(unit)
    if isinstance(value, str):
        return repr(value), f"{allowed}; a string is not a Quantity (u.Quantity({value!r}) makes one)"
    try:
        numeric = np.asarray(value).dtype.kind in "biufc"
    except Exception:  # an object NumPy cannot even hold
        numeric = False
    if numeric:
        return value, f"{allowed}; a plain number has no unit"
    if value is None:
        return value, f"{allowed}; None is not a Quantity"
    if isinstance(value, (list, tuple)) and any(isinstance(v, u.Quantity) for v in value):
        return value, f"{allowed}; a {type(value).__name__} of Quantities is not one (u.Quantity(...) makes one)"
    return value, f"{allowed}; a {type(value).__name__} is not a Quantity"


def to_si(
    value,
    name: str,
    unit: u.UnitBase,
    *,
    positive: bool = False,
    nonnegative: bool = False,
    finite: bool = True,
    shape: tuple[int, ...] | None = None,
    equivalencies=None,
):
    """Convert a Quantity to a float (or float64 array) in ``unit``, checking it.

    Parameters
    ----------
    value : astropy.units.Quantity
        The user's value. Plain numbers are refused for dimensional quantities.
    name : str
        Parameter name used in error messages.
    unit : astropy.units.UnitBase
        Target (SI) unit, e.g. ``u.s`` or ``u.kg * u.m**2``.
    positive, nonnegative, finite : bool
        Checks applied element-wise after conversion.
    shape : tuple of int, optional
        Required shape (``()`` for a scalar).
    equivalencies : list, optional
        Passed to :meth:`~astropy.units.Quantity.to_value`.

    Returns
    -------
    float or numpy.ndarray
        A Python float for scalars, a float64 array otherwise.

    Raises
    ------
    wobble.errors.InputError
        Not a Quantity, incompatible unit, wrong shape, non-finite or out of range.
    """
    # The unit's description (for the error messages) is formed only when one is raised:
    # it costs more than the conversion itself.
    if not isinstance(value, u.Quantity):
        raise InputError(name, *_not_a_quantity(value, unit))
    # A finite value whose conversion overflows (1e300 Msun in kg) becomes inf and is refused
    # below with one line, without NumPy's overflow warning on stderr before it.
    with np.errstate(over="ignore"):
        try:
            # Plain conversion first (wobble.io.quantity_values: float64, a copy, no equivalencies at
            # all, not even any the caller enabled globally: dimensionless_angles() read 10 Hz as
            # 10 rad/s); astropy tries it first with equivalencies too (same result), and the
            # equivalencies' set-up costs several times the conversion.
            si = float64_value(value, unit)
        except NotReal as exc:
            raise InputError(name, value, f"{exc} ({describe_unit(unit)})") from None
        except u.UnitConversionError:
            if not equivalencies:
                raise InputError(name, value, describe_unit(unit)) from None
            try:
                si = np.asarray(value.to_value(unit, equivalencies=equivalencies), dtype=float)
            except u.UnitConversionError:
                raise InputError(name, value, describe_unit(unit)) from None
    if shape is not None and si.shape != shape:
        want = "a scalar" if shape == () else f"shape {shape}"
        raise InputError(name, value, f"{want} ({describe_unit(unit)})")
    if si.ndim == 0:  # a scalar: Python comparisons, no array reductions
        x = float(si)
        if finite and not math.isfinite(x):
            raise InputError(name, value, _finite_allowed(value, unit))
        if positive and not x > 0:
            raise InputError(name, value, f"positive values ({describe_unit(unit)})")
        if nonnegative and not x >= 0:
            raise InputError(name, value, f"non-negative values ({describe_unit(unit)})")
        return x
    if finite and not np.all(np.isfinite(si)):
        raise InputError(name, value, _finite_allowed(value, unit))
    if positive and not np.all(si > 0):
        raise InputError(name, value, f"positive values ({describe_unit(unit)})")
    if nonnegative and not np.all(si >= 0):
        raise InputError(name, value, f"non-negative values ({describe_unit(unit)})")
    return si


def freeze_quantities(obj) -> None:
    """Make every Quantity field of the frozen dataclass ``obj`` read-only: a result hands out its own
    values, and ``budget.period[...] = 1 * u.d`` edited the budget (its to_dict said 1.0 d after)."""
    import dataclasses

    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, u.Quantity):
            value.flags.writeable = False


def plain_array(value, name: str, allowed: str) -> np.ndarray:
    """A new float64 array from plain numbers or a dimensionless Quantity (a quaternion, a unit
    vector); a Quantity with a unit, text, masked or complex values are refused naming ``name``
    (a quaternion in degrees was taken as numbers; "identity" raised a bare ValueError)."""
    if isinstance(value, u.Quantity):
        try:
            return float64_value(value, u.dimensionless_unscaled)
        except (u.UnitConversionError, NotReal):
            raise InputError(name, value, allowed) from None
    try:
        return np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(name, value, allowed) from None


def _finite_allowed(value: u.Quantity, unit: u.UnitBase) -> str:
    """What a non-finite conversion is told: finite values, or values that fit a double in ``unit``."""
    if np.all(np.isfinite(value.value)):  # finite as typed: the conversion overflowed
        return f"values that stay finite in {unit.to_string()} (at most {HUGE:.3g} {unit.to_string()})"
    return "finite values (no NaN or inf)"


def dimensionless(value, name: str, *, low=None, high=None, open_interval: bool = True):
    """Check a plain dimensionless ratio (float or dimensionless Quantity).

    Parameters
    ----------
    value : float or astropy.units.Quantity
        The ratio. A Quantity must be dimensionless.
    name : str
        Parameter name for error messages.
    low, high : float, optional
        Bounds; open by default (e.g. a ratio in (-1, 1)).
    open_interval : bool
        Whether the bounds are excluded.

    Returns
    -------
    float
    """
    if isinstance(value, u.Quantity):
        try:
            value = value.to_value(u.dimensionless_unscaled, equivalencies=None)
        except u.UnitConversionError:
            raise InputError(name, value, "a dimensionless number") from None
    if np.ndim(value) != 0:  # an array of ratios was told "a dimensionless number", which it is
        raise InputError(name, value, "a scalar: one dimensionless number")
    try:
        x = real_float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, "a dimensionless number") from None
    bounds = _interval_text(low, high, open_interval)
    if not np.isfinite(x):
        raise InputError(name, value, f"a finite number {bounds}".strip())
    too_low = low is not None and (x <= low if open_interval else x < low)
    too_high = high is not None and (x >= high if open_interval else x > high)
    if too_low or too_high:
        raise InputError(name, value, f"a number {bounds}")
    return x


def _interval_text(low, high, open_interval: bool) -> str:
    if low is None and high is None:
        return ""
    left = "(" if open_interval else "["
    right = ")" if open_interval else "]"
    lo = "-inf" if low is None else f"{low:g}"
    hi = "inf" if high is None else f"{high:g}"
    return f"in {left}{lo}, {hi}{right}"


def spin_rate_si(spin, name: str = "spin") -> float:
    """Angular rate in rad/s from either a rate or a rotation period.

    A time is read as the rotation period P (rate 2 pi / P); an angular speed
    is used as it is. Signed rates are allowed (the sense of rotation matters
    for the direction of the wobble); a period must be positive.
    """
    if isinstance(spin, u.Quantity) and spin.unit.is_equivalent(u.s, equivalencies=None):
        period = to_si(spin, name, u.s, positive=True, shape=())
        return 2.0 * np.pi / period
    if isinstance(spin, u.Quantity) and spin.unit.is_equivalent(u.rad / u.s, equivalencies=None):
        return to_si(spin, name, u.rad / u.s, shape=())
    raise InputError(
        name,
        spin,
        "an angular speed (e.g. 7.292115e-05 rad / s) or a rotation period (e.g. 1 sday, 24.6229 h)",
    )


@contextlib.contextmanager
def as_given(**given):
    """Show a model's refusal of one of ``given`` with the value as the caller gave it, unit and all.

    The models work in SI floats, so their InputError showed ``mgl: got -1.0`` for ``mgl=-1 * u.J``
    (and ``I3: got 2.5`` for a moment given in kg m2). A refusal naming another parameter, or one whose
    value is text, passes unchanged.
    """
    try:
        yield
    except InputError as exc:
        typed = given.get(exc.parameter)
        if not isinstance(typed, u.Quantity) or isinstance(exc.value, (str, u.Quantity)):
            raise
        raise InputError(exc.parameter, typed, exc.allowed) from None


def parse_quantity(text: str, name: str, default_unit: u.UnitBase) -> u.Quantity:
    """Parse command-line text such as ``"1 d"`` or ``"3"`` into a Quantity.

    A bare number takes ``default_unit`` (the CLI documents SI defaults); text
    with a unit must be convertible to ``default_unit``.
    """
    text = text.strip()
    try:
        return float(text) * default_unit
    except ValueError:
        pass
    try:
        q = quantity_from_text(text)
    except (TypeError, ValueError):
        raise InputError(name, text, f"a number with an optional unit ({describe_unit(default_unit)})") from None
    if not q.unit.is_equivalent(default_unit, equivalencies=None):
        raise InputError(name, text, describe_unit(default_unit))
    return q


def parse_duration(text: str, name: str, example: str) -> float:
    """Parse a command-line time span (``"100"`` in s, ``"2 d"``) into seconds, positive and finite.

    A finite span whose conversion to seconds overflows (``1.7e308 d``) is refused like an
    infinite one, without NumPy's overflow warning on stderr before the line.
    """
    q = parse_quantity(text, name, u.s)
    with np.errstate(over="ignore"):
        seconds = float(q.to_value(u.s))
    if not (math.isfinite(seconds) and seconds > 0):
        raise InputError(name, text, f"a positive, finite time (e.g. {example})")
    return seconds


def parse_quantities(texts, name: str, default_unit: u.UnitBase) -> u.Quantity:
    """Parse the values of a vector option (``--inertia 1 2 3``) into one Quantity.

    A unit on the first value only applies to all of them, as a physicist writes a vector
    (``"1 g cm2" 2 3`` is (1, 2, 3) g cm2, and keeps that unit, so an error about it shows
    the user's numbers); otherwise each value is read alone, a bare number in ``default_unit``
    (``7.292115e-11 0 "360.98 deg/d"``).
    """
    texts = [t.strip() for t in texts]
    bare = [is_number(t) for t in texts]
    if all(bare):
        return u.Quantity([float(t) for t in texts], default_unit)
    first = parse_quantity(texts[0], name, default_unit)
    if not bare[0] and all(bare[1:]):
        return u.Quantity([first.value, *(float(t) for t in texts[1:])], first.unit)
    parts = [parse_quantity(t, name, default_unit) for t in texts]
    with np.errstate(over="ignore"):  # a finite value that overflows in the first one's unit is refused below
        values = [p.to(first.unit) for p in parts]
    for text, part, value in zip(texts, parts, values):
        if not np.isfinite(value.value) and np.isfinite(part.value):
            raise InputError(name, text, _finite_allowed(part, first.unit))
    return u.Quantity(values)


def parse_angle(text: str, name: str) -> u.Quantity:
    """Parse a command-line angle: a bare number is degrees, as people write tilts.

    ``"30"`` and ``"30 deg"`` are 30 degrees; ``"0.5 rad"`` is half a radian.
    JSON output speaks degrees too (``theta_min_deg``), so one number means one
    thing on the way in and on the way out.
    """
    return parse_quantity(text, name, u.deg)
