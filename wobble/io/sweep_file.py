"""Sweep files (``data/sweeps/*.toml``): what varies, how, and what to keep.

Schema ``wobble-sweep/1``::

    schema = "wobble-sweep/1"
    name = "mars_chandler"
    title = "Mars' Chandler period given its parameters' uncertainties"
    target = "chandler"          # what each member evaluates
    body = "mars"                # catalogue name, or a planet file (relative to this file)
    model = "full"               # Chandler model (target chandler)
    members = 100000             # random sweeps (grids set their own size)
    seed = 20201013              # same seed, same numbers, whatever the chunking
    chunk_size = 20000           # members per dask chunk (optional)
    outputs = ["chandler_period", "quality_factor"]
    vary_all_uncertain = false   # also draw every catalogued parameter with an uncertainty

    [vary.love_number_k2]
    distribution = "normal"      # normal | uniform | grid
    mean = 0.169                 # normal: default mean and sd are the catalogue's
    sd = 0.006                   #   value and uncertainty
    unit = ""                    # unit of mean/sd/low/high/values (default: the catalogue's)

    [vary.anelastic_exponent]
    distribution = "uniform"
    low = 0.1
    high = 0.3

    [vary.theta0]                # grids: one dimension each, outer product
    distribution = "grid"
    start = 0.0
    stop = 90.0
    num = 91                     # or: values = [...]
    unit = "deg"

Targets ``heavy_top`` and ``free_rotation`` take their fixed parameters from a
``[base]`` table instead of a body (every number with its unit and source)::

    [base]
    I1 = { value = 1.0, unit = "kg m2", uncertainty = 0, source = "illustrative top" }

Which parameter names and outputs are valid depends on the target; the
API checks them (with the file and key in the message) before any work starts.
"""

from __future__ import annotations

import math

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wobble.io.cf import INT64_ALLOWED, INT64_MAX
from wobble.errors import FileFormatError
from wobble.io.parameter_file import read_toml

__all__ = ["SCHEMA", "DISTRIBUTIONS", "BaseValue", "Variation", "SweepSpec", "read_sweep_file", "sweep_spec_from_dict"]

SCHEMA = "wobble-sweep/1"
DISTRIBUTIONS = ("normal", "uniform", "grid")
_TOP = {
    "schema",
    "name",
    "title",
    "description",
    "target",
    "body",
    "model",
    "members",
    "seed",
    "chunk_size",
    "outputs",
    "vary",
    "vary_all_uncertain",
    "base",
}
_BASE_FIELDS = {"value", "unit", "uncertainty", "source", "status", "note"}
_FIELDS = {
    "normal": {"mean", "sd", "unit", "note"},
    "uniform": {"low", "high", "unit", "note"},
    "grid": {"values", "start", "stop", "num", "unit", "note"},
}


@dataclass(frozen=True)
class Variation:
    """How one parameter varies across the sweep (numbers in ``unit``; None: catalogue default)."""

    parameter: str
    distribution: str
    mean: float | None = None
    sd: float | None = None
    low: float | None = None
    high: float | None = None
    values: tuple[float, ...] | None = None
    unit: str | None = None


@dataclass(frozen=True)
class BaseValue:
    """A fixed parameter of the base top or body (targets heavy_top, free_rotation)."""

    parameter: str
    value: float
    unit: str
    uncertainty: float | None = None
    source: str = ""


@dataclass(frozen=True)
class SweepSpec:
    """A parsed sweep: the target, the base body, the variations and the outputs."""

    name: str
    title: str
    description: str
    target: str
    body: str | None
    model: str
    members: int | None
    seed: int
    chunk_size: int | None
    outputs: tuple[str, ...]
    variations: tuple[Variation, ...]
    vary_all_uncertain: bool = False
    path: str | None = None
    base: tuple[BaseValue, ...] = ()

    @property
    def is_grid(self) -> bool:
        return any(v.distribution == "grid" for v in self.variations)


def _number(path, where, raw, *, integer=False, positive=False) -> float | int:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or (integer and not isinstance(raw, int)):
        kind = "an integer" if integer else "a number"
        raise FileFormatError(path, where, f"got {raw!r}; allowed: {kind}")
    if not math.isfinite(raw) or (positive and raw <= 0):  # math: an integer past int64 is still a number
        raise FileFormatError(path, where, f"got {raw!r}; allowed: a {'positive' if positive else 'finite'} number")
    return raw


def _variation(path, name: str, raw) -> Variation:
    where = f"vary.{name}"
    if not isinstance(raw, dict):
        raise FileFormatError(path, where, "must be a table with a distribution")
    dist = raw.get("distribution")
    if dist not in DISTRIBUTIONS:
        raise FileFormatError(path, f"{where}.distribution", f"got {dist!r}; allowed: {', '.join(DISTRIBUTIONS)}")
    unknown = set(raw) - _FIELDS[dist] - {"distribution"}
    if unknown:
        allowed = ", ".join(sorted(_FIELDS[dist]))
        raise FileFormatError(
            path, f"{where}.{sorted(unknown)[0]}", f"not a field of a {dist} variation; allowed: {allowed}"
        )
    num = {k: _number(path, f"{where}.{k}", raw[k]) for k in ("mean", "sd", "low", "high", "start", "stop") if k in raw}
    if "note" in raw and not isinstance(raw["note"], str):
        raise FileFormatError(path, f"{where}.note", f"got {raw['note']!r}; allowed: a string")
    unit = raw.get("unit")
    if unit is not None and not isinstance(unit, str):
        raise FileFormatError(path, f"{where}.unit", f"got {unit!r}; allowed: a unit string")
    if dist == "normal":
        if num.get("sd", 1.0) < 0:
            raise FileFormatError(path, f"{where}.sd", f"got {num['sd']!r}; allowed: >= 0")
        return Variation(name, dist, mean=num.get("mean"), sd=num.get("sd"), unit=unit)
    if dist == "uniform":
        if "low" not in num or "high" not in num:
            raise FileFormatError(path, where, "a uniform variation needs low and high")
        if not num["low"] < num["high"]:
            raise FileFormatError(path, f"{where}.high", f"got {num['high']!r}; allowed: above low = {num['low']!r}")
        return Variation(name, dist, low=num["low"], high=num["high"], unit=unit)
    if "values" in raw:
        values = raw["values"]
        if not isinstance(values, list) or not values:
            raise FileFormatError(path, f"{where}.values", "allowed: a non-empty list of numbers")
        vals = tuple(float(_number(path, f"{where}.values", v)) for v in values)
    elif {"start", "stop", "num"} <= set(raw):
        n = _number(path, f"{where}.num", raw["num"], integer=True, positive=True)
        vals = tuple(np.linspace(num["start"], num["stop"], n).tolist())
    else:
        raise FileFormatError(path, where, "a grid needs values = [...] or start, stop and num")
    return Variation(name, dist, values=vals, unit=unit)


def _base(path, raw) -> tuple[BaseValue, ...]:
    if not isinstance(raw, dict):
        raise FileFormatError(path, "base", 'must be a table of parameters, e.g. I1 = { value = 1.0, unit = "kg m2" }')
    out = []
    for name, entry in raw.items():
        where = f"base.{name}"
        if not isinstance(entry, dict):
            raise FileFormatError(
                path, where, f"got {entry!r}; allowed: a table {{ value = ..., unit = ..., source = ... }}"
            )
        unknown = set(entry) - _BASE_FIELDS
        if unknown:
            raise FileFormatError(
                path, f"{where}.{sorted(unknown)[0]}", f"unknown field; allowed: {', '.join(sorted(_BASE_FIELDS))}"
            )
        if "value" not in entry:
            raise FileFormatError(path, f"{where}.value", "missing; allowed: a number")
        value = _number(path, f"{where}.value", entry["value"])
        unit = entry.get("unit")
        if not isinstance(unit, str):
            raise FileFormatError(path, f"{where}.unit", f'got {unit!r}; allowed: a unit string ("" for dimensionless)')
        unc = entry.get("uncertainty")
        if unc is not None and _number(path, f"{where}.uncertainty", unc) < 0:
            raise FileFormatError(path, f"{where}.uncertainty", f"got {unc!r}; allowed: >= 0")
        for key in ("source", "status", "note"):
            if key in entry and not isinstance(entry[key], str):
                raise FileFormatError(path, f"{where}.{key}", f"got {entry[key]!r}; allowed: a string")
        source = "; ".join(str(entry[k]) for k in ("source", "note") if entry.get(k))
        out.append(BaseValue(name, float(value), unit, None if unc is None else float(unc), source))
    return tuple(out)


def sweep_spec_from_dict(data: dict, path: str | os.PathLike | None = None) -> SweepSpec:
    """Validate a sweep given as a dict (the TOML structure) and return its spec."""
    where_path = str(path) if path is not None else "<sweep>"
    unknown = set(data) - _TOP
    if unknown:
        key = sorted(unknown)[0]
        raise FileFormatError(where_path, key, f"unknown key; allowed: {', '.join(sorted(_TOP))}")
    if data.get("schema") != SCHEMA:
        raise FileFormatError(where_path, "schema", f"got {data.get('schema')!r}; allowed: {SCHEMA!r}")
    for key in ("name", "target"):
        if not isinstance(data.get(key), str) or not data[key]:
            raise FileFormatError(where_path, key, "missing; allowed: a non-empty string")
    vary = data.get("vary", {})
    if not isinstance(vary, dict):
        raise FileFormatError(where_path, "vary", "must be a table of parameter tables")
    variations = tuple(_variation(where_path, name, raw) for name, raw in vary.items())
    vary_all = data.get("vary_all_uncertain", False)
    if not isinstance(vary_all, bool):
        raise FileFormatError(where_path, "vary_all_uncertain", f"got {vary_all!r}; allowed: true or false")
    if not variations and not vary_all:
        raise FileFormatError(
            where_path, "vary", "nothing varies; add [vary.<parameter>] tables or vary_all_uncertain = true"
        )
    grid = [v for v in variations if v.distribution == "grid"]
    if grid and (len(grid) != len(variations) or vary_all):
        raise FileFormatError(where_path, "vary", "mixing grid and random variations is not supported; use one kind")
    members = data.get("members")
    if grid:
        if members is not None:
            raise FileFormatError(
                where_path, "members", "a grid sweep's size is the product of its grids; remove members"
            )
    else:
        members = _number(where_path, "members", members, integer=True, positive=True) if members is not None else None
        if members is None:
            raise FileFormatError(where_path, "members", "missing; allowed: a positive integer (random sweeps)")
        if members > INT64_MAX:
            raise FileFormatError(where_path, "members", f"got {members}; allowed: a positive integer {INT64_ALLOWED}")
    seed = data.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= INT64_MAX:
        raise FileFormatError(where_path, "seed", f"got {seed!r}; allowed: a non-negative integer {INT64_ALLOWED}")
    chunk = data.get("chunk_size")
    if chunk is not None:
        chunk = _number(where_path, "chunk_size", chunk, integer=True, positive=True)
    outputs = data.get("outputs", [])
    if not isinstance(outputs, list) or not all(isinstance(o, str) for o in outputs):
        raise FileFormatError(where_path, "outputs", "allowed: a list of output names")
    body = data.get("body")
    if body is not None and not isinstance(body, str):
        raise FileFormatError(where_path, "body", f"got {body!r}; allowed: a catalogue name or a file path")
    if body is not None and path is not None and not body.strip().lower().isidentifier():
        candidate = Path(path).parent / body
        body = str(candidate) if candidate.exists() else body
    model = data.get("model", "full")
    if not isinstance(model, str):
        raise FileFormatError(where_path, "model", f"got {model!r}; allowed: a model name")
    return SweepSpec(
        name=data["name"],
        title=str(data.get("title", data["name"])),
        description=str(data.get("description", "")),
        target=data["target"],
        body=body,
        model=model,
        members=members,
        seed=seed,
        chunk_size=chunk,
        outputs=tuple(outputs),
        variations=variations,
        vary_all_uncertain=vary_all,
        path=None if path is None else str(path),
        base=_base(where_path, data.get("base", {})),
    )


def read_sweep_file(path: str | os.PathLike) -> SweepSpec:
    """Read and validate a sweep file; errors name the file and the key."""
    path = Path(path)
    return sweep_spec_from_dict(read_toml(path), path)
