"""Dates as users write them, and the Modified Julian Dates (UTC) the IERS files use.

>>> to_mjd("2015-06", "start"), to_mjd("2000.5", "end"), iso_date(51544.0)
(57174.0, 51727.0, '2000-01-01')

A date is a string (``2015-01-01``, ``2015-06``, ``2015`` or ``2015.5``), an
:class:`astropy.time.Time`, a :class:`datetime.date` or :class:`datetime.datetime`,
or a :class:`numpy.datetime64`; anything else, or a string that is not a date,
is an :class:`~wobble.errors.InputError` naming the parameter.
"""

from __future__ import annotations

import datetime as _dt
import math
import re
import warnings

import numpy as np
from astropy.time import Time

from wobble.errors import InputError

__all__ = ["DATE_HELP", "MJD_UNITS", "to_mjd", "iso_date", "mjd_time", "select_dates", "cf_time_to_mjd"]

DATE_HELP = "a UTC date such as 2015-01-01, 2015-06, 2015 or 2015.5 (an astropy Time or datetime also works)"
#: CF units of wobble's time coordinates for dated series: the Modified Julian Date.
MJD_UNITS = "days since 1858-11-17 00:00:00"


def to_mjd(value, name: str) -> float:
    """A user's date as MJD (UTC); ``name`` is the parameter named in the error."""
    try:
        from erfa import ErfaWarning
    except ImportError:  # pragma: no cover - erfa ships with astropy
        ErfaWarning = Warning
    try:
        with warnings.catch_warnings():
            # Dates before 1960 or past the leap-second table are "dubious" to ERFA
            # only for their UTC seconds; as calendar dates they are exact.
            warnings.simplefilter("ignore", ErfaWarning)
            if isinstance(value, Time):
                return float(value.utc.mjd)
            if isinstance(value, _dt.date) and not isinstance(value, _dt.datetime):
                value = _dt.datetime(value.year, value.month, value.day)
            if isinstance(value, (_dt.datetime, np.datetime64)):
                return float(Time(value, scale="utc").mjd)
            if isinstance(value, str):
                text = value.strip()
                if re.fullmatch(r"\d{4}(\.\d*)?", text):
                    return float(Time(float(text), format="decimalyear", scale="utc").mjd)
                if re.fullmatch(r"\d{4}-\d{1,2}", text):
                    text += "-01"
                return float(Time(text, scale="utc").mjd)
    except (ValueError, TypeError):
        pass
    if isinstance(value, (int, float, np.integer, np.floating)):
        # The help lists 2015 and 2015.5, as text: a number could be a year or an MJD, so it is not guessed.
        raise InputError(name, value, f"{DATE_HELP}; a year as text ('2015'), not a number (a year or an MJD?)")
    raise InputError(name, value, DATE_HELP)


def iso_date(when) -> str:
    """The calendar date (UTC) of an MJD or an astropy Time, ``YYYY-MM-DD``.

    By calendar arithmetic (MJD 0 is 1858-11-17), not ERFA's: a UTC date before 1960 or past the
    leap-second table is exact as a date, and ERFA's "dubious year" warning would only be noise.
    """
    mjd = float(when.utc.mjd) if isinstance(when, Time) else float(when)
    if not abs(mjd) < 1e9:  # millions of years from now (or not a number): no calendar date to print
        return f"MJD {mjd:g}"
    return str(np.datetime64("1858-11-17", "D") + np.timedelta64(math.floor(mjd), "D"))


def mjd_time(mjd: float) -> Time:
    """An MJD (UTC) as an astropy Time."""
    return Time(mjd, format="mjd", scale="utc")


def select_dates(mjd: np.ndarray, start, end, what: str = "the data") -> np.ndarray:
    """The mask of ``mjd`` from ``start`` to ``end`` inclusive (None: the first or last date).

    A date outside ``mjd`` is an error naming the span (``what`` says whose),
    never a silently shorter series; so is an empty span, naming the date given
    (``start`` when it is the only one, on or after the last day).
    """
    first, last = float(mjd[0]), float(mjd[-1])
    span = f"a date from {iso_date(first)} to {iso_date(last)} ({what})"
    lo = first if start is None else to_mjd(start, "start")
    hi = last if end is None else to_mjd(end, "end")
    if not first - 0.5 <= lo <= last:
        raise InputError("start", start, span)
    if not first <= hi <= last + 0.5:
        raise InputError("end", end, span)
    if hi <= lo:
        # The option given is the one at fault: a start on the last day with no end had named 'end' and
        # printed Python's None ("end: got None; allowed: a date after start").
        if end is None:
            raise InputError("start", start, f"a date before {iso_date(last)}, the last day of {what}")
        if start is None:
            raise InputError("end", end, f"a date after {iso_date(first)}, the first day of {what}")
        raise InputError("end", end, f"a date after start ({iso_date(lo)})")
    return (mjd >= lo) & (mjd <= hi)


def cf_time_to_mjd(values, units: str) -> np.ndarray:
    """MJD (UTC) of a time coordinate: datetime64 values, or numbers in CF units ``<unit> since <date>``."""
    values = np.asarray(values)
    if np.issubdtype(values.dtype, np.datetime64):
        return np.asarray(Time(values, scale="utc").mjd, dtype=float)
    units = str(units or "")
    match = re.fullmatch(r"\s*(days?|d|hours?|h|minutes?|min|seconds?|s)\s+since\s+(.+?)\s*", units)
    if not match:
        raise InputError("time", f"units {units!r}", f"CF time units such as '{MJD_UNITS}'")
    scale = {"d": 1.0, "h": 1 / 24, "m": 1 / 1440, "s": 1 / 86400}[match.group(1)[0]]
    epoch = to_mjd(match.group(2).replace(" ", "T", 1) if " " in match.group(2) else match.group(2), "time units epoch")
    return epoch + scale * np.asarray(values, dtype=float)
