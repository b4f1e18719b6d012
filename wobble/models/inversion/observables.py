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

That is the whole contract: adding an observable is one function and one
decorator in this module, vectorised over members (no Python loop over walkers).
Everything else (priors, likelihood, sampler, posterior predictive, netCDF, CLI)
picks it up by name. Fixed inputs that are not planet parameters (the perturbers'
orbits of the precession, the density profile that gives the core's hydrostatic
flattening) come in ``batch.context``
(:class:`~wobble.models.inversion.context.ForwardContext`, built by the setup reader).

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
from wobble.models import modes as _modes
from wobble.models.inversion.context import ForwardContext
from wobble.models.planet import PlanetParameters
from wobble.models.precession import ring_factor

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
    context : ForwardContext, optional
        Fixed inputs that are not planet parameters (perturbers, the hydrostatic core).

    Forward functions share expensive evaluations through :meth:`memo`, so that
    the Chandler period and the wobble's Q of one batch cost one model call.
    """

    def __init__(
        self,
        planet: PlanetParameters | None,
        values: Mapping[str, np.ndarray],
        model: str = "full",
        context: ForwardContext | None = None,
    ):
        self.planet = planet
        self.values = dict(values)
        self.model = model
        self.context = context if context is not None else ForwardContext()
        self._nominal = {} if planet is None else planet.values()
        self.shape = np.broadcast_shapes(*(np.shape(v) for v in self.values.values())) if self.values else ()
        self._memo: dict[str, object] = {}

    def __getitem__(self, name: str) -> np.ndarray:
        """A parameter's values: sampled, else the planet's nominal value broadcast."""
        if name in self.values:
            return np.broadcast_to(self.values[name], self.shape)
        nominal = self._nominal.get(name)
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

    def arrays(self):
        """The planet's parameters as arrays with the batch's values (shared by the mode solvers)."""
        return self.memo("arrays", lambda: _chandler.ParameterValues(self._nominal, self.values))

    def chandler_rate(self) -> np.ndarray:
        """Signed Chandler rate (rad/s) of the budget's last step for every member, NaN where it has none.

        For the full model, the uncoupled Chandler root of the mantle + core
        equations in closed form (:func:`wobble.models.modes.mode_rates_samples`,
        coupling off): the budget's equation (1) with k2 at the wobble's own
        frequency, the same numbers as :func:`wobble.models.chandler.chandler_samples`
        (to 1e-13, tested) at a third of the cost. Other models: the budget itself.
        """
        if self.planet is None:
            raise InputError("planet", None, "a planet for the Chandler model")
        if _chandler.resolve_model(self.planet, self.model)[0] != "full":
            return self.chandler().rate

        def compute():
            return _modes.mode_rates_samples(
                self.planet, self.values, coupled=False, which=("CW",), values=self.arrays()
            )["CW"][0]

        return self.memo("chandler_rate", compute)

    def value_or(self, name: str, default: float) -> np.ndarray:
        """A parameter's values, or ``default`` where neither sampled nor given by the planet."""
        if name in self.values or self._nominal.get(name) is not None:
            return self[name]
        return np.full(self.shape, float(default))

    def core_ellipticity(self) -> np.ndarray:
        """The liquid core's dynamical ellipticity e_f = e_hyd (1 + core_flattening_excess) of every member."""

        def compute():
            figure = self.context.core_figure
            if figure is None:
                raise InputError(
                    "core_figure",
                    "none",
                    "a density profile for the core's hydrostatic flattening (a setup read from a file provides it)",
                )
            return figure.hydrostatic(self) * (1.0 + self.value_or("core_flattening_excess", 0.0))

        return self.memo("core_ellipticity", compute)

    def normal_modes(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """The FCN (terrestrial-frame rate, rad/s, and its k2) of every member
        (:func:`wobble.models.modes.mode_rates_samples`)."""
        if self.planet is None:
            raise InputError("planet", None, "a planet for the normal modes")
        return self.memo(
            "normal_modes",
            lambda: _modes.mode_rates_samples(
                self.planet, self.values, self.core_ellipticity(), which=("FCN",), values=self.arrays()
            ),
        )


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
            name,
            predict,
            unit,
            unit if display_unit is None else display_unit,
            description,
            references,
            dict(options or {}),
            catalogue_key,
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
    """The Chandler budget's period (the last model step), s (:meth:`Batch.chandler_rate`)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.abs(2.0 * math.pi / batch.chandler_rate())


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
    if batch.planet.love_number_k2 is None and "love_number_k2" not in batch.values:
        raise InputError("love_number_k2", "not given", "a planet with a Love number k2")
    # As wobble.models.chandler.love_number_samples, on the batch's shared parameter arrays.
    vals = batch.arrays()
    if "anelastic" in _chandler.available_steps(batch.planet):
        real, _ = vals.anelastic_k(2.0 * math.pi / np.asarray(tidal_period, dtype=float))
    else:
        real = vals["love_number_k2"] + np.zeros(batch.shape)
    return np.where(vals.out_of_range, np.nan, real)


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
        real, _ = _chandler.love_number_samples(
            batch.planet, batch.values, np.where(np.isfinite(period), period, math.nan)
        )
    return real


@register_observable(
    "fcn_period",
    unit="s",
    display_unit="d",
    description="period of the free core nutation in space (celestial frame, as VLBI and lander tracking report it), "
    "days of 86400 s, negative: retrograde",
    references="Sasao, Okubo & Saito 1980; Mathews, Buffett, Herring & Shapiro 1991; Mathews, Herring & Buffett 2002",
    catalogue_key="observed_fcn_period",
)
def fcn_period(batch: Batch) -> np.ndarray:
    """Signed space-frame FCN period 2 pi/(sigma_FCN + Omega), s (negative: retrograde).

    sigma_FCN is the terrestrial-frame rate of the mantle + liquid core normal modes
    with k2 at its own frequency (:func:`wobble.models.modes.mode_rates_samples`),
    the core's e_f its hydrostatic value from the context's profile times
    (1 + core_flattening_excess).
    """
    rate, _ = batch.normal_modes()["FCN"]
    spin = batch["rotation_rate"]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.sign(spin) * 2.0 * math.pi / (rate + spin)


@register_observable(
    "core_ellipticity",
    unit="",
    description="dynamical ellipticity e_f = (C_f - A_f)/A_f of the liquid core (hydrostatic value times 1 + excess)",
    references="Clairaut's equation (Jeffreys 1976, The Earth, ch. 4); Mathews, Buffett, Herring & Shapiro 1991",
)
def core_ellipticity(batch: Batch) -> np.ndarray:
    """e_f of every member (the FCN's input)."""
    return batch.core_ellipticity()


@register_observable(
    "precession_rate",
    unit="rad / s",
    display_unit="mas / yr",
    description="rate of precession of the spin axis (node of the equator; negative: retrograde), mas per Julian year, "
    "with geodesic precession where the observed rate includes it",
    references="Goldstein, Poole & Safko 2002, sec. 5.8; Woolard 1953; Kinoshita 1977",
    catalogue_key="observed_precession_rate",
)
def precession_rate(batch: Batch) -> np.ndarray:
    """First-order tidal precession, -(3/2) sum_k k_k (H/omega) cos(eps), plus geodesic precession if observed.

    H = (C - (A + B)/2)/C of each member (the catalogue's H, or else J2/(C/(M a^2)),
    so that a sampled polar moment moves it), omega the spin, eps the obliquity, k_k each
    perturber's torque strength (:func:`wobble.models.precession.torque_strength`),
    times equation (6)'s factor for ring satellites (Phobos and Deimos) at each member's
    H and C/(M a^2); the same equations as the precession budget.
    """
    ctx = batch.context
    if not ctx.perturbers:
        raise InputError(
            "perturbers",
            "none",
            "the perturbers' orbits (a setup read from a file provides the Sun and the catalogued satellites)",
        )
    # H and C/(M a^2) as the Chandler model and the precession budget take them: the catalogue's, else from J2.
    figure = batch.arrays()
    h = figure.flattening
    tidal = -1.5 * ctx.torque_strength * h / batch["rotation_rate"] * np.cos(batch["obliquity"])
    if ctx.rings:
        if figure.c_factor is None:
            raise InputError(
                "polar_moment_factor", "missing", "C/(M a^2), or J2 beside H, for the ring satellites' precession"
            )
        sun = ctx.perturbers[0]
        tidal = tidal * ring_factor(
            ctx.rings,
            h,
            figure.c_factor,
            batch["gm"],
            batch["equatorial_radius"],
            batch["rotation_rate"],
            batch["obliquity"],
            sun,
        )
    return tidal + ctx.geodesic_rate
