"""Torque-free tumbling of many bodies at once: regime, periods, wobble angles (SI, float64).

Course notes section 5.6 (free precession) with Landau & Lifshitz, Mechanics,
section 37, for N bodies in one vectorised call (no loop over members). In
the ascending principal frame I0 <= I1 <= I2, with D_j = 2 E I_j - L^2 =
sum_i I_i omega_i^2 (I_j - I_i) (formed without cancellation):

* D_1 < 0 (L^2 > 2 E I1): omega circulates about the axis of largest moment,
  the body's shortest axis: short-axis mode (SAM; ``major-axis`` in
  :mod:`wobble.models.free`); D_1 > 0: about the axis of smallest moment,
  the longest axis: long-axis mode (LAM); D_1 = 0: the separatrix;
  omega along a principal axis (the intermediate one too: an unstable
  equilibrium, which never leaves it) or a sphere: steady spin, as
  :func:`wobble.models.free.free_rotation` has it.
* In the solution's frame (a, b, c), c the circulation axis,
  omega_a = A_a cn u, omega_b = A_b sn u, omega_c = A_c dn u, u = lambda t + u0,
  lambda^2 = (I_c - I_b)(-D_a) / (I0 I1 I2),
  m = (I_b - I_a) D_c / ((I_c - I_b)(-D_a)); the nutation period (of omega in
  the body) is 4 K(m) / lambda; with two equal moments m = 0 and it is the
  notes' 2 pi / ``|Omega|``, Omega = (I3 - I1) omega3 / I1.
* The wobble angle theta between the circulation axis and L swings between
  tan theta_min = I_a A_a / (I_c A_c) (at sn u = 0) and
  tan theta_max = I_b A_b / (I_c A_c sqrt(1 - m)) (at cn u = 0); for a
  symmetric body it is constant, cos theta = I3 omega3 / L.
* The mean precession rate of the circulation axis about L (the mean of
  Landau & Lifshitz's phidot = L (I_a omega_a^2 + I_b omega_b^2) / (I_a^2 omega_a^2 + I_b^2 omega_b^2),
  eq. 37.14) is the mean rate of the attitude angle psi of docs/free-rotation.md,
  L / I_c + (I_c - I_a)[L Pi(-nu|m) / (I_a I_c) - A_c (pi/2) / (I_a sqrt(1 + nu))] / K(m),
  nu = I_c (I_b - I_a) / (I_a (I_c - I_b)), plus 2 pi / T for SAM and minus
  2 pi / T for LAM (psi is measured from the shortest-arc frame, which turns
  once per nutation period T); for a symmetric body it is L / I1, the notes'
  free precession. ``precession_period`` = 2 pi / rate.
* omega at a later time t comes from the exact flow map
  :func:`wobble.models.free_flow.free_flow`.

Members whose moments violate the triangle inequality I0 + I1 >= I2 (no real
body) or are not positive and finite are marked invalid (codes
:data:`INVALID_REASONS`) and get NaN outputs; the others are unaffected.
"""

from __future__ import annotations

import numpy as np
from scipy import special as _sp

from wobble.numerics.floats import EPS
from wobble.models.free_flow import free_flow
from wobble.models.principal_axes import proper_sort
from wobble.models.vocabulary import Regime
from wobble.numerics import elliptic as ell

__all__ = ["REGIMES", "INVALID_REASONS", "free_ensemble"]

# The torque-free regimes an ensemble member can be in (no exactly symmetric bodies: their
# circulation is counted with the axis it goes round).
REGIMES = (Regime.STEADY.value, Regime.MAJOR_AXIS.value, Regime.MINOR_AXIS.value, Regime.SEPARATRIX.value)
INVALID_REASONS = {
    0: "",
    1: "principal moments violate the triangle inequality I1 + I2 >= I3 (no real body)",
    2: "a moment is not positive and finite, or omega0 or the time is not finite",
}


def free_ensemble(moments, omega0, t=None) -> dict[str, np.ndarray]:
    """Regime, nutation period, mean precession rate and wobble-angle range of N free bodies.

    Parameters
    ----------
    moments : array_like, shape (N, 3)
        Principal moments (kg m^2), any order per member.
    omega0 : array_like, shape (N, 3)
        Body-frame angular velocity (rad/s), the same axis order.
    t : array_like, shape (N,) or scalar, optional
        A time (s) at which to report omega (exact flow map).

    Returns
    -------
    dict of numpy.ndarray
        ``regime`` (int8 index into :data:`REGIMES`, -1 invalid),
        ``nutation_period`` (s; inf for steady spin and on the separatrix),
        ``precession_rate`` (rad/s, mean rate of the circulation axis about L)
        and ``precession_period`` (s, 2 pi / rate),
        ``wobble_angle_min`` and ``wobble_angle_max`` (rad, between the
        circulation axis and L), ``omega_final`` (N, 3; rad/s, at ``t``,
        only when ``t`` is given) and ``invalid_reason`` (int8).
    """
    moments = np.atleast_2d(np.asarray(moments, dtype=float))
    omega0 = np.atleast_2d(np.asarray(omega0, dtype=float))
    moments, omega0 = np.broadcast_arrays(moments, omega0)
    n = omega0.shape[0]
    srt = np.sort(moments, axis=-1)
    with np.errstate(invalid="ignore"):
        finite = np.all(np.isfinite(moments), -1) & np.all(np.isfinite(omega0), -1) & (srt[:, 0] > 0)
        if t is not None:
            finite &= np.isfinite(np.broadcast_to(np.asarray(t, dtype=float), (n,)))
        triangle = srt[:, 0] + srt[:, 1] >= srt[:, 2] * (1 - 8 * EPS)
    reason = np.where(~finite, 2, np.where(~triangle, 1, 0)).astype(np.int8)
    ok = reason == 0
    out = {
        "regime": np.full(n, -1, dtype=np.int8),
        "nutation_period": np.full(n, np.nan),
        "precession_rate": np.full(n, np.nan),
        "precession_period": np.full(n, np.nan),
        "wobble_angle_min": np.full(n, np.nan),
        "wobble_angle_max": np.full(n, np.nan),
    }
    idx = np.flatnonzero(ok)
    if idx.size:
        with np.errstate(divide="ignore", invalid="ignore"):
            res = _analyse(moments[idx], omega0[idx])
        for key, vals in res.items():
            out[key][idx] = vals
    if t is not None:
        w_final = np.full((n, 3), np.nan)
        if idx.size:
            h = np.broadcast_to(np.asarray(t, dtype=float), (n,))[idx]
            w_final[idx], _ = free_flow(moments[idx], omega0[idx], None, h)
        out["omega_final"] = w_final
    out["invalid_reason"] = reason
    return out


def _analyse(moments, omega):
    order, signs = proper_sort(moments)
    I = np.take_along_axis(moments, order, -1)
    w = np.take_along_axis(omega, order, -1)  # signs do not matter for what follows
    i0, i1, i2 = I[:, 0], I[:, 1], I[:, 2]
    e0, e1, e2 = i0 * w[:, 0] ** 2, i1 * w[:, 1] ** 2, i2 * w[:, 2] ** 2
    d01, d02, d12 = i0 - i1, i0 - i2, i1 - i2
    big_d0 = e1 * d01 + e2 * d02
    big_d1 = e2 * d12 - e0 * d01
    big_d2 = -e0 * d02 - e1 * d12
    big_l = np.sqrt((i0 * w[:, 0]) ** 2 + (i1 * w[:, 1]) ** 2 + (i2 * w[:, 2]) ** 2)
    minor = big_d1 > 0  # LAM
    ia, ic = np.where(minor, i2, i0), np.where(minor, i0, i2)
    da, dc = np.where(minor, big_d2, big_d0), np.where(minor, big_d0, big_d2)
    ib = i1
    # Steady spin: omega in one eigenspace of the inertia tensor. D_c = 0 or D_a = 0 holds
    # for a spin about the largest or the smallest moment (and a sphere); a spin about a
    # distinct intermediate axis has D_1 = 0 but D_0, D_2 != 0, and is told by omega_0 = omega_2 = 0
    # (it is an equilibrium, unstable, not the separatrix's asymptotic motion). The components, not
    # e0 and e2: their squares underflow below 1e-162 rad/s, which made a spin 1e-200 off the axis steady.
    steady = (dc == 0) | (da == 0) | ((w[:, 0] == 0) & (w[:, 2] == 0))
    sep = (big_d1 == 0) & ~steady
    ica, icb, iba = ic - ia, ic - ib, ib - ia
    den = icb * (-da)
    m1_dir = ica * (-big_d1) / den
    m_dir = iba * dc / den
    small = m1_dir < 0.5
    m1 = np.clip(np.where(small, m1_dir, 1.0 - m_dir), 0.0, 1.0)
    lam = np.sqrt(np.abs(den) / (i0 * i1 * i2))
    amp_a = np.sqrt(np.abs(dc / (ia * ica)))
    amp_b = np.sqrt(np.abs(dc / (ib * icb)))
    amp_c = np.sqrt(np.abs(-da / (ic * ica)))
    K = _sp.elliprf(0.0, m1, 1.0)  # inf on the separatrix
    period = 4.0 * K / lam
    nu = np.abs(ic * iba / (ia * icb))
    ones = np.ones_like(nu)
    pi_c = ell.pi_negative_scd(nu, ones, 0.0 * ones, np.where(sep, 1.0, m1), np.where(sep, 1.0, m1))
    rate_psi = (
        big_l / ic + (ica * big_l * pi_c / (ia * ic) - ica * amp_c * (0.5 * np.pi) / (ia * np.sqrt(1.0 + nu))) / K
    )
    rate = rate_psi + np.where(minor, -2.0, 2.0) * np.pi / period
    theta_min = np.arctan2(ia * amp_a, ic * amp_c)
    theta_max = np.arctan2(ib * amp_b, ic * amp_c * np.sqrt(m1))
    regime = np.where(minor, 2, 1)
    regime = np.where(sep, 3, regime)
    regime = np.where(steady, 0, regime)
    # Steady spin: omega constant, the body spins about L (wobble 0); separatrix: the
    # asymptotic motion takes infinitely long, the mean precession rate is undefined.
    period = np.where(steady, np.inf, np.where(sep, np.inf, period))
    rate = np.where(steady, np.sqrt(np.sum(w * w, -1)), np.where(sep, np.nan, rate))
    theta_min = np.where(steady, 0.0, theta_min)
    theta_max = np.where(steady, 0.0, np.where(sep, 0.5 * np.pi, theta_max))
    return {
        "regime": regime.astype(np.int8),
        "nutation_period": period,
        "precession_rate": rate,
        "precession_period": 2.0 * np.pi / rate,
        "wobble_angle_min": theta_min,
        "wobble_angle_max": theta_max,
    }
