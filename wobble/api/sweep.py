"""Parameter sweeps and ensembles on dask, in bounded memory.

A sweep (``data/sweeps/*.toml``, schema in :mod:`wobble.io.sweep_file`)
names a target, a base body, the parameters that vary (random draws or
grids) and the outputs to keep. Members are evaluated chunk by chunk with the
vectorised models (no Python loop over members):

* :func:`sweep` returns a lazy, dask-backed :class:`xarray.Dataset`; compute it
  with any dask scheduler;
* :func:`run_sweep` streams the chunks to a CF netCDF file as they finish
  (threads, processes or a ``dask.distributed`` cluster), writing under a
  temporary name and renaming at the end, with a progress bar when asked.

Random draws depend only on (seed, parameter, member index)
(:mod:`wobble.numerics.draws`): the same seed gives the same numbers whatever
the chunking and the number of workers.

>>> import wobble
>>> ds = wobble.sweep({"schema": "wobble-sweep/1", "name": "demo", "target": "chandler",
...                    "body": "mars", "members": 1000, "seed": 1,
...                    "vary": {"love_number_k2": {"distribution": "normal"}}}).compute()
>>> bool(200 < float(ds.chandler_period.mean()) < 210)
True
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time
import zlib
from dataclasses import dataclass

import dask
import dask.array as da
import numpy as np
import xarray as xr
from astropy import units as u

from wobble.api.chandler import load_planet
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import PLANET_UNITS
from wobble.io.netcdf import write_netcdf_blocks
from wobble.io.sweep_file import (
    SweepSpec,
    Variation,
    read_sweep_file,
    sweep_spec_from_dict,
)
from wobble.io.zarr_store import is_zarr_path, open_wobble_zarr, write_zarr_blocks
from wobble.models import chandler as chandler_model
from wobble.models import free_ensemble, top_phase
from wobble.models.vocabulary import flag_meanings
from wobble.numerics import draws

__all__ = ["load_sweep", "sweep", "run_sweep", "SweepSummary", "summarize_sweep"]

DEFAULT_CHUNK = 20_000
_LOCAL_SCHEDULERS = ("threads", "processes", "synchronous")


def load_sweep(sweep) -> SweepSpec:
    """A sweep from a path, a dict with the TOML structure, or a SweepSpec."""
    if isinstance(sweep, SweepSpec):
        return sweep
    if isinstance(sweep, dict):
        return sweep_spec_from_dict(sweep)
    return read_sweep_file(sweep)


def _where(spec: SweepSpec) -> str:
    return spec.path or "<sweep>"


def _stream_id(name: str) -> int:
    # Stable per parameter name, so adding a parameter never changes another's draws.
    return zlib.crc32(name.encode())


# ---------------------------------------------------------------------------
# Targets: what one member computes
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _Resolved:
    """A variation with its numbers in SI."""

    name: str
    distribution: str
    mean: float = math.nan
    sd: float = math.nan
    low: float = math.nan
    high: float = math.nan
    values: tuple[float, ...] = ()
    unit: str = ""

    def member_values(self, seed: int, start: int, stop: int) -> np.ndarray:
        if self.distribution == "normal":
            return self.mean + self.sd * draws.standard_normal(seed, _stream_id(self.name), start, stop)
        return self.low + (self.high - self.low) * draws.uniform(seed, _stream_id(self.name), start, stop)


class ChandlerTarget:
    """Chandler periods of a planet whose parameters vary (vectorised model)."""

    name = "chandler"
    outputs = {
        "chandler_period": ("day", "modelled Chandler wobble period"),
        "wobble_rate": ("rad s-1", "signed free wobble frequency (positive: prograde)"),
        "quality_factor": ("1", "wobble quality factor implied by the out-of-phase Love number"),
        "step_period": ("day", "Chandler period after each model step"),
        "dynamical_flattening": ("1", "dynamical flattening H = (C - A)/C of the member"),
    }
    default_outputs = ("chandler_period",)

    def __init__(self, spec: SweepSpec):
        where = _where(spec)
        if spec.body is None:
            raise FileFormatError(where, "body", "missing; allowed: a catalogue name or a planet file")
        try:
            planet = load_planet(spec.body)
        except InputError as exc:
            raise FileFormatError(where, "body", f"got {spec.body!r}; allowed: {exc.allowed}") from None
        self.planet = planet
        self.params = planet.parameters
        try:
            self.model, self.steps = chandler_model.resolve_model(self.params, spec.model)
        except InputError as exc:
            raise FileFormatError(where, "model", f"got {spec.model!r}; allowed: {exc.allowed}") from None
        self.variations = self._resolve(spec)
        unknown = [o for o in spec.outputs if o not in self.outputs]
        if unknown:
            raise FileFormatError(where, "outputs", f"got {unknown[0]!r}; allowed: {', '.join(self.outputs)}")
        self.selected = spec.outputs or self.default_outputs

    def _resolve(self, spec: SweepSpec) -> tuple[_Resolved, ...]:
        where = _where(spec)
        allowed = sorted(k for k in self.params.values() if k not in ("observed_chandler_period",))
        out = {}
        for v in spec.variations:
            if v.parameter not in allowed:
                raise FileFormatError(where, f"vary.{v.parameter}", f"unknown parameter; allowed: {', '.join(allowed)}")
            out[v.parameter] = self._si(spec, v)
        if spec.vary_all_uncertain:
            for key, m in self.params.measured_fields().items():
                if key not in out and key != "observed_chandler_period":
                    out[key] = _Resolved(key, "normal", mean=m.value, sd=m.sigma, unit=_unit_text(key))
        return tuple(out.values())  # the file's order (grid dimensions follow it)

    def _si(self, spec: SweepSpec, v: Variation) -> _Resolved:
        where = f"vary.{v.parameter}"
        si = PLANET_UNITS[v.parameter]
        try:
            unit = si if v.unit is None else u.Unit(v.unit or u.dimensionless_unscaled)
            scale = (1.0 * unit).to_value(si)
        except (ValueError, u.UnitConversionError):
            raise FileFormatError(_where(spec), f"{where}.unit", f"got {v.unit!r}; allowed: a unit of {si.to_string() or 'dimensionless'}") from None
        catalogued = getattr(self.params, v.parameter)
        if v.distribution == "normal":
            mean = v.mean * scale if v.mean is not None else (catalogued.value if catalogued else None)
            sd = v.sd * scale if v.sd is not None else (catalogued.sigma if catalogued else None)
            if mean is None or sd is None:
                raise FileFormatError(_where(spec), where, f"{self.planet.name} does not catalogue {v.parameter}; give mean and sd")
            return _Resolved(v.parameter, "normal", mean=mean, sd=sd, unit=_unit_text(v.parameter))
        if v.distribution == "uniform":
            return _Resolved(v.parameter, "uniform", low=v.low * scale, high=v.high * scale, unit=_unit_text(v.parameter))
        return _Resolved(v.parameter, "grid", values=tuple(x * scale for x in v.values), unit=_unit_text(v.parameter))

    def evaluate(self, overrides: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Outputs for one chunk of members (plain arrays; SI except periods in days)."""
        s = chandler_model.chandler_samples(self.params, overrides, self.model)
        out = {"invalid_reason": s.code}
        if "chandler_period" in self.selected:
            out["chandler_period"] = s.period / 86400.0
        if "wobble_rate" in self.selected:
            out["wobble_rate"] = s.rate
        if "quality_factor" in self.selected:
            out["quality_factor"] = s.quality_factor
        if "step_period" in self.selected:
            out["step_period"] = np.moveaxis(s.step_periods, 0, -1) / 86400.0
        if "dynamical_flattening" in self.selected:
            vals = chandler_model._Values(self.params.values(), overrides)
            out["dynamical_flattening"] = np.broadcast_to(vals.flattening, s.period.shape).copy()
        return out

    def extra_dims(self, name: str) -> tuple[tuple[str, np.ndarray], ...]:
        return (("step", np.array(self.steps)),) if name == "step_period" else ()

    def invalid_attrs(self) -> dict:
        codes = sorted(chandler_model.INVALID_REASONS)
        return {
            "units": "1",
            "long_name": "why the member is invalid (0: valid)",
            "flag_values": np.array(codes, dtype=np.int8),
            "flag_meanings": "valid intermediate_axis_spin core_too_large softer_than_fluid k2_not_converged parameter_out_of_range",
            "comment": "; ".join(f"{k}: {v}" for k, v in chandler_model.INVALID_REASONS.items() if k),
        }

    def output_attrs(self, name: str) -> dict:
        units, long_name = self.outputs[name]
        return {"units": units, "long_name": long_name}

    def attrs(self) -> dict:
        obs = self.planet.observed_chandler_period
        return {
            "sweep_main_output": "chandler_period",
            "body": self.planet.name,
            "chandler_model": self.model,
            "observed_chandler_period_days": float(obs.to_value(u.day)) if obs is not None else math.nan,
        }


def _unit_text(key: str) -> str:
    text = PLANET_UNITS[key].to_string()
    return text if text else "1"


class _BaseTarget:
    """A target whose members are set by a fixed ``[base]`` table plus the varied parameters.

    Subclasses give ``parameters`` (name -> (SI unit, long name, default in SI or
    None when required)), ``outputs`` (name -> (units, long name)), ``flags``
    (output name -> flag meanings, codes from ``flag_start``), the invalid
    reasons and :meth:`compute`.
    """

    name = ""
    parameters: dict = {}
    outputs: dict = {}
    flags: dict = {}
    default_outputs: tuple = ()
    invalid_reasons: dict = {}
    invalid_meanings = ""
    main_output = ""
    class_output = ""

    def __init__(self, spec: SweepSpec):
        where = _where(spec)
        if spec.body is not None:
            raise FileFormatError(where, "body", f"not used by target {self.name}; give the fixed parameters in [base]")
        if spec.vary_all_uncertain:
            raise FileFormatError(where, "vary_all_uncertain", f"only for target chandler, not {self.name}")
        allowed = ", ".join(self.parameters)
        self.base = {}
        for bv in spec.base:
            if bv.parameter not in self.parameters:
                raise FileFormatError(where, f"base.{bv.parameter}", f"unknown parameter of target {self.name}; allowed: {allowed}")
            self.base[bv.parameter] = bv.value * self._scale(spec, f"base.{bv.parameter}.unit", bv.unit, bv.parameter)
        out = {}
        for v in spec.variations:
            if v.parameter not in self.parameters:
                raise FileFormatError(where, f"vary.{v.parameter}", f"unknown parameter of target {self.name}; allowed: {allowed}")
            if v.parameter in self.base:
                raise FileFormatError(where, f"vary.{v.parameter}", "also fixed in [base]; give it in one place")
            out[v.parameter] = self._si(spec, v)
        self.variations = tuple(out.values())
        for name, (_, _, default) in self.parameters.items():
            if default is None and name not in self.base and name not in out:
                raise FileFormatError(where, "base", f"missing {name}; give it in [base] or [vary.{name}]")
        unknown = [o for o in spec.outputs if o not in self.outputs]
        if unknown:
            raise FileFormatError(where, "outputs", f"got {unknown[0]!r}; allowed: {', '.join(self.outputs)}")
        self.selected = spec.outputs or self.default_outputs

    def _scale(self, spec, where, unit, name) -> float:
        si = u.Unit(self.parameters[name][0])
        try:
            return float((1.0 * u.Unit(unit or u.dimensionless_unscaled)).to_value(si))
        except (ValueError, TypeError, u.UnitConversionError):
            raise FileFormatError(_where(spec), where, f"got {unit!r}; allowed: a unit of {si.to_string() or 'dimensionless'}") from None

    def _si(self, spec: SweepSpec, v: Variation) -> _Resolved:
        where = f"vary.{v.parameter}"
        unit_text = self.parameters[v.parameter][0]
        scale = 1.0 if v.unit is None else self._scale(spec, f"{where}.unit", v.unit, v.parameter)
        if v.distribution == "normal":
            if v.mean is None or v.sd is None:
                raise FileFormatError(_where(spec), where, f"target {self.name} has no catalogue; give mean and sd")
            return _Resolved(v.parameter, "normal", mean=v.mean * scale, sd=v.sd * scale, unit=unit_text)
        if v.distribution == "uniform":
            return _Resolved(v.parameter, "uniform", low=v.low * scale, high=v.high * scale, unit=unit_text)
        return _Resolved(v.parameter, "grid", values=tuple(x * scale for x in v.values), unit=unit_text)

    def values(self, overrides: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Every parameter for the chunk's members (SI), broadcast to the chunk's shape."""
        shape = np.broadcast_shapes(*(np.shape(a) for a in overrides.values()))
        out = {}
        for name, (_, _, default) in self.parameters.items():
            value = overrides.get(name, self.base.get(name, default))
            out[name] = np.broadcast_to(np.asarray(value, dtype=float), shape)
        return out

    def evaluate(self, overrides: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        res = self.compute(self.values(overrides))
        out = {"invalid_reason": res["invalid_reason"]}
        out.update({k: res[k] for k in self.selected})
        return out

    def extra_dims(self, name: str) -> tuple[tuple[str, np.ndarray], ...]:
        return ()

    def invalid_attrs(self) -> dict:
        return {
            "units": "1",
            "long_name": "why the member is invalid (0: valid)",
            "flag_values": np.array(sorted(self.invalid_reasons), dtype=np.int8),
            "flag_meanings": self.invalid_meanings,
            "comment": "; ".join(f"{k}: {v}" for k, v in self.invalid_reasons.items() if k),
        }

    def output_attrs(self, name: str) -> dict:
        units, long_name = self.outputs[name]
        attrs = {"units": units, "long_name": long_name}
        if name in self.flags:  # a CF flag variable: integer codes with their meanings
            start, meanings = self.flags[name]
            attrs = {"long_name": long_name, "units": "1",
                     "flag_values": np.arange(start, start + len(meanings.split()), dtype=np.int8),
                     "flag_meanings": meanings}
        return attrs

    def attrs(self) -> dict:
        base = "; ".join(f"{k} = {v:.10g} {self.parameters[k][0]}" for k, v in self.base.items())
        return {
            "sweep_main_output": self.main_output,
            "sweep_class_output": self.class_output,
            "sweep_base": base,
            "comment": "SI units (angles in rad). Random draws depend only on (seed, parameter, member).",
        }


class HeavyTopTarget(_BaseTarget):
    """The heavy symmetric top's nutation over a grid (or draws) of initial states (notes section 5.7).

    Evaluated by :func:`wobble.models.top_phase.phase_analysis`: numpy over the
    chunk, with the exact scalar model for members next to a class boundary.
    """

    name = "heavy_top"
    parameters = {
        "I1": ("kg m2", "transverse moment about the tip", None),
        "I3": ("kg m2", "axial moment", None),
        "mgl": ("J", "M g l", None),
        "theta0": ("rad", "initial tilt from the upward vertical", None),
        "omega3": ("rad s-1", "spin about the symmetry axis", None),
        "phidot0": ("rad s-1", "initial precession rate", 0.0),
        "thetadot0": ("rad s-1", "initial nutation rate", 0.0),
    }
    outputs = {
        "nutation_class": ("1", "class of the nutation (Goldstein, Poole & Safko 2002, sec. 5.7)"),
        "nutation_period": ("s", "nutation period 4 K(m) / sqrt(beta (u3 - u1)) (small-nutation period for uniform motion)"),
        "theta_min": ("rad", "smallest tilt of the symmetry axis (turning point u2)"),
        "theta_max": ("rad", "largest tilt of the symmetry axis (turning point u1)"),
        "mean_precession_rate": ("rad s-1", "mean of phidot over a nutation period"),
        "sleeping_stable": ("1", "sleeping top with this spin is stable: I3^2 omega3^2 > 4 M g l I1"),
        "scalar_fallback": ("1", "member analysed by the exact scalar model (next to a class boundary)"),
    }
    flags = {
        "nutation_class": (-1, flag_meanings(top_phase.NUTATION_CLASSES, "invalid")),
        "sleeping_stable": (0, "unstable stable"),
        "scalar_fallback": (0, "vectorised exact_scalar_model"),
    }
    default_outputs = tuple(outputs)
    invalid_meanings = "valid bad_top_parameters bad_initial_state separatrix"
    main_output = "nutation_period"
    class_output = "nutation_class"

    invalid_reasons = top_phase.INVALID_REASONS

    def compute(self, p):
        res = top_phase.phase_analysis(p["I1"], p["I3"], p["mgl"], p["theta0"], p["omega3"], p["phidot0"], p["thetadot0"])
        for k in ("sleeping_stable", "scalar_fallback"):
            res[k] = res[k].astype(np.int8)
        return res


class FreeRotationTarget(_BaseTarget):
    """Torque-free tumbling bodies (asteroids): regime, periods, wobble angles, omega at a time.

    Member j has moments (I_a, I_a r_b, I_a r_b r_c) along its body axes (a, b, c)
    and omega0 of period P along the direction with cos(colatitude from c) and
    longitude from a towards b; evaluated by
    :func:`wobble.models.free_ensemble.free_ensemble` (numpy over the chunk).
    """

    name = "free_rotation"
    parameters = {
        "moment_a": ("kg m2", "principal moment about body axis a", None),
        "moment_ratio_ba": ("1", "I_b / I_a", None),
        "moment_ratio_cb": ("1", "I_c / I_b", None),
        "spin_period": ("s", "2 pi / |omega0|", None),
        "spin_cos_colatitude": ("1", "cosine of the angle between omega0 and body axis c", None),
        "spin_longitude": ("rad", "azimuth of omega0 about c, from a towards b", 0.0),
        "final_time": ("s", "time of omega_final", 0.0),
    }
    outputs = {
        "regime": ("1", "rotation state"),
        "nutation_period": ("s", "period of omega in the body frame, 4 K(m) / lambda"),
        "precession_period": ("s", "2 pi / mean precession rate of the circulation axis about L"),
        "precession_rate": ("rad s-1", "mean precession rate of the circulation axis about L"),
        "wobble_angle_min": ("rad", "smallest angle between the circulation axis and L"),
        "wobble_angle_max": ("rad", "largest angle between the circulation axis and L"),
        "omega_final": ("rad s-1", "body-frame angular velocity at final_time (exact flow map)"),
    }
    flags = {"regime": (-1, flag_meanings(free_ensemble.REGIMES, "invalid"))}
    default_outputs = tuple(outputs)
    invalid_meanings = "valid triangle_inequality_violated bad_moments_or_spin"
    main_output = "precession_period"
    class_output = "regime"

    invalid_reasons = free_ensemble.INVALID_REASONS

    coord_attrs = {"body_axis": {"long_name": "body axis (1: a, 2: b, 3: c)", "units": "1"}}

    def extra_dims(self, name: str):
        return (("body_axis", np.arange(1, 4, dtype=np.int8)),) if name == "omega_final" else ()

    def compute(self, p):
        shape = p["moment_a"].shape
        ia = p["moment_a"].ravel()
        ib = ia * p["moment_ratio_ba"].ravel()
        ic = ib * p["moment_ratio_cb"].ravel()
        with np.errstate(invalid="ignore", divide="ignore"):
            rate = 2.0 * np.pi / p["spin_period"].ravel()
        cz = p["spin_cos_colatitude"].ravel()
        with np.errstate(invalid="ignore"):
            sz = np.sqrt(np.maximum(1.0 - cz * cz, 0.0))
        lon = p["spin_longitude"].ravel()
        omega0 = rate[:, None] * np.stack([sz * np.cos(lon), sz * np.sin(lon), cz], -1)
        res = free_ensemble.free_ensemble(np.stack([ia, ib, ic], -1), omega0, p["final_time"].ravel())
        bad_spin = ~((np.abs(cz) <= 1) & (p["spin_period"].ravel() > 0))
        res["invalid_reason"] = np.where(bad_spin & (res["invalid_reason"] == 0), 2, res["invalid_reason"]).astype(np.int8)
        for k, v in res.items():
            if k != "invalid_reason":
                v[bad_spin] = -1 if v.dtype == np.int8 else np.nan
        return {k: v.reshape(shape + v.shape[1:]) for k, v in res.items()}


TARGETS = {"chandler": ChandlerTarget, "heavy_top": HeavyTopTarget, "free_rotation": FreeRotationTarget}


def _target(spec: SweepSpec):
    if spec.target not in TARGETS:
        raise FileFormatError(_where(spec), "target", f"got {spec.target!r}; allowed: {', '.join(TARGETS)}")
    return TARGETS[spec.target](spec)


# ---------------------------------------------------------------------------
# Members, chunks and the lazy dataset
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _Plan:
    spec: SweepSpec
    target: object
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    chunk_rows: int  # along the first dimension

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def row_chunks(self):
        for start in range(0, self.shape[0], self.chunk_rows):
            yield start, min(self.shape[0], start + self.chunk_rows)

    def overrides(self, r0: int, r1: int) -> dict[str, np.ndarray]:
        """Parameter values for rows r0..r1 of the first dimension (all members in them)."""
        if self.spec.is_grid:
            grids = [np.asarray(v.values) for v in self.target.variations]
            grids[0] = grids[0][r0:r1]
            mesh = np.meshgrid(*grids, indexing="ij")
            return {v.name: m for v, m in zip(self.target.variations, mesh)}
        return {v.name: v.member_values(self.spec.seed, r0, r1) for v in self.target.variations}


def _plan(spec: SweepSpec, chunk_size: int | None) -> _Plan:
    target = _target(spec)
    chunk = chunk_size or spec.chunk_size or DEFAULT_CHUNK
    if not isinstance(chunk, int) or isinstance(chunk, bool) or chunk <= 0:
        raise InputError("chunk_size", chunk, "a positive integer")
    if spec.is_grid:
        dims = tuple(v.name for v in target.variations)
        shape = tuple(len(v.values) for v in target.variations)
        per_row = int(np.prod(shape[1:])) if len(shape) > 1 else 1
        rows = max(1, chunk // per_row)
    else:
        dims, shape, rows = ("member",), (spec.members,), chunk
    return _Plan(spec, target, dims, shape, rows)


def _chunk(plan: _Plan, r0: int, r1: int) -> dict[str, np.ndarray]:
    over = plan.overrides(r0, r1)
    out = plan.target.evaluate(over)
    if not plan.spec.is_grid:
        out.update(over)  # keep each member's drawn values
    return out


def _var_attrs(plan: _Plan, name: str) -> dict:
    target = plan.target
    if name == "invalid_reason":
        return target.invalid_attrs()
    if name in target.outputs:
        return target.output_attrs(name)
    var = next(v for v in target.variations if v.name == name)
    how = f"normal(mean={var.mean:.10g}, sd={var.sd:.6g})" if var.distribution == "normal" else f"uniform({var.low:.10g}, {var.high:.10g})"
    return {"units": var.unit, "long_name": f"sampled {name}", "comment": f"drawn from {how} in SI units"}


def _layout(plan: _Plan):
    """Names, dims, shapes and dtypes of the output variables (from a 1-row probe)."""
    probe = _chunk(plan, 0, min(plan.shape[0], 1))
    layout = {}
    for name, arr in probe.items():
        extra = plan.target.extra_dims(name)
        dims = plan.dims + tuple(d for d, _ in extra)
        shape = plan.shape + tuple(len(c) for _, c in extra)
        layout[name] = (dims, shape, arr.dtype)
    return layout


def _coords(plan: _Plan) -> dict:
    coords = {}
    if plan.spec.is_grid:
        for v in plan.target.variations:
            coords[v.name] = (v.name, np.asarray(v.values), {"units": v.unit, "long_name": f"grid of {v.name}"})
    else:
        coords["member"] = ("member", np.arange(plan.shape[0]), {"long_name": "member index", "units": "1"})
    for name in plan.target.outputs:
        for dim, values in plan.target.extra_dims(name):
            attrs = getattr(plan.target, "coord_attrs", {}).get(dim, {"long_name": f"{dim} of the model"})
            coords[dim] = (dim, values, attrs)
    return coords


def _attrs(plan: _Plan) -> dict:
    spec = plan.spec
    return {
        "title": spec.title,
        "references": "Monte Carlo propagation of the catalogue's uncertainties (JCGM 101:2008, GUM Supplement 1)",
        "sweep_name": spec.name,
        "sweep_target": spec.target,
        "sweep_seed": spec.seed,
        "sweep_file": spec.path or "",
        "comment": "Periods in days of 86400 s. Random draws depend only on (seed, parameter, member).",
        **plan.target.attrs(),
    }


def sweep(spec, *, chunk_size: int | None = None) -> xr.Dataset:
    """A sweep as a lazy (dask-backed) Dataset; nothing is computed yet.

    Parameters
    ----------
    spec : path, dict or SweepSpec
        The sweep (see :mod:`wobble.io.sweep_file`).
    chunk_size : int, optional
        Members per chunk (default: the file's ``chunk_size`` or 20000).

    Returns
    -------
    xarray.Dataset
        Dimension ``member`` (random sweeps) or one per grid parameter; the
        outputs, each member's drawn values and ``invalid_reason``.
    """
    plan = _plan(load_sweep(spec), chunk_size)
    layout = _layout(plan)
    parts = {name: [] for name in layout}
    for r0, r1 in plan.row_chunks():
        result = dask.delayed(_chunk, pure=True)(plan, r0, r1)
        for name, (dims, shape, dtype) in layout.items():
            block_shape = (r1 - r0, *shape[1:])
            parts[name].append(da.from_delayed(result[name], shape=block_shape, dtype=dtype))
    data = {
        name: (dims, da.concatenate(parts[name], axis=0), _var_attrs(plan, name))
        for name, (dims, shape, dtype) in layout.items()
    }
    return xr.Dataset(data, coords=_coords(plan), attrs=_attrs(plan))


# ---------------------------------------------------------------------------
# Running to a file, on any scheduler
# ---------------------------------------------------------------------------


class _Progress:
    """A one-line progress bar on stderr (only when asked: the CLI asks on a terminal)."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled, self.done, self.t0 = total, enabled, 0, time.perf_counter()

    def advance(self, n: int):
        self.done += n
        if self.enabled:
            frac = self.done / self.total
            bar = "#" * int(30 * frac)
            rate = self.done / max(time.perf_counter() - self.t0, 1e-9)
            sys.stderr.write(f"\r[{bar:<30}] {100 * frac:5.1f}% {self.done}/{self.total} members, {rate:,.0f}/s")
            sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\n")


@contextlib.contextmanager
def _pool(scheduler, n_chunks: int):
    """One process pool for a whole run (dask would start a new one per compute call)."""
    if scheduler != "processes" or n_chunks <= 1:
        yield None
        return
    import concurrent.futures
    import multiprocessing

    workers = min(os.cpu_count() or 1, n_chunks)
    with concurrent.futures.ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        yield pool


def _compute_chunks(plan: _Plan, scheduler, batch: int):
    """Yield (r0, r1, outputs) chunk by chunk, computed in parallel batches on dask."""
    chunks = list(plan.row_chunks())
    if scheduler is None or scheduler in _LOCAL_SCHEDULERS:
        with _pool(scheduler, len(chunks)) as pool:
            extra = {"pool": pool} if pool is not None else {}
            for i in range(0, len(chunks), batch):
                todo = chunks[i : i + batch]
                delayed = [dask.delayed(_chunk, pure=True)(plan, a, b) for a, b in todo]
                results = dask.compute(*delayed, scheduler=scheduler or "threads", **extra)
                for (a, b), res in zip(todo, results):
                    yield a, b, res
        return
    from distributed import Client, as_completed

    own = isinstance(scheduler, str)
    client = Client(scheduler) if own else scheduler
    try:
        pending = iter(chunks)
        futures = {}
        for a, b in [next(pending) for _ in range(min(batch, len(chunks)))]:
            futures[client.submit(_chunk, plan, a, b, pure=True)] = (a, b)
        queue = as_completed(list(futures))
        for fut in queue:
            a, b = futures.pop(fut)
            yield a, b, fut.result()
            nxt = next(pending, None)
            if nxt is not None:
                new = client.submit(_chunk, plan, *nxt, pure=True)
                futures[new] = nxt
                queue.add(new)
    finally:
        if own:
            client.close()


def run_sweep(
    spec,
    output: str | os.PathLike | None = None,
    *,
    overwrite: bool = False,
    chunk_size: int | None = None,
    scheduler=None,
    progress: bool = False,
    command: str | None = None,
) -> xr.Dataset:
    """Run a sweep; stream it to ``output`` (CF netCDF) if given, else compute it in memory.

    Parameters
    ----------
    spec : path, dict or SweepSpec
        The sweep.
    output : path-like, optional
        netCDF file, or a Zarr store when the name ends in ``.zarr`` (needs the
        optional ``zarr`` package), written chunk by chunk under a temporary name
        and renamed at the end (memory stays bounded whatever the member count).
    overwrite : bool
        Replace an existing output file.
    chunk_size : int, optional
        Members per chunk.
    scheduler : str or distributed.Client, optional
        ``"threads"`` (default), ``"processes"``, ``"synchronous"``, a
        ``dask.distributed`` scheduler address (``"tcp://..."``) or a Client.
    progress : bool
        Show a progress bar on stderr.
    command : str, optional
        Recorded in the file's history.

    Returns
    -------
    xarray.Dataset
        The results (read back from the file when ``output`` is given).
    """
    from wobble.io.netcdf import open_wobble

    plan = _plan(load_sweep(spec), chunk_size)
    if isinstance(scheduler, str) and scheduler not in _LOCAL_SCHEDULERS and "://" not in scheduler:
        raise InputError("scheduler", scheduler, "threads, processes, synchronous or a scheduler address such as tcp://127.0.0.1:8786")
    template = sweep(plan.spec, chunk_size=chunk_size)
    batch = 2 * (os.cpu_count() or 2)
    bar = _Progress(plan.size, progress)

    def blocks():
        per_row = plan.size // plan.shape[0]
        for r0, r1, res in _compute_chunks(plan, scheduler, batch):
            for name, values in res.items():
                index = (slice(r0, r1),) + (slice(None),) * (values.ndim - 1)
                yield name, index, values
            bar.advance((r1 - r0) * per_row)

    try:
        if output is None:
            arrays = {name: np.empty(template[name].shape, dtype=template[name].dtype) for name in template.data_vars}
            for name, index, values in blocks():
                arrays[name][index] = values
            data = {n: (template[n].dims, a, template[n].attrs) for n, a in arrays.items()}
            return xr.Dataset(data, coords=template.coords, attrs=template.attrs)
        if is_zarr_path(output):
            write_zarr_blocks(template, output, blocks(), overwrite=overwrite, command=command)
        else:
            write_netcdf_blocks(template, output, blocks(), overwrite=overwrite, command=command)
    finally:
        bar.close()
    return open_wobble_zarr(output) if is_zarr_path(output) else open_wobble(output)


# ---------------------------------------------------------------------------
# Summaries
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SweepSummary:
    """Distribution of a sweep's main output over its valid members."""

    variable: str
    units: str
    members: int
    valid: int
    mean: float
    std: float
    percentiles: dict
    observed: float
    invalid_reasons: dict
    classes: dict = None

    def to_dict(self) -> dict:
        d = self.__dict__.copy()
        d["observed"] = None if math.isnan(self.observed) else self.observed
        return d


def summarize_sweep(ds: xr.Dataset, variable: str | None = None) -> SweepSummary:
    """Mean, spread and percentiles of ``variable`` over valid finite members, invalid counts by reason.

    ``variable`` defaults to the target's main output (``chandler_period``,
    ``nutation_period`` or ``precession_period``); for targets with a class
    output (``nutation_class``, ``regime``) ``classes`` counts the valid
    members in each class.
    """
    variable = variable or ds.attrs.get("sweep_main_output", "chandler_period")
    if variable not in ds:
        raise InputError("variable", variable, f"one of {', '.join(map(str, ds.data_vars))}")
    values = np.asarray(ds[variable].values, dtype=float).ravel()
    codes = np.asarray(ds["invalid_reason"].values).ravel()
    ok = (codes == 0) & np.isfinite(values)
    good = values[ok]
    pct = {str(p): float(np.percentile(good, p)) if good.size else math.nan for p in (2.5, 16, 50, 84, 97.5)}
    target = TARGETS.get(ds.attrs.get("sweep_target", "chandler"), ChandlerTarget)
    texts = chandler_model.INVALID_REASONS if target is ChandlerTarget else target.invalid_reasons
    reasons = {texts[int(c)]: int(n) for c, n in zip(*np.unique(codes[codes != 0], return_counts=True))}
    classes = None
    class_output = ds.attrs.get("sweep_class_output", "")
    if class_output and class_output in ds:
        flag = ds[class_output]
        meanings = str(flag.attrs["flag_meanings"]).split()
        flag_values = np.asarray(flag.attrs["flag_values"]).tolist()
        cls = np.asarray(flag.values).ravel()[codes == 0]
        classes = {meaning: int((cls == v).sum()) for v, meaning in zip(flag_values, meanings) if v >= 0}
    return SweepSummary(
        variable=variable,
        units=str(ds[variable].attrs.get("units", "")),
        members=int(values.size),
        valid=int(ok.sum()),
        mean=float(good.mean()) if good.size else math.nan,
        std=float(good.std(ddof=1)) if good.size > 1 else math.nan,
        percentiles=pct,
        observed=float(ds.attrs.get("observed_chandler_period_days", math.nan)),
        invalid_reasons=reasons,
        classes=classes,
    )

