"""Q of the Chandler wobble from the shape of its spectral line (Whittle likelihood of a damped oscillator).

Times in s, angles in rad, rates in rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from wobble.errors import InputError
from wobble.models.polar_motion.record import ANNUAL_RATE, DAY, TROPICAL_YEAR, as_series, bin_means
from wobble.numerics.nelder_mead import minimize_nelder_mead
from wobble.numerics.spectral import dtft_at
from wobble.numerics.threads import one_blas_thread

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = ["QualityFactor", "MIN_Q_SPAN", "quality_factor"]


@dataclass(frozen=True)
class QualityFactor:
    """Q of the Chandler wobble from the shape of its spectral line (see :func:`quality_factor`).

    ``value`` is the maximum-likelihood Q (``inf`` when the line is no wider
    than the record's resolution); ``low``/``high`` bound the 68 % interval
    (profile likelihood); ``lower_bound_95`` is the one-sided 95 % lower limit.
    """

    value: float
    low: float
    high: float
    lower_bound_95: float
    period: float
    n_ordinates: int
    resolved: bool
    caveats: tuple[str, ...]


MIN_Q_SPAN = 20.0 * JULIAN_YEAR
_Q_GRID = np.concatenate([np.logspace(0.5, 5.0, 22), [np.inf]])
_Q_BIN = 10.0 * DAY
# Centre offset (resolution units), log line power and log background (periodogram scale).
_Q_BOUNDS = [(-3.0, 3.0), (-30.0, 30.0), (-30.0, 30.0)]
_HALF_BAND = 0.25 * 2 * math.pi / TROPICAL_YEAR  # +/- 0.25 cycle per year around the peak
_ANNUAL_NOTCH = 0.03 * 2 * math.pi / TROPICAL_YEAR


def _lag_counts(t: np.ndarray) -> tuple[np.ndarray, float]:
    """Number of sample pairs at each lag l*dt (l >= 0) of the sampling grid."""
    dt = float(np.median(np.diff(t)))
    idx = np.rint((t - t[0]) / dt).astype(int)
    n = int(idx[-1]) + 1
    mask = np.zeros(n)
    mask[idx] = 1.0
    nfft = 1 << int(math.ceil(math.log2(2 * n)))
    m = np.fft.rfft(mask, nfft)
    counts = np.fft.irfft(np.abs(m) ** 2, nfft)[:n]
    return np.rint(counts), dt


@one_blas_thread
def quality_factor(t, y, rate: float) -> QualityFactor:
    """Q of the Chandler wobble from the width of its spectral line (Whittle likelihood).

    The Chandler term of a record with the drift and the annual terms removed
    (``y``, rad; times ``t``, s) is modelled as a randomly excited damped
    oscillator, a complex process with autocovariance

        R(tau) = P exp(i sigma_0 tau - sigma_0 |tau| / (2 Q))               (3)

    (a Lorentzian line of full width sigma_0/Q; amplitude decay time 2Q/sigma_0)
    plus a flat background b. The expected periodogram at the Fourier
    frequencies within 0.25 cycle per year of ``rate`` (0.03 cycle per year
    around the annual frequency left out) follows exactly from (3)
    and the sampling (no window approximation):
    E I(sigma) = (1/N) sum_{n,m} R(t_n - t_m) e^{-i sigma (t_n - t_m)} + b.
    The Whittle likelihood sum(ln E + I/E) is profiled over Q (sigma_0, P and
    b free at each Q); ``low``/``high`` are where it rises by 0.5 (68 %), the
    one-sided 95 % lower bound where it rises by 1.35.

    Caveats (returned in the result): the model assumes an excitation with a
    flat spectrum near the Chandler frequency and a stationary process;
    Yamaguchi & Furuya (2025, Earth Planets Space 77) argue that neither P nor
    Q can be optimised from polar motion alone for that reason. A record of a
    few decades holds only one or two decay times (38 years for Q = 100), so
    the line is barely resolved and Q is often only bounded from below.
    """
    t, y = as_series(t, y, "chandler series")
    span = t[-1] - t[0]
    if span < MIN_Q_SPAN:
        raise InputError(
            "span", f"{span / JULIAN_YEAR:.1f} yr", f"at least {MIN_Q_SPAN / JULIAN_YEAR:.0f} yr for a Q estimate"
        )
    # Ten-day means: the line is within 0.12 cycle/yr of 0.84 cycle/yr, far below
    # the new Nyquist frequency (18 cycles/yr); the boxcar loses 0.1 % there.
    t, y = bin_means(t, y, _Q_BIN)
    lik = _Whittle(t, y, rate, span)
    fresh = np.array([0.0, math.log(4.0), math.log(0.05)])
    offsets = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    options = {"xatol": 1e-4, "fatol": 1e-6, "maxfev": 2000}
    lower, upper = np.array(_Q_BOUNDS).T
    # Two searches at each Q: a warm start from the previous Q's best, and a fresh start (a warm
    # start alone can stay in a poor local minimum found at a very different Q). The fresh starts
    # depend on nothing else: all their searches run at once, step by step in lockstep.
    fresh_x, fresh_f = minimize_nelder_mead(
        lik.nlls, np.broadcast_to(fresh + offsets, (_Q_GRID.size, 4, 3)), lower, upper, **options
    )
    x = fresh
    profile = []
    for j in range(_Q_GRID.size):
        res = optimize.minimize(
            lik.nll,
            x,
            args=(j,),
            method="Nelder-Mead",
            bounds=_Q_BOUNDS,
            options={"initial_simplex": x + offsets, **options},
        )
        best_x, best_f = res.x, res.fun
        if fresh_f[j] < best_f:
            best_x, best_f = fresh_x[j], fresh_f[j]
        x = best_x
        profile.append((best_f, best_x[0]))
    values = np.array([p[0] for p in profile])
    i = int(np.argmin(values))
    dev = values - values[i]
    logq = np.log10(np.where(np.isfinite(_Q_GRID), _Q_GRID, 1e6))
    low = _crossing(logq, dev, i, 0.5, -1)
    high = _crossing(logq, dev, i, 0.5, +1)
    lower95 = _crossing(logq, dev, i, 1.3528, -1)
    sigma0 = rate + profile[i][1] * 2 * math.pi / span
    value = _vertex(logq, dev, i) if i < len(_Q_GRID) - 2 else math.inf
    resolved = math.isfinite(value) and math.isfinite(high)
    caveats = [
        "assumes a flat excitation spectrum near the Chandler frequency and a stationary process "
        "(Yamaguchi & Furuya 2025 argue P and Q cannot be optimised from polar motion alone)",
        f"the {span / JULIAN_YEAR:.0f}-yr record spans only {span * sigma0 / 200:.1f} "
        "decay times for Q = 100 (decay time 2Q/sigma_0): the line is barely resolved",
    ]
    if not resolved:
        caveats.append("the line is no wider than the resolution: only a lower bound on Q is meaningful")
    return QualityFactor(value, low, high, lower95, 2 * math.pi / sigma0, int(lik.ords.size), resolved, tuple(caveats))


class _Whittle:
    """The Whittle likelihood of :func:`quality_factor` for a binned series ``(t, y)``: ``nlls(xs, index)``
    at many points (Q = ``_Q_GRID[index]``), ``nll(x, j)`` at one.

    x = (centre offset in resolution units, log line power, log background), both relative to
    the periodogram's scale, at the Fourier frequencies within 0.25 cycle per year of ``rate``.
    """

    def __init__(self, t, y, rate, span):
        s = t - t[0]
        counts, dt = _lag_counts(t)
        lags = dt * np.arange(counts.size)
        n = t.size
        k0 = math.ceil((rate - _HALF_BAND) * span / (2 * math.pi))
        k1 = math.floor((rate + _HALF_BAND) * span / (2 * math.pi))
        ords = 2 * math.pi * np.arange(k0, k1 + 1) / span
        # Leave out the annual frequency, whose fitted term leaves a notch.
        ords = ords[np.abs(ords - ANNUAL_RATE) > _ANNUAL_NOTCH]
        self.spec = np.abs(dtft_at(s, y, ords)) ** 2 / n
        keep = counts > 0
        self.lags, self.counts = lags[keep], counts[keep]
        # Without gaps the pair counts are n - l at lag l, and the sum over lags has a
        # closed form (a geometric series and its derivative): O(K) instead of O(K L).
        self.complete = self.counts.size == n and np.array_equal(self.counts, n - np.arange(n))
        self.phase = None if self.complete else np.exp(-1j * np.multiply.outer(ords, self.lags))
        self.t, self.y, self.ords, self.n, self.dt, self.rate, self.span = t, y, ords, n, dt, rate, span
        # Power and background are fitted relative to the periodogram's scale.
        self.scale = float(np.mean(self.spec))

    def nll(self, x, j) -> float:
        """sum(ln E + I/E) at x for the quality factor ``_Q_GRID[j]`` (1e300 where E is not positive)."""
        return float(self.nlls(np.asarray(x, dtype=float)[None, :], np.array([j]))[0])

    def nlls(self, xs, index) -> np.ndarray:
        """The negative log-likelihood at every point ``xs[j]`` for the quality factor ``_Q_GRID[index[j]]``.

        E I, the expected periodogram at the ordinates (equation 3 plus the background), from the
        pair counts at each lag (one matrix product, with one BLAS thread: see quality_factor's
        decorator), or, without gaps, their closed form.
        """
        scale, n = self.scale, self.n
        qs = _Q_GRID[index]
        sigma0 = self.rate + xs[:, 0] * 2 * math.pi / self.span
        power = scale * np.exp(xs[:, 1:2]) / n
        background = scale * np.exp(xs[:, 2:3])
        gamma = np.where(np.isfinite(qs), sigma0 / (2 * qs), 0.0)[:, None]
        if self.complete:
            total = 2 * _lag_sum(n, (1j * (sigma0[:, None] - self.ords) - gamma) * self.dt).real - n
        else:
            kern = self.counts * np.exp(1j * sigma0[:, None] * self.lags - gamma * self.lags)
            total = 2 * (kern @ self.phase.T).real - self.counts[0]  # lag 0 counted once
        e = power * total / n + background
        out = np.full(len(index), 1e300)
        good = ~(e <= 0).any(axis=1)
        out[good] = (np.log(e[good]) + self.spec / e[good]).sum(axis=1)
        return out


def _lag_sum(n: int, a: np.ndarray) -> np.ndarray:
    """sum_{l=0}^{n-1} (n - l) exp(a l) for each complex ``a`` (Re a <= 0), in closed form.

    With r = e^a and w = 1 - r: (n w - r (1 - r^n)) / w^2. The numerator is
    about n^2 w^2 / 2 made of terms of order one, so where |n w| < 0.5 the
    closed form would lose digits and the sum is taken term by term.
    """
    r = np.exp(a)
    w = -np.expm1(a)
    far = np.abs(n * w) >= 0.5
    if far.all():  # the usual case: no selection to make (this runs thousands of times per Q profile)
        return (n * w - r * (-np.expm1(n * a))) / w**2
    out = np.empty(a.shape, dtype=complex)
    rf, wf = r[far], w[far]
    out[far] = (n * wf - rf * (-np.expm1(n * a[far]))) / wf**2
    if not np.all(far):
        l = np.arange(n)
        out[~far] = np.exp(np.multiply.outer(a[~far], l)) @ (n - l).astype(float)
    return out


def _vertex(logq, dev, i) -> float:
    """Q at the vertex of the parabola in log Q through the profile's least deviance and its two neighbours.

    The grid's points are a factor 1.64 apart, so the least one alone put the maximum-likelihood Q up to 28 %
    off (and printed a grid value to every digit, 439.397056076079); the crossings of the intervals were
    already interpolated. With dev[i] the least of the three the vertex lies within half a step of it.
    """
    if i == 0:
        return float(10 ** logq[0])
    a, b, c = dev[i - 1], dev[i], dev[i + 1]
    curvature = a - 2.0 * b + c
    shift = 0.5 * (a - c) / curvature if curvature > 0 else 0.0
    step = logq[i + 1] - logq[i]
    return float(10 ** (logq[i] + min(max(shift, -0.5), 0.5) * step))


def _crossing(logq, dev, i, level, direction) -> float:
    """Q where the profile deviance ``dev`` first exceeds ``level`` going ``direction`` from index i."""
    j = i
    while 0 <= j + direction < len(dev):
        nxt = j + direction
        if dev[nxt] >= level:
            a, b = dev[j], dev[nxt]
            frac = (level - a) / (b - a) if b != a else 0.0
            lq = logq[j] + frac * (logq[nxt] - logq[j])
            return float(10**lq) if lq < 5.99 else math.inf
        j = nxt
    return 0.0 if direction < 0 else math.inf
