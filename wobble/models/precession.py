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

A satellite close to its planet (Phobos and Deimos) is not a perturber of
that kind: the planet's J2 turns its orbit's node in years about the local
Laplace plane, which lies between the equator and the orbit plane at the tilt
phi from the equator given by

    tan 2 phi = sin 2 eps / (cos 2 eps + 2 (r_L/a)^5),                      (5)

r_L^5 = J2 R^2 a_p^3 (1 - e_p^2)^(3/2) M/M_sun the Laplace radius (Tremaine,
Touma & Namouni 2009, AJ 137, 3706; the factor 2 makes (5) the balance of the
planet's and the Sun's torques on the orbit). Averaged over its node the
satellite is a ring in that plane, and the plane precesses with the equator.
The Sun torques the ring as it torques the bulge, and the planet and its
rings precess as one: with Q = G m <r^2> P2(cos i)/2 each ring's C - A
(<r^2> = a^2 (1 + 3 e^2/2) on a Kepler ellipse, i its inclination to the
Laplace plane) and L = G m a^2 n sqrt(1 - e^2) cos i its orbital angular momentum
averaged over the node,

    dpsi/dt = (3) x (1 + sum Q sin 2(eps - phi) / (G (C - A) sin 2 eps))
                   / (1 + sum L sin(eps - phi) / (G C omega sin eps)).      (6)

For phi = 0 this is the precession constant (3 n^2 / 2 omega) (J2 + q) /
(lambda + l) of a planet with close satellites (Tremaine 1991, Icarus 89, 85;
Ward & Hamilton 2004, AJ 128, 2501), q = sum (m/M)(a/R)^2/2 and
l = sum (m/M)(a/R)^2 (n/omega); by (5), sin 2(eps - phi)/sin 2 eps = 2 rho/D,
rho = (r_L/a)^5, D = sqrt(1 + 4 rho cos 2 eps + 4 rho^2). The factor multiplies every
tidal perturber's rate (each torques the rings as it torques the bulge), while
the Laplace planes are the Sun's: a planet with a large moon as well as close
satellites would need that moon in (5) too (Mars has none).

A planet k on its own heliocentric orbit torques the body's bulge as the Sun
does, with G M_k <1/d^3> in place of G M/(a^3 (1 - e^2)^(3/2)) in (3), d the
distance between the two. For circular orbits in one plane, radii r (the
body's) and a_k, averaged over both (mean motions not commensurate), every
relative direction in the plane is equally likely, so the averaged tidal
tensor is again symmetric about the orbit normal and (3) holds with

    <1/d^3> = (1/2pi) int (r^2 + a_k^2 - 2 r a_k cos theta)^(-3/2) dtheta
            = 2 E(m) / (pi (1 - alpha)^2 (1 + alpha) b^3),                  (7)

b = max(r, a_k), alpha = min(r, a_k)/b, m = 4 alpha/(1 + alpha)^2 and E the
complete elliptic integral of the second kind (parameter m): half the Laplace
coefficient b_{3/2}^(0)(alpha)/b^3 (Murray & Dermott 1999, sec. 6.4). The
planets torque ring satellites as they torque the bulge, so (6)'s factor
multiplies their terms too. For Earth the planets' sum is 0.0327"/cy against
the 0.031367"/cy of Williams (1994) that IAU 2006 adopts; eccentric, inclined
orbits move it by a few per cent (docs/precession.md, section 2). Orbits close
together (alpha near 1) are left to the caller to refuse: there the planets'
own eccentricities and resonances matter, and (7) grows without bound.

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
    "ring_moment",
    "ring_angular_momentum",
    "laplace_radius",
    "laplace_tilt",
    "ring_factor",
    "mean_inverse_cube_distance",
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
    ring : bool
        True for a satellite whose orbit the planet's J2 holds near its
        equator (Phobos, Deimos): a ring in its Laplace plane that precesses
        with the planet, equations (5) and (6), ``inclination`` measured from
        that plane. False (default): a perturber whose torque is equation (3).
    body_semi_major_axis : float or None
        For a planet on its own heliocentric orbit (``semi_major_axis`` is then
        that orbit's): the perturbed body's heliocentric semi-major axis, m. Its
        strength is G M <1/d^3> over both circular orbits, equation (7). None
        (default): a perturber orbiting the body.
    """

    name: str
    gm: float
    semi_major_axis: float
    eccentricity: float = 0.0
    inclination: float = 0.0
    perturbation_factor: float = 1.0
    node_rate: float | None = None
    ring: bool = False
    body_semi_major_axis: float | None = None

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
        if self.ring and self.node_rate is not None:
            # Its node turns about its Laplace plane, which moves with the equator: no nodal nutation of (3)'s kind.
            raise InputError(
                f"{self.name}.node_rate",
                self.node_rate,
                "none for a ring satellite (its node turns about its Laplace plane)",
            )
        if self.is_planet:
            self._check_planet()

    @property
    def is_planet(self) -> bool:
        """True for a planet on its own heliocentric orbit (equation (7))."""
        return self.body_semi_major_axis is not None

    def _check_planet(self) -> None:
        r = self.body_semi_major_axis
        if not (math.isfinite(r) and r > 0):
            raise InputError(f"{self.name}.body_semi_major_axis", r, "the body's positive heliocentric distance")
        if self.ring:
            raise InputError(f"{self.name}.ring", True, "False for a planet (equation (7); a ring is a satellite)")
        if self.node_rate is not None:
            raise InputError(f"{self.name}.node_rate", self.node_rate, "none for a planet (equation (7))")
        extras = {
            "eccentricity": (self.eccentricity, 0.0),
            "inclination": (self.inclination, 0.0),
            "perturbation_factor": (self.perturbation_factor, 1.0),
        }
        for key, (value, flat) in extras.items():
            if value != flat:
                raise InputError(
                    f"{self.name}.{key}", value, f"{flat} for a planet (equation (7) takes circular, coplanar orbits)"
                )
        if self.semi_major_axis == r:
            raise InputError(
                f"{self.name}.semi_major_axis",
                f"{self.semi_major_axis:.6g} m, the body's own",
                "an orbit apart from the body's (equation (7) diverges as they meet)",
            )

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


def laplace_radius(j2: float, radius: float, gm: float, sun: PerturberOrbit) -> float:
    """r_L = (J2 R^2 a_p^3 (1 - e_p^2)^(3/2) G M / G M_sun)^(1/5), m: the distance inside which the planet's J2,
    and outside which the Sun, sets the plane a satellite's orbit precesses about (Tremaine, Touma & Namouni 2009).
    Works on arrays of ``j2``, ``radius`` and ``gm``."""
    return (j2 * radius**2 * sun.semi_major_axis**3 * (1.0 - sun.eccentricity**2) ** 1.5 * gm / sun.gm) ** 0.2


def laplace_tilt(semi_major_axis, r_laplace, obliquity):
    """phi of equation (5), rad: the Laplace plane's tilt from the equator towards the orbit plane (arrays work).

    0 close in, eps far out; atan2 keeps the branch that starts at 0 close in for any obliquity in [0, pi].
    """
    rho = (r_laplace / semi_major_axis) ** 5
    return 0.5 * np.arctan2(np.sin(2.0 * obliquity), np.cos(2.0 * obliquity) + 2.0 * rho)


def ring_moment(orbit: PerturberOrbit) -> float:
    """G Q = G m <r^2> P2(cos i)/2 of a ring satellite, m^5/s^2: the C - A of its orbit averaged over the orbit
    and over its node (a ring's C - A is half its moment m <r^2>; <r^2> = a^2 (1 + 3 e^2/2) on a Kepler ellipse)."""
    return 0.5 * orbit.gm * orbit.semi_major_axis**2 * (1.0 + 1.5 * orbit.eccentricity**2) * orbit.inclination_factor


def ring_angular_momentum(orbit: PerturberOrbit, gm_planet: float) -> float:
    """G L cos i = G m a^2 n sqrt(1 - e^2) cos i of a ring satellite, m^5/s^3, n from Kepler's third law: its
    orbital angular momentum averaged over the node, along the Laplace plane's normal (negative for a
    retrograde orbit), which precesses with the spin's."""
    n = np.sqrt((gm_planet + orbit.gm) / orbit.semi_major_axis**3)
    return (
        orbit.gm * orbit.semi_major_axis**2 * n * math.sqrt(1.0 - orbit.eccentricity**2) * math.cos(orbit.inclination)
    )


def ring_factor(
    rings: Sequence[PerturberOrbit],
    flattening,
    polar_moment_factor,
    gm,
    radius,
    spin_rate,
    obliquity,
    sun: PerturberOrbit,
):
    """The factor of equation (6) by which ring satellites multiply the tidal rate (1 without rings; arrays work).

    ``flattening`` H and ``polar_moment_factor`` C/(M R^2) give G (C - A) = H (C/(M R^2)) G M R^2 and G C omega;
    J2 = H C/(M R^2) sets the Laplace radius; ``sun`` is the planet's orbit about the Sun.
    """
    moment = polar_moment_factor * gm * radius**2  # G C
    r_laplace = laplace_radius(flattening * polar_moment_factor, radius, gm, sun)
    two_eps = 2.0 * obliquity
    torque, momentum = 0.0, 0.0
    for ring in rings:
        rho = (r_laplace / ring.semi_major_axis) ** 5
        # sin 2(eps - phi) / sin 2 eps = 2 rho / D by equation (5): no 0/0 at eps = 0 or 90 deg.
        torque = torque + ring_moment(ring) * 2.0 * rho / np.sqrt(1.0 + 4.0 * rho * np.cos(two_eps) + 4.0 * rho**2)
        eps_phi = obliquity - laplace_tilt(ring.semi_major_axis, r_laplace, obliquity)
        sin_eps = np.sin(obliquity)
        # sin(eps - phi)/sin eps, whose limit at eps = 0 is 2 rho/(1 + 2 rho).
        share = np.where(
            np.abs(sin_eps) > 1e-12, np.sin(eps_phi) / np.where(sin_eps == 0, 1.0, sin_eps), 2 * rho / (1 + 2 * rho)
        )
        momentum = momentum + ring_angular_momentum(ring, gm) * share
    return (1.0 + torque / (flattening * moment)) / (1.0 + momentum / (moment * spin_rate))


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


def mean_inverse_cube_distance(r, a):
    """<1/d^3> between two circular, coplanar orbits of radii ``r`` and ``a``, equation (7), m^-3 (arrays work).

    Averaged over both orbits: (1/2pi) int (r^2 + a^2 - 2 r a cos theta)^(-3/2) dtheta
    = 2 E(m)/(pi (1 - alpha)^2 (1 + alpha) b^3) with b = max(r, a), alpha = min(r, a)/b,
    m = 4 alpha/(1 + alpha)^2; 1/b^3 when alpha -> 0, unbounded as alpha -> 1 (the orbits meet).
    """
    # SciPy's E(m), not wobble.numerics.elliptic.ellipe: that one's double-double AGM keeps half an ulp down to
    # 1 - m = 1e-308 (the free body's separatrix) at 290 us a call; here 1 - m = ((1 - alpha)/(1 + alpha))^2 stays
    # above 2.8e-3 (the callers keep orbits 10 % apart), where SciPy's is within an ulp of mpmath in 0.2 us, and a
    # budget's uncertainty propagation evaluates (7) some 300 times.
    from scipy.special import ellipe

    r = np.asarray(r, dtype=float)
    a = np.asarray(a, dtype=float)
    b = np.maximum(r, a)
    alpha = np.minimum(r, a) / b
    if np.any(alpha >= 1.0):
        same = r[alpha >= 1.0] if r.ndim else r
        raise InputError(
            "semi_major_axis", f"{np.ravel(same)[0]:.6g} m for both orbits", "two orbits apart (equation (7) diverges)"
        )
    m = 4.0 * alpha / (1.0 + alpha) ** 2
    out = 2.0 * ellipe(m) / (math.pi * (1.0 - alpha) ** 2 * (1.0 + alpha) * b**3)
    return out if out.ndim else float(out)


def torque_strength(orbit: PerturberOrbit) -> float:
    """k = G M <(1/r)^3 P2> / (-1/2) of one perturber: G M/a^3 times its factors, s^-2 (a planet: G M <1/d^3>,
    equation (7))."""
    if orbit.is_planet:
        return orbit.gm * mean_inverse_cube_distance(orbit.body_semi_major_axis, orbit.semi_major_axis)
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
    rings = [o.name for o in orbits if o.ring]
    if rings:
        raise InputError("orbits", ", ".join(rings), "tidal perturbers (a ring satellite needs the planet's figure)")
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


def _planet_term(orbit: PerturberOrbit, scale: float) -> Term:
    """Equation (3) with a planet's G M <1/d^3> of equation (7)."""
    return Term(
        orbit.name,
        scale * torque_strength(orbit),
        f"{orbit.name.capitalize()}: its direct torque on the bulge, circular orbits in one plane averaged over "
        "both (Laplace coefficient b_3/2^(0); Murray & Dermott 1999, sec. 6.4; IAU 2006's planetary term: Williams "
        "1994)",
    )


def _ring_terms(inputs: Inputs, rings: list[PerturberOrbit], tidal: float) -> list[Term]:
    """Equation (6), one term per ring: the rate with the rings up to it less the rate without it."""
    # Named as planet files name them.
    for attr, key in (("polar_moment_factor", "polar_moment_factor"), ("gm", "gm"), ("radius", "equatorial_radius")):
        if getattr(inputs, attr) is None:
            raise InputError(
                key, "missing", f"the planet's {key} for its ring satellites ({', '.join(o.name for o in rings)})"
            )
    if inputs.sun is None:
        raise InputError("sun", None, "the planet's orbit about the Sun (it sets the rings' Laplace planes)")
    figure = (inputs.dynamical_flattening, inputs.polar_moment_factor, inputs.gm, inputs.radius, inputs.spin_rate)
    rings = sorted(rings, key=lambda o: o.semi_major_axis)  # inside out: Phobos, then Deimos
    out, before = [], tidal
    for k, ring in enumerate(rings):
        after = tidal * float(ring_factor(rings[: k + 1], *figure, inputs.obliquity, inputs.sun))
        out.append(
            Term(
                ring.name,
                after - before,
                f"{ring.name.capitalize()}: its orbit, held by the planet's J2 near the equator, a ring the Sun "
                "(and the planets) torque with the bulge (Tremaine 1991; Ward & Hamilton 2004; Laplace plane: "
                "Tremaine, Touma & Namouni 2009)",
            )
        )
        before = after
    return out


@dataclass(frozen=True)
class Inputs:
    """What equations (3) and (6) need, SI: H, omega (rad/s), eps (rad), the orbits, the Sun's orbit or None;
    with ring satellites also the planet's C/(M R^2), G M (m^3/s^2) and the radius R (m) of both."""

    dynamical_flattening: float
    spin_rate: float
    obliquity: float
    orbits: tuple[PerturberOrbit, ...]
    sun: PerturberOrbit | None = None
    polar_moment_factor: float | None = None
    gm: float | None = None
    radius: float | None = None


def budget_terms(inputs: Inputs) -> list[Term]:
    """Every term of the budget: each perturber's circular rate and factors, then geodesic precession."""
    check_obliquity(inputs.obliquity)
    if inputs.spin_rate == 0:
        raise InputError("rotation_rate", 0.0, "a non-zero spin rate")
    scale = -1.5 * inputs.dynamical_flattening / inputs.spin_rate * math.cos(inputs.obliquity)
    terms: list[Term] = []
    for o in inputs.orbits:
        if o.is_planet:
            terms.append(_planet_term(o, scale))
        elif not o.ring:
            terms += _factor_terms(o, scale, o.name.capitalize(), _REFS)
    rings = [o for o in inputs.orbits if o.ring]
    if rings:
        terms += _ring_terms(inputs, rings, sum(t.rate for t in terms))
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
        try:
            delta = 0.5 * (evaluate(up)[2] - evaluate(down)[2])
        except InputError:
            # The value is physical (evaluated above) but value -+ sigma is not: an uncertainty as large as a
            # positive value (one left in AU after the value was given in metres), named as such.
            raise InputError(
                key,
                f"{values[key]:.6g} +/- {sigma:.6g} (SI)",
                "an uncertainty that keeps value - sigma and value + sigma physical: the +-1 sigma propagation "
                "evaluates the model there",
            ) from None
        if delta != 0 and math.isfinite(delta):
            contributions[key] = delta
    sigma_total = math.sqrt(sum(v * v for v in contributions.values()))
    return PrecessionBudget(name, tuple(terms), torque, total, sigma_total, contributions)
