"""Compiled DOP853 for Euler's equations with the engine's built-in torques (float64, SI).

The same method as :class:`wobble.numerics.integrators.DOP853` (Dormand & Prince
8(5,3), Hairer's step control and starting step, 7th-order dense output, the
quaternion projected back to unit length after each accepted step, each member
with its own step), for the right-hand side of notes section 5.5

    I_1 domega_1/dt = tau_1 + (I_2 - I_3) omega_2 omega_3   (and cyclic),
    dq/dt = q * (0, omega) / 2,

compiled with Numba and run member after member. Why: one trajectory in Python
pays the interpreter's cost at every stage (~20 us, SciPy's solve_ivp as much),
while the arithmetic of a stage is ~100 floating-point operations; an ensemble
in NumPy makes a memory-bound pass over the member arrays for every operation.
Compiled, a stage costs tens of nanoseconds and each member stays in registers.

The torque is a *program* of the engine's built-in kinds, one
:class:`~wobble.numerics.torque_program.TorqueProgram` of arrays packed by the engine
(:mod:`wobble.numerics.torque_program` lists its fields and the torque each computes;
internal frame: principal axes sorted by increasing moment).

Numba is imported by this module only: import it where a compiled run is wanted
(the import costs ~0.4 s once per process; compiled code is cached on disk).
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from wobble.numerics.floats import EPS
from wobble.numerics import _dop853_tableau as _T
from wobble.numerics import compiled as _compiled
from wobble.numerics import kepler as _kepler
from wobble.numerics.integrators import StepLimitError, check_output_times
from wobble.numerics.torque_program import TorqueProgram

__all__ = ["OK", "STEP_LIMIT", "STEP_UNDERFLOW", "RigidDOP853"]

OK, STEP_UNDERFLOW, STEP_LIMIT = 0, 1, 2

_NS = _T.N_STAGES  # 12
_T_EXT = _T.N_STAGES_EXTENDED  # 16: the stages with the three of the dense output
_A = np.ascontiguousarray(_T.A)  # (16, 16)
_C = np.ascontiguousarray(_T.C)  # (16,)
_E3 = np.ascontiguousarray(_T.E3)  # (13,)
_E5 = np.ascontiguousarray(_T.E5)  # (13,)
_D = np.ascontiguousarray(_T.D)  # (4, 16)
_SAFETY = 0.9
_MIN_FACTOR = 0.2
_MAX_FACTOR = 10.0
_EXPONENT = -1.0 / 8.0
_TWO_PI = 2.0 * np.pi
_KEPLER_ITERATIONS = _kepler.MAX_ITERATIONS
_KEPLER_TOL = 4.0 * EPS

_MEMBERS_PER_THREAD = 256


def _cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


# fastmath "contract" only: fused multiply-adds (one rounding instead of two, ~20 % faster);
# no reassociation, no assumptions about NaN or infinity (the first-step test reads a NaN).
_OPTIONS = {"nogil": True, "fastmath": {"contract"}, "error_model": "numpy"}  # cached on disk where Numba can
_compiled.listen()  # a command line may announce the first compilation (15 to 35 s after installing)
_jit = _compiled.njit(**_OPTIONS)
# The right-hand side is inlined into the stage loop: passed as a call, its ten parameter arrays
# are reference-counted at every evaluation, and a step took 3.6 times as long (measured
# 2026-11-30). Each inlined copy costs seconds of compilation, so the step has one call site
# (every stage, the new state's and the dense output's, in one loop): the first compilation
# took 16 s instead of 35 with four copies, for bit-identical results and the same speed.
_jit_inline = _compiled.njit(inline="always", **_OPTIONS)


@_jit_inline
def _to_body(qw, ux, uy, uz, v0, v1, v2):
    """R(q)^T v = v + 2 w (u x v) + 2 u x (u x v), u = -(x, y, z) the vector part of q*:
    the rotation into the body frame as wobble.models.engine does it (q need not be unit
    within a step)."""
    a0 = 2.0 * (uy * v2 - uz * v1)
    a1 = 2.0 * (uz * v0 - ux * v2)
    a2 = 2.0 * (ux * v1 - uy * v0)
    return v0 + qw * a0 + (uy * a2 - uz * a1), v1 + qw * a1 + (uz * a0 - ux * a2), v2 + qw * a2 + (ux * a1 - uy * a0)


@_jit_inline
def _lever_torque(qw, ux, uy, uz, i, arms, forces):
    """sum over terms of arm x R(q)^T force: gravity about a pivot (arm r, force m g) and a
    body-fixed magnetic dipole in a uniform field (arm mu, force B) have the same form."""
    tx = ty = tz = 0.0
    for g in range(arms.shape[0]):
        r = i if arms.shape[1] > 1 else 0
        b0, b1, b2 = _to_body(qw, ux, uy, uz, forces[g, r, 0], forces[g, r, 1], forces[g, r, 2])
        c0, c1, c2 = arms[g, r, 0], arms[g, r, 1], arms[g, r, 2]
        tx += c1 * b2 - c2 * b1
        ty += c2 * b0 - c0 * b2
        tz += c0 * b1 - c1 * b0
    return tx, ty, tz


@_jit_inline
def _kepler_position(t, row):
    """Position and distance on the Keplerian orbit of a ``third_body`` row at time t:
    :func:`wobble.numerics.kepler.position_one` step for step (Danby's start, Newton until
    the correction is below 4 eps)."""
    a, e, inc = row[1], row[2], row[3]
    m = row[6] + row[7] * t
    m = m - _TWO_PI * np.round(m / _TWO_PI)
    s = np.sin(m)
    E = m + 0.85 * e * (1.0 if s > 0.0 else (-1.0 if s < 0.0 else 0.0))
    for _ in range(_KEPLER_ITERATIONS):
        d = (E - e * np.sin(E) - m) / (1.0 - e * np.cos(E))
        E -= d
        if abs(d) <= _KEPLER_TOL:
            break
    cE, sE = np.cos(E), np.sin(E)
    x = a * (cE - e)
    yy = a * np.sqrt(1.0 - e * e) * sE
    node = row[4] + row[8] * t
    peri = row[5] + row[9] * t
    cO, sO, cw, sw = np.cos(node), np.sin(node), np.cos(peri), np.sin(peri)
    ci, si = np.cos(inc), np.sin(inc)
    return (
        x * (cO * cw - sO * sw * ci) - yy * (cO * sw + sO * cw * ci),
        x * (sO * cw + cO * sw * ci) - yy * (sO * sw - cO * cw * ci),
        (x * sw + yy * cw) * si,
        a * (1.0 - e * cE),
    )


@_jit_inline
def _rhs(t, y, out, i, prog):
    """Euler's equations with the torque program, for member i (notes 5.5)."""
    d = y.shape[0]
    w0, w1, w2 = y[0], y[1], y[2]
    body = prog.body
    r = i if body.shape[0] > 1 else 0
    tx, ty, tz = body[r, 0], body[r, 1], body[r, 2]
    moments = prog.moments
    m = i if moments.shape[0] > 1 else 0
    i0, i1, i2 = moments[m, 0], moments[m, 1], moments[m, 2]
    if d == 7:
        # u = -(x, y, z): the vector part of q*, for the rotation into the body frame.
        qw, ux, uy, uz = y[3], -y[4], -y[5], -y[6]
        inertial = prog.inertial
        r = i if inertial.shape[0] > 1 else 0
        v0, v1, v2 = inertial[r, 0], inertial[r, 1], inertial[r, 2]
        if v0 != 0.0 or v1 != 0.0 or v2 != 0.0:
            b0, b1, b2 = _to_body(qw, ux, uy, uz, v0, v1, v2)
            tx += b0
            ty += b1
            tz += b2
        c0, c1, c2 = _lever_torque(qw, ux, uy, uz, i, prog.grav_r, prog.grav_mg)
        tx += c0
        ty += c1
        tz += c2
        c0, c1, c2 = _lever_torque(qw, ux, uy, uz, i, prog.magnetic_dipole, prog.magnetic_field)
        tx += c0
        ty += c1
        tz += c2
        gg = prog.gradient
        for j in range(gg.shape[0]):
            k = gg[j, 0]
            ang = gg[j, 7] * t + gg[j, 8]
            c, s = np.cos(ang), np.sin(ang)
            b0, b1, b2 = _to_body(
                qw, ux, uy, uz, c * gg[j, 1] + s * gg[j, 4], c * gg[j, 2] + s * gg[j, 5], c * gg[j, 3] + s * gg[j, 6]
            )
            # rho x I rho = ((I3 - I2) r1 r2, (I1 - I3) r2 r0, (I2 - I1) r0 r1)
            tx += k * (i2 - i1) * b1 * b2
            ty += k * (i0 - i2) * b2 * b0
            tz += k * (i1 - i0) * b0 * b1
        tb = prog.third_body
        for j in range(tb.shape[0]):
            p0, p1, p2, dist = _kepler_position(t, tb[j])
            k = 3.0 * tb[j, 0] / (dist * dist * dist)
            b0, b1, b2 = _to_body(qw, ux, uy, uz, p0 / dist, p1 / dist, p2 / dist)
            tx += k * (i2 - i1) * b1 * b2
            ty += k * (i0 - i2) * b2 * b0
            tz += k * (i1 - i0) * b0 * b1
    damp = prog.damping
    if damp.shape[0] > 0:
        r = i if damp.shape[0] > 1 else 0
        tx -= damp[r, 0] * w0
        ty -= damp[r, 1] * w1
        tz -= damp[r, 2] * w2
    out[0] = (tx + (i1 - i2) * w1 * w2) / i0
    out[1] = (ty + (i2 - i0) * w2 * w0) / i1
    out[2] = (tz + (i0 - i1) * w0 * w1) / i2
    if d == 7:
        qw, qx, qy, qz = y[3], y[4], y[5], y[6]
        out[3] = -0.5 * (qx * w0 + qy * w1 + qz * w2)
        out[4] = 0.5 * (qw * w0 + qy * w2 - qz * w1)
        out[5] = 0.5 * (qw * w1 - qx * w2 + qz * w0)
        out[6] = 0.5 * (qw * w2 + qx * w1 - qy * w0)


@_jit
def _rhs_at(t, y, out, i, prog):
    """f(t, y) for member i, as a call: for the evaluations outside the steps (the stages inline it)."""
    _rhs(t, y, out, i, prog)


@_jit
def _project(y):
    """Back onto unit quaternions (the attitude part, when there is one)."""
    if y.shape[0] == 7:
        n = np.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6])
        for c in range(3, 7):
            y[c] = y[c] / n


@_jit
def _rms_scaled(x, scale):
    s = 0.0
    for c in range(x.shape[0]):
        v = x[c] / scale[c]
        s += v * v
    return np.sqrt(s / x.shape[0])


@_jit
def _member(
    i,
    t_out,
    t_end,
    t,
    y,
    f,
    h,
    ymax,
    steps,
    rejected,
    nfev,
    flags,
    rtol,
    atol,
    max_steps,
    out,
    prog,
    K,
    ytmp,
    ynew,
    scale,
    F,
):
    """Advance member i to t_end, writing its outputs; returns an error code (OK, ...)."""
    d = y.shape[1]
    ti = t[i]
    yi = y[i]
    fi = f[i]
    n_out = t_out.shape[0]
    # Outputs at the current time come straight from the state (as DOP853.advance).
    ptr = 0
    while ptr < n_out and t_out[ptr] <= ti:
        if t_out[ptr] == ti:
            for c in range(d):
                out[ptr, i, c] = yi[c]
        ptr += 1
    if ti >= t_end:
        return OK
    rt = rtol[i]
    hi = h[i]
    if not hi > 0.0:
        if np.isnan(hi):  # first call: Hairer's starting step (Solving ODEs I, II.4)
            span = abs(t_end - ti)
            for c in range(d):
                scale[c] = atol[i, c] + rt * ymax[i, c]
            d0 = _rms_scaled(yi, scale)
            d1 = _rms_scaled(fi, scale)
            if d0 < 1e-5 or d1 < 1e-5:
                h0 = 1e-6 * max(span, 1e-300)
            else:
                h0 = 0.01 * d0 / d1
            h0 = min(h0, span)
            for c in range(d):
                ytmp[c] = yi[c] + h0 * fi[c]
            _rhs_at(ti + h0, ytmp, K[1], i, prog)
            nfev[i] += 1
            s = 0.0
            for c in range(d):
                v = (K[1, c] - fi[c]) / scale[c]
                s += v * v
            d2 = np.sqrt(s / d) / h0
            big = max(d1, d2)
            if big <= 1e-15:
                h1 = max(1e-6, h0 * 1e-3)
            else:
                h1 = (0.01 / big) ** (1.0 / 9.0)
            hi = min(min(100.0 * h0, h1), span)
        else:
            hi = abs(t_end - ti)
    while ti < t_end:
        remaining = t_end - ti
        last = hi * (1.0 + 1e-9) >= remaining  # no sliver of a last step
        hs = remaining if last else min(hi, remaining)
        if hs <= 16.0 * EPS * max(abs(ti), 1e-300):
            t[i], h[i] = ti, hs
            return STEP_UNDERFLOW
        # The stages: the twelve of the step, f at the new state (the thirteenth, whose weights
        # are the step's), and, when an output falls in the step, the three of the dense output.
        # One loop, so that the right-hand side is inlined once (each inlined copy costs seconds
        # of compilation).
        for c in range(d):
            K[0, c] = fi[c]
        t_new = t_end if last else ti + hs
        accepted = False
        dense = False
        for s in range(1, _T_EXT):
            if s == _NS + 1:
                nfev[i] += _NS
                # Error norm: 5th and 3rd order estimators, each component scaled by the largest
                # value it has reached (DOP853's docstring in wobble.numerics.integrators).
                e5 = 0.0
                e3 = 0.0
                for c in range(d):
                    sc = atol[i, c] + rt * max(ymax[i, c], abs(ynew[c]))
                    a5 = 0.0
                    a3 = 0.0
                    for j in range(_NS + 1):
                        a5 += _E5[j] * K[j, c]
                        a3 += _E3[j] * K[j, c]
                    a5 /= sc
                    a3 /= sc
                    e5 += a5 * a5
                    e3 += a3 * a3
                denom = e5 + 0.01 * e3
                err = abs(hs) * e5 / np.sqrt(denom * d) if denom > 0.0 else 0.0
                if flags[i] != 0:  # rejected just before: do not grow
                    grow = 1.0 if err == 0.0 else min(1.0, min(_MAX_FACTOR, _SAFETY * err**_EXPONENT))
                else:
                    grow = _MAX_FACTOR if err == 0.0 else min(_MAX_FACTOR, _SAFETY * err**_EXPONENT)
                if err > 1.0:
                    hi = hs * max(_MIN_FACTOR, _SAFETY * err**_EXPONENT)
                    flags[i] = 1
                    rejected[i] += 1
                    break
                accepted = True
                hi = hs * grow
                flags[i] = 0
                # K[_NS] (f at the unprojected y_new) becomes the next f, as in DOP853.advance.
                _project(ynew)
                dense = ptr < n_out and t_out[ptr] <= t_new
                if not dense:
                    break
                nfev[i] += 3
            for c in range(d):
                acc = 0.0
                for j in range(s):
                    acc += _A[s, j] * K[j, c]
                ytmp[c] = yi[c] + hs * acc
            ts = ti + _C[s] * hs
            if s == _NS:
                # y_new = y + h sum_j b_j K[j]: the thirteenth stage's weights are b (the tableau's B is A[12, :12]).
                for c in range(d):
                    ynew[c] = ytmp[c]
                ts = t_new
            _rhs(ts, ytmp, K[s], i, prog)
        if not accepted:
            continue
        if dense:
            # The 7th-order interpolant.
            for c in range(d):
                delta = ynew[c] - yi[c]
                F[0, c] = delta
                F[1, c] = hs * fi[c] - delta
                F[2, c] = 2.0 * delta - hs * (K[_NS, c] + fi[c])
                for r in range(4):
                    acc = 0.0
                    for j in range(_T_EXT):
                        acc += _D[r, j] * K[j, c]
                    F[3 + r, c] = hs * acc
            while ptr < n_out and t_out[ptr] <= t_new:
                if t_out[ptr] == t_new:
                    for c in range(d):
                        ytmp[c] = ynew[c]
                else:
                    x = (t_out[ptr] - ti) / hs
                    for c in range(d):
                        v = 0.0
                        for r in range(6, -1, -1):
                            v += F[r, c]
                            v *= x if (6 - r) % 2 == 0 else 1.0 - x
                        ytmp[c] = v + yi[c]
                _project(ytmp)
                for c in range(d):
                    out[ptr, i, c] = ytmp[c]
                ptr += 1
        ti = t_new
        for c in range(d):
            yi[c] = ynew[c]
            fi[c] = K[_NS, c]
            ymax[i, c] = max(ymax[i, c], abs(ynew[c]))
        steps[i] += 1
        if steps[i] > max_steps:
            t[i], h[i] = ti, hi
            return STEP_LIMIT
    t[i], h[i] = ti, hi
    return OK


@_jit
def _advance(lo, hi, t_out, t, y, f, h, ymax, steps, rejected, nfev, flags, rtol, atol, max_steps, out, prog):
    """Members lo <= i < hi, one after the other; returns (code, member)."""
    d = y.shape[1]
    t_end = t_out[t_out.shape[0] - 1]
    K = np.empty((_T_EXT, d))
    ytmp = np.empty(d)
    ynew = np.empty(d)
    scale = np.empty(d)
    F = np.empty((7, d))
    for i in range(lo, hi):
        code = _member(
            i,
            t_out,
            t_end,
            t,
            y,
            f,
            h,
            ymax,
            steps,
            rejected,
            nfev,
            flags,
            rtol,
            atol,
            max_steps,
            out,
            prog,
            K,
            ytmp,
            ynew,
            scale,
            F,
        )
        if code != OK:
            return code, i
    return OK, -1


@_jit
def _initial_f(t0, y, f, prog):
    for i in range(y.shape[0]):
        _rhs_at(t0, y[i], f[i], i, prog)


class RigidDOP853:
    """:class:`wobble.numerics.integrators.DOP853` for Euler's equations, compiled.

    Parameters
    ----------
    program : TorqueProgram
        The torques and moments as arrays in the internal frame
        (:mod:`wobble.numerics.torque_program`).
    t0 : float
        Start time (s), shared by all members.
    y0 : numpy.ndarray (N, 3) or (N, 7)
        omega (rad/s), then the unit quaternion when the attitude is carried.
    rtol : float or numpy.ndarray (N,)
        Relative tolerance (at least 100 eps).
    atol : numpy.ndarray (d,) or (N, d)
        Absolute floor of each component's scale.
    max_steps : int
        Step budget per member across all calls.
    workers : int, optional
        Threads for an ensemble (default: the CPUs this process may use); members are
        split in contiguous blocks of at least 256. Results do not depend on it.

    Attributes
    ----------
    t, y, f, h, ymax : numpy.ndarray
        Per-member time, state, derivative, next step and largest |y| so far.
    n_steps, n_rejected : numpy.ndarray of int
        Accepted and rejected steps per member.
    """

    order = 8

    def __init__(self, program, t0, y0, *, rtol, atol, max_steps: int = 10_000_000, workers: int | None = None):
        y = np.array(y0, dtype=float, order="C")
        if y.ndim != 2 or y.shape[1] not in (3, 7):
            raise ValueError("y0 must have shape (N, 3) or (N, 7)")
        n, d = y.shape
        # Writable C-ordered float64 copies: Numba compiles (and caches) one version per array type.
        self.program = TorqueProgram(*(np.array(a, dtype=float, order="C") for a in program))
        # Writable C-ordered copies: Numba compiles (and caches) one version per array
        # type, and a read-only broadcast view is another type.
        self.rtol = np.array(np.broadcast_to(np.asarray(rtol, dtype=float), (n,)), order="C")
        if np.any(self.rtol < 100 * EPS):
            raise ValueError("rtol below 100 eps cannot be met in float64")
        self.atol = np.array(np.broadcast_to(np.asarray(atol, dtype=float), (n, d)), order="C")
        self.max_steps = int(max_steps)
        self.workers = _cpus() if workers is None else max(1, int(workers))
        self.t = np.full(n, float(t0))
        self.y = y
        self.f = np.empty_like(y)
        _initial_f(float(t0), y, self.f, self.program)
        self.h = np.full(n, np.nan)  # chosen on the first call, when the end time is known
        self.ymax = np.abs(y)
        self.n_steps = np.zeros(n, dtype=np.int64)
        self.n_rejected = np.zeros(n, dtype=np.int64)
        self._nfev = np.ones(n, dtype=np.int64)
        self._flags = np.zeros(n, dtype=np.int64)

    @property
    def nfev(self) -> int:
        """Member-evaluations of the right-hand side."""
        return int(self._nfev.sum())

    def advance(self, t_out):
        """Integrate every member to ``t_out[-1]``, returning the states at ``t_out``, (T, N, d).

        Raises
        ------
        StepLimitError
            A member's step underflowed or its budget ran out (the message says which).
        """
        t_out = np.ascontiguousarray(t_out, dtype=float).reshape(-1)
        n, d = self.y.shape
        out = np.empty((t_out.size, n, d))
        if t_out.size == 0:
            return out
        check_output_times(t_out, self.t)
        self._flags[:] = 0  # "rejected just before" does not carry over from an earlier call
        args = (
            t_out,
            self.t,
            self.y,
            self.f,
            self.h,
            self.ymax,
            self.n_steps,
            self.n_rejected,
            self._nfev,
            self._flags,
            self.rtol,
            self.atol,
            self.max_steps,
            out,
            self.program,
        )
        workers = min(self.workers, n // _MEMBERS_PER_THREAD)
        if workers <= 1:
            code, member = _advance(0, n, *args)
        else:
            # The kernel releases the GIL: threads share the member arrays (disjoint rows),
            # and nest safely inside a caller's own pool (dask), unlike Numba's parallel layers.
            bounds = np.linspace(0, n, workers + 1).astype(int)
            with ThreadPoolExecutor(workers) as pool:
                results = list(pool.map(lambda k: _advance(int(bounds[k]), int(bounds[k + 1]), *args), range(workers)))
            code, member = next(((c, m) for c, m in results if c != OK), (OK, -1))
        if code == STEP_UNDERFLOW:
            raise StepLimitError(f"step size underflow at t = {self.t[member]!r} (member {member})")
        if code == STEP_LIMIT:
            raise StepLimitError(f"more than {self.max_steps} steps (tolerance too tight for the span?)")
        return out
