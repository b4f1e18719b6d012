"""Forced precession and the principal nutation with units: the public API.

>>> import wobble
>>> budget = wobble.precession_rate("earth")
>>> [t.name for t in budget.terms][:3]
['sun', 'sun_eccentricity', 'moon']
>>> print(f"{-budget.lunisolar:.2f}")      # the Sun and Moon; IAU: 5494.062986" cos(eps_0) = 5040.70"/cy
5040.69 arcsec / century

Rates follow the sign of the node longitude of the equator (eastward; negative is
retrograde, as the Mars literature writes it). IAU's psi_A and p_A count the other
way, so Earth's lunisolar -5040.69"/cy here is IAU's +5040.69"/cy. The physics is in
:mod:`wobble.models.precession` and ``docs/precession.md``.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from astropy import units as u

from wobble.api.chandler import Planet, load_planet
from wobble.errors import FileFormatError, InputError
from wobble.io.json_keys import deprecate
from wobble.io.parameter_file import ParameterFile
from wobble.io.perturbers import (
    MIN_SEPARATION,
    NUTATION_REFERENCE_UNITS,
    REFERENCE_UNITS,
    default_perturbers,
    is_planet,
    load_nutation_reference,
    load_perturber,
    load_precession_reference,
    measured,
    perturber_orbit,
    perturber_values,
    too_close,
    too_close_note,
)
from wobble.models import nutation as _nutation
from wobble.models import precession as _model

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "CENTURY",
    "ARCSEC_PER_CENTURY",
    "PrecessionTerm",
    "LiteratureStep",
    "RigidEarthNutation",
    "PrincipalNutation",
    "PrecessionBudget",
    "precession_rate",
    "principal_nutation",
    "precession_dataset",
]

CENTURY = u.def_unit("century", 100 * u.yr, doc="Julian century, 36525 d")
ARCSEC_PER_CENTURY = u.arcsec / CENTURY
_RATE = u.rad / u.s
#: JSON keys that had a second, unsuffixed name holding the same value (kept for one release, as
#: polar-motion's renamed keys): old name -> the name to use.
DEPRECATED_KEYS = {
    "rate_uncertainty": "rate_uncertainty_arcsec_per_century",
    "observed": "observed_arcsec_per_century",
    "observed_uncertainty": "observed_uncertainty_arcsec_per_century",
}

_SIGN_NOTE = (
    "rates are of the node longitude of the equator on the orbit plane, eastward (negative: retrograde); "
    "IAU's psi_A and p_A count westward, with the opposite sign"
)


@dataclass(frozen=True)
class PrecessionTerm:
    """One term of the precession budget.

    Attributes
    ----------
    name : str
        ``sun``, ``sun_eccentricity``, ``moon``, ``moon_inclination``, ``phobos`` (a ring satellite),
        ``geodesic``, ...
    rate : Quantity
        Its contribution, arcsec per Julian century (negative: retrograde).
    description : str
        The physics and its literature.
    """

    name: str
    rate: u.Quantity
    description: str


@dataclass(frozen=True)
class LiteratureStep:
    """A published step towards IAU 2006 precession that this model does not compute.

    Attributes
    ----------
    name : str
    change : Quantity
        What the step adds, arcsec per century (wobble's sign).
    value : Quantity
        The running total after the step, arcsec per century.
    description : str
    """

    name: str
    change: u.Quantity
    value: u.Quantity
    description: str


@dataclass(frozen=True)
class RigidEarthNutation:
    """A published rigid-Earth series' 18.6-year term, to compare the rigid model with like for like.

    Attributes
    ----------
    name : str
        The series (``REN-2000``).
    longitude, obliquity : Quantity
        Its coefficients of sin(Omega) in Delta psi and cos(Omega) in Delta eps, as
        published (IAU sign), arcsec.
    dynamical_flattening : float
        The H the series was computed with.
    scale : float
        The model's H over the series' H: a first-order amplitude is proportional
        to H, so ``scale * longitude`` is the series brought to the model's H.
    source : str
        Where the numbers come from.
    """

    name: str
    longitude: u.Quantity
    obliquity: u.Quantity
    dynamical_flattening: float
    scale: float
    source: str

    @property
    def scaled_longitude(self) -> u.Quantity:
        """The longitude coefficient at the model's H (``scale * longitude``), arcsec."""
        return self.scale * self.longitude

    @property
    def scaled_obliquity(self) -> u.Quantity:
        """The obliquity coefficient at the model's H (``scale * obliquity``), arcsec."""
        return self.scale * self.obliquity


@dataclass(frozen=True)
class PrincipalNutation:
    """The nutation driven by a perturber's node regression (the Moon: 18.6 years).

    Amplitudes in the IAU convention: Delta psi = longitude sin(Omega),
    Delta eps = obliquity cos(Omega).

    Attributes
    ----------
    perturber : str
    longitude, obliquity : Quantity
        Rigid-body first-order amplitudes (Woolard 1953; Kinoshita 1977), arcsec.
    period : Quantity
        Period of the node, Julian years.
    reference_longitude, reference_obliquity : Quantity or None
        IAU 2000A (non-rigid Earth, Mathews, Herring & Buffett 2002), arcsec.
    rigid : RigidEarthNutation or None
        A rigid-Earth series' 18.6-year term (REN-2000, Souchay et al. 1999), for
        Earth's Moon; the like-for-like comparison of a rigid model.
    """

    perturber: str
    longitude: u.Quantity
    obliquity: u.Quantity
    period: u.Quantity
    reference_longitude: u.Quantity | None = None
    reference_obliquity: u.Quantity | None = None
    rigid: RigidEarthNutation | None = None

    @property
    def rigid_difference(self) -> tuple[float, float] | None:
        """(longitude, obliquity): model over the rigid-Earth series at the model's H, minus 1 (None without one)."""
        if self.rigid is None:
            return None
        return (
            float(self.longitude / self.rigid.scaled_longitude - 1),
            float(self.obliquity / self.rigid.scaled_obliquity - 1),
        )

    def to_dict(self) -> dict:
        """JSON-ready amplitudes (arcsec) and their differences from the rigid-Earth series and from IAU 2000A."""
        out = {
            "perturber": self.perturber,
            "period_years": float(self.period.to_value(u.yr)),
            "longitude_arcsec": float(self.longitude.to_value(u.arcsec)),
            "obliquity_arcsec": float(self.obliquity.to_value(u.arcsec)),
        }
        if self.rigid is not None:
            r = self.rigid
            dl, de = self.rigid_difference
            out.update(
                {
                    "rigid_earth_series": r.name,
                    "rigid_earth_longitude_arcsec": float(r.longitude.to_value(u.arcsec)),
                    "rigid_earth_obliquity_arcsec": float(r.obliquity.to_value(u.arcsec)),
                    "rigid_earth_dynamical_flattening": r.dynamical_flattening,
                    "rigid_earth_scale_to_model_h": r.scale,
                    "rigid_earth_longitude_scaled_arcsec": float(r.scaled_longitude.to_value(u.arcsec)),
                    "rigid_earth_obliquity_scaled_arcsec": float(r.scaled_obliquity.to_value(u.arcsec)),
                    "difference_rigid_longitude_percent": 100 * dl,
                    "difference_rigid_obliquity_percent": 100 * de,
                    "rigid_earth_source": r.source,
                }
            )
        if self.reference_longitude is not None:
            out["iau2000a_longitude_arcsec"] = float(self.reference_longitude.to_value(u.arcsec))
            out["iau2000a_obliquity_arcsec"] = float(self.reference_obliquity.to_value(u.arcsec))
            out["difference_longitude_percent"] = 100 * float(self.longitude / self.reference_longitude - 1)
            out["difference_obliquity_percent"] = 100 * float(self.obliquity / self.reference_obliquity - 1)
        return out


def _arcsec_cy(rate_si: float) -> u.Quantity:
    return (rate_si << _RATE).to(ARCSEC_PER_CENTURY)


class PrecessionBudget:
    """A body's forced precession, term by term, with units. Build with :func:`precession_rate`."""

    def __init__(
        self,
        planet: Planet,
        raw: _model.PrecessionBudget,
        nutation: list[PrincipalNutation],
        steps: list[LiteratureStep],
        notes: list[str],
        iau: dict[str, u.Quantity] | None = None,
        planets: set[str] | frozenset[str] = frozenset(),
        left_out: tuple[str, ...] = (),
    ):
        self.planet = planet
        #: The catalogue's satellites of the body that the perturbers given left out (the observed rate holds them).
        self.left_out = tuple(left_out)
        #: Names of the terms that are planets' torques (equation (7) of wobble.models.precession).
        self.planet_terms = frozenset(planets)
        #: IAU 2006/2000A values to compare with (Earth only): first_order, psi_rate, general_precession.
        self.iau = iau
        self.raw = raw
        self.terms = [PrecessionTerm(t.name, _arcsec_cy(t.rate), t.description) for t in raw.terms]
        self.nutation = nutation
        self.literature_steps = steps
        self.notes = notes

    @property
    def body(self) -> str:
        return self.planet.name

    @property
    def first_order(self) -> u.Quantity:
        """First-order tidal precession from every perturber and ring satellite (no relativity), arcsec/century."""
        return _arcsec_cy(self.raw.torque_rate)

    @property
    def planetary(self) -> u.Quantity | None:
        """The planets' direct torque on the bulge, summed over the planets in the budget (None without any)."""
        if not self.planet_terms:
            return None
        return _arcsec_cy(sum(t.rate for t in self.raw.terms if t.name in self.planet_terms))

    @property
    def lunisolar(self) -> u.Quantity:
        """The first order less the planets' torque: the Sun's, the satellites' and the rings' share."""
        return self.first_order - (0 if self.planetary is None else self.planetary)

    @property
    def includes_geodesic(self) -> bool:
        """Whether the observed rate (and so :attr:`rate`) includes geodesic precession."""
        flag = self.planet.parameters.observed_precession_includes_geodesic
        return flag is None or flag.value != 0

    @property
    def rate(self) -> u.Quantity:
        """The model's precession rate, defined as the observed one is, arcsec/century.

        Tidal precession plus geodesic precession when the observation includes it
        (Earth's psi_A), the tidal precession alone when relativistic terms were
        modelled separately (the Mars tracking analyses).
        """
        return _arcsec_cy(self.raw.rate if self.includes_geodesic else self.raw.torque_rate)

    @property
    def inertial_rate(self) -> u.Quantity:
        """Tidal plus geodesic precession: the axis' motion in a non-rotating (BCRS) frame."""
        return _arcsec_cy(self.raw.rate)

    @property
    def rate_uncertainty(self) -> u.Quantity:
        """One-sigma uncertainty propagated linearly from the catalogue's uncertainties."""
        return _arcsec_cy(self.raw.rate_sigma)

    @property
    def observed(self) -> u.Quantity | None:
        obs = self.planet.parameters.observed_precession_rate
        return None if obs is None else _arcsec_cy(obs.value)

    @property
    def observed_uncertainty(self) -> u.Quantity | None:
        obs = self.planet.parameters.observed_precession_rate
        return None if obs is None else _arcsec_cy(obs.sigma)

    @property
    def observed_source(self) -> str | None:
        return None if self.observed is None else self.planet.source("observed_precession_rate")

    @property
    def residual(self) -> u.Quantity | None:
        """Model minus observed, arcsec/century."""
        return None if self.observed is None else self.rate - self.observed

    @property
    def residual_sigma(self) -> float | None:
        """The residual in units of the combined one-sigma uncertainty."""
        if self.observed is None:
            return None
        total = math.hypot(self.rate_uncertainty.value, self.observed_uncertainty.value)
        return float(self.residual.value / total) if total > 0 else math.inf

    @property
    def uncertainty_contributions(self) -> dict[str, u.Quantity]:
        """Rate change for +1 sigma of each input, largest first."""
        items = sorted(self.raw.contributions.items(), key=lambda kv: -abs(kv[1]))
        return {k: _arcsec_cy(v) for k, v in items}

    def to_dict(self) -> dict:
        """A JSON-ready summary (arcsec per Julian century; wobble's sign convention)."""

        def num(q):
            return None if q is None else float(q.to_value(ARCSEC_PER_CENTURY))

        out = {
            "body": self.body,
            "title": self.planet.title,
            "rate_arcsec_per_century": num(self.rate),
            "rate_uncertainty_arcsec_per_century": num(self.rate_uncertainty),
            "first_order_arcsec_per_century": num(self.first_order),
            "planetary_arcsec_per_century": num(self.planetary),
            "lunisolar_arcsec_per_century": num(self.lunisolar),
            "with_geodesic_arcsec_per_century": num(self.inertial_rate),
            "observed_includes_geodesic": self.includes_geodesic,
            "rate_mas_per_year": float(self.rate.to_value(u.mas / u.yr)),
            "terms": [
                {
                    "name": t.name,
                    "value_arcsec_per_century": num(t.rate),
                    "description": t.description,
                }
                for t in self.terms
            ],
            "observed_arcsec_per_century": num(self.observed),
            "observed_uncertainty_arcsec_per_century": num(self.observed_uncertainty),
            "residual_arcsec_per_century": num(self.residual),
            "residual_sigma": self.residual_sigma,
            "source": self.observed_source,
            "sign_convention": _SIGN_NOTE,
            "literature_steps": [
                {
                    "name": s.name,
                    "change_arcsec_per_century": num(s.change),
                    "value_arcsec_per_century": num(s.value),
                    "description": s.description,
                }
                for s in self.literature_steps
            ],
            "nutation": [n.to_dict() for n in self.nutation],
            "notes": self.notes,
            "uncertainty_contributions_arcsec_per_century": {
                k: num(v) for k, v in self.uncertainty_contributions.items()
            },
        }
        return deprecate(out, {**DEPRECATED_KEYS, "terms[].value": "terms[].value_arcsec_per_century"})

    def summary(self) -> str:
        """The budget as text for a person."""
        return _summary(self)

    def to_dataset(self) -> xr.Dataset:
        """This budget as a CF Dataset; see :func:`precession_dataset`."""
        return precession_dataset([self])

    def __repr__(self) -> str:
        return f"PrecessionBudget({self.body!r}, rate={self.rate:.3f})"


# ---------------------------------------------------------------------------
# Building the model's inputs from the catalogue.
# ---------------------------------------------------------------------------


def _require(planet: Planet, key: str):
    value = getattr(planet.parameters, key)
    if value is None:
        raise FileFormatError(
            planet.file.path or planet.name, f"parameters.{key}", "missing; needed for the precession rate"
        )
    return value


def _planet_values(planet: Planet):
    p = planet.parameters
    values, sigmas = {}, {}
    for key in ("rotation_rate", "obliquity", "orbit_semi_major_axis", "orbit_eccentricity"):
        m = _require(planet, key)
        values[key], sigmas[key] = m.value, m.sigma
    for key in ("dynamical_flattening", "j2", "polar_moment_factor", "gm", "equatorial_radius"):
        m = getattr(p, key)
        if m is not None:
            values[key], sigmas[key] = m.value, m.sigma
    eps = values["obliquity"]
    if not 0.0 <= eps <= math.pi:
        raise FileFormatError(
            planet.file.path or planet.name,
            "parameters.obliquity.value",
            f"got {math.degrees(eps):.6g} deg; allowed: 0 to 180 deg",
        )
    e = values["orbit_eccentricity"]
    if not 0.0 <= e < 1.0:
        raise FileFormatError(
            planet.file.path or planet.name,
            "parameters.orbit_eccentricity.value",
            f"got {e!r}; allowed: 0 <= e < 1 (a bound orbit)",
        )
    return values, sigmas


def _flattening(values) -> float:
    if "dynamical_flattening" in values:
        return values["dynamical_flattening"]
    return values["j2"] / values["polar_moment_factor"]


def _polar_moment_factor(values) -> float | None:
    """C/(M R^2): catalogued, else J2/H (the ring satellites need it)."""
    if "polar_moment_factor" in values:
        return values["polar_moment_factor"]
    if "j2" in values and "dynamical_flattening" in values:
        return values["j2"] / values["dynamical_flattening"]
    return None


def _prepare(perturbers: list[ParameterFile]):
    def prepare(values) -> _model.Inputs:
        sun = _model.PerturberOrbit(
            "sun",
            values["sun.gm"],
            values["orbit_semi_major_axis"],
            values["orbit_eccentricity"],
        )
        orbits = (sun, *(perturber_orbit(pf, values, values["orbit_semi_major_axis"]) for pf in perturbers))
        return _model.Inputs(
            _flattening(values),
            values["rotation_rate"],
            values["obliquity"],
            orbits,
            sun,
            _polar_moment_factor(values),
            values.get("gm"),
            values.get("equatorial_radius"),
        )

    return prepare


def _steps_explain(b) -> bool:
    """True when the published terms take the model to the observed rate within 3 combined sigma
    (not, e.g., when --perturber left the Moon out: the residual is then the Moon's term)."""
    if not b.literature_steps or b.observed is None:
        return False
    psi = next((s.value for s in b.literature_steps if s.name == "nonlinear_term"), b.literature_steps[-1].value)
    total = math.hypot(b.rate_uncertainty.value, b.observed_uncertainty.value)
    return abs((psi - b.observed).to_value(b.observed.unit)) <= 3 * total


def _orbit_range(planet: Planet) -> tuple[float, float]:
    return planet.parameters.orbit_semi_major_axis.value, planet.parameters.orbit_eccentricity.value


def _default_perturbers(planet: Planet) -> tuple[list[ParameterFile], list[str]]:
    """The catalogue's satellites of the body, then the planets apart from its own orbit; and what was left out."""
    files, close = default_perturbers(planet.name, *_orbit_range(planet))
    return files, [too_close_note(close)] if close else []


def _perturber_files(planet: Planet, perturbers) -> tuple[list[ParameterFile], list[str]]:
    """The perturbers besides the Sun: the catalogue's (satellites and planets) or those given; notes of omissions."""
    if perturbers is None:
        return _default_perturbers(planet)
    if isinstance(perturbers, (str, os.PathLike)):  # one perturber: "moon" is ["moon"], not its letters
        perturbers = [perturbers]
    files = [load_perturber(p) for p in perturbers]
    seen = set()
    body = planet.name.strip().lower()
    for given, pf in zip(perturbers, files):
        primary = str(pf.extra.get("primary", "")).strip().lower()
        if pf.name == "sun":
            continue  # the Sun is always there, on the planet's own orbit
        if is_planet(pf):
            if too_close(pf, *_orbit_range(planet)):
                why = "the body itself" if pf.name == body else f"within {MIN_SEPARATION:.0%} of its orbit"
                raise InputError("perturber", str(given), f"a planet apart from the body's orbit (this one is {why})")
        elif primary != body:
            # A satellite's orbit (its semi-major axis about its primary) means nothing about
            # another body: the Moon about Mars gave -5780"/cy and a residual of -2905 sigma.
            raise InputError(
                "perturber",
                str(given),
                f"a satellite of {planet.name}, or a planet (this one orbits {primary or 'nothing named'})",
            )
        if pf.name in seen:
            raise InputError("perturber", str(given), "each perturber once (it is already included)")
        seen.add(pf.name)
    files = [pf for pf in files if pf.name != "sun"]
    # Given perturbers replace the catalogue's: say which were left out (--perturber sun alone,
    # the Sun only, printed Earth's rate without the Moon and a residual of 3.7 million sigma, silently).
    given = {pf.name for pf in files}
    left = [pf.name for pf in _default_perturbers(planet)[0] if pf.name not in given]
    notes = []
    if left:
        notes.append(
            f"left out: {', '.join(left)} (the catalogue's perturbers of {planet.title}; the perturbers given "
            "replace them)"
        )
    return files, notes


def _check_orbits(planet: Planet, files: list[ParameterFile], values) -> None:
    radius = planet.parameters.equatorial_radius
    for pf in files:
        try:
            orbit = perturber_orbit(pf, values, values["orbit_semi_major_axis"])
            if not orbit.is_planet:  # a planet's heliocentric orbit: checked against the body's by too_close()
                _model.check_inside(orbit, None if radius is None else radius.value)
        except InputError as exc:
            raise FileFormatError(
                pf.path, f"parameters ({exc.parameter})", f"{exc.value}; needs {exc.allowed}"
            ) from None


def _literature_steps(
    first_order_si: float, geodesic_si: float, planetary_si: float | None, only: list[str] | None = None
) -> tuple[list[LiteratureStep], ParameterFile]:
    """From this model's first-order lunisolar rate to psi_A and p_A, with the published terms (wobble's sign).

    ``first_order_si`` includes the planets' torque when ``planetary_si`` (their sum) is given; it is then shown
    as a step computed here, and the published planetary step beside it, instead of added. ``only`` names the
    planets when they are not all the catalogue's (``--perturber``): the published value is for all of them.
    """
    ref = load_precession_reference()

    def si(key):
        return measured(ref, key, REFERENCE_UNITS[key]).value

    steps = []
    running = first_order_si - (planetary_si or 0.0)

    def add(name, change_si, description):
        nonlocal running
        running += change_si
        steps.append(LiteratureStep(name, _arcsec_cy(change_si), _arcsec_cy(running), description))

    add("geodesic", geodesic_si, 'geodesic precession, computed here (IAU 2006: -1.919883"/cy in psi_A)')
    others = ("planetary_first_order", "lunisolar_second_order", "j4_term", "j2_planetary_tilt", "nonlinear_term")
    if planetary_si is not None:
        published = _arcsec_cy(-si("planetary_first_order")).to_value(ARCSEC_PER_CENTURY)
        if only is None:
            what, reference = "the planets' torque", f'IAU 2006, after Williams 1994: {published:+.6f}"/cy'
        else:
            what = f"the torque of {', '.join(only)} alone"
            reference = f"IAU 2006's {published:+.6f}\"/cy, after Williams 1994, is for all the planets"
        add("planets", planetary_si, f"{what} on the bulge, computed here (circular orbits; {reference})")
        others = others[1:]
    labels = {
        "planetary_first_order": "planets' torque on the bulge, first order",
        "lunisolar_second_order": "lunisolar torque, second order in H",
        "j4_term": "lunisolar torque on J4",
        "j2_planetary_tilt": "J2 with the planets' tilting of the lunar and solar orbits",
        "nonlinear_term": "non-linear effect of the nutation on the precession",
    }
    for key in others:
        # IAU rates count westward: a published +x"/cy is -x here.
        add(key, -si(key), f"{labels[key]} ({ref.get(key).source})")
    chi = si("chi_rate")
    eps0 = si("obliquity")
    add(
        "ecliptic_motion",
        chi * math.cos(eps0),
        "the ecliptic's own motion: p_A = psi_A - chi_A cos(eps_0) (Lieske et al. 1977; Capitaine et al. 2003)",
    )
    return steps, ref


def _iau_references(ref: ParameterFile) -> dict[str, u.Quantity]:
    def q(key):
        return measured(ref, key, REFERENCE_UNITS[key]).value

    return {
        "first_order": _arcsec_cy(-q("first_order_lunisolar_coefficient") * math.cos(q("obliquity"))),
        "psi_rate": _arcsec_cy(-q("psi_rate")),
        "general_precession": _arcsec_cy(-q("general_precession")),
        "nutation_longitude": (q("nutation_longitude_iau2000a") << u.rad).to(u.arcsec),
        "nutation_obliquity": (q("nutation_obliquity_iau2000a") << u.rad).to(u.arcsec),
    }


def _rigid_reference(model_flattening: float) -> RigidEarthNutation:
    """REN-2000's 18.6-year term from the catalogue, with the ratio of the model's H to the series'."""
    ref = load_nutation_reference()

    def q(key):
        return measured(ref, key, NUTATION_REFERENCE_UNITS[key]).value

    h = q("dynamical_flattening")
    return RigidEarthNutation(
        "REN-2000",
        (q("nutation_longitude") << u.rad).to(u.arcsec),
        (q("nutation_obliquity") << u.rad).to(u.arcsec),
        h,
        model_flattening / h,
        ref.get("nutation_longitude").source,
    )


def precession_rate(body: str | os.PathLike | Planet, perturbers=None) -> PrecessionBudget:
    """The forced precession rate of a planet's spin axis, term by term, from its physical parameters.

    Parameters
    ----------
    body : str, path-like or Planet
        A catalogue name (``"earth"``, ``"mars"``), a planet file with
        ``obliquity``, ``orbit_semi_major_axis`` and ``orbit_eccentricity``,
        or a :class:`~wobble.Planet`.
    perturbers : str, path-like or a list of them, optional
        Satellites to include (catalogue names or perturber files). Default:
        the catalogued perturbers whose ``primary`` is the body (the Moon for
        Earth). The Sun is always included, on the body's own orbit.

    Returns
    -------
    PrecessionBudget
        Rates in arcsec per Julian century, negative when retrograde. The
        observed rate is shown for comparison and is never an input.

    Examples
    --------
    >>> import wobble
    >>> mars = wobble.precession_rate("mars")
    >>> print(f"{mars.rate.to('mas / yr'):.1f}")   # observed: -7608.3 +- 2.1 mas/yr
    -7604.0 mas / yr
    """
    planet = load_planet(body)
    values, sigmas = _planet_values(planet)
    sun = load_perturber("sun")
    perturber_values(sun, values, sigmas)
    files, omitted = _perturber_files(planet, perturbers)
    # Satellites of the catalogue left out by --perturber: the observed rate holds their torque, so neither the
    # residual nor the steps to IAU 2006 test the model (--perturber sun alone: "+3678486.5 sigma").
    given = {pf.name for pf in files}
    missing = tuple(pf.name for pf in _default_perturbers(planet)[0] if not is_planet(pf) and pf.name not in given)
    for pf in files:
        perturber_values(pf, values, sigmas)
    _check_orbits(planet, files, values)
    try:
        raw = _model.precession_budget(planet.name, values, _prepare(files), sigmas)
    except InputError as exc:
        # A perturber's value ("moon.semi_major_axis") is its own file's, not the body's.
        owner, _, key = exc.parameter.partition(".")
        pf = next((f for f in (sun, *files) if key and f.name == owner), None)
        path, where = (pf.path or pf.name, f"parameters.{key}") if pf is not None else (planet.file.path, None)
        raise FileFormatError(
            path or planet.name, where or f"parameters ({exc.parameter})", f"{exc.value}; needs {exc.allowed}"
        ) from None
    inputs = _prepare(files)(values)
    planets = {o.name for o in inputs.orbits if o.is_planet}
    nutation = []
    refs = None
    rigid = None
    steps: list[LiteratureStep] = []
    notes = []
    if planet.name == "earth" and not missing:
        geodesic = next(t.rate for t in raw.terms if t.name == "geodesic")
        planetary = sum(t.rate for t in raw.terms if t.name in planets) if planets else None
        every = {pf.name for pf in _default_perturbers(planet)[0] if is_planet(pf)}
        only = None if every <= planets else [o.name for o in inputs.orbits if o.is_planet]
        steps, ref_file = _literature_steps(raw.torque_rate, geodesic, planetary, only)
        refs = _iau_references(ref_file)
        rigid = _rigid_reference(inputs.dynamical_flattening)
    for orbit in inputs.orbits:
        if orbit.node_rate:
            n = _nutation.nodal_nutation(inputs.dynamical_flattening, inputs.spin_rate, inputs.obliquity, orbit)
            nutation.append(
                PrincipalNutation(
                    orbit.name,
                    (n.longitude << u.rad).to(u.arcsec),
                    (n.obliquity << u.rad).to(u.arcsec),
                    (n.period << u.s).to(u.yr),
                    None if refs is None else refs["nutation_longitude"],
                    None if refs is None else refs["nutation_obliquity"],
                    rigid if orbit.name == "moon" else None,
                )
            )
    obs = planet.file.get("observed_precession_rate")
    if obs is not None and "circular" in obs.note.lower():
        notes.append(" ".join(obs.note.split()))
    notes += omitted
    if missing and planet.name == "earth":
        notes.append(f"no steps to IAU 2006: its rates hold the torque of {', '.join(missing)}, left out here")
    return PrecessionBudget(planet, raw, nutation, steps, notes, refs, planets, left_out=missing)


def principal_nutation(body: str | os.PathLike | Planet = "earth", perturbers=None) -> list[PrincipalNutation]:
    """The rigid-body principal nutation of ``body`` from each perturber with a node rate (the Moon).

    For Earth's Moon each result carries the rigid-Earth series REN-2000's 18.6-year
    term (``rigid``; Souchay et al. 1999), the like-for-like comparison, and IAU 2000A's
    (``reference_longitude``, ``reference_obliquity``; non-rigid Earth).

    Examples
    --------
    >>> import wobble
    >>> (n,) = wobble.principal_nutation("earth")
    >>> print(f"{n.longitude:.4f} vs REN-2000 {n.rigid.scaled_longitude:.4f}")
    -17.2857 arcsec vs REN-2000 -17.2808 arcsec
    """
    return precession_rate(body, perturbers).nutation


def precession_dataset(budgets: list[PrecessionBudget]) -> xr.Dataset:
    """Several precession budgets as one CF Dataset (dimensions ``body`` and ``term``), rates in rad/s."""
    from wobble.api.dataset import xarray
    from wobble.io.cf import variable

    xr = xarray()
    if not budgets:
        raise InputError("budgets", "[]", "at least one PrecessionBudget")
    names = []
    for b in budgets:
        for t in b.terms:
            if t.name not in names:
                names.append(t.name)
    rate = np.full((len(budgets), len(names)), np.nan)
    for i, b in enumerate(budgets):
        for t in b.terms:
            rate[i, names.index(t.name)] = t.rate.to_value(_RATE)

    def per_body(fn):
        return np.array([np.nan if (v := fn(b)) is None else v.to_value(_RATE) for b in budgets], dtype=float)

    def nut(b, key):
        return (b.nutation[0].longitude if key == "lon" else b.nutation[0].obliquity) if b.nutation else None

    def per_body_angle(fn):
        return np.array([np.nan if (v := fn(b)) is None else v.to_value(u.rad) for b in budgets], dtype=float)

    def var(name, data, **extra):
        return variable("precession", name, data, **extra)

    refs = sorted(
        {b.planet.source(k) for b in budgets for k in ("dynamical_flattening", "obliquity", "orbit_semi_major_axis")}
    )
    descriptions = {}
    for b in budgets:
        for t in b.terms:
            descriptions.setdefault(t.name, t.description)
    ds = xr.Dataset(
        {
            "term_rate": var("term_rate", rate, comment="; ".join(f"{k}: {v}" for k, v in descriptions.items())),
            "first_order_rate": var("first_order_rate", per_body(lambda b: b.first_order)),
            "planetary_rate": var("planetary_rate", per_body(lambda b: b.planetary)),
            "precession_rate": var("precession_rate", per_body(lambda b: b.rate), comment=_SIGN_NOTE),
            "precession_rate_uncertainty": var("precession_rate_uncertainty", per_body(lambda b: b.rate_uncertainty)),
            "observed_precession_rate": var("observed_precession_rate", per_body(lambda b: b.observed)),
            "observed_precession_rate_uncertainty": var(
                "observed_precession_rate_uncertainty", per_body(lambda b: b.observed_uncertainty)
            ),
            "nutation_longitude": var("nutation_longitude", per_body_angle(lambda b: nut(b, "lon"))),
            "nutation_obliquity": var("nutation_obliquity", per_body_angle(lambda b: nut(b, "obl"))),
            "spin_rate": var("spin_rate", np.array([b.planet.rotation_rate.to_value(_RATE) for b in budgets])),
        },
        coords={
            "body": ("body", [b.body for b in budgets], {"long_name": "body identifier"}),
            "term": ("term", names, {"long_name": "term of the precession budget"}),
        },
        attrs={
            "title": "Forced precession budget",
            "references": "; ".join(refs),
            "comment": "Rates from physical parameters only (the observed rate is never an input); "
            + _SIGN_NOTE
            + ". "
            + " ".join(n for b in budgets for n in b.notes),
        },
    )
    return ds


# ---------------------------------------------------------------------------
# Text for a person.
# ---------------------------------------------------------------------------


def _fmt(q, digits=3, sign=True) -> str:
    x = float(q.to_value(ARCSEC_PER_CENTURY))
    return f"{x:+.{digits}f}" if sign else f"{x:.{digits}f}"


def with_uncertainty(value: float, sigma: float | None, *, sign: bool = False) -> str:
    """``value +/- sigma`` to the uncertainty's two significant digits (the CLI's style)."""
    if sigma is None or not (math.isfinite(sigma) and sigma > 0):
        return f"{value:+.3f}" if sign else f"{value:.3f}"
    d = max(0, 1 - math.floor(math.log10(sigma)))
    return f"{value:{'+' if sign else ''}.{d}f} +/- {sigma:.{d}f}"


def _mas_per_year(rate, sigma) -> str:
    """A rate again in mas/yr, with its uncertainty, both to the uncertainty's two significant digits
    (``-14640 +/- 49 mas/yr``); to 0.1 mas/yr without one."""
    value = float(rate.to_value(u.mas / u.yr))
    s = None if sigma is None else float(sigma.to_value(u.mas / u.yr))
    if s is None or not (math.isfinite(s) and s > 0):
        return f"{value:+.1f} mas/yr"
    return f"{with_uncertainty(value, s, sign=True)} mas/yr"


def _summary(b: PrecessionBudget) -> str:
    lines = _budget_lines(b)
    if b.iau is not None:
        lines += _iau_lines(b)
    for n in b.nutation:
        lines += _nutation_lines(n)
    if not b.includes_geodesic:
        lines.append("  note: the observed rate excludes geodesic precession (relativistic terms modelled separately),")
        lines.append(
            f"  so the comparison uses the tidal rate; with geodesic precession the model is {_fmt(b.inertial_rate)}."
        )
    for note in b.notes:
        lines.append(f"  note: {note}")
    return "\n".join(lines)


def _budget_lines(b: PrecessionBudget) -> list[str]:
    """The terms, the first order, the model with its uncertainty, and the observed rate and residual."""
    lines = [f"{b.planet.title}: forced precession of the spin axis (arcsec per Julian century; negative = retrograde)"]
    lines.append(f"  {'term':<26}{'rate':>14}   physics (references)")
    for t in b.terms:
        if t.name not in b.planet_terms:
            lines.append(f"  {t.name:<26}{_fmt(t.rate):>14}   {t.description}")
        elif t.name == next(p.name for p in b.terms if p.name in b.planet_terms):
            lines.append(_planets_line(b))
    lines.append(f"  {'first order (torques)':<26}{_fmt(b.first_order):>14}")
    rate = b.rate.to_value(ARCSEC_PER_CENTURY)
    sigma = b.rate_uncertainty.to_value(ARCSEC_PER_CENTURY)
    label = "model (with geodesic)" if b.includes_geodesic else "model (tidal; see note)"
    lines.append(
        f"  {label:<26}{with_uncertainty(rate, sigma if sigma > 0 else None, sign=True):>14}"
        f"   = {_mas_per_year(b.rate, b.rate_uncertainty)}"
    )
    if b.observed is not None:
        obs = b.observed.to_value(ARCSEC_PER_CENTURY)
        osig = b.observed_uncertainty.to_value(ARCSEC_PER_CENTURY)
        lines.append(
            f"  {'observed':<26}{with_uncertainty(obs, osig, sign=True):>14}"
            f"   = {_mas_per_year(b.observed, b.observed_uncertainty)}; {b.observed_source}"
        )
        why = "; the published higher-order terms below account for it" if _steps_explain(b) else ""
        if b.left_out:
            lines.append(
                f"  {'residual':<26}{_fmt(b.residual):>14}   (not a test of the model: the observed rate holds the "
                f"torque of {', '.join(b.left_out)}, left out here)"
            )
        else:
            lines.append(
                f"  {'residual':<26}{_fmt(b.residual):>14}   ({b.residual_sigma:+.1f} sigma of the model and "
                f"observed uncertainties{why})"
            )
    return lines


def _planets_line(b: PrecessionBudget) -> str:
    """The planets' terms as one line (each is in ``terms``, the JSON and the Dataset), largest first."""
    planets = sorted((t for t in b.terms if t.name in b.planet_terms), key=lambda t: -abs(t.rate.value))
    shares = ", ".join(f"{t.name} {t.rate.to_value(ARCSEC_PER_CENTURY):+.2g}" for t in planets)
    return (
        f"  {'planets':<26}{_fmt(b.planetary):>14}   their direct torques on the bulge, circular orbits in one plane "
        f"averaged over both (Laplace coefficient b_3/2^(0); Murray & Dermott 1999, sec. 6.4): {shares}"
    )


def _iau_lines(b: PrecessionBudget) -> list[str]:
    """The steps from the model's first order to IAU 2006's psi_A and p_A, with the differences."""
    lines = [
        "  steps to IAU 2006 (the model's first order from the Sun and Moon, then the terms computed here and the",
        '  published ones; IAU counts westward, so its psi_A = +5038.48"/cy is -5038.48 here):',
        f'    {"Sun and Moon (model)":<24}{_fmt(b.lunisolar):>14}   IAU 2006: 5494.062986" cos(eps_0) = '
        f"{_fmt(b.iau['first_order'])}",
    ]
    for s in b.literature_steps:
        lines.append(f"    + {s.name:<22}{_fmt(s.change, 6):>14}  -> {_fmt(s.value)}   {s.description}")
        if s.name == "nonlinear_term":
            lines.append(
                f"    {'= psi_A (model)':<24}{_fmt(s.value):>14}   IAU 2006 psi_A: {_fmt(b.iau['psi_rate'])}"
                f"  (difference {_fmt(s.value - b.iau['psi_rate'], 4)})"
            )
    last = b.literature_steps[-1].value
    lines.append(
        f"    {'= p_A (model)':<24}{_fmt(last):>14}   IAU 2006 p_A: {_fmt(b.iau['general_precession'])}"
        f"  (difference {_fmt(last - b.iau['general_precession'], 4)})"
    )
    return lines


def _nutation_lines(n) -> list[str]:
    """One principal nutation: the model's amplitudes, beside the rigid-Earth series and IAU 2000A."""
    lines = [
        f"  principal nutation from the {n.perturber.capitalize()}'s node ({n.period.to_value(u.yr):.2f} yr), "
        "rigid body, first order:",
        f'    Delta psi = {n.longitude.to_value(u.arcsec):+.4f}" sin(Omega), Delta eps = '
        f'{n.obliquity.to_value(u.arcsec):+.4f}" cos(Omega)',
    ]
    if n.rigid is not None:
        r = n.rigid
        dl, de = n.rigid_difference
        lines.append(
            f"    rigid Earth, {r.name} (Souchay et al. 1999; H = {r.dynamical_flattening:.8g}): "
            f'{r.longitude.to_value(u.arcsec):+.4f}", {r.obliquity.to_value(u.arcsec):+.4f}"; '
            f"at the catalogue's H (x {r.scale:.7f}): {r.scaled_longitude.to_value(u.arcsec):+.4f}\", "
            f'{r.scaled_obliquity.to_value(u.arcsec):+.4f}"'
        )
        lines.append(
            f"    model - {r.name}: {100 * dl:+.3f} %, {100 * de:+.3f} % (the series adds the second-order and "
            "planetary-tilt terms a first-order model leaves out)"
        )
    if n.reference_longitude is not None:
        dl = 100 * float(n.longitude / n.reference_longitude - 1)
        de = 100 * float(n.obliquity / n.reference_obliquity - 1)
        lines.append(
            f'    IAU 2000A (non-rigid Earth): {n.reference_longitude.to_value(u.arcsec):+.4f}", '
            f'{n.reference_obliquity.to_value(u.arcsec):+.4f}"; model - IAU 2000A: {dl:+.2f} %, {de:+.2f} %'
        )
    return lines
