"""argparse value types whose refusals read like every other wobble error: the option, what was typed,
what is allowed (``--samples: got 2.5; allowed: a whole number of at most 30 digits (1001, 1e3)``).

argparse's own ``type=int`` said ``argument --samples: invalid int value: '2.5'``: the option and the
value, but not what would do. The option's own range (``>= 2``) is checked after parsing, where the
command knows it.
"""

from __future__ import annotations

import argparse
import decimal
import math

from wobble.errors import shown

__all__ = ["whole_number", "real_number"]

# Whole numbers beyond this many digits are refused: no count wobble takes comes near, and "1e999999999"
# would otherwise be a Python int of a billion digits.
_DIGITS = 30


def whole_number(text: str) -> int:
    """A whole number as typed: ``1001``, ``1_000``, or a number with no fraction (``1e3``, ``10.0``).

    Read as the decimal it is written as (:class:`decimal.Decimal`), never through a float: ``1e16`` is
    10**16, ``9007199254740993.0`` is itself, and ``1e-400`` or ``1.0000000000000001`` are not whole.
    """
    try:
        return _bounded(int(text), text)  # Python's own rules: spaces around, single underscores between digits
    except ValueError:
        pass
    try:
        # Decimal takes "_1" and "1__0", which int refuses: a number with underscores is int's alone.
        value = None if "_" in text else decimal.Decimal(text)
    except (decimal.InvalidOperation, ValueError):
        value = None
    # The size first: int() of 1e999999999 would build a billion digits.
    if value is not None and value.is_finite() and value.adjusted() < _DIGITS and value == value.to_integral_value():
        return int(value)
    raise _refusal(text)


def _bounded(value: int, text: str) -> int:
    if len(str(abs(value))) > _DIGITS:
        raise _refusal(text)
    return value


def _refusal(text: str) -> argparse.ArgumentTypeError:
    return argparse.ArgumentTypeError(
        f"got {shown(text)}; allowed: a whole number of at most {_DIGITS} digits (1001, 1e3)"
    )


def real_number(text: str) -> float:
    """A number as typed (``1e-10``, ``0.5``); a finite one (``nan`` and ``inf`` are refused here)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if math.isfinite(value):
        return value
    raise argparse.ArgumentTypeError(f"got {shown(text)}; allowed: a finite number (1e-10, 0.5)")
