"""The forward-model registry: what the inversion can predict from a planet's parameters.

An *observable* is one registered function of the parameter arrays. It receives a
:class:`Batch` (the nominal planet, the sampled parameters as float64 arrays in SI,
all of one shape) plus its options (SI floats), and returns the predicted value of
every member as an array of that shape, NaN where the parameters are unphysical::

    @register_observable(
        "chandler_period", unit="s", display_unit="d",
        description="period of the Chandler wobble",
        references="Smith & Dahlen 1981; IERS Conventions 2010 eq. 6.12",
        catalogue_key="observed_chandler_period",
    )
    def chandler_period(batch):
        return batch.chandler().period

That is the whole contract: adding an observable (the free core nutation period
once the normal-mode model exists, the precession rate once the precession model
exists) is one function and one decorator in this module, vectorised over members
(no Python loop over walkers). Everything else (priors, likelihood, sampler,
posterior predictive, netCDF, CLI) picks it up by name.

The same registry holds *derived* quantities (the wobble's Q): predictions that
a setup reports from the posterior without a measurement to compare with. Any
registered name can be either, depending on whether the setup gives a measured
value.

All values are SI; ``display_unit`` is the unit people read (days for periods)
and is converted at the API boundary.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from wobble.errors import InputError
from wobble.models import chandler as _chandler
from wobble.models.planet import PlanetParameters

__all__ = ["Batch", "ObservableModel", "REGISTRY", "register_observable", "observable_model"]


class Batch:
    """One vectorised evaluation: a planet with some parameters replaced by arrays.

    Parameters
    ----------
    planet : PlanetParameters or None
        The nominal planet (SI); None for problems that are not about a planet
        (the closed-form test cases).
    values : mapping
        Sampled parameter name -> float64 array (SI), all of one shape.
    model : str
        Chandler model (``full`` or the last step), as in :func:`wobble.models.chandler.chandler_budget`.

    Forward functions share expensive evaluations through :meth:`memo`, so that
    the Chandler period and the wobble's Q of one batch cost one model call.
    """

    def __init__(self, planet: PlanetParameters | None, values: Mapping[str, np.ndarray], model: str = "full"):
        self.planet = planet
        self.values = dict(values)
        self.model = model
        self.shape = np.broadcast_shapes(*(np.shape(v) for v in self.values.values())) if self.values else ()
        self._memo: dict[str, object] = {}

    def __getitem__(self, name: str) -> np.ndarray:
        """A parameter's values: sampled, else the planet's nominal value broadcast."""
        if name in self.values:
            return np.broadcast_to(self.values[name], self.shape)
        nominal = None if self.planet is None else self.planet.values().get(name)
        if nominal is None:
            raise InputError("parameter", name, "a parameter that is sampled or given by the planet")
        return np.full(self.shape, nominal)

    def memo(self, key: str, compute: Callable[[], object]):
        """``compute()`` once per batch under ``key``."""
        if key not in self._memo:
            self._memo[key] = compute()
        return self._memo[key]

    def chandler(self) -> _chandler.Samples:
        """The Chandler model on this batch (:func:`wobble.models.chandler.chandler_samples`)."""
        if self.planet is None:
            raise InputError("planet", None, "a planet for the Chandler model")
        return self.memo("chandler", lambda: _chandler.chandler_samples(self.planet, self.values, self.model))


@dataclass(frozen=True)
class ObservableModel:
    """A registered forward model.

    Attributes
    ----------
    name : str
        The observable's name in setups, files and JSON.
    predict : callable
        ``predict(batch, **options) -> ndarray`` (SI, NaN where unphysical).
    unit, display_unit : str
        SI unit of the predictions and the unit people read (astropy syntax; ``""``
        for a dimensionless number).
    description, references : str
        What it is and the literature of its forward model (shown to users).
    options : mapping
        Option name -> SI unit of the option's value (e.g. the tidal period).
    catalogue_key : str or None
        The planet-catalogue entry holding a measured value, used when a setup
        names the observable without giving a value.
    """

    name: str
    predict: Callable[..., np.ndarray]
    unit: str
    display_unit: str
    description: str
    references: str
    options: Mapping[str, str] = field(default_factory=dict)
    catalogue_key: str | None = None

    def __call__(self, batch: Batch, options: Mapping[str, float] | None = None) -> np.ndarray:
        out = np.asarray(self.predict(batch, **dict(options or {})), dtype=float)
        return np.broadcast_to(out, batch.shape).copy()


REGISTRY: dict[str, ObservableModel] = {}


def register_observable(
    name: str,
    *,
    unit: str,
    display_unit: str | None = None,
    description: str,
    references: str,
    options: Mapping[str, str] | None = None,
    catalogue_key: str | None = None,
):
    """Decorator: register ``predict(batch, **options)`` as the forward model of ``name``."""

    def decorate(predict):
        if name in REGISTRY:
            raise InputError("observable", name, "a name not registered yet")
        REGISTRY[name] = ObservableModel(
            name, predict, unit, unit if display_unit is None else display_unit, description, references,
            dict(options or {}), catalogue_key,
        )
        return predict

    return decorate


def observable_model(name: str) -> ObservableModel:
    """The registered forward model ``name`` (InputError naming the known ones)."""
    try:
        return REGISTRY[name]
    except KeyError:
        raise InputError("observable", name, f"one of {', '.join(sorted(REGISTRY))}") from None


# ---------------------------------------------------------------------------
# The registered observables.
# ---------------------------------------------------------------------------


@register_observable(
    "chandler_period",
    unit="s",
    display_unit="d",
    description="period of the Chandler wobble (free polar motion), days of 86400 s",
    references="Smith & Dahlen 1981; Sasao, Okubo & Saito 1980; Wahr & Bergen 1986; IERS Conventions 2010 eq. 6.12",
    catalogue_key="observed_chandler_period",
)
def chandler_period(batch: Batch) -> np.ndarray:
    """The Chandler budget's period (the last model step), s."""
    return batch.chandler().period


@register_observable(
    "tidal_k2",
    unit="",
    description="real part of the degree-2 tidal Love number k2 measured at a tidal period",
    references="IERS Conventions 2010 eq. 6.12 (Wahr & Bergen 1986; Mathews et al. 2002)",
    options={"tidal_period": "s"},
)
def tidal_k2(batch: Batch, tidal_period: float | None = None) -> np.ndarray:
    """Re k2 at the tidal period (default: the planet's ``love_number_k2_period``).

    The *parameter* ``love_number_k2`` is k2 at the reference period
    ``love_number_k2_period``; the *observable* is k2 at the period of the tide that
    was measured. The absorption-band model relates the two
    (:func:`wobble.models.chandler.love_number_samples`); they coincide only when the
    two periods are equal (Mars' catalogue refers k2 to the semidiurnal solar tide
    that dominates its measurement).
    """
    if tidal_period is None:
        tidal_period = batch["love_number_k2_period"]
    if not np.all(np.asarray(tidal_period) > 0):
        raise InputError("tidal_period", tidal_period, "a positive period")
    real, _ = _chandler.love_number_samples(batch.planet, batch.values, tidal_period)
    return real


@register_observable(
    "chandler_quality_factor",
    unit="",
    description="quality factor Q of the Chandler wobble implied by the out-of-phase k2 at its frequency",
    references="Smith & Dahlen 1981; IERS Conventions 2010 eq. 6.12",
)
def chandler_quality_factor(batch: Batch) -> np.ndarray:
    """Q = Re sigma/(2 |Im sigma|) of the complex wobble frequency (NaN without anelasticity)."""
    return batch.chandler().quality_factor


@register_observable(
    "love_number_k2_chandler",
    unit="",
    description="real part of k2 at the Chandler frequency (anelastic dispersion)",
    references="IERS Conventions 2010 eq. 6.12 and sec. 6.4",
)
def love_number_k2_chandler(batch: Batch) -> np.ndarray:
    """Re k2 at the modelled Chandler period (without the ocean term)."""
    period = batch.chandler().period
    with np.errstate(invalid="ignore"):
        real, _ = _chandler.love_number_samples(batch.planet, batch.values, np.where(np.isfinite(period), period, math.nan))
    return real
