"""The heavy top integrated numerically without Euler angles: quaternion + body omega (SI).

A cross-check of the exact solution (:mod:`wobble.models.top`) that has no
coordinate singularity: the state is the body angular velocity omega and the unit
quaternion q (body -> space), with Euler's equations for a symmetric body under the
gravity torque about the tip (notes section 5.5, p. 68, and 5.7, p. 70):

    I1 omega1' = (I1 - I3) omega2 omega3 + M g l gamma2,
    I1 omega2' = (I3 - I1) omega3 omega1 - M g l gamma1,
    I3 omega3' = 0,
    q' = q (0, omega) / 2,

where gamma = R^T e_z is the upward vertical seen in the body (tau = l e3 x (-M g gamma)).
Nothing here is singular at theta = 0 (gamma = e3), so this integration is valid
exactly where the Euler angles of the closed form break down. Integration by
scipy's DOP853 with per-component absolute tolerances scaled to the state (an SI
absolute tolerance would be meaningless for slow or small components); the
quaternion is renormalised at the outputs only. This is a check, not the
production integrator (that is the engine's).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from wobble.errors import InputError
from wobble.models.top import check_top_parameters

__all__ = ["top_rhs", "integrate_top", "vertical_in_body"]


def vertical_in_body(q) -> np.ndarray:
    """gamma = R(q)^T e_z: the space vertical in body coordinates, shape (..., 3)."""
    q = np.asarray(q, dtype=float)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)


def top_rhs(I1: float, I3: float, mgl: float):
    """Right-hand side f(t, y) for y = (omega1, omega2, omega3, qw, qx, qy, qz) (SI)."""
    c13 = (I1 - I3) / I1
    g = mgl / I1

    def rhs(t, y):
        w1, w2, w3, qw, qx, qy, qz = y
        gam1 = 2 * (qx * qz - qw * qy)
        gam2 = 2 * (qy * qz + qw * qx)
        return np.array(
            [
                c13 * w2 * w3 + g * gam2,
                -c13 * w3 * w1 - g * gam1,
                0.0 * w3,
                0.5 * (-qx * w1 - qy * w2 - qz * w3),
                0.5 * (qw * w1 + qy * w3 - qz * w2),
                0.5 * (qw * w2 - qx * w3 + qz * w1),
                0.5 * (qw * w3 + qx * w2 - qy * w1),
            ]
        )

    return rhs


def integrate_top(I1: float, I3: float, mgl: float, omega0, q0, t, *, rtol: float = 1e-12, method: str = "DOP853"):
    """Integrate the top from (omega0, q0) and return omega (N, 3) and q (N, 4) at times t (s).

    Parameters
    ----------
    I1, I3, mgl : float
        Moments about the tip (kg m^2) and M g l (J).
    omega0 : sequence of 3 float
        Body angular velocity at t = 0 (rad/s).
    q0 : sequence of 4 float
        Unit quaternion body -> space at t = 0.
    t : array_like
        Increasing output times (s), starting at or after 0.
    rtol : float
        Relative tolerance; the absolute tolerance is rtol times the size of
        each component (the norm of omega for omega, 1 for q).
    method : str
        A scipy.integrate.solve_ivp method (DOP853, Radau, ...).

    Returns
    -------
    omega, q : numpy.ndarray
    """
    I1, I3, mgl = check_top_parameters(I1, I3, mgl)
    w0 = np.asarray(omega0, dtype=float).reshape(3)
    q0 = np.asarray(q0, dtype=float).reshape(4)
    t = np.asarray(t, dtype=float).reshape(-1)
    if t.size == 0 or np.any(np.diff(t) < 0) or t[0] < 0:
        raise InputError("t", t, "increasing times >= 0 (s)")
    # Scale of omega: the spin and the largest transverse rate the energy allows.
    wscale = max(np.linalg.norm(w0), np.sqrt(2 * mgl / I1), 1e-300)
    atol = rtol * np.array([wscale] * 3 + [1.0] * 4)
    y0 = np.concatenate([w0, q0 / np.linalg.norm(q0)])
    sol = solve_ivp(top_rhs(I1, I3, mgl), (0.0, float(t[-1])), y0, method=method, t_eval=t, rtol=rtol, atol=atol)
    if not sol.success:  # pragma: no cover - scipy failure
        raise RuntimeError(sol.message)
    y = sol.y.T
    q = y[:, 3:] / np.linalg.norm(y[:, 3:], axis=1, keepdims=True)
    return y[:, :3], q
