"""Parameter files: every number with value, uncertainty, unit, source and status.

The catalogue in ``data/`` and users' own files share one TOML schema
(documented in ``data/README.md``)::

    schema = "wobble/1"
    kind = "planet"            # what the file describes: planet, rigid_body, ...
    name = "earth"             # identifier (lower case)
    title = "Earth"            # display name
    description = "..."

    [parameters.gm]
    value = 3.986004418e14     # number or list of numbers
    uncertainty = 8e5          # one standard deviation, same unit (0 if exact)
    unit = "m3 s-2"            # astropy/UDUNITS-style string; "" for dimensionless
    source = "IERS Conventions (2010), TN36, Table 1.1"
    status = "read"            # read | secondary | derived | assumed
    note = "..."               # optional: how derived, why assumed

This module reads and writes that schema only; what the parameters mean is up
to the caller (the planet catalogue, the bodies library).
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from astropy import units as u

from wobble.errors import FileFormatError
from wobble.io.atomic import atomic_target

__all__ = [
    "SCHEMA",
    "STATUSES",
    "Parameter",
    "ParameterFile",
    "read_toml",
    "read_parameter_file",
    "write_parameter_file",
]

SCHEMA = "wobble/1"
STATUSES = ("read", "secondary", "derived", "assumed")
_REQUIRED_TOP = ("schema", "kind", "name")
_REQUIRED_ENTRY = ("value", "uncertainty", "unit", "source", "status")
#: Top-level keys a kind of file may carry besides schema, kind, name, title, description and parameters.
_EXTRA_TOP = {"density_profile": ("body", "construction"), "perturber": ("primary", "coupling")}


@dataclass(frozen=True)
class Parameter:
    """One catalogued number: a Quantity with its standard uncertainty and provenance."""

    value: u.Quantity
    uncertainty: u.Quantity
    source: str
    status: str
    note: str = ""
    #: The unit as the file spells it ("kg m-3"), for messages: astropy's own spelling differs ("kg / m3").
    unit_text: str = ""

    @property
    def relative_uncertainty(self) -> float:
        """Uncertainty over value (inf for a zero value with non-zero uncertainty)."""
        v = np.abs(self.value.value).max()
        s = np.abs(self.uncertainty.to_value(self.value.unit)).max()
        return s / v if v else (0.0 if s == 0 else math.inf)


@dataclass(frozen=True)
class ParameterFile:
    """A parsed parameter file."""

    kind: str
    name: str
    title: str
    description: str
    parameters: dict[str, Parameter]
    path: str | None = None
    extra: dict = field(default_factory=dict)

    def get(self, key: str) -> Parameter | None:
        """The parameter ``key``, or None when the file does not give it."""
        return self.parameters.get(key)

    def require(self, key: str, why: str) -> Parameter:
        """The parameter ``key``; a FileFormatError naming the file and key if absent."""
        if key not in self.parameters:
            raise FileFormatError(self.path or self.name, f"parameters.{key}", f"missing; needed for {why}")
        return self.parameters[key]


def _parse_unit(path, key: str, text) -> u.UnitBase:
    if not isinstance(text, str):
        raise FileFormatError(path, f"{key}.unit", f'got {text!r}; allowed: a unit string such as "m3 s-2" or ""')
    try:
        return u.Unit(text.strip() or u.dimensionless_unscaled, parse_strict="raise")
    except ValueError:
        raise FileFormatError(
            path, f"{key}.unit", f'got {text!r}; allowed: a unit astropy can parse (e.g. "kg m2", "d")'
        ) from None


def _parse_number(path, where: str, raw) -> np.ndarray:
    if isinstance(raw, str) or (isinstance(raw, list) and any(isinstance(x, str) for x in raw)):
        # "0.169" in quotes is text in TOML: refused as "1830 s" is, not read as a number behind the user's back.
        raise FileFormatError(path, where, f"got {raw!r} (text); allowed: a number or a list of numbers, unquoted")
    try:
        arr = np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise FileFormatError(path, where, f"got {raw!r}; allowed: a number or a list of numbers") from None
    if isinstance(raw, bool) or arr.dtype.kind not in "f" or not np.all(np.isfinite(arr)):
        raise FileFormatError(path, where, f"got {raw!r}; allowed: finite numbers")
    return arr


def _parse_entry(path, key: str, entry) -> Parameter:
    where = f"parameters.{key}"
    if not isinstance(entry, dict):
        raise FileFormatError(path, where, "must be a table with value, uncertainty, unit, source, status")
    missing = [k for k in _REQUIRED_ENTRY if k not in entry]
    if missing:
        hint = " (uncertainty = 0 for an exact or conventional value)" if "uncertainty" in missing else ""
        raise FileFormatError(path, where, f"missing field(s) {', '.join(missing)}{hint}")
    unit = _parse_unit(path, where, entry["unit"])
    value = _parse_number(path, f"{where}.value", entry["value"])
    sigma = _parse_number(path, f"{where}.uncertainty", entry.get("uncertainty", 0.0))
    if np.any(sigma < 0):
        raise FileFormatError(path, f"{where}.uncertainty", f"got {entry['uncertainty']!r}; allowed: >= 0")
    if sigma.shape not in ((), value.shape):
        raise FileFormatError(path, f"{where}.uncertainty", "must be a number or match the shape of value")
    status = entry["status"]
    if status not in STATUSES:
        raise FileFormatError(path, f"{where}.status", f"got {status!r}; allowed: {', '.join(STATUSES)}")
    source = entry["source"]
    if not isinstance(source, str) or not source.strip():
        raise FileFormatError(path, f"{where}.source", "must name where the number comes from")
    note = entry.get("note", "")
    unknown = set(entry) - {"value", "uncertainty", "unit", "source", "status", "note"}
    if unknown:
        raise FileFormatError(path, where, f"unknown field(s) {', '.join(sorted(unknown))}")
    return Parameter(
        value * unit, np.broadcast_to(sigma, value.shape) * unit, source.strip(), status, str(note), str(entry["unit"])
    )


def wrong_unit(pf: ParameterFile, key: str, unit: u.UnitBase) -> FileFormatError:
    """The error for parameter ``key`` whose unit does not convert to ``unit``: the unit as the file spells it."""
    param = pf.get(key)
    want = f"a unit of {unit.to_string()}" if unit.to_string() else 'a pure number (unit = "")'
    got = param.unit_text or param.value.unit.to_string()
    return FileFormatError(pf.path, f"parameters.{key}.unit", f"got {got!r}; allowed: {want}")


def read_toml(path: str | os.PathLike) -> dict:
    """Load a TOML file; a missing or malformed file is a FileFormatError naming it."""
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise FileFormatError(path, None, "no such file") from None
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(path, None, f"not valid TOML ({exc})") from None


def read_parameter_file(
    path: str | os.PathLike, *, kind: str | None = None, known: set[str] | None = None
) -> ParameterFile:
    """Read and validate a wobble parameter file.

    Parameters
    ----------
    path : path-like
        The TOML file.
    kind : str, optional
        Required value of the top-level ``kind`` (e.g. ``"planet"``).
    known : set of str, optional
        Parameter names the caller understands; any other name is an error
        (a misspelt key must not be silently ignored).

    Raises
    ------
    wobble.errors.FileFormatError
        Naming the file and the key: unreadable TOML, missing or malformed fields.
    """
    path = Path(path)
    data = read_toml(path)
    missing = [k for k in _REQUIRED_TOP if k not in data]
    if missing:
        raise FileFormatError(path, None, f"missing top-level key(s) {', '.join(missing)}")
    if data["schema"] != SCHEMA:
        raise FileFormatError(path, "schema", f"got {data['schema']!r}; allowed: {SCHEMA!r}")
    if kind is not None and data["kind"] != kind:
        raise FileFormatError(path, "kind", f"got {data['kind']!r}; allowed: {kind!r}")
    raw = data.get("parameters", {})
    if not isinstance(raw, dict):
        raise FileFormatError(path, "parameters", "must be a table of parameter tables")
    if known is not None:
        unknown = sorted(set(raw) - known)
        if unknown:
            raise FileFormatError(
                path, f"parameters.{unknown[0]}", f"unknown parameter; allowed: {', '.join(sorted(known))}"
            )
    params = {key: _parse_entry(path, key, entry) for key, entry in raw.items()}
    extra = {k: v for k, v in data.items() if k not in (*_REQUIRED_TOP, "title", "description", "parameters")}
    allowed_extra = _EXTRA_TOP.get(str(data["kind"]), ())
    unknown_top = sorted(set(extra) - set(allowed_extra))
    if unknown_top:
        # A misspelt top-level key (descripton, titel) must not be dropped silently, as a parameter is not.
        allowed = ", ".join((*_REQUIRED_TOP, "title", "description", "parameters", *allowed_extra))
        raise FileFormatError(path, unknown_top[0], f"unknown top-level key; allowed: {allowed}")
    return ParameterFile(
        kind=str(data["kind"]),
        name=str(data["name"]),
        title=str(data.get("title", data["name"])),
        description=str(data.get("description", "")),
        parameters=params,
        path=str(path),
        extra=extra,
    )


def _toml_value(x) -> str:
    if isinstance(x, str):
        return '"' + x.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0:
        return repr(float(arr))
    return "[" + ", ".join(_toml_value(v) for v in arr) + "]"


def write_parameter_file(pf: ParameterFile, path: str | os.PathLike, *, overwrite: bool = False) -> Path:
    """Write ``pf`` in the wobble/1 schema, atomically (temporary file, then rename)."""
    path = Path(path)
    lines = [
        f"schema = {_toml_value(SCHEMA)}",
        f"kind = {_toml_value(pf.kind)}",
        f"name = {_toml_value(pf.name)}",
        f"title = {_toml_value(pf.title)}",
        f"description = {_toml_value(pf.description)}",
    ]
    for key, p in pf.parameters.items():
        unit = p.value.unit.to_string()
        lines += [
            "",
            f"[parameters.{key}]",
            f"value = {_toml_value(p.value.value)}",
            f"uncertainty = {_toml_value(p.uncertainty.to_value(p.value.unit))}",
            f"unit = {_toml_value(unit)}",
            f"source = {_toml_value(p.source)}",
            f"status = {_toml_value(p.status)}",
        ]
        if p.note:
            lines.append(f"note = {_toml_value(p.note)}")
    with atomic_target(path, overwrite) as tmp:
        Path(tmp).write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
