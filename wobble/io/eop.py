"""Earth-orientation files: the IERS 20 C04 series and the finals2000A table.

Both readers return a :class:`PoleRecord` of plain arrays in the files' own
units (MJD in UTC days, pole coordinates and their errors in arcseconds);
:mod:`wobble.api.polar_motion` turns them into an xarray Dataset with units.

* **IERS 20 C04** (``eopc04.1962-now``; format in ``ReadMe.eopc04`` of the
  astropy-iers-data package): daily values at 0 h UTC since 1962, one line per
  day, fixed columns: MJD in columns 17-26, x_p 27-38, y_p 39-50, their errors
  123-134 and 135-146. Lines starting with ``#`` are header lines.
* **finals2000A** (``finals2000A.all``/``.data``/``.daily``; format in
  ``ReadMe.finals2000A``): daily IERS Bulletin A values since 1973, MJD in
  columns 8-15, flag in 17 (``I`` = IERS value, ``P`` = prediction), x_p
  19-27, its error 28-36, y_p 38-46, its error 47-55. Only ``I`` rows are
  observations; predictions and the empty future rows are left out.

A malformed or truncated line, or one whose calendar date is not that of its
MJD, is an error naming the file and the line, never a silently shorter series. A file cut exactly at a line boundary
cannot be told from a complete one (neither format has a trailer); its last
date is always reported.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wobble.errors import FileFormatError, InputError
from wobble.io.shipped import not_a_file

__all__ = [
    "PoleRecord",
    "SHIPPED_FILES",
    "default_c04_path",
    "resolve_eop_path",
    "existing_eop_path",
    "read_c04",
    "read_finals2000a",
    "read_pole_file",
]

#: The Earth-orientation files the astropy-iers-data package ships, found by name from any folder.
SHIPPED_FILES = ("eopc04.1962-now", "finals2000A.all")


@dataclass(frozen=True, eq=False)
class PoleRecord:
    """Pole coordinates read from an Earth-orientation file.

    Attributes
    ----------
    mjd : ndarray
        Modified Julian Date (UTC), days, strictly increasing.
    x, y : ndarray
        Pole coordinates x_p, y_p, arcsec (IERS: x toward Greenwich, y toward 90 deg W).
    x_error, y_error : ndarray
        Their one-sigma errors as given in the file, arcsec.
    path : str
        The file read.
    format : str
        ``"c04"`` or ``"finals2000A"``.
    title : str
        The series' own description (C04 header, or the Bulletin A note).
    """

    mjd: np.ndarray
    x: np.ndarray
    y: np.ndarray
    x_error: np.ndarray
    y_error: np.ndarray
    path: str
    format: str
    title: str


def default_c04_path() -> Path:
    """The IERS 20 C04 file shipped with the ``astropy-iers-data`` package (no download)."""
    import astropy_iers_data

    return Path(os.path.dirname(astropy_iers_data.__file__)) / "data" / "eopc04.1962-now"


def resolve_eop_path(path) -> Path:
    """``path`` itself if it exists or names a folder; else, for a bare name of a shipped file, that file.

    ``finals2000A.all`` or ``eopc04.1962-now`` given without a folder, and not
    present in the working folder, mean the copies shipped with
    astropy-iers-data (:data:`SHIPPED_FILES`), so examples run as printed from
    any folder. Anything else is returned unchanged (and a missing file is
    reported by the reader).
    """
    path = Path(path)
    if path.exists() or path.name != str(path) or path.name not in SHIPPED_FILES:
        return path
    shipped = default_c04_path().parent / path.name
    return shipped if shipped.is_file() else path


def existing_eop_path(path, parameter: str) -> Path:
    """:func:`resolve_eop_path`, refusing a path that names no file to read before anything is read.

    The refusal is an :class:`~wobble.errors.InputError` naming ``parameter`` (the option, ``--file``),
    the path as typed and why it is not a file (it is a folder, is empty or does not exist).
    """
    resolved = resolve_eop_path(path)
    if os.fspath(path) and resolved.is_file():
        return resolved
    raise InputError(
        parameter,
        os.fspath(path),
        f"an IERS C04 or finals2000A file ({not_a_file(path)}), or by name one of astropy-iers-data: "
        f"{', '.join(SHIPPED_FILES)}",
    )


# (first, last) columns, 1-based inclusive as in the ReadMe files.
_C04_FIELDS = {"MJD": (17, 26), "x": (27, 38), "y": (39, 50), "x error": (123, 134), "y error": (135, 146)}
_FINALS_FIELDS = {"MJD": (8, 15), "x": (19, 27), "x error": (28, 36), "y": (38, 46), "y error": (47, 55)}
# The calendar date each line also carries (the finals' year in two digits).
_C04_DATE = {"year": (1, 4), "month": (5, 8), "day": (9, 12)}
_FINALS_DATE = {"year": (1, 2), "month": (3, 4), "day": (5, 6)}
_MJD_ZERO = np.datetime64("1858-11-17", "D")


def _field(line: str, name: str, cols: tuple[int, int], path, lineno: int) -> float:
    text = line[cols[0] - 1 : cols[1]]
    try:
        value = float(text)
    except ValueError:
        raise FileFormatError(
            path, f"line {lineno}", f"columns {cols[0]}-{cols[1]} ({name}) hold {text.strip()!r}, not a number"
        ) from None
    if not np.isfinite(value):
        raise FileFormatError(path, f"line {lineno}", f"columns {cols[0]}-{cols[1]} ({name}) hold {text.strip()!r}")
    return value


def _require_length(line: str, need: int, path, lineno: int, fields: str) -> None:
    """Refuse a data line shorter than the columns it must hold (a truncated download)."""
    if len(line.rstrip()) < need:
        raise FileFormatError(
            path, f"line {lineno}", f"truncated: {len(line.rstrip())} characters, expected at least {need} ({fields})"
        )


def _columns(lines: list[tuple[int, str]], fields: dict, path) -> np.ndarray:
    """The fields of every line as floats, shape (n, len(fields)).

    Fast path: the lines as one array of ASCII bytes, one row per line, from
    which NumPy converts each column at once (the same conversion of the same
    text as field by field). If any value is not a finite number, the lines
    are read one by one to name the first bad one.
    """
    out = np.empty((len(lines), len(fields)))
    try:
        text = np.array([line for _, line in lines], dtype=bytes)
        chars = text.view("S1").reshape(len(lines), text.dtype.itemsize)
        for j, (a, b) in enumerate(fields.values()):
            out[:, j] = np.ascontiguousarray(chars[:, a - 1 : b]).view(f"S{b - a + 1}").ravel().astype(float)
        if np.all(np.isfinite(out)):
            return out
    except ValueError:
        pass
    for i, (lineno, line) in enumerate(lines):
        out[i] = [_field(line, name, cols, path, lineno) for name, cols in fields.items()]
    return out  # pragma: no cover - the loop above raises first


def _read_lines(path, typed=None) -> list[str]:
    """The file's lines; a path that names no file is refused as ``typed`` (the caller's text, before
    :func:`resolve_eop_path`, which turns "" into the current folder)."""
    path = Path(path)
    if not path.is_file():
        shown = path if typed is None else os.fspath(typed)
        raise FileFormatError(
            shown or "''",
            None,
            f"{not_a_file(shown)} (the files of astropy-iers-data are found by name: {', '.join(SHIPPED_FILES)})",
        )
    try:
        with open(path, encoding="ascii") as fh:
            return fh.read().splitlines()
    except UnicodeDecodeError as exc:
        raise FileFormatError(path, None, f"not a text (ASCII) file: byte {exc.start} cannot be decoded") from None
    except OSError as exc:
        raise FileFormatError(path, None, f"cannot be read ({exc.strerror})") from None


def _check_dates(path, lines: list[tuple[int, str]], mjd: np.ndarray, columns: dict, century: bool) -> None:
    """Refuse a line whose calendar date is not that of its MJD: a damaged MJD that still increases would
    otherwise pass as a gap of years in the record. ``century``: the year has its four digits."""
    if not lines:
        return
    ymd = _columns(lines, columns, path)
    sane = np.abs(mjd) < 1e9  # an MJD of millions of years has no date to compare (nor a place in a record)
    day = _MJD_ZERO + np.floor(np.where(sane, mjd, 0.0)).astype("int64").astype("timedelta64[D]")
    year = day.astype("datetime64[Y]").astype(int) + 1970
    month = day.astype("datetime64[M]").astype(int) % 12 + 1
    dom = (day - day.astype("datetime64[M]")).astype(int) + 1
    want = np.stack([year if century else year % 100, month, dom], axis=1)
    bad = np.nonzero(np.any(ymd != want, axis=1) | ~sane)[0]
    if bad.size:
        k = int(bad[0])
        lineno, line = lines[k]
        first, last = min(c[0] for c in columns.values()), max(c[1] for c in columns.values())
        of_mjd = f"{mjd[k]:.2f} ({day[k]})" if sane[k] else f"{mjd[k]:g} (no calendar date)"
        raise FileFormatError(
            path,
            f"line {lineno}",
            f"the date in columns {first}-{last} ({line[first - 1 : last].strip()!r}) is not that of the MJD {of_mjd}",
        )


def _finish(path, numbered: list[int], data: np.ndarray, fmt: str, title: str) -> PoleRecord:
    if data.shape[0] == 0:
        raise FileFormatError(path, None, f"no data lines in the {fmt} format")
    mjd = data[:, 0]
    bad = np.nonzero(np.diff(mjd) <= 0)[0]
    if bad.size:
        k = int(bad[0]) + 1
        raise FileFormatError(
            path, f"line {numbered[k]}", f"MJD {mjd[k]:.2f} does not follow {mjd[k - 1]:.2f}: dates must increase"
        )
    return PoleRecord(mjd, data[:, 1], data[:, 2], data[:, 3], data[:, 4], str(path), fmt, title)


def read_c04(path=None) -> PoleRecord:
    """Read an IERS C04 series (default: the file shipped by astropy-iers-data).

    Raises
    ------
    wobble.errors.FileFormatError
        Missing file; a data line shorter than 146 columns (truncated); a
        field that is not a number; dates that do not increase.
    """
    path = default_c04_path() if path is None else Path(path)
    lines = _read_lines(path)
    title = ""
    rows = []
    need = max(c[1] for c in _C04_FIELDS.values())
    for lineno, line in enumerate(lines, start=1):
        if line.startswith("#"):
            if "C04" in line and not title:
                title = line.lstrip("# ").strip()
            continue
        if not line.strip():
            continue
        if len(line.rstrip()) < need:  # tested here: a function call per line cost 40 ms on the C04 file
            _require_length(line, need, path, lineno, "date, x_p, y_p and their errors; see ReadMe.eopc04")
        rows.append((lineno, line))
    data = _columns(rows, _C04_FIELDS, path)  # MJD, x, y, x error, y error
    _check_dates(path, rows, data[:, 0], _C04_DATE, century=True)
    return _finish(path, [r[0] for r in rows], data, "c04", title or "IERS C04 series")


def read_finals2000a(path) -> PoleRecord:
    """Read the IERS Bulletin A ``I`` (observed) rows of a finals2000A file.

    Rows flagged ``P`` (predictions) and rows without a flag (future dates with
    no values) are left out. The order of the columns is
    x_p, error, y_p, error (unlike C04).

    Raises
    ------
    wobble.errors.FileFormatError
        Missing file; a flagged row shorter than 55 columns (truncated); a flag
        other than I, P or blank; a field that is not a number; dates that do
        not increase; no observed rows.
    """
    path = Path(path)
    lines = _read_lines(path)
    rows = []
    need = max(c[1] for c in _FINALS_FIELDS.values())
    for lineno, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        flag = line[16] if len(line) > 16 else " "
        if flag not in "IP ":
            raise FileFormatError(
                path, f"line {lineno}", f"column 17 holds {flag!r}; allowed: I (IERS), P (prediction) or blank"
            )
        if flag == " ":
            _field(line, "MJD", _FINALS_FIELDS["MJD"], path, lineno)  # a bare future date is fine; junk is not
            continue
        _require_length(line, need, path, lineno, "date, flag, x_p, y_p and their errors; see ReadMe.finals2000A")
        if flag == "I":
            rows.append((lineno, line))
        else:  # predictions are not used, but a malformed one is still a broken file
            _columns([(lineno, line)], _FINALS_FIELDS, path)
    data = _columns(rows, _FINALS_FIELDS, path)[:, [0, 1, 3, 2, 4]]  # MJD, x, y, x error, y error
    _check_dates(path, rows, data[:, 0], _FINALS_DATE, century=False)
    return _finish(
        path, [r[0] for r in rows], data, "finals2000A", "IERS Bulletin A (finals2000A), observed values only"
    )


def read_pole_file(path=None) -> PoleRecord:
    """Read ``path`` in whichever format it is (C04 or finals2000A); default: the shipped C04 file.

    A bare ``finals2000A.all`` or ``eopc04.1962-now`` not in the working folder
    is the copy shipped with astropy-iers-data (:func:`resolve_eop_path`).

    The format is recognised from the first data line: a four-digit year in
    columns 1-4 and at least 146 columns is C04; a flag I or P in column 17
    with the MJD in columns 8-15 is finals2000A.
    """
    if path is None:
        return read_c04()
    typed, path = path, resolve_eop_path(path)
    for lineno, line in enumerate(_read_lines(path, typed), start=1):
        if line.startswith("#") or not line.strip():
            continue
        head = line[:4].strip()
        if head.isdigit() and len(head) == 4 and len(line) >= 26 and line[16:26].strip().replace(".", "", 1).isdigit():
            return read_c04(path)
        if len(line) > 16 and line[16] in "IP" and line[7:15].strip().replace(".", "", 1).isdigit():
            return read_finals2000a(path)
        raise FileFormatError(
            path,
            f"line {lineno}",
            "neither the IERS C04 format (year in columns 1-4, MJD in 17-26) nor finals2000A "
            "(MJD in columns 8-15, flag I or P in column 17)",
        )
    raise FileFormatError(path, None, "no data lines (empty file?)")
