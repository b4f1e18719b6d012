"""Clairaut's equation for the hydrostatic flattening of a layered body (float64, SI-free).

A body in hydrostatic equilibrium, rotating slowly, has level surfaces that are
spheroids r = s (1 - (2/3) epsilon(s) P2(cos theta)). To first order in the
rotation, their flattening epsilon(s) obeys Clairaut's equation (Jeffreys 1976,
*The Earth*, ch. 4; Moritz 1990, *The Figure of the Earth*, ch. 3)

    r^2 eps'' + 6 (rho/rhobar) (r eps' + eps) - 6 eps = 0,               (C)

where rhobar(r) is the mean density inside r. With Radau's variable
eta = r eps'/eps it becomes a first-order Riccati equation,

    r d(eta)/dr = 6 - 6 (rho/rhobar)(eta + 1) - eta (eta - 1),   eta(0) = 0,   (R)

which is integrated outward here in t = ln r (there it is not stiff: near the
centre eta relaxes like r^-5 toward its regular solution), layer by layer, with
wobble's Dormand-Prince 8(5,3) (:class:`wobble.numerics.integrators.DOP853`,
Hairer, Norsett & Wanner's tableau, as SciPy's ``solve_ivp(method="DOP853")``:
the two agree to 1e-14 on PREM; wobble's spares ``wobble modes`` the import of
``scipy.integrate``, a third of its run time). The surface closes
the problem: eta(a) = 5 q/(2 eps(a)) - 2 with q = Omega^2 a^3/(G M), so

    eps(a) = 5 q / (2 (eta(a) + 2)),   eps(r) = eps(a) exp(-int_r^a eta dr'/r').

The moments follow from summing homogeneous spheroidal shells,
C - A = (8 pi/15) int rho d(r^5 eps), evaluated with the same integration.

The density is a piecewise polynomial in x = r/scale (the form of PREM,
Dziewonski & Anderson 1981, Table 1): layer i spans edges[i] <= r <= edges[i+1]
with rho = sum_j coeffs[i, j] x^j. Lengths here are in units of the outer
radius and densities in units of the body's mean density: the kernel is
dimensionless; :mod:`wobble.models.hydrostatic` supplies the SI.
"""

from __future__ import annotations

import math

import numpy as np

from wobble.numerics.integrators import DOP853

__all__ = [
    "RTOL",
    "layer_integrals",
    "radau_profile",
    "radau_darwin_eta",
    "darwin_radau_moment",
]

#: Relative tolerance of the Radau integration (the closed-form tests ask 1e-10).
RTOL = 1e-12
_ATOL = 1e-15
#: Start of the integration, relative to the first layer's top: the error of
#: starting at eta = 0 there decays like (r/r0)^-5 and is invisible by 10 r0.
_START = 1e-7


def _powers(coeffs: np.ndarray, scale: float) -> np.ndarray:
    """Coefficients of rho in powers of r (not r/scale): c_j / scale^j."""
    j = np.arange(coeffs.shape[1])
    return coeffs / scale**j


def layer_integrals(edges: np.ndarray, coeffs: np.ndarray, scale: float, n: int) -> np.ndarray:
    """int rho r^n dr over each layer, exactly (polynomials).

    Parameters
    ----------
    edges : (L + 1,) array
        Layer boundaries, increasing, edges[0] = 0.
    coeffs : (L, K) array
        Density polynomial of each layer in powers of r/scale.
    scale : float
        The polynomials' normalising radius.
    n : int
        Power of r (2: mass / 4 pi; 4: spherical moment / (8 pi/3)).
    """
    c = _powers(coeffs, scale)
    p = np.arange(c.shape[1]) + n + 1
    hi = edges[1:, None] ** p
    lo = edges[:-1, None] ** p
    return np.sum(c * (hi - lo) / p, axis=1)


def _horner(coeffs: tuple, x: float) -> float:
    """sum coeffs[i] x^(n-1-i) (highest power first) in plain floats: the right-hand
    side is called thousands of times on scalars, where np.polyval costs ten times more."""
    out = 0.0
    for c in coeffs:
        out = out * x + c
    return out


def _rhs_factory(edges, coeffs, scale, layer, moment_unit=1.0):
    c_arr = _powers(coeffs, scale)[layer][::-1]  # highest power first
    lo = float(edges[layer])
    below = float(np.sum(layer_integrals(edges[: layer + 1], coeffs[:layer], scale, 2))) if layer else 0.0
    k = np.arange(c_arr.size)[::-1]
    c = tuple(map(float, c_arr))
    # m(r) - m(lo) = sum c_j (r^{j+3} - lo^{j+3})/(j+3): a polynomial in r.
    mass_poly = tuple(map(float, c_arr / (k + 3.0))) + (0.0, 0.0, 0.0)
    mass_lo = _horner(mass_poly, lo)
    if lo == 0.0:
        mean_poly = tuple(map(float, 3.0 * c_arr / (k + 3.0)))  # rhobar = 3 m/r^3, a polynomial here

        def ratio(r, rho):
            return rho / _horner(mean_poly, r)

    else:

        def ratio(r, rho):
            m = below + _horner(mass_poly, r) - mass_lo
            return rho * r**3 / (3.0 * m)

    def rhs(t, y):
        r = math.exp(t)
        eta, log_eps = float(y[0]) - 1.0, float(y[1])
        rho = _horner(c, r)
        rr = ratio(r, rho)
        deta = 6.0 - 6.0 * rr * (eta + 1.0) - eta * (eta - 1.0)
        # d(ln eps)/dt = eta; the moment integrand rho r^5 e^L (5 + eta) dt, in the layer's own unit.
        dmom = rho * r**5 * math.exp(log_eps) * (5.0 + eta) / moment_unit
        return [deta, eta, dmom]

    return rhs


def radau_profile(edges, coeffs, scale, sample_radii=(), rtol: float = RTOL):
    """Integrate Radau's equation (R) outward through every layer.

    Parameters
    ----------
    edges, coeffs, scale
        The piecewise-polynomial density (dimensionless units: outer radius 1,
        any density unit).
    sample_radii : array_like
        Radii (in (0, edges[-1]]) where eta and L are wanted.
    rtol : float
        Relative tolerance (default :data:`RTOL`; error propagation uses looser ones).

    Returns
    -------
    dict
        ``eta_edges``, ``log_edges`` (L = int_0^r eta dr'/r', up to a constant
        common to all radii), ``moment_edges`` (cumulative
        int rho r^4 e^L (5 + eta) dr, so that C - A = (8 pi/15) eps(a) e^{-L(a)}
        times its differences), and ``eta``, ``log`` at ``sample_radii``.
    """
    edges = np.asarray(edges, dtype=float)
    coeffs = np.asarray(coeffs, dtype=float)
    samples = np.asarray(sample_radii, dtype=float)
    n_layers = coeffs.shape[0]
    eta_e = np.zeros(n_layers + 1)
    log_e = np.zeros(n_layers + 1)
    mom_e = np.zeros(n_layers + 1)
    eta_s = np.full(samples.shape, np.nan)
    log_s = np.full(samples.shape, np.nan)
    # State (eta + 1, L, moment): eta stays 0 through a uniform layer, where a relative scale means
    # nothing (the first step chosen from it underflows at the next interface); eta + 1 is O(1),
    # and eps feels the absolute error of eta.
    y = np.array([[1.0, 0.0, 0.0]])
    for i in range(n_layers):
        lo = edges[i] if i else edges[1] * _START
        hi = edges[i + 1]
        inside = (samples > lo) & (samples <= hi) if i else (samples <= hi)
        pts = np.log(np.maximum(samples[inside], lo))
        # The moment integral restarts at 0 in each layer, in units of the layer's own size
        # max|rho| hi^5 e^L(lo), so that the relative tolerance holds for every layer's share: one
        # running integral under the absolute floor _ATOL loses a small core's moment (~ b^5).
        rho_size = float(np.max(np.abs(_powers(coeffs, scale)[i] * hi ** np.arange(coeffs.shape[1]))))
        unit = (rho_size if rho_size > 0 else 1.0) * hi**5 * math.exp(y[0, 1])
        rhs = _rhs_factory(edges, coeffs, scale, i, unit)
        y[0, 2] = 0.0
        solver = DOP853(
            lambda t, yy, idx, rhs=rhs: np.array([rhs(float(t[0]), yy[0])]), math.log(lo), y, rtol=rtol, atol=_ATOL
        )
        order = np.argsort(pts)
        out = solver.advance(np.concatenate([pts[order], [math.log(hi)]]))
        y = out[-1].copy()
        eta_e[i + 1], log_e[i + 1] = y[0, 0] - 1.0, y[0, 1]
        mom_e[i + 1] = mom_e[i] + y[0, 2] * unit
        if pts.size:
            idx = np.flatnonzero(inside)[order]
            eta_s[idx] = out[:-1, 0, 0] - 1.0
            log_s[idx] = out[:-1, 0, 1]
    return {"eta_edges": eta_e, "log_edges": log_e, "moment_edges": mom_e, "eta": eta_s, "log": log_s}


def radau_darwin_eta(moment_factor: float) -> float:
    """eta(a) from C/(M a^2) by the Radau-Darwin approximation.

    C/(M a^2) = (2/3) (1 - (2/5) sqrt(1 + eta(a)))  (Jeffreys 1976, sec. 4.04;
    exact for a homogeneous body, eta = 0, C/(Ma^2) = 2/5).
    """
    root = 2.5 * (1.0 - 1.5 * moment_factor)
    return root * root - 1.0


def darwin_radau_moment(eta_surface: float) -> float:
    """C/(M a^2) from eta(a), the inverse of :func:`radau_darwin_eta`."""
    return (2.0 / 3.0) * (1.0 - 0.4 * math.sqrt(1.0 + eta_surface))
