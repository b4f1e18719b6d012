"""The IERS polar-motion record as an xarray Dataset with units, and the series the estimators take from it.

>>> import wobble
>>> data = wobble.load_polar_motion(start="2000-01-01", end="2004-12-31")
>>> data["x_p"].attrs["units"], data.sizes["time"]
('milliarcsecond', 1827)
>>> data["time"].attrs["units"]
'days since 1858-11-17 00:00:00'
"""

from __future__ import annotations

import math
import os
from dataclasses import replace

import numpy as np
from astropy import units as u

from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.io.dates import MJD_UNITS, cf_time_to_mjd, iso_date, select_dates
from wobble.io.eop import PoleRecord, read_pole_file
from wobble.models.polar_motion.record import DAY, complex_pole
from wobble.numerics.calendar import MJD_J2000

__all__ = [
    "MJD_UNITS",
    "MJD_J2000",
    "RAD_PER_ARCSEC",
    "RAD_PER_MAS",
    "C04_REFERENCE",
    "FINALS_REFERENCE",
    "SIGN_NOTE",
    "attrs",
    "time_coord",
    "load_polar_motion",
    "read_record",
    "record_attrs",
    "record_dataset",
    "record_series",
    "resolve_series",
    "series_with_attrs",
    "series",
    "mjd_values",
    "resolve_data",
    "short_span_error",
    "check_daily",
]

#: MJD of 2000-01-01 12:00; the origin of the models' seconds.
RAD_PER_ARCSEC = math.pi / (180.0 * 3600.0)
RAD_PER_MAS = RAD_PER_ARCSEC * 1e-3

C04_REFERENCE = (
    "IERS EOP 20 C04 series (IERS Earth Orientation Centre, Paris Observatory; consistent with ITRF 2020), "
    "https://hpiers.obspm.fr/eoppc/eop/eopc04/, as shipped by the astropy-iers-data package"
)
FINALS_REFERENCE = "IERS Rapid Service/Prediction Centre, Bulletin A (finals2000A), observed (I) rows only"
SIGN_NOTE = (
    "complex pole p = x_p - i y_p (x_p toward Greenwich, y_p toward 90 deg W); terms exp(+i sigma t) with "
    "sigma > 0 are prograde (counter-clockwise seen from above the north pole)"
)


def attrs(units: str, long_name: str, **extra) -> dict:
    """``units`` and ``long_name`` (and any extra) attributes of a variable."""
    return {"units": units, "long_name": long_name, **extra}


def time_coord(mjd, long_name="time (UTC)") -> tuple:
    """The CF time coordinate of a dated series, in MJD."""
    return (
        "time",
        np.asarray(mjd, dtype=float),
        {"units": MJD_UNITS, "calendar": "standard", "standard_name": "time", "axis": "T", "long_name": long_name},
    )


def read_record(file: str | os.PathLike | None = None, *, start=None, end=None) -> PoleRecord:
    """The pole coordinates of an IERS file from ``start`` to ``end``, as plain arrays (no Dataset).

    What :func:`load_polar_motion` holds, without xarray: the text and JSON of
    ``wobble polar-motion`` need only the arrays (xarray, pandas and, through
    xarray's duck-array check, dask cost about half a second to import).
    Parameters as in :func:`load_polar_motion`.

    Returns
    -------
    wobble.io.eop.PoleRecord
        The rows kept (MJD UTC; x_p, y_p and their errors in arcsec).
    """
    rec = read_pole_file(file)
    keep = select_dates(rec.mjd, start, end, f"the span of {os.path.basename(rec.path)}")
    if keep.sum() < 2:
        # The dates as given, or the file's own where one was not given (it printed "2026-09-28 to None").
        first = start if start is not None else iso_date(rec.mjd[0])
        given = f"{first} to {end if end is not None else iso_date(rec.mjd[-1])}"
        raise InputError("start/end", given, "an interval holding at least two days of data")
    return replace(
        rec, mjd=rec.mjd[keep], x=rec.x[keep], y=rec.y[keep], x_error=rec.x_error[keep], y_error=rec.y_error[keep]
    )


def record_attrs(rec: PoleRecord) -> dict:
    """The global attributes of the Dataset of a record (title, source file and format, references)."""
    return {
        "title": f"Polar motion: {rec.title}",
        "source_file": rec.path,
        "source_format": rec.format,
        "references": C04_REFERENCE if rec.format == "c04" else FINALS_REFERENCE,
        "comment": "Times are UTC (C04: 0 h UTC each day). " + SIGN_NOTE,
    }


def _in_mas(arcsec: np.ndarray) -> np.ndarray:
    """File values (arcsec) in mas, as the decimal the file wrote (:func:`observed_mas`)."""
    return _file_decimals(np.asarray(arcsec, dtype=float) * 1e3)


def observed_mas(rad: np.ndarray) -> np.ndarray:
    """An observed pole coordinate (rad, from a record) in mas as the record's Dataset holds it, so that the
    excitation's and a hindcast's observed pole equal :func:`load_polar_motion`'s and merge with it."""
    return _file_decimals(np.asarray(rad, dtype=float) / RAD_PER_MAS)


def _file_decimals(mas: np.ndarray) -> np.ndarray:
    """Rounded to 1e-6 mas: the IERS files give 1e-3 mas (6 decimals of arcsec), and times 1000 or the trip
    through radians ends an ulp or two off that decimal (123.45600000000002); rounding gives the nearest double."""
    return np.round(mas, 6)


def record_dataset(rec: PoleRecord):
    """A record from :func:`read_record` as the xarray Dataset of :func:`load_polar_motion`."""
    from wobble.api.dataset import xarray

    xr = xarray()
    mas = _in_mas
    ds = xr.Dataset(
        {
            "x_p": ("time", mas(rec.x), attrs("milliarcsecond", "pole coordinate x_p (toward the Greenwich meridian)")),
            "y_p": ("time", mas(rec.y), attrs("milliarcsecond", "pole coordinate y_p (toward 90 deg W longitude)")),
            "x_p_error": (
                "time",
                mas(rec.x_error),
                attrs("milliarcsecond", "one-sigma error of x_p given in the file"),
            ),
            "y_p_error": (
                "time",
                mas(rec.y_error),
                attrs("milliarcsecond", "one-sigma error of y_p given in the file"),
            ),
        },
        coords={"time": time_coord(rec.mjd)},
        attrs=record_attrs(rec),
    )
    ds["x_p"].attrs["ancillary_variables"] = "x_p_error"
    ds["y_p"].attrs["ancillary_variables"] = "y_p_error"
    return ds


def load_polar_motion(file: str | os.PathLike | None = None, *, start=None, end=None):
    """The pole coordinates of an IERS file as an xarray Dataset.

    Parameters
    ----------
    file : path-like, optional
        An IERS C04 or finals2000A file (recognised from its lines). Default:
        the IERS 20 C04 series shipped with astropy-iers-data (no download).
    start, end : str, astropy.time.Time or datetime, optional
        Keep the days from ``start`` to ``end`` inclusive (UTC; default: all).
        Dates outside the file are an error, not a silently shorter series.

    Returns
    -------
    xarray.Dataset
        ``x_p``, ``y_p``, ``x_p_error``, ``y_p_error`` (milliarcsecond, as every wobble file writes the
        pole; the IERS files give arcsec) on a ``time``
        coordinate in MJD (CF units ``days since 1858-11-17 00:00:00``).

    Examples
    --------
    >>> import wobble
    >>> pm = wobble.load_polar_motion(start="2020-01-01", end="2020-12-31")
    >>> pm.sizes["time"], list(pm.data_vars), pm["x_p"].attrs["units"]
    (366, ['x_p', 'y_p', 'x_p_error', 'y_p_error'], 'milliarcsecond')
    """
    return record_dataset(read_record(file, start=start, end=end))


def series(data) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(MJD, t in s since J2000, p = x - i y in rad) from a Dataset, checked."""
    for name in ("x_p", "y_p", "time"):
        if name not in data.variables:
            raise InputError("data", f"a Dataset without {name!r}", "a Dataset from load_polar_motion (time, x_p, y_p)")
    columns = [(name, data[name].values, data[name].attrs.get("units")) for name in ("x_p", "y_p")]
    return _pole_series(mjd_values(data["time"]), columns)


def record_series(rec: PoleRecord) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(MJD, t in s since J2000, p = x - i y in rad) of a record from :func:`read_record`.

    The same numbers as :func:`series` of its Dataset (the same conversion, without xarray).
    """
    # Through the Dataset's mas (rounded as there), so that a file and its Dataset give the same bits.
    return _pole_series(
        np.asarray(rec.mjd, dtype=float), [("x_p", _in_mas(rec.x), "mas"), ("y_p", _in_mas(rec.y), "mas")]
    )


def _pole_series(mjd: np.ndarray, columns) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(MJD, t, p) from the MJD and the (name, values, units) of x_p and y_p: converted, finite, increasing."""
    xy = []
    for name, values, unit in columns:
        try:
            xy.append(to_si(np.asarray(values, dtype=float) * u.Unit(unit), name, u.rad, finite=False))
        except (ValueError, TypeError):
            raise InputError(name, f"units {unit!r}", "angle units such as 'arcsec' or 'milliarcsecond'") from None
    ok = np.isfinite(mjd) & np.isfinite(xy[0]) & np.isfinite(xy[1])
    mjd = mjd[ok]
    if mjd.size > 1 and not np.all(np.diff(mjd) > 0):
        raise InputError("data", "times not increasing", "a Dataset with strictly increasing times")
    t = (mjd - MJD_J2000) * DAY
    return mjd, t, complex_pole(xy[0][ok], xy[1][ok])


def mjd_values(time) -> np.ndarray:
    """MJD (UTC) of a time coordinate (a DataArray with CF units, or datetime64)."""
    return cf_time_to_mjd(time.values, time.attrs.get("units", ""))


def check_one_source(data, file) -> None:
    """Refuse a record given twice: ``data`` (a Dataset or a path) and ``file`` together would
    leave one of them silently unused."""
    if data is not None and file is not None:
        raise InputError("file", str(file), "either data or file, not both (data was given too)")


def resolve_data(data, file, start, end):
    """The record a function was given: a Dataset (cut to start/end), a file, or None for the shipped C04 series."""
    from wobble.api.dataset import xarray

    check_one_source(data, file)
    xr = xarray()
    if data is None:
        return load_polar_motion(file, start=start, end=end)
    if isinstance(data, (str, os.PathLike)):
        return load_polar_motion(data, start=start, end=end)
    if not isinstance(data, xr.Dataset):
        raise InputError("data", type(data).__name__, "an xarray Dataset from load_polar_motion, a file path, or None")
    if start is None and end is None:
        return data
    keep = select_dates(mjd_values(data["time"]), start, end)
    return data.isel(time=np.nonzero(keep)[0])


def series_with_attrs(data, file) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """``(mjd, t, p, attrs)`` of the whole record a function was given (:func:`series`), with the
    global attributes of its Dataset (``source_file``, ``source_format``, ...).

    A file, or None for ``file`` or the shipped C04 series, is read into plain arrays
    (:func:`read_record`), so that a command printing text or JSON imports no xarray; a
    Dataset is taken as it is. The numbers are the same either way.
    """
    check_one_source(data, file)
    mjd, t, z, record = resolve_series(file if data is None else data, None, None)
    return mjd, t, z, record_attrs(record) if isinstance(record, PoleRecord) else dict(record.attrs)


def resolve_series(data, start, end):
    """The series a function was given, as ``(mjd, t, z, record)``: ``record`` is the Dataset it was
    given (cut to start/end), or, for a file or None (the shipped C04 series), the
    :class:`~wobble.io.eop.PoleRecord` read, with no Dataset built (:func:`record_dataset` builds it)."""
    if data is None or isinstance(data, (str, os.PathLike)):
        rec = read_record(data, start=start, end=end)
        return (*record_series(rec), rec)
    ds = resolve_data(data, None, start, end)
    return (*series(ds), ds)


def short_span_error(mjd, start, end, need_days: float, why: str, *, name: str = "start/end") -> InputError:
    """The error for a span whose days kept, ``mjd``, span less than ``need_days``, naming the date the user gave.

    ``start`` alone (the span runs to the record's last day) is told the latest start that leaves
    ``need_days``, ``end`` alone the earliest end; both, or neither (``name`` then, e.g. ``data``), are
    told the span. ``why`` follows the least span in the message (" (two Julian years ...)", ": ...").
    A start three days before the record's end had been refused as "start/end", a start on its last
    day as "end: got None".
    """
    least = f"at least {need_days:g} d{why}"
    if mjd.size and start is not None and end is None:
        latest = iso_date(math.floor(float(mjd[-1]) - need_days + 1e-9))
        return InputError(
            "start",
            start,
            f"a date on or before {latest}: the span to the record's last day, {iso_date(float(mjd[-1]))}, must be "
            f"{least}",
        )
    if mjd.size and end is not None and start is None:
        earliest = iso_date(math.ceil(float(mjd[0]) + need_days - 1e-9))
        return InputError(
            "end",
            end,
            f"a date on or after {earliest}: the span from the record's first day, {iso_date(float(mjd[0]))}, must be "
            f"{least}",
        )
    span = f"{iso_date(mjd[0])} to {iso_date(mjd[-1])} ({float(mjd[-1] - mjd[0]):g} d)" if mjd.size else "no data"
    return InputError(name, span, f"a span of {least}")


def check_daily(mjd, first: float, last: float, where: str, remedy: str = "") -> None:
    """Refuse days missing from the daily record ``mjd`` between ``first`` and ``last`` (MJD), naming them.

    The forecasts step by days, and each past forecast that calibrates a forecast's intervals reads its own
    fitting span: a day missing years before the issue date was refused as "gaps in the Kalman fitting span"
    (the forecast's own span had none), without the date or the way round it. ``where`` says which stretch
    the days are read for; ``remedy``, when given, what else the user can do.
    """
    mjd = np.asarray(mjd, dtype=float)
    inside = mjd[(mjd >= first - 0.5) & (mjd <= last + 0.5)]
    steps = np.diff(inside)
    gaps = np.flatnonzero(~np.isclose(steps, 1.0, rtol=0, atol=1e-6))
    if gaps.size == 0:
        return
    odd = gaps[~np.isclose(steps[gaps], np.round(steps[gaps]), rtol=0, atol=1e-6)]
    if odd.size:  # a Dataset sampled other than daily: no whole number of days is missing
        raise InputError(
            "data",
            f"samples {steps[odd[0]]:g} d apart after {iso_date(inside[odd[0]])} in {where}",
            "a daily record (one sample a day, at the same time of day)",
        )
    missing = int(np.sum(np.round(steps[gaps]) - 1))
    shown = []
    for k in gaps[:3]:
        a, b = inside[k] + 1, inside[k + 1] - 1
        shown.append(iso_date(a) if b <= a else f"{iso_date(a)} to {iso_date(b)}")
    more = f" and {gaps.size - 3} more gaps" if gaps.size > 3 else ""
    raise InputError(
        "data",
        f"{missing} day{'s' if missing != 1 else ''} missing ({', '.join(shown)}{more}) from {where}, "
        f"{iso_date(first)} to {iso_date(last)}",
        "a daily record without gaps there" + (f"; {remedy}" if remedy else ""),
    )
