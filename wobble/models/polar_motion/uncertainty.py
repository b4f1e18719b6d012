"""The uncertainty of a Chandler estimate: autocorrelation (HAC), sub-spans, drift model, excitation.

The residuals of equation (2) are not white: they hold the changes of the
Chandler amplitude and phase over the decades, interannual motion and the
annual wobble's variations, all strongly autocorrelated. A white-noise
("formal") error is 20-300 times too small. Each estimator reports

* ``autocorrelation``: for least squares, the sandwich (HAC) covariance
  B^-1 M B^-1 whose middle term sums the autocovariances of the score series
  with Bartlett weights up to one beat period or a tenth of the span,
  whichever is shorter (Newey & West 1987; :func:`hac_meat`), divided by the
  fixed-b bias factor 1 - b + b^2/3 of that estimator (Kiefer & Vogelsang
  2005); for the spectrum, the local level of the residual spectrum in a ring
  outside the peak's main lobe (Whittle 1952; Hannan 1973);
* ``subspans``: the scatter of the same estimator over n >= 3 disjoint
  sub-spans of at least two beat periods (:func:`subspan_scatter`);
* ``excitation``: the scatter of a randomly excited damped mode's mean period
  (parametric Monte Carlo, :func:`excitation_scatter`);
* ``model``: the largest change when the drift polynomial has one degree
  more or less (:func:`model_sensitivity`).

The adopted uncertainty is ``sqrt(max(autocorrelation, subspans,
excitation)^2 + model^2)`` (:func:`combine`). Times in s, angles in rad.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from wobble.errors import InputError
from wobble.models.polar_motion.fit import ChandlerFit, Uncertainty
from wobble.models.polar_motion.record import DAY, MAX_DRIFT_DEGREE, bin_means, same_times
from wobble.numerics.recurrence import linear_recurrence

__all__ = [
    "HAC_MAX_B",
    "TRACKED",
    "tracked_columns",
    "hac_meat",
    "scaled_inverse",
    "sqrt_var",
    "scatter",
    "tracked",
    "subspan_scatter",
    "model_degrees",
    "model_sensitivity",
    "largest_change",
    "annual_sigmas",
    "combine",
    "damped_oscillator",
    "excitation_scatter",
    "amp_phase_sigma",
]

# Bartlett bandwidth: one beat period, at most a tenth of the span (a wider
# window is biased low by the scores' zero sum; checked on synthetic records).
HAC_MAX_B = 0.1
_MC_BIN = 5.0 * DAY
# Student-t factor turning a scatter over n sub-spans into a 68 % (1-sigma) error.
# (scipy.special, not scipy.stats: the same numbers, without the 0.3-0.6 s import.)
_ONE_SIGMA = float(special.ndtr(1.0))


def hac_meat(t: np.ndarray, scores: np.ndarray, lag: float) -> np.ndarray:
    """Sum over lags |k| <= L of (1 - |k|/(L+1)) Gamma_k for the score series (Bartlett; Newey & West 1987).

    Samples are placed on a uniform grid of the median spacing (gaps stay
    empty), so uneven and gappy records are handled; the sum is done with FFTs.
    """
    dt = float(np.median(np.diff(t)))
    idx = np.rint((t - t[0]) / dt).astype(int)
    n = int(idx[-1]) + 1
    grid = np.zeros((n, scores.shape[1]))
    if np.all(np.diff(idx) > 0):
        grid[idx] = scores  # one sample per grid point (the usual case): the same as adding, without ufunc.at's cost
    else:
        np.add.at(grid, idx, scores)
    nlag = int(min(max(round(lag / dt), 1), n - 1))
    nfft = 1 << int(math.ceil(math.log2(n + nlag + 1)))
    weights = np.zeros(nfft)
    k = np.arange(nlag + 1)
    weights[: nlag + 1] = 1.0 - k / (nlag + 1.0)
    weights[nfft - nlag :] = weights[1 : nlag + 1][::-1]
    w_hat = np.fft.rfft(weights)
    g = np.fft.rfft(grid, nfft, axis=0)
    # sum over all f of w_f g_fi conj(g_fj), real: the scores are real and the weights even, so the
    # term at nfft - f is the conjugate of the term at f, and the half spectrum with its interior
    # frequencies counted twice gives the sum. One matrix product (a three-operand einsum was 20
    # times slower).
    w_hat = w_hat.real * np.where((np.arange(w_hat.size) == 0) | (np.arange(w_hat.size) == nfft // 2), 1.0, 2.0)
    meat = ((g.T * w_hat) @ g.conj()).real / nfft
    return 0.5 * (meat + meat.T)


def scaled_inverse(b: np.ndarray) -> np.ndarray:
    """Inverse of a normal matrix after scaling it to unit diagonal.

    The amplitude parameters (rad) and the frequency parameter (whose column
    is proportional to the Chandler amplitude, ~1e-7 rad) differ in scale by
    ~1e13; unscaled, the inverse loses every digit of the frequency's variance.
    """
    d = np.sqrt(np.diag(b))
    d = np.where(d > 0, d, 1.0)
    return np.linalg.inv(b / np.outer(d, d)) / np.outer(d, d)


def sqrt_var(v: float) -> float:
    """sqrt of a variance; inf when the information matrix is singular (the parameter is not determined)."""
    return math.sqrt(v) if math.isfinite(v) and v > 0 else math.inf


def scatter(values: list[float]) -> float:
    """sd / sqrt(n) times the Student-t factor: the 68 % error of the mean of n values."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    n = v.size
    if n < 3:
        return math.nan
    return float(np.std(v, ddof=1) / math.sqrt(n) * special.stdtrit(n - 1, _ONE_SIGMA))


TRACKED = ("period", "amplitude", "annual", "retrograde")


def tracked(f: ChandlerFit) -> dict[str, float]:
    return {
        "period": f.chandler.period,
        "amplitude": f.chandler.amplitude,
        "annual": f.annual_prograde.amplitude,
        "retrograde": f.annual_retrograde.amplitude,
    }


def tracked_columns(rates, chandler, annual, retrograde) -> list[dict[str, float]]:
    """:func:`tracked` values of many fits at once, from their Chandler rates (rad/s) and the complex
    amplitudes of the Chandler and annual terms (one entry per fit)."""
    return [
        {
            "period": 2 * math.pi / abs(rates[k]),
            "amplitude": abs(chandler[k]),
            "annual": abs(annual[k]),
            "retrograde": abs(retrograde[k]),
        }
        for k in range(len(rates))
    ]


def subspan_scatter(t, z, estimator, beat: float, batch=None, **kwargs) -> tuple[dict[str, float], int]:
    """Scatter of ``estimator`` over n >= 3 disjoint sub-spans of >= 2 beat periods.

    Returns the 68 % error of the mean of each tracked quantity (Chandler
    period and amplitude, annual amplitudes) and the number of sub-spans.
    ``batch(t, zs)``, when given, returns the :func:`tracked` values of the
    columns of ``zs`` (many series on the same times) as ``estimator`` would:
    sub-spans that hold the same times about their centre (a gap-free daily
    record's) are measured by it together.
    """
    span = t[-1] - t[0]
    n = int(span // (2.0 * beat))
    if n < 3:
        return dict.fromkeys(TRACKED, math.nan), 0
    edges = t[0] + span * np.arange(n + 1) / n
    masks = {}
    for j, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        m = (t >= a) & (t <= b)
        if m.sum() < 10 or t[m][-1] - t[m][0] < 0.8 * (b - a):
            continue
        masks[j] = m
    found = {}
    for members in same_times(t, masks) if batch is not None else []:
        tm = t[masks[members[0]]]
        found.update(zip(members, batch(tm, np.column_stack([z[masks[j]] for j in members]))))
    values: dict[str, list[float]] = {k: [] for k in TRACKED}
    for j, m in masks.items():  # in the order of the sub-spans, as the scatter's sums have always run
        if j not in found:
            try:
                found[j] = tracked(estimator(t[m], z[m], uncertainty=False, **kwargs))
            except InputError:
                continue
        for k, v in found[j].items():
            values[k].append(v)
    return {k: scatter(v) for k, v in values.items()}, len(values["period"])


def model_degrees(degree: int) -> list[int]:
    """The drift degrees of the model check: one less (not below 0) and one more (not above
    :data:`~wobble.models.polar_motion.record.MAX_DRIFT_DEGREE`) than ``degree``."""
    return sorted({max(degree - 1, 0), min(degree + 1, MAX_DRIFT_DEGREE)} - {degree})


def model_sensitivity(t, z, estimator, degree, base: ChandlerFit, **kwargs) -> dict[str, float]:
    """Largest change of each tracked quantity with drift degree -1/+1."""
    return largest_change(
        base, [tracked(estimator(t, z, drift_degree=d, uncertainty=False, **kwargs)) for d in model_degrees(degree)]
    )


def largest_change(base: ChandlerFit, others: list[dict[str, float]]) -> dict[str, float]:
    """Largest change of each tracked quantity from ``base`` to the ``others`` (:func:`tracked` values)."""
    ref = tracked(base)
    out = dict.fromkeys(TRACKED, 0.0)
    for values in others:
        for k, v in values.items():
            out[k] = max(out[k], abs(v - ref[k]))
    return out


def annual_sigmas(auto: list[tuple[float, float]], sub: dict, mod: dict) -> list[tuple[float, float]]:
    """Adopted (amplitude, phase) sigmas of the annual terms: autocorrelation, sub-spans and drift model."""
    out = []
    for (a_auto, p_auto), key in zip(auto, ("annual", "retrograde")):
        main = max(x for x in (a_auto, sub[key], 0.0) if math.isfinite(x))
        out.append((math.hypot(main, mod[key]), p_auto))
    return out


def combine(formal, autocorrelation, subspans, model, excitation=math.nan) -> Uncertainty:
    main = max(x for x in (autocorrelation, subspans, excitation, 0.0) if math.isfinite(x))
    return Uncertainty(formal, autocorrelation, subspans, model, math.hypot(main, model), excitation)


def damped_oscillator(t, rate, q, power, draws, rng) -> np.ndarray:
    """Realisations of the randomly excited free wobble, equation (3), at times ``t``: shape (n, draws).

    The complex Ornstein-Uhlenbeck process m(t + d) = exp((i rate - g) d) m(t)
    + sqrt(power (1 - exp(-2 g d))) xi, g = rate/(2Q), started in its
    stationary state (E|m|^2 = power): exact for any spacing d.
    """
    g = rate / (2.0 * q)
    dt = np.diff(t)
    scale = np.sqrt(power * -np.expm1(-2.0 * g * dt))
    xi = (rng.standard_normal((t.size, draws)) + 1j * rng.standard_normal((t.size, draws))) / math.sqrt(2.0)
    kick = scale[:, None] * xi[1:]
    if dt.size and np.all(dt == dt[0]):
        # A uniform grid (the Monte Carlo's five-day means of a daily record): one factor, and the
        # recurrence by blocks of matrix products.
        return linear_recurrence(math.sqrt(power) * xi[0], (1j * rate - g) * dt[0], kick)
    lam = np.exp((1j * rate - g) * dt)
    out = np.empty((t.size, draws), dtype=complex)
    out[0] = math.sqrt(power) * xi[0]
    for k in range(1, t.size):
        np.multiply(lam[k - 1], out[k - 1], out=out[k])
        out[k] += kick[k - 1]
    return out


def excitation_scatter(t, fit: ChandlerFit, estimator, q, draws, seed) -> float:
    """RMS error of the period when the wobble is a randomly excited damped mode of quality ``q``.

    Parametric Monte Carlo: the fitted drift and annual terms plus ``draws``
    realisations of equation (3) with the fitted period and a mean power equal
    to the fitted amplitude squared, sampled at the record's own times (in
    five-day means when the record is denser) and measured with the same
    estimator. This is the scatter of a record's mean period about the free
    mode's period (Kuehne, Johnson & Wilson 1996 use the same kind of test).
    The errors have heavy tails; their RMS is returned (the half-width of
    their central 68 % is some 30 % smaller), so the 68 % level is covered
    with room and a 2-sigma interval stays near 95 %. With the default 64
    draws the RMS itself is uncertain by about 15 %.

    ``estimator(t, zs)`` returns the periods of all the columns of ``zs`` at once
    (both estimators' batched searches: ``vp_periods``, ``spectrum_periods``).
    """
    rng = np.random.default_rng(seed)
    if np.median(np.diff(t)) < _MC_BIN:
        # Five-day means for speed: the averaging changes the Chandler and
        # annual terms by less than 0.1 %, and keeps the record's gaps.
        t, _ = bin_means(t, np.zeros(t.size, dtype=complex), _MC_BIN)
    base = fit.model(t, terms=("drift", "annual_prograde", "annual_retrograde"))
    sims = damped_oscillator(t, fit.chandler.rate, q, fit.chandler.amplitude**2, draws, rng)
    errors = estimator(t, base[:, None] + sims) - fit.chandler.period
    return float(np.sqrt(np.mean(np.square(errors)))) if errors.size else math.nan


def amp_phase_sigma(c: complex, cov2: np.ndarray) -> tuple[float, float]:
    """Delta-method sigmas of |c| and arg c from the 2x2 covariance of (Re c, Im c)."""
    a = abs(c)
    if a == 0:
        return math.nan, math.nan
    ga = np.array([c.real, c.imag]) / a
    gp = np.array([-c.imag, c.real]) / a**2
    return float(math.sqrt(max(ga @ cov2 @ ga, 0.0))), float(math.sqrt(max(gp @ cov2 @ gp, 0.0)))
