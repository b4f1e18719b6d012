"""Every free wobble of a layered planet, and its hydrostatic figure, with units: the public API.

>>> import wobble
>>> from astropy import units as u
>>> figure = wobble.hydrostatic_figure("prem", spin=1 * u.sday)
>>> print(f"1/{1 / figure.surface_flattening:.2f}")    # Clairaut, first order, a = 6371 km
1/299.96
>>> modes = wobble.normal_modes("earth")
>>> fcn = modes.mode("FCN", "celestial")
>>> print(f"{fcn.period.to(u.day):.0f} {fcn.sense}")    # from the hydrostatic core
-459 d retrograde
>>> print(f"{100 * modes.core_flattening_excess:.1f} %")  # what the observed FCN asks of the core
5.1 %

Days are days of 86400 s (``astropy.units.day``); ``u.sday`` is the sidereal day.
The physics is in :mod:`wobble.models.hydrostatic`, :mod:`wobble.models.modes`
and ``docs/modes.md``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING
from types import MappingProxyType

import numpy as np
from astropy import constants as const
from astropy import units as u

from wobble.api.chandler import Planet, in_planet_file, load_planet
from wobble.api.units import as_given, freeze_quantities, spin_rate_si, to_si
from wobble.errors import InputError
from wobble.io.json_keys import deprecate
from wobble.io.density_profile import load_profile, profile_for_body, profile_names
from wobble.io.parameter_file import ParameterFile
from wobble.io.text import with_uncertainty
from wobble.models import chandler as _chandler
from wobble.models import hydrostatic as _hydro
from wobble.models import modes as _modes

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["HydrostaticFigure", "FreeMode", "NormalModes", "hydrostatic_figure", "normal_modes", "modes_dataset"]

DAY_NOTE = "days of 86400 s (astropy u.day); negative periods are retrograde"
MODE_REFERENCES = {
    "CW": "Euler 1765; Sasao, Okubo & Saito 1980; Smith & Dahlen 1981",
    "FCN": "Sasao, Okubo & Saito 1980; Mathews, Buffett, Herring & Shapiro 1991; Mathews, Herring & Buffett 2002",
}
_OBSERVED_KEY = {"CW": "observed_chandler_period", "FCN": "observed_fcn_period"}


def _days(seconds) -> u.Quantity | None:
    return None if seconds is None else (seconds << u.s).to(u.day)


#: Keys of the hydrostatic figure's JSON kept under their old names for one release (README, "Commands"):
#: ``q`` (Omega^2 a^3/(GM)) is the Chandler Q in ``wobble forecast``.
DEPRECATED_FIGURE_KEYS = {"q": "centrifugal_ratio"}
#: Published values a density profile may ship (``observed_flattening``, ``reference_hydrostatic_flattening``).
FIGURE_ANCHOR_KEYS = ("observed_flattening", "reference_hydrostatic_flattening")
#: Keys of ``wobble modes --json`` (each body's object) kept under their old names for one release: the
#: uncertainty of the excess in the order of period_uncertainty_days, <quantity>_uncertainty_<unit>.
DEPRECATED_KEYS = {"core_flattening_excess_percent_uncertainty": "core_flattening_excess_uncertainty_percent"}


class HydrostaticFigure:
    """The first-order hydrostatic figure of a layered body, with units.

    Build with :func:`hydrostatic_figure`.

    Attributes
    ----------
    profile : str
        Name of the density profile.
    raw : wobble.models.hydrostatic.HydrostaticFigure
        The SI result.
    anchors : mapping
        Published values shipped with the profile (``observed_flattening``,
        ``reference_hydrostatic_flattening``) as ``(value, uncertainty, source)``, read-only.
    """

    def __init__(self, profile: str, raw: _hydro.HydrostaticFigure, anchors: dict | None = None, density_profile=None):
        self.profile = profile
        self.raw = raw
        self.anchors = MappingProxyType(dict(anchors or {}))
        self._profile = density_profile

    @property
    def radius(self) -> u.Quantity:
        """Sample radii."""
        return (self.raw.radius << u.m).to(u.km)

    @property
    def flattening(self) -> np.ndarray:
        """eps(r) of the level surface through each radius (dimensionless)."""
        return self.raw.flattening

    @property
    def surface_flattening(self) -> float:
        return self.raw.surface_flattening

    @property
    def radau_darwin_flattening(self) -> float:
        """eps(a) from C/(M a^2) by the Radau-Darwin approximation."""
        return self.raw.radau_darwin_flattening

    @property
    def j2(self) -> float:
        """(C - A)/(M a^2), a the profile's outer radius."""
        return self.raw.j2

    @property
    def dynamical_flattening(self) -> float:
        """H = (C - A)/C."""
        return self.raw.dynamical_flattening

    @property
    def moment_factor(self) -> float:
        """C/(M a^2)."""
        return self.raw.moment_factor

    @property
    def q(self) -> float:
        """Omega^2 a^3/(G M)."""
        return self.raw.q

    @property
    def mass(self) -> u.Quantity:
        return self.raw.mass << u.kg

    @property
    def core_dynamical_ellipticity(self) -> float | None:
        """e_f = (C_f - A_f)/A_f of the liquid core, or None."""
        return self.raw.core_dynamical_ellipticity

    def to_dict(self) -> dict:
        """A JSON-ready summary (no unit suffix: every number is dimensionless except the mass)."""
        out = {
            "profile": self.profile,
            "surface_flattening": self.surface_flattening,
            "inverse_surface_flattening": 1.0 / self.surface_flattening,
            "radau_darwin_flattening": self.radau_darwin_flattening,
            "j2": self.j2,
            "j2_clairaut_theorem": self.raw.j2_clairaut,
            "dynamical_flattening": self.dynamical_flattening,
            "moment_factor": self.moment_factor,
            "centrifugal_ratio": self.q,  # Omega^2 a^3/(GM); "q" is the Chandler Q in forecast
            "mass_kg": self.raw.mass,
            "core_dynamical_ellipticity": self.core_dynamical_ellipticity,
        }
        # Every profile's figure has both keys (README, "Commands": null where they do not apply); a profile with no
        # published anchors (mars_layered) had neither.
        for key in FIGURE_ANCHOR_KEYS:
            out[key] = None
            if key in self.anchors:
                value, sigma, source = self.anchors[key]
                out[key] = {"value": value, "uncertainty": sigma, "source": source}
        return deprecate(out, DEPRECATED_FIGURE_KEYS)

    def to_dataset(self) -> xr.Dataset:
        """eps(r), Radau's eta and the density on the sample radii, CF-ready (dimension ``radius``, km).

        The scalar results (surface flattening, J2, H, C/(Ma^2), q, e_f) are global attributes.
        """
        from wobble.api.dataset import xarray
        from wobble.io.cf import variable

        xr = xarray()
        radius = self.raw.radius
        density = self._density(radius)
        # The file keeps its attribute names (hydrostatic_q): a JSON key's new name is not added to it.
        scalars = {
            k: v
            for k, v in self.to_dict().items()
            if isinstance(v, (int, float)) and not isinstance(v, bool) and k not in DEPRECATED_FIGURE_KEYS.values()
        }
        ds = xr.Dataset(
            {
                "level_surface_flattening": variable("modes", "level_surface_flattening", self.raw.flattening),
                "radau_parameter": variable("modes", "radau_parameter", self.raw.eta),
                "density": variable("modes", "density", density),
            },
            coords={"radius": variable("modes", "radius", radius / 1e3)},
            attrs={
                "title": f"Hydrostatic figure of the density profile {self.profile} (Clairaut's equation, first order)",
                "references": "Jeffreys 1976, The Earth, ch. 4 (Clairaut's and Radau's equations)",
                **{f"hydrostatic_{k}": float(v) for k, v in scalars.items()},
            },
        )
        return ds

    def _density(self, radius):
        return (
            np.asarray(self._profile.density(radius), dtype=float)
            if self._profile is not None
            else np.full(radius.shape, np.nan)
        )

    def summary(self) -> str:
        """One paragraph for a person."""
        lines = [
            f"hydrostatic figure ({self.profile}; Clairaut's equation to first order): "
            f"surface flattening 1/{1 / self.surface_flattening:.2f} (Radau-Darwin "
            f"1/{1 / self.radau_darwin_flattening:.2f}), "
            f"J2 = {self.j2:.7g}, H = {self.dynamical_flattening:.7g}, C/(Ma^2) = {self.moment_factor:.5f} "
            # The profile's outer radius, which may differ from the catalogue's reference radius (Mars:
            # 3389.5 km against R0 = 3396 km), so that J2 and C/(Ma^2) are not read against the wrong a.
            f"(a = {float(self.radius[-1].to_value(u.km)):.1f} km, the profile's outer radius)"
        ]
        for key, label in (
            ("observed_flattening", "observed"),
            ("reference_hydrostatic_flattening", "published hydrostatic"),
        ):
            if key in self.anchors:
                value, _, source = self.anchors[key]
                lines.append(f"  {label} flattening 1/{1 / value:.2f} ({source})")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"HydrostaticFigure({self.profile!r}, flattening=1/{1 / self.surface_flattening:.2f})"


def _profile(profile) -> tuple[_hydro.DensityProfile, ParameterFile | None]:
    if isinstance(profile, _hydro.DensityProfile):
        return profile, None
    if not isinstance(profile, (str, os.PathLike)):
        raise InputError(
            "profile", profile, "a profile name (prem, mars_layered), the path of a profile file, or a DensityProfile"
        )
    return load_profile(profile)


def _anchors(pf: ParameterFile | None) -> dict:
    out = {}
    if pf is None:
        return out
    for key in FIGURE_ANCHOR_KEYS:
        p = pf.get(key)
        if p is not None:
            out[key] = (float(p.value.value), float(p.uncertainty.value), p.source)
    return out


def hydrostatic_figure(
    profile, spin: u.Quantity, *, gravitational_constant: u.Quantity | None = None
) -> HydrostaticFigure:
    """The hydrostatic figure of a layered body from its density profile (Clairaut's equation).

    Parameters
    ----------
    profile : str, path-like or DensityProfile
        A shipped profile (``"prem"``, ``"mars_layered"``) or a profile file
        (``data/README.md`` describes the schema).
    spin : Quantity
        Spin rate (``7.292115e-5 * u.rad / u.s``) or rotation period (``1 * u.sday``).
    gravitational_constant : Quantity, optional
        G (default: CODATA 2018 from astropy).

    Returns
    -------
    HydrostaticFigure

    Examples
    --------
    >>> import wobble
    >>> from astropy import units as u
    >>> mars = wobble.hydrostatic_figure("mars_layered", spin=24.6229 * u.h)
    >>> print(f"e_f = {mars.core_dynamical_ellipticity:.5f}, 1/f = {1 / mars.surface_flattening:.1f}")
    e_f = 0.00435, 1/f = 199.3
    """
    omega = spin_rate_si(spin)
    g = (
        const.G.si.value
        if gravitational_constant is None
        else to_si(gravitational_constant, "gravitational_constant", u.m**3 / (u.kg * u.s**2), positive=True, shape=())
    )
    prof, pf = _profile(profile)
    with as_given(spin=spin):
        figure = _hydro.hydrostatic_figure(prof, omega, g)
    return HydrostaticFigure(prof.name, figure, _anchors(pf), prof)


@dataclass(frozen=True)
class FreeMode:
    """One free mode of a planet in one frame, with units.

    Attributes
    ----------
    name : str
        ``CW`` (Chandler wobble) or ``FCN`` (free core nutation).
    frame : str
        ``terrestrial`` (seen from the planet) or ``celestial`` (seen from space).
    period, period_uncertainty : Quantity
        Period signed relative to the spin (negative: retrograde) and its one-sigma uncertainty, days.
    rate : Quantity
        Frequency about the planet's axis, rad/s (the spin's sign when prograde).
    sense : str
        ``prograde`` or ``retrograde``.
    love_number : float
        k2 at the mode's frequency in the planet's frame.
    observed, observed_uncertainty : Quantity or None
        The observed signed period, days.
    observed_source : str or None
        Where the observation comes from.
    """

    name: str
    frame: str
    period: u.Quantity
    period_uncertainty: u.Quantity
    rate: u.Quantity
    sense: str
    love_number: float
    observed: u.Quantity | None
    observed_uncertainty: u.Quantity | None
    observed_source: str | None

    def __post_init__(self):
        freeze_quantities(self)

    @property
    def label(self) -> str:
        return f"{self.name}_{self.frame}"


class NormalModes:
    """A planet's free modes and the core flattening both ways, with units.

    Build with :func:`normal_modes`.
    """

    def __init__(
        self,
        planet: Planet,
        raw: _modes.NormalModes,
        figure: HydrostaticFigure | None,
        budget_period: u.Quantity,
        not_run: dict[str, str] | None = None,
    ):
        self.planet = planet
        #: Modes asked for but not computed, with the reason (``{"FCN": "no density profile ..."}``).
        self.not_run: dict[str, str] = dict(not_run or {})
        self.raw = raw
        self.figure = figure
        self.chandler_budget_period = budget_period
        #: Every mode computed (the physics of the whole planet); ``modes`` are those asked for.
        self.computed: list[FreeMode] = []
        for m in raw.computed or raw.modes:
            key = _OBSERVED_KEY[m.name]
            self.computed.append(
                FreeMode(
                    m.name,
                    m.frame,
                    _days(m.period),
                    _days(m.period_sigma),
                    m.rate << (u.rad / u.s),
                    m.sense,
                    m.love_number,
                    _days(m.observed_period),
                    _days(m.observed_sigma),
                    None if m.observed_period is None else planet.source(key),
                )
            )
        shown = {(m.name, m.frame) for m in raw.modes}
        #: The modes asked for (``normal_modes(..., modes=...)``, ``wobble modes --mode``): what
        #: the summary, ``to_dict`` and the Dataset show.
        self.modes: list[FreeMode] = [m for m in self.computed if (m.name, m.frame) in shown]

    @property
    def body(self) -> str:
        return self.planet.name

    @property
    def shown(self) -> tuple[str, ...]:
        """Names of the modes shown (``CW``, ``FCN``), in order."""
        return tuple(dict.fromkeys(m.name for m in self.modes))

    def mode(self, name: str, frame: str = "terrestrial") -> FreeMode:
        """The mode ``name`` (``CW``, ``FCN``) in ``frame`` (``terrestrial``, ``celestial``): any mode
        computed, shown or not."""
        return _modes.find_mode(self.computed, name, frame)

    @property
    def core_flattening_hydrostatic(self) -> float | None:
        """e_f of the hydrostatic core (the forward prediction's input)."""
        return self.raw.core_ellipticity_hydrostatic

    @property
    def core_flattening_required(self) -> float | None:
        """e_f that the observed FCN period requires (an output, never an input)."""
        return self.raw.core_ellipticity_required

    @property
    def core_flattening_required_uncertainty(self) -> float | None:
        return self.raw.core_ellipticity_required_sigma

    @property
    def core_flattening_excess(self) -> float | None:
        """Required over hydrostatic e_f, minus one (0.05: 5 % flatter than hydrostatic)."""
        return self.raw.core_flattening_excess

    @property
    def core_flattening_hydrostatic_uncertainty(self) -> float | None:
        """One-sigma uncertainty of the hydrostatic e_f (0 for a fixed profile such as PREM)."""
        return self.raw.core_ellipticity_hydrostatic_sigma

    @property
    def core_flattening_excess_uncertainty(self) -> float | None:
        """One-sigma uncertainty of the excess (required and hydrostatic e_f propagated together)."""
        return self.raw.core_flattening_excess_sigma

    @property
    def fcn_period_required(self) -> u.Quantity | None:
        """FCN period in space with the required e_f put back (equals the observed period)."""
        return _days(self.raw.fcn_period_required)

    @property
    def chandler_coupling_off(self) -> u.Quantity:
        """Chandler period with the core-mantle coupling off (same Liouville equations), days."""
        return _days(abs(2 * math.pi / self.raw.cw_rate_uncoupled))

    @property
    def chandler_first_order(self) -> u.Quantity:
        """Chandler period with the coupling off and the deformation's own angular momentum dropped (the
        classic first-order formula), days."""
        return _days(abs(2 * math.pi / self.raw.cw_rate_first_order))

    @property
    def fcn_effect_on_chandler(self) -> u.Quantity:
        """Chandler period with the coupling minus without it, days."""
        return self.mode("CW").period - self.chandler_coupling_off

    def to_dict(self) -> dict:
        """JSON-ready: what ``wobble modes --json`` prints for this body."""

        def num(q):
            return None if q is None else float(q.to_value(u.day))

        def pct(x):
            return None if x is None else 100.0 * x

        out = {
            "body": self.body,
            "title": self.planet.title,
            "day": DAY_NOTE,
            "modes": [
                {
                    "mode": m.name,
                    "frame": m.frame,
                    "period_days": num(m.period),
                    "period_uncertainty_days": num(m.period_uncertainty),
                    "sense": m.sense,
                    "rate_rad_per_s": float(m.rate.value),
                    "love_number_k2": m.love_number,
                    "observed_days": num(m.observed),
                    "observed_uncertainty_days": num(m.observed_uncertainty),
                    "observed_source": m.observed_source,
                    "references": MODE_REFERENCES[m.name],
                }
                for m in self.modes
            ],
            "core_flattening_hydrostatic": self.core_flattening_hydrostatic,
            "core_flattening_hydrostatic_uncertainty": self.core_flattening_hydrostatic_uncertainty,
            "core_flattening_required": self.core_flattening_required,
            "core_flattening_required_uncertainty": self.core_flattening_required_uncertainty,
            "core_flattening_excess_percent": pct(self.core_flattening_excess),
            "core_flattening_excess_uncertainty_percent": pct(self.core_flattening_excess_uncertainty),
            "fcn_period_required_days": num(self.fcn_period_required),
            "chandler_budget_days": num(self.chandler_budget_period),
            "chandler_coupling_off_days": num(self.chandler_coupling_off),
            "chandler_first_order_days": num(self.chandler_first_order),
            "fcn_effect_on_chandler_days": num(self.fcn_effect_on_chandler),
            "hydrostatic_figure": None if self.figure is None else self.figure.to_dict(),
            "not_run": self.not_run,
        }
        # The root lists every rename in the object, the figure's too (which its own deprecated_keys lists), as
        # polar-motion's does; the figure's only where there is a figure.
        nested = (
            {}
            if self.figure is None
            else {f"hydrostatic_figure.{k}": f"hydrostatic_figure.{v}" for k, v in DEPRECATED_FIGURE_KEYS.items()}
        )
        return deprecate(out, {**DEPRECATED_KEYS, **nested})

    def summary(self) -> str:
        """The table a person reads (``wobble modes``)."""

        def fmt(q, sigma=None):
            if q is None:
                return "-"
            return with_uncertainty(q.to_value(u.day), None if sigma is None else sigma.to_value(u.day))

        lines = [f"{self.planet.title}: free rotational modes (days of 86400 s; negative: retrograde)"]
        lines.append(f"  {'mode':<5}{'frame':<13}{'period [d]':>22}  {'sense':<11}{'observed [d]':>22}")
        for m in self.modes:
            lines.append(
                f"  {m.name:<5}{m.frame:<13}{fmt(m.period, m.period_uncertainty):>22}  {m.sense:<11}"
                f"{fmt(m.observed, m.observed_uncertainty):>22}"
            )
        for name, why in self.not_run.items():
            lines.append(f"  {name:<5}not run: {why}")
        lines.append(
            "  (+/- of the model: first-order propagation of the catalogued uncertainties; wobble chandler's is "
            "Monte Carlo, a little wider where the period is not linear in them)"
        )
        for name in ("CW", "FCN"):
            source = next((m.observed_source for m in self.modes if m.name == name and m.observed_source), None)
            if source:
                lines.append(f"  observed {name}: {source}")
        if self.core_flattening_hydrostatic is not None and "FCN" in self.shown:
            source = self.figure.profile if self.figure is not None else "given"
            fcn = self.mode("FCN", "celestial")
            hyd = self.core_flattening_hydrostatic
            hyd_text = (
                f"{hyd:.7f}"
                if not self.core_flattening_hydrostatic_uncertainty
                else with_uncertainty(hyd, self.core_flattening_hydrostatic_uncertainty)
            )
            # In the planet's own sidereal days (2 pi / Omega): Earth's for Earth, Mars's for Mars (a Mars
            # FCN was printed in Earth's sidereal days).
            sidereal_days = fcn.period.to_value(u.s) * abs(self.raw.spin_rate) / (2 * math.pi)
            whose = "" if self.body == "earth" else f" of {self.planet.title}"
            lines.append(
                f"  core flattening e_f: hydrostatic {hyd_text} ({source}, Clairaut) "
                f"gives the FCN above ({fcn.period.to_value(u.day):.1f} d = {sidereal_days:.1f} "
                f"sidereal days{whose} in space)"
            )
            if self.core_flattening_required is not None:
                excess = with_uncertainty(
                    100 * self.core_flattening_excess, 100 * self.core_flattening_excess_uncertainty, sign=True
                )
                lines.append(
                    "  the observed FCN requires e_f = "
                    f"{with_uncertainty(self.core_flattening_required, self.core_flattening_required_uncertainty)}"
                    f": {excess} % "
                    f"against hydrostatic (put back, it gives {self.fcn_period_required.to_value(u.day):.4f} d)"
                )
        if "CW" in self.shown:
            cw = self.mode("CW")
            days = cw.period.to_value(u.day)
            # Two places for planets' hundreds of days; four significant digits for a fast body's fraction of one.
            d = max(2, 3 - math.floor(math.log10(abs(days)))) if math.isfinite(days) and days != 0 else 2
            lines.append(
                f"  Chandler wobble {days:.{d}f} d; coupling off "
                f"{self.chandler_coupling_off.to_value(u.day):.{d}f} d "
                f"= the Chandler budget {self.chandler_budget_period.to_value(u.day):.{d}f} d (FCN effect "
                f"{self.fcn_effect_on_chandler.to_value(u.day):+.{d}f} d; the classic first-order formula would give "
                f"{self.chandler_first_order.to_value(u.day):.{d}f} d)"
            )
        if self.figure is not None:
            lines.append("  " + self.figure.summary().replace("\n", "\n  "))
        return "\n".join(lines)

    def periods_against_core_flattening(self, core_flattening) -> dict[str, u.Quantity]:
        """Mode periods for other core flattenings e_f, everything else as catalogued.

        Parameters
        ----------
        core_flattening : array_like
            Values of e_f (dimensionless).

        Returns
        -------
        dict
            ``CW``, ``FCN_terrestrial``, ``FCN_celestial``: signed periods, days.
        """
        values = np.atleast_1d(np.asarray(core_flattening, dtype=float))
        if not np.all(np.isfinite(values) & (values > 0)):
            raise InputError("core_flattening", core_flattening, "positive, finite values")
        if self.core_flattening_hydrostatic is None:
            raise InputError(
                "core_flattening", self.body, "a body whose free core nutation is modelled (a liquid core)"
            )
        spin = self.raw.spin_rate
        turn = 2 * math.pi * math.copysign(1.0, spin)  # periods signed relative to the spin
        out = {"CW": [], "FCN_terrestrial": [], "FCN_celestial": []}
        for e in values:
            rates = _modes.mode_rates(self.planet.parameters, float(e))
            out["CW"].append(turn / rates["CW"][0])
            out["FCN_terrestrial"].append(turn / rates["FCN"][0])
            out["FCN_celestial"].append(turn / (rates["FCN"][0] + spin))
        return {k: (np.array(v) << u.s).to(u.day) for k, v in out.items()}

    def to_dataset(self) -> xr.Dataset:
        """This body as an xarray Dataset (see :func:`modes_dataset`)."""
        return modes_dataset([self])

    def __repr__(self) -> str:
        return "NormalModes({!r}, {})".format(self.body, ", ".join(f"{m.label}={m.period:.2f}" for m in self.modes))


def _check_mass(planet: Planet, prof: _hydro.DensityProfile, pf: ParameterFile | None) -> None:
    params = planet.parameters
    if params.gm is None:
        return
    mass = params.gm.value / params.gravitational_constant.value
    tol_param = None if pf is None else pf.get("mass_tolerance")
    tolerance = 1e-3 if tol_param is None else float(tol_param.value.value)
    if abs(prof.mass() / mass - 1.0) > tolerance:
        raise InputError(
            "density profile mass",
            f"{prof.mass():.6g} kg ({prof.name})",
            f"within {tolerance:g} of the body's GM/G = {mass:.6g} kg ({planet.name})",
        )


#: Profiles whose layers are re-derived from the body's catalogue when used with it
#: (top-level ``construction`` of the profile file).
CONSTRUCTIONS = ("core_under_linear_mantle",)


def _rebuilder(prof: _hydro.DensityProfile, pf: ParameterFile | None):
    """A function planet -> DensityProfile for a profile built from its body's catalogue, else None.

    ``construction = "core_under_linear_mantle"`` (``mars_layered``): the uniform
    liquid core of the body's ``fluid_core_radius`` and ``fluid_core_density`` under
    a linear mantle fitted to its GM/G and polar moment, at the profile's radius.
    """
    construction = None if pf is None else pf.extra.get("construction")
    if construction is None:
        return None
    if construction not in CONSTRUCTIONS:
        raise InputError("construction", construction, f"one of {', '.join(CONSTRUCTIONS)}")

    def rebuild(p):
        missing = [
            k for k in ("gm", "equatorial_radius", "fluid_core_radius", "fluid_core_density") if getattr(p, k) is None
        ]
        if p.c_factor is None:
            missing.append("polar_moment_factor")
        if missing:
            raise InputError(
                missing[0], "not given", f"the profile {prof.name} is built from the body's {', '.join(missing)}"
            )
        mass = p.gm.value / p.gravitational_constant.value
        moment = p.c_factor * mass * p.equatorial_radius.value**2
        return _hydro.core_under_linear_mantle(
            prof.name, mass, moment, prof.radius, p.fluid_core_radius.value, p.fluid_core_density.value
        )

    return rebuild


def _hydrostatic_core_ellipticity(rebuild, nominal: float, nominal_planet):
    """e_f as a function of the planet, memoised on the profile it rebuilds (a +-1 sigma
    step of the spin, G, M, C or the core re-solves Clairaut's equation, to 1e-9)."""
    cache = {}

    def signature(p):
        prof = rebuild(p)
        return prof, (prof.edges, prof.coeffs, abs(p.rotation_rate.value), p.gravitational_constant.value)

    cache[signature(nominal_planet)[1]] = nominal

    def e_of(p):
        prof, sig = signature(p)
        if sig not in cache:
            fig = _hydro.hydrostatic_figure(
                prof, p.rotation_rate.value, p.gravitational_constant.value, samples=2, rtol=1e-9
            )
            cache[sig] = fig.core_dynamical_ellipticity
        return cache[sig]

    return e_of


def normal_modes(
    body: str | os.PathLike | Planet, *, profile=None, modes: tuple[str, ...] | None = None
) -> NormalModes:
    """The free modes of a planet: Chandler wobble and free core nutation, from one body file.

    Parameters
    ----------
    body : str, path-like or Planet
        A catalogue name (``"earth"``, ``"mars"``) or a planet file.
    profile : str, path-like or DensityProfile, optional
        The density profile that gives the hydrostatic core flattening
        (default: the shipped profile of a catalogued body, ``prem`` for Earth).
    modes : str or tuple of str, optional
        The modes to show (``summary``, ``to_dict``, the Dataset): ``("CW",)``, ``("FCN",)``
        or ``("CW", "FCN")``; default every mode the parameters support. Only what is shown
        changes: every supported mode is computed, so the Chandler wobble is always coupled
        to the liquid core when the FCN can be computed (``mode()`` finds any of them).
        A mode whose parameters are missing is an InputError naming them.

    Returns
    -------
    NormalModes
        Periods in days of 86400 s (negative: retrograde). The observed
        periods are never inputs; the e_f the observed FCN requires is an output.

    Examples
    --------
    >>> import wobble
    >>> from astropy import units as u
    >>> mars = wobble.normal_modes("mars")
    >>> [f"{m.name} {m.frame}" for m in mars.modes]
    ['CW terrestrial', 'FCN terrestrial', 'FCN celestial']
    >>> print(f"{mars.mode('FCN', 'celestial').period:.0f}, observed {mars.mode('FCN', 'celestial').observed:.0f}")
    -242 d, observed -243 d
    """
    if isinstance(modes, str):  # one mode by name: "CW" is ("CW",), not the letters C and W
        modes = (modes,)
    planet = load_planet(body)
    figure = None
    e_f = None
    if profile is None and planet.parameters.fluid_core_moment is not None:
        profile = profile_for_body(planet.name)
    not_run = {}
    if modes is None or "FCN" in {str(m).strip().upper() for m in modes}:
        # Say why a mode the user expects is missing, rather than leave a silent gap (or a null in the JSON).
        if planet.parameters.fluid_core_moment is None:
            not_run["FCN"] = (
                "the body gives no liquid core (fluid_core_equatorial_moment, or fluid_core_radius and "
                "fluid_core_density)"
            )
        elif profile is None:
            not_run["FCN"] = (
                f"no density profile is tied to {planet.name!r} for the core's hydrostatic flattening: give one "
                f"(profile=, --profile on the command line; shipped: {', '.join(profile_names())})"
            )
    if profile is not None:
        prof, pf = _profile(profile)
        rebuild = _rebuilder(prof, pf)
        if rebuild is not None:
            try:
                prof = rebuild(planet.parameters)
            except InputError as exc:
                # The layers are re-derived from the body: say which profile and body made them.
                raise InputError(
                    exc.parameter,
                    exc.value,
                    f"{exc.allowed} (in the profile {pf.name!r} rebuilt from {planet.file.path or planet.name}: its "
                    "core, mass and polar moment under the profile's own radius)",
                ) from None
        else:
            _check_mass(planet, prof, pf)
        figure = HydrostaticFigure(
            prof.name,
            _hydro.hydrostatic_figure(
                prof, planet.parameters.rotation_rate.value, planet.parameters.gravitational_constant.value
            ),
            _anchors(pf),
            prof,
        )
        e_f = figure.core_dynamical_ellipticity
        if rebuild is not None and e_f is not None:
            e_f = _hydrostatic_core_ellipticity(rebuild, e_f, planet.parameters)
    if modes is not None:
        modes = tuple(str(m).strip().upper() for m in modes)
    with in_planet_file(planet):
        raw = _modes.normal_modes(planet.parameters, e_f, modes)
        # Only the budget's period is wanted here, not its Monte Carlo uncertainty.
        budget = _chandler.chandler_budget(planet.parameters, uncertainty=False)
    computed = {m.name for m in (raw.computed or raw.modes)}
    not_run = {k: v for k, v in not_run.items() if k not in computed}
    return NormalModes(planet, raw, figure, (budget.period << u.s).to(u.day), not_run)


def modes_dataset(results: list[NormalModes]) -> xr.Dataset:
    """Several bodies' modes as one CF-ready Dataset with dimensions ``body`` and ``mode``.

    Modes a body does not have are NaN. Periods are in days of 86400 s.
    """
    from wobble.api.dataset import xarray
    from wobble.io.cf import flag_attrs, variable

    xr = xarray()
    if not results:
        raise InputError("results", "[]", "at least one NormalModes")
    labels = [
        lab
        for lab in ("CW_terrestrial", "FCN_terrestrial", "FCN_celestial")
        if any(lab in [m.label for m in r.modes] for r in results)
    ]
    fields, sense = _per_mode(results, labels)

    def var(name, data, **extra):
        return variable("modes", name, data, **extra)

    refs = "; ".join(f"{k}: {v}" for k, v in MODE_REFERENCES.items())
    data = {name: var(name, values, comment=DAY_NOTE if "period" in name else None) for name, values in fields.items()}
    data["sense"] = var("sense", sense, **flag_attrs({-1: "retrograde", 0: "absent", 1: "prograde"}))
    data.update({name: var(name, values) for name, values in _per_body(results).items()})
    sources = sorted({m.observed_source for r in results for m in r.modes if m.observed_source})
    return xr.Dataset(
        data,
        coords={
            "body": ("body", [r.body for r in results], {"long_name": "body identifier"}),
            "mode": ("mode", labels, {"long_name": "free mode and the frame it is seen in"}),
        },
        attrs={
            "title": "Rotational normal modes: Chandler wobble and free core nutation",
            "references": refs + ("; observed: " + "; ".join(sources) if sources else ""),
            "comment": "Periods from physical parameters only; the observed periods are never inputs, and the core "
            "flattening the observed FCN requires is an output. " + DAY_NOTE,
        },
    )


def _per_mode(results: list[NormalModes], labels: list[str]) -> tuple[dict, np.ndarray]:
    """(body, mode) arrays of the modelled and observed periods, rates and Love numbers (NaN where a body
    lacks the mode), and the sense of each mode (+1 prograde, -1 retrograde, 0 absent)."""
    shape = (len(results), len(labels))
    fields = {
        k: np.full(shape, np.nan)
        for k in (
            "period",
            "period_uncertainty",
            "rate",
            "observed_period",
            "observed_period_uncertainty",
            "love_number_k2",
        )
    }
    sense = np.zeros(shape, dtype=np.int8)
    for i, r in enumerate(results):
        for m in r.modes:
            j = labels.index(m.label)
            fields["period"][i, j] = m.period.to_value(u.day)
            fields["period_uncertainty"][i, j] = m.period_uncertainty.to_value(u.day)
            fields["rate"][i, j] = m.rate.to_value(u.rad / u.s)
            fields["love_number_k2"][i, j] = m.love_number
            sense[i, j] = 1 if m.sense == "prograde" else -1
            if m.observed is not None:
                fields["observed_period"][i, j] = m.observed.to_value(u.day)
                fields["observed_period_uncertainty"][i, j] = m.observed_uncertainty.to_value(u.day)
    return fields, sense


def _per_body(results: list[NormalModes]) -> dict[str, np.ndarray]:
    """Each body's core flattening (hydrostatic, required by the observed FCN, the excess in per cent), the
    FCN period required, the Chandler periods of the budget and without core coupling, its hydrostatic
    figure and spin rate (NaN where a body has no value)."""

    def per_body(fn):
        return np.array([np.nan if (v := fn(r)) is None else float(v) for r in results])

    def day(q):
        return None if q is None else q.to_value(u.day)

    def percent(x):
        return None if x is None else 100 * x

    return {
        "core_flattening_hydrostatic": per_body(lambda r: r.core_flattening_hydrostatic),
        "core_flattening_hydrostatic_uncertainty": per_body(lambda r: r.core_flattening_hydrostatic_uncertainty),
        "core_flattening_required": per_body(lambda r: r.core_flattening_required),
        "core_flattening_required_uncertainty": per_body(lambda r: r.core_flattening_required_uncertainty),
        "core_flattening_excess": per_body(lambda r: percent(r.core_flattening_excess)),
        "core_flattening_excess_uncertainty": per_body(lambda r: percent(r.core_flattening_excess_uncertainty)),
        "fcn_period_required": per_body(lambda r: day(r.fcn_period_required)),
        "chandler_budget_period": per_body(lambda r: day(r.chandler_budget_period)),
        "chandler_period_coupling_off": per_body(lambda r: day(r.chandler_coupling_off)),
        "surface_flattening_hydrostatic": per_body(lambda r: None if r.figure is None else r.figure.surface_flattening),
        "dynamical_flattening_hydrostatic": per_body(
            lambda r: None if r.figure is None else r.figure.dynamical_flattening
        ),
        "spin_rate": per_body(lambda r: r.raw.spin_rate),
    }
