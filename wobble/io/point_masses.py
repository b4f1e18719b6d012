"""Point masses from a CSV file: columns m, x, y, z, with units in the header.

The file looks like::

    # a dumbbell
    m [g], x [cm], y [cm], z [cm]
    10, -5, 0, 0
    10,  5, 0, 0

Lines starting with ``#`` and blank lines are skipped. The header is optional
(without it the columns are m, x, y, z in that order); a unit may follow a
column name in brackets or parentheses (``x [cm]``, ``m (kg)``). Columns without a
unit take the caller's default (the command line's ``--mass-unit`` and
``--length-unit``, SI otherwise); giving both a header unit and a different
default for the same column is an error rather than a guess.
"""

from __future__ import annotations

import csv
import math
import os
import re
from pathlib import Path

import numpy as np
from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.text import is_number

__all__ = ["read_point_masses"]

_COLUMNS = ("m", "x", "y", "z")
_ALIASES = {"mass": "m"}
_HEADER = re.compile(r"^\s*([A-Za-z_]\w*)\s*(?:[\[(]\s*(.*?)\s*[\])])?\s*$")


def _parse_header(path, line_no: int, fields: list[str]) -> dict[str, tuple[int, str | None]]:
    found: dict[str, tuple[int, str | None]] = {}
    for i, field in enumerate(fields):
        match = _HEADER.match(field)
        name = _ALIASES.get(match.group(1).lower(), match.group(1).lower()) if match else None
        if name not in _COLUMNS:
            raise FileFormatError(
                path,
                f"line {line_no}",
                f"column {field.strip()!r}; allowed: columns m, x, y, z with optional units, e.g. 'x [cm]'",
            )
        if name in found:
            raise FileFormatError(path, f"line {line_no}", f"column {name!r} appears twice")
        found[name] = (i, match.group(2) or None)
    missing = [c for c in _COLUMNS if c not in found]
    if missing:
        raise FileFormatError(path, f"line {line_no}", f"missing column(s) {', '.join(missing)}")
    return found


def _unit(
    path, line_no, column: str, header_unit: str | None, default: u.UnitBase | None, kind: u.UnitBase, option: str
):
    if header_unit is None:
        return default if default is not None else kind
    try:
        unit = u.Unit(header_unit, parse_strict="raise")
    except ValueError:
        raise FileFormatError(
            path, f"line {line_no}", f"unit {header_unit!r} of column {column!r} is not a unit astropy can parse"
        ) from None
    if not unit.is_equivalent(kind, equivalencies=None):
        raise FileFormatError(
            path,
            f"line {line_no}",
            f"unit {header_unit!r} of column {column!r}; allowed: a unit of {kind.physical_type}",
        )
    if default is not None and default != unit:
        raise InputError(
            option, str(default), f"the header's unit {header_unit!r} for column {column!r}, or no {option}"
        )
    return unit


def read_point_masses(
    path: str | os.PathLike, *, mass_unit: u.UnitBase | None = None, length_unit: u.UnitBase | None = None
) -> tuple[u.Quantity, u.Quantity]:
    """Read point masses from a CSV file.

    Parameters
    ----------
    path : path-like
        The CSV file (see the module docstring for the layout).
    mass_unit, length_unit : astropy unit, optional
        Units for columns whose header gives none (default kg and m).

    Returns
    -------
    masses : Quantity, shape (N,)
    positions : Quantity, shape (N, 3), in metres

    Raises
    ------
    wobble.errors.FileFormatError
        Naming the file and line: missing file, bad header, a row that is not four numbers, a value
        that is not finite (NaN, inf; named with its column too), or a mass that is not positive.
    """
    path = os.fspath(path)  # messages name the file as the caller gave it (Path() drops a leading ./)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileFormatError(path, None, "no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise FileFormatError(path, None, f"unreadable ({exc})") from None
    columns = None
    rows: list[list[float]] = []
    for line_no, fields in enumerate(csv.reader(text.splitlines()), start=1):
        if not fields or not "".join(fields).strip() or fields[0].lstrip().startswith("#"):
            continue
        if columns is None:
            if all(is_number(f) for f in fields):
                columns = {c: (i, None) for i, c in enumerate(_COLUMNS)}
                header_line = line_no
            else:
                columns = _parse_header(path, line_no, fields)
                header_line = line_no
                continue
        if len(fields) != len(columns):
            raise FileFormatError(
                path, f"line {line_no}", f"{len(fields)} fields; allowed: {len(columns)} (m, x, y, z)"
            )
        try:
            values = [float(f) for f in fields]
        except ValueError:
            raise FileFormatError(path, f"line {line_no}", f"got {','.join(fields)!r}; allowed: numbers") from None
        for c in _COLUMNS:
            if not math.isfinite(values[columns[c][0]]):
                # Named here, where the line and the column are known: the model's refusal named neither
                # ("positions: got (0, 0, 0, nan, 0, 1) m").
                raise FileFormatError(
                    path,
                    f"line {line_no}, column {c!r}",
                    f"got {fields[columns[c][0]].strip()!r}; allowed: a finite number",
                )
        if not values[columns["m"][0]] > 0:  # the model's refusal named neither ("masses: got (1, -1) kg")
            raise FileFormatError(
                path,
                f"line {line_no}, column 'm'",
                f"got {fields[columns['m'][0]].strip()!r}; allowed: a positive mass",
            )
        rows.append([values[columns[c][0]] for c in _COLUMNS])
    if not rows:
        raise FileFormatError(path, None, "no point masses (expected rows m, x, y, z)")
    data = np.array(rows)
    munit = _unit(path, header_line, "m", columns["m"][1], mass_unit, u.kg, "--mass-unit")
    masses = data[:, 0] << munit
    positions = np.column_stack(
        [
            (data[:, k + 1] << _unit(path, header_line, c, columns[c][1], length_unit, u.m, "--length-unit")).to_value(
                u.m
            )
            for k, c in enumerate("xyz")
        ]
    )
    return masses, positions << u.m
