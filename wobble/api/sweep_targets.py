"""Sweep targets: what one member of a sweep computes, vectorised over a chunk of members.

A target reads its part of the sweep file (the body, the varied parameters and their
distributions, the outputs wanted), resolves every number to SI, and evaluates a chunk
of members at once with the vectorised models: the Chandler budget
(:func:`wobble.models.chandler.chandler_samples`), the heavy top's phase diagram
(:mod:`wobble.models.top_phase`) and the free body's regimes
(:mod:`wobble.models.free_ensemble`). :mod:`wobble.api.sweep` plans, runs and writes them.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass

import numpy as np
from astropy import units as u

from wobble.api.chandler import load_planet
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import PLANET_UNITS
from wobble.io.cf import udunits
from wobble.io.sweep_file import SweepSpec, Variation
from wobble.models import chandler as chandler_model
from wobble.models import free_ensemble, top_phase
from wobble.models.vocabulary import flag_meanings
from wobble.numerics import draws

__all__ = ["TARGETS", "ChandlerTarget", "HeavyTopTarget", "FreeRotationTarget", "sweep_source", "target_for"]


def sweep_source(spec: SweepSpec) -> str:
    """The sweep's file for error messages (``<sweep>`` for a mapping)."""
    return spec.path or "<sweep>"


def _stream_id(name: str) -> int:
    # Stable per parameter name, so adding a parameter never changes another's draws.
    return zlib.crc32(name.encode())


@dataclass(frozen=True)
class _Resolved:
    """A variation with its numbers in SI (``unit``), and the unit the file gave them in (``shown``, ``scale``
    SI per shown unit: a grid or draws given in km are written in km, as the user speaks; the model gets SI)."""

    name: str
    distribution: str
    mean: float = math.nan
    sd: float = math.nan
    low: float = math.nan
    high: float = math.nan
    values: tuple[float, ...] = ()
    unit: str = ""
    shown: str = ""
    scale: float = 1.0
    shown_values: tuple[float, ...] = ()

    @property
    def shown_units(self) -> str:
        """The ``units`` attribute of this parameter's coordinate or variable in the output."""
        return self.shown or self.unit

    def shown_grid(self) -> np.ndarray:
        """The grid as the file gave it (not SI and back, which may move a value by a rounding)."""
        return np.asarray(self.shown_values, dtype=float)

    def shown_draws(self, si: np.ndarray) -> np.ndarray:
        """Drawn values (SI) in the shown unit."""
        return si if self.scale == 1.0 else si / self.scale

    def member_values(self, seed: int, start: int, stop: int) -> np.ndarray:
        if self.distribution == "normal":
            return self.mean + self.sd * draws.standard_normal(seed, _stream_id(self.name), start, stop)
        return self.low + (self.high - self.low) * draws.uniform(seed, _stream_id(self.name), start, stop)


class ChandlerTarget:
    """Chandler periods of a planet whose parameters vary (vectorised model)."""

    name = "chandler"
    references = "Chandler period budget: see wobble chandler --sources for every parameter's source"
    outputs = {
        "chandler_period": ("day", "modelled Chandler wobble period"),
        "wobble_rate": ("rad s-1", "signed free wobble frequency (positive: prograde)"),
        "quality_factor": ("1", "wobble quality factor implied by the out-of-phase Love number"),
        "step_period": ("day", "Chandler period after each model step"),
        "dynamical_flattening": ("1", "dynamical flattening H = (C - A)/C of the member"),
    }
    default_outputs = ("chandler_period",)

    def __init__(self, spec: SweepSpec):
        where = sweep_source(spec)
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
        where = sweep_source(spec)
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
        require_unit(spec, v, si)
        try:
            unit = si if v.unit is None else u.Unit(v.unit or u.dimensionless_unscaled)
            scale = (1.0 * unit).to_value(si)
        except (ValueError, u.UnitConversionError):
            raise FileFormatError(
                sweep_source(spec),
                f"{where}.unit",
                f"got {v.unit!r}; allowed: {_unit_kind(si)}",
            ) from None
        catalogued = getattr(self.params, v.parameter)
        if v.distribution == "normal":
            mean = v.mean * scale if v.mean is not None else (catalogued.value if catalogued else None)
            sd = v.sd * scale if v.sd is not None else (catalogued.sigma if catalogued else None)
            if mean is None or sd is None:
                raise FileFormatError(
                    sweep_source(spec), where, f"{self.planet.name} does not catalogue {v.parameter}; give mean and sd"
                )
            return _resolved(v, _unit_text(v.parameter), scale, mean=mean, sd=sd)
        return _resolved(v, _unit_text(v.parameter), scale)

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
            vals = chandler_model.ParameterValues(self.params.values(), overrides)
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
            "flag_meanings": "valid intermediate_axis_spin core_too_large softer_than_fluid k2_not_converged "
            "parameter_out_of_range",
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


def require_unit(spec: SweepSpec, v: Variation, si) -> None:
    """A variation that gives numbers for a parameter with a dimension says their unit.

    Read in SI without one, a core radius of 5000 (meant in km, as the planet file gives it) was a 5 m core,
    and the run said nothing; the planet and base tables already require a unit ("" for a pure number).
    """
    numbers = any(x is not None for x in (v.mean, v.sd, v.low, v.high, v.values))
    if v.unit is None and numbers and si.physical_type != "dimensionless":
        raise FileFormatError(
            sweep_source(spec),
            f"vary.{v.parameter}.unit",
            f"missing; allowed: the unit of the numbers given (a unit of {si.physical_type}, e.g. "
            f'unit = "{si.to_string()}")',
        )


def _resolved(v: Variation, unit_text: str, scale: float, mean=None, sd=None) -> _Resolved:
    """``v`` in SI (``scale``: SI per unit of the file), remembering the file's unit for the output;
    ``mean`` and ``sd`` (SI) replace a normal distribution's where they are the catalogue's."""
    shown = {} if v.unit is None else {"shown": udunits(v.unit), "scale": scale}
    if v.distribution == "normal":
        mean = v.mean * scale if mean is None else mean
        sd = v.sd * scale if sd is None else sd
        return _Resolved(v.parameter, "normal", mean=mean, sd=sd, unit=unit_text, **shown)
    if v.distribution == "uniform":
        return _Resolved(v.parameter, "uniform", low=v.low * scale, high=v.high * scale, unit=unit_text, **shown)
    values = tuple(x * scale for x in v.values)
    return _Resolved(v.parameter, "grid", values=values, unit=unit_text, shown_values=tuple(v.values), **shown)


def _unit_kind(si) -> str:
    """What a unit must be, for an error: ``a unit of length (e.g. m)``; it said ``a unit of m``."""
    if si.physical_type == "dimensionless":
        return 'a pure number (unit = "" or left out)'
    return f"a unit of {si.physical_type} (e.g. {si.to_string()})"


def _unit_text(key: str) -> str:
    """The UDUNITS-style string of the parameter's SI unit, as the other files write them (``rad s-1``, not
    astropy's ``rad / s``); "1" for a pure number (:func:`wobble.io.cf.udunits`, as the posterior files)."""
    return udunits(PLANET_UNITS[key])


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
        where = sweep_source(spec)
        if spec.body is not None:
            raise FileFormatError(where, "body", f"not used by target {self.name}; give the fixed parameters in [base]")
        if spec.vary_all_uncertain:
            raise FileFormatError(where, "vary_all_uncertain", f"only for target chandler, not {self.name}")
        allowed = ", ".join(self.parameters)
        self.base = {}
        self._base_text = {}
        for bv in spec.base:
            if bv.parameter not in self.parameters:
                raise FileFormatError(
                    where, f"base.{bv.parameter}", f"unknown parameter of target {self.name}; allowed: {allowed}"
                )
            self.base[bv.parameter] = bv.value * self._scale(spec, f"base.{bv.parameter}.unit", bv.unit, bv.parameter)
            # As the file gave it (10 d, not 864000 s), for the file's sweep_base attribute.
            self._base_text[bv.parameter] = (
                f"{bv.value:.10g} {self.parameters[bv.parameter][0] if bv.unit is None else udunits(bv.unit)}"
            )
        out = {}
        for v in spec.variations:
            if v.parameter not in self.parameters:
                raise FileFormatError(
                    where, f"vary.{v.parameter}", f"unknown parameter of target {self.name}; allowed: {allowed}"
                )
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
            raise FileFormatError(sweep_source(spec), where, f"got {unit!r}; allowed: {_unit_kind(si)}") from None

    def _si(self, spec: SweepSpec, v: Variation) -> _Resolved:
        where = f"vary.{v.parameter}"
        unit_text = self.parameters[v.parameter][0]
        require_unit(spec, v, u.Unit(unit_text))
        scale = 1.0 if v.unit is None else self._scale(spec, f"{where}.unit", v.unit, v.parameter)
        if v.distribution == "normal" and (v.mean is None or v.sd is None):
            raise FileFormatError(sweep_source(spec), where, f"target {self.name} has no catalogue; give mean and sd")
        return _resolved(v, unit_text, scale)

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
            attrs = {
                "long_name": long_name,
                "units": "1",
                "flag_values": np.arange(start, start + len(meanings.split()), dtype=np.int8),
                "flag_meanings": meanings,
            }
        return attrs

    def attrs(self) -> dict:
        base = "; ".join(f"{k} = {text}" for k, text in self._base_text.items())
        return {
            "sweep_main_output": self.main_output,
            "sweep_class_output": self.class_output,
            "sweep_base": base,
            "comment": "Outputs in SI units (angles in rad); the varied and fixed parameters in the units the sweep "
            "file gave them (see each one's units). Random draws depend only on (seed, parameter, member).",
        }


class HeavyTopTarget(_BaseTarget):
    """The heavy symmetric top's nutation over a grid (or draws) of initial states (Goldstein et al. 2002, sec. 5.7).

    Evaluated by :func:`wobble.models.top_phase.phase_analysis`: numpy over the
    chunk, with the exact scalar model for members next to a class boundary.
    """

    name = "heavy_top"
    references = "Goldstein, Poole & Safko 2002, Classical Mechanics, sec. 5.7 (the heavy symmetric top)"
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
        "nutation_period": (
            "s",
            "nutation period 4 K(m) / sqrt(beta (u3 - u1)) (small-nutation period for uniform motion)",
        ),
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
        res = top_phase.phase_analysis(
            p["I1"], p["I3"], p["mgl"], p["theta0"], p["omega3"], p["phidot0"], p["thetadot0"]
        )
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
    references = "Landau & Lifshitz, Mechanics, sec. 37; Goldstein, Poole & Safko 2002, Classical Mechanics, sec. 5.6"
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
        res["invalid_reason"] = np.where(bad_spin & (res["invalid_reason"] == 0), 2, res["invalid_reason"]).astype(
            np.int8
        )
        for k, v in res.items():
            if k != "invalid_reason":
                v[bad_spin] = -1 if v.dtype == np.int8 else np.nan
        return {k: v.reshape(shape + v.shape[1:]) for k, v in res.items()}


TARGETS = {"chandler": ChandlerTarget, "heavy_top": HeavyTopTarget, "free_rotation": FreeRotationTarget}


def target_for(spec: SweepSpec):
    """The target object the sweep names (a file error when it names none)."""
    if spec.target not in TARGETS:
        raise FileFormatError(sweep_source(spec), "target", f"got {spec.target!r}; allowed: {', '.join(TARGETS)}")
    return TARGETS[spec.target](spec)
