"""Kepler's equation and the position on a Keplerian orbit with secular node and periapsis rates (float64, SI).

Kepler's equation ``E - e sin E = M`` (e.g. Murray & Dermott 1999, *Solar System Dynamics*,
sec. 2.4) is solved by Newton's method from Danby's starting value (Danby 1987,
*Celest. Mech.* 40, 303): ``E0 = M + 0.85 e sign(sin M)``, which converges monotonically
for every ``0 <= e < 1``, with M reduced to [-pi, pi]. Each value iterates until its own
Newton correction falls below 4 eps (absolute, |E| <= pi), so the vectorised, the scalar
and the compiled (:mod:`wobble.numerics.rigid_dop853`) solvers take the same steps.

The position of the orbiting body (Murray & Dermott 1999, eqs. 2.41 and 2.122):

    r = a (cos E - e) P + a sqrt(1 - e^2) sin E Q,     |r| = a (1 - e cos E),

with P (towards periapsis) and Q the orbit-plane unit vectors of the node longitude
Omega, the inclination i and the argument of periapsis w:

    P = (cos O cos w - sin O sin w cos i,  sin O cos w + cos O sin w cos i,  sin w sin i)
    Q = (-cos O sin w - sin O cos w cos i, -sin O sin w + cos O cos w cos i,  cos w sin i)

The elements turn secularly: ``M = M0 + n t``, ``Omega = Omega0 + Omega_dot t``,
``w = w0 + w_dot t`` (t in s from the elements' epoch). ``n`` is the rate of the mean
anomaly (the anomalistic mean motion).

An element row (the compiled kernel's layout, :mod:`wobble.numerics.torque_program`) is
``(a, e, i, Omega0, w0, M0, n, Omega_dot, w_dot)``: :data:`ELEMENTS`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ELEMENTS", "MAX_ITERATIONS", "solve_kepler", "solve_kepler_one", "position", "position_one"]

#: The element row: semi-major axis (m), eccentricity, inclination, node longitude at epoch,
#: argument of periapsis at epoch, mean anomaly at epoch (rad), mean motion, node rate,
#: periapsis rate (rad/s).
ELEMENTS = ("a", "e", "i", "node", "periapsis", "mean_anomaly", "mean_motion", "node_rate", "periapsis_rate")
#: Newton's method from Danby's start needs at most ~6 iterations below e = 0.9; the cap only
#: guards against a NaN.
MAX_ITERATIONS = 64
_TOL = 4.0 * np.finfo(float).eps
_TWO_PI = 2.0 * math.pi


def _reduce(m):
    """M reduced to [-pi, pi] (the same operations in every solver)."""
    return m - _TWO_PI * np.round(m / _TWO_PI)


def solve_kepler(mean_anomaly, e):
    """Eccentric anomaly E with ``E - e sin E = M`` (M reduced to [-pi, pi]), vectorised.

    Parameters
    ----------
    mean_anomaly : array_like
        M, rad.
    e : float or array_like
        Eccentricity in [0, 1), broadcast against M.

    Returns
    -------
    numpy.ndarray
        E in [-pi, pi], rad.
    """
    m = _reduce(np.asarray(mean_anomaly, dtype=float))
    e = np.broadcast_to(np.asarray(e, dtype=float), m.shape)
    E = m + 0.85 * e * np.sign(np.sin(m))
    active = np.ones(m.shape, dtype=bool)
    for _ in range(MAX_ITERATIONS):
        f = E - e * np.sin(E) - m
        d = f / (1.0 - e * np.cos(E))
        E = np.where(active, E - d, E)
        active &= ~(np.abs(d) <= _TOL)
        if not active.any():
            break
    return E


def solve_kepler_one(mean_anomaly: float, e: float) -> float:
    """:func:`solve_kepler` for one value in Python floats (a single trajectory's hot path)."""
    m = mean_anomaly - _TWO_PI * round(mean_anomaly / _TWO_PI)
    s = math.sin(m)
    E = m + 0.85 * e * (1.0 if s > 0 else (-1.0 if s < 0 else 0.0))
    for _ in range(MAX_ITERATIONS):
        d = (E - e * math.sin(E) - m) / (1.0 - e * math.cos(E))
        E -= d
        if abs(d) <= _TOL:
            break
    return E


def _place(t, E, a, e, inc, node0, peri0, node_rate, peri_rate, xp):
    """(x, y, z, |r|) at times ``t`` with eccentric anomaly ``E``: the point of the ellipse in its plane,
    turned by the argument of pericentre, the inclination and the node (both precessing linearly).
    ``xp``: :mod:`math` for one time in floats (:func:`position_one`), NumPy for arrays (:func:`position`),
    the same arithmetic."""
    cE, sE = xp.cos(E), xp.sin(E)
    x = a * (cE - e)
    y = a * math.sqrt(1.0 - e * e) * sE
    node = node0 + node_rate * t
    peri = peri0 + peri_rate * t
    cO, sO, cw, sw = xp.cos(node), xp.sin(node), xp.cos(peri), xp.sin(peri)
    ci, si = math.cos(inc), math.sin(inc)
    return (
        x * (cO * cw - sO * sw * ci) - y * (cO * sw + sO * cw * ci),
        x * (sO * cw + cO * sw * ci) - y * (sO * sw - cO * cw * ci),
        (x * sw + y * cw) * si,
        a * (1.0 - e * cE),
    )


def position(t, elements):
    """Positions (n, 3) in m on the orbit ``elements`` (a row of :data:`ELEMENTS`) at times t (n,) in s.

    Returns
    -------
    (numpy.ndarray (n, 3), numpy.ndarray (n,))
        The position vectors and their lengths |r| = a (1 - e cos E).
    """
    a, e, inc, node0, peri0, m0, n, node_rate, peri_rate = (float(x) for x in elements)
    t = np.asarray(t, dtype=float)
    E = solve_kepler(m0 + n * t, e)
    px, py, pz, r = _place(t, E, a, e, inc, node0, peri0, node_rate, peri_rate, np)
    out = np.empty(t.shape + (3,))
    out[..., 0], out[..., 1], out[..., 2] = px, py, pz
    return out, r


def position_one(t: float, elements) -> tuple[float, float, float, float]:
    """:func:`position` for one time in Python floats: (x, y, z, |r|)."""
    a, e, inc, node0, peri0, m0, n, node_rate, peri_rate = elements
    return _place(t, solve_kepler_one(m0 + n * t, e), a, e, inc, node0, peri0, node_rate, peri_rate, math)
