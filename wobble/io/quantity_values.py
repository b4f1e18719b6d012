"""The plain float64 numbers of a user's Quantity in a unit, or why it has none.

One rule for every place that takes a Quantity from a user (:func:`wobble.api.units.to_si`, the
scene reader): the conversion runs in float64 whatever the input's dtype (a float32 day count
converted to seconds in float32 was 96 s off at a century); masked and complex values are refused
rather than stripped of their mask or imaginary part; no equivalency applies, not even one the
caller enabled for the whole process; and the result is a copy, never a view of the caller's
array (a scene's times or moments changed when the caller later changed its own array).
"""

from __future__ import annotations

import re

import numpy as np
from astropy import units as u

__all__ = ["float64_value", "real_float", "NotReal", "quantity_from_text"]


class NotReal(ValueError):
    """A Quantity whose values are masked or complex: the reason, for the caller's error message."""


def float64_value(value: u.Quantity, unit: u.UnitBase) -> np.ndarray:
    """``value`` in ``unit`` as a new float64 array (0-d for a scalar).

    Raises
    ------
    astropy.units.UnitConversionError
        The units are not convertible (no equivalencies).
    NotReal
        Masked or complex values.
    """
    from astropy.utils.masked import Masked

    if isinstance(value, Masked):
        raise NotReal("unmasked values (a masked Quantity's hidden entries would be used)")
    if np.iscomplexobj(value):
        raise NotReal("real values (an imaginary part would be dropped)")
    if value.dtype != np.float64:  # before the conversion: a float32 day in seconds loses digits
        value = value.astype(np.float64)
    with np.errstate(over="ignore"):  # an overflow is inf, refused by the callers in one line
        return np.array(value.to_value(unit, equivalencies=None), dtype=np.float64)


def real_float(value) -> float:
    """``float(value)`` of a real number (int, float, NumPy scalar, Fraction, Decimal); TypeError for
    text, bools and complex numbers, which ``float`` reads ("0.003", True) or refuses unclearly."""
    if isinstance(value, (str, bytes, bool, np.bool_, complex, np.complexfloating)):
        raise TypeError(f"not a real number: {value!r}")
    return float(value)


_UNIT_WORD = re.compile(r"[A-Za-z_]+")


def _known_unit(word: str) -> bool:
    try:
        u.Unit(word, parse_strict="raise")
    except ValueError:
        return False
    return True


def _singular(match: re.Match) -> str:
    word = match.group(0)
    if word.endswith("s") and len(word) > 2 and not _known_unit(word) and _known_unit(word[:-1]):
        return word[:-1]
    return word


def quantity_from_text(text: str) -> u.Quantity:
    """``u.Quantity(text)``, also for units in the plural as people write them ("90 days", "3 years",
    "60 degrees", "2 hours"), which astropy does not parse: a word astropy does not know but knows
    without its final s is read in the singular. A word astropy knows (``mas``, ``Ms``) is never changed.

    Raises
    ------
    TypeError, ValueError
        As ``u.Quantity`` for text that is not a quantity either way.
    """
    try:
        return u.Quantity(text)
    except (TypeError, ValueError):
        singular = _UNIT_WORD.sub(_singular, text)
        if singular == text:
            raise
        return u.Quantity(singular)
