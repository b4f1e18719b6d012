"""The hydrostatic figure of a layered planet: Clairaut's equation from a density profile (SI).

Given a radial density profile rho(r) (piecewise polynomial, the form of PREM:
Dziewonski & Anderson 1981) and a spin rate Omega, :func:`hydrostatic_figure`
solves Clairaut's equation (Jeffreys 1976, *The Earth*, ch. 4; the kernel is
:mod:`wobble.numerics.clairaut`) for the flattening eps(r) of the level
surfaces and returns, to first order in the rotation,

* the surface flattening eps(a) and q = Omega^2 a^3/(G M);
* J2 = (C - A)/(M a^2) with C - A = (8 pi/15) int rho d(r^5 eps), and
  Clairaut's theorem J2 = (2 eps(a) - q)/3 as a check of the integration;
* H = (C - A)/C and C/(M a^2) = (8 pi/3) int rho r^4 dr / (M a^2);
* the fluid core's dynamical ellipticity e_f = (C_f - A_f)/A_f, the same
  integral over the liquid shell only (Mathews, Buffett, Herring & Shapiro 1991);
* the Radau-Darwin flattening from C/(M a^2), an independent approximation.

Everything is SI (m, kg, kg/m^3, rad/s); moments are about the centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wobble.errors import InputError
from wobble.numerics import clairaut
from wobble.numerics.integrators import DOP853

__all__ = [
    "DensityProfile",
    "HydrostaticFigure",
    "hydrostatic_figure",
    "check_profile",
    "core_under_linear_mantle",
    "linear_mantle_coefficients",
    "linear_mantle_core_density_range",
    "core_flattening_under_linear_mantle",
    "core_flattening_unchecked",
]

_SAMPLES_PER_LAYER = 24
# A density jump outward smaller than this (relative) is rounding, not inversion.
_JUMP_TOLERANCE = 1e-9


@dataclass(frozen=True)
class DensityProfile:
    """A spherically symmetric density model, piecewise polynomial in r/scale (SI).

    Attributes
    ----------
    name : str
        Identifier (``"prem"``).
    edges : tuple of float
        Layer boundaries in m, increasing, starting at 0; the last is the radius a.
    coeffs : tuple of tuple of float
        Layer i: density in kg/m^3 = sum_j coeffs[i][j] (r/scale)^j.
    scale : float
        Normalising radius of the polynomials, m.
    fluid_core : tuple of float or None
        (inner, outer) radius of the liquid core, m (inner 0 without a solid inner core).
    """

    name: str
    edges: tuple[float, ...]
    coeffs: tuple[tuple[float, ...], ...]
    scale: float
    fluid_core: tuple[float, float] | None = None

    @property
    def radius(self) -> float:
        """Outer radius a, m."""
        return self.edges[-1]

    def arrays(self):
        """(edges, coeffs) as float64 arrays, coefficients padded to one degree."""
        k = max(len(c) for c in self.coeffs)
        coeffs = np.zeros((len(self.coeffs), k))
        for i, c in enumerate(self.coeffs):
            coeffs[i, : len(c)] = c
        return np.asarray(self.edges, dtype=float), coeffs

    def density(self, r) -> np.ndarray:
        """rho(r) in kg/m^3 (at an interface, the layer above)."""
        edges, coeffs = self.arrays()
        r = np.asarray(r, dtype=float)
        layer = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, len(coeffs) - 1)
        x = r / self.scale
        powers = x[..., None] ** np.arange(coeffs.shape[1])
        return np.sum(coeffs[layer] * powers, axis=-1)

    def mass(self) -> float:
        """M = 4 pi int rho r^2 dr, kg."""
        edges, coeffs = self.arrays()
        return 4.0 * math.pi * float(np.sum(clairaut.layer_integrals(edges, coeffs, self.scale, 2)))

    def moment(self, lo: float = 0.0, hi: float | None = None) -> float:
        """Spherical moment (8 pi/3) int rho r^4 dr between two interfaces, kg m^2."""
        edges, coeffs = self.arrays()
        hi = self.radius if hi is None else hi
        per_layer = clairaut.layer_integrals(edges, coeffs, self.scale, 4)
        keep = (edges[:-1] >= lo * (1 - 1e-12)) & (edges[1:] <= hi * (1 + 1e-12))
        return 8.0 * math.pi / 3.0 * float(np.sum(per_layer[keep]))


def check_profile(profile: DensityProfile) -> None:
    """Refuse a profile that cannot be in hydrostatic equilibrium, naming what is wrong.

    Raises
    ------
    wobble.errors.InputError
        Radii not increasing from 0; a density that is not positive; a density
        that increases outward across an interface or anywhere inside the liquid
        core (a heavier fluid above a lighter one is not in equilibrium); a
        liquid core outside the body or not on layer boundaries.
    """
    edges = np.asarray(profile.edges, dtype=float)
    if edges.ndim != 1 or edges.size < 2 or edges[0] != 0.0 or not np.all(np.diff(edges) > 0):
        tops = ", ".join(f"{r / 1e3:.6g}" for r in np.ravel(edges)[1:])  # the file's tops; the centre's 0 is implied
        raise InputError("layer_top_radius", f"({tops}) km", "layer radii increasing from the centre")
    if len(profile.coeffs) != edges.size - 1:
        raise InputError(
            "density_coefficients", f"{len(profile.coeffs)} layers", f"one polynomial per layer ({edges.size - 1})"
        )
    lo_side, hi_side = _layer_end_densities(profile)
    inner = np.concatenate([np.linspace(a, b, _SAMPLES_PER_LAYER) for a, b in zip(edges[:-1], edges[1:])])
    rho = np.concatenate([lo_side, hi_side, profile.density(inner)])
    if not np.all(rho > 0):
        raise InputError("density", f"{np.min(rho):.6g} kg/m3", "a positive density everywhere")
    jumps = lo_side[1:] - hi_side[:-1]
    worst = int(np.argmax(jumps)) if jumps.size else 0
    if jumps.size and jumps[worst] > _JUMP_TOLERANCE * hi_side[worst]:
        raise InputError(
            "density",
            f"{hi_side[worst]:.6g} -> {lo_side[worst + 1]:.6g} kg/m3 outward at r = {edges[worst + 1] / 1e3:.6g} km",
            "a density that does not increase outward across an interface (hydrostatic equilibrium)",
        )
    if profile.fluid_core is not None:
        _check_core(profile, edges)


def _layer_end_densities(profile):
    edges, coeffs = profile.arrays()
    x_lo = edges[:-1] / profile.scale
    x_hi = edges[1:] / profile.scale
    j = np.arange(coeffs.shape[1])
    return np.sum(coeffs * x_lo[:, None] ** j, axis=1), np.sum(coeffs * x_hi[:, None] ** j, axis=1)


def _check_core(profile, edges):
    inner, outer = profile.fluid_core
    if not inner >= 0.0:
        raise InputError(
            "fluid_core_inner_radius", f"{inner / 1e3:.6g} km", "a radius of at least 0 (0: no solid inner core)"
        )
    if not inner < outer:
        raise InputError(
            "fluid_core_outer_radius", f"{outer / 1e3:.6g} km", f"larger than the inner radius {inner / 1e3:.6g} km"
        )
    if outer > profile.radius * (1 + 1e-12):
        raise InputError(
            "fluid_core_outer_radius",
            f"{outer / 1e3:.6g} km",
            f"a core inside the planet (radius {profile.radius / 1e3:.6g} km)",
        )
    for name, r in (("fluid_core_inner_radius", inner), ("fluid_core_outer_radius", outer)):
        if not np.any(np.isclose(edges, r, rtol=1e-12, atol=0.0)):
            raise InputError(name, f"{r / 1e3:.6g} km", "a layer boundary of the density profile")
    r = np.linspace(max(inner, 1e-9 * outer), outer, 400)[:-1]
    rho = profile.density(r)
    if np.any(np.diff(rho) > _JUMP_TOLERANCE * rho[:-1]):
        raise InputError(
            "density",
            "increasing outward inside the liquid core",
            "a liquid core whose density does not increase outward",
        )


@dataclass(frozen=True)
class HydrostaticFigure:
    """The first-order hydrostatic figure of a layered body (SI).

    Attributes
    ----------
    radius : numpy.ndarray
        Sample radii, m (layer boundaries included).
    flattening : numpy.ndarray
        eps(r) of the level surface through each radius.
    eta : numpy.ndarray
        Radau's eta = r eps'/eps at each radius.
    surface_flattening : float
        eps(a).
    q : float
        Omega^2 a^3/(G M).
    mass : float
        M of the profile, kg.
    j2 : float
        (C - A)/(M a^2) from the shell integral.
    j2_clairaut : float
        (2 eps(a) - q)/3 (Clairaut's theorem): equal to ``j2`` up to the integration error.
    dynamical_flattening : float
        H = (C - A)/C.
    moment_factor : float
        C/(M a^2) (spherical moment).
    core_dynamical_ellipticity : float or None
        e_f = (C_f - A_f)/A_f of the liquid core.
    core_moment : float or None
        A_f (spherical moment of the liquid shell), kg m^2.
    radau_darwin_flattening : float
        eps(a) from C/(M a^2) by the Radau-Darwin approximation.
    """

    radius: np.ndarray
    flattening: np.ndarray
    eta: np.ndarray
    surface_flattening: float
    q: float
    mass: float
    j2: float
    j2_clairaut: float
    dynamical_flattening: float
    moment_factor: float
    core_dynamical_ellipticity: float | None
    core_moment: float | None
    radau_darwin_flattening: float

    def __post_init__(self):
        # A frozen result hands out its own arrays: figure.flattening[:] = 0 edited the figure
        # (its to_dataset then wrote zeros). Read-only, as the budgets' and modes' Quantities.
        for name in ("radius", "flattening", "eta"):
            getattr(self, name).flags.writeable = False


def core_under_linear_mantle(
    name: str, mass: float, polar_moment: float, radius: float, core_radius: float, core_density: float
) -> DensityProfile:
    """A uniform liquid core under a mantle whose density falls linearly with radius (SI).

    The mantle's rho = a0 + a1 r/R has the two coefficients that give the body
    its mass M and polar moment C (spherical, first order):
    4 pi int rho r^2 dr = M - M_core and (8 pi/3) int rho r^4 dr = C - C_core
    over core_radius < r < R, a 2 x 2 linear system. This is how
    ``data/profiles/mars_layered.toml`` was built; rebuilding it from a planet's
    catalogue lets the uncertainties of M, C and the core reach the hydrostatic e_f.
    A spherical profile's moment is strictly the mean one, I = C - (2/3) J2 M R0^2:
    fitted to I, Mars' core e_f is 0.26 % smaller, inside first-order Clairaut theory's
    own relative error (the flattening, 0.5 %), so callers pass C (docs/modes.md).

    Raises
    ------
    wobble.errors.InputError
        A core outside the body; the mantle comes out non-positive or denser
        than the core (checked by :func:`check_profile`).
    """
    if not 0 < core_radius < radius:
        raise InputError(
            "fluid_core_radius",
            f"{core_radius / 1e3:.6g} km",
            f"a core inside the planet (radius {radius / 1e3:.6g} km)",
        )
    m_core = 4.0 / 3.0 * math.pi * core_density * core_radius**3
    c_core = 8.0 / 15.0 * math.pi * core_density * core_radius**5

    def shell(n, j):  # int (r/R)^j r^n dr over the mantle
        return (radius ** (n + j + 1) - core_radius ** (n + j + 1)) / ((n + j + 1) * radius**j)

    a11, a12 = 4.0 * math.pi * shell(2, 0), 4.0 * math.pi * shell(2, 1)
    a21, a22 = 8.0 * math.pi / 3.0 * shell(4, 0), 8.0 * math.pi / 3.0 * shell(4, 1)
    b1, b2 = mass - m_core, polar_moment - c_core
    det = a11 * a22 - a12 * a21
    a0 = (b1 * a22 - a12 * b2) / det
    a1 = (a11 * b2 - a21 * b1) / det
    profile = DensityProfile(
        name,
        (0.0, core_radius, radius),
        ((float(core_density),), (float(a0), float(a1))),
        radius,
        fluid_core=(0.0, core_radius),
    )
    check_profile(profile)
    return profile


def hydrostatic_figure(
    profile: DensityProfile,
    spin_rate: float,
    gravitational_constant: float,
    *,
    samples: int = _SAMPLES_PER_LAYER,
    rtol: float = clairaut.RTOL,
) -> HydrostaticFigure:
    """Solve Clairaut's equation for ``profile`` spinning at ``spin_rate`` (rad/s).

    Parameters
    ----------
    profile : DensityProfile
        Checked with :func:`check_profile` first.
    spin_rate : float
        Omega, rad/s (its sign does not matter: the figure depends on Omega^2).
    gravitational_constant : float
        G, m^3 kg^-1 s^-2.
    samples : int
        Radii sampled per layer for eps(r).
    rtol : float
        Relative tolerance of the integration.
    """
    check_profile(profile)
    if not (math.isfinite(spin_rate) and spin_rate != 0):
        raise InputError("spin", spin_rate, "a non-zero, finite spin rate")
    edges, coeffs = profile.arrays()
    a = profile.radius
    mass = profile.mass()
    rho_mean = mass / (4.0 / 3.0 * math.pi * a**3)
    # Dimensionless: radii in units of a, density in units of the mean density.
    e_hat = edges / a
    c_hat = coeffs / rho_mean
    s_hat = profile.scale / a
    grid = np.unique(np.concatenate([np.linspace(lo, hi, samples) for lo, hi in zip(e_hat[:-1], e_hat[1:])]))[1:]
    sol = clairaut.radau_profile(e_hat, c_hat, s_hat, grid, rtol=rtol)
    q = spin_rate**2 * a**3 / (gravitational_constant * mass)
    eta_a = float(sol["eta_edges"][-1])
    eps_a = 2.5 * q / (eta_a + 2.0)
    if not (q < 1.0 and eps_a < 1.0):
        # Past break-up the equator is unbound, and a flattening of 1 or more has no pole: at 1e-2 rad/s
        # PREM came out with a flattening of 62.7 and no word that first-order theory had long stopped.
        period_h = 2.0 * math.pi / math.sqrt(gravitational_constant * mass / a**3) / 3600.0
        raise InputError(
            "spin",
            f"{spin_rate:.6g} rad/s",
            f"a spin well below break-up, Omega^2 a^3/(G M) < 1 (here {q:.3g}; first-order Clairaut theory "
            f"wants it small, and gives a flattening of {eps_a:.3g}): a rotation period above {period_h:.3g} h",
        )
    log_a = float(sol["log_edges"][-1])
    eps = eps_a * np.exp(sol["log"] - log_a)
    # C - A = (8 pi/15) rho_mean a^5 eps(a) e^{-L(a)} int rho^ r^4 e^L (5 + eta) dr^
    shell = eps_a * math.exp(-log_a) * 8.0 * math.pi / 15.0 * rho_mean * a**5
    c_minus_a = shell * float(sol["moment_edges"][-1])
    c = profile.moment()
    core_e = core_moment = None
    if profile.fluid_core is not None:
        inner, outer = profile.fluid_core
        i_lo = int(np.argmin(np.abs(edges - inner)))
        i_hi = int(np.argmin(np.abs(edges - outer)))
        core_moment = profile.moment(inner, outer)
        core_e = shell * float(sol["moment_edges"][i_hi] - sol["moment_edges"][i_lo]) / core_moment
    moment_factor = c / (mass * a**2)
    eta_rd = clairaut.radau_darwin_eta(moment_factor)
    return HydrostaticFigure(
        radius=np.concatenate([[0.0], grid * a]),
        flattening=np.concatenate([[eps[0]], eps]),
        eta=np.concatenate([[0.0], sol["eta"]]),
        surface_flattening=eps_a,
        q=q,
        mass=mass,
        j2=c_minus_a / (mass * a**2),
        j2_clairaut=(2.0 * eps_a - q) / 3.0,
        dynamical_flattening=c_minus_a / c,
        moment_factor=moment_factor,
        core_dynamical_ellipticity=core_e,
        core_moment=core_moment,
        radau_darwin_flattening=2.5 * q / (eta_rd + 2.0),
    )


# ---------------------------------------------------------------------------
# A uniform core under a linear mantle, vectorised (the inversion's hydrostatic core)
# ---------------------------------------------------------------------------


def linear_mantle_coefficients(x, y, c):
    """Mantle rho = a0 + a1 r of :func:`core_under_linear_mantle` in dimensionless form (arrays).

    Units: radius R = 1, density in units of the body's mean density 3M/(4 pi R^3).
    ``x`` = core radius/R, ``y`` = core density/mean density, ``c`` = C/(M R^2). The
    body's mass and moment fix (a0, a1): int_x^1 rho r^2 dr = (1 - y x^3)/3 and
    int_x^1 rho r^4 dr = c/2 - y x^5/5, a 2 x 2 linear system (Cramer's rule).
    """
    x, y, c = (np.asarray(v, dtype=float) for v in (x, y, c))
    a11, a12 = (1.0 - x**3) / 3.0, (1.0 - x**4) / 4.0
    a21, a22 = (1.0 - x**5) / 5.0, (1.0 - x**6) / 6.0
    b1 = (1.0 - y * x**3) / 3.0
    b2 = 0.5 * c - y * x**5 / 5.0
    det = a11 * a22 - a12 * a21
    return (b1 * a22 - a12 * b2) / det, (a11 * b2 - a21 * b1) / det


def linear_mantle_core_density_range(x, c):
    """(y_min, y_max): the core densities (in units of the mean density) that
    :func:`check_profile` accepts for a core of radius x R under a linear mantle, C = c M R^2.

    a0 and a1 are linear in y, so each condition is a half-line in y: the mantle's
    density at the core (rho_b) and at the surface (rho_s) positive, and no denser
    than the core at the boundary, rho_b <= y (a fluid in equilibrium is not lighter
    below). Empty where y_min >= y_max.
    """
    x, c = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, c)))
    a0_0, a1_0 = linear_mantle_coefficients(x, 0.0, c)
    a0_1, a1_1 = linear_mantle_coefficients(x, 1.0, c)
    lo = np.full(x.shape, 0.0)
    hi = np.full(x.shape, np.inf)
    # rho_b = p0 + p1 y, rho_s = s0 + s1 y.
    p0, p1 = a0_0 + a1_0 * x, (a0_1 - a0_0) + (a1_1 - a1_0) * x
    s0, s1 = a0_0 + a1_0, (a0_1 - a0_0) + (a1_1 - a1_0)
    with np.errstate(divide="ignore", invalid="ignore"):
        for u0, u1 in ((p0, p1), (s0, s1), (-p0, 1.0 - p1)):  # u0 + u1 y > 0 (the last: y - rho_b >= 0)
            edge = -u0 / u1
            lo = np.where(u1 > 0, np.maximum(lo, edge), lo)
            hi = np.where(u1 < 0, np.minimum(hi, edge), hi)
            lo = np.where((u1 == 0) & (u0 <= 0), np.inf, lo)
    return lo, hi


def core_flattening_under_linear_mantle(x, y, c, *, rtol: float = 1e-12) -> np.ndarray:
    """e_f/q of a uniform liquid core under a linear mantle, for many bodies at once.

    The same figure as :func:`hydrostatic_figure` of :func:`core_under_linear_mantle`
    (Clairaut's equation, first order), vectorised over members: inside a uniform
    core Radau's eta is 0 (rho = rhobar), so the core's level surfaces share one
    flattening and e_f = eps(r_c) = eps(R) exp(-int_{r_c}^R eta dr/r) with
    eps(R) = 5 q/(2 (eta(R) + 2)); eta obeys Radau's equation through the mantle
    from eta(r_c) = 0. All members are integrated together with
    :class:`~wobble.numerics.integrators.DOP853` in u = (ln r - ln x)/(-ln x) on [0, 1].

    Parameters
    ----------
    x, y, c : array_like
        Core radius/R, core density/mean density, C/(M R^2) (dimensionless; broadcast).
    rtol : float
        Relative tolerance of the integration.

    Returns
    -------
    numpy.ndarray
        e_f/q, q = Omega^2 R^3/(G M) (e_f is linear in q at first order); NaN where the
        profile is not one :func:`check_profile` accepts
        (:func:`linear_mantle_core_density_range`) or x is not in (0, 1).
    """
    x, y, c = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, c)))
    shape = x.shape
    x, y, c = x.ravel(), y.ravel(), c.ravel()
    lo, hi = linear_mantle_core_density_range(np.clip(x, 1e-3, 1 - 1e-3), c)
    ok = (x > 0) & (x < 1) & (y >= lo * (1 - _JUMP_TOLERANCE)) & (y < hi) & np.isfinite(y) & np.isfinite(c)
    out = np.full(x.shape, np.nan)
    if not np.any(ok):
        return out.reshape(shape)
    out[ok] = core_flattening_unchecked(x[ok], y[ok], c[ok], rtol)
    return out.reshape(shape)


def core_flattening_unchecked(x, y, c, rtol):
    """e_f/q of :func:`core_flattening_under_linear_mantle` without its admissibility check.

    The Radau integration itself only needs the mass inside each radius to stay positive,
    so this also answers for profiles :func:`check_profile` refuses (a mantle denser than
    the core, just outside :func:`linear_mantle_core_density_range`): a smooth extension
    that a Chebyshev table over a box of priors can be fitted to.

    Parameters
    ----------
    x, y, c : numpy.ndarray
        1-d arrays of one length: core radius/R, core density/mean density, C/(M R^2)
        (dimensionless).
    rtol : float
        Relative tolerance of the integration.

    Returns
    -------
    numpy.ndarray
        e_f/q for each member; NaN where the mass inside some radius is not positive, or
        where the integration does not finish.
    """
    from wobble.numerics.integrators import StepLimitError

    out = np.full(np.shape(x), np.nan)
    a0, a1 = linear_mantle_coefficients(x, y, c)
    # m(r) = int_0^r rho r'^2 dr' = core + mantle from x to r.
    m_core = y * x**3 / 3.0 - a0 * x**3 / 3.0 - a1 * x**4 / 4.0
    r = x[:, None] + (1.0 - x[:, None]) * np.linspace(0.0, 1.0, 65)
    regular = np.all(m_core[:, None] + a0[:, None] * r**3 / 3.0 + a1[:, None] * r**4 / 4.0 > 0, axis=1)
    if not np.any(regular):
        return out
    x, a0, a1, m_core = x[regular], a0[regular], a1[regular], m_core[regular]
    span = -np.log(x)
    log_x = np.log(x)

    def rhs(u, state, idx):
        r = np.exp(log_x[idx] + u * span[idx])
        rho = a0[idx] + a1[idx] * r
        m = m_core[idx] + a0[idx] * r**3 / 3.0 + a1[idx] * r**4 / 4.0
        ratio = rho * r**3 / (3.0 * m)
        eta = state[:, 0]
        deta = 6.0 - 6.0 * ratio * (eta + 1.0) - eta * (eta - 1.0)
        return np.stack([deta * span[idx], eta * span[idx]], axis=-1)

    solver = DOP853(rhs, 0.0, np.zeros((x.size, 2)), rtol=rtol, atol=1e-15, max_steps=5000)
    try:
        end = solver.advance([1.0])[-1]
    except StepLimitError:  # a nearly singular member (extreme densities): no answer
        return out
    out[regular] = 2.5 * np.exp(-end[:, 1]) / (end[:, 0] + 2.0)
    return out
