"""Time integrators in float64, vectorised over ensemble members (no units, SI by convention).

Two families, both stepping N independent members at once (arrays of shape
``(N, ...)``, no Python loop over members):

* :class:`DOP853`: the explicit Runge-Kutta pair of Dormand & Prince of
  order 8 with the 5th- and 3rd-order error estimators and the 7th-order
  dense output (Hairer, Norsett & Wanner, *Solving ODEs I*, section II.10;
  the tableau is :mod:`wobble.numerics._dop853_tableau`). **Every member
  has its own time, step size and error control**: members that finish
  drop out of the arrays; each member's outputs come from its own dense
  output. The error norm is the RMS over components of
  ``err_i / (atol_i + rtol * max(|y_i| so far, |y_new_i|))``: each component
  is scaled by the largest value *it* has reached, so a component that
  stays small (the wobble of a planet, 1e-6 of its spin) is controlled
  relative to its own size, not to the spin (see docs/engine.md).
* :class:`Splitting`: symmetric compositions of the Strang splitting
  ``K(h/2) D(h) K(h/2)`` of two exactly solvable flows (Touma & Wisdom 1994,
  AJ 107, 1189: the exact free rigid body ``D`` between torque kicks ``K``),
  of order 2, 4 (Suzuki 1990, five stages) and 6 (Yoshida 1990, solution
  A, seven stages). Fixed steps shared by all members; the flows may
  differ per member. Both flows are exact, so the method is a Poisson map
  for conservative torques: energy and |L| errors stay bounded over very
  long runs instead of drifting.

Both expose ``advance(t_out)``, which continues from where the last call
stopped, so long runs can be computed (and written) block by block.

Global error: neither method knows its global error from one run. The
callers (:mod:`wobble.models.engine`) run a companion (a looser tolerance,
or twice the step) and compare; see :func:`composition` for the splitting's
Richardson factor.
"""

from __future__ import annotations

import numpy as np

from wobble.numerics import _dop853_tableau as _T

__all__ = ["DOP853", "Splitting", "composition", "StepLimitError", "COMPOSITIONS", "check_output_times"]

_SAFETY = 0.9
_MIN_FACTOR = 0.2
_MAX_FACTOR = 10.0
_EXPONENT = -1.0 / 8.0  # 1 / (order of the error estimator + 1), as in Hairer's DOP853

_A = _T.A[: _T.N_STAGES, : _T.N_STAGES]
_B = _T.B
_C = _T.C[: _T.N_STAGES]
_E3 = _T.E3
_E5 = _T.E5
_A_EXTRA = _T.A[_T.N_STAGES + 1 :]
_C_EXTRA = _T.C[_T.N_STAGES + 1 :]
_D = _T.D


class StepLimitError(RuntimeError):
    """An integration needed more steps than allowed, or its step underflowed."""


def _rows(a, rows):
    """``a[rows]``, or ``a`` itself for rows None (all members: a view, no copy)."""
    return a if rows is None else a[rows]


def check_output_times(t_out, t):
    """Refuse output times that decrease or precede any member's current time ``t``."""
    if np.any(np.diff(t_out) < 0) or t_out[0] < t.max():
        raise ValueError("output times must increase and not precede the current time")


def _rms(x):
    return np.sqrt(np.mean(x * x, axis=-1))


class DOP853:
    """Adaptive Dormand-Prince 8(5,3) for N independent members, with dense output.

    Parameters
    ----------
    fun : callable
        ``fun(t, y, idx) -> dy/dt`` with ``t`` of shape (n,), ``y`` of shape
        (n, d) and ``idx`` the indices (n,) of the members they belong to
        (so that per-member parameters can be picked).
    t0 : float
        Start time, shared by all members.
    y0 : array_like, shape (N, d)
        Initial states.
    rtol : float or array_like, shape (N,)
        Relative tolerance per member (at least 100 eps).
    atol : float or array_like, shape (d,) or (N, d)
        Absolute floor of the scale of each component (> 0 where a component
        may stay exactly zero and then become non-zero).
    project : callable, optional
        ``project(y)`` returns y mapped back onto the manifold (e.g. unit
        quaternions) after each accepted step.
    max_steps : int
        Step budget per member across all calls; exceeding it raises
        :class:`StepLimitError`.
    fixed_step : float, optional
        Take steps of this size (the last one of each call shorter) and accept
        them all, without error control: for measuring the order of the method.

    Attributes
    ----------
    t, y : numpy.ndarray
        Current time and state of each member.
    n_steps, n_rejected : numpy.ndarray of int
        Accepted and rejected steps per member.
    nfev : int
        Member-evaluations of ``fun`` (one call on n members counts n).
    """

    order = 8

    def __init__(self, fun, t0, y0, *, rtol, atol, project=None, max_steps: int = 10_000_000, fixed_step=None):
        self.fun = fun
        y0 = np.array(y0, dtype=float)
        if y0.ndim != 2:
            raise ValueError("y0 must have shape (N, d)")
        n, d = y0.shape
        self.t = np.full(n, float(t0))
        self.y = y0
        self.rtol = np.broadcast_to(np.asarray(rtol, dtype=float), (n,)).copy()
        if np.any(self.rtol < 100 * np.finfo(float).eps):
            raise ValueError("rtol below 100 eps cannot be met in float64")
        self.atol = np.broadcast_to(np.asarray(atol, dtype=float), (n, d)).copy()
        self.project = project
        self.max_steps = int(max_steps)
        self.ymax = np.abs(y0)
        self._all = np.arange(n)
        self.f = np.asarray(fun(self.t, self.y, self._all), dtype=float)
        self.nfev = n
        self.n_steps = np.zeros(n, dtype=np.int64)
        self.n_rejected = np.zeros(n, dtype=np.int64)
        self.h = None  # chosen on the first call, when the direction of time is known
        self.fixed_step = None if fixed_step is None else float(fixed_step)
        if self.fixed_step is not None:
            self.h = np.full(n, self.fixed_step)

    # -- step-size heuristics ---------------------------------------------------
    def _scale(self, idx, y_new=None):
        """atol + rtol * (largest |y| so far, and |y_new|), for the members ``idx`` (None: all)."""
        ymax = _rows(self.ymax, idx)
        ref = ymax if y_new is None else np.maximum(ymax, np.abs(y_new))
        return _rows(self.atol, idx) + _rows(self.rtol, idx)[:, None] * ref

    def _initial_step(self, t_end):
        """Hairer's starting step (Solving ODEs I, II.4), per member; one extra evaluation."""
        span = np.abs(t_end - self.t)
        scale = self._scale(None)
        d0 = _rms(self.y / scale)
        d1 = _rms(self.f / scale)
        with np.errstate(divide="ignore", invalid="ignore"):
            h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6 * np.maximum(span, 1e-300), 0.01 * d0 / d1)
        h0 = np.minimum(h0, span)
        y1 = self.y + h0[:, None] * self.f
        f1 = np.asarray(self.fun(self.t + h0, y1, self._all), dtype=float)
        self.nfev += self.t.size
        with np.errstate(divide="ignore", invalid="ignore"):
            d2 = _rms((f1 - self.f) / scale) / h0
            big = np.maximum(d1, d2)
            h1 = np.where(big <= 1e-15, np.maximum(1e-6, h0 * 1e-3), (0.01 / big) ** (1.0 / (self.order + 1)))
        return np.minimum(np.minimum(100 * h0, h1), span)

    # -- the step ---------------------------------------------------------------
    def _stages(self, t, y, f, h, idx):
        n, d = y.shape
        K = np.empty((_T.N_STAGES + 1, n, d))
        K[0] = f
        hh = h[:, None]
        for s in range(1, _T.N_STAGES):
            dy = np.einsum("j,jnd->nd", _A[s, :s], K[:s])
            K[s] = self.fun(t + _C[s] * h, y + hh * dy, idx)
        y_new = y + hh * np.einsum("j,jnd->nd", _B, K[: _T.N_STAGES])
        return K, y_new

    def _error_norm(self, K, h, scale):
        err5 = np.einsum("j,jnd->nd", _E5, K) / scale
        err3 = np.einsum("j,jnd->nd", _E3, K) / scale
        e5 = np.sum(err5 * err5, axis=-1)
        e3 = np.sum(err3 * err3, axis=-1)
        denom = e5 + 0.01 * e3
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.abs(h) * e5 / np.sqrt(denom * K.shape[-1])
        return np.where(denom > 0, out, 0.0)

    def _dense(self, t_old, y_old, y_new, f_old, f_new, K, h, idx):
        """Coefficients F (7, n, d) of the 7th-order interpolant (three extra stages)."""
        n, d = y_old.shape
        Kx = np.empty((_T.N_STAGES_EXTENDED, n, d))
        Kx[: _T.N_STAGES + 1] = K
        hh = h[:, None]
        for s, (a, c) in enumerate(zip(_A_EXTRA, _C_EXTRA), start=_T.N_STAGES + 1):
            dy = np.einsum("j,jnd->nd", a[:s], Kx[:s])
            Kx[s] = self.fun(t_old + c * h, y_old + hh * dy, idx)
        self.nfev += 3 * n
        F = np.empty((_T.INTERPOLATOR_POWER, n, d))
        delta = y_new - y_old
        F[0] = delta
        F[1] = hh * f_old - delta
        F[2] = 2 * delta - hh * (f_new + f_old)
        F[3:] = hh * np.einsum("ij,jnd->ind", _D, Kx)
        return F

    @staticmethod
    def _interpolate(F, y_old, x):
        y = np.zeros_like(y_old)
        xx = x[:, None]
        for i, f in enumerate(F[::-1]):
            y += f
            y *= xx if i % 2 == 0 else 1.0 - xx
        return y + y_old

    def advance(self, t_out) -> np.ndarray:
        """Integrate every member to ``t_out[-1]``, returning the states at ``t_out``.

        Parameters
        ----------
        t_out : array_like, shape (T,)
            Increasing output times, none before the current time.

        Returns
        -------
        numpy.ndarray, shape (T, N, d)
        """
        t_out = np.asarray(t_out, dtype=float).reshape(-1)
        n, d = self.y.shape
        out = np.empty((t_out.size, n, d))
        if t_out.size == 0:
            return out
        check_output_times(t_out, self.t)
        t_end = t_out[-1]
        # Outputs at the current time come straight from the state.
        ptr = np.searchsorted(t_out, self.t, side="right")
        for k in range(int(ptr.max())):
            rows = np.flatnonzero((ptr > k) & (t_out[k] == self.t))
            out[k, rows] = self.y[rows]
        if self.h is None:
            self.h = self._initial_step(t_end)
        self.h = np.where(self.h > 0, self.h, np.abs(t_end - self.t))
        rejected_before = np.zeros(n, dtype=bool)
        while True:
            active = self.t < t_end
            if not active.any():
                break
            # All members active (the usual case): views, no gathers and scatters.
            idx = None if active.all() else np.flatnonzero(active)
            ids = self._all if idx is None else idx
            t, y, f = _rows(self.t, idx), _rows(self.y, idx), _rows(self.f, idx)
            h_now = _rows(self.h, idx)
            remaining = t_end - t
            last = h_now * (1 + 1e-9) >= remaining  # no sliver of a last step
            h = np.where(last, remaining, np.minimum(h_now, remaining))
            # A floor of 1e-290 s, not 1e-300: 16 eps 1e-300 is subnormal, an underflow that a caller's
            # np.seterr(under="raise") turned into a FloatingPointError at t = 0.
            if np.any(h <= 16 * np.finfo(float).eps * np.maximum(np.abs(t), 1e-290)):
                raise StepLimitError(f"step size underflow at t = {t[np.argmin(h)]!r}")
            K, y_new = self._stages(t, y, f, h, ids)
            t_new = np.where(last, t_end, t + h)
            K[-1] = self.fun(t_new, y_new, ids)
            self.nfev += (_T.N_STAGES) * ids.size
            err = self._error_norm(K, h, self._scale(idx, y_new))
            ok = err <= 1.0
            if self.fixed_step is not None:
                ok[:] = True
                err[:] = 1.0  # the step size stays as it is
            with np.errstate(divide="ignore"):
                grow = np.where(err == 0, _MAX_FACTOR, np.minimum(_MAX_FACTOR, _SAFETY * err**_EXPONENT))
                shrink = np.maximum(_MIN_FACTOR, _SAFETY * err**_EXPONENT)
            grow = np.where(_rows(rejected_before, idx), np.minimum(1.0, grow), grow)
            new_h = np.where(ok, h * grow, h * shrink)
            if self.fixed_step is not None:
                new_h[:] = self.fixed_step
            if idx is None:
                self.h = new_h
            else:
                self.h[idx] = new_h
            # Rejected members retry; accepted members move on.
            all_ok = bool(ok.all())
            if not all_ok:
                bad = ids[~ok]
                rejected_before[bad] = True
                self.n_rejected[bad] += 1
            gsel = None if all_ok else np.flatnonzero(ok)
            if gsel is not None and gsel.size == 0:
                continue
            gi = ids if gsel is None else ids[gsel]
            rejected_before[gi] = False
            yn = _rows(y_new, gsel)
            if self.project is not None:
                yn = self.project(yn)
            f_new = _rows(K[-1], gsel).copy()
            # Dense output for members with outputs in (t_old, t_new].
            t_old, tn, hg = _rows(t, gsel), _rows(t_new, gsel), _rows(h, gsel)
            first = ptr[gi]
            stop = np.searchsorted(t_out, tn, side="right")
            counts = stop - first
            has = counts > 0
            if np.any(has):
                ssel = None if has.all() else np.flatnonzero(has)
                Kg = K if gsel is None else K[:, gsel]
                F = self._dense(
                    _rows(t_old, ssel),
                    _rows(_rows(y, gsel), ssel),
                    _rows(yn, ssel),
                    _rows(_rows(f, gsel), ssel),
                    _rows(f_new, ssel),
                    Kg if ssel is None else Kg[:, ssel],
                    _rows(hg, ssel),
                    _rows(gi, ssel),
                )
                reps = _rows(counts, ssel)
                y_sel, yn_sel, t_sel, h_sel, tn_sel = (_rows(a, ssel) for a in (_rows(y, gsel), yn, t_old, hg, tn))
                g_sel, first_sel = _rows(gi, ssel), _rows(first, ssel)
                if np.all(reps == 1):
                    k_out, members = first_sel, g_sel
                    vals = self._interpolate(F, y_sel, (t_out[k_out] - t_sel) / h_sel)
                    at_end = t_out[k_out] == tn_sel
                    vals = np.where(at_end[:, None], yn_sel, vals)
                else:
                    member = np.repeat(np.arange(reps.size), reps)
                    offsets = np.arange(reps.sum()) - np.repeat(np.cumsum(reps) - reps, reps)
                    k_out = np.repeat(first_sel, reps) + offsets
                    members = g_sel[member]
                    vals = self._interpolate(
                        F[:, member], y_sel[member], (t_out[k_out] - t_sel[member]) / h_sel[member]
                    )
                    at_end = t_out[k_out] == tn_sel[member]
                    vals = np.where(at_end[:, None], yn_sel[member], vals)
                if self.project is not None:
                    vals = self.project(vals)
                out[k_out, members] = vals
                ptr[gi] = stop
            if idx is None and gsel is None:
                self.t, self.y, self.f = tn, yn, f_new
                self.ymax = np.maximum(self.ymax, np.abs(yn))
            else:
                self.t[gi] = tn
                self.y[gi] = yn
                self.f[gi] = f_new
                self.ymax[gi] = np.maximum(self.ymax[gi], np.abs(yn))
            self.n_steps[gi] += 1
            if self.n_steps.max() > self.max_steps:
                raise StepLimitError(f"more than {self.max_steps} steps (tolerance too tight for the span?)")
        return out


# --------------------------------------------------------------------------
# Splitting: symmetric compositions of Strang's K(h/2) D(h) K(h/2)
# --------------------------------------------------------------------------
def _suzuki4():
    p = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))
    return (p, p, 1.0 - 4.0 * p, p, p)


def _yoshida6():
    # Yoshida (1990), Phys. Lett. A 150, 262, Table 1, solution A.
    w1 = -1.17767998417887
    w2 = 0.235573213359357
    w3 = 0.784513610477560
    w0 = 1.0 - 2.0 * (w1 + w2 + w3)
    return (w3, w2, w1, w0, w1, w2, w3)


#: Drift fractions of each step, by order: Strang (2), Suzuki's fractal
#: five-stage (4), Yoshida's seven-stage solution A (6).
COMPOSITIONS = {2: (1.0,), 4: _suzuki4(), 6: _yoshida6()}


def composition(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Drift fractions ``a`` (s) and kick fractions ``b`` (s + 1) of one step of ``order``.

    A step of size h is ``K(b_0 h) D(a_0 h) K(b_1 h) ... D(a_{s-1} h) K(b_s h)``
    with ``b_0 = a_0 / 2``, ``b_i = (a_{i-1} + a_i) / 2``, ``b_s = a_{s-1} / 2``
    (adjacent half kicks merged). Richardson: with a step twice as long the
    error is ``2^order`` times larger, so the difference of the two runs
    divided by ``2^order - 1`` estimates the error of the finer one.
    """
    if order not in COMPOSITIONS:
        raise ValueError(f"order must be one of {sorted(COMPOSITIONS)}")
    a = np.asarray(COMPOSITIONS[order])
    b = np.empty(a.size + 1)
    b[0] = 0.5 * a[0]
    b[-1] = 0.5 * a[-1]
    b[1:-1] = 0.5 * (a[:-1] + a[1:])
    return a, b


class Splitting:
    """Composition integrator of two exact flows, shared fixed steps, N members.

    Parameters
    ----------
    drift : callable
        ``drift(state, t, h) -> state``: the exact flow of the first part
        (time-independent) over h (any sign), for all members.
    kick : callable
        ``kick(state, t, h) -> state``: the exact flow of the second part
        with the time frozen at t (time-dependent torques are evaluated at
        the time the kick happens: the extended phase space of Touma &
        Wisdom, where time advances during drifts only).
    t0 : float
        Start time.
    state : tuple of numpy.ndarray
        Initial state; its layout is the flows' business.
    order : int
        2, 4 or 6.
    step : float
        Largest step (s); each output interval is split into equal steps no
        longer than this.
    multiple : int
        The number of steps in each output interval is made a multiple of
        this (2 for a run that a companion at twice the step checks: the
        companion then takes exactly half as many steps, even where the
        outputs are closer together than the step).

    Attributes
    ----------
    n_steps : int
        Composition steps taken.
    """

    def __init__(self, drift, kick, t0, state, *, order: int, step: float, multiple: int = 1):
        self.drift = drift
        self.kick = kick
        self.t = float(t0)
        self.state = state
        self.order = int(order)
        self.a, self.b = composition(self.order)
        if not (np.isfinite(step) and step > 0):
            raise ValueError("step must be positive and finite")
        self.step_size = float(step)
        self.multiple = int(multiple)
        self.n_steps = 0

    def step(self, h: float) -> None:
        """One composition step of size ``h``."""
        state, t = self.state, self.t
        for a, b in zip(self.a, self.b):
            state = self.kick(state, t, b * h)
            state = self.drift(state, t, a * h)
            t += a * h
        self.state = self.kick(state, t, self.b[-1] * h)
        self.t += h
        self.n_steps += 1

    def advance(self, t_out) -> list:
        """States at the increasing times ``t_out`` (list of state tuples), continuing the run."""
        states = []
        for t_next in np.asarray(t_out, dtype=float).reshape(-1):
            span = t_next - self.t
            if span < 0:
                raise ValueError("output times must increase and not precede the current time")
            if span > 0:
                k = self.multiple
                n = k * max(1, int(np.ceil(span / (k * self.step_size) * (1 - 1e-12))))
                h = span / n
                start = self.t
                for k in range(n):
                    self.step(h)
                    self.t = start + (k + 1) * h  # no accumulated rounding in the clock
                self.t = float(t_next)
            states.append(self.state)
        return states
