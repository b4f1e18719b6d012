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
tables per coefficient; here the samples go in blocks of :data:`_BLOCK` through a
cache-resident scratch array, and the outputs are the only large memory written. Within
a block a scalar pass gathers (the nodes' coefficients and phasors) and a second pass,
which gathers nothing, does the rest four samples per instruction (LLVM's loop
vectoriser, with :func:`_horner6`); a third pass writes the block out by non-temporal
stores (:func:`_stream4`). docs/heavy-top.md gives the times of each step. The
arithmetic is the NumPy path's, operation for operation and without fused multiply-adds, so
the two agree bit for bit (tested, at and across block ends).

Numba is imported only with the compiled modules (~0.4 s once per process).
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from wobble.numerics import compiled as _compiled
from wobble.numerics.double_double import SPLIT_THRESHOLD, WHOLE_PIECES
from wobble.numerics.phase import PER_SAMPLE, reduce_phase


__all__ = [
    "phase",
    "angles",
    "motion",
    "CONSTANTS",
    "carlson",
    "sample",
    "phasors",
    "check",
    "check_at",
    "prepare",
    "coefficients",
    "spectrum",
    "SAMPLE_CONSTANTS",
]

_compiled.listen()  # a command line may announce the first compilation (15 to 35 s after installing)
_jit = _compiled.njit(nogil=True, error_model="numpy")  # cached on disk where Numba can
_SPLITTER = 134217729.0  # 2^27 + 1

#: Layout of the constants vector handed to :func:`angles` and :func:`motion`.
CONSTANTS = (
    "K0",
    "h",
    "inv_h",
    "w0",
    "lam0",
    "hx1",
    "hy2",
    "B_x1",
    "C_y2",
    "Bp",
    "Cp",
    "w3",
    "w3_minus_a",
    "sig_a1",
    "sig_a2",
    "sig_a3",
    "sig_c",
    "sig_off",
    "sig_p0",
    "dlt_a1",
    "dlt_a2",
    "dlt_a3",
    "dlt_c",
    "dlt_off",
    "dlt_p0",
    "tp0",
    "tp1",
    "tp2",
    "inv_two_pi",
    "two_pi",
    "half_inv_pi",
    "energy_I1",
    "energy_I3",
    "I1",
    "I3",
    "mgl",
    "E0",
    "p_phi0",
    "p_psi0",
    "phi_a1",
    "phi_a2",
    "phi_a3",
    "phi_c",
    "phi_off",
    "psi_a1",
    "psi_a2",
    "psi_a3",
    "psi_c",
    "psi_off",
    "energy_mgl",
    "energy_scale",
)
(
    K0,
    H,
    INV_H,
    W0,
    LAM0,
    HX1,
    HY2,
    BX1,
    CY2,
    BP,
    CP,
    W3,
    W3MA,
    SA1,
    SA2,
    SA3,
    SC,
    SOFF,
    SP0,
    DA1,
    DA2,
    DA3,
    DC,
    DOFF,
    DP0,
    TP0,
    TP1,
    TP2,
    INV_TP,
    TWO_PI,
    HALF_INV_PI,
    EI1,
    EI3,
    I1_,
    I3_,
    MGL,
    E0_,
    PPHI0_,
    PPSI0_,
    FA1,
    FA2,
    FA3,
    FC,
    FOFF,
    QA1,
    QA2,
    QA3,
    QC,
    QOFF,
    EMGL,
    ESCALE,
) = range(len(CONSTANTS))


@_jit
def _two_prod(a, b):
    """Dekker's exact product a b = p + e (wobble.numerics.double_double.two_prod, operands below 2^996)."""
    p = a * b
    c = _SPLITTER * a
    ah = c - (c - a)
    al = a - ah
    c = _SPLITTER * b
    bh = c - (c - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@_jit
def _phase(t, lam0, lam1, w0, p1, p2, p3, period, r_out, j_out):
    # No reduction in this loop (the range of j is NumPy's min and max afterwards): a running
    # min/max is a floating-point reduction LLVM may not reorder, which kept the loop scalar
    # (0.12-0.14 ms for 20,001 times against 0.05 ms vectorised, with the min and max).
    half = 0.5 * period
    for i in range(t.shape[0]):
        ti = t[i]
        p, e = _two_prod(ti, lam0)
        e = e + ti * lam1
        x = p + w0
        bb = x - p
        e2 = (p - (x - bb)) + (w0 - bb)
        lo = e + e2
        j = np.rint((x + lo) / period)
        # Exact for |j| < 2^26; phase() leaves larger j to NumPy's reduction (a branch for them here
        # kept LLVM from vectorising the loop: 0.42 ms for 20,001 times against 0.31).
        r = ((x - j * p1) - j * p2) + (lo - j * p3)
        if r > half:
            r = ((r - p1) - p2) - p3
            j = j + 1.0
        elif r < -half:
            r = ((r + p1) + p2) + p3
            j = j - 1.0
        r_out[i] = r
        j_out[i] = j


def phase(t, lam, period, offset, pieces, with_range=False):
    """Reduced nutation phase r and whole half-periods j of ``lam * t + offset`` (as
    :func:`wobble.numerics.phase.reduce_phase`, bit for bit; ``pieces`` = its three-float
    split of ``period``); ``with_range``: also the smallest and largest j."""
    t = np.ascontiguousarray(t, dtype=float)
    r = np.empty_like(t)
    j = np.empty_like(t)
    if t.size and np.max(np.abs(t)) > SPLIT_THRESHOLD:
        # Times past 2^996 s: Veltkamp's split of t overflows here, where NumPy's scales it first
        # (wobble.numerics.double_double); the few tops whose span reaches that take NumPy's reduction.
        r, j = reduce_phase(t, lam, period, offset)
    else:
        _phase(
            t,
            float(lam[0]),
            float(lam[1]),
            float(offset),
            float(pieces[0]),
            float(pieces[1]),
            float(pieces[2]),
            float(period[0]),
            r,
            j,
        )
        if np.any(np.abs(j) >= WHOLE_PIECES):  # past 2^26 half-periods: Dekker's exact j period
            r, j = reduce_phase(t, lam, period, offset)
    if with_range:  # a nan time gives a nan range (np.min and np.max propagate it); none: (inf, -inf)
        return r, j, (float(np.min(j)), float(np.max(j))) if j.size else (np.inf, -np.inf)
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
        # phi = sigma + delta and psi = sigma - delta, each from its own secular phase (a fast spin in
        # sigma's and delta's would cancel into phi).
        sp = a1 - k[SP0]
        dp = a2 - k[DP0]
        phi = _secular(j[i], r[i], k, k[FA1], k[FA2], k[FA3], k[FC], k[FOFF], k[W0]) + (sp + dp)
        psi = _secular(j[i], r[i], k, k[QA1], k[QA2], k[QA3], k[QC], k[QOFF], k[W0]) + (sp - dp)
        out[0, i] = a0
        out[1, i] = _wrap(phi, k)
        out[2, i] = _wrap(psi, k)


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


@intrinsic
def _horner6(typingctx, tab, ii, d):
    """The six degree-5 Horner sums of node ``ii`` of a C-contiguous (S, 6, 6) table at ``d``,
    four rows and two rows per instruction: (theta, v1, v2, sigma_p, delta_p, dtheta/dr,
    sin(theta/2), cos(theta/2)) with v = a d the phase rows' change from the node.

    Why by hand: a node's six coefficients of one order are contiguous, but Numba leaves
    LLVM's vectoriser of straight-line code off (NUMBA_SLP_VECTORIZE), so the scalar sums
    took 0.20 ms for 20,001 samples against 0.08 ms here. Each lane does the scalar
    sequence (a multiply, then an add; no fused multiply-add), so the sums are the same to
    the bit as the NumPy path's.
    """
    if not (isinstance(tab, types.Array) and tab.ndim == 3 and tab.dtype == types.float64 and tab.layout == "C"):
        return None
    signature = types.UniTuple(types.float64, 8)(tab, ii, d)

    def codegen(context, builder, sig, args):
        tab_v, ii_v, d_v = args
        i64, i32 = ir.IntType(64), ir.IntType(32)
        v4, v2 = ir.VectorType(ir.DoubleType(), 4), ir.VectorType(ir.DoubleType(), 2)
        data = context.make_array(sig.args[0])(context, builder, tab_v).data
        node = builder.gep(data, [builder.mul(context.cast(builder, ii_v, sig.args[1], types.int64), i64(36))])

        def load(order, row, vt):  # rows row..row+len(vt) of one order: contiguous
            ptr = builder.bitcast(builder.gep(node, [i64(6 * order + row)]), vt.as_pointer())
            return builder.load(ptr, align=8)

        d1 = builder.insert_element(ir.Constant(v4, ir.Undefined), d_v, i32(0))
        d4 = builder.shuffle_vector(d1, d1, ir.Constant(ir.VectorType(i32, 4), [0, 0, 0, 0]))
        d2 = builder.shuffle_vector(d1, d1, ir.Constant(ir.VectorType(i32, 2), [0, 0]))
        a4, a2 = load(5, 0, v4), load(5, 4, v2)
        for order in range(4, 0, -1):
            a4 = builder.fadd(builder.fmul(a4, d4), load(order, 0, v4))
            a2 = builder.fadd(builder.fmul(a2, d2), load(order, 4, v2))
        p4, p2 = builder.fmul(a4, d4), builder.fmul(a2, d2)
        r4, r2 = builder.fadd(p4, load(0, 0, v4)), builder.fadd(p2, load(0, 4, v2))

        def lane(v, k):
            return builder.extract_element(v, i32(k))

        values = [
            lane(r4, 0),
            lane(p4, 1),
            lane(p4, 2),
            lane(r4, 1),
            lane(r4, 2),
            lane(r4, 3),
            lane(r2, 0),
            lane(r2, 1),
        ]
        return context.make_tuple(builder, sig.return_type, values)

    return signature, codegen


@intrinsic
def _stream4(typingctx, arr, idx, a, b, c, d):
    """``arr[idx : idx + 4] = (a, b, c, d)``: one aligned non-temporal vector store (``vmovntpd``).

    For the outputs of :func:`_motion` (3.7 MB for 20,001 samples, more than this machine's 2 MB
    L2 cache): a non-temporal store writes a whole cache line without reading it first, where
    the plain copy-out read every output line before writing it, and the interleaved outputs
    (omega, the axis: three values per sample) go out as whole vectors instead of shuffled
    scalars (docs/heavy-top.md: the kernel's time with and without them). ``arr`` must be C-contiguous 1-D
    float64 with ``arr[idx]`` 32-byte aligned (the caller's duty: a misaligned address faults).
    """
    if not (isinstance(arr, types.Array) and arr.ndim == 1 and arr.dtype == types.float64 and arr.layout == "C"):
        return None
    signature = types.void(arr, idx, a, b, c, d)

    def codegen(context, builder, sig, args):
        v4 = ir.VectorType(ir.DoubleType(), 4)
        data = context.make_array(sig.args[0])(context, builder, args[0]).data
        ptr = builder.gep(data, [context.cast(builder, args[1], sig.args[1], types.int64)])
        vec = ir.Constant(v4, ir.Undefined)
        for lane in range(4):
            value = context.cast(builder, args[2 + lane], sig.args[2 + lane], types.float64)
            vec = builder.insert_element(vec, value, ir.IntType(32)(lane))
        store = builder.store(vec, builder.bitcast(ptr, v4.as_pointer()), align=32)
        store.set_metadata("nontemporal", builder.module.add_metadata([ir.IntType(32)(1)]))
        return context.get_dummy_value()

    return signature, codegen


@intrinsic
def _store_fence(typingctx):
    """A sequentially consistent fence (on x86-64 a locked instruction, which drains the
    write-combining buffers): non-temporal stores are weakly ordered, and the outputs of
    :func:`_motion` may be handed to another thread (a dask worker) next."""
    signature = types.void()

    def codegen(context, builder, sig, args):
        builder.fence("seq_cst")
        return context.get_dummy_value()

    return signature, codegen


@_jit
def _turn(x, cc, sc, pc, ps, jc, js):
    """cos and sin of a sample's phase: exp(i j A) exp(i g(node)) exp(i x) from the period's
    phasor (jc, js), the node's (pc, ps) and the small remainder x (:func:`_cis`)."""
    ec, es = _cis(x, cc, sc)
    nc = pc * ec - ps * es
    ns = pc * es + ps * ec
    return jc * nc - js * ns, jc * ns + js * nc


#: Samples per block of :func:`_motion`: its 35 rows of intermediates (36 kB) stay in the L1/L2
#: caches. (512 was 2.7 times slower: rows 4 kB apart alias in the load/store unit.)
_BLOCK = 128
# _stream4 writes whole 32-byte vectors: a block, like every output's stride, holds whole vectors.
assert _BLOCK % 4 == 0
# The rows of a block: what the scalar pass gathers (0-18), what the vectorised pass computes (19-34).
(_R, _J, _TH, _V1, _V2, _SP, _DP, _DTH, _SH, _CH, _DN, _PSC, _PSS, _PDC, _PDS, _JSC, _JSS, _JDC, _JDS) = range(19)
(_PHI, _PSI, _THD, _PHD, _PSD, _U, _E, _PPHI, _W1, _W2, _QW, _QX, _QY, _QZ, _AX, _AY) = range(19, 35)
_ROWS = 35
#: Rows of :func:`_motion`'s ``out``: theta, phi, psi, thetadot, phidot, psidot, u, E, p_phi, p_psi and
#: the drifts of the last three from their initial values.
_OUT_ROWS = 13


@_jit
def _motion(r, j, jidx, tab, node_r, phasor, jtab, cos_c, sin_c, k, out, stride, omega, quat, axis):
    # Three passes per block of _BLOCK samples, so that most of the arithmetic is vectorised
    # (LLVM vectorises a loop only if it gathers nothing and provably writes nowhere it reads):
    # (1) scalar: the node of each sample, the Horner sums from the node's coefficients and the
    # node's and period's phasors, gathered into the block's rows; (2) everything else from those
    # rows, four samples per instruction, into more rows of the same local array (whose rows LLVM
    # knows apart); (3) the rows copied to the outputs by aligned non-temporal stores. The
    # operations and their order are those of the NumPy path, so the two agree bit for bit.
    n = r.shape[0]
    nodes = tab.shape[0]
    s = np.empty((_ROWS, _BLOCK))
    cc = (cos_c[0], cos_c[1], cos_c[2], cos_c[3])
    sn = (sin_c[0], sin_c[1], sin_c[2], sin_c[3])
    k0, inv_h, h = k[K0], k[INV_H], k[H]
    hx1, hy2, bx1, cy2, bp, cp = k[HX1], k[HY2], k[BX1], k[CY2], k[BP], k[CP]
    lam0, w3, w3ma = k[LAM0], k[W3], k[W3MA]
    i1, i3 = k[I1_], k[I3_]
    ei1, ei3, emgl, escale = k[EI1], k[EI3], k[EMGL], k[ESCALE]
    e0, p_phi0 = k[E0_], k[PPHI0_]
    p_psi = i3 * w3
    p_psi_drift = p_psi - k[PPSI0_]
    for start in range(0, n, _BLOCK):
        m = min(_BLOCK, n - start)
        for b in range(m):  # (1) gather
            i = start + b
            ri = r[i]
            ji = j[i]
            u = (ri + k0) * inv_h
            idx = np.rint(u)
            d = (u - idx) * h
            iu = int(idx)
            ii = iu
            if ii >= nodes:
                ii -= nodes
            # theta, sigma_p, delta_p, dtheta/dr, sin(theta/2), cos(theta/2) by Horner (degree 5); the
            # phase rows stop before their constant term (v is their change from the node).
            theta, v1, v2, sp, dp, dth, sh, ch = _horner6(tab, ii, d)
            s[_R, b] = ri
            s[_J, b] = ji
            s[_TH, b] = theta
            s[_V1, b] = v1
            s[_V2, b] = v2
            s[_SP, b] = sp
            s[_DP, b] = dp
            s[_DTH, b] = dth
            s[_SH, b] = sh
            s[_CH, b] = ch
            s[_DN, b] = ri - node_r[iu]  # exact: r is within h/2 of its node
            s[_PSC, b] = phasor[0, 0, iu]
            s[_PSS, b] = phasor[0, 1, iu]
            s[_PDC, b] = phasor[1, 0, iu]
            s[_PDS, b] = phasor[1, 1, iu]
            jj = i if jidx == PER_SAMPLE else int(ji) - jidx
            s[_JSC, b] = jtab[0, 0, jj]
            s[_JSS, b] = jtab[0, 1, jj]
            s[_JDC, b] = jtab[1, 0, jj]
            s[_JDS, b] = jtab[1, 1, jj]
        for b in range(m):  # (2) compute
            ri = s[_R, b]
            ji = s[_J, b]
            sh = s[_SH, b]
            ch = s[_CH, b]
            dn = s[_DN, b]
            cs, ss = _turn(k[SC] * dn + s[_V1, b], cc, sn, s[_PSC, b], s[_PSS, b], s[_JSC, b], s[_JSS, b])
            cd, sd = _turn(k[DC] * dn + s[_V2, b], cc, sn, s[_PDC, b], s[_PDS, b], s[_JDC, b], s[_JDS, b])
            # The Euler angles (phi, psi wrapped to [-pi, pi]), each from its own secular phase: sigma's
            # and delta's carry a fast spin that would cancel into phi = sigma + delta.
            spr = s[_SP, b] - k[SP0]
            dpr = s[_DP, b] - k[DP0]
            phi = _secular(ji, ri, k, k[FA1], k[FA2], k[FA3], k[FC], k[FOFF], k[W0]) + (spr + dpr)
            psi = _secular(ji, ri, k, k[QA1], k[QA2], k[QA3], k[QC], k[QOFF], k[W0]) + (spr - dpr)
            x = 2.0 * sh * sh
            y = 2.0 * ch * ch
            # B/x and C/y as the closed form takes them (top_closed_form.Elliptic.core): scaled by the
            # turning points, so that a tilt whose sin^2(theta/2) underflows still gives them.
            sx = sh / hx1
            sy = ch / hy2
            bx = bx1 / (sx * sx) if bx1 != 0.0 else 0.0
            cy = cy2 / (sy * sy) if cy2 != 0.0 else 0.0
            thetadot = lam0 * s[_DTH, b]
            uu = 1.0 - x if x <= 1.0 else y - 1.0
            ps = (bp * sy / sx if bp != 0.0 else 0.0) + (cp * sx / sy if cp != 0.0 else 0.0)  # phidot sin(theta)
            s[_PHI, b] = _wrap(phi, k)
            s[_PSI, b] = _wrap(psi, k)
            s[_THD, b] = thetadot
            s[_PHD, b] = 0.5 * (bx + cy)
            s[_PSD, b] = w3ma - 0.5 * (bx - cy)
            s[_U, b] = uu
            qw = ch * cs
            qx = sh * cd
            qy = sh * sd
            qz = ch * ss
            s[_QW, b] = qw
            s[_QX, b] = qx
            s[_QY, b] = qy
            s[_QZ, b] = qz
            sin_t = 2.0 * sh * ch
            s[_AX, b] = sin_t * (ss * cd + cs * sd)  # sin(theta) sin(phi)
            s[_AY, b] = -(sin_t * (cs * cd - ss * sd))
            spsi = ss * cd - cs * sd
            cpsi = cs * cd + ss * sd
            w1 = ps * spsi + thetadot * cpsi
            w2 = ps * cpsi - thetadot * spsi
            s[_W1, b] = w1
            s[_W2, b] = w2
            # E, p_phi, p_psi from omega and the vertical in the body (HeavyTopModel.invariants).
            g1 = 2.0 * (qx * qz - qw * qy)
            g2 = 2.0 * (qy * qz + qw * qx)
            # As HeavyTopModel: (I w) w, not I w^2 (the squares overflow for I1 = 5e-324 kg m2, 1e157 rad/s),
            # in units of energy_scale (1 unless the energy nears the largest double: top_series.energy_terms).
            s[_E, b] = ((0.5 * ((ei1 * w1) * w1 + (ei1 * w2) * w2) + 0.5 * ((ei3 * w3) * w3)) + emgl * uu) * escale
            s[_PPHI, b] = i1 * (w1 * g1 + w2 * g2) + (i3 * w3) * uu
        # (3) copy out: a whole block by aligned non-temporal stores (_stream4), four values each;
        # the last, partial block by plain ones. The omega and axis blocks (three per sample) are
        # whole vectors too: four samples are twelve values, three stores.
        if m == _BLOCK:
            for row, src in enumerate((_TH, _PHI, _PSI, _THD, _PHD, _PSD, _U, _E, _PPHI)):
                at = row * stride + start
                for b in range(0, m, 4):
                    _stream4(out, at + b, s[src, b], s[src, b + 1], s[src, b + 2], s[src, b + 3])
            at = 9 * stride + start
            for b in range(0, m, 4):
                _stream4(out, at + b, p_psi, p_psi, p_psi, p_psi)
            for row, src, start_value in ((10, _E, e0), (11, _PPHI, p_phi0)):  # the drifts
                at = row * stride + start
                for b in range(0, m, 4):
                    _stream4(
                        out,
                        at + b,
                        s[src, b] - start_value,
                        s[src, b + 1] - start_value,
                        s[src, b + 2] - start_value,
                        s[src, b + 3] - start_value,
                    )
            at = 12 * stride + start
            for b in range(0, m, 4):
                _stream4(out, at + b, p_psi_drift, p_psi_drift, p_psi_drift, p_psi_drift)
            for b in range(m):
                _stream4(quat, 4 * (start + b), s[_QW, b], s[_QX, b], s[_QY, b], s[_QZ, b])
            for b in range(0, m, 4):
                at = 3 * (start + b)
                _stream4(axis, at, s[_AX, b], s[_AY, b], s[_U, b], s[_AX, b + 1])
                _stream4(axis, at + 4, s[_AY, b + 1], s[_U, b + 1], s[_AX, b + 2], s[_AY, b + 2])
                _stream4(axis, at + 8, s[_U, b + 2], s[_AX, b + 3], s[_AY, b + 3], s[_U, b + 3])
                _stream4(omega, at, s[_W1, b], s[_W2, b], w3, s[_W1, b + 1])
                _stream4(omega, at + 4, s[_W2, b + 1], w3, s[_W1, b + 2], s[_W2, b + 2])
                _stream4(omega, at + 8, w3, s[_W1, b + 3], s[_W2, b + 3], w3)
            continue
        for row, src in enumerate((_TH, _PHI, _PSI, _THD, _PHD, _PSD, _U, _E, _PPHI)):
            for b in range(m):
                out[row * stride + start + b] = s[src, b]
        for b in range(m):
            out[9 * stride + start + b] = p_psi
            out[10 * stride + start + b] = s[_E, b] - e0
            out[11 * stride + start + b] = s[_PPHI, b] - p_phi0
            out[12 * stride + start + b] = p_psi_drift
        for b in range(m):
            at = start + b
            quat[4 * at] = s[_QW, b]
            quat[4 * at + 1] = s[_QX, b]
            quat[4 * at + 2] = s[_QY, b]
            quat[4 * at + 3] = s[_QZ, b]
            axis[3 * at] = s[_AX, b]
            axis[3 * at + 1] = s[_AY, b]
            axis[3 * at + 2] = s[_U, b]
            omega[3 * at] = s[_W1, b]
            omega[3 * at + 1] = s[_W2, b]
            omega[3 * at + 2] = w3
    _store_fence()  # the non-temporal stores are visible to every thread before the caller goes on


def motion(r, j, jidx, table, node_r, phasor, jtab, cos_c, sin_c, constants):
    """The motion at reduced phases ``r`` and half-periods ``j``.

    Parameters
    ----------
    r, j : numpy.ndarray
        From :func:`phase`.
    jidx : int
        ``jtab[..., j - jidx]`` holds exp(i j A) of each phase; :data:`PER_SAMPLE`: ``jtab[..., i]``
        per sample (a dense range may start at any j, negative ones included).
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
        ``out`` (13, N), rows of a padded buffer: theta, phi, psi, thetadot, phidot, psidot, u, E,
        p_phi, p_psi, and E - E0, p_phi - p_phi0, p_psi - p_psi0 (the constants' initial values);
        omega (N, 3), quaternion (N, 4), axis (N, 3).
    """
    if table.shape[1:] != (6, 6):
        raise ValueError("a table of six rows of degree-5 Taylor coefficients per node")
    n = r.size
    flat, stride, omega, quat, axis = _outputs(n)
    _motion(r, j, int(jidx), table, node_r, phasor, jtab, cos_c, sin_c, constants, flat, stride, omega, quat, axis)
    out = flat.reshape(_OUT_ROWS, stride)[:, :n]
    return out, omega.reshape(n, 3), quat.reshape(n, 4), axis.reshape(n, 3)


def _outputs(n: int):
    """The flat outputs of :func:`_motion` for ``n`` samples, carved from one allocation: 13 rows of
    ``stride`` values (n rounded up to a multiple of 4), then omega, the quaternions and the axis
    (n x 3, n x 4, n x 3 values), each starting on a 32-byte boundary as :func:`_stream4` needs.

    One allocation, because a fresh multi-megabyte array per output costs a page fault per 4 kB
    (about as much as the arithmetic) whenever the allocator maps it anew.
    """
    stride = -(-n // 4) * 4
    sizes = (_OUT_ROWS * stride, 3 * n, 4 * n, 3 * n)
    spans = [-(-size // 4) * 4 for size in sizes]  # each part padded to whole 32-byte vectors
    raw = np.empty(sum(spans) + 4)
    address = raw.ctypes.data
    assert address % 8 == 0  # NumPy aligns float64 arrays to 8 bytes (at least)
    first = (-address // 8) % 4  # the first 32-byte boundary (NumPy guarantees 8 bytes, not 32)
    parts, at = [], first
    for size, span in zip(sizes, spans):  # every span a multiple of 4 values: each part aligned too
        parts.append(raw[at : at + size])
        at += span
    flat, omega, quat, axis = parts
    return flat, stride, omega, quat, axis


# ---------------------------------------------------------------------------------------------
# The table's set-up, compiled: the samples of the direct evaluation, the phasors at the nodes
# and the check between the nodes (wobble.models.top_series.build; NumPy does the same when
# Numba is not in use). The arithmetic is that of the NumPy functions named, operation for
# operation; the transcendental functions are the C library's, as NumPy's are where it does
# not vectorise them, and Carlson's R_F, R_J, R_C are SciPy's own (scipy.special.cython_special).
# ---------------------------------------------------------------------------------------------
_CARLSON = None


def carlson():
    """SciPy's double-precision R_F, R_J and R_C as C function pointers callable from compiled
    code (the functions behind scipy.special.elliprf, elliprj, elliprc), or None."""
    global _CARLSON
    if _CARLSON is None:
        _CARLSON = _find_carlson() or False
    return _CARLSON or None


def _find_carlson():
    import ctypes

    try:
        from numba.extending import get_cython_function_address
        from scipy.special import cython_special
    except ImportError:  # pragma: no cover - SciPy is a dependency
        return None
    # A prototype of our own (setting restype on ctypes.pythonapi's shared one would change it for everyone).
    get_name = ctypes.PYFUNCTYPE(ctypes.c_char_p, ctypes.py_object)(("PyCapsule_GetName", ctypes.pythonapi))
    double = ctypes.c_double
    found = {}
    for key, capsule in getattr(cython_special, "__pyx_capi__", {}).items():
        for fn, nargs in (("elliprf", 3), ("elliprj", 4), ("elliprc", 2)):
            if not key.endswith(fn):
                continue
            # The real version of the fused function: "double (double, ..., int __pyx_skip_dispatch)".
            signature = (get_name(capsule) or b"").decode()
            if signature.replace(" ", "") == "double(" + "double," * nargs + "int__pyx_skip_dispatch)":
                addr = get_cython_function_address("scipy.special.cython_special", key)
                found[fn] = ctypes.CFUNCTYPE(double, *([double] * nargs), ctypes.c_int)(addr)
    if set(found) != {"elliprf", "elliprj", "elliprc"}:
        return None
    return found["elliprf"], found["elliprj"], found["elliprc"]


# The evaluator's constants for sample(): layout of the vector ``e``.
SAMPLE_CONSTANTS = (
    "m",
    "m1",
    "K",
    "k_lo",
    "scale",
    "rho_x",
    "rho_y",
    "hx1",
    "hy2",
    "W",
    "k_plus",
    "k_minus",
    "n_plus",
    "one_minus_n_plus",
    "nu_minus",
    "pi_plus_over_k",
    "pi_minus_over_k",
    "three_square",
)
(_M, _M1, _K, _KLO, _SCALE, _RX, _RY, _HX1, _HY2, _W, _KP, _KM, _NP, _OMNP, _NUM, _PPK, _PMK, _TSQ) = range(
    len(SAMPLE_CONSTANTS)
)
_SMALL_M = 1e-9  # wobble.numerics.elliptic._SMALL_M
_ASIN_SAFE = 0.5  # wobble.numerics.elliptic._ASIN_SAFE


@_jit
def _sign(x):
    if x > 0:
        return 1.0
    if x < 0:
        return -1.0
    return x  # 0.0, -0.0 or nan, as np.sign


@_jit
def _sample(r, e, ratios, ratios_b, rf_fn, rj_fn, rc_fn, out, raw):
    m, m1, kk = e[_M], e[_M1], e[_K]
    kp = np.sqrt(m1)
    for i in range(r.shape[0]):
        ri = r[i]
        # wobble.numerics.elliptic.jacobi_reduced (with _landen_amplitude)
        if m < _SMALL_M:
            s = np.sin(ri)
            c = np.cos(ri)
            corr = 0.25 * m * (ri - s * c)
            cn = c + corr * s
            sn = s - corr * c
            dn = np.sqrt(m1 + m * cn * cn)
        else:
            v = abs(ri)
            far = v > 0.5 * kk
            w = (kk - v) + e[_KLO] if far else v
            phi = e[_SCALE] * w
            for q in range(ratios.shape[0] - 1, -1, -1):
                ratio = ratios[q]
                x = ratio * np.sin(phi)
                if ratio > _ASIN_SAFE:
                    cphi = np.cos(phi)
                    sphi = np.sin(phi)
                    t = ratios_b[q] * sphi
                    phi = 0.5 * (phi + np.arctan2(x, np.sqrt(cphi * cphi + t * t)))
                else:
                    phi = 0.5 * (phi + np.arcsin(x))
            s = np.sin(phi)
            c = np.cos(phi)
            d = np.sqrt(m1 + m * c * c)
            if far:
                sn = c / d
                cn = kp * s / d
                dn = kp / d
            else:
                sn = s
                cn = c
                dn = d
            sn = np.copysign(sn, ri)
        # Elliptic._scaled, the half angles and theta
        sn2 = sn * sn
        cn2 = cn * cn
        sx = np.sqrt(cn2 + e[_RX] * sn2)
        sy = np.sqrt(e[_RY] * cn2 + sn2)
        sh = e[_HX1] * sx
        ch = e[_HY2] * sy
        # Elliptic.periodic_parts (pi_positive_scd, pi_negative_scd)
        d2 = dn * dn
        sg = _sign(sn)
        sa = abs(sn)
        c2 = cn * cn
        s2 = sa * sa
        p_plus = 0.0
        p_minus = 0.0
        rf = 0.0
        if e[_KP] != 0.0 or e[_KM] != 0.0:
            rf = rf_fn(c2, d2, 1.0, 0)
        if e[_KP] != 0.0:
            n = e[_NP]
            pp = c2 + e[_OMNP] * s2
            o = sa * rf
            if n > 0:
                rj = rj_fn(c2, d2, 1.0, pp if pp > 0 else 1.0, 0)
                o = o + ((n / 3.0) * sa * s2 * rj if sa > 0 else 0.0)
            p_plus = sg * o - e[_PPK] * ri
        if e[_KM] != 0.0:
            nu = e[_NUM]
            pm = 1.0 + nu * s2
            qm = c2 + m1 * s2 / (1.0 + nu)
            o = sa * rf / (1.0 + nu)
            if nu > 0:
                o = o + (nu * sa * cn * rc_fn(d2, pm * qm, 0) if nu > 0 else 0.0) / (1.0 + nu)
                if m1 > 0:
                    rj = rj_fn(c2, d2, 1.0, qm if qm > 0 else 1.0, 0)
                    numi = nu * m1
                    o = o + (numi * sa * s2 * rj if numi * sa > 0 else 0.0) / e[_TSQ]
            p_minus = sg * o - e[_PMK] * ri
        out[0, i] = 2.0 * np.arctan2(sh, ch)
        out[1, i] = e[_KM] * p_minus
        out[2, i] = e[_KP] * p_plus
        out[3, i] = -e[_W] * sn * cn * dn / (sx * sy)
        out[4, i] = sh
        out[5, i] = ch
        raw[0, i] = p_plus
        raw[1, i] = p_minus


def sample(r, constants, ratios, ratios_b, functions):
    """The six rows of :meth:`wobble.models.top_closed_form.Elliptic.periodic_with_half_angles`
    (6, N) and the raw P_+, P_- (2, N) at reduced phases ``r``; ``constants`` as
    :data:`SAMPLE_CONSTANTS` (``three_square`` is 3 (1 + nu_minus)**2 as Python's power rounds
    it, which is not always the product), ``ratios`` and ``ratios_b`` the Landen levels',
    ``functions`` from :func:`carlson`."""
    r = np.ascontiguousarray(r, dtype=float)
    out = np.empty((6, r.size))
    raw = np.empty((2, r.size))
    _sample(r, constants, ratios, ratios_b, *functions, out, raw)
    return out, raw


@_jit
def _two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@_jit
def _split27(a):
    c = _SPLITTER * a
    hi = c - (c - a)
    return hi, a - hi


@_jit
def _phasors(table, node_r, w0, c, offset, p0, phasor):
    nodes = table.shape[0]
    for p in range(2):
        cp = c[p]
        ch_, cl_ = _split27(cp)
        for i in range(nodes + 1):
            at = table[i if i < nodes else 0, 0, 1 + p]
            dh, dl = _two_sum(node_r[i], -w0)
            gh = cp * dh  # wobble.numerics.phase.two_prod(c, dh)
            bh, bl = _split27(dh)
            gl = ((ch_ * bh - gh) + ch_ * bl + cl_ * bh) + cl_ * bl
            gl = gl + cp * dl
            gh, e1 = _two_sum(gh, offset[p])
            ph, pl = _two_sum(at, -p0[p])
            gh, e2 = _two_sum(gh, ph)
            gl = gl + (e1 + (e2 + pl))
            cos_h = np.cos(gh)
            sin_h = np.sin(gh)
            phasor[p, 0, i] = cos_h - sin_h * gl
            phasor[p, 1, i] = sin_h + cos_h * gl


def phasors(table, node_r, w0, c, offset, p0):
    """cos and sin (2, 2, S + 1) of the node parts of sigma and delta (the NumPy lines of
    :func:`wobble.models.top_series._tabulate`)."""
    out = np.empty((2, 2, node_r.size))
    _phasors(
        table,
        node_r,
        float(w0),
        np.asarray(c, dtype=float),
        np.asarray(offset, dtype=float),
        np.asarray(p0, dtype=float),
        out,
    )
    return out


@_jit
def _direct_phasors(r, want, c, offset, start, w0, cos_g, sin_g):
    for i in range(r.shape[0]):
        for p in range(2):
            g = (c[p] * (r[i] - w0) + offset[p]) + (want[i, 1 + p] - start[p])
            cos_g[i, p] = np.cos(g)
            sin_g[i, p] = np.sin(g)


def check_at(r, want, table, node_r, phasor, k0, h, c, offset, start, w0, cos_c, sin_c):
    """:func:`check` with the direct phases' cosines and sines formed here: at j = 0 the phase of
    sigma (delta) is c (r - w0) + offset + (P(r) - P(r0)), with P(r) the row of ``want``."""
    r = np.ascontiguousarray(r, dtype=float)
    want = np.ascontiguousarray(want)
    cos_g = np.empty((r.size, 2))
    sin_g = np.empty((r.size, 2))
    c = np.asarray(c, dtype=float)
    _direct_phasors(
        r, want, c, np.asarray(offset, dtype=float), np.asarray(start, dtype=float), float(w0), cos_g, sin_g
    )
    return check(r, want, cos_g, sin_g, table, node_r, phasor, k0, h, c, cos_c, sin_c)


@_jit
def _check(r, want, cos_g, sin_g, tab, node_r, phasor, k0, h, inv_h, c, cos_c, sin_c, err):
    nodes = tab.shape[0]
    order = tab.shape[1] - 1
    rows = tab.shape[2]
    cc = (cos_c[0], cos_c[1], cos_c[2], cos_c[3])
    sc = (sin_c[0], sin_c[1], sin_c[2], sin_c[3])
    miss = 0.0
    for q in range(rows):
        err[q] = 0.0
    for i in range(r.shape[0]):
        u = (r[i] + k0) * inv_h
        idx = np.rint(u)
        d = (u - idx) * h
        iu = int(idx)
        ii = iu - nodes if iu >= nodes else iu
        dn = r[i] - node_r[iu]
        for q in range(rows):
            acc = tab[ii, order, q]
            for o in range(order - 1, 0, -1):
                acc = acc * d + tab[ii, o, q]
            acc = acc * d
            got = acc + tab[ii, 0, q]
            dev = abs(got - want[i, q])
            if dev > err[q] or dev != dev:
                err[q] = dev  # a nan stays (as np.max)
            if q == 1 or q == 2:
                ec, es = _cis(c[q - 1] * dn + acc, cc, sc)
                pc = phasor[q - 1, 0, iu]
                ps = phasor[q - 1, 1, iu]
                dev = np.hypot(pc * ec - ps * es - cos_g[i, q - 1], pc * es + ps * ec - sin_g[i, q - 1])
                if dev > miss or dev != dev:
                    miss = dev
    return miss


def check(r, want, cos_g, sin_g, table, node_r, phasor, k0, h, c, cos_c, sin_c):
    """The largest deviation of each row (rows,) of the table from ``want`` (N, rows) at the
    phases ``r``, and of the half angles' phasors from (cos_g, sin_g) (N, 2): the check of
    :func:`wobble.models.top_series._check_fourier` in one pass."""
    err = np.empty(table.shape[2])
    miss = _check(
        np.ascontiguousarray(r, dtype=float),
        np.ascontiguousarray(want),
        np.ascontiguousarray(cos_g),
        np.ascontiguousarray(sin_g),
        table,
        node_r,
        phasor,
        float(k0),
        float(h),
        1.0 / h,
        np.asarray(c, dtype=float),
        cos_c,
        sin_c,
        err,
    )
    return err, miss


@_jit
def _prepare(part, n, parity, vals, scales):
    half = n // 2
    rows = part.shape[0]
    for q in range(rows):
        big = 0.0
        for i in range(half + 1):
            v = part[q, i]
            vals[q, i] = v
            a = abs(v)
            if a > big or a != a:
                big = a
        for i in range(half + 1, n):
            v = parity[q] * part[q, n - i]
            vals[q, i] = v
            a = abs(v)
            if a > big or a != a:
                big = a
        scales[q] = big if big > 1e-300 or big != big else 1e-300
    # The phase rows (sigma's and delta's periodic parts) are judged in absolute terms (rad).
    ph = max(1.0, scales[1], scales[2])
    scales[1] = ph
    scales[2] = ph


def prepare(part, n, parity):
    """The samples over the whole period (rows, n) from those on [0, pi] (rows, n/2 + 1) by the
    rows' parity (+1 even, -1 odd), and each row's scale: max |value| (at least 1e-300; the
    two phase rows together, at least 1 rad)."""
    vals = np.empty((part.shape[0], n))
    scales = np.empty(part.shape[0])
    _prepare(np.ascontiguousarray(part), n, parity, vals, scales)
    return vals, scales


@_jit
def _coefficients(spectra, scales, n, noise, cos_rows, keep_level, max_terms, scale, coef):
    rows = spectra.shape[0]
    ncoef = spectra.shape[1]
    # Aliasing folds c_{n-k} onto c_k: the top of the band must be at rounding level.
    for q in range(rows):
        top = 0.0
        for kk in range(7 * n // 16, ncoef):
            a = np.hypot(spectra[q, kk].real, spectra[q, kk].imag)
            if a > top or a != a:
                top = a
        if not top <= noise * scales[q]:
            return 0, 0, 0.0, 0.0, 0.0
    last = 1
    for kk in range(ncoef):
        for q in range(rows):
            if kk == 0:
                c = spectra[q, 0].real if cos_rows[q] else 0.0
            else:
                c = 2.0 * spectra[q, kk].real if cos_rows[q] else -2.0 * spectra[q, kk].imag
            coef[q, kk] = c
            if abs(c) / scales[q] > keep_level:
                last = kk
    if last > max_terms:
        return 2, last, 0.0, 0.0, 0.0
    need = 0.0
    for q in range(rows):
        moment = 0.0
        for kk in range(last + 1):
            f = float(kk)
            moment += abs(coef[q, kk]) * (f * f * f * f * f * f)
        x = (moment / (720.0 * 2.220446049250313e-16 * scales[q])) ** (1.0 / 6.0)
        if x > need or x != x:
            need = x
    slope_s = 0.0
    slope_d = 0.0
    for kk in range(last + 1):
        slope_s += abs(coef[1, kk]) * (kk * scale)
        slope_d += abs(coef[2, kk]) * (kk * scale)
    return 1, last, np.pi * need, slope_s, slope_d


def coefficients(spectra, scales, n, noise, cos_rows, keep_level, max_terms, scale):
    """From the rows' spectra (rfft / n): 0 where the top of a band is above ``noise`` times its
    row's scale; otherwise the Fourier coefficients (rows, L + 1) up to the last whose size
    relative to its row's scale exceeds ``keep_level`` (2 and no table where L > ``max_terms``),
    the node count the Taylor remainder bound asks (sum_k |c_k| (k pi / S)^6 / 6! below each
    row's rounding) and the sums of |k c_k| ``scale`` of the two phase rows. The arithmetic of
    the NumPy lines of wobble.models.top_series.build and _fourier_from_spectra."""
    coef = np.empty((spectra.shape[0], spectra.shape[1]))
    status, last, need, slope_s, slope_d = _coefficients(
        spectra, scales, n, noise, cos_rows, keep_level, max_terms, scale, coef
    )
    return status, np.ascontiguousarray(coef[:, : last + 1]), need, slope_s, slope_d


@_jit
def _spectrum(coef, scale, cos_rows, fact, spec):
    rows = coef.shape[0]
    for kk in range(coef.shape[1]):
        sign = 1.0 if kk == 0 else (0.5 if kk % 2 == 0 else -0.5)
        a = kk * scale
        p = 1.0
        for j in range(fact.shape[0]):
            if j > 0:
                p = p * a
            w = p / fact[j]  # (k scale)^j / j!; times i^j
            for q in range(rows):
                v = coef[q, kk] * sign * w
                # i^j times the row's rotation: cos series 1, sin series -i.
                m = j % 4 if cos_rows[q] else (j + 3) % 4
                if m == 0:
                    spec[kk, j, q] = complex(v, 0.0)
                elif m == 1:
                    spec[kk, j, q] = complex(0.0, v)
                elif m == 2:
                    spec[kk, j, q] = complex(-v, 0.0)
                else:
                    spec[kk, j, q] = complex(0.0, -v)


def spectrum(coef, scale, nodes, cos_rows, fact):
    """The half-spectrum (nodes // 2 + 1, orders, rows) whose inverse real FFT is the Taylor
    table of wobble.models.top_series._taylor_table: c_k (-1)^k (halved for k >= 1)
    (i k scale)^j / j!, times -i for a sine series."""
    spec = np.zeros((nodes // 2 + 1, fact.shape[0], coef.shape[0]), dtype=np.complex128)
    _spectrum(coef, float(scale), cos_rows, fact, spec)
    return spec
