"""Chandler wobble periods with units: the public API.

>>> import wobble
>>> from astropy import units as u
>>> budget = wobble.chandler_budget("earth")
>>> [step.name for step in budget.steps]
['rigid', 'elastic', 'fluid_core', 'ocean_pole_tide', 'anelastic']
>>> print(round(budget.steps[0].period.to_value(u.day), 1))     # Euler's rigid period
303.6
>>> wobble.euler_period(dynamical_flattening=3.273795e-3, spin=1 * u.sday).round(2)
<Quantity 303.62 d>

Days are days of 86400 s (``astropy.units.day``); a sidereal day is 0.27 %
shorter. The physics is documented in :mod:`wobble.models.chandler` and
``docs/chandler.md``.
"""

from __future__ import annotations

import contextlib
import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from astropy import units as u

from wobble.api.units import dimensionless, freeze_quantities, spin_rate_si, to_si
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import catalogue_names
from wobble.io.catalog import load_planet as _load_planet_si
from wobble.io.parameter_file import Parameter, ParameterFile
from wobble.models import chandler as _model
from wobble.models.planet import PlanetParameters

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "Planet",
    "BudgetStep",
    "ChandlerBudget",
    "FreeWobble",
    "known_planets",
    "load_planet",
    "chandler_budget",
    "chandler_dataset",
    "rigid_wobble",
    "free_precession_rate",
    "euler_period",
    "PARAMETER_RENAMES",
]

DAY_NOTE = "days of 86400 s (astropy u.day); a sidereal day is 86164.1 s, 0.27 % shorter"

#: Catalogue entries that are yes/no flags (1 or 0 in the file), not measured numbers.
FLAGS = frozenset({"observed_precession_includes_geodesic"})

# Units named as a geodesist writes them (astropy's hyr is the Julian century, 100 Julian years).
_UNIT_NAMES = {"hyr": "cy", "sday": "sidereal day"}

#: ``wobble chandler --sources --json``: keys of each ``parameters[]`` row kept under their old names for one
#: release (README, "Commands"). ``unit`` held the label for people (``arcsec / cy``, which astropy reads as
#: arcseconds per cycle, silently); it is now the unit astropy reads, as in ``wobble invert``.
PARAMETER_RENAMES = {"parameters[].unit_astropy": "parameters[].unit"}


def unit_label(unit: u.UnitBase) -> str:
    """A unit as a person reads it: ``""`` when dimensionless, ``arcsec / cy`` (per Julian
    century) for astropy's ``arcsec / hyr``, ``sidereal days``, ``kg m2`` (not ``m2 kg``).

    >>> unit_label(u.Unit("arcsec / hyr")), unit_label(u.Unit("kg m2")), unit_label(u.dimensionless_unscaled)
    ('arcsec / cy', 'kg m2', '')
    """
    unit = u.Unit(unit)
    if unit == u.dimensionless_unscaled:
        return ""
    if unit.scale != 1.0 or not unit.bases:
        return unit.to_string()

    def part(base, power) -> str:
        name = _UNIT_NAMES.get(base.to_string(), base.to_string())
        power = abs(power)
        return name if power == 1 else f"{name}{power:g}" if " " not in name else f"{name}^{power:g}"

    pairs = list(zip(unit.bases, unit.powers))
    if len(pairs) == 1 and pairs[0][1] == 1:
        name = part(*pairs[0])
        return name + "s" if " " in name else name
    # Numerator by increasing power (kg m2), then the denominator.
    top = [part(b, p) for b, p in sorted(((b, p) for b, p in pairs if p > 0), key=lambda bp: bp[1])]
    bottom = [part(b, p) for b, p in pairs if p < 0]
    text = " ".join(top) or "1"
    return text + (" / " + " ".join(bottom) if bottom else "")


class Planet:
    """A planet described for the Chandler model, with every parameter's source.

    Build with :func:`load_planet` (a catalogue name or a planet file).

    Attributes
    ----------
    name, title, description : str
    parameters : PlanetParameters
        The SI description the model runs on.
    file : ParameterFile
        The parsed file: values as Quantities with uncertainty, source, status.
    """

    def __init__(self, parameters: PlanetParameters, file: ParameterFile):
        self.parameters = parameters
        self.file = file

    @property
    def name(self) -> str:
        return self.file.name

    @property
    def title(self) -> str:
        return self.file.title

    @property
    def description(self) -> str:
        return self.file.description

    def parameter(self, key: str) -> Parameter | None:
        """The catalogued entry ``key`` (value and uncertainty as Quantities, source, status)."""
        return self.file.get(key)

    def source(self, key: str) -> str:
        """Where the number ``key`` comes from (``derived``/``assumed`` entries say so)."""
        # Alternative spellings of the same quantity in the file.
        for alias, stored in (("j2", "c20"), ("rotation_rate", "rotation_period")):
            if key == alias and self.file.get(key) is None and self.file.get(stored) is not None:
                key = stored
        p = self.file.get(key)
        if p is None:
            return "CODATA 2018 via astropy.constants" if key == "gravitational_constant" else "not given"
        return p.source if p.status == "read" else f"{p.source} [{p.status}]"

    def parameter_list(self) -> list[dict]:
        """Every catalogued parameter as the file gives it, for ``--sources``.

        One dict per parameter, in the file's order: ``name``, ``value``, ``uncertainty``
        (one sigma; None for a yes/no flag, whose value is then True or False), ``unit`` (as
        ``astropy.units.Unit`` reads it, ``arcsec / hyr``; ``""`` when dimensionless),
        ``unit_label`` (as a person reads it: ``arcsec / cy`` for arcseconds per Julian century,
        which astropy would read as per cycle), ``source``, ``status`` (``read``, ``secondary``,
        ``derived``, ``assumed``) and ``unit_astropy``, the old name of ``unit`` (kept for one
        release, :data:`PARAMETER_RENAMES`).
        """
        out = []
        for key, p in self.file.parameters.items():
            flag = key in FLAGS
            value = p.value.value
            value = value.tolist() if np.ndim(value) else float(value)
            sigma = p.uncertainty.to_value(p.value.unit)
            sigma = sigma.tolist() if np.ndim(sigma) else float(sigma)
            out.append(
                {
                    "name": key,
                    "value": bool(value) if flag else value,
                    "uncertainty": None if flag else sigma,
                    "unit": "" if flag else p.value.unit.to_string(),
                    "unit_label": "" if flag else unit_label(p.value.unit),
                    "source": p.source,
                    "status": p.status,
                }
            )
            out[-1]["unit_astropy"] = out[-1]["unit"]  # the old name (PARAMETER_RENAMES)
        return out

    @property
    def rotation_rate(self) -> u.Quantity:
        """Sidereal spin rate."""
        return self.parameters.rotation_rate.value << (u.rad / u.s)

    @property
    def observed_chandler_period(self) -> u.Quantity | None:
        """The observed Chandler period in days, or None (the catalogue's decimal value, not a round trip through s)."""
        entry = self.file.get("observed_chandler_period")
        return None if entry is None else entry.value.to(u.day)

    def __repr__(self) -> str:
        return f"Planet({self.name!r}, {len(self.file.parameters)} parameters)"


def known_planets() -> list[str]:
    """Names of the catalogued planets."""
    return catalogue_names()


def load_planet(body: str | os.PathLike | Planet) -> Planet:
    """A catalogued planet by name (``"earth"``, ``"mars"``) or a planet file by path."""
    if isinstance(body, Planet):
        return body
    params, pf = _load_planet_si(body)
    return Planet(params, pf)


@dataclass(frozen=True)
class BudgetStep:
    """One step of the Chandler budget, with units.

    Attributes
    ----------
    name : str
        ``rigid``, ``elastic``, ``fluid_core``, ``ocean_pole_tide`` or ``anelastic``.
    description : str
        The physics and its literature.
    period : Quantity
        Period after this step, days (inf: no wobble).
    change : Quantity or None
        Change from the previous step, days.
    rate : Quantity
        Signed wobble frequency, rad/s (positive: prograde).
    love_number : float
        Effective k2 (0 for the rigid step).
    sources : dict
        The parameters this step brings in, with their sources.
    """

    name: str
    description: str
    period: u.Quantity
    change: u.Quantity | None
    rate: u.Quantity
    love_number: float
    sources: dict[str, str]

    def __post_init__(self):
        freeze_quantities(self)


class ChandlerBudget:
    """The Chandler wobble of one planet, step by step, with units.

    Build with :func:`chandler_budget`. ``period`` is the model's answer;
    ``steps`` shows how the rigid period becomes it.
    """

    def __init__(self, planet: Planet, raw: _model.Budget):
        self.planet = planet
        self.raw = raw
        steps = []
        previous = None
        for s in raw.steps:
            period = (s.period << u.s).to(u.day)
            change = None if previous is None else period - previous
            previous = period
            sources = {key: planet.source(key) for key in s.uses}
            steps.append(
                BudgetStep(
                    s.name,
                    _model.STEP_DESCRIPTIONS[s.name],
                    period,
                    change,
                    s.rate << (u.rad / u.s),
                    s.love_number,
                    sources,
                )
            )
        self.steps: list[BudgetStep] = steps

    @property
    def body(self) -> str:
        return self.planet.name

    @property
    def model(self) -> str:
        return self.raw.model

    @property
    def period(self) -> u.Quantity:
        """The model's Chandler period, days."""
        return self.steps[-1].period

    @property
    def period_uncertainty(self) -> u.Quantity:
        """One-sigma uncertainty of the period from the catalogue's uncertainties, days.

        The standard deviation over 10^5 seeded Monte Carlo draws of every uncertain
        parameter (JCGM 101:2008): the model is not linear over the parameters' ranges, so
        this is what a sweep over the same parameters finds (``wobble sweep earth_chandler``).
        """
        return (self.raw.period_sigma << u.s).to(u.day)

    @property
    def period_uncertainty_linear(self) -> u.Quantity:
        """The first-order (linear) propagation of the same uncertainties, days."""
        return (self.raw.period_sigma_linear << u.s).to(u.day)

    @property
    def rate(self) -> u.Quantity:
        """Signed wobble frequency (positive: prograde, with the spin)."""
        return self.steps[-1].rate

    @property
    def sense(self) -> str:
        """``prograde``, ``retrograde`` (prolate body) or ``none`` (sphere)."""
        return self.raw.sense

    @property
    def observed(self) -> u.Quantity | None:
        return self.planet.observed_chandler_period

    @property
    def observed_uncertainty(self) -> u.Quantity | None:
        entry = self.planet.file.get("observed_chandler_period")
        return None if entry is None else entry.uncertainty.to(u.day)

    @property
    def residual(self) -> u.Quantity | None:
        """Model minus observed, days."""
        return None if self.observed is None else self.period - self.observed

    @property
    def relative_residual(self) -> float | None:
        """(model - observed)/observed."""
        return None if self.observed is None else float((self.residual / self.observed).decompose())

    @property
    def quality_factor(self) -> float | None:
        """Q of the wobble implied by the out-of-phase k2 (anelastic step): inf where k2 has no
        out-of-phase part, None without an anelastic step (JSON: null in both cases; the netCDF
        variable holds inf and NaN)."""
        return self.raw.quality_factor

    @property
    def secular_love_number(self) -> float | None:
        return self.raw.secular_love_number

    @property
    def uncertainty_contributions(self) -> dict[str, u.Quantity]:
        """Period change for +1 sigma of each parameter, days, largest first."""
        items = sorted(self.raw.contributions.items(), key=lambda kv: -abs(kv[1]))
        return {k: (v << u.s).to(u.day) for k, v in items}

    def to_dict(self) -> dict:
        """A JSON-ready summary (days of 86400 s; null where unknown or infinite)."""
        return {
            "body": self.body,
            "title": self.planet.title,
            "model": self.model,
            "period_days": _num(self.period),
            "period_uncertainty_days": _num(self.period_uncertainty),
            "period_uncertainty_linear_days": _num(self.period_uncertainty_linear),
            "monte_carlo_draws": _model.MC_DRAWS,
            "monte_carlo_valid_fraction": self.raw.valid_fraction,
            "observed_days": _num(self.observed),
            "observed_uncertainty_days": _num(self.observed_uncertainty),
            "residual_days": _num(self.residual),
            "residual_percent": None if self.relative_residual is None else 100 * self.relative_residual,
            "sense": self.sense,
            "rate_rad_per_s": _num(self.rate),
            "quality_factor": self.quality_factor,
            "secular_love_number": self.secular_love_number,
            "day": DAY_NOTE,
            "steps": [
                {
                    "name": s.name,
                    "period_days": _num(s.period),
                    "change_days": _num(s.change),
                    "love_number_k2": s.love_number,
                    "description": s.description,
                    "sources": s.sources,
                }
                for s in self.steps
            ],
            "uncertainty_contributions_days": {k: _num(v) for k, v in self.uncertainty_contributions.items()},
            "not_run": self.not_run,
        }

    @property
    def not_run(self) -> dict[str, list[str]]:
        """Steps of the full model this planet's file cannot run: step -> the parameters it lacks
        (empty for a model other than ``full``; the text prints them, and so does the JSON)."""
        if self.model != "full":
            return {}
        done = {s.name for s in self.steps}
        params = self.planet.parameters
        return {step: list(_model.missing_parameters(params, step)) for step in _model.STEPS if step not in done}

    def to_dataset(self) -> xr.Dataset:
        """This budget as an xarray Dataset (dimensions body, step); see :func:`chandler_dataset`."""
        return chandler_dataset([self])

    def summary(self, sources: bool = False) -> str:
        """The budget as ``wobble chandler`` prints it: each step's period, change, k2 and physics with its
        references, the model against the observed period, Q and the secular Love number; ``sources`` lists
        every catalogued number with its source."""
        from wobble.api.chandler_text import budget_text

        return budget_text(self, sources)

    def __repr__(self) -> str:
        return f"ChandlerBudget({self.body!r}, model={self.model!r}, period={self.period:.2f})"


def _num(q) -> float | None:
    if q is None:
        return None
    x = float(q.to_value(u.day) if q.unit.is_equivalent(u.day, equivalencies=None) else q.value)
    return x if math.isfinite(x) else None


def chandler_budget(body: str | os.PathLike | Planet, model: str = "full") -> ChandlerBudget:
    """The Chandler wobble budget of a planet, from its physical parameters only.

    Parameters
    ----------
    body : str, path-like or Planet
        A catalogue name (see :func:`known_planets`), a planet file, or a Planet.
    model : str
        ``full`` (default: every step the parameters support) or the last step
        to include: ``rigid``, ``elastic``, ``fluid_core``, ``ocean_pole_tide``,
        ``anelastic`` (aliases ``core``, ``ocean``).

    Returns
    -------
    ChandlerBudget
        Periods in days of 86400 s. The observed period is never an input.

    Examples
    --------
    >>> import wobble
    >>> budget = wobble.chandler_budget("earth")
    >>> [step.name for step in budget.steps]
    ['rigid', 'elastic', 'fluid_core', 'ocean_pole_tide', 'anelastic']
    >>> print(f"{budget.steps[0].period:.1f} -> {budget.period:.1f}; observed {budget.observed:.1f}")
    303.6 d -> 432.1 d; observed 433.1 d
    """
    planet = load_planet(body)
    if not isinstance(model, str):
        raise InputError("model", model, "a model name such as 'full' or 'rigid'")
    with in_planet_file(planet):
        raw = _model.chandler_budget(planet.parameters, model.strip().lower())
    return ChandlerBudget(planet, raw)


@contextlib.contextmanager
def in_planet_file(planet: Planet):
    """An InputError about one of the planet file's parameters, named with the file and key, as a
    wrong unit there is (``my_planet.toml, parameters.love_number_k2.value: got -0.3; ...``)."""
    try:
        yield
    except InputError as exc:
        if planet.file.get(exc.parameter) is None:
            raise
        where = f"parameters.{exc.parameter}.value"
        raise FileFormatError(
            planet.file.path or planet.name, where, f"got {exc.value}; allowed: {exc.allowed}"
        ) from None


def chandler_dataset(budgets: list[ChandlerBudget]) -> xr.Dataset:
    """Several budgets as one CF-ready Dataset with dimensions ``body`` and ``step``.

    Steps a body does not have (Mars has no ocean) are NaN with ``applied = 0``.
    Periods are in days of 86400 s.
    """
    from wobble.api.dataset import xarray
    from wobble.io.cf import flag_attrs, variable

    xr = xarray()
    if isinstance(budgets, ChandlerBudget):  # one budget: a list of it (it raised TypeError: not iterable)
        budgets = [budgets]
    if not budgets:
        raise InputError("budgets", "[]", "at least one ChandlerBudget")
    for b in budgets:
        if not isinstance(b, ChandlerBudget):  # ["earth"] raised AttributeError
            raise InputError("budgets", repr(b), "ChandlerBudgets, from wobble.chandler_budget(body)")
    steps = [s for s in _model.STEPS if any(s in [x.name for x in b.steps] for b in budgets)]
    shape = (len(budgets), len(steps))
    period = np.full(shape, np.nan)
    rate = np.full(shape, np.nan)
    k2 = np.full(shape, np.nan)
    applied = np.zeros(shape, dtype=np.int8)
    for i, b in enumerate(budgets):
        for s in b.steps:
            j = steps.index(s.name)
            period[i, j] = s.period.to_value(u.day)
            rate[i, j] = s.rate.to_value(u.rad / u.s)
            k2[i, j] = s.love_number
            applied[i, j] = 1

    def per_body(fn):
        return np.array([np.nan if (v := fn(b)) is None else v for b in budgets], dtype=float)

    def var(name, data, **extra):
        return variable("chandler", name, data, **extra)

    refs = sorted({src for b in budgets for s in b.steps for src in s.sources.values()})
    step_refs = "; ".join(f"{s}: {_model.STEP_DESCRIPTIONS[s]}" for s in steps)
    ds = xr.Dataset(
        {
            "period": var("period", period, references=step_refs, comment=DAY_NOTE),
            "wobble_rate": var("wobble_rate", rate),
            "love_number_k2_effective": var("love_number_k2_effective", k2),
            "applied": var("applied", applied, **flag_attrs({0: "not_applied", 1: "applied"})),
            "model_period": var("model_period", per_body(lambda b: b.period.to_value(u.day))),
            "model_period_uncertainty": var(
                "model_period_uncertainty", per_body(lambda b: b.period_uncertainty.to_value(u.day))
            ),
            "model_period_uncertainty_linear": var(
                "model_period_uncertainty_linear", per_body(lambda b: b.period_uncertainty_linear.to_value(u.day))
            ),
            "observed_period": var("observed_period", per_body(lambda b: _num(b.observed))),
            "observed_period_uncertainty": var(
                "observed_period_uncertainty", per_body(lambda b: _num(b.observed_uncertainty))
            ),
            "residual": var("residual", per_body(lambda b: _num(b.residual))),
            "quality_factor": var(
                "quality_factor",
                per_body(lambda b: b.quality_factor),
                comment="inf: k2 has no out-of-phase part (no dissipation); NaN: the model has no anelastic step",
            ),
            "secular_love_number": var("secular_love_number", per_body(lambda b: b.secular_love_number)),
            "spin_rate": var("spin_rate", per_body(lambda b: b.planet.rotation_rate.to_value(u.rad / u.s))),
        },
        coords={
            "body": ("body", [b.body for b in budgets], {"long_name": "body identifier"}),
            "step": ("step", steps, {"long_name": "model step (each includes the steps before it)"}),
            "model": ("body", [b.model for b in budgets], {"long_name": "model requested for the body"}),
        },
        attrs={
            "title": "Chandler wobble period budget",
            "references": "; ".join(refs),
            "comment": "Periods from physical parameters only (the observed period is never an input). " + DAY_NOTE,
        },
    )
    return ds


# ---------------------------------------------------------------------------
# The rigid free precession of any body (Goldstein, Poole & Safko 2002, sec. 5.6)
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class FreeWobble:
    """Rigid free precession (Euler's free wobble) of a body.

    Attributes
    ----------
    rate : Quantity
        Signed frequency Omega in rad/s: positive is prograde (same sense as
        the spin, oblate body), negative retrograde (prolate body).
    period : Quantity
        abs(2 pi / Omega) in days; infinite for a sphere.
    sense : str
        ``prograde``, ``retrograde`` or ``none``.
    message : str
        One sentence saying which case this is.
    """

    rate: u.Quantity
    period: u.Quantity
    sense: str
    message: str

    def __post_init__(self):
        freeze_quantities(self)


_MOMENT = u.kg * u.m**2


def _ratios_from_moments(moments) -> tuple[float, float]:
    arr = to_si(moments, "moments", _MOMENT, positive=True)
    arr = np.atleast_1d(arr)
    if arr.shape == (2,):
        i1, i3 = arr
        i2 = i1
    elif arr.shape == (3,):
        i1, i2, i3 = arr
    else:
        raise InputError("moments", moments, "(I1, I3) for a symmetric body or (I1, I2, I3), spin about axis 3")
    for a, b, c in ((i1, i2, i3), (i2, i3, i1), (i3, i1, i2)):
        if a + b < c * (1 - 1e-12):
            raise InputError(
                "moments", moments, "moments satisfying the triangle inequalities I1 + I2 >= I3 (and cyclic)"
            )
    # (I3 - I1)/I3: the subtraction is exact when I1 and I3 are within a factor 2 (Sterbenz).
    return (i3 - i1) / i3, (i3 - i2) / i3


def rigid_wobble(
    moments: u.Quantity | None = None,
    *,
    spin: u.Quantity,
    dynamical_flattening: float | None = None,
    inertia_ratio: float | None = None,
) -> FreeWobble:
    """Euler's free wobble of a rigid body (Goldstein, Poole & Safko 2002, sec. 5.6).

    Give exactly one of ``moments``, ``dynamical_flattening`` (H = (C-A)/C) or
    ``inertia_ratio`` ((C-A)/A), and the spin about the axis of C as a rate or
    a rotation period.

    Parameters
    ----------
    moments : Quantity, optional
        (I1, I3) of a symmetric body, or (I1, I2, I3) with the spin about axis 3.
        For a symmetric body Omega = (I3 - I1)/I1 omega3 (Goldstein, Poole & Safko 2002 sec. 5.6); for a
        triaxial one Omega = omega3 sqrt((I3-I1)(I3-I2)/(I1 I2)).
    spin : Quantity
        omega3 (e.g. ``7.292115e-5 * u.rad / u.s``) or the rotation period
        (e.g. ``1 * u.sday``; a sidereal day, not a solar one, for a planet).
    dynamical_flattening : float, optional
        H = (C - A)/C in (-inf, 1/2]: C <= 2A (the triangle inequality); negative for a prolate body.
    inertia_ratio : float, optional
        (C - A)/A in (-1, 1].

    Returns
    -------
    FreeWobble
        Signed rate, period (inf for a sphere) and the sense of the wobble.

    Examples
    --------
    >>> import wobble
    >>> from astropy import units as u
    >>> wobble_ = wobble.rigid_wobble(dynamical_flattening=3.273795e-3, spin=1 * u.sday)
    >>> print(f"{wobble_.period:.2f}", wobble_.sense)
    303.62 d prograde
    """
    given = [x is not None for x in (moments, dynamical_flattening, inertia_ratio)]
    if sum(given) != 1:
        raise InputError(
            "moments/dynamical_flattening/inertia_ratio",
            f"{sum(given)} given",
            "exactly one of moments, dynamical_flattening (H) or inertia_ratio ((C-A)/A)",
        )
    omega = spin_rate_si(spin)
    if moments is not None:
        ca, cb = _ratios_from_moments(moments)
    elif dynamical_flattening is not None:
        # H = 1 - A/C reaches every value below 1/2: a thin rod spun about its own axis has A/C -> inf.
        h = dimensionless(dynamical_flattening, "dynamical_flattening")
        if not h <= 0.5:
            raise InputError(
                "dynamical_flattening",
                dynamical_flattening,
                "a number in (-inf, 0.5]: H = (C - A)/C, at most 1/2 as C <= 2A (the triangle inequality)",
            )
        ca = cb = h
    else:
        e = dimensionless(inertia_ratio, "inertia_ratio")
        if not -1 < e <= 1:
            raise InputError(
                "inertia_ratio",
                inertia_ratio,
                "a number in (-1, 1]: (C - A)/A, at most 1 as C <= 2A (a flat disc), above -1 as C > 0",
            )
        ca = cb = e / (1.0 + e)  # (C-A)/C from (C-A)/A
    rate = _model.free_wobble_rate(omega, ca, cb)
    if rate == 0 and omega == 0:
        sense, message = "none", "no spin: a body at rest has no free wobble, the period is infinite"
    elif rate == 0:
        sense, message = "none", "spherical body (I1 = I3): no free wobble, the period is infinite"
    elif (rate > 0) == (omega > 0):
        sense, message = "prograde", "oblate body (C largest): the wobble is prograde, with the spin"
    else:
        sense, message = "retrograde", "prolate body (C smallest): the wobble is retrograde, against the spin"
    period = math.inf if rate == 0 else abs(2 * math.pi / rate)
    return FreeWobble(rate << (u.rad / u.s), (period << u.s).to(u.day), sense, message)


def free_precession_rate(moments=None, *, spin, dynamical_flattening=None, inertia_ratio=None) -> u.Quantity:
    """Signed rigid free-precession rate Omega in rad/s (see :func:`rigid_wobble`)."""
    return rigid_wobble(moments, spin=spin, dynamical_flattening=dynamical_flattening, inertia_ratio=inertia_ratio).rate


def euler_period(moments=None, *, spin, dynamical_flattening=None, inertia_ratio=None) -> u.Quantity:
    """Rigid (Euler) wobble period in days of 86400 s; inf for a sphere (see :func:`rigid_wobble`).

    Examples
    --------
    Earth's Euler period from the IERS dynamical flattening H = (C - A)/C:

    >>> import wobble
    >>> from astropy import units as u
    >>> print(f"{wobble.euler_period(dynamical_flattening=3.273795e-3, spin=1 * u.sday):.2f}")
    303.62 d
    """
    return rigid_wobble(
        moments, spin=spin, dynamical_flattening=dynamical_flattening, inertia_ratio=inertia_ratio
    ).period
