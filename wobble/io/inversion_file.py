"""Inversion setups (``data/inversions/*.toml``): priors, observables, sampler settings.

Schema ``wobble-inversion/1``::

    schema = "wobble-inversion/1"
    name = "mars"
    title = "Mars' liquid core from its Chandler period and tidal k2"
    description = "..."
    body = "mars"                    # catalogue name, or a planet file (relative to this file)
    model = "full"                   # Chandler model: full or the last step
    profile = "mars_layered"         # density profile of the core's hydrostatic flattening (FCN);
                                     # default: the shipped profile of the body
    derived = ["chandler_quality_factor"]   # registered quantities reported without a measurement

    [sampler]                        # all optional
    walkers = 32                     # even, >= 2 x parameters
    steps = 3000                     # kept per walker after the burn-in
    burn = 1000
    thin = 1
    ensembles = 1                    # independent ensembles (parallel on a dask scheduler)
    seed = 20230621                  # same seed, same numbers
    moves = { independence = 0.8, de = 0.15, de_snooker = 0.05 }   # the default mixture (also: stretch)

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

Forward models that need more than the planet's parameters get it here
(:class:`~wobble.models.inversion.context.ForwardContext`): the free core nutation
(``fcn_period``, ``core_ellipticity``) the hydrostatic flattening of the core from the
density profile (a fixed profile such as PREM gives one number; a profile built from
the body's catalogue, ``construction = "core_under_linear_mantle"``, is rebuilt for
every draw, tabulated over the box the priors reach); the precession rate
(``precession_rate``) the Sun on the body's orbit and the catalogued satellites
(``data/precession``), with geodesic precession when the observed rate includes it.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from astropy import units as u

from wobble.io.cf import INT64_ALLOWED, INT64_MAX
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import PLANET_UNITS, load_planet
from wobble.io.density_profile import load_profile, profile_for_body
from wobble.io.parameter_file import ParameterFile, read_toml
from wobble.io.perturbers import (
    PERTURBER_UNITS,
    default_perturbers,
    load_perturber,
    measured,
    perturber_orbit,
    perturber_values,
    too_close_note,
)
from wobble.models import hydrostatic as _hydro
from wobble.models import precession as _precession
from wobble.models.inversion.context import FixedCoreFigure, ForwardContext, LinearMantleCoreFigure, box_corners
from wobble.models.inversion.likelihood import Measurement, Parameter, Posterior
from wobble.models.inversion.observables import REGISTRY
from wobble.models.inversion.priors import KINDS, LogUniform, Normal, Uniform, physical_range
from wobble.models.inversion.sampling import MOVE_NAMES, SamplerSettings
from wobble.models.planet import PlanetParameters

__all__ = ["SCHEMA", "InversionSetup", "Comparison", "setup_names", "resolve_setup", "read_setup", "setup_from_dict"]

SCHEMA = "wobble-inversion/1"
_TOP = {
    "schema",
    "name",
    "title",
    "description",
    "body",
    "model",
    "profile",
    "derived",
    "sampler",
    "parameters",
    "observables",
    "compare",
}
_SAMPLER = {"walkers", "steps", "burn", "thin", "ensembles", "prior_draws", "seed", "moves"}
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
_NOT_INVERTIBLE = {
    "observed_chandler_period",
    "observed_fcn_period",
    "observed_precession_rate",
    "observed_precession_includes_geodesic",
}
# Observables that need the core's hydrostatic figure, or the perturbers.
_NEEDS_CORE = {"fcn_period", "core_ellipticity"}
_NEEDS_PERTURBERS = {"precession_rate"}
# Tail probability of a normal prior left outside the tabulated hydrostatic core.
_PRIOR_TAIL = 1e-12


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
    context: ForwardContext = field(default_factory=ForwardContext)
    #: What the forward models leave out and say so (a planet too close to the body's orbit).
    notes: tuple[str, ...] = ()

    def posterior(self, prior_only: bool = False) -> Posterior:
        return Posterior(
            self.parameters, self.measurements, self.planet, self.model, prior_only=prior_only, context=self.context
        )


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
        raise FileFormatError(path, where, f'got {text!r}; allowed: a unit string such as "km" or ""')
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
        raise FileFormatError(
            path, f"sampler.{sorted(unknown)[0]}", f"unknown key; allowed: {', '.join(sorted(_SAMPLER))}"
        )
    kwargs = {}
    if "moves" in raw:
        moves = raw["moves"]
        if not isinstance(moves, dict) or not moves:
            raise FileFormatError(
                path, "sampler.moves", f"got {moves!r}; allowed: a table of move = weight ({', '.join(MOVE_NAMES)})"
            )
        for name, weight in moves.items():
            if name not in MOVE_NAMES:
                raise FileFormatError(path, f"sampler.moves.{name}", f"unknown move; allowed: {', '.join(MOVE_NAMES)}")
            if (
                isinstance(weight, bool)
                or not isinstance(weight, (int, float))
                or not (math.isfinite(weight) and weight > 0)
            ):
                raise FileFormatError(path, f"sampler.moves.{name}", f"got {weight!r}; allowed: a positive weight")
        kwargs["moves"] = tuple((name, float(weight)) for name, weight in moves.items())
        raw = {k: v for k, v in raw.items() if k != "moves"}
    for key, value in raw.items():
        if isinstance(value, bool) or not isinstance(value, int) or value < (0 if key in ("burn", "seed") else 1):
            raise FileFormatError(
                path,
                f"sampler.{key}",
                f"got {value!r}; allowed: a {'non-negative' if key in ('burn', 'seed') else 'positive'} integer",
            )
        if key == "seed" and value > INT64_MAX:
            raise FileFormatError(path, "sampler.seed", f"got {value}; allowed: a non-negative integer {INT64_ALLOWED}")
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
        raise FileFormatError(
            path, f"{where}.{sorted(unknown)[0]}", f"not a field of a {kind or 'catalogue'} prior; allowed: {allowed}"
        )
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
                path,
                where,
                f"{planet.name} does not catalogue an uncertainty for {name}; allowed: a prior (uniform, "
                "log_uniform or normal)",
            )
        prior = Normal(measured.value, measured.sigma, low_phys, high_phys)
        source = source or f"catalogue: {catalogued.source if catalogued is not None else name}"
    else:
        missing = [k for k in _REQUIRED[kind] if k not in raw]
        if missing:
            raise FileFormatError(
                path, f"{where}.{missing[0]}", f"missing; a {kind} prior needs {' and '.join(_REQUIRED[kind])}"
            )
        nums = {k: _num(path, f"{where}.{k}", raw[k]) * scale for k in _PRIOR_FIELDS[kind] if k in raw}
        if kind == "uniform":
            prior = Uniform(nums["low"], nums["high"])
        elif kind == "log_uniform":
            prior = LogUniform(nums["low"], nums["high"])
        else:
            prior = Normal(
                nums["mean"],
                nums["sd"],
                max(nums.get("low", -math.inf), low_phys),
                min(nums.get("high", math.inf), high_phys),
            )
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
                raise FileFormatError(path, f"{where}.{opt}", 'allowed: a table { value = ..., unit = "..." }')
            _, opt_scale = _unit(path, f"{where}.{opt}.unit", entry.get("unit", opt_unit), _si_unit(opt_unit))
            options[opt] = _num(path, f"{where}.{opt}.value", entry["value"], positive=True) * opt_scale
    source = _string(path, f"{where}.source", raw.get("source"))
    if "value" not in raw:
        if "uncertainty" in raw:
            raise FileFormatError(path, f"{where}.value", "missing: an uncertainty needs its value")
        key = model.catalogue_key
        measured = getattr(planet, key) if key else None
        if measured is None:
            raise FileFormatError(
                path, f"{where}.value", f"missing, and {planet.name} does not catalogue it; give value and uncertainty"
            )
        value, sigma = measured.value, measured.sigma
        entry = pf.get(key)
        source = source or (entry.source if entry is not None else key)
    else:
        value = _num(path, f"{where}.value", raw["value"]) * scale
        if "uncertainty" not in raw:
            raise FileFormatError(
                path,
                f"{where}.uncertainty",
                "missing; allowed: a positive one-sigma uncertainty (a measurement without one cannot be weighed)",
            )
        sigma = _num(path, f"{where}.uncertainty", raw["uncertainty"]) * scale
    if not sigma > 0:
        raise FileFormatError(
            path, f"{where}.uncertainty", f"got {sigma / scale:g}; allowed: a positive one-sigma uncertainty"
        )
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
            raise FileFormatError(
                path, f"compare.{name}", "not a sampled parameter or a reported quantity of this setup"
            )
        if not isinstance(entries, list):
            entries = [entries]
        for i, entry in enumerate(entries):
            where = f"compare.{name}[{i}]"
            if not isinstance(entry, dict):
                raise FileFormatError(path, where, "must be a table")
            unknown = set(entry) - _COMPARE_FIELDS
            if unknown:
                raise FileFormatError(
                    path, f"{where}.{sorted(unknown)[0]}", f"unknown key; allowed: {', '.join(sorted(_COMPARE_FIELDS))}"
                )
            _, scale = _unit(path, f"{where}.unit", entry.get("unit", units[name].to_string()), units[name])
            nums = {
                k: _num(path, f"{where}.{k}", entry[k]) * scale
                for k in ("value", "uncertainty", "low", "high")
                if k in entry
            }
            if ("value" in nums) == ("low" in nums or "high" in nums) or ("low" in nums) != ("high" in nums):
                raise FileFormatError(path, where, "give value (with optional uncertainty) or low and high")
            source = _string(path, f"{where}.source", entry.get("source"))
            if not source:
                raise FileFormatError(path, f"{where}.source", "missing: a published value names its source")
            out.append(
                Comparison(name, source, nums.get("value"), nums.get("uncertainty"), nums.get("low"), nums.get("high"))
            )
    return tuple(out)


def _prior_range(parameters, name: str, nominal) -> tuple[float, float] | None:
    """(low, high) a parameter can take: its prior's support (a normal prior to 1e-12 in
    each tail), or its nominal value when not sampled; None when neither."""
    for p in parameters:
        if p.name == name:
            lo, hi = (float(p.prior.ppf(q)) for q in (_PRIOR_TAIL, 1.0 - _PRIOR_TAIL))
            return max(lo, p.prior.low), min(hi, p.prior.high)
    return None if nominal is None else (float(nominal), float(nominal))


def _padded(lo: float, hi: float) -> tuple[float, float]:
    """A range with room for rounding (and some width where nothing varies)."""
    mid = 0.5 * (lo + hi)
    half = max(0.5 * (hi - lo), 1e-6 * abs(mid)) * (1.0 + 1e-9)
    return mid - half, mid + half


def _core_figure(where, raw_profile, planet: PlanetParameters, parameters):
    """The hydrostatic core of the setup's body (FixedCoreFigure or LinearMantleCoreFigure)."""
    prof, pf = _core_profile(where, raw_profile, planet)
    construction = pf.extra.get("construction")
    if construction is None:
        return _fixed_core(where, prof, planet)
    if construction != "core_under_linear_mantle":
        raise FileFormatError(pf.path, "construction", f"got {construction!r}; allowed: core_under_linear_mantle")
    return _core_under_linear_mantle(where, prof, planet, parameters)


def _core_profile(where, raw_profile, planet: PlanetParameters):
    """The density profile the setup names (default: the body's shipped one), which must have a liquid core."""
    name = _string(where, "profile", raw_profile) or profile_for_body(planet.name)
    if not name:
        raise FileFormatError(
            where,
            "profile",
            f"missing: {planet.name} has no shipped density profile; give one for the core's hydrostatic flattening",
        )
    try:
        prof, pf = load_profile(name)
    except InputError as exc:
        raise FileFormatError(where, "profile", f"got {name!r}; allowed: {exc.allowed}") from None
    if prof.fluid_core is None:
        raise FileFormatError(
            where,
            "profile",
            f"{prof.name} has no liquid core; allowed: a profile with a liquid core (the FCN needs one)",
        )
    return prof, pf


def _fixed_core(where, prof, planet: PlanetParameters) -> FixedCoreFigure:
    """A fixed profile's core ellipticity (Clairaut's equation once); the profile must be this body's: its mass
    within 1e-3 of GM/G (as wobble modes asks)."""
    if planet.gm is not None:
        mass = planet.gm.value / planet.gravitational_constant.value
        if abs(prof.mass() / mass - 1.0) > 1e-3:
            raise FileFormatError(
                where,
                "profile",
                f"{prof.name} has a mass of {prof.mass():.6g} kg; allowed: a profile of {planet.name} (GM/G = "
                f"{mass:.6g} kg)",
            )
    fig = _hydro.hydrostatic_figure(prof, planet.rotation_rate.value, planet.gravitational_constant.value)
    return FixedCoreFigure(prof.name, float(fig.core_dynamical_ellipticity))


#: The parameters a core under a linear mantle is built from (the last four give C/(MR^2) one way or the other).
_LINEAR_MANTLE_KEYS = (
    "fluid_core_radius",
    "fluid_core_density",
    "gm",
    "gravitational_constant",
    "equatorial_radius",
    "polar_moment_factor",
    "j2",
    "dynamical_flattening",
)


def _core_under_linear_mantle(where, prof, planet: PlanetParameters, parameters) -> LinearMantleCoreFigure:
    """A core rebuilt for every draw: its table over the box the priors (or the catalogued values) span, in
    x = core radius/R, y = core density/mean density and c = C/(MR^2)."""
    values = planet.values()
    ranges = {}
    for key in _LINEAR_MANTLE_KEYS:
        found = _prior_range(parameters, key, values.get(key))
        if found is not None:
            ranges[key] = found
    missing = [k for k in ("fluid_core_radius", "fluid_core_density", "gm", "equatorial_radius") if k not in ranges]
    if missing:
        raise FileFormatError(
            where,
            "profile",
            f"{prof.name} is built from the body's {', '.join(missing)}; allowed: a body that gives them",
        )
    r = prof.radius

    def pick(*keys):
        return {k: ranges[k] for k in keys}

    x = box_corners(pick("fluid_core_radius"), lambda fluid_core_radius: fluid_core_radius / r)
    y = box_corners(
        pick("fluid_core_density", "gm", "gravitational_constant"),
        lambda fluid_core_density, gm, gravitational_constant: (
            fluid_core_density / (gm / gravitational_constant / (4.0 / 3.0 * math.pi * r**3))
        ),
    )
    if "polar_moment_factor" in ranges:
        c = box_corners(
            pick("polar_moment_factor", "equatorial_radius"),
            lambda polar_moment_factor, equatorial_radius: polar_moment_factor * (equatorial_radius / r) ** 2,
        )
    else:
        c = box_corners(
            pick("j2", "dynamical_flattening", "equatorial_radius"),
            lambda j2, dynamical_flattening, equatorial_radius: (
                j2 / dynamical_flattening * (equatorial_radius / r) ** 2
            ),
        )
    try:
        return LinearMantleCoreFigure.build(prof.name, r, (_padded(*x), _padded(*y), _padded(*c)))
    except InputError as exc:
        raise FileFormatError(where, "parameters", f"{exc.value}; allowed: {exc.allowed}") from None


def _perturber_orbits(where, planet: PlanetParameters) -> tuple[tuple[_precession.PerturberOrbit, ...], float, list]:
    """The Sun on the body's orbit, its catalogued satellites and the planets apart from its orbit (as the precession
    budget takes them); the geodesic rate the observed precession includes; the notes of planets left out."""
    missing = [k for k in ("obliquity", "orbit_semi_major_axis", "orbit_eccentricity") if getattr(planet, k) is None]
    if missing:
        raise FileFormatError(
            where,
            "observables.precession_rate",
            f"{planet.name} does not catalogue {', '.join(missing)}; allowed: a body with its obliquity and orbit",
        )
    sun = load_perturber("sun")
    sun_orbit = _precession.PerturberOrbit(
        "sun",
        measured(sun, "gm", PERTURBER_UNITS["gm"]).value,
        planet.orbit_semi_major_axis.value,
        planet.orbit_eccentricity.value,
    )
    files, close = default_perturbers(planet.name, sun_orbit.semi_major_axis, sun_orbit.eccentricity)
    values: dict[str, float] = {}
    for pf in files:
        perturber_values(pf, values)
    orbits = [sun_orbit, *(perturber_orbit(pf, values, sun_orbit.semi_major_axis) for pf in files)]
    flag = planet.observed_precession_includes_geodesic
    includes = flag is None or flag.value != 0
    geodesic = (
        _precession.geodesic_precession_rate(sun_orbit.gm, sun_orbit.semi_major_axis, sun_orbit.eccentricity)
        if includes
        else 0.0
    )
    return tuple(orbits), geodesic, [f"precession: {too_close_note(close)}"] if close else []


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
    names = {m.name for m in (*measurements, *derived)}
    core_figure = _core_figure(where, data.get("profile"), planet, parameters) if names & _NEEDS_CORE else None
    perturbers, geodesic, notes = _perturber_orbits(where, planet) if names & _NEEDS_PERTURBERS else ((), 0.0, [])
    context = ForwardContext(core_figure, perturbers, geodesic)
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
        context=context,
        notes=tuple(notes),
    )
    try:
        posterior = setup.posterior()
        settings.check(posterior.ndim)
        posterior.check_centre()
    except InputError as exc:
        raise FileFormatError(where, exc.parameter, f"{exc.value}; allowed: {exc.allowed}") from None
    return setup
