"""argparse value types whose refusals read like every other wobble error: the option, what was typed,
what is allowed (``--samples: got 2.5; allowed: a whole number (1001, 1e3)``).

argparse's own ``type=int`` said ``argument --samples: invalid int value: '2.5'``: the option and the
value, but not what would do. The option's own range (``>= 2``) is checked after parsing, where the
command knows it.
"""

from __future__ import annotations

import argparse
import math

__all__ = ["whole_number", "real_number"]

# Above 2^53 not every whole number is a float: "1e300" names none exactly, and is refused (digits are not).
_EXACT = 2.0**53


def whole_number(text: str) -> int:
    """A whole number as typed: ``1001``, ``1_000``, or a float literal with no fraction (``1e3``, ``10.0``)."""
    try:
        return int(text)
    except ValueError:
        pass
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if math.isfinite(value) and value == math.floor(value) and abs(value) <= _EXACT:
        return int(value)
    raise argparse.ArgumentTypeError(f"got {text}; allowed: a whole number (1001, 1e3)")


def real_number(text: str) -> float:
    """A number as typed (``1e-10``, ``0.5``); a finite one (``nan`` and ``inf`` are refused here)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if math.isfinite(value):
        return value
    raise argparse.ArgumentTypeError(f"got {text}; allowed: a finite number (1e-10, 0.5)")
