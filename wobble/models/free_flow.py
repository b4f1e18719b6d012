"""The exact torque-free flow as a map (omega, q) -> (omega, q) after a step h (SI, float64).

The drift of the splitting integrators (:mod:`wobble.numerics.integrators`, Touma &
Wisdom 1994) and the free model of ensembles: the same Jacobi elliptic solution and exact
attitude as :func:`wobble.models.free.free_rotation` (Landau & Lifshitz section 37),
started from a state instead of from t = 0, vectorised over bodies and states. Float64
throughout: no exact rational set-up per member.

Two implementations of one map: :func:`flow_many` in NumPy for N members, and
:func:`flow_one` in Python floats for one (NumPy's per-call cost on one-element arrays is
twenty times the arithmetic, and a single trajectory of the splitting is a long chain of
such calls). They are the same formulas, line for line; tests/test_free_flow.py holds them
equal on generated states of every regime (major and minor axis, symmetric, steady, the
exact separatrix).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special as _sp

from wobble.numerics.floats import EPS
from wobble.errors import InputError
from wobble.models.principal_axes import proper_sort, to_sorted, to_user
from wobble.numerics import elliptic as ell
from wobble.numerics import quaternion as quat

__all__ = ["free_flow", "flow_sorted", "flow_many", "flow_one", "proper_sort"]


def free_flow(moments, omega, q=None, h=0.0):
    """Exact torque-free flow of N rigid bodies over a step h, vectorised.

    Maps the body-frame angular velocity ``omega`` and the attitude ``q``
    (unit quaternion body -> inertial, scalar first) at some time to their
    values a time ``h`` later, for each member independently: the same Jacobi
    elliptic solution and exact attitude as :func:`free_rotation` (Landau &
    Lifshitz section 37; docs/free-rotation.md), started from the state
    itself instead of from t = 0:

    * the phase u0 of the state comes from ``sn, cn, dn = omega_a / A_a,
      s omega_b / A_b, |omega_c| / A_c`` through the quarter-period inverse
      (:func:`wobble.numerics.elliptic.jacobi_quarter_inverse`, Carlson R_F);
    * u1 = u0 + lambda h, evaluated with the exact quarter shifts
      (:func:`wobble.numerics.elliptic.jacobi_quarter`);
    * the attitude increment is ``S(l0)* R_z(dpsi) S(l1)`` with
      ``dpsi = Omega_psi h + P(u1) - P(u0)`` (the mean precession rate and
      the 2K-periodic part built on Pi(-nu; phi | m)), applied on the right:
      ``q1 = q0 * dq``.

    Symmetric bodies (two equal moments) come out of the same formulas with
    m = 0; steady rotation (omega along a principal axis, a sphere, omega = 0)
    is a uniform rotation; the exact separatrix uses tanh and sech.

    Parameters
    ----------
    moments : array_like, shape (3,) or (N, 3)
        Principal moments (kg m^2), any order, per member or shared.
    omega : array_like, shape (N, 3)
        Body-frame angular velocities (rad/s), same axis order.
    q : array_like, shape (N, 4), optional
        Attitudes. Without it only omega is advanced (cheaper: no
        integrals of the third kind).
    h : float or array_like, shape (N,)
        Step (s); any size and sign.

    Returns
    -------
    omega1 : numpy.ndarray, shape (N, 3)
    q1 : numpy.ndarray, shape (N, 4) or None
        Renormalised to unit length.

    Notes
    -----
    Float64 set-up per call, so unlike :func:`free_rotation` the phase
    lambda h carries the rounding of a float product: the error of one call
    is a few ulps of the phase advanced (checked against
    :func:`free_rotation` in tests/test_free_flow.py: within
    ``64 eps (1 + |omega| |h|)`` of the exact solution).
    """
    moments = np.asarray(moments, dtype=float)
    omega = np.atleast_2d(np.asarray(omega, dtype=float))
    order, signs = proper_sort(moments)
    moments_sorted = np.take_along_axis(np.broadcast_to(moments, omega.shape), np.broadcast_to(order, omega.shape), -1)
    w = to_sorted(omega, order, signs)
    h = np.broadcast_to(np.asarray(h, dtype=float), omega.shape[:-1])
    w1, dq = flow_sorted(moments_sorted, w, h, attitude=q is not None)
    w1 = to_user(w1, order, signs)
    if q is None:
        return w1, None
    dq = np.concatenate([dq[..., :1], to_user(dq[..., 1:], order, signs)], axis=-1)
    q1 = quat.multiply(np.asarray(q, dtype=float), dq)
    return w1, quat.normalize(q1)


_TINY = np.finfo(float).tiny


def _invariants(i0, i1, i2, w0, w1, w2):
    """The body-frame angular momentum ``(I_k w_k)``, the terms ``I_k w_k^2`` of 2E and the invariants
    ``D_j = 2 E I_j - L^2 = sum_i I_i w_i^2 (I_j - I_i)``, formed from differences of moments so that
    no large terms cancel; floats (:func:`flow_one`) or arrays (:func:`flow_many`), the same arithmetic."""
    l0, l1, l2 = i0 * w0, i1 * w1, i2 * w2
    e0, e1, e2 = l0 * w0, l1 * w1, l2 * w2
    d01, d02, d12 = i0 - i1, i0 - i2, i1 - i2
    big_d = (e1 * d01 + e2 * d02, e2 * d12 - e0 * d01, -e0 * d02 - e1 * d12)
    return (l0, l1, l2), (e0, e1, e2), big_d


def _increment(moments, w0, w1, inv_l, s, fl, dpsi, xp):
    """The attitude increment ``dq = S(l0)* R_z(dpsi) S(l1)`` in the (a, b, c) frame, with the flip
    (the pi rotation about c) undone: ``(w, a, b, c)``. ``S`` is the shortest arc from ``l = I omega / L``
    to ``z = s e_c``, ``S = (1 + s l_c, s l_b, -s l_a, 0) / norm``; ``w0``, ``w1`` are omega's (a, b, c)
    components at the two ends (flipped), ``inv_l`` = 1/L. ``xp``: :mod:`math` for floats
    (:func:`flow_one`), NumPy for arrays (:func:`flow_many`), the same arithmetic."""
    ia, ib, ic = moments
    la0, lb0, lc0 = ia * w0[0] * inv_l, ib * w0[1] * inv_l, ic * w0[2] * inv_l
    la1, lb1, lc1 = ia * w1[0] * inv_l, ib * w1[1] * inv_l, ic * w1[2] * inv_l
    p_w, p_x, p_y = 1.0 + s * lc0, s * lb0, -s * la0
    q_w, q_x, q_y = 1.0 + s * lc1, s * lb1, -s * la1
    inv_p = 1.0 / xp.sqrt(p_w * p_w + p_x * p_x + p_y * p_y)
    inv_q = 1.0 / xp.sqrt(q_w * q_w + q_x * q_x + q_y * q_y)
    p_w, p_x, p_y = p_w * inv_p, -p_x * inv_p, -p_y * inv_p  # conjugate of S(l0)
    q_w, q_x, q_y = q_w * inv_q, q_x * inv_q, q_y * inv_q
    t_w, t_z = xp.cos(0.5 * dpsi), s * xp.sin(0.5 * dpsi)
    # R = twist * S(l1) (twist has no x, y parts; S no z part)
    r_w, r_x, r_y, r_z = t_w * q_w, t_w * q_x - t_z * q_y, t_w * q_y + t_z * q_x, t_z * q_w
    # dq = S(l0)* * R (S(l0)* has no z part); then undo the flip (x, y parts).
    dq_w = p_w * r_w - p_x * r_x - p_y * r_y
    dq_a = fl * (p_w * r_x + p_x * r_w + p_y * r_z)
    dq_b = fl * (p_w * r_y - p_x * r_z + p_y * r_w)
    dq_c = p_w * r_z + p_x * r_y - p_y * r_x
    return dq_w, dq_a, dq_b, dq_c


def _unrepresentable_one(omega, energies, m1) -> bool:
    """:func:`_check_representable`'s test for one unsteady member in floats (the arrays cost 40 % of a
    splitting stage, 82.6 us against 45-48, scripts/calibrate_chooser.py): the same two conditions."""
    return 0.0 < m1 < ell.M1_MIN or any(w != 0.0 and abs(e) < _TINY for w, e in zip(omega, energies))


def _check_representable(omega, energies, m1, steady) -> None:
    """Refuse states the float64 formulas cannot carry (an InputError naming the member).

    * a non-zero component whose I w^2 underflows (below 2.2e-308): the invariants D_j
      lose it, and a state next to the intermediate axis would pass for the separatrix;
    * 1 - m between 0 and :data:`wobble.numerics.elliptic.M1_MIN`: within ~1e-75 of the
      separatrix, where the integrals of the third kind leave double precision (the exact
      separatrix, 1 - m = 0, is computed).
    """
    e = np.stack([np.abs(x) for x in energies], axis=-1)
    lost = np.any((omega != 0) & (e < _TINY), axis=-1)
    near = (~steady) & (m1 > 0) & (m1 < ell.M1_MIN)
    bad = np.flatnonzero(lost | near)
    if bad.size:
        k = int(bad[0])
        why = (
            "components whose squares underflow double precision (|omega_k| below ~1e-154 beside a non-zero one)"
            if lost[k]
            else f"1 - m = {float(m1[k]):.3g}, below {ell.M1_MIN:g}: within ~1e-75 of "
            "the separatrix, where the elliptic integrals leave double precision"
        )
        raise InputError(
            f"omega[{k}]", omega[k].tolist(), f"a state the free flow can carry in float64; this one has {why}"
        )


def flow_sorted(moments, omega, h, attitude=True):
    """:func:`free_flow` in the ascending principal frame (moments sorted, proper).

    Returns ``omega1`` (N, 3) and the body-frame increment ``dq`` (N, 4)
    with ``q1 = q0 * dq`` (None without ``attitude``). The splitting
    integrator calls this directly: its bodies are sorted once. Written
    component by component, with the three integrals of the third kind in
    one vectorised call, because it is the inner loop of the splitting.
    """
    I = np.broadcast_to(np.asarray(moments, dtype=float), np.shape(omega))
    if omega.shape[0] == 1:
        w1, dq = flow_one(tuple(I[0]), tuple(omega[0]), float(np.reshape(h, -1)[0]), attitude)
        return np.array([w1]), (None if dq is None else np.array([dq]))
    with np.errstate(divide="ignore", invalid="ignore"):
        return flow_many(I, omega, h, attitude)


def flow_many(I, omega, h, attitude):
    """:func:`flow_sorted` for N members at once in NumPy (moments ascending, the sorted frame)."""
    i0, i1, i2 = I[:, 0], I[:, 1], I[:, 2]
    w0, w1, w2 = omega[:, 0], omega[:, 1], omega[:, 2]
    h = np.broadcast_to(np.asarray(h, dtype=float), w0.shape)
    (l0, l1, l2), (e0, e1, e2), (big_d0, big_d1, big_d2) = _invariants(i0, i1, i2, w0, w1, w2)
    # The solution's right-handed frame (a, b, c): (x0, x1, x2) when omega circulates
    # about the largest axis, (x2, x1, -x0) about the smallest (L^2 < 2 E I2).
    minor = big_d1 > 0
    any_minor = bool(minor.any())
    if any_minor:
        ia, ic = np.where(minor, i2, i0), np.where(minor, i0, i2)
        da, dc = np.where(minor, big_d2, big_d0), np.where(minor, big_d0, big_d2)
        wa, wc = np.where(minor, w2, w0), np.where(minor, -w0, w2)
    else:
        ia, ic, da, dc, wa, wc = i0, i2, big_d0, big_d2, w0, w2
    ib, wb = i1, w1
    steady = (dc == 0) | (da == 0) | ((wa == 0) & (wc == 0))
    any_steady = bool(steady.any())
    # A rotation by pi about c is a symmetry of the free motion: it makes
    # omega_a >= 0 (cn u0 >= 0; on the separatrix cn = sech > 0).
    fl = np.where(wa < 0, -1.0, 1.0)
    wa, wb = fl * wa, fl * wb
    s = np.where(wc < 0, -1.0, 1.0)
    # omega_b = s_b A_b sn u: in the (x2, x1, -x0) frame the sign of omega_b is reversed.
    sb = np.where(minor, -s, s) if any_minor else s
    ica, icb, iba = ic - ia, ic - ib, ib - ia
    neg_da = -da
    if any_steady:  # harmless values where the motion is steady (replaced at the end)
        neg_da = np.where(steady, 1.0, neg_da)
        dc = np.where(steady, 1.0, dc)
        icb = np.where(steady, 1.0, icb)
        ica = np.where(steady, 1.0, ica)
    den = icb * neg_da
    m1_dir = ica * (-big_d1) / den
    m_dir = iba * dc / den
    small = m1_dir < 0.5
    m1 = np.clip(np.where(small, m1_dir, 1.0 - m_dir), 0.0, 1.0)
    m = np.clip(np.where(small, 1.0 - m1_dir, m_dir), 0.0, 1.0)
    sep = m1 == 0.0
    _check_representable(omega, (e0, e1, e2), m1, steady)
    any_sep = bool(sep.any())
    lam = np.sqrt(np.abs(den) / (i0 * i1 * i2))
    amp_a = np.sqrt(np.abs(dc / (ia * ica)))
    amp_b = np.sqrt(np.abs(dc / (ib * icb)))
    amp_c = np.sqrt(np.abs(neg_da / (ic * ica)))
    cn0 = wa / amp_a
    sn0 = sb * wb / amp_b
    norm = np.hypot(cn0, sn0)
    cn0, sn0 = cn0 / norm, sn0 / norm
    dn0 = np.sqrt(m1 + m * cn0 * cn0)
    if any_sep:  # Landen levels with a placeholder parameter on the separatrix (tanh / sech there)
        lv = ell.landen_levels(np.where(sep, 0.0, m), np.where(sep, 1.0, m1))
        K = np.where(sep, np.inf, lv.K)
    else:
        lv = ell.landen_levels(m, m1)
        K = lv.K
    n0, x0, snx0, cnx0, dnx0 = ell.jacobi_quarter_inverse(sn0, cn0, dn0, m, m1)
    y = x0 + lam * h
    if any_sep:
        finite = ~sep
        k_safe = np.where(finite, K, 1.0)
        qn = np.where(finite, np.rint(y / k_safe), 0.0)
        x1 = np.where(finite, y - qn * k_safe, y)
    else:
        k_safe = K
        qn = np.rint(y / K)
        x1 = y - qn * K
    n1 = n0 + qn
    (sn1, cn1, dn1), (snx1, cnx1, dnx1) = ell.jacobi_quarter(n1, x1, lv, sep if any_sep else None)
    v_a = fl * amp_a * cn1
    v_b = fl * sb * amp_b * sn1
    v_c = s * amp_c * dn1
    if any_minor:
        o0, o2 = np.where(minor, -v_c, v_a), np.where(minor, v_a, v_c)
    else:
        o0, o2 = v_a, v_c
    w_new = np.stack([o0, v_b, o2], axis=-1)
    if any_steady:
        w_new = np.where(steady[:, None], omega, w_new)
    if not attitude:
        return w_new, None

    # ---- attitude: psi(t1) - psi(t0) = Omega_psi h + P(u1) - P(u0) ---------------
    big_l = np.sqrt(l0 * l0 + l1 * l1 + l2 * l2)
    nu = np.abs(ic * iba / (ia * icb))
    sq = np.sqrt(1.0 + nu)
    kp = np.sqrt(m1)
    lin_scale = 0.0 if any_sep and bool(sep.all()) else 1.0 / k_safe
    if any_sep:
        lin_scale = np.where(sep, 0.0, 1.0 / k_safe)

    def reduced(n, x, snx, cnx, dnx):
        """sn, cn, dn^2 and r/K of r = u reduced to [-K, K] (P is 2K-periodic)."""
        odd = np.mod(n, 2.0) == 1.0
        left = x <= 0
        inv = 1.0 / dnx
        s_r = np.where(odd, np.where(left, cnx, -cnx) * inv, snx)
        c_r = np.where(odd, np.where(left, -kp, kp) * snx * inv, cnx)
        d_r = np.where(odd, kp * inv, dnx)
        lin_x = x * lin_scale
        lin = np.where(odd, np.where(left, 1.0 + lin_x, lin_x - 1.0), lin_x)
        return s_r, c_r, d_r * d_r, lin

    s_0, c_0, d2_0, lin0 = reduced(n0, x0, snx0, cnx0, dnx0)
    s_1, c_1, d2_1, lin1 = reduced(n1, x1, snx1, cnx1, dnx1)
    n = w0.size
    ones = np.ones(n)
    m1_pi = np.where(sep, 1.0, m1) if any_sep else m1  # the complete integral is unused on the separatrix
    pis = ell.pi_negative_scd(
        np.concatenate([nu, nu, nu]),
        np.concatenate([s_0, s_1, ones]),
        np.concatenate([c_0, c_1, 0.0 * ones]),
        np.concatenate([d2_0, d2_1, m1_pi]),
        np.concatenate([m1, m1, m1_pi]),
    )
    pi0, pi1, pi_c = pis[:n], pis[n : 2 * n], pis[2 * n :]
    g = np.arctan2(np.concatenate([sq * s_0, sq * s_1]), np.concatenate([c_0, c_1]))
    lam_safe = np.where(lam > 0, lam, 1.0) if any_steady else lam
    c_pi = ica * big_l / (ia * ic * lam_safe)
    c_g = ica * amp_c / (ia * lam_safe * sq)
    if any_sep:
        pi_c = np.where(sep, 0.0, pi_c)
    # P(r) = c_pi (Pi(r) - Pi_c r/K) - c_g (g(r) - (pi/2) r/K); the mean rate Omega_psi.
    rate = big_l / ic + (ica * big_l * pi_c / (ia * ic) - ica * amp_c * (0.5 * np.pi) / (ia * sq)) * lin_scale
    dpsi = (
        rate * h + c_pi * ((pi1 - pi0) - pi_c * (lin1 - lin0)) - c_g * ((g[n:] - g[:n]) - 0.5 * np.pi * (lin1 - lin0))
    )
    inv_l = 1.0 / np.where(big_l > 0, big_l, 1.0)
    dq_w, dq_a, dq_b, dq_c = _increment((ia, ib, ic), (wa, wb, wc), (fl * v_a, fl * v_b, v_c), inv_l, s, fl, dpsi, np)
    # Undo the frame.
    if any_minor:
        dq_0, dq_2 = np.where(minor, -dq_c, dq_a), np.where(minor, dq_a, dq_c)
    else:
        dq_0, dq_2 = dq_a, dq_c
    dq = np.stack([dq_w, dq_0, dq_b, dq_2], axis=-1)
    if any_steady:
        dq = np.where(steady[:, None], quat.exp(omega * h[:, None]), dq)
    return w_new, dq


# --------------------------------------------------------------------------
# The same flow for one member in Python floats: NumPy's per-call overhead on
# 1-element arrays costs twenty times the arithmetic, and a single trajectory
# of the splitting integrator is a long sequence of such calls. Line for line
# the formulas of _flow_many (tests/test_free_flow.py checks they agree).
# --------------------------------------------------------------------------
def _landen_one(m, m1):
    a, b, c = 1.0, math.sqrt(m1), math.sqrt(m)
    levels = []
    while c > 0.5 * EPS * a and len(levels) < 40:
        a, b, c = 0.5 * (a + b), math.sqrt(a * b), 0.5 * (a - b)
        levels.append((c / a, b / a))
    return 0.5 * math.pi / a, (2.0 ** len(levels)) * a, levels


def _amplitude_one(w, scale, levels):
    phi = scale * w
    for ratio, ratio_b in reversed(levels):
        sp = math.sin(phi)
        if ratio > 0.5:
            cp = math.cos(phi)
            phi = 0.5 * (phi + math.atan2(ratio * sp, math.sqrt(cp * cp + (ratio_b * sp) ** 2)))
        else:
            phi = 0.5 * (phi + math.asin(ratio * sp))
    return phi


def _pi_one(nu, s, c, d2, m1):
    """pi_negative_scd for floats."""
    sign = -1.0 if s < 0 else 1.0
    s = abs(s)
    c2, s2 = c * c, s * s
    out = s * float(_sp.elliprf(c2, d2, 1.0)) / (1.0 + nu)
    if nu > 0:
        p = 1.0 + nu * s2
        q = c2 + m1 * s2 / (1.0 + nu)
        out += nu * s * c * float(_sp.elliprc(d2, p * q)) / (1.0 + nu)
        if m1 * s > 0:
            out += nu * m1 * s * s2 * float(_sp.elliprj(c2, d2, 1.0, q if q > 0 else 1.0)) / (3.0 * (1.0 + nu) ** 2)
    return sign * out


def _exp_one(w0, w1, w2, h):
    """Quaternion of the rotation by the vector omega h (a uniform spin)."""
    x0, x1, x2 = w0 * h, w1 * h, w2 * h
    angle = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    if angle == 0.0:
        return (1.0, 0.0, 0.0, 0.0)
    f = math.sin(0.5 * angle) / angle
    return (math.cos(0.5 * angle), f * x0, f * x1, f * x2)


def flow_one(moments, omega, h, attitude=True):
    """:func:`flow_sorted` for one member in Python floats: tuples in, tuples out.

    ``moments`` ascending (3 floats), ``omega`` (3 floats, that frame), step ``h``;
    returns ``(omega1, dq)`` as tuples (``dq`` None without ``attitude``).
    """
    i0, i1, i2 = (float(x) for x in moments)
    w0, w1, w2 = (float(x) for x in omega)
    h = float(h)
    (l0, l1, l2), (e0, e1, e2), (big_d0, big_d1, big_d2) = _invariants(i0, i1, i2, w0, w1, w2)
    minor = big_d1 > 0
    if minor:
        ia, ic, da, dc, wa, wc = i2, i0, big_d2, big_d0, w2, -w0
    else:
        ia, ic, da, dc, wa, wc = i0, i2, big_d0, big_d2, w0, w2
    ib, wb = i1, w1
    if dc == 0 or da == 0 or (wa == 0 and wc == 0):  # steady rotation about a principal axis
        return (w0, w1, w2), (_exp_one(w0, w1, w2, h) if attitude else None)
    fl = -1.0 if wa < 0 else 1.0
    wa, wb = fl * wa, fl * wb
    s = -1.0 if wc < 0 else 1.0
    sb = -s if minor else s
    ica, icb, iba = ic - ia, ic - ib, ib - ia
    neg_da = -da
    den = icb * neg_da
    m1_dir = ica * (-big_d1) / den
    m_dir = iba * dc / den
    if m1_dir < 0.5:
        m1, m = m1_dir, 1.0 - m1_dir
    else:
        m1, m = 1.0 - m_dir, m_dir
    m1, m = min(max(m1, 0.0), 1.0), min(max(m, 0.0), 1.0)
    sep = m1 == 0.0
    if _unrepresentable_one((w0, w1, w2), (e0, e1, e2), m1):  # the arrays only to raise the message
        _check_representable(
            np.array([[w0, w1, w2]]),
            (np.array([e0]), np.array([e1]), np.array([e2])),
            np.array([m1]),
            np.array([False]),
        )
    lam = math.sqrt(abs(den) / (i0 * i1 * i2))
    amp_a = math.sqrt(abs(dc / (ia * ica)))
    amp_b = math.sqrt(abs(dc / (ib * icb)))
    amp_c = math.sqrt(abs(neg_da / (ic * ica)))
    cn0, sn0 = wa / amp_a, sb * wb / amp_b
    norm = math.hypot(cn0, sn0)
    cn0, sn0 = cn0 / norm, sn0 / norm
    dn0 = math.sqrt(m1 + m * cn0 * cn0)
    kp = math.sqrt(m1)
    K, scale, levels = _landen_one(0.0, 1.0) if sep else _landen_one(m, m1)
    # inverse: u0 = n0 K + x0 (jacobi_quarter_inverse)
    if sep or dn0 * dn0 >= kp:
        n0 = 0.0 if cn0 >= 0 else 2.0
        snx0 = sn0 if cn0 >= 0 else -sn0
        cnx0, dnx0 = abs(cn0), dn0
        d2 = cnx0 * cnx0 + m1 * snx0 * snx0
    else:
        n0 = 1.0 if sn0 > 0 else -1.0
        snx0 = (-cn0 if sn0 > 0 else cn0) / dn0
        cnx0 = kp * abs(sn0) / dn0
        dnx0 = kp / dn0
        d2 = m1 / (dn0 * dn0)
    x0 = snx0 * float(_sp.elliprf(cnx0 * cnx0, d2, 1.0))
    y = x0 + lam * h
    if sep:
        qn, x1 = 0.0, y
    else:
        qn = float(np.rint(y / K))
        x1 = y - qn * K
    n1 = n0 + qn
    # forward: sn, cn, dn of x1, then the quarter shift (jacobi_quarter)
    if sep:
        sech = 1.0 / math.cosh(x1) if abs(x1) < 700 else 0.0
        snx1, cnx1, dnx1 = math.tanh(x1), sech, sech
    else:
        phi = _amplitude_one(x1, scale, levels)
        snx1, cnx1 = math.sin(phi), math.cos(phi)
        dnx1 = math.sqrt(m1 + m * cnx1 * cnx1)
    quarter = n1 % 4.0
    if quarter in (1.0, 3.0):
        sn1, cn1, dn1 = cnx1 / dnx1, -kp * snx1 / dnx1, kp / dnx1
    else:
        sn1, cn1, dn1 = snx1, cnx1, dnx1
    if quarter >= 2.0:
        sn1, cn1 = -sn1, -cn1
    v_a, v_b, v_c = fl * amp_a * cn1, fl * sb * amp_b * sn1, s * amp_c * dn1
    w_new = (-v_c, v_b, v_a) if minor else (v_a, v_b, v_c)
    if not attitude:
        return w_new, None
    big_l = math.sqrt(l0 * l0 + l1 * l1 + l2 * l2)
    nu = abs(ic * iba / (ia * icb))
    sq = math.sqrt(1.0 + nu)
    lin_scale = 0.0 if sep else 1.0 / K

    def periodic(n, x, snx, cnx, dnx):
        if n % 2.0 == 1.0:
            if x <= 0:
                s_r, c_r, lin = cnx / dnx, -kp * snx / dnx, 1.0 + x * lin_scale
            else:
                s_r, c_r, lin = -cnx / dnx, kp * snx / dnx, x * lin_scale - 1.0
            d_r = kp / dnx
        else:
            s_r, c_r, d_r, lin = snx, cnx, dnx, x * lin_scale
        return _pi_one(nu, s_r, c_r, d_r * d_r, m1), math.atan2(sq * s_r, c_r), lin

    pi0, g0, lin0 = periodic(n0, x0, snx0, cnx0, dnx0)
    pi1, g1, lin1 = periodic(n1, x1, snx1, cnx1, dnx1)
    pi_c = 0.0 if sep else _pi_one(nu, 1.0, 0.0, m1, m1)
    c_pi = ica * big_l / (ia * ic * lam)
    c_g = ica * amp_c / (ia * lam * sq)
    rate = big_l / ic + (ica * big_l * pi_c / (ia * ic) - ica * amp_c * (0.5 * math.pi) / (ia * sq)) * lin_scale
    dpsi = rate * h + c_pi * ((pi1 - pi0) - pi_c * (lin1 - lin0)) - c_g * ((g1 - g0) - 0.5 * math.pi * (lin1 - lin0))
    dq_w, dq_a, dq_b, dq_c = _increment(
        (ia, ib, ic), (wa, wb, wc), (fl * v_a, fl * v_b, v_c), 1.0 / big_l, s, fl, dpsi, math
    )
    dq = (dq_w, -dq_c, dq_b, dq_a) if minor else (dq_w, dq_a, dq_b, dq_c)
    return w_new, dq
