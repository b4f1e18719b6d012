"""Forced precession of an oblate body's spin axis by the tidal torque of its perturbers.

The gravity-gradient torque of a point mass M at r on an axisymmetric body
(polar moment C about the unit axis s, equatorial moment A) is

    tau = (3 G M / r^5) (C - A) (s . r) (r x s)                             (1)

(MacCullagh's formula; Goldstein, Poole & Safko 2002, *Classical Mechanics*,
sec. 5.8, "precession of the equinoxes"). Averaged over a Keplerian orbit of
semi-major axis a, eccentricity e and unit normal n (time average of
r r^T / r^5 = (1 - e^2)^(-3/2) (I - n n^T) / (2 a^3)),

    <tau> = (3 G M (C - A) / (2 a^3 (1 - e^2)^(3/2))) (s . n) (s x n).     (2)

With the spin angular momentum C omega s (the body spins much faster than s
moves) the axis precesses about n, retrogradely for an oblate body (C > A)
spinning prograde, at the rate

    dpsi/dt = -(3/2) (G M / (a^3 (1 - e^2)^(3/2))) (H / omega) cos(eps),    (3)

H = (C - A)/C, eps the obliquity (angle between s and n), psi the longitude
of the ascending node of the equator on the orbit plane (eastward). When the
perturber's orbit is inclined by i to the reference plane and its node
regresses fast compared with the precession (the Moon: 18.6 yr against
26 000 yr), the average over the node multiplies (3) by
P2(cos i) = 1 - (3/2) sin^2 i (Woolard 1953). A real orbit differs from the
Keplerian ellipse (the Sun's perturbations of the lunar orbit); a catalogued
factor carries that difference. The rates of several perturbers add.

Geodesic (de Sitter) precession of the spin in the Sun's field, prograde about
the orbit normal, is

    Omega_geo = (3/2) (G M_sun / (c^2 a (1 - e^2))) n                       (4)

with n the orbital mean motion (e.g. Soffel 1989, *Relativity in Astrometry,
Celestial Mechanics and Geodesy*, sec. 9; for Earth 1.92"/cy).

Everything here is SI (kg, m, s, rad); the sign convention is that of the
node longitude psi (eastward positive), so a retrograde precession is
negative. IAU's precession in longitude psi_A has the opposite sign.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from wobble.errors import InputError

__all__ = [
    "SPEED_OF_LIGHT",
    "PerturberOrbit",
    "Term",
    "PrecessionBudget",
    "check_obliquity",
    "tidal_torque",
    "averaged_tidal_torque",
    "orbit_average_torque_numerically",
    "torque_strength",
    "precession_rate",
    "geodesic_precession_rate",
    "Inputs",
    "budget_terms",
    "precession_budget",
    "check_inside",
]

SPEED_OF_LIGHT = 299_792_458.0  # m/s, exact (SI definition)


@dataclass(frozen=True)
class PerturberOrbit:
    """A perturbing point mass on its mean orbit about the body (SI).

    Attributes
    ----------
    name : str
        ``"sun"``, ``"moon"``, ...
    gm : float
        G M of the perturber, m^3/s^2 (positive).
    semi_major_axis : float
        a, m (positive). For the Sun: the body's heliocentric orbit.
    eccentricity : float
        e in [0, 1).
    inclination : float
        i to the reference plane (the body's orbit plane for a satellite of
        a planet: the ecliptic for the Moon), rad; the node is assumed to
        regress fast compared with the precession.
    perturbation_factor : float
        Ratio of the real orbit's average <(a/r)^3 P2(sin beta)> to the
        Keplerian one (1 for a Keplerian orbit).
    node_rate : float or None
        Rate of the orbit's node on the reference plane, rad/s (for nutation).
    """

    name: str
    gm: float
    semi_major_axis: float
    eccentricity: float = 0.0
    inclination: float = 0.0
    perturbation_factor: float = 1.0
    node_rate: float | None = None

    def __post_init__(self):
        if not (math.isfinite(self.gm) and self.gm > 0):
            raise InputError(f"{self.name}.gm", self.gm, "a positive G M (a perturber has positive mass)")
        if not (math.isfinite(self.semi_major_axis) and self.semi_major_axis > 0):
            raise InputError(f"{self.name}.semi_major_axis", self.semi_major_axis, "a positive, finite length")
        if not (0.0 <= self.eccentricity < 1.0):
            raise InputError(
                f"{self.name}.eccentricity",
                self.eccentricity,
                "0 <= e < 1 (a bound orbit; e >= 1 is parabolic or hyperbolic)",
            )
        if not (0.0 <= self.inclination <= math.pi):
            raise InputError(
                f"{self.name}.inclination", self.inclination, "an inclination in [0, pi] rad (0 to 180 deg)"
            )
        if not (math.isfinite(self.perturbation_factor) and self.perturbation_factor > 0):
            raise InputError(f"{self.name}.perturbation_factor", self.perturbation_factor, "a positive factor near 1")

    @property
    def periapsis(self) -> float:
        """a (1 - e), m."""
        return self.semi_major_axis * (1.0 - self.eccentricity)

    @property
    def eccentricity_factor(self) -> float:
        """(1 - e^2)^(-3/2): the time average of (a/r)^3 on the ellipse."""
        return (1.0 - self.eccentricity**2) ** -1.5

    @property
    def inclination_factor(self) -> float:
        """P2(cos i) = 1 - (3/2) sin^2 i: the average over a regressing node."""
        return 1.0 - 1.5 * math.sin(self.inclination) ** 2


def check_obliquity(obliquity: float) -> float:
    """The obliquity in rad, checked to lie in [0, pi] (0 to 180 deg)."""
    if not (math.isfinite(obliquity) and 0.0 <= obliquity <= math.pi):
        raise InputError("obliquity", f"{math.degrees(obliquity):.6g} deg", "an angle in [0, 180] deg")
    return obliquity


def check_inside(orbit: PerturberOrbit, radius: float | None) -> None:
    """Refuse a perturber whose periapsis lies inside the body (radius in m, or None)."""
    if radius is not None and orbit.periapsis <= radius:
        raise InputError(
            f"{orbit.name}.semi_major_axis",
            f"periapsis a(1 - e) = {orbit.periapsis:.6g} m",
            f"an orbit outside the body (periapsis above its radius {radius:.6g} m)",
        )


def tidal_torque(gm: float, c_minus_a: float, axis, position) -> np.ndarray:
    """Instantaneous gravity-gradient torque of a point mass, equation (1), N m.

    Parameters
    ----------
    gm : float
        G M of the point mass, m^3/s^2.
    c_minus_a : float
        C - A of the axisymmetric body, kg m^2.
    axis : array_like, shape (3,)
        Unit symmetry axis s.
    position : array_like, shape (..., 3)
        Position(s) r of the point mass relative to the body's centre, m.
    """
    s = np.asarray(axis, dtype=float)
    r = np.asarray(position, dtype=float)
    rn = np.linalg.norm(r, axis=-1, keepdims=True)
    return 3.0 * gm * c_minus_a / rn**5 * (r @ s)[..., None] * np.cross(r, s)


def averaged_tidal_torque(
    gm: float, c_minus_a: float, axis, normal, semi_major_axis: float, eccentricity: float = 0.0
) -> np.ndarray:
    """Orbit-averaged torque of a Keplerian perturber, equation (2), N m."""
    s = np.asarray(axis, dtype=float)
    n = np.asarray(normal, dtype=float)
    k = 1.5 * gm * c_minus_a / (semi_major_axis**3 * (1.0 - eccentricity**2) ** 1.5)
    return k * float(s @ n) * np.cross(s, n)


def orbit_average_torque_numerically(gm, c_minus_a, axis, normal, semi_major_axis, eccentricity=0.0, samples=256):
    """Time average of equation (1) over one Keplerian orbit, by quadrature in the eccentric anomaly.

    dt is proportional to (1 - e cos E) dE, and the integrand is periodic and
    smooth, so the trapezoidal rule on a uniform grid converges geometrically.
    Used to test equation (2), not by the budget.
    """
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    # An orthonormal basis (p, q) of the orbit plane, perihelion along p.
    trial = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    p = np.cross(n, trial)
    p /= np.linalg.norm(p)
    q = np.cross(n, p)
    big_e = 2.0 * math.pi * np.arange(samples) / samples
    x = semi_major_axis * (np.cos(big_e) - eccentricity)
    y = semi_major_axis * math.sqrt(1.0 - eccentricity**2) * np.sin(big_e)
    r = x[:, None] * p + y[:, None] * q
    weight = (1.0 - eccentricity * np.cos(big_e)) / samples
    return (weight[:, None] * tidal_torque(gm, c_minus_a, axis, r)).sum(axis=0)


def torque_strength(orbit: PerturberOrbit) -> float:
    """k = G M <(1/r)^3 P2> / (-1/2) of one perturber: G M/a^3 times its factors, s^-2."""
    return (
        orbit.gm
        / orbit.semi_major_axis**3
        * orbit.eccentricity_factor
        * orbit.inclination_factor
        * orbit.perturbation_factor
    )


def precession_rate(
    dynamical_flattening: float, spin_rate: float, obliquity: float, orbits: Sequence[PerturberOrbit]
) -> float:
    """Secular precession rate of the node of the equator, equation (3) summed, rad/s.

    Negative (retrograde) for an oblate body (H > 0) spinning prograde
    (omega > 0) with eps < 90 deg.
    """
    check_obliquity(obliquity)
    if spin_rate == 0:
        raise InputError("rotation_rate", 0.0, "a non-zero spin rate")
    total = sum(torque_strength(o) for o in orbits)
    return -1.5 * total * dynamical_flattening / spin_rate * math.cos(obliquity)


def geodesic_precession_rate(gm_sun: float, semi_major_axis: float, eccentricity: float) -> float:
    """Geodesic (de Sitter) precession, equation (4), rad/s: positive (prograde)."""
    mean_motion = math.sqrt(gm_sun / semi_major_axis**3)
    return 1.5 * gm_sun / (SPEED_OF_LIGHT**2 * semi_major_axis * (1.0 - eccentricity**2)) * mean_motion


# ---------------------------------------------------------------------------
# The budget: each factor of equation (3) as its own term.
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Term:
    """One contribution to the precession rate.

    Attributes
    ----------
    name : str
        Identifier (``sun``, ``moon_inclination``, ...).
    rate : float
        Its contribution, rad/s (node-longitude sign: negative is retrograde).
    description : str
        The physics and its literature.
    kind : str
        ``model`` (computed here from the catalogue) or ``literature``
        (a published contribution this model does not compute).
    """

    name: str
    rate: float
    description: str
    kind: str = "model"


@dataclass(frozen=True)
class PrecessionBudget:
    """A body's precession rate, term by term, with its propagated uncertainty.

    Attributes
    ----------
    name : str
        The body.
    terms : tuple of Term
        The torque terms (their sum is :attr:`torque_rate`), then geodesic
        precession when the Sun is a perturber.
    torque_rate : float
        First-order tidal precession from every perturber, rad/s.
    rate : float
        torque_rate plus geodesic precession, rad/s: the model's answer.
    rate_sigma : float
        One-sigma uncertainty of ``rate`` (linear propagation), rad/s.
    contributions : dict
        Signed rate change (rad/s) for +1 sigma of each uncertain input.
    """

    name: str
    terms: tuple[Term, ...]
    torque_rate: float
    rate: float
    rate_sigma: float
    contributions: dict[str, float] = field(default_factory=dict)


def _factor_terms(orbit: PerturberOrbit, scale: float, title: str, refs: Mapping[str, str]) -> list[Term]:
    """Equation (3) for one perturber, split into its circular rate and each factor's increment."""
    base = scale * orbit.gm / orbit.semi_major_axis**3
    out = [
        Term(orbit.name, base, f"{title}: circular orbit in the reference plane at the mean distance ({refs['base']})")
    ]
    running = base
    for key, factor, label in (
        ("eccentricity", orbit.eccentricity_factor, "eccentricity of the orbit, (1 - e^2)^(-3/2)"),
        (
            "inclination",
            orbit.inclination_factor,
            "inclination of the orbit averaged over its regressing node, 1 - (3/2) sin^2 i",
        ),
        (
            "solar_perturbation",
            orbit.perturbation_factor,
            "the Sun's perturbations of the orbit (evection, variation) on the mean tidal torque",
        ),
    ):
        if factor == 1.0:
            continue
        out.append(Term(f"{orbit.name}_{key}", running * (factor - 1.0), f"{title}: {label} ({refs[key]})"))
        running *= factor
    return out


_REFS = {
    "base": "MacCullagh's torque averaged over the orbit; Goldstein, Poole & Safko 2002, sec. 5.8",
    "eccentricity": "mean of (a/r)^3 on a Kepler ellipse",
    "inclination": "Woolard 1953; Kinoshita 1977",
    "solar_perturbation": "ELP-2000/82, Chapront-Touze & Chapront 1983; Kinoshita 1977",
}


@dataclass(frozen=True)
class Inputs:
    """What equation (3) needs, SI: H, omega (rad/s), eps (rad), the orbits, the Sun's orbit or None."""

    dynamical_flattening: float
    spin_rate: float
    obliquity: float
    orbits: tuple[PerturberOrbit, ...]
    sun: PerturberOrbit | None = None


def budget_terms(inputs: Inputs) -> list[Term]:
    """Every term of the budget: each perturber's circular rate and factors, then geodesic precession."""
    check_obliquity(inputs.obliquity)
    if inputs.spin_rate == 0:
        raise InputError("rotation_rate", 0.0, "a non-zero spin rate")
    scale = -1.5 * inputs.dynamical_flattening / inputs.spin_rate * math.cos(inputs.obliquity)
    terms: list[Term] = []
    for o in inputs.orbits:
        terms += _factor_terms(o, scale, o.name.capitalize(), _REFS)
    if inputs.sun is not None:
        sun = inputs.sun
        terms.append(
            Term(
                "geodesic",
                geodesic_precession_rate(sun.gm, sun.semi_major_axis, sun.eccentricity),
                "geodesic (de Sitter) precession in the Sun's field, prograde (de Sitter 1916; Soffel 1989; "
                "Capitaine et al. 2003)",
            )
        )
    return terms


def precession_budget(
    name: str,
    values: Mapping[str, float],
    prepare: Callable[[Mapping[str, float]], Inputs],
    sigmas: Mapping[str, float] | None = None,
) -> PrecessionBudget:
    """The precession budget of one body, with linear propagation of uncertainties.

    Parameters
    ----------
    name : str
        The body.
    values : mapping
        Every scalar input by name (SI), e.g. ``dynamical_flattening``,
        ``rotation_rate``, ``obliquity``, ``moon.gm``.
    prepare : callable
        ``values -> Inputs``: the model's inputs built from the named values
        (so that each named value can be perturbed by its uncertainty).
    sigmas : mapping, optional
        One-sigma uncertainty of each uncertain input (same names). Inputs are
        taken as independent; the rate's uncertainty is the root sum of
        squares of central differences over +-1 sigma (as the Chandler budget).

    Returns
    -------
    PrecessionBudget
    """

    def evaluate(vals):
        terms = budget_terms(prepare(vals))
        torque = sum(t.rate for t in terms if t.name != "geodesic")
        return terms, torque, sum(t.rate for t in terms)

    terms, torque, total = evaluate(values)
    contributions = {}
    for key, sigma in (sigmas or {}).items():
        if not sigma:
            continue
        up = dict(values, **{key: values[key] + sigma})
        down = dict(values, **{key: values[key] - sigma})
        delta = 0.5 * (evaluate(up)[2] - evaluate(down)[2])
        if delta != 0 and math.isfinite(delta):
            contributions[key] = delta
    sigma_total = math.sqrt(sum(v * v for v in contributions.values()))
    return PrecessionBudget(name, tuple(terms), torque, total, sigma_total, contributions)
