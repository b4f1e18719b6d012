"""The heavy top's series accelerator: its periodic parts as Fourier series (SI, float64; notes 5.7).

The nutating top's theta(r), the periodic parts of its half angles and dtheta/dr are
analytic and 2K-periodic in the reduced nutation phase r while the axis stays off the
poles (:meth:`wobble.models.top_closed_form.Elliptic.periodic_of_r`). Their Fourier
coefficients decay geometrically; :func:`build` computes them once per top by an FFT
of exact values and tabulates the series with their derivatives as Taylor expansions
at equispaced nodes, so that each output costs a degree-5 polynomial instead of
Jacobi functions and Carlson integrals (~3 us). The table is used only after it
reproduces the direct evaluation between the nodes within the solution's error
estimate; otherwise the model keeps the direct path.

The table of a top is built on first use and kept in :func:`series_of`'s cache, keyed
by the model and released with it: the frozen model itself holds no mutable state.
"""

from __future__ import annotations

import bisect
import math
import weakref
from dataclasses import dataclass, replace

import numpy as np

from wobble.numerics.floats import EPS
from wobble.models.top_closed_form import TWO_PI, TWO_PI_PIECES
from wobble.numerics import compiled
from wobble.numerics.double_double import WHOLE_PIECES, two_prod, two_sum
from wobble.numerics.phase import PER_SAMPLE, split_dd

__all__ = ["MIN_SAMPLES", "Fourier", "build", "series_of", "wrap_angle", "blocked"]

_ORDER = 5  # degree of the Taylor polynomials
# The tabulated rows: theta (even), the periodic parts k_- P_- of sigma and k_+ P_+ of delta
# (odd), dtheta/dr (odd), sin(theta/2) and cos(theta/2) (even).
_KINDS = ("cos", "sin", "sin", "sin", "cos", "cos")
_SIGMA, _DELTA = 1, 2
_ROT = np.array([1.0 if k == "cos" else -1j for k in _KINDS])  # cos series: c_k = a_k; sin: c_k = -i b_k
_ORDERS = np.arange(_ORDER + 1)
_FACT = np.cumprod(np.concatenate([[1.0], np.arange(1.0, _ORDER + 1)]))
# exp(i x) for |x| <= 1/32 by its Taylor polynomials in x^2: the first terms left out,
# x^8/8! and x^9/9!, are below 3e-17 and 1e-19 there.
_CIS_MAX = 1 / 32
_COS = np.array([1.0, -1 / 2, 1 / 24, -1 / 720])
_SIN = np.array([1.0, -1 / 6, 1 / 120, -1 / 5040])
_BLOCK = 8192


@dataclass(frozen=True)
class Fourier:
    """The periodic parts as Fourier series in the nutation phase, tabulated (fast evaluation).

    theta(r) (even), k_- P_-(r), k_+ P_+(r), dtheta/dr (odd), sin(theta/2) and cos(theta/2)
    (even) are analytic and 2K-periodic in the reduced phase r while the axis stays off
    the poles; their Fourier coefficients in vartheta = pi r / K decay geometrically and are
    computed once by an FFT of exact values
    (:meth:`~wobble.models.top_closed_form.Elliptic.periodic_with_half_angles`). For
    evaluation the series are tabulated with their derivatives up to order 5 at S equispaced
    phases (one batched inverse FFT), and each output takes a degree-5 Taylor polynomial from
    the nearest node: 5 Horner steps per series, whatever the series' length.

    The unit phasors exp(i sigma) and exp(i delta) of the half angles need no trigonometric
    call per output: with lambda t + w0 = 2K j + r and r = node + d,

        sigma = j A + [c node + P(node) + const] + [c d + P(r) - P(node)],

    the first factor exp(i j A) is computed once per whole period, the second once per node
    (``phasor``), and the third is the Taylor polynomial of cos and sin of a small argument
    (|x| <= 1/32: the nodes are dense enough for that). The node parts are formed in
    double-double arithmetic and d = r - node exactly, so the phasors carry a few ulps of
    error whatever the size of the secular term c node. The table is accepted only
    after it agrees with the direct evaluation between the nodes to within the solution's
    error estimate (:func:`build`); otherwise the direct path is used.
    """

    base: object  # the Elliptic evaluator (wobble.models.top_closed_form)
    coef: np.ndarray  # (6, L + 1) Fourier coefficients of the rows (_KINDS)
    scale: float  # pi / K
    table: np.ndarray  # (S, order + 1, 6): f^(j)(node) / j! in units of r, node-major
    h: float  # node spacing in r
    phasor: np.ndarray | None = None  # (2, 2, S + 1): cos, sin of sigma's and delta's node parts
    node_r: np.ndarray | None = None  # (S + 1,) the nodes -K + i h, as the phasors take them
    error_theta: float = 0.0
    error_phase: float = 0.0
    # k_- P_-(r0) and k_+ P_+(r0): the periodic parts of sigma and delta at t = 0, as the samples
    # the series come from give them (the direct path's own when the samples are NumPy's).
    start: tuple = (0.0, 0.0)
    compiled: bool = False  # set up with the compiled helpers (wobble.numerics.taylor_table)

    # -- building and checking -------------------------------------------------
    def clenshaw(self, r, rows):
        """The series summed directly (Clenshaw), for building and checking the table."""
        vt = r * self.scale
        c, s_ = np.cos(vt), np.sin(vt)
        alpha = 2.0 * c
        coef = self.coef[list(rows)]
        nrow, ncoef = coef.shape
        b1 = np.zeros((nrow,) + r.shape)
        b2 = np.zeros_like(b1)
        tmp = np.empty_like(b1)
        for k in range(ncoef - 1, 0, -1):
            np.multiply(alpha, b1, out=tmp)
            tmp -= b2
            tmp += coef[:, k, None]
            b1, b2, tmp = tmp, b1, b2
        out = []
        for i, row in enumerate(rows):
            out.append(coef[i, 0] + b1[i] * c - b2[i] if _KINDS[row] == "cos" else b1[i] * s_)
        return out

    def _nodes(self, r):
        """Nearest node of each reduced phase: series index (wrapped), phasor index, offset d."""
        u = (r + self.base.K[0]) * (1.0 / self.h)
        idx = np.rint(u)
        d = (u - idx) * self.h
        iu = idx.astype(np.intp)
        ii = iu.copy()
        ii[ii >= self.table.shape[0]] -= self.table.shape[0]  # r = +K is the node of r = -K
        return ii, iu, d

    @staticmethod
    def _horner(coef, row, d, split=False):
        """Row ``row`` from the gathered coefficients ``coef`` (N, order + 1, rows) at offsets ``d``.
        ``split``: also its change from the node, v = f(r) - f(node)."""
        acc = coef[:, _ORDER, row].copy()
        for j in range(_ORDER - 1, 0, -1):
            acc *= d
            acc += coef[:, j, row]
        acc *= d
        if split:
            return acc + coef[:, 0, row], acc
        acc += coef[:, 0, row]
        return acc

    def series(self, r, rows):
        """The series ``rows`` at reduced phases r from the Taylor table (nearest node, Horner)."""
        values, _, _, _ = self._all_rows(r)
        return [values[:, row] for row in rows]

    def _all_rows(self, r):
        """Every row at phases r (as :meth:`_horner` row by row, in one pass over the rows):
        the values (N, rows), their changes from the node (N, rows), the phasor index and d."""
        ii, iu, d = self._nodes(r)
        coef = self.table[ii]  # one gather: a node's coefficients are contiguous
        dd = d[:, None]
        acc = coef[:, _ORDER, :].copy()
        for j in range(_ORDER - 1, 0, -1):
            acc *= dd
            acc += coef[:, j, :]
        acc *= dd
        return acc + coef[:, 0, :], acc, iu, d

    def constants(self, inertia=(0.0, 0.0, 0.0), initial=(0.0, 0.0, 0.0)) -> np.ndarray:
        """The constants of the compiled pass (:data:`wobble.numerics.taylor_table.CONSTANTS`);
        ``initial``: E, p_phi and p_psi at t = 0, from which the drifts are measured."""
        e = self.base
        i1, i3, mgl = inertia
        s_, d_ = e.sigma_sec, e.delta_sec
        return np.array(
            [
                e.K[0],
                self.h,
                1.0 / self.h,
                e.w0,
                e.lam[0],
                e.hx1,
                e.hy2,
                e.B_x1,
                e.C_y2,
                e.Bp,
                e.Cp,
                e.omega3,
                e.omega3 - e.a,
                *s_.a,
                s_.c,
                s_.offset,
                self.start[0],
                *d_.a,
                d_.c,
                d_.offset,
                self.start[1],
                *TWO_PI_PIECES,
                1.0 / TWO_PI,
                2 * np.pi,
                0.5 / np.pi,
                *energy_terms(i1, i3, mgl, initial[0])[:2],
                i1,
                i3,
                mgl,
                *initial,
                *e.phi_sec.a,
                e.phi_sec.c,
                e.phi_sec.offset,
                *e.psi_sec.a,
                e.psi_sec.c,
                e.psi_sec.offset,
                *energy_terms(i1, i3, mgl, initial[0])[2:],
            ]
        )

    @staticmethod
    def _cis(x):
        """cos and sin of a small x (|x| <= 1/32) by their Taylor polynomials in x^2."""
        z = x * x
        c = _COS[3] * z
        s = _SIN[3] * z
        for n in (2, 1):
            c += _COS[n]
            c *= z
            s += _SIN[n]
            s *= z
        c += _COS[0]
        s += _SIN[0]
        s *= x
        return c, s

    def whole_periods(self, j, j_range=None):
        """exp(i j A) of sigma and delta for the half-periods ``j``, as (2, 2, M) and the index
        base: one value per distinct j of a dense range (``j - base``), else per sample (PER_SAMPLE).
        ``j_range``: the smallest and largest j where known."""
        e = self.base
        if j.size == 0:
            return np.empty((2, 2, 0)), 0
        lo, hi = (float(np.min(j)), float(np.max(j))) if j_range is None else j_range
        if hi - lo < max(2 * j.size, 64):
            jj, base = np.arange(lo, hi + 1.0), int(lo)
        else:  # a few times spread over very many periods
            jj, base = j, PER_SAMPLE
        out = np.empty((2, 2, jj.size))
        for p, sec in enumerate((e.sigma_sec, e.delta_sec)):
            a = sec.whole_periods(jj)
            out[p, 0] = np.cos(a)
            out[p, 1] = np.sin(a)
        return out, base

    # -- evaluation -------------------------------------------------------------
    def _phase(self, t):
        e = self.base
        if t.size >= compiled.LONG_ARRAY and compiled.available():
            from wobble.numerics import taylor_table

            return taylor_table.phase(t, e.lam, (2 * e.K[0], 2 * e.K[1]), e.w0, self._period_pieces())
        return e.phase(t)

    def _period_pieces(self):
        e = self.base
        return split_dd(2 * e.K[0], 2 * e.K[1])

    def angles(self, t):
        """theta, phi and psi (rad; phi and psi wrapped to [-pi, pi]) at times t (1-D)."""
        if t.size >= compiled.LONG_ARRAY and compiled.available():  # one pass, bit for bit the NumPy path
            from wobble.numerics import taylor_table

            r, j = self._phase(t)
            if not _far(float(np.min(j)), float(np.max(j))):
                return tuple(taylor_table.angles(r, j, self.table, self.constants()))
        return blocked(self._angles_numpy, t)

    def _angles_numpy(self, t):
        e = self.base
        r, j = e.phase(t)
        ii, _, d = self._nodes(r)
        coef = self.table[ii]
        theta, sp, dp = (self._horner(coef, row, d) for row in (0, _SIGMA, _DELTA))
        # phi = sigma + delta and psi = sigma - delta from their own secular phases (a fast spin in
        # sigma's and delta's would cancel into phi).
        spr, dpr = sp - self.start[0], dp - self.start[1]
        phi = e.phi_sec(j, r, e.w0) + (spr + dpr)
        psi = e.psi_sec(j, r, e.w0) + (spr - dpr)
        return theta, wrap_angle(phi), wrap_angle(psi)

    def motion(self, t, inertia, initial) -> dict:
        """The motion at times t (1-D): theta, phi, psi, their rates, u = cos theta, omega (body),
        the quaternion, the symmetry axis, and E, p_phi, p_psi for ``inertia`` = (I1, I3, M g l)
        with their drifts from ``initial`` = (E, p_phi, p_psi) at t = 0."""
        if t.size >= compiled.LONG_ARRAY and compiled.available():  # one pass, bit for bit the NumPy path
            from wobble.numerics import taylor_table

            e = self.base
            r, j, j_range = taylor_table.phase(t, e.lam, (2 * e.K[0], 2 * e.K[1]), e.w0, self._period_pieces(), True)
            if not _far(*j_range):
                jtab, base = self.whole_periods(j, j_range)
                out, omega, quat, axis = taylor_table.motion(
                    r, j, base, self.table, self.node_r, self.phasor, jtab, _COS, _SIN, self.constants(inertia, initial)
                )
                return {**dict(zip(_MOTION_ROWS, out)), "omega": omega, "quaternion": quat, "axis": axis}
        return blocked(lambda tb: self._motion_numpy(tb, inertia, initial), t)

    def _motion_numpy(self, t, inertia, initial) -> dict:
        """:func:`wobble.numerics.taylor_table.motion` in NumPy, operation for operation."""
        e = self.base
        i1, i3, mgl = inertia
        e0, p_phi0, p_psi0 = initial
        r, j = e.phase(t)
        jtab, base = self.whole_periods(j)
        jj = np.arange(j.size) if base == PER_SAMPLE else j.astype(np.intp) - base
        ii, iu, d = self._nodes(r)
        coef = self.table[ii]
        theta = self._horner(coef, 0, d)
        sp, v1 = self._horner(coef, _SIGMA, d, split=True)
        dp, v2 = self._horner(coef, _DELTA, d, split=True)
        dth, sh, ch = (self._horner(coef, row, d) for row in (3, 4, 5))
        phases = []
        dn = r - np.take(self.node_r, iu)  # exact: r is within h/2 of its node
        for p, (sec, v) in enumerate(((e.sigma_sec, v1), (e.delta_sec, v2))):
            ec, es = self._cis(sec.c * dn + v)
            pc, ps_ = np.take(self.phasor[p, 0], iu), np.take(self.phasor[p, 1], iu)
            nc = pc * ec - ps_ * es
            ns = pc * es + ps_ * ec
            jc, js = np.take(jtab[p, 0], jj), np.take(jtab[p, 1], jj)
            phases.append((jc * nc - js * ns, jc * ns + js * nc))
        (cs, ss), (cd, sd) = phases
        spr, dpr = sp - self.start[0], dp - self.start[1]
        phi = e.phi_sec(j, r, e.w0) + (spr + dpr)
        psi = e.psi_sec(j, r, e.w0) + (spr - dpr)
        x = 2.0 * sh * sh
        y = 2.0 * ch * ch
        # B/x, C/y and phidot sin(theta) in the closed form's scaled terms (Elliptic.core): exact where
        # sin^2(theta/2) underflows (a tilt under 1e-154 rad), and no 0/0 where B or C is zero.
        sx = sh / e.hx1
        sy = ch / e.hy2
        zero = np.zeros_like(sx)
        bx = e.B_x1 / (sx * sx) if e.B_x1 != 0.0 else zero
        cy = e.C_y2 / (sy * sy) if e.C_y2 != 0.0 else zero
        thetadot = e.lam[0] * dth
        u = np.where(x <= 1.0, 1.0 - x, y - 1.0)
        ps = (e.Bp * sy / sx if e.Bp != 0.0 else zero) + (e.Cp * sx / sy if e.Cp != 0.0 else zero)
        qw, qx, qy, qz = ch * cs, sh * cd, sh * sd, ch * ss
        sin_t = 2.0 * sh * ch
        spsi = ss * cd - cs * sd
        cpsi = cs * cd + ss * sd
        w1 = ps * spsi + thetadot * cpsi
        w2 = ps * cpsi - thetadot * spsi
        w3 = np.full_like(w1, e.omega3)
        g1 = 2.0 * (qx * qz - qw * qy)
        g2 = 2.0 * (qy * qz + qw * qx)
        # The compiled pass's sum, operation for operation (energy_terms: in units of S where E nears the
        # largest double; (I w) w, not I w^2).
        ei1, ei3, emgl, scale = energy_terms(i1, i3, mgl, e0)
        energy = ((0.5 * ((ei1 * w1) * w1 + (ei1 * w2) * w2) + 0.5 * ((ei3 * w3) * w3)) + emgl * u) * scale
        p_phi = i1 * (w1 * g1 + w2 * g2) + (i3 * w3) * u
        p_psi = i3 * w3
        return dict(
            theta=theta,
            phi=wrap_angle(phi),
            psi=wrap_angle(psi),
            thetadot=thetadot,
            phidot=0.5 * (bx + cy),
            psidot=(e.omega3 - e.a) - 0.5 * (bx - cy),
            u=u,
            energy=energy,
            p_phi=p_phi,
            p_psi=p_psi,
            energy_drift=energy - e0,
            p_phi_drift=p_phi - p_phi0,
            p_psi_drift=p_psi - p_psi0,
            omega=np.stack([w1, w2, w3], axis=-1),
            quaternion=np.stack([qw, qx, qy, qz], axis=-1),
            axis=np.stack([sin_t * (ss * cd + cs * sd), -(sin_t * (cs * cd - ss * sd)), u], axis=-1),
        )


# The rows of wobble.numerics.taylor_table.motion's ``out``, by name (fields of wobble.models.top.TopMotion).
_MOTION_ROWS = ("theta", "phi", "psi", "thetadot", "phidot", "psidot", "u", "energy", "p_phi", "p_psi") + tuple(
    name + "_drift" for name in ("energy", "p_phi", "p_psi")
)


def energy_terms(i1: float, i3: float, mgl: float, e0: float) -> tuple[float, float, float, float]:
    """(I1, I3, M g l) / S and S for the energy the output recomputes, E = S ((I1/S w1) w1 / 2 + ... +
    (M g l / S) cos theta), in both the NumPy and the compiled pass: S = 1 (the sum as written) unless the
    energy's scale nears the largest double, then the power of two that keeps every partial sum finite.
    The kinetic part alone reaches |E| + M g l: a top of M g l = 1.7e308 J overflowed (fuzz seed 307)."""
    _, exponent = math.frexp(max(abs(e0), abs(mgl)))
    scale = math.ldexp(1.0, exponent - 1000) if exponent > 1000 else 1.0  # a power of two: exact divisions
    return i1 / scale, i3 / scale, mgl / scale, scale


def _far(j_lo: float, j_hi: float) -> bool:
    """Whether whole half-periods from ``j_lo`` to ``j_hi`` reach 2^26, past which the compiled
    secular phase's three-piece products stop being exact: such times take the NumPy path, whose
    :meth:`~wobble.models.top_closed_form.Secular.far` carries them to 2^50 (a branch for them in
    the compiled loop would keep LLVM from vectorising it, as in :func:`wobble.numerics.taylor_table.phase`)."""
    return max(abs(j_lo), abs(j_hi)) >= WHOLE_PIECES


def wrap_angle(a):
    """Angles to [-pi, pi] (a few times faster than np.remainder; |a| here is < 10 pi)."""
    return a - (2 * np.pi) * np.rint(a * (0.5 / np.pi))


def blocked(fn, t):
    """Evaluate fn on cache-sized blocks of t and concatenate the outputs (tuple or dict)."""
    if t.size <= _BLOCK:
        return fn(t)
    parts = [fn(t[i : i + _BLOCK]) for i in range(0, t.size, _BLOCK)]
    if isinstance(parts[0], dict):
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(len(parts[0])))


#: From this many samples on, the model evaluates through the series (where verified).
MIN_SAMPLES = 1024
_FOURIER_MAX_N = 512
_FOURIER_MAX_TERMS = 96
_TAYLOR_MAX_NODES = 1 << 15


def build(e, est: dict, fast: bool = False) -> Fourier | None:
    """Fourier series of the periodic parts of ``e``, tabulated and verified; None where not worth it.

    Six 2K-periodic functions of the reduced phase are sampled exactly at N equispaced
    phases: theta, sin(theta/2), cos(theta/2) (even), k_- P_- and k_+ P_+ and dtheta/dr (odd,
    sampled from its closed form rather than by differentiating the theta series, which
    would amplify the rounding of theta's samples). N doubles until the upper half of every
    spectrum is at rounding level; the table must then reproduce the direct evaluation
    between the nodes within the solution's error estimate, the phasors of the half angles
    included. Used only off the poles (x, y > 0 on the orbit).

    ``fast``: the samples, the phasors and the check by the compiled helpers of
    :mod:`wobble.numerics.taylor_table` (the same arithmetic, in one pass each) where Numba
    and SciPy's C Carlson functions are at hand.
    """
    if e.through_top or e.through_bottom:
        return None
    k = e.K[0]
    noise = 8 * EPS  # the FFT of exact values has a noise floor of a few eps
    sample, fast = _sampler(e, fast)
    if fast:
        return _build_compiled(e, est, sample)
    r_check = _CHECK_VT * (k / np.pi)
    parity = _PARITY
    for n, part, want, start, raw in _half_node_samples(e, sample, r_check):
        # The nodes vartheta_i = 2 pi i / n in [0, pi]; those in (pi, 2 pi) are -vartheta_{n-i}, where
        # the rows are their mirror images (theta and the half angles' sines and cosines even,
        # the rest odd, and exactly so in the direct path: sn odd, cn and dn even, Pi odd).
        half = n // 2
        if raw is not None:  # the direct path's own P_+(r0), P_-(r0) (elementwise: as if alone)
            e.__dict__.setdefault("_start", (float(raw[0][-1]), float(raw[1][-1])))
        vals = np.empty((len(_KINDS), n))
        vals[:, : half + 1] = part
        vals[:, half + 1 :] = parity * part[:, half - 1 : 0 : -1]
        spectra = np.fft.rfft(vals, axis=-1) / n
        scales = np.maximum(np.max(np.abs(vals), axis=1), 1e-300)
        scales[_SIGMA] = scales[_DELTA] = max(1.0, scales[_SIGMA], scales[_DELTA])  # phases: absolute (rad)
        # Aliasing folds c_{n-k} onto c_k: only the top of the band must be at rounding
        # level; the check against the direct evaluation below decides.
        top = np.max(np.abs(spectra[:, 7 * n // 16 :]), axis=1)
        if not np.all(top <= noise * scales):
            continue
        fo = _fourier_from_spectra(e, spectra, scales, k, start, fast)
        if fo is None:
            return None  # too long a series: the direct path is about as fast
        checked = _check_fourier(fo, r_check, want, scales, est, k)
        if checked is not None:
            return checked
    return None


def _half_node_samples(e, sample, r_check):
    """For n = 64, 128, 256, ... the samples on the nodes r = (2 pi i / n) K/pi, i = 0 .. n/2, of half
    the period; the first pass also samples the check points ``r_check`` and the phase at t = 0
    (one pass of the direct path). Yields ``(n, part, want, start, raw)``: ``part`` (rows, n/2 + 1),
    ``want`` (check points, rows), ``start`` (sigma, delta) at r0, and ``raw`` the sampler's second
    output on the first pass (None after it)."""
    k = e.K[0]
    want = start = None
    for n in (64, 128, 256, _FOURIER_MAX_N):
        half = n // 2
        r_half = (2 * np.pi * np.arange(half + 1) / n) * (k / np.pi)
        if want is None:
            both, raw = sample(np.concatenate([r_half, r_check, [e.r0]]))
            part, want = both[:, : half + 1], both[:, half + 1 : -1].T
            # sigma's and delta's anchors: their periodic parts at the exact start (Elliptic.core's).
            start = (float(both[_SIGMA, -1]) + e.anchor_sigma, float(both[_DELTA, -1]) + e.anchor_delta)
        else:
            part, raw = sample(r_half)[0], None
        yield n, part, want, start, raw


def _build_compiled(e, est, sample):
    """:func:`build` with the compiled helpers of :mod:`wobble.numerics.taylor_table` between the
    FFTs: the same steps (samples on half the nodes, the spectra, the coefficients and the node
    count, the Taylor table, the phasors, the check, finer tables on failure) in a few calls."""
    from wobble.numerics import taylor_table as tt

    k = e.K[0]
    scale = np.pi / k
    r_check = _CHECK_VT * (k / np.pi)
    c = (e.sigma_sec.c, e.delta_sec.c)
    offset = (e.sigma_sec.offset, e.delta_sec.offset)
    for n, part, want, start, _ in _half_node_samples(e, sample, r_check):
        vals, scales = tt.prepare(part, n, _PARITY[:, 0])
        spectra = np.fft.rfft(vals, axis=-1) / n
        status, coef, need, slope_s, slope_d = tt.coefficients(
            spectra, scales, n, 8 * EPS, _COS_ROWS, 0.25 * EPS, _FOURIER_MAX_TERMS, scale
        )
        if status == 0:
            continue
        if status == 2:
            return None  # too long a series: the direct path is about as fast
        nodes = _fft_size(max(256, int(np.ceil(need)) if np.isfinite(need) else 1 << 30))
        slope = max(abs(c[0]) + slope_s, abs(c[1]) + slope_d)
        limits = _check_limits(est, scales, k)
        while True:
            while slope * k / nodes > _CIS_MAX:
                nodes *= 2
            if nodes > _TAYLOR_MAX_NODES:
                return None
            h = 2 * k / nodes
            table = np.fft.irfft(tt.spectrum(coef, scale, nodes, _COS_ROWS, _FACT), n=nodes, axis=0, norm="forward")
            node_r = -k + h * np.arange(nodes + 1)
            phasor = tt.phasors(table, node_r, e.w0, c, offset, start)
            err, miss = tt.check_at(r_check, want, table, node_r, phasor, k, h, c, offset, start, e.w0, _COS, _SIN)
            if np.all(err <= limits) and miss <= est["attitude_rad"]:
                return Fourier(
                    base=e,
                    coef=coef,
                    scale=scale,
                    table=table,
                    h=h,
                    phasor=phasor,
                    node_r=node_r,
                    error_theta=float(err[0]),
                    error_phase=max(float(err[_SIGMA]), float(err[_DELTA]), miss),
                    start=start,
                    compiled=True,
                )
            nodes *= 2
    return None


# Check points between the nodes (phases offset by an irrational fraction of the spacing).
_CHECK_VT = -np.pi + 2 * np.pi * (np.arange(41) + 0.6180339887498949) / 41
_PARITY = np.array([1.0 if kind == "cos" else -1.0 for kind in _KINDS])[:, None]  # even rows 1, odd rows -1
_COS_ROWS = np.array([kind == "cos" for kind in _KINDS])


def _sampler(e, fast):
    """The direct evaluation of the six rows at phases r as (rows (6, N), (P_+, P_-)), and
    whether it is the compiled one."""
    if fast:
        from wobble.numerics import taylor_table

        functions = taylor_table.carlson()
        if functions is not None:
            lv = e.levels
            constants = np.array(
                [
                    float(lv.m),
                    float(lv.m1),
                    float(lv.K),
                    e.K[1],
                    float(lv.scale),
                    e.rho_x,
                    e.rho_y,
                    e.hx1,
                    e.hy2,
                    e.W,
                    e.k_plus,
                    e.k_minus,
                    e.n_plus,
                    e.one_minus_n_plus,
                    e.nu_minus,
                    e.pi_plus_over_k,
                    e.pi_minus_over_k,
                    3.0 * (1.0 + e.nu_minus) ** 2,
                ]
            )
            ratios = np.array(lv.ratios, dtype=float).reshape(-1)
            ratios_b = np.array(lv.ratios_b, dtype=float).reshape(-1)
            return (lambda r: taylor_table.sample(r, constants, ratios, ratios_b, functions)), True

    def numpy_sample(r):
        rows, raw = e.periodic_with_half_angles_and_parts(r)
        return np.stack(rows), raw

    return numpy_sample, False


def _fourier_from_spectra(e, spectra, scales, k, start=(0.0, 0.0), fast=False):
    cos_rows = _COS_ROWS
    coef = np.where(cos_rows[:, None], 2 * spectra.real, -2 * spectra.imag)
    coef[:, 0] = np.where(cos_rows, spectra[:, 0].real, 0.0)
    big = np.max(np.abs(coef) / np.asarray(scales)[:, None], axis=0)
    keep = np.nonzero(big > 0.25 * EPS)[0]
    last = int(keep.max()) if keep.size else 1
    if last > _FOURIER_MAX_TERMS:
        return None
    coef = np.ascontiguousarray(coef[:, : last + 1])
    scale = np.pi / k
    # Nodes: the remainder of the degree-5 Taylor polynomials half a spacing from their node,
    # |f^(6)| (h/2)^6 / 6! <= sum_k |c_k| (k pi / S)^6 / 720, below each row's rounding (eps times
    # its scale); S the smallest FFT-friendly size (2^a 3^b 5^c, even) from 256 on.
    moment = np.sum(np.abs(coef) * np.arange(last + 1.0) ** 6, axis=1)
    need = np.pi * float(np.max((moment / (720 * EPS * np.asarray(scales))) ** (1 / 6)))
    nodes = _fft_size(max(256, int(np.ceil(need)) if np.isfinite(need) else 1 << 30))
    return _tabulate(
        Fourier(base=e, coef=coef, scale=scale, table=np.empty((0, 0, 0)), h=0.0, start=start, compiled=fast), nodes
    )


def _fft_size(n: int) -> int:
    """The smallest even 2^a 3^b 5^c >= n."""
    if n <= _FFT_SIZES[-1]:
        return _FFT_SIZES[bisect.bisect_left(_FFT_SIZES, n)]
    return _fft_size_search(n)


def _fft_size_search(n: int) -> int:
    best = 1 << max(1, (n - 1).bit_length())
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            m = p35
            while m < n or m % 2:
                m *= 2
            best = min(best, m)
            p35 *= 3
        p5 *= 5
    return best


# The even 2^a 3^b 5^c up to the cap of nodes (and the next one above it).
_FFT_SIZES = sorted(
    2**a * 3**b * 5**c
    for a in range(1, 17)
    for b in range(11)
    for c in range(8)
    if 2**a * 3**b * 5**c <= 2 * _TAYLOR_MAX_NODES
)


def _tabulate(fo: Fourier, nodes: int) -> Fourier | None:
    """The Taylor table of ``fo``'s series at ``nodes`` nodes (more where the half angles turn
    faster than 1/32 rad between a node and the next midpoint) and the node phasors of the
    half angles; None when that would take more than the cap of nodes."""
    e = fo.base
    k = e.K[0]
    # Bounds of |d/dr| of sigma's and delta's arguments: their secular rate plus the sum of
    # |k b_k| (pi / K) of their periodic parts.
    sums = np.abs(fo.coef[_SIGMA : _DELTA + 1]) @ (np.arange(fo.coef.shape[1]) * fo.scale)
    slopes = [abs(e.sigma_sec.c) + float(sums[0]), abs(e.delta_sec.c) + float(sums[1])]
    while max(slopes) * k / nodes > _CIS_MAX:
        nodes *= 2
    if nodes > _TAYLOR_MAX_NODES:
        return None
    h = 2 * k / nodes
    table = _taylor_table(fo.coef, nodes, fo.scale)
    node_r = -k + h * np.arange(nodes + 1)
    # g = c (node - w0) + offset + (P(node) - P0) of sigma and delta in double-double: |c (node - w0)|
    # reaches several radians, whose rounding would otherwise be the phasors' largest error.
    if fo.compiled:  # the lines below in one compiled pass
        from wobble.numerics import taylor_table

        phasor = taylor_table.phasors(
            table, node_r, e.w0, (e.sigma_sec.c, e.delta_sec.c), (e.sigma_sec.offset, e.delta_sec.offset), fo.start
        )
        return replace(fo, table=table, h=h, phasor=phasor, node_r=node_r)
    c = np.array([[e.sigma_sec.c], [e.delta_sec.c]])
    offset = np.array([[e.sigma_sec.offset], [e.delta_sec.offset]])
    p0 = np.array([[fo.start[0]], [fo.start[1]]])
    at_node = np.empty((2, nodes + 1))
    at_node[:, :nodes] = table[:, 0, _SIGMA : _DELTA + 1].T
    at_node[:, nodes] = at_node[:, 0]  # r = +K is the node of r = -K
    dh, dl = two_sum(node_r, -e.w0)
    gh, gl = two_prod(c, dh)
    gl = gl + c * dl
    gh, e1 = two_sum(gh, offset)
    ph, pl = two_sum(at_node, -p0)
    gh, e2 = two_sum(gh, ph)
    gl = gl + (e1 + (e2 + pl))
    cos_h, sin_h = np.cos(gh), np.sin(gh)
    phasor = np.empty((2, 2, nodes + 1))  # (sigma, delta) x (cos, sin) x node
    phasor[:, 0] = cos_h - sin_h * gl
    phasor[:, 1] = sin_h + cos_h * gl
    return replace(fo, table=table, h=h, phasor=phasor, node_r=node_r)


def _check_limits(est, scales, k):
    """How far the table may stray from the direct values, per tabulated row: theta and the phases
    sigma, delta by the solution's error estimate; dtheta/dr, sin(theta/2) and cos(theta/2) relative to
    their scales."""
    rel = 32 * EPS * (1 + k)  # theta's own standard (est["theta_rad"] / theta_max), for sin and cos of theta/2
    return np.array(
        [
            est["theta_rad"],
            est["attitude_rad"],
            est["attitude_rad"],
            64 * EPS * (1 + k) * scales[3],
            rel * scales[4],
            rel * scales[5],
        ]
    )


def _check_fourier(fo, r, want, scales, est, k):
    """The table if it reproduces the direct values within the error estimate (finer tables
    are tried first); None otherwise."""
    e = fo.base
    want = np.asarray(want)  # (m, rows), as the table's rows come
    # The phases the phasors must reproduce (at j = 0): c (r - w0) + offset + (P(r) - P(r0)).
    c = np.array([e.sigma_sec.c, e.delta_sec.c])
    g = (c * (r - e.w0)[:, None] + np.array([e.sigma_sec.offset, e.delta_sec.offset])) + (
        want[:, _SIGMA : _DELTA + 1] - np.array(fo.start)
    )
    cos_g, sin_g = np.cos(g), np.sin(g)
    limits = _check_limits(est, scales, k)
    while fo is not None:
        if fo.compiled:  # the lines of the other branch in one compiled pass
            from wobble.numerics import taylor_table

            err, miss = taylor_table.check(
                r, want, cos_g, sin_g, fo.table, fo.node_r, fo.phasor, e.K[0], fo.h, c, _COS, _SIN
            )
        else:
            got, v, iu, _ = fo._all_rows(r)
            err = np.max(np.abs(got - want), axis=0)
            # The phasors of the half angles (at j = 0) against cos and sin of the direct phases.
            ec, es = fo._cis(c * (r - fo.node_r[iu])[:, None] + v[:, _SIGMA : _DELTA + 1])
            pc, ps_ = fo.phasor[:, 0, iu].T, fo.phasor[:, 1, iu].T
            miss = float(np.max(np.hypot(pc * ec - ps_ * es - cos_g, pc * es + ps_ * ec - sin_g)))
        if np.all(err <= limits) and miss <= est["attitude_rad"]:
            return replace(
                fo, error_theta=float(err[0]), error_phase=max(float(np.max(err[_SIGMA : _DELTA + 1])), miss)
            )
        nodes = 2 * fo.table.shape[0]
        if nodes > _TAYLOR_MAX_NODES:
            return None
        fo = _tabulate(fo, nodes)
    return None


def _taylor_table(coef, nodes, scale):
    """f^(j)(r_i)/j! (j = 0.._ORDER, r-units) of every series at the nodes r_i = -K + i h, as
    (nodes, order + 1, rows): the coefficients an output needs are contiguous.

    With vartheta_i = -pi + 2 pi i / S, e^{i k vartheta_i} = (-1)^k e^{2 pi i k i / S}, so
    Re sum_k c_k (i k scale)^j e^{i k vartheta_i} for all rows and orders is one batched
    real inverse FFT (cos series: c_k = a_k; sin series: c_k = -i b_k).
    """
    nrow, ncoef = coef.shape
    kk = np.arange(ncoef)
    # (-1)^k, halved for k >= 1 (irfft counts each k >= 1 twice: the Hermitian extension)
    sign = np.where(kk % 2 == 0, 0.5, -0.5)
    sign[0] = 1.0
    power = (1j * kk[:, None] * scale) ** _ORDERS  # (ncoef, order + 1)
    spec = np.zeros((nodes // 2 + 1, _ORDER + 1, nrow), dtype=complex)
    spec[:ncoef] = (coef.T * sign[:, None])[:, None, :] * (power / _FACT)[:, :, None] * _ROT  # (ncoef, order + 1, rows)
    # norm="forward": the inverse without its 1/S (the sum itself, with no scaling to undo).
    return np.fft.irfft(spec, n=nodes, axis=0, norm="forward")


# The tables of each model, built on first use: keyed by (id(model), fast), dropped when the model
# is collected (weakref.finalize), so a frozen model stays immutable and the cache never grows
# with models that are gone. One table per set-up path: the compiled and the NumPy set-ups agree
# to rounding, not bit for bit, and with one table shared a call's last bits depended on which
# call came first (4e-16 in theta, and so on the order of threads).
_TABLES: dict[tuple[int, bool], Fourier | None] = {}


def series_of(owner, e, est: dict, fast: bool = False) -> Fourier | None:
    """The verified series of the evaluator ``e`` of model ``owner`` (built once per path), or None.

    ``owner`` is the object the table belongs to (the frozen model): the table lives
    here, not in it, for as long as ``owner`` does. ``fast``: set it up with the compiled
    helpers (:func:`build`); the two set-ups keep their own tables, so that a call's result
    depends on its inputs (and their number), never on the calls before it.
    """
    key = (id(owner), bool(fast))
    try:
        return _TABLES[key]
    except KeyError:
        pass
    table = build(e, est, fast)
    _TABLES[key] = table
    weakref.finalize(owner, _TABLES.pop, key, None)
    return table
