"""The Chandler wobble measured in a polar-motion record (SI floats).

Units: time in seconds (any origin; the caller's), angles in radians,
angular frequencies in rad/s. Nothing here knows about files or units.

**Sign convention.** The pole is the complex number

    p = x_p - i y_p,                                                        (1)

with x_p toward the Greenwich meridian and y_p toward 90 deg W (IERS). With
this sign a term ``a exp(+i sigma t)``, sigma > 0, turns counter-clockwise seen
from above the north pole: *prograde*, in the sense of the Earth's rotation
(Munk & MacDonald 1960, sec. 6; Gross 2007, Treatise on Geophysics 3, eq. 11).
The Chandler wobble is prograde: its spectral peak is at +0.843 cycles per
year, which the test-suite checks on the IERS record.

**The model** of a record is

    p(t) = sum_j c_j tau^j + A_c e^{i sigma_c s} + A_+ e^{i Omega_a s}
           + A_- e^{-i Omega_a s},   s = t - t_e,  tau = s / h,              (2)

a slow drift of the mean pole (a polynomial of degree ``drift_degree`` in the
scaled time tau, h = half the span, t_e the mid epoch), the Chandler term and
the prograde and retrograde annual terms at the tropical year. The complex
amplitudes carry the phase at the epoch t_e.

**Two independent estimators** of sigma_c:

* :func:`fit_least_squares` - nonlinear least squares of (2) on the complex
  series: the frequency from the maximum of the profile (variable-projection)
  gain, then polished by :func:`scipy.optimize.least_squares` on every
  parameter;
* :func:`fit_spectrum` - the peak of the two-sided (complex) amplitude
  spectrum of the detrended series with a Hann taper (no annual terms are
  fitted: the taper's low side lobes keep the annual peak out).

**Uncertainties.** The residuals of (2) are not white: they hold the changes of
the Chandler amplitude and phase over the decades, interannual motion and the
annual wobble's variations, all strongly autocorrelated. A white-noise
("formal") error is 20-300 times too small. Each estimator reports

* ``autocorrelation``: for least squares, the sandwich (HAC) covariance
  B^-1 M B^-1 whose middle term sums the autocovariances of the score series
  with Bartlett weights up to one beat period or a tenth of the span,
  whichever is shorter (Newey & West 1987), divided by the fixed-b bias
  factor 1 - b + b^2/3 of that estimator (Kiefer & Vogelsang 2005); for the
  spectrum, the local level of the residual spectrum in a ring outside the
  peak's main lobe, in the peak-location variance (Whittle 1952; Hannan 1973:
  coloured noise enters through its spectral density at the line's frequency).
  On synthetic records with AR(1) noise of 200-day correlation time these
  match the actual scatter to 5-30 %;
* ``subspans``: the scatter of the same estimator over n >= 3 disjoint
  sub-spans of at least two beat periods, sd/sqrt(n) times the Student-t
  factor for 68 %. If the wobble's phase wanders this is the error of the
  record's mean frequency; for a pure sinusoid in noise it is conservative
  by about n;
* ``excitation``: the Chandler wobble is a free mode kept up by random
  excitation, so a record's mean period scatters about the mode's period by
  far more than the residual noise says (several days for 30-65 years at
  Q = 100). A parametric Monte Carlo (:func:`_excitation_scatter`) measures
  that scatter for an assumed Q (default 100; ``excitation_q=None`` leaves it
  out);
* ``model``: the largest change when the drift polynomial has one degree
  more or less.

The adopted uncertainty is ``sqrt(max(autocorrelation, subspans,
excitation)^2 + model^2)``: the first three are alternative measures of the
same random error under different hypotheses, the last a systematic one.
Spans shorter than one beat period between the Chandler and the annual term
(about 6.4 years) cannot separate the two well: the result says so in
``caveats``, and the model and excitation terms, which grow quickly there,
widen the error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from wobble.errors import InputError
from wobble.numerics.spectral import dtft, dtft_at

__all__ = [
    "DAY",
    "TROPICAL_YEAR",
    "ANNUAL_RATE",
    "REFERENCE_CHANDLER_PERIOD",
    "BEAT_PERIOD",
    "CHANDLER_BAND",
    "MIN_SPAN",
    "complex_pole",
    "pole_xy",
    "Harmonic",
    "Uncertainty",
    "ChandlerFit",
    "Spectrum",
    "WindowedFits",
    "QualityFactor",
    "fit_least_squares",
    "fit_spectrum",
    "two_sided_spectrum",
    "sliding_windows",
    "quality_factor",
    "MIN_Q_SPAN",
]

DAY = 86400.0
#: Mean tropical year (s): the period of the seasonal forcing of the annual wobble.
TROPICAL_YEAR = 365.24219 * DAY
ANNUAL_RATE = 2.0 * math.pi / TROPICAL_YEAR
#: Published Chandler period (Vicente & Wilson 1997: 433.1 d; data/bodies/earth.toml). Used only
#: to place the beat period that decides what a "short" span is; never a prior.
REFERENCE_CHANDLER_PERIOD = 433.1 * DAY
#: Beat of the Chandler and annual terms, 1/(1/T_a - 1/T_c): about 6.4 years.
BEAT_PERIOD = 1.0 / (1.0 / TROPICAL_YEAR - 1.0 / REFERENCE_CHANDLER_PERIOD)
#: Default search band for the Chandler period, s (390 to 500 days).
CHANDLER_BAND = (390.0 * DAY, 500.0 * DAY)
#: Shortest span analysed: two years (fewer than two Chandler cycles is not a period).
MIN_SPAN = 2.0 * 365.25 * DAY
_OVERSAMPLE = 8
_PREWHITEN = 30
_MC_BIN = 5.0 * DAY
# Bartlett bandwidth: one beat period, at most a tenth of the span (a wider
# window is biased low by the scores' zero sum; checked on synthetic records).
_HAC_MAX_B = 0.1
# Student-t factor turning a scatter over n sub-spans into a 68 % (1-sigma) error.
_ONE_SIGMA = stats.norm.cdf(1.0)


def complex_pole(x, y) -> np.ndarray:
    """The pole as p = x_p - i y_p (equation 1): prograde terms rotate as exp(+i sigma t)."""
    return np.asarray(x, dtype=float) - 1j * np.asarray(y, dtype=float)


def pole_xy(p) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`complex_pole`: (x_p, y_p) = (Re p, -Im p)."""
    p = np.asarray(p)
    return p.real.copy(), -p.imag


@dataclass(frozen=True)
class Harmonic:
    """One circular term a exp(i (rate s + phase)) of equation (2).

    Attributes
    ----------
    rate : float
        Signed angular frequency, rad/s (positive: prograde).
    rate_sigma : float
        One-sigma uncertainty of the rate, rad/s (0 when the rate is fixed).
    amplitude, amplitude_sigma : float
        Radius of the circle and its uncertainty, rad.
    phase, phase_sigma : float
        Argument of the complex amplitude at the fit's epoch, rad.
    """

    rate: float
    rate_sigma: float
    amplitude: float
    amplitude_sigma: float
    phase: float
    phase_sigma: float

    @property
    def period(self) -> float:
        """2 pi / |rate|, s."""
        return 2.0 * math.pi / abs(self.rate)

    @property
    def period_sigma(self) -> float:
        """Uncertainty of the period, s (first order: 2 pi sigma_rate / rate^2)."""
        return 2.0 * math.pi * self.rate_sigma / self.rate**2

    @property
    def complex_amplitude(self) -> complex:
        return self.amplitude * complex(math.cos(self.phase), math.sin(self.phase))


@dataclass(frozen=True)
class Uncertainty:
    """The pieces of one quantity's uncertainty (same unit as the quantity; NaN: not computed).

    ``adopted = sqrt(max(autocorrelation, subspans, excitation)^2 + model^2)``;
    ``formal`` (white residuals) is shown only to say how much too small it is.
    """

    formal: float
    autocorrelation: float
    subspans: float
    model: float
    adopted: float
    excitation: float = math.nan


@dataclass(frozen=True, eq=False)
class ChandlerFit:
    """The Chandler and annual terms and the mean-pole drift of one span.

    Times are in the caller's seconds; angles in rad; rates in rad/s.
    ``chandler.rate_sigma`` and ``chandler.amplitude_sigma`` are the adopted
    uncertainties; the breakdown is in ``period_uncertainty`` (s) and
    ``amplitude_uncertainty`` (rad).
    """

    method: str
    epoch: float
    start: float
    end: float
    n_samples: int
    drift_degree: int
    chandler: Harmonic
    annual_prograde: Harmonic
    annual_retrograde: Harmonic
    drift: np.ndarray
    half_span: float
    period_uncertainty: Uncertainty
    amplitude_uncertainty: Uncertainty
    residual_rms: float
    caveats: tuple[str, ...] = ()
    details: dict = field(default_factory=dict)

    @property
    def span(self) -> float:
        return self.end - self.start

    def mean_pole(self, t) -> np.ndarray:
        """The drift polynomial of equation (2) at times ``t`` (complex, rad)."""
        tau = (np.asarray(t, dtype=float) - self.epoch) / self.half_span
        return np.polynomial.polynomial.polyval(tau, self.drift)

    def model(self, t, *, terms=("drift", "chandler", "annual_prograde", "annual_retrograde")) -> np.ndarray:
        """Equation (2) at times ``t`` with the chosen terms (complex, rad)."""
        t = np.asarray(t, dtype=float)
        s = t - self.epoch
        out = np.zeros(t.shape, dtype=complex)
        if "drift" in terms:
            out += self.mean_pole(t)
        for name in ("chandler", "annual_prograde", "annual_retrograde"):
            if name in terms:
                h: Harmonic = getattr(self, name)
                out += h.complex_amplitude * np.exp(1j * h.rate * s)
        return out


@dataclass(frozen=True, eq=False)
class Spectrum:
    """Two-sided amplitude spectrum of a detrended pole series.

    ``amplitude[k]`` is |sum w z exp(-i rate_k s)| / sum w: the radius (rad) of
    a circular term at ``rate[k]`` (rad/s; negative = retrograde).
    """

    rate: np.ndarray
    amplitude: np.ndarray
    taper: str
    drift_degree: int


@dataclass(frozen=True, eq=False)
class WindowedFits:
    """Least-squares fits of equation (2) on sliding windows (arrays over windows).

    Windows whose data cover less than 80 % of their length are NaN.
    """

    centre: np.ndarray
    start: np.ndarray
    end: np.ndarray
    n_samples: np.ndarray
    period: np.ndarray
    period_sigma: np.ndarray
    amplitude: np.ndarray
    amplitude_sigma: np.ndarray
    phase: np.ndarray
    annual_amplitude: np.ndarray
    annual_amplitude_sigma: np.ndarray
    retrograde_annual_amplitude: np.ndarray
    window: float
    step: float
    drift_degree: int


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


# ---------------------------------------------------------------------------
# Checks
# ---------------------------------------------------------------------------


def _as_series(t, z, name: str = "series") -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(t, dtype=float)
    z = np.asarray(z, dtype=complex)
    if t.ndim != 1 or t.shape != z.shape:
        raise InputError(name, f"times {t.shape}, values {z.shape}", "1-D times and values of the same length")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(z))):
        raise InputError(name, "NaN or inf", "finite times and pole coordinates (drop missing samples first)")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        raise InputError(name, "times not increasing", "strictly increasing sample times")
    if t.size < 2 or t[-1] - t[0] < MIN_SPAN:
        span = 0.0 if t.size < 2 else (t[-1] - t[0]) / DAY
        raise InputError(
            name, f"a span of {span:.0f} d", f"a span of at least {MIN_SPAN / DAY:.0f} d (two years) to measure a period"
        )
    return t, z


def _check_band(band) -> tuple[float, float]:
    lo, hi = (float(b) for b in band)
    if not (math.isfinite(lo) and math.isfinite(hi) and TROPICAL_YEAR * 1.02 < lo < hi):
        raise InputError(
            "band", f"{lo / DAY:g} to {hi / DAY:g} d", "two periods, increasing, above 1.02 tropical years (372.5 d)"
        )
    return lo, hi


def _check_degree(drift_degree) -> int:
    if isinstance(drift_degree, bool) or not isinstance(drift_degree, (int, np.integer)) or not 0 <= drift_degree <= 6:
        raise InputError("drift_degree", drift_degree, "an integer from 0 (a fixed mean pole) to 6")
    return int(drift_degree)


def _check_q(q) -> float:
    try:
        value = float(q)
    except (TypeError, ValueError):
        raise InputError("excitation_q", q, "a quality factor above 1, or None") from None
    if not (math.isfinite(value) and value > 1.0):
        raise InputError("excitation_q", q, "a finite quality factor above 1, or None")
    return value


def _span_caveats(span: float) -> list[str]:
    notes = []
    if span < BEAT_PERIOD:
        notes.append(
            f"span {span / (365.25 * DAY):.1f} yr is shorter than the {BEAT_PERIOD / (365.25 * DAY):.1f}-yr beat of "
            "the Chandler and annual terms: the two are barely separable, and the uncertainty is widened "
            "by the drift-model and excitation terms"
        )
    return notes


# ---------------------------------------------------------------------------
# Least squares (equation 2)
# ---------------------------------------------------------------------------


def _fixed_columns(s: np.ndarray, half: float, degree: int) -> np.ndarray:
    tau = s / half
    cols = [tau**j for j in range(degree + 1)]
    cols += [np.exp(1j * ANNUAL_RATE * s), np.exp(-1j * ANNUAL_RATE * s)]
    return np.stack(cols, axis=1).astype(complex)


def _profile(s, z, fixed):
    """QR of the fixed columns and the residual r0 of the fit without the Chandler term."""
    q, _ = np.linalg.qr(fixed)
    r0 = z - q @ (q.conj().T @ z)
    return q, r0


def _gain(s, q, r0, rates) -> np.ndarray:
    """Drop of the residual sum of squares when exp(i rate s) joins the fixed columns.

    gain = |e^H r0|^2 / (n - |Q^H e|^2) (Frisch-Waugh: the projection of e
    orthogonal to the fixed columns), the complex generalisation of the
    Lomb-Scargle periodogram with nuisance terms.
    """
    cols = np.column_stack([r0, q])
    f = dtft_at(s, cols, rates)
    denom = s.size - np.sum(np.abs(f[..., 1:]) ** 2, axis=-1)
    return np.abs(f[..., 0]) ** 2 / np.maximum(denom, 1e-12 * s.size)


def _grid_gain(s, q, r0, lo_rate, hi_rate, span):
    rates, d = _band_grid(lo_rate, hi_rate, span)
    cols = np.column_stack([r0, q])
    f = dtft(s, cols, rates[0], d, rates.size)
    denom = s.size - np.sum(np.abs(f[:, 1:]) ** 2, axis=1)
    gain = np.abs(f[:, 0]) ** 2 / np.maximum(denom, 1e-12 * s.size)
    return rates, gain, d


def _band_grid(lo_rate, hi_rate, span):
    """Rates from lo to hi (inclusive) with about 8 points per Rayleigh resolution 2 pi / T."""
    count = int(math.ceil((hi_rate - lo_rate) * _OVERSAMPLE * span / (2 * math.pi))) + 1
    d = (hi_rate - lo_rate) / (count - 1)
    return lo_rate + d * np.arange(count), d


def _refine_peak(fun, rates, values, step, lo, hi) -> float:
    """Maximise ``fun`` near the largest grid value (bounded Brent)."""
    k = int(np.argmax(values))
    a = max(lo, rates[k] - step)
    b = min(hi, rates[k] + step)
    res = optimize.minimize_scalar(lambda r: -fun(r), bounds=(a, b), method="bounded", options={"xatol": step * 1e-4})
    return float(res.x) if -res.fun >= values[k] else float(rates[k])


def _ls_solve(s, z, half, degree, band, polish=True):
    """Variable projection, then (``polish``) a full nonlinear least-squares polish.

    Returns (coefficients, rate, at_edge); the coefficients are ordered as the
    columns: drift (degree + 1), annual +, annual -, Chandler.
    """
    lo_rate, hi_rate = 2 * math.pi / band[1], 2 * math.pi / band[0]
    span = s[-1] - s[0]
    fixed = _fixed_columns(s, half, degree)
    q, r0 = _profile(s, z, fixed)
    rates, gain, step = _grid_gain(s, q, r0, lo_rate, hi_rate, span)
    rate = _refine_peak(lambda r: float(_gain(s, q, r0, r)), rates, gain, step, lo_rate, hi_rate)
    coeffs = np.linalg.lstsq(np.column_stack([fixed, np.exp(1j * rate * s)]), z, rcond=None)[0]
    if polish:
        coeffs, rate = _polish(s, z, half, fixed, coeffs, rate)
    at_edge = not (lo_rate + 0.5 * step < rate < hi_rate - 0.5 * step)
    return coeffs, rate, at_edge


def _polish(s, z, half, fixed, coeffs, rate):
    """scipy.optimize.least_squares on all real parameters of equation (2).

    Parameters: real and imaginary parts of every complex amplitude, and
    u = rate * h (the phase the Chandler term gains over half the span), so
    that all parameters are of comparable scale. Starting from the
    variable-projection optimum it confirms it (and would correct a grid or
    Brent inaccuracy).
    """
    ncols = coeffs.size

    def unpack(theta):
        c = theta[0 : 2 * ncols : 2] + 1j * theta[1 : 2 * ncols : 2]
        return c, theta[-1] / half

    def residual(theta):
        c, r = unpack(theta)
        d = z - fixed @ c[:-1] - c[-1] * np.exp(1j * r * s)
        return np.concatenate([d.real, d.imag])

    def jacobian(theta):
        c, r = unpack(theta)
        jc = _jacobian_complex(s, half, fixed, c, r)
        return -np.concatenate([jc.real, jc.imag])

    theta0 = np.empty(2 * ncols + 1)
    theta0[0 : 2 * ncols : 2] = coeffs.real
    theta0[1 : 2 * ncols : 2] = coeffs.imag
    theta0[-1] = rate * half
    scale = np.full(theta0.size, max(np.abs(coeffs).max(), 1e-300))
    scale[-1] = 1.0
    sol = optimize.least_squares(residual, theta0, jac=jacobian, method="lm", x_scale=scale)
    if not sol.success or sol.cost > 0.5 * np.sum(residual(theta0) ** 2) * (1 + 1e-12):
        return coeffs, rate
    return unpack(sol.x)


def _jacobian_complex(s, half, fixed, c, rate) -> np.ndarray:
    """d(model)/d(real parameters), complex, shape (n, 2 ncols + 1); last column per u = rate h."""
    e = np.exp(1j * rate * s)
    n, nfix = fixed.shape
    j = np.empty((n, 2 * (nfix + 1) + 1), dtype=complex)
    j[:, 0 : 2 * nfix : 2] = fixed
    j[:, 1 : 2 * nfix : 2] = 1j * fixed
    j[:, 2 * nfix] = e
    j[:, 2 * nfix + 1] = 1j * e
    j[:, -1] = c[-1] * 1j * (s / half) * e
    return j


def _hac_meat(t: np.ndarray, scores: np.ndarray, lag: float) -> np.ndarray:
    """Sum over lags |k| <= L of (1 - |k|/(L+1)) Gamma_k for the score series (Bartlett; Newey & West 1987).

    Samples are placed on a uniform grid of the median spacing (gaps stay
    empty), so uneven and gappy records are handled; the sum is done with FFTs.
    """
    dt = float(np.median(np.diff(t)))
    idx = np.rint((t - t[0]) / dt).astype(int)
    n = int(idx[-1]) + 1
    grid = np.zeros((n, scores.shape[1]))
    np.add.at(grid, idx, scores)
    nlag = int(min(max(round(lag / dt), 1), n - 1))
    nfft = 1 << int(math.ceil(math.log2(n + nlag + 1)))
    weights = np.zeros(nfft)
    k = np.arange(nlag + 1)
    weights[: nlag + 1] = 1.0 - k / (nlag + 1.0)
    weights[nfft - nlag :] = weights[1 : nlag + 1][::-1]
    w_hat = np.fft.fft(weights).real
    g = np.fft.fft(grid, nfft, axis=0)
    meat = np.einsum("f,fi,fj->ij", w_hat, g, g.conj()).real / nfft
    return 0.5 * (meat + meat.T)


def _scaled_inverse(b: np.ndarray) -> np.ndarray:
    """Inverse of a normal matrix after scaling it to unit diagonal.

    The amplitude parameters (rad) and the frequency parameter (whose column
    is proportional to the Chandler amplitude, ~1e-7 rad) differ in scale by
    ~1e13; unscaled, the inverse loses every digit of the frequency's variance.
    """
    d = np.sqrt(np.diag(b))
    d = np.where(d > 0, d, 1.0)
    return np.linalg.inv(b / np.outer(d, d)) / np.outer(d, d)


def _sqrt_var(v: float) -> float:
    """sqrt of a variance; inf when the information matrix is singular (the parameter is not determined)."""
    return math.sqrt(v) if math.isfinite(v) and v > 0 else math.inf


def _scatter(values: list[float]) -> float:
    """sd / sqrt(n) times the Student-t factor: the 68 % error of the mean of n values."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    n = v.size
    if n < 3:
        return math.nan
    return float(np.std(v, ddof=1) / math.sqrt(n) * stats.t.ppf(_ONE_SIGMA, n - 1))


_TRACKED = ("period", "amplitude", "annual", "retrograde")


def _tracked(f: "ChandlerFit") -> dict[str, float]:
    return {
        "period": f.chandler.period,
        "amplitude": f.chandler.amplitude,
        "annual": f.annual_prograde.amplitude,
        "retrograde": f.annual_retrograde.amplitude,
    }


def _subspans(t, z, estimator, **kwargs) -> tuple[dict[str, float], int]:
    """Scatter of ``estimator`` over n >= 3 disjoint sub-spans of >= 2 beat periods.

    Returns the 68 % error of the mean of each tracked quantity (Chandler
    period and amplitude, annual amplitudes) and the number of sub-spans.
    """
    span = t[-1] - t[0]
    n = int(span // (2.0 * BEAT_PERIOD))
    if n < 3:
        return dict.fromkeys(_TRACKED, math.nan), 0
    edges = t[0] + span * np.arange(n + 1) / n
    values: dict[str, list[float]] = {k: [] for k in _TRACKED}
    for a, b in zip(edges[:-1], edges[1:]):
        m = (t >= a) & (t <= b)
        if m.sum() < 10 or t[m][-1] - t[m][0] < 0.8 * (b - a):
            continue
        try:
            f = estimator(t[m], z[m], uncertainty=False, **kwargs)
        except InputError:
            continue
        for k, v in _tracked(f).items():
            values[k].append(v)
    return {k: _scatter(v) for k, v in values.items()}, len(values["period"])


def _model_sensitivity(t, z, estimator, degree, base: "ChandlerFit", **kwargs) -> dict[str, float]:
    """Largest change of each tracked quantity with drift degree -1/+1."""
    ref = _tracked(base)
    out = dict.fromkeys(_TRACKED, 0.0)
    for d in {max(degree - 1, 0), degree + 1} - {degree}:
        f = estimator(t, z, drift_degree=d, uncertainty=False, **kwargs)
        for k, v in _tracked(f).items():
            out[k] = max(out[k], abs(v - ref[k]))
    return out


def _annual_sigmas(auto: list[tuple[float, float]], sub: dict, mod: dict) -> list[tuple[float, float]]:
    """Adopted (amplitude, phase) sigmas of the annual terms: autocorrelation, sub-spans and drift model."""
    out = []
    for (a_auto, p_auto), key in zip(auto, ("annual", "retrograde")):
        main = max(x for x in (a_auto, sub[key], 0.0) if math.isfinite(x))
        out.append((math.hypot(main, mod[key]), p_auto))
    return out


def _combine(formal, autocorrelation, subspans, model, excitation=math.nan) -> Uncertainty:
    main = max(x for x in (autocorrelation, subspans, excitation, 0.0) if math.isfinite(x))
    return Uncertainty(formal, autocorrelation, subspans, model, math.hypot(main, model), excitation)


def _damped_oscillator(t, rate, q, power, draws, rng) -> np.ndarray:
    """Realisations of the randomly excited free wobble, equation (3), at times ``t``: shape (n, draws).

    The complex Ornstein-Uhlenbeck process m(t + d) = exp((i rate - g) d) m(t)
    + sqrt(power (1 - exp(-2 g d))) xi, g = rate/(2Q), started in its
    stationary state (E|m|^2 = power): exact for any spacing d.
    """
    g = rate / (2.0 * q)
    dt = np.diff(t)
    lam = np.exp((1j * rate - g) * dt)
    scale = np.sqrt(power * -np.expm1(-2.0 * g * dt))
    xi = (rng.standard_normal((t.size, draws)) + 1j * rng.standard_normal((t.size, draws))) / math.sqrt(2.0)
    out = np.empty((t.size, draws), dtype=complex)
    out[0] = math.sqrt(power) * xi[0]
    for k in range(1, t.size):
        out[k] = lam[k - 1] * out[k - 1] + scale[k - 1] * xi[k]
    return out


def _excitation_scatter(t, fit: "ChandlerFit", estimator, q, draws, seed, **kwargs) -> float:
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
    """
    rng = np.random.default_rng(seed)
    if np.median(np.diff(t)) < _MC_BIN:
        # Five-day means for speed: the averaging changes the Chandler and
        # annual terms by less than 0.1 %, and keeps the record's gaps.
        t, _ = _bin_means(t, np.zeros(t.size, dtype=complex), _MC_BIN)
    base = fit.model(t, terms=("drift", "annual_prograde", "annual_retrograde"))
    sims = _damped_oscillator(t, fit.chandler.rate, q, fit.chandler.amplitude**2, draws, rng)
    errors = []
    for k in range(draws):
        try:
            f = estimator(t, base + sims[:, k], uncertainty=False, **kwargs)
        except InputError:
            continue
        errors.append(f.chandler.period - fit.chandler.period)
    return float(np.sqrt(np.mean(np.square(errors)))) if errors else math.nan


def _amp_phase_sigma(c: complex, cov2: np.ndarray) -> tuple[float, float]:
    """Delta-method sigmas of |c| and arg c from the 2x2 covariance of (Re c, Im c)."""
    a = abs(c)
    if a == 0:
        return math.nan, math.nan
    ga = np.array([c.real, c.imag]) / a
    gp = np.array([-c.imag, c.real]) / a**2
    return float(math.sqrt(max(ga @ cov2 @ ga, 0.0))), float(math.sqrt(max(gp @ cov2 @ gp, 0.0)))


def fit_least_squares(
    t,
    z,
    *,
    drift_degree: int = 2,
    band: tuple[float, float] = CHANDLER_BAND,
    uncertainty: bool = True,
    subspans: bool = True,
    excitation_q: float | None = 100.0,
    draws: int = 64,
    seed: int = 0,
) -> ChandlerFit:
    """Nonlinear least-squares fit of equation (2) to the complex pole series.

    Parameters
    ----------
    t : ndarray
        Sample times, s, strictly increasing; gaps and uneven spacing are fine.
    z : ndarray, complex
        The pole p = x_p - i y_p (equation 1), rad.
    drift_degree : int
        Degree of the mean-pole polynomial (default 2: the pole's drift turned
        toward the east after about 2005, which a line cannot follow).
    band : (float, float)
        Search interval for the Chandler period, s (default 390 to 500 d).
    uncertainty : bool
        Compute the uncertainty breakdown (off for the inner fits of the
        sub-span and model checks).
    subspans : bool
        Include the sub-span scatter (needs a span of six beat periods, 38 yr).
    excitation_q : float or None
        Q of the randomly excited wobble assumed by the Monte-Carlo
        ``excitation`` term (default 100; None leaves the term out).
    draws, seed : int
        Monte-Carlo realisations and the seed of their generator (fixed, so
        results are reproducible).

    Returns
    -------
    ChandlerFit
        ``method = "least_squares"``. Equal weights: the misfit (tens of mas)
        is geophysical, far above the formal errors of modern data, which
        would otherwise give the last decades nearly all the weight.

    Notes
    -----
    The frequency maximises the profile gain (the residual-sum-of-squares drop
    of adding the Chandler column to the drift and annual columns), searched
    on a grid oversampled 8 times over the Rayleigh resolution and refined by
    bounded Brent; :func:`scipy.optimize.least_squares` then polishes all
    parameters together and gives the Jacobian for the covariances.
    """
    t, z = _as_series(t, z)
    degree = _check_degree(drift_degree)
    band = _check_band(band)
    epoch = 0.5 * (t[0] + t[-1])
    half = 0.5 * (t[-1] - t[0])
    s = t - epoch
    coeffs, rate, at_edge = _ls_solve(s, z, half, degree, band, polish=uncertainty)
    fixed = _fixed_columns(s, half, degree)
    resid = z - fixed @ coeffs[:-1] - coeffs[-1] * np.exp(1j * rate * s)
    caveats = _span_caveats(t[-1] - t[0])
    if at_edge:
        caveats.append(
            f"the best period lies at the edge of the search band {band[0] / DAY:.0f}-{band[1] / DAY:.0f} d: "
            "no Chandler term is resolved in this span"
        )
    nan = math.nan
    sig_rate = sig_amp = sig_phase = nan
    ann_sig = [(nan, nan), (nan, nan)]
    pu = au = Uncertainty(nan, nan, nan, nan, nan)
    details: dict = {"solver": "variable projection + scipy.optimize.least_squares (lm)"}
    if uncertainty:
        jc = _jacobian_complex(s, half, fixed, coeffs, rate)
        bread = _scaled_inverse((jc.conj().T @ jc).real)
        npar = jc.shape[1]
        s2 = float(np.sum(np.abs(resid) ** 2)) / max(2 * s.size - npar, 1)
        cov_formal = s2 * bread
        scores = (jc.conj() * resid[:, None]).real
        lag = min(BEAT_PERIOD, (t[-1] - t[0]) * _HAC_MAX_B)
        b = lag / (t[-1] - t[0])
        # Fixed-b bias of the Bartlett estimator, E = (1 - b + b^2/3) x the true
        # long-run variance (Kiefer & Vogelsang 2005): divided out.
        cov_hac = bread @ _hac_meat(t, scores, lag) @ bread / (1.0 - b + b * b / 3.0)
        details["hac_bandwidth_days"] = lag / DAY
        # period sigma from u = rate * half: sigma_P = 2 pi sigma_u / (half rate^2)
        to_period = 2 * math.pi / (half * rate**2)
        ic = 2 * (coeffs.size - 1)  # (Re, Im) of the Chandler amplitude
        p_formal = _sqrt_var(cov_formal[-1, -1]) * to_period
        p_hac = _sqrt_var(cov_hac[-1, -1]) * to_period
        a_formal = _amp_phase_sigma(coeffs[-1], cov_formal[ic : ic + 2, ic : ic + 2])[0]
        a_hac, sig_phase = _amp_phase_sigma(coeffs[-1], cov_hac[ic : ic + 2, ic : ic + 2])
        sub = dict.fromkeys(_TRACKED, nan)
        if subspans:
            sub, nsub = _subspans(t, z, fit_least_squares, band=band, drift_degree=degree)
            details["subspans"] = nsub
        base = _make_fit("least_squares", t, epoch, half, degree, coeffs, rate, resid, 0, 0, 0, ann_sig)
        mod = _model_sensitivity(t, z, fit_least_squares, degree, base, band=band)
        p_sub, a_sub, p_mod, a_mod = sub["period"], sub["amplitude"], mod["period"], mod["amplitude"]
        p_exc = math.nan
        if excitation_q is not None:
            p_exc = _excitation_scatter(t, base, fit_least_squares, _check_q(excitation_q), draws, seed, band=band, drift_degree=degree)
            details["excitation_q"] = float(excitation_q)
        pu = _combine(p_formal, p_hac, p_sub, p_mod, p_exc)
        au = _combine(a_formal, a_hac, a_sub, a_mod)
        sig_rate = pu.adopted * rate**2 / (2 * math.pi)
        sig_amp = au.adopted
        ann_auto = [
            _amp_phase_sigma(coeffs[degree + 1 + k], cov_hac[2 * (degree + 1 + k) : 2 * (degree + 2 + k), 2 * (degree + 1 + k) : 2 * (degree + 2 + k)])
            for k in (0, 1)
        ]
        ann_sig = _annual_sigmas(ann_auto, sub, mod)
    fit = _make_fit("least_squares", t, epoch, half, degree, coeffs, rate, resid, sig_rate, sig_amp, sig_phase, ann_sig)
    return _with(fit, period_uncertainty=pu, amplitude_uncertainty=au, caveats=tuple(caveats), details=details)


def _make_fit(method, t, epoch, half, degree, coeffs, rate, resid, sig_rate, sig_amp, sig_phase, ann_sig) -> ChandlerFit:
    nan = math.nan
    c = coeffs
    chandler = Harmonic(rate, sig_rate, abs(c[-1]), sig_amp, float(np.angle(c[-1])), sig_phase)
    pro = Harmonic(ANNUAL_RATE, 0.0, abs(c[degree + 1]), ann_sig[0][0], float(np.angle(c[degree + 1])), ann_sig[0][1])
    retro = Harmonic(-ANNUAL_RATE, 0.0, abs(c[degree + 2]), ann_sig[1][0], float(np.angle(c[degree + 2])), ann_sig[1][1])
    unc = Uncertainty(nan, nan, nan, nan, nan)
    return ChandlerFit(
        method=method,
        epoch=float(epoch),
        start=float(t[0]),
        end=float(t[-1]),
        n_samples=int(t.size),
        drift_degree=degree,
        chandler=chandler,
        annual_prograde=pro,
        annual_retrograde=retro,
        drift=np.array(c[: degree + 1]),
        half_span=float(half),
        period_uncertainty=unc,
        amplitude_uncertainty=unc,
        residual_rms=float(np.sqrt(np.mean(np.abs(resid) ** 2))),
    )


def _with(fit: ChandlerFit, **changes) -> ChandlerFit:
    from dataclasses import replace

    return replace(fit, **changes)


# ---------------------------------------------------------------------------
# The two-sided spectrum
# ---------------------------------------------------------------------------


def _detrend(s, z, half, degree):
    tau = s / half
    v = np.stack([tau**j for j in range(degree + 1)], axis=1).astype(complex)
    c = np.linalg.lstsq(v, z, rcond=None)[0]
    return z - v @ c, c


def _taper(t, kind: str) -> np.ndarray:
    if kind == "hann":
        return np.sin(np.pi * (t - t[0]) / (t[-1] - t[0])) ** 2
    return np.ones_like(t)


def _auto_taper(span: float, taper: str) -> str:
    if taper not in ("auto", "hann", "none"):
        raise InputError("taper", taper, "'auto', 'hann' or 'none'")
    if taper == "auto":
        # With the annual terms prewhitened, the Hann main lobe (half-width 2/T)
        # may overlap the annual peak; under one beat period it is too wide.
        return "hann" if span >= BEAT_PERIOD else "none"
    return taper


def two_sided_spectrum(
    t, z, *, max_rate: float = 3.0 * 2 * math.pi / TROPICAL_YEAR, drift_degree: int = 2, taper: str = "auto", oversample: int = 4
) -> Spectrum:
    """Amplitude spectrum |sum w y e^{-i sigma s}| / sum w of the detrended series, for -max_rate..max_rate.

    Negative rates are retrograde terms, positive prograde (equation 1). The
    grid is ``oversample`` times finer than the Rayleigh resolution 2 pi / T.
    """
    t, z = _as_series(t, z)
    degree = _check_degree(drift_degree)
    span = t[-1] - t[0]
    kind = _auto_taper(span, taper)
    epoch = 0.5 * (t[0] + t[-1])
    s = t - epoch
    y, _ = _detrend(s, z, 0.5 * span, degree)
    w = _taper(t, kind)
    d = 2 * math.pi / (oversample * span)
    count = int(2 * math.ceil(max_rate / d)) + 1
    rates = -math.ceil(max_rate / d) * d + d * np.arange(count)
    amp = np.abs(dtft(s, w * y, rates[0], d, count)) / w.sum()
    return Spectrum(rates, amp, kind, degree)


def fit_spectrum(
    t,
    z,
    *,
    drift_degree: int = 2,
    band: tuple[float, float] = CHANDLER_BAND,
    taper: str = "auto",
    uncertainty: bool = True,
    subspans: bool = True,
    excitation_q: float | None = 100.0,
    draws: int = 64,
    seed: int = 0,
) -> ChandlerFit:
    """The Chandler term from the peak of the two-sided spectrum (independent of the least squares).

    The series is detrended with a polynomial of ``drift_degree``, tapered
    (Hann when the span is at least one beat period, otherwise none) and
    Fourier-summed at its own sample times (gaps need no filling). The peak in
    the prograde band is refined by bounded Brent on the exact sum; the
    amplitude is |F|/sum w. The annual terms are read at +/- one cycle per
    tropical year and removed before the peak is sought again (prewhitening,
    repeated until the peak stops moving), so the annual peak's main lobe does not pull the Chandler
    peak in short spans. Nothing is fitted jointly: this is a spectral
    estimator, independent of :func:`fit_least_squares`.

    The ``autocorrelation`` error is the peak-location variance in coloured
    noise, var(sigma) = S sum(w^2 s^2) / (2 |A|^2 (sum w s^2)^2), with S the
    level of the residual spectrum (the three terms removed) beside the peak
    (Whittle 1952; Hannan 1973); ``subspans``, ``excitation`` and ``model`` as
    in :func:`fit_least_squares`.
    """
    t, z = _as_series(t, z)
    degree = _check_degree(drift_degree)
    band = _check_band(band)
    span = t[-1] - t[0]
    kind = _auto_taper(span, taper)
    epoch = 0.5 * (t[0] + t[-1])
    half = 0.5 * span
    s = t - epoch
    y, drift = _detrend(s, z, half, degree)
    w = _taper(t, kind)
    lo_rate, hi_rate = 2 * math.pi / band[1], 2 * math.pi / band[0]
    rates, d = _band_grid(lo_rate, hi_rate, span)
    annual_cols = np.exp(1j * ANNUAL_RATE * np.outer(s, [1.0, -1.0]))
    ann = np.zeros(2, dtype=complex)
    rate = math.nan
    for _ in range(_PREWHITEN):
        # Prewhitening (CLEAN-like): remove the current annual terms, find the
        # Chandler peak, remove it, read the annual terms again; repeat until the
        # peak stops moving (block relaxation, which converges however much the
        # main lobes overlap, only more slowly).
        wy = w * (y - annual_cols @ ann)
        power = np.abs(dtft(s, wy, rates[0], d, rates.size)) ** 2
        previous = rate
        rate = _refine_peak(lambda r: float(np.abs(dtft_at(s, wy, r)) ** 2), rates, power, d, lo_rate, hi_rate)
        chandler = complex(dtft_at(s, wy, rate)) / w.sum()
        ann = dtft_at(s, w * (y - chandler * np.exp(1j * rate * s)), np.array([ANNUAL_RATE, -ANNUAL_RATE])) / w.sum()
        if abs(rate - previous) < 1e-3 * d:
            break
    f = np.array([chandler, ann[0], ann[1]])
    coeffs = np.concatenate([drift, [f[1], f[2], f[0]]])
    resid = y - f[0] * np.exp(1j * rate * s) - annual_cols @ ann
    caveats = _span_caveats(span)
    if kind == "none" and taper == "auto":
        caveats.append("span under one beat period: no taper, so the side lobes of other terms leak into the Chandler peak")
    if not (lo_rate + 0.5 * d < rate < hi_rate - 0.5 * d):
        caveats.append(
            f"the spectral peak lies at the edge of the search band {band[0] / DAY:.0f}-{band[1] / DAY:.0f} d: "
            "no Chandler peak is resolved in this span"
        )
    nan = math.nan
    ann_sig = [(nan, nan), (nan, nan)]
    sig_rate = sig_amp = sig_phase = nan
    pu = au = Uncertainty(nan, nan, nan, nan, nan)
    details: dict = {"taper": kind}
    if uncertainty:
        fitted = (rate, ANNUAL_RATE, -ANNUAL_RATE)
        level = _local_level(s, w * resid, w, rate, span, kind, fitted)
        sw, sw2 = w.sum(), np.sum(w**2)
        sc = s - np.sum(w * s) / sw
        amp = abs(f[0])
        var_rate = level * np.sum(w**2 * sc**2) / (2 * amp**2 * np.sum(w * sc**2) ** 2)
        var_amp = level * sw2 / (2 * sw**2)
        to_period = 2 * math.pi / rate**2
        white = np.mean(np.abs(resid) ** 2)
        p_formal = math.sqrt(white * np.sum(w**2 * sc**2) / (2 * amp**2 * np.sum(w * sc**2) ** 2)) * to_period
        a_formal = math.sqrt(white * sw2 / (2 * sw**2))
        p_auto = math.sqrt(var_rate) * to_period
        a_auto = math.sqrt(var_amp)
        sig_phase = a_auto / amp
        ann_auto = []
        for k, sign in ((1, 1.0), (2, -1.0)):
            a_k = math.sqrt(_local_level(s, w * resid, w, sign * ANNUAL_RATE, span, kind, fitted) * sw2 / (2 * sw**2))
            ann_auto.append((a_k, a_k / max(abs(f[k]), 1e-300)))
        sub = dict.fromkeys(_TRACKED, nan)
        if subspans:
            sub, nsub = _subspans(t, z, fit_spectrum, band=band, drift_degree=degree, taper=kind)
            details["subspans"] = nsub
        base = _make_fit("spectrum", t, epoch, half, degree, coeffs, rate, resid, 0, 0, 0, ann_auto)
        mod = _model_sensitivity(t, z, fit_spectrum, degree, base, band=band, taper=kind)
        p_sub, a_sub, p_mod, a_mod = sub["period"], sub["amplitude"], mod["period"], mod["amplitude"]
        ann_sig = _annual_sigmas(ann_auto, sub, mod)
        p_exc = math.nan
        if excitation_q is not None:
            p_exc = _excitation_scatter(t, base, fit_spectrum, _check_q(excitation_q), draws, seed, band=band, drift_degree=degree, taper=kind)
            details["excitation_q"] = float(excitation_q)
        pu = _combine(p_formal, p_auto, p_sub, p_mod, p_exc)
        au = _combine(a_formal, a_auto, a_sub, a_mod)
        sig_rate = pu.adopted * rate**2 / (2 * math.pi)
        sig_amp = au.adopted
    fit = _make_fit("spectrum", t, epoch, half, degree, coeffs, rate, resid, sig_rate, sig_amp, sig_phase, ann_sig)
    return _with(fit, period_uncertainty=pu, amplitude_uncertainty=au, caveats=tuple(caveats), details=details)


def _local_level(s, wr, w, rate, span, kind, fitted=()) -> float:
    """Mean |F_w r|^2 / sum w^2 in a ring 0.1 cycle per year wide just outside the peak's main lobe.

    For white noise of variance sigma^2 this is sigma^2; for coloured noise it
    is the noise spectral density near ``rate`` in the same units (the "S"
    of the peak-location variance). The main lobes of the fitted terms
    (``rate`` and ``fitted``) are left out: their removal leaves holes in
    the residual spectrum there.
    """
    year_rate = 2 * math.pi / TROPICAL_YEAR
    lobe = (2.0 if kind == "hann" else 1.0) * 2 * math.pi / span
    reach = lobe + 0.1 * year_rate
    d = 2 * math.pi / (4 * span)
    count = int(2 * math.ceil(reach / d)) + 1
    grid = rate - math.ceil(reach / d) * d + d * np.arange(count)
    p = np.abs(dtft(s, wr, grid[0], d, count)) ** 2 / np.sum(w**2)
    side = np.abs(grid - rate) > lobe
    for other in fitted:
        side &= np.abs(grid - other) > lobe
    return float(np.mean(p[side]))


# ---------------------------------------------------------------------------
# Sliding windows
# ---------------------------------------------------------------------------


def sliding_windows(
    t,
    z,
    window: float,
    step: float | None = None,
    *,
    drift_degree: int = 2,
    band: tuple[float, float] = CHANDLER_BAND,
    progress=None,
) -> WindowedFits:
    """Least-squares fits of equation (2) on windows of length ``window`` moved by ``step`` (s).

    Each window gets its own drift, annual terms and Chandler period,
    amplitude and phase, with the autocorrelation and drift-model
    uncertainty (a window is too short for the sub-span check). ``progress``
    (optional) is called as ``progress(done, total)``.
    """
    t, z = _as_series(t, z)
    span = t[-1] - t[0]
    window = float(window)
    if not (math.isfinite(window) and MIN_SPAN <= window <= span * (1 + 1e-9)):
        raise InputError(
            "window",
            f"{window / (365.25 * DAY):g} yr",
            f"a length from {MIN_SPAN / (365.25 * DAY):g} yr to the span of the data ({span / (365.25 * DAY):.2f} yr)",
        )
    step = 365.25 * DAY if step is None else float(step)
    if not (math.isfinite(step) and step > 0):
        raise InputError("step", f"{step / DAY:g} d", "a positive, finite time")
    n = int(math.floor((span - window) / step + 1e-9)) + 1
    starts = t[0] + step * np.arange(n)
    # Centre the set of windows in the span.
    starts += 0.5 * (span - window - (starts[-1] - t[0]))
    out = {k: np.full(n, np.nan) for k in ("period", "period_sigma", "amplitude", "amplitude_sigma", "phase", "annual", "annual_sigma", "retro")}
    counts = np.zeros(n, dtype=int)
    for i, a in enumerate(starts):
        m = (t >= a) & (t <= a + window)
        counts[i] = int(m.sum())
        if progress is not None:
            progress(i, n)
        if counts[i] < 10 or t[m][-1] - t[m][0] < 0.8 * window:
            continue
        try:
            f = fit_least_squares(t[m], z[m], drift_degree=drift_degree, band=band, subspans=False, excitation_q=None)
        except InputError:
            continue
        out["period"][i] = f.chandler.period
        out["period_sigma"][i] = f.chandler.period_sigma
        out["amplitude"][i] = f.chandler.amplitude
        out["amplitude_sigma"][i] = f.chandler.amplitude_sigma
        out["phase"][i] = f.chandler.phase
        out["annual"][i] = f.annual_prograde.amplitude
        out["annual_sigma"][i] = f.annual_prograde.amplitude_sigma
        out["retro"][i] = f.annual_retrograde.amplitude
    if progress is not None:
        progress(n, n)
    return WindowedFits(
        centre=starts + 0.5 * window,
        start=starts,
        end=starts + window,
        n_samples=counts,
        period=out["period"],
        period_sigma=out["period_sigma"],
        amplitude=out["amplitude"],
        amplitude_sigma=out["amplitude_sigma"],
        phase=out["phase"],
        annual_amplitude=out["annual"],
        annual_amplitude_sigma=out["annual_sigma"],
        retrograde_annual_amplitude=out["retro"],
        window=window,
        step=step,
        drift_degree=_check_degree(drift_degree),
    )


# ---------------------------------------------------------------------------
# Quality factor from the line shape
# ---------------------------------------------------------------------------

#: Shortest span for the Q estimate: the line must span several Fourier ordinates.
MIN_Q_SPAN = 20.0 * 365.25 * DAY
_Q_GRID = np.concatenate([np.logspace(0.5, 5.0, 22), [np.inf]])
_Q_BIN = 10.0 * DAY
# Centre offset (resolution units), log line power and log background (periodogram scale).
_Q_BOUNDS = [(-3.0, 3.0), (-30.0, 30.0), (-30.0, 30.0)]
_HALF_BAND = 0.25 * 2 * math.pi / TROPICAL_YEAR  # +/- 0.25 cycle per year around the peak
_ANNUAL_NOTCH = 0.03 * 2 * math.pi / TROPICAL_YEAR


def _bin_means(t: np.ndarray, y: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Means of ``y`` in bins of ``width`` (s) from t[0]; times are the bin centres; empty bins dropped."""
    idx = np.floor((t - t[0]) / width).astype(int)
    n = int(idx[-1]) + 1
    counts = np.bincount(idx, minlength=n)
    sums = np.bincount(idx, weights=y.real, minlength=n) + 1j * np.bincount(idx, weights=y.imag, minlength=n)
    keep = counts > 0
    centres = t[0] + width * (np.arange(n) + 0.5)
    return centres[keep], sums[keep] / counts[keep]


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
    t, y = _as_series(t, y, "chandler series")
    span = t[-1] - t[0]
    if span < MIN_Q_SPAN:
        raise InputError("span", f"{span / (365.25 * DAY):.1f} yr", f"at least {MIN_Q_SPAN / (365.25 * DAY):.0f} yr for a Q estimate")
    # Ten-day means: the line is within 0.12 cycle/yr of 0.84 cycle/yr, far below
    # the new Nyquist frequency (18 cycles/yr); the boxcar loses 0.1 % there.
    t, y = _bin_means(t, y, _Q_BIN)
    s = t - t[0]
    counts, dt = _lag_counts(t)
    lags = dt * np.arange(counts.size)
    n = t.size
    k0 = math.ceil((rate - _HALF_BAND) * span / (2 * math.pi))
    k1 = math.floor((rate + _HALF_BAND) * span / (2 * math.pi))
    ords = 2 * math.pi * np.arange(k0, k1 + 1) / span
    # Leave out the annual frequency, whose fitted term leaves a notch.
    ords = ords[np.abs(ords - ANNUAL_RATE) > _ANNUAL_NOTCH]
    spec = np.abs(dtft_at(s, y, ords)) ** 2 / n
    keep = counts > 0
    lags, counts = lags[keep], counts[keep]
    phase = np.exp(-1j * np.multiply.outer(ords, lags))  # (K, L)

    def expected(sigma0, q, power, background):
        gamma = 0.0 if not math.isfinite(q) else sigma0 / (2 * q)
        kern = counts * np.exp(1j * sigma0 * lags - gamma * lags)
        # Element-wise product and sum: no threaded BLAS call for a small product.
        total = 2 * (phase * kern).sum(axis=1).real - counts[0]  # lag 0 counted once
        return power * total / n + background

    # Power and background are fitted relative to the periodogram's scale.
    scale = float(np.mean(spec))

    def nll(x, q):
        e = expected(rate + x[0] * 2 * math.pi / span, q, scale * math.exp(x[1]) / n, scale * math.exp(x[2]))
        if np.any(e <= 0):
            return 1e300
        return float(np.sum(np.log(e) + spec / e))

    fresh = np.array([0.0, math.log(4.0), math.log(0.05)])
    x = fresh
    profile = []
    for q in _Q_GRID:
        best = None
        # Warm start from the previous Q, and a fresh start (a warm start alone
        # can stay in a poor local minimum found at a very different Q).
        for start in (x, fresh):
            simplex = start + np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
            res = optimize.minimize(
                nll, start, args=(q,), method="Nelder-Mead", bounds=_Q_BOUNDS,
                options={"initial_simplex": simplex, "xatol": 1e-4, "fatol": 1e-6, "maxfev": 2000},
            )
            if best is None or res.fun < best.fun:
                best = res
        x = best.x
        profile.append((best.fun, best.x[0]))
    values = np.array([p[0] for p in profile])
    i = int(np.argmin(values))
    dev = values - values[i]
    logq = np.log10(np.where(np.isfinite(_Q_GRID), _Q_GRID, 1e6))
    low = _crossing(logq, dev, i, 0.5, -1)
    high = _crossing(logq, dev, i, 0.5, +1)
    lower95 = _crossing(logq, dev, i, 1.3528, -1)
    sigma0 = rate + profile[i][1] * 2 * math.pi / span
    value = float(_Q_GRID[i]) if i < len(_Q_GRID) - 2 else math.inf
    resolved = math.isfinite(value) and math.isfinite(high)
    caveats = [
        "assumes a flat excitation spectrum near the Chandler frequency and a stationary process "
        "(Yamaguchi & Furuya 2025 argue P and Q cannot be optimised from polar motion alone)",
        f"the {span / (365.25 * DAY):.0f}-yr record spans only {span * sigma0 / 200:.1f} "
        "decay times for Q = 100 (decay time 2Q/sigma_0): the line is barely resolved",
    ]
    if not resolved:
        caveats.append("the line is no wider than the resolution: only a lower bound on Q is meaningful")
    return QualityFactor(value, low, high, lower95, 2 * math.pi / sigma0, int(ords.size), resolved, tuple(caveats))


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
