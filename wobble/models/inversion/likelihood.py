"""The posterior of an inversion: priors times a Gaussian likelihood, vectorised over walkers.

For parameters theta with independent priors p_i and measurements y_j with one-sigma
uncertainties s_j of observables whose forward models predict f_j(theta),

    ln p(theta | y) = sum_i ln p_i(theta_i)
                      - 1/2 sum_j ((f_j(theta) - y_j)/s_j)^2 - sum_j ln(s_j sqrt(2 pi)) + const,

the independent Gaussian likelihood (Gelman et al. 2013, *Bayesian Data Analysis*,
3rd ed., ch. 14; Hogg, Bovy & Lang 2010, arXiv:1008.4686). Members for which a forward
model has no answer (an unphysical parameter set, flagged NaN by the model) get
ln p = -inf: the posterior is zero there, which is what truncating the prior to the
physical region means.

Model error is not in this likelihood: s_j is the measurement's uncertainty only
(docs/inversion.md discusses what that leaves out).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from wobble.errors import InputError
from wobble.models import chandler as _chandler
from wobble.models.inversion.context import ForwardContext
from wobble.models.inversion.observables import Batch, ObservableModel, observable_model
from wobble.models.inversion.priors import Prior, physical_range
from wobble.models.planet import PlanetParameters

__all__ = ["Parameter", "Measurement", "Posterior"]


@dataclass(frozen=True)
class Parameter:
    """A sampled parameter: its name (a planet parameter), prior (SI) and display unit.

    Attributes
    ----------
    name : str
    prior : Prior
    unit : str
        The unit people read it in (astropy syntax; ``""`` for a number).
    scale : float
        SI value of one ``unit`` (values are divided by it for display).
    source : str
        Where the prior comes from.
    """

    name: str
    prior: Prior
    unit: str = ""
    scale: float = 1.0
    source: str = ""

    def __post_init__(self):
        problems = self.prior.problems()
        if problems:
            raise InputError(f"prior of {self.name}", self.prior.describe(self.scale, self.unit), problems[0])
        low, high = physical_range(self.name)
        if self.prior.low < low or self.prior.high > high:
            raise InputError(
                f"prior of {self.name}",
                self.prior.describe(self.scale, self.unit),
                f"a prior inside the physical range [{low / self.scale:.6g}, {high / self.scale:.6g}] of {self.name}",
            )


@dataclass(frozen=True)
class Measurement:
    """A measured value of a registered observable (SI) or a derived quantity (no value).

    Attributes
    ----------
    name : str
        A registered observable.
    value, sigma : float or None
        Measured value and one-sigma uncertainty, SI; None for a derived quantity.
    options : mapping
        The observable's options, SI (e.g. ``tidal_period``).
    unit : str
        Display unit; ``scale`` its SI value.
    source : str
        Where the measurement comes from.
    forward : ObservableModel or None
        A forward model not in the registry (closed-form test problems); by default
        the registered model of ``name``.
    """

    name: str
    value: float | None = None
    sigma: float | None = None
    options: Mapping[str, float] = field(default_factory=dict)
    unit: str = ""
    scale: float = 1.0
    source: str = ""
    forward: ObservableModel | None = None

    def __post_init__(self):
        model = self.model
        unknown = sorted(set(self.options) - set(model.options))
        if unknown:
            raise InputError(f"options of {self.name}", unknown[0], f"one of {', '.join(model.options) or 'none'}")
        if self.value is None:
            if self.sigma is not None:
                raise InputError(
                    f"observable {self.name}", "an uncertainty without a value", "a measured value with its uncertainty"
                )
            return
        if not math.isfinite(self.value):
            raise InputError(f"observable {self.name}", self.value, "a finite measured value")
        if self.sigma is None or not (math.isfinite(self.sigma) and self.sigma > 0):
            raise InputError(
                f"uncertainty of observable {self.name}",
                "missing" if self.sigma is None else self.sigma / self.scale,
                "a positive, finite one-sigma uncertainty (a measurement without one cannot be weighed)",
            )

    @property
    def measured(self) -> bool:
        return self.value is not None

    @property
    def model(self) -> ObservableModel:
        return self.forward if self.forward is not None else observable_model(self.name)


class Posterior:
    """ln p(theta | y) of one setup, evaluated for many parameter vectors at once.

    Parameters
    ----------
    parameters : sequence of Parameter
        The sampled parameters, in order (theta's columns).
    measurements : sequence of Measurement
        Measured observables (in the likelihood) and derived quantities (value None).
    planet : PlanetParameters or None
        The nominal planet; parameters not sampled keep its values.
    model : str
        Chandler model (``full`` or the last step).
    prior_only : bool
        Drop the likelihood (a prior-only run: what the data add is the difference).
    context : ForwardContext, optional
        Fixed inputs of the forward models that are not planet parameters (the
        perturbers of the precession, the hydrostatic core of the FCN).

    Calling the object with an array of shape (n, ndim) returns ln p for each row:
    the form ``emcee.EnsembleSampler(..., vectorize=True)`` wants.
    """

    def __init__(
        self,
        parameters: Sequence[Parameter],
        measurements: Sequence[Measurement],
        planet: PlanetParameters | None = None,
        model: str = "full",
        prior_only: bool = False,
        context: ForwardContext | None = None,
    ):
        self.parameters = tuple(parameters)
        self.measurements = tuple(measurements)
        self.planet = planet
        self.model = model
        self.prior_only = prior_only
        self.context = context if context is not None else ForwardContext()
        names = [p.name for p in self.parameters]
        if not names:
            raise InputError("parameters", "none", "at least one parameter to invert")
        for collection, what in ((names, "parameter"), ([m.name for m in self.measurements], "observable")):
            duplicates = sorted({n for n in collection if collection.count(n) > 1})
            if duplicates:
                raise InputError(what, duplicates[0], f"each {what} once")
        if planet is not None:
            known = {k for k in planet.values() if not k.startswith("observed_")}
            unknown = [n for n in names if n not in known]
            if unknown:
                raise InputError("parameter", unknown[0], f"one of {', '.join(sorted(known))}")
            _chandler.resolve_model(planet, model)
        self._measured = tuple(m for m in self.measurements if m.measured)
        self._value = np.array([m.value for m in self._measured], dtype=float)
        self._sigma = np.array([m.sigma for m in self._measured], dtype=float)
        self._norm = float(np.sum(np.log(self._sigma * math.sqrt(2.0 * math.pi))))

    # -- shape ------------------------------------------------------------------

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def ndim(self) -> int:
        return len(self.parameters)

    @property
    def measured(self) -> tuple[Measurement, ...]:
        """The measurements in the likelihood (derived quantities excluded)."""
        return self._measured

    def with_measured_values(self, values: Mapping[str, float]) -> Posterior:
        """The same setup with other measured values (synthetic data for injection tests)."""
        new = [replace(m, value=float(values[m.name])) if m.name in values else m for m in self.measurements]
        return Posterior(self.parameters, new, self.planet, self.model, self.prior_only, self.context)

    def without_likelihood(self) -> Posterior:
        """The prior-only version of this posterior."""
        return Posterior(
            self.parameters, self.measurements, self.planet, self.model, prior_only=True, context=self.context
        )

    # -- evaluation -------------------------------------------------------------

    def _theta(self, theta) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        if theta.shape[-1] != self.ndim:
            raise InputError("theta", theta.shape, f"an array whose last axis has {self.ndim} parameters")
        return theta

    def log_prior(self, theta) -> np.ndarray:
        """Sum of the priors' log densities, shape theta.shape[:-1]."""
        theta = self._theta(theta)
        return sum(p.prior.logpdf(theta[..., i]) for i, p in enumerate(self.parameters))

    def predict(self, theta, names: Sequence[str] | None = None) -> dict[str, np.ndarray]:
        """Forward predictions (SI) of every measurement (or of ``names``) for each row."""
        theta = self._theta(theta)
        batch = Batch(
            self.planet, {p.name: theta[..., i] for i, p in enumerate(self.parameters)}, self.model, self.context
        )
        wanted = self.measurements if names is None else [m for m in self.measurements if m.name in names]
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            return {m.name: m.model(batch, m.options) for m in wanted}

    def log_likelihood(self, theta) -> np.ndarray:
        """Gaussian log-likelihood of the measured values; -inf where a model has no answer."""
        theta = self._theta(theta)
        if not self._measured or self.prior_only:
            return np.zeros(theta.shape[:-1])
        pred = self.predict(theta, [m.name for m in self._measured])
        stack = np.stack([pred[m.name] for m in self._measured], axis=-1)
        z = (stack - self._value) / self._sigma
        chi2 = np.sum(z * z, axis=-1)
        return np.where(np.isfinite(chi2), -0.5 * chi2 - self._norm, -np.inf)

    def __call__(self, theta) -> np.ndarray:
        """ln p(theta | y) up to the evidence, for each row of theta (vectorised)."""
        theta = self._theta(theta)
        lp = self.log_prior(theta)
        out = np.full(theta.shape[:-1], -np.inf)
        ok = np.isfinite(lp)
        if np.any(ok):
            out[ok] = lp[ok] + self.log_likelihood(theta[ok])
        return out

    def prior_centre(self) -> np.ndarray:
        """The priors' medians (one row)."""
        return np.array([p.prior.median for p in self.parameters])

    def check_centre(self) -> None:
        """Raise InputError when a forward model has no answer at the priors' centre."""
        centre = self.prior_centre()[None, :]
        pred = self.predict(centre)
        failed = [name for name, v in pred.items() if not np.isfinite(v[0])]
        if failed:
            reason = ""
            if self.planet is not None:
                code = int(
                    _chandler.chandler_samples(
                        self.planet, {p.name: centre[:, i] for i, p in enumerate(self.parameters)}, self.model
                    ).code[0]
                )
                reason = _chandler.INVALID_REASONS.get(code, "")
            values = ", ".join(
                f"{p.name} = {c / p.scale:.6g}{' ' + p.unit if p.unit else ''}"
                for p, c in zip(self.parameters, centre[0])
            )
            raise InputError(
                f"observable {failed[0]}",
                f"no prediction at the priors' centre ({values})" + (f": {reason}" if reason else ""),
                "a setup whose forward model works at the centre of its priors",
            )
