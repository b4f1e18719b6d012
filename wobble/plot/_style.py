"""Small conventions shared by wobble's figures."""

from __future__ import annotations

__all__ = ["time_axis"]

_YEAR = 365.25 * 86400.0


def time_axis(span_s: float) -> tuple[float, str]:
    """(seconds per unit, unit name) for a time axis spanning ``span_s`` seconds.

    >>> time_axis(200.0), time_axis(3e7)
    ((1.0, 's'), (86400.0, 'd'))
    """
    for limit, size, name in (
        (300.0, 1.0, "s"),
        (3 * 3600.0, 60.0, "min"),
        (3 * 86400.0, 3600.0, "h"),
        (3 * _YEAR, 86400.0, "d"),
    ):
        if span_s < limit:
            return size, name
    return _YEAR, "yr"
