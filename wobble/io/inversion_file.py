"""Inversion setups (``data/inversions/*.toml``): priors, observables, sampler settings.

Schema ``wobble-inversion/1``::

    schema = "wobble-inversion/1"
    name = "mars"
    title = "Mars' liquid core from its Chandler period and tidal k2"
    description = "..."
    body = "mars"                    # catalogue name, or a planet file (relative to this file)
    model = "full"                   # Chandler model: full or the last step
    derived = ["chandler_quality_factor"]   # registered quantities reported without a measurement

    [sampler]                        # all optional
    walkers = 32                     # even, >= 2 x parameters
    steps = 3000                     # kept per walker after the burn-in
    burn = 1000
    thin = 1
    ensembles = 1                    # independent ensembles (parallel on a dask scheduler)
    seed = 20230621                  # same seed, same numbers

    [parameters.fluid_core_radius]   # sampled; every other planet parameter keeps its value
    prior = "uniform"                # uniform | log_uniform | normal
    low = 1400                       # uniform, log_uniform: low, high; normal: mean, sd (+ low, high to truncate)
    high = 2200
    unit = "km"                      # unit of these numbers, and of the results
    source = "why this prior"

    [parameters.fluid_core_density]  # no prior given: normal(catalogue value, uncertainty),
    unit = "kg m-3"                  # truncated to the parameter's physical range

    [observables.chandler_period]    # a registered observable; no value: the catalogue's
    value = 206.9
    uncertainty = 0.5                # one sigma, required with a value
    unit = "d"
    source = "Konopliv et al. 2020"

    [observables.tidal_k2]
    value = 0.169
    uncertainty = 0.006
    tidal_period = { value = 44387.6, unit = "s" }   # an option of the observable
    source = "..."

    [[compare.fluid_core_radius]]    # published values shown beside the posterior
    value = 1830                     # value with uncertainty, or low and high (a range)
    uncertainty = 40
    unit = "km"
    source = "Staehler et al. 2021"

Everything is checked (with the file and key in the message) before any sampling:
unknown names, improper or contradictory priors, an observable without an
uncertainty, a forward model that fails at the priors' centre.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import PLANET_UNITS, load_planet
from wobble.io.parameter_file import ParameterFile, read_toml
from wobble.models.inversion.likelihood import Measurement, Parameter, Posterior
from wobble.models.inversion.observables import REGISTRY
from wobble.models.inversion.priors import KINDS, LogUniform, Normal, Uniform, physical_range
from wobble.models.inversion.sampling import SamplerSettings
from wobble.models.planet import PlanetParameters

__all__ = ["SCHEMA", "InversionSetup", "Comparison", "setup_names", "resolve_setup", "read_setup", "setup_from_dict"]

SCHEMA = "wobble-inversion/1"
_TOP = {"schema", "name", "title", "description", "body", "model", "derived", "sampler", "parameters", "observables", "compare"}
_SAMPLER = {"walkers", "steps", "burn", "thin", "ensembles", "prior_draws", "seed"}
_PRIOR_FIELDS = {
    "uniform": {"low", "high"},
    "log_uniform": {"low", "high"},
    "normal": {"mean", "sd", "low", "high"},
    None: set(),
}
_REQUIRED = {"uniform": ("low", "high"), "log_uniform": ("low", "high"), "normal": ("mean", "sd")}
_COMMON = {"prior", "unit", "source", "note"}
_OBS_FIELDS = {"value", "uncertainty", "unit", "source", "note"}
_COMPARE_FIELDS = {"value", "uncertainty", "low", "high", "unit", "source", "note"}
# Parameters that describe how the model is set up, not physics to infer.
_NOT_INVERTIBLE = {"observed_chandler_period"}


@dataclass(frozen=True)
class Comparison:
    """A published value (or range) of a parameter or derived quantity, for display (SI)."""

    name: str
    source: str
    value: float | None = None
    uncertainty: float | None = None
    low: float | None = None
    high: float | None = None


@dataclass(frozen=True)
class InversionSetup:
    """A checked setup: the planet, the parameters with priors, the observables, the sampler."""

    name: str
    title: str
    description: str
    body: str
    planet: PlanetParameters
    planet_file: ParameterFile
    model: str
    parameters: tuple[Parameter, ...]
    measurements: tuple[Measurement, ...]
    settings: SamplerSettings
    seed: int
    comparisons: tuple[Comparison, ...] = ()
    path: str | None = None
    extra: dict = field(default_factory=dict)

    def posterior(self, prior_only: bool = False) -> Posterior:
        return Posterior(self.parameters, self.measurements, self.planet, self.model, prior_only=prior_only)


def _folder():
    return resources.files("wobble._data") / "inversions"


def setup_names() -> list[str]:
    """Names of the shipped setups (``data/inversions/*.toml``)."""
    return sorted(p.name[:-5] for p in _folder().iterdir() if p.name.endswith(".toml"))


def resolve_setup(name: str | os.PathLike) -> Path:
    """A setup file by path, or a shipped setup by name (from any folder)."""
    text = os.fspath(name)
    path = Path(text)
    if path.is_file():
        return path
    if text.strip().lower() in setup_names():
        with resources.as_file(_folder() / f"{text.strip().lower()}.toml") as found:
            return Path(found)
    if path.suffix == ".toml":
        raise FileFormatError(path, None, "no such file")
    raise InputError("setup", text, f"a setup file (.toml) or one of {', '.join(setup_names())}")


def read_setup(name: str | os.PathLike) -> InversionSetup:
    """Read and check a setup file (or a shipped setup by name)."""
    path = resolve_setup(name)
    return setup_from_dict(read_toml(path), path)


def _num(path, where, raw, *, positive=False) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw):
        raise FileFormatError(path, where, f"got {raw!r}; allowed: a finite number")
    if positive and raw <= 0:
        raise FileFormatError(path, where, f"got {raw!r}; allowed: a positive number")
    return float(raw)


def _unit(path, where, text, si: u.UnitBase) -> tuple[str, float]:
    """(unit text, SI value of one unit), checked against the SI unit ``si``."""
    if not isinstance(text, str):
        raise FileFormatError(path, where, f"got {text!r}; allowed: a unit string such as \"km\" or \"\"")
    try:
        unit = u.Unit(text.strip() or u.dimensionless_unscaled, parse_strict="raise")
        scale = float((1.0 * unit).to_value(si))
    except (ValueError, u.UnitConversionError):
        want = si.to_string() or "dimensionless"
        raise FileFormatError(path, where, f"got {text!r}; allowed: a unit of {want}") from None
    return text.strip(), scale


def _si_unit(unit_text: str) -> u.UnitBase:
    return u.Unit(unit_text or u.dimensionless_unscaled)


def _string(path, where, raw, default="") -> str:
    if raw is None:
        return default
    if not isinstance(raw, str):
        raise FileFormatError(path, where, f"got {raw!r}; allowed: a string")
    return raw.strip()


def _sampler(path, raw) -> tuple[SamplerSettings, int]:
    if not isinstance(raw, dict):
        raise FileFormatError(path, "sampler", "must be a table")
    unknown = set(raw) - _SAMPLER
    if unknown:
        raise FileFormatError(path, f"sampler.{sorted(unknown)[0]}", f"unknown key; allowed: {', '.join(sorted(_SAMPLER))}")
    kwargs = {}
    for key, value in raw.items():
        if isinstance(value, bool) or not isinstance(value, int) or value < (0 if key in ("burn", "seed") else 1):
            raise FileFormatError(path, f"sampler.{key}", f"got {value!r}; allowed: a {'non-negative' if key in ('burn', 'seed') else 'positive'} integer")
        kwargs[key] = value
    seed = kwargs.pop("seed", 0)
    return SamplerSettings(**kwargs), seed


def _prior(path, name, raw, planet: PlanetParameters, pf: ParameterFile) -> Parameter:
    where = f"parameters.{name}"
    if not isinstance(raw, dict):
        raise FileFormatError(path, where, "must be a table (empty for the catalogue's value and uncertainty)")
    kind = raw.get("prior")
    if kind is not None and kind not in KINDS:
        raise FileFormatError(path, f"{where}.prior", f"got {kind!r}; allowed: {', '.join(KINDS)}")
    unknown = set(raw) - _COMMON - _PRIOR_FIELDS[kind]
    if unknown:
        allowed = ", ".join(sorted(_COMMON | _PRIOR_FIELDS[kind]))
        raise FileFormatError(path, f"{where}.{sorted(unknown)[0]}", f"not a field of a {kind or 'catalogue'} prior; allowed: {allowed}")
    si = PLANET_UNITS[name]
    catalogued = pf.get(name)
    default_unit = catalogued.value.unit.to_string() if catalogued is not None else si.to_string()
    unit, scale = _unit(path, f"{where}.unit", raw.get("unit", default_unit), si)
    source = _string(path, f"{where}.source", raw.get("source"))
    low_phys, high_phys = physical_range(name)
    if kind is None:
        measured = getattr(planet, name)
        if measured is None or measured.sigma == 0:
            raise FileFormatError(
                path, where,
                f"{planet.name} does not catalogue an uncertainty for {name}; allowed: a prior (uniform, log_uniform or normal)",
            )
        prior = Normal(measured.value, measured.sigma, low_phys, high_phys)
        source = source or f"catalogue: {catalogued.source if catalogued is not None else name}"
    else:
        missing = [k for k in _REQUIRED[kind] if k not in raw]
        if missing:
            raise FileFormatError(path, f"{where}.{missing[0]}", f"missing; a {kind} prior needs {' and '.join(_REQUIRED[kind])}")
        nums = {k: _num(path, f"{where}.{k}", raw[k]) * scale for k in _PRIOR_FIELDS[kind] if k in raw}
        if kind == "uniform":
            prior = Uniform(nums["low"], nums["high"])
        elif kind == "log_uniform":
            prior = LogUniform(nums["low"], nums["high"])
        else:
            prior = Normal(nums["mean"], nums["sd"], max(nums.get("low", -math.inf), low_phys), min(nums.get("high", math.inf), high_phys))
    try:
        return Parameter(name, prior, unit, scale, source)
    except InputError as exc:
        raise FileFormatError(path, where, f"{exc.value}; allowed: {exc.allowed}") from None


def _measurement(path, name, raw, planet: PlanetParameters, pf: ParameterFile) -> Measurement:
    where = f"observables.{name}"
    if name not in REGISTRY:
        raise FileFormatError(path, where, f"unknown observable; allowed: {', '.join(sorted(REGISTRY))}")
    model = REGISTRY[name]
    if not isinstance(raw, dict):
        raise FileFormatError(path, where, "must be a table (empty for the catalogue's measured value)")
    unknown = set(raw) - _OBS_FIELDS - set(model.options)
    if unknown:
        allowed = ", ".join(sorted(_OBS_FIELDS | set(model.options)))
        raise FileFormatError(path, f"{where}.{sorted(unknown)[0]}", f"unknown key; allowed: {allowed}")
    si = _si_unit(model.unit)
    unit, scale = _unit(path, f"{where}.unit", raw.get("unit", model.display_unit), si)
    options = {}
    for opt, opt_unit in model.options.items():
        if opt in raw:
            entry = raw[opt]
            if not isinstance(entry, dict) or set(entry) - {"value", "unit"} or "value" not in entry:
                raise FileFormatError(path, f"{where}.{opt}", "allowed: a table { value = ..., unit = \"...\" }")
            _, opt_scale = _unit(path, f"{where}.{opt}.unit", entry.get("unit", opt_unit), _si_unit(opt_unit))
            options[opt] = _num(path, f"{where}.{opt}.value", entry["value"], positive=True) * opt_scale
    source = _string(path, f"{where}.source", raw.get("source"))
    if "value" not in raw:
        if "uncertainty" in raw:
            raise FileFormatError(path, f"{where}.value", "missing: an uncertainty needs its value")
        key = model.catalogue_key
        measured = getattr(planet, key) if key else None
        if measured is None:
            raise FileFormatError(path, f"{where}.value", f"missing, and {planet.name} does not catalogue it; give value and uncertainty")
        value, sigma = measured.value, measured.sigma
        entry = pf.get(key)
        source = source or (entry.source if entry is not None else key)
    else:
        value = _num(path, f"{where}.value", raw["value"]) * scale
        if "uncertainty" not in raw:
            raise FileFormatError(path, f"{where}.uncertainty", "missing; allowed: a positive one-sigma uncertainty (a measurement without one cannot be weighed)")
        sigma = _num(path, f"{where}.uncertainty", raw["uncertainty"]) * scale
    if not sigma > 0:
        raise FileFormatError(path, f"{where}.uncertainty", f"got {sigma / scale:g}; allowed: a positive one-sigma uncertainty")
    try:
        return Measurement(name, value, sigma, options, unit, scale, source)
    except InputError as exc:
        raise FileFormatError(path, where, f"{exc.value}; allowed: {exc.allowed}") from None


def _derived(path, raw) -> tuple[Measurement, ...]:
    if not isinstance(raw, list) or not all(isinstance(x, str) for x in raw):
        raise FileFormatError(path, "derived", f"got {raw!r}; allowed: a list of registered quantity names")
    out = []
    for name in raw:
        if name not in REGISTRY:
            raise FileFormatError(path, "derived", f"unknown quantity {name!r}; allowed: {', '.join(sorted(REGISTRY))}")
        model = REGISTRY[name]
        _, scale = _unit(path, "derived", model.display_unit, _si_unit(model.unit))
        out.append(Measurement(name, unit=model.display_unit, scale=scale))
    return tuple(out)


def _comparisons(path, raw, units: dict[str, u.UnitBase]) -> tuple[Comparison, ...]:
    if not isinstance(raw, dict):
        raise FileFormatError(path, "compare", "must be a table of lists of published values")
    out = []
    for name, entries in raw.items():
        if name not in units:
            raise FileFormatError(path, f"compare.{name}", "not a sampled parameter or a reported quantity of this setup")
        if not isinstance(entries, list):
            entries = [entries]
        for i, entry in enumerate(entries):
            where = f"compare.{name}[{i}]"
            if not isinstance(entry, dict):
                raise FileFormatError(path, where, "must be a table")
            unknown = set(entry) - _COMPARE_FIELDS
            if unknown:
                raise FileFormatError(path, f"{where}.{sorted(unknown)[0]}", f"unknown key; allowed: {', '.join(sorted(_COMPARE_FIELDS))}")
            _, scale = _unit(path, f"{where}.unit", entry.get("unit", units[name].to_string()), units[name])
            nums = {k: _num(path, f"{where}.{k}", entry[k]) * scale for k in ("value", "uncertainty", "low", "high") if k in entry}
            if ("value" in nums) == ("low" in nums or "high" in nums) or ("low" in nums) != ("high" in nums):
                raise FileFormatError(path, where, "give value (with optional uncertainty) or low and high")
            source = _string(path, f"{where}.source", entry.get("source"))
            if not source:
                raise FileFormatError(path, f"{where}.source", "missing: a published value names its source")
            out.append(Comparison(name, source, nums.get("value"), nums.get("uncertainty"), nums.get("low"), nums.get("high")))
    return tuple(out)


def setup_from_dict(data: dict, path: str | os.PathLike | None = None) -> InversionSetup:
    """Check a setup given as a dict (the TOML structure) and build it (SI)."""
    where = str(path) if path is not None else "<setup>"
    if not isinstance(data, dict):
        raise FileFormatError(where, None, "a setup is a table (dict)")
    unknown = set(data) - _TOP
    if unknown:
        raise FileFormatError(where, sorted(unknown)[0], f"unknown key; allowed: {', '.join(sorted(_TOP))}")
    if data.get("schema") != SCHEMA:
        raise FileFormatError(where, "schema", f"got {data.get('schema')!r}; allowed: {SCHEMA!r}")
    name = _string(where, "name", data.get("name"))
    if not name:
        raise FileFormatError(where, "name", "missing; allowed: a non-empty string")
    body = _string(where, "body", data.get("body"))
    if not body:
        raise FileFormatError(where, "body", "missing; allowed: a catalogue name or a planet file")
    if path is not None and not body.lower().isidentifier():
        candidate = Path(path).parent / body
        body = str(candidate) if candidate.exists() else body
    try:
        planet, pf = load_planet(body)
    except InputError as exc:
        raise FileFormatError(where, "body", f"got {body!r}; allowed: {exc.allowed}") from None
    model = _string(where, "model", data.get("model"), "full")
    settings, seed = _sampler(where, data.get("sampler", {}))
    params_raw = data.get("parameters", {})
    if not isinstance(params_raw, dict) or not params_raw:
        raise FileFormatError(where, "parameters", "missing; allowed: one table per parameter to invert")
    allowed = sorted(k for k in planet.values() if k not in _NOT_INVERTIBLE)
    parameters = []
    for key, raw in params_raw.items():
        if key not in allowed:
            raise FileFormatError(where, f"parameters.{key}", f"unknown parameter; allowed: {', '.join(allowed)}")
        parameters.append(_prior(where, key, raw, planet, pf))
    obs_raw = data.get("observables", {})
    if not isinstance(obs_raw, dict):
        raise FileFormatError(where, "observables", "must be a table of observables")
    measurements = [_measurement(where, key, raw, planet, pf) for key, raw in obs_raw.items()]
    derived = _derived(where, data.get("derived", []))
    clash = {m.name for m in measurements} & {m.name for m in derived}
    if clash:
        raise FileFormatError(where, "derived", f"{sorted(clash)[0]} is also an observable; list it once")
    units = {p.name: _si_unit(PLANET_UNITS[p.name].to_string()) for p in parameters}
    units.update({m.name: _si_unit(REGISTRY[m.name].unit) for m in (*measurements, *derived)})
    comparisons = _comparisons(where, data.get("compare", {}), units)
    setup = InversionSetup(
        name=name,
        title=_string(where, "title", data.get("title"), name),
        description=_string(where, "description", data.get("description")),
        body=body,
        planet=planet,
        planet_file=pf,
        model=model,
        parameters=tuple(parameters),
        measurements=(*measurements, *derived),
        settings=settings,
        seed=seed,
        comparisons=comparisons,
        path=None if path is None else str(path),
    )
    try:
        posterior = setup.posterior()
        settings.check(posterior.ndim)
        posterior.check_centre()
    except InputError as exc:
        raise FileFormatError(where, exc.parameter, f"{exc.value}; allowed: {exc.allowed}") from None
    return setup
