"""The heavy top's motion from its table of Taylor expansions, compiled (Numba; float64, SI).

The nutating top's periodic parts (theta, the periodic parts of the half angles
sigma = (phi + psi)/2 and delta = (phi - psi)/2, dtheta/dr, sin(theta/2) and
cos(theta/2); docs/heavy-top.md, Goldstein, Poole & Safko 2002 sec. 5.7) are tabulated
at S nodes over one nutation period as Taylor coefficients ``f^(j)(node) / j!``
(:mod:`wobble.models.top_series`). Here one pass over the samples does what the NumPy
path of that module does in a dozen passes: the nutation phase reduced exactly
(:func:`phase`, Dekker's product and a Cody-Waite reduction, as
:func:`wobble.numerics.phase.reduce_phase`), the six polynomials from the nearest node
(the coefficients of one node are contiguous: node-major table), the unit phasors
exp(i sigma) and exp(i delta) as a product of three (whole periods, the node, and the
polynomial of the small remainder r - node: no trigonometric call per sample), then the
quaternion, omega in the body, the symmetry axis and E, p_phi, p_psi.

Why compiled: the NumPy path makes ~40 temporaries of the samples' size and gathers six
tables per coefficient; here the outputs are the only memory written. The arithmetic is
the NumPy path's, operation for operation and without fused multiply-adds, so the two
agree bit for bit (tested).

Numba is imported by this module only (~0.4 s once per process).
"""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["phase", "angles", "motion", "CONSTANTS"]

_jit = nb.njit(cache=True, nogil=True, error_model="numpy")
_SPLITTER = 134217729.0  # 2^27 + 1

#: Layout of the constants vector handed to :func:`angles` and :func:`motion`.
CONSTANTS = (
    "K0", "h", "inv_h", "w0", "lam0", "B", "C", "w3", "w3_minus_a",
    "sig_a1", "sig_a2", "sig_a3", "sig_c", "sig_off", "sig_p0",
    "dlt_a1", "dlt_a2", "dlt_a3", "dlt_c", "dlt_off", "dlt_p0",
    "tp0", "tp1", "tp2", "inv_two_pi", "two_pi", "half_inv_pi",
    "half_I1", "half_I3", "I1", "I3", "mgl",
)
_I = {name: i for i, name in enumerate(CONSTANTS)}
(K0, H, INV_H, W0, LAM0, B_, C_, W3, W3MA, SA1, SA2, SA3, SC, SOFF, SP0, DA1, DA2, DA3, DC, DOFF, DP0,
 TP0, TP1, TP2, INV_TP, TWO_PI, HALF_INV_PI, HALF_I1, HALF_I3, I1_, I3_, MGL) = range(len(CONSTANTS))


@_jit
def _phase(t, lam0, lam1, w0, p1, p2, p3, period, r_out, j_out):
    half = 0.5 * period
    for i in range(t.shape[0]):
        ti = t[i]
        p = ti * lam0
        c = _SPLITTER * ti
        ah = c - (c - ti)
        al = ti - ah
        c = _SPLITTER * lam0
        bh = c - (c - lam0)
        bl = lam0 - bh
        e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
        e = e + ti * lam1
        x = p + w0
        bb = x - p
        e2 = (p - (x - bb)) + (w0 - bb)
        lo = e + e2
        j = np.rint((x + lo) / period)
        r = ((x - j * p1) - j * p2) + (lo - j * p3)
        if r > half:
            r = ((r - p1) - p2) - p3
            j = j + 1.0
        elif r < -half:
            r = ((r + p1) + p2) + p3
            j = j - 1.0
        r_out[i] = r
        j_out[i] = j


def phase(t, lam, period, offset, pieces):
    """Reduced nutation phase r and whole half-periods j of ``lam * t + offset`` (as
    :func:`wobble.numerics.phase.reduce_phase`, bit for bit; ``pieces`` = its three-float
    split of ``period``)."""
    t = np.ascontiguousarray(t, dtype=float)
    r = np.empty_like(t)
    j = np.empty_like(t)
    _phase(t, float(lam[0]), float(lam[1]), float(offset), float(pieces[0]), float(pieces[1]), float(pieces[2]),
           float(period[0]), r, j)
    return r, j


@_jit
def _secular(j, r, k, a1, a2, a3, c, off, w0):
    """Secular.__call__ of wobble.models.top_closed_form, one sample."""
    z = j * a1
    n = np.rint(z * k[INV_TP])
    z = ((z - n * k[TP0]) - n * k[TP1]) - n * k[TP2]
    return z + (j * a2 + (j * a3 + (c * (r - w0) + off)))


@_jit
def _wrap(a, k):
    return a - k[TWO_PI] * np.rint(a * k[HALF_INV_PI])


@_jit
def _angles(r, j, tab, k, out):
    nodes = tab.shape[0]
    order = tab.shape[1] - 1
    for i in range(r.shape[0]):
        u = (r[i] + k[K0]) * k[INV_H]
        idx = np.rint(u)
        d = (u - idx) * k[H]
        ii = int(idx)
        if ii >= nodes:
            ii -= nodes
        a0 = tab[ii, order, 0]
        a1 = tab[ii, order, 1]
        a2 = tab[ii, order, 2]
        for o in range(order - 1, -1, -1):
            a0 = a0 * d + tab[ii, o, 0]
            a1 = a1 * d + tab[ii, o, 1]
            a2 = a2 * d + tab[ii, o, 2]
        sig = _secular(j[i], r[i], k, k[SA1], k[SA2], k[SA3], k[SC], k[SOFF], k[W0]) + (a1 - k[SP0])
        dlt = _secular(j[i], r[i], k, k[DA1], k[DA2], k[DA3], k[DC], k[DOFF], k[W0]) + (a2 - k[DP0])
        out[0, i] = a0
        out[1, i] = _wrap(sig + dlt, k)
        out[2, i] = _wrap(sig - dlt, k)


def angles(r, j, table, constants):
    """theta, phi, psi (3, N) at reduced phases ``r`` and half-periods ``j`` from a node-major
    table (S, order + 1, rows >= 3)."""
    out = np.empty((3, r.size))
    _angles(r, j, table, constants, out)
    return out


@_jit
def _cis(x, cc, sc):
    """cos and sin of a small x (|x| <= 1/32) by their Taylor polynomials in x^2 (four
    coefficients each, cc and sc)."""
    z = x * x
    c = ((cc[3] * z + cc[2]) * z + cc[1]) * z + cc[0]
    s = (((sc[3] * z + sc[2]) * z + sc[1]) * z + sc[0]) * x
    return c, s


@_jit
def _motion(r, j, jidx, tab, node_r, phasor, jtab, cos_c, sin_c, k, out, omega, quat, axis):
    nodes = tab.shape[0]
    cc = (cos_c[0], cos_c[1], cos_c[2], cos_c[3])
    sc = (sin_c[0], sin_c[1], sin_c[2], sin_c[3])
    for i in range(r.shape[0]):
        ri = r[i]
        ji = j[i]
        u = (ri + k[K0]) * k[INV_H]
        idx = np.rint(u)
        d = (u - idx) * k[H]
        iu = int(idx)
        ii = iu
        if ii >= nodes:
            ii -= nodes
        # theta, sigma_p, delta_p, dtheta/dr, sin(theta/2), cos(theta/2) by Horner (degree 5,
        # unrolled); the phase rows stop before their constant term (v is their change from the node).
        a0 = tab[ii, 5, 0]
        a1 = tab[ii, 5, 1]
        a2 = tab[ii, 5, 2]
        a3 = tab[ii, 5, 3]
        a4 = tab[ii, 5, 4]
        a5 = tab[ii, 5, 5]
        a0 = a0 * d + tab[ii, 4, 0]
        a1 = a1 * d + tab[ii, 4, 1]
        a2 = a2 * d + tab[ii, 4, 2]
        a3 = a3 * d + tab[ii, 4, 3]
        a4 = a4 * d + tab[ii, 4, 4]
        a5 = a5 * d + tab[ii, 4, 5]
        a0 = a0 * d + tab[ii, 3, 0]
        a1 = a1 * d + tab[ii, 3, 1]
        a2 = a2 * d + tab[ii, 3, 2]
        a3 = a3 * d + tab[ii, 3, 3]
        a4 = a4 * d + tab[ii, 3, 4]
        a5 = a5 * d + tab[ii, 3, 5]
        a0 = a0 * d + tab[ii, 2, 0]
        a1 = a1 * d + tab[ii, 2, 1]
        a2 = a2 * d + tab[ii, 2, 2]
        a3 = a3 * d + tab[ii, 2, 3]
        a4 = a4 * d + tab[ii, 2, 4]
        a5 = a5 * d + tab[ii, 2, 5]
        a0 = a0 * d + tab[ii, 1, 0]
        a1 = a1 * d + tab[ii, 1, 1]
        a2 = a2 * d + tab[ii, 1, 2]
        a3 = a3 * d + tab[ii, 1, 3]
        a4 = a4 * d + tab[ii, 1, 4]
        a5 = a5 * d + tab[ii, 1, 5]
        theta = a0 * d + tab[ii, 0, 0]
        v1 = a1 * d
        v2 = a2 * d
        sp = v1 + tab[ii, 0, 1]
        dp = v2 + tab[ii, 0, 2]
        dth = a3 * d + tab[ii, 0, 3]
        sh = a4 * d + tab[ii, 0, 4]
        ch = a5 * d + tab[ii, 0, 5]
        # exp(i sigma) = exp(i j A) exp(i g(node)) exp(i (c d + v)), and the same for delta.
        jj = i if jidx < 0 else int(ji) - jidx
        dn = ri - node_r[iu]  # exact: r is within h/2 of its node
        ec, es = _cis(k[SC] * dn + v1, cc, sc)
        nc = phasor[0, 0, iu] * ec - phasor[0, 1, iu] * es
        ns = phasor[0, 0, iu] * es + phasor[0, 1, iu] * ec
        cs = jtab[0, 0, jj] * nc - jtab[0, 1, jj] * ns
        ss = jtab[0, 0, jj] * ns + jtab[0, 1, jj] * nc
        ec, es = _cis(k[DC] * dn + v2, cc, sc)
        nc = phasor[1, 0, iu] * ec - phasor[1, 1, iu] * es
        ns = phasor[1, 0, iu] * es + phasor[1, 1, iu] * ec
        cd = jtab[1, 0, jj] * nc - jtab[1, 1, jj] * ns
        sd = jtab[1, 0, jj] * ns + jtab[1, 1, jj] * nc
        # The Euler angles (phi, psi wrapped to [-pi, pi]) from the secular phases.
        sig = _secular(ji, ri, k, k[SA1], k[SA2], k[SA3], k[SC], k[SOFF], k[W0]) + (sp - k[SP0])
        dlt = _secular(ji, ri, k, k[DA1], k[DA2], k[DA3], k[DC], k[DOFF], k[W0]) + (dp - k[DP0])
        x = 2.0 * sh * sh
        y = 2.0 * ch * ch
        bx = k[B_] / x
        cy = k[C_] / y
        thetadot = k[LAM0] * dth
        uu = 1.0 - x if x <= 1.0 else y - 1.0
        ps = 0.5 * (k[B_] * ch / sh + k[C_] * sh / ch)  # phidot sin(theta)
        out[0, i] = theta
        out[1, i] = _wrap(sig + dlt, k)
        out[2, i] = _wrap(sig - dlt, k)
        out[3, i] = thetadot
        out[4, i] = 0.5 * (bx + cy)
        out[5, i] = k[W3MA] - 0.5 * (bx - cy)
        out[6, i] = uu
        qw = ch * cs
        qx = sh * cd
        qy = sh * sd
        qz = ch * ss
        quat[i, 0] = qw
        quat[i, 1] = qx
        quat[i, 2] = qy
        quat[i, 3] = qz
        sin_t = 2.0 * sh * ch
        axis[i, 0] = sin_t * (ss * cd + cs * sd)  # sin(theta) sin(phi)
        axis[i, 1] = -(sin_t * (cs * cd - ss * sd))
        axis[i, 2] = uu
        spsi = ss * cd - cs * sd
        cpsi = cs * cd + ss * sd
        w1 = ps * spsi + thetadot * cpsi
        w2 = ps * cpsi - thetadot * spsi
        w3 = k[W3]
        omega[i, 0] = w1
        omega[i, 1] = w2
        omega[i, 2] = w3
        # E, p_phi, p_psi from omega and the vertical in the body (HeavyTopModel.invariants).
        g1 = 2.0 * (qx * qz - qw * qy)
        g2 = 2.0 * (qy * qz + qw * qx)
        out[7, i] = (k[HALF_I1] * (w1 * w1 + w2 * w2) + k[HALF_I3] * (w3 * w3)) + k[MGL] * uu
        out[8, i] = k[I1_] * (w1 * g1 + w2 * g2) + (k[I3_] * w3) * uu
        out[9, i] = k[I3_] * w3


def motion(r, j, jidx, table, node_r, phasor, jtab, cos_c, sin_c, constants):
    """The motion at reduced phases ``r`` and half-periods ``j``.

    Parameters
    ----------
    r, j : numpy.ndarray
        From :func:`phase`.
    jidx : int
        ``jtab[..., j - jidx]`` holds exp(i j A) of each phase; -1: ``jtab[..., i]`` per sample.
    table : numpy.ndarray
        (S, 6, 6) node-major Taylor coefficients (degree 5).
    node_r : numpy.ndarray
        (S + 1,) the nodes' reduced phases.
    phasor : numpy.ndarray
        (2, 2, S + 1): cos and sin of sigma and delta's node parts.
    jtab : numpy.ndarray
        (2, 2, M): cos and sin of the whole-period advances.
    cos_c, sin_c : numpy.ndarray
        The four Taylor coefficients of cos and sin in x^2.
    constants : numpy.ndarray
        :data:`CONSTANTS`.

    Returns
    -------
    out, omega, quaternion, axis : numpy.ndarray
        ``out`` (10, N): theta, phi, psi, thetadot, phidot, psidot, u, E, p_phi, p_psi;
        omega (N, 3), quaternion (N, 4), axis (N, 3).
    """
    if table.shape[1:] != (6, 6):
        raise ValueError("a table of six rows of degree-5 Taylor coefficients per node")
    n = r.size
    # One allocation carved into the outputs: a fresh multi-megabyte array per output costs
    # a page fault per 4 kB (about as much as the arithmetic) whenever the allocator maps it anew.
    buf = np.empty(20 * n)
    out = buf[: 10 * n].reshape(10, n)
    omega = buf[10 * n : 13 * n].reshape(n, 3)
    quat = buf[13 * n : 17 * n].reshape(n, 4)
    axis = buf[17 * n :].reshape(n, 3)
    _motion(r, j, int(jidx), table, node_r, phasor, jtab, cos_c, sin_c, constants, out, omega, quat, axis)
    return out, omega, quat, axis
