"""A physical forecast: the damped Chandler oscillator driven by coloured excitation, in a Kalman filter.

The pole is the sum of four parts, each a state of a linear Gaussian model
stepped once a day (Delta = 1 d):

* the **free wobble** w, the solution of the Liouville equation
  w + (i / sigma_c) dw/dt = chi (Munk & MacDonald 1960; Gross 1992) with the
  complex Chandler frequency sigma_c = 2 pi / T_c (1 + i / (2Q)); over a step
  with the excitation held constant (:mod:`.excitation`, exact)

      w_k = lambda w_{k-1} + (1 - lambda) chi_k,   lambda = exp(i sigma_c Delta);

* its **stochastic excitation** chi, coloured: a complex autoregression of
  order p, chi_k = phi_1 chi_{k-1} + ... + phi_p chi_{k-p} + eta_k with real
  coefficients (atmospheric, oceanic and hydrological excitation is red),
  parametrised by its partial autocorrelations r_1 .. r_p (Durbin-Levinson;
  stationary for |r_j| < 1; Barndorff-Nielsen & Schou 1973), r_1 = exp(-Delta /
  tau) with the lag-one correlation time tau. p = 1 is the first-order
  (Ornstein-Uhlenbeck) excitation; the default, :data:`EXCITATION_ORDER`, is
  chosen on the record before 2016 (see the constant);
* the **seasonal terms**, the response to deterministic annual and
  semi-annual excitation: four circles a_j exp(i n_j Omega_a t), n_j = +/-1,
  +/-2, whose amplitudes may drift slowly (a random walk);
* the **mean pole** (a level and a slope, each a random walk).

The observation is their sum plus white noise. The noise variances (of eta,
the seasonal amplitudes, level, slope and the observation), tau and r_2 .. r_p
are estimated by maximum likelihood on the fitting span (the innovations of the
steady-state filter, :mod:`wobble.numerics.kalman`; the overall scale in
closed form), T_c and Q are physics given to the model (wobble's own
estimates), not fitted. Noise is circular (equal in x_p and y_p). Times in s,
angles in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg, optimize

from wobble.errors import InputError
from wobble.models.polar_motion.excitation import chandler_frequency
from wobble.models.polar_motion.forecast import Forecast, PastForecasts, daily, information_set
from wobble.models.polar_motion.ls_ar import harmonic_columns
from wobble.models.polar_motion.record import ANNUAL_RATE, DAY
from wobble.numerics import kalman
from wobble.numerics.threads import one_blas_thread

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = [
    "FIT_SPAN",
    "BURN_IN",
    "state_names",
    "ar_coefficients",
    "NoiseParameters",
    "EXCITATION_ORDER",
    "DEFAULT_NOISE",
    "GRADIENT_STEP",
    "mean_pole_index",
    "likelihood_bounds",
    "concentrated_likelihood",
    "stationary_covariance",
    "system",
    "initial_state",
    "fit_noise",
    "PRIOR_SD_MAS",
    "prior",
    "KalmanSetup",
    "forecast_kalman",
    "past_forecasts_kalman",
]

#: Default fitting span: ten years of daily values before the information set's end.
FIT_SPAN = 10.0 * JULIAN_YEAR
#: Days at the start of the fitting span that initialise the filter and are left out of the likelihood.
BURN_IN = 365
_SEASONAL = ("annual_prograde", "annual_retrograde", "semiannual_prograde", "semiannual_retrograde")
_MAS = math.pi / 648e6


def state_names(order: int) -> tuple[str, ...]:
    """The states of the model with an excitation autoregression of ``order``, in order: the wobble, the
    excitation and its ``order - 1`` previous values, the four seasonal circles, the mean pole and its rate."""
    lags = tuple(f"excitation_lag_{j}" for j in range(1, order))
    return ("wobble", "excitation", *lags, *_SEASONAL, "mean_pole", "mean_pole_rate")


def ar_coefficients(partial) -> np.ndarray:
    """phi_1 .. phi_p of the autoregression with partial autocorrelations ``partial`` (r_1 .. r_p): the
    Durbin-Levinson recursion phi_j^(k) = phi_j^(k-1) - r_k conj(phi_{k-j}^(k-1)), phi_k^(k) = r_k (Durbin
    1960, Rev. Int. Stat. Inst. 28, 233; the conjugate for complex r, whose coefficients then turn the
    excitation in the plane); stationary when every |r_k| < 1 (Barndorff-Nielsen & Schou 1973, J. Multivar.
    Anal. 3, 408). Real for real ``partial``."""
    partial = np.asarray(partial)
    phi = np.zeros(0, dtype=partial.dtype if np.iscomplexobj(partial) else float)
    for r in partial:
        phi = np.append(phi - r * np.conj(phi[::-1]), r)
    return phi


@dataclass(frozen=True)
class NoiseParameters:
    """The model's noise, per daily step (rad^2; the correlation time in s).

    Attributes
    ----------
    excitation : float
        Variance of the excitation's innovation eta (the scale of the rest).
    correlation_time : float
        Lag-one correlation time tau of the coloured excitation, s: its
        first partial autocorrelation (the lag-one autocorrelation) is
        r_1 = exp(-1 d / tau).
    seasonal, mean_pole, mean_pole_rate, observation : float
        Variances of the daily changes of each seasonal amplitude, the mean
        pole, its rate (per day), and of the observation noise.
    partial_autocorrelations : tuple of float
        The excitation's partial autocorrelations r_2 .. r_p beyond the
        first (empty: a first-order excitation); the order is p = 1 + their
        number.
    """

    excitation: float
    correlation_time: float
    seasonal: float
    mean_pole: float
    mean_pole_rate: float
    observation: float
    partial_autocorrelations: tuple[float, ...] = ()

    @property
    def order(self) -> int:
        """Order p of the excitation's autoregression."""
        return 1 + len(self.partial_autocorrelations)

    def ar(self) -> np.ndarray:
        """The excitation's autoregressive coefficients phi_1 .. phi_p (per daily step)."""
        return ar_coefficients((math.exp(-DAY / self.correlation_time), *self.partial_autocorrelations))

    def with_order(self, order: int) -> NoiseParameters:
        """These parameters with an excitation of ``order``: partial autocorrelations cut or padded with 0."""
        r = (tuple(self.partial_autocorrelations) + (0.0,) * order)[: order - 1]
        return NoiseParameters(**{**self.__dict__, "partial_autocorrelations": r})

    def ratios(self) -> np.ndarray:
        """The MLE's free parameters: ln(tau / 1 d), the logs of the other variances over the excitation's,
        and artanh r_2 .. artanh r_p."""
        q = self.excitation
        return np.array(
            [
                math.log(self.correlation_time / DAY),
                math.log(self.seasonal / q),
                math.log(self.mean_pole / q),
                math.log(self.mean_pole_rate / q),
                math.log(self.observation / q),
                *(math.atanh(r) for r in self.partial_autocorrelations),
            ]
        )

    @classmethod
    def from_ratios(cls, theta, scale: float = 1.0) -> NoiseParameters:
        """The inverse of :meth:`ratios` with excitation variance ``scale`` (the order from the length of theta)."""
        lt, ls, lm, lr, lo, *partial = (float(v) for v in theta)
        return cls(
            scale,
            math.exp(lt) * DAY,
            scale * math.exp(ls),
            scale * math.exp(lm),
            scale * math.exp(lr),
            scale * math.exp(lo),
            tuple(math.tanh(u) for u in partial),
        )


#: Order of the excitation's autoregression. Chosen on forecasts issued every four weeks in 2006-2015 (before the
#: 2016-2020 hindcast, with a latency of one day, each from its own ten years of data, the noise refitted yearly;
#: ``scripts/excitation_order.py``): the 2-D RMS errors at 1 / 5 / 10 / 30 / 90 / 365 days were
#: 0.78 / 2.80 / 4.54 / 9.88 / 20.97 / 38.48 mas with p = 1 and 0.67 / 2.54 / 4.18 / 9.68 / 20.88 / 37.90 with
#: p = 3; p = 2, 4, 5, 6 and 8 gave 4.18-4.42 and 20.83-22.28 mas at 10 and 90 days, the best of them (p = 8,
#: 4.177 / 20.83) within the 0.9 % these scores move by where the noise fit stops (docs/forecast.md, "Why
#: order 3"); p = 3 is the smallest of the orders that tie. The likelihood
#: asks for more lags (on the ten years before 2006: +1694 from p = 1 to 3, +492 more to 6, +125 more to 8): the
#: C04 series, combined and smoothed, rings over a few days, which the forecasts use little beyond three lags.
EXCITATION_ORDER = 3

#: The starting point of the maximum likelihood: near the optimum for the IERS 20 C04 record 2006-2015 (ten years
#: before the first hindcast issue, 2016-01-01), rounded: the excitation, its lag-one correlation time and partial
#: autocorrelations to two digits (17.7 mas, 6.64 d, -0.566 and 0.366 at the optimum), the four small variances,
#: which the likelihood barely determines, to one (0.00098, 0.00098, 0.00126 and 0.00080 mas). From a poor start
#: L-BFGS-B can stop in a corner where random-walk seasonal terms mimic the wobble (likelihood lower by ~5000 on
#: ten years of data).
DEFAULT_NOISE = NoiseParameters(
    excitation=(18.0 * _MAS) ** 2,
    correlation_time=6.6 * DAY,
    seasonal=(0.001 * _MAS) ** 2,
    mean_pole=(0.001 * _MAS) ** 2,
    mean_pole_rate=(0.001 * _MAS) ** 2,
    observation=(0.0008 * _MAS) ** 2,
    partial_autocorrelations=(-0.57, 0.37),
)
# Bounds of the free parameters of the likelihood (ln tau in days, ln variance ratios, artanh of the partial
# autocorrelations beyond the first: |r| <= 0.995). tau down to 0.1 d (r_1 = 5e-5): before 1996 the record's
# day-to-day excitation is nearly white.
_BOUNDS = [(math.log(0.1), math.log(3650.0)), (-30.0, 5.0), (-30.0, 5.0), (-40.0, 0.0), (-20.0, 10.0)]
_PARTIAL_BOUND = (-3.0, 3.0)


def likelihood_bounds(order: int) -> list[tuple[float, float]]:
    """Bounds of the free parameters (:meth:`NoiseParameters.ratios`) of the model of ``order``."""
    return _BOUNDS + [_PARTIAL_BOUND] * (order - 1)


#: Finite-difference step of L-BFGS-B's gradient in the (logarithmic) free parameters. SciPy's default, 1e-8,
# divides the likelihood's rounding noise (~5e-9 on ten years) by 1e-8: gradients wrong by ~0.5 near the optimum,
# where the variance ratios are flat, so the search stopped 0.3-0.9 short of the maximum at a point that moved
# with the start and the machine; with 1e-5 four perturbed starts agree to 0.005 at the same cost.
GRADIENT_STEP = 1e-5


def mean_pole_index(order: int) -> int:
    """Index of the mean pole in the state of the model with an excitation of ``order`` (its rate follows)."""
    return order + 5


def system(sigma_c: complex, noise: NoiseParameters, dt: float = DAY):
    """(F, Q, h, r) of the daily model: transition, process covariance, observation vector, observation variance.

    The state is (w_k, chi_k, chi_{k-1} .. chi_{k-p+1}, seasonal, mean pole, rate): the excitation's companion
    form, and the wobble stepped with the new excitation, w_k = lambda w_{k-1} + (1 - lambda) chi_k.
    """
    p = noise.order
    m = p + 7
    lam = np.exp(1j * sigma_c * dt)
    phi = noise.ar()
    F = np.zeros((m, m), dtype=complex)
    F[0, 0] = lam
    F[0, 1 : 1 + p] = (1 - lam) * phi
    F[1, 1 : 1 + p] = phi
    F[np.arange(2, 1 + p), np.arange(1, p)] = 1.0  # chi_{k-j} moves down one lag
    for j, n in enumerate((1, -1, 2, -2)):
        F[1 + p + j, 1 + p + j] = np.exp(1j * n * ANNUAL_RATE * dt)
    mp = mean_pole_index(p)
    F[mp, mp], F[mp, mp + 1], F[mp + 1, mp + 1] = 1.0, 1.0, 1.0
    g = np.zeros(m, dtype=complex)
    g[0], g[1] = 1 - lam, 1.0
    Q = noise.excitation * np.outer(g, g.conj())
    Q[1 + p : mp, 1 + p : mp] += noise.seasonal * np.eye(4)
    Q[mp, mp] += noise.mean_pole
    Q[mp + 1, mp + 1] += noise.mean_pole_rate
    h = np.zeros(m, dtype=complex)
    h[0], h[1 + p : mp + 1] = 1.0, 1.0
    return F, Q, h, float(noise.observation)


def initial_state(t, z, sigma_c: complex, order: int = 1) -> np.ndarray:
    """A prior mean at the first sample from a least-squares fit of trend and harmonics to the first two years
    (the excitation and its lags zero)."""
    first = t <= t[0] + 2 * JULIAN_YEAR
    s = t[first] - t[0]
    cols = harmonic_columns(s, sigma_c.real)
    c, *_ = np.linalg.lstsq(cols, z[first], rcond=None)
    # Columns: 1, s/yr, Chandler, annual +, annual -, semi-annual +, semi-annual -; at s = 0 each is its coefficient.
    return np.array([c[2], *([0.0] * order), c[3], c[4], c[5], c[6], c[0], c[1] * DAY / JULIAN_YEAR], dtype=complex)


def concentrated_likelihood(F, Q, h, r, y, x0, burn: int = BURN_IN) -> tuple[float, float | None]:
    """(-log-likelihood, scale) of the daily series ``y`` under the model (F, s Q, h, s r) with the scale s
    in closed form (the mean squared innovation of the steady-state filter over its unit-scale variance),
    the first ``burn`` innovations left out; (inf, None) where the model has no stabilising filter."""
    try:
        steady = kalman.steady_state(F, Q, h, r)
        _, innov = kalman.filter_steady(F, steady, h, y, x0)
    except (np.linalg.LinAlgError, ValueError):  # no stabilising solution: the likelihood has no value here
        return math.inf, None
    e = innov[burn:]
    scale = float(np.mean(np.abs(e) ** 2)) / steady.innovation_variance
    if not (math.isfinite(scale) and scale > 0):
        return math.inf, None
    return e.size * (math.log(math.pi * scale * steady.innovation_variance) + 1.0), scale


def _concentrated(theta, sigma_c, y, x0, burn):
    """:func:`concentrated_likelihood` at the free parameters ``theta`` (:meth:`NoiseParameters.ratios`)."""
    return concentrated_likelihood(*system(sigma_c, NoiseParameters.from_ratios(theta)), y, x0, burn)


def fit_noise(
    t, z, sigma_c: complex, start: NoiseParameters = DEFAULT_NOISE, burn: int = BURN_IN
) -> tuple[NoiseParameters, float]:
    """Maximum-likelihood noise parameters on the daily series (t, z); returns them and the log-likelihood.

    The excitation variance (the overall scale) is concentrated out; the other
    parameters (:meth:`NoiseParameters.ratios`) are found by L-BFGS-B from
    ``start``, whose order the fit keeps.
    """
    y = np.asarray(z, dtype=complex)
    x0 = initial_state(t, y, sigma_c, start.order)
    bounds = likelihood_bounds(start.order)
    theta0 = np.clip(start.ratios(), [b[0] for b in bounds], [b[1] for b in bounds])
    # Where the likelihood has no value (_concentrated's inf), finite differences of inf give nan: L-BFGS-B
    # backs off from there, and numpy's warnings about it say nothing to a user.
    with np.errstate(invalid="ignore", over="ignore"):
        res = optimize.minimize(
            lambda th: _concentrated(th, sigma_c, y, x0, burn)[0],
            theta0,
            method="L-BFGS-B",
            bounds=bounds,
            options={"maxiter": 60, "ftol": 1e-9, "eps": GRADIENT_STEP},
        )
    nll, scale = _concentrated(res.x, sigma_c, y, x0, burn)
    if not math.isfinite(nll):
        raise InputError(
            "data", "a span where the state-space likelihood cannot be evaluated", "a daily record of the pole"
        )
    return NoiseParameters.from_ratios(res.x, scale), -nll


#: Diffuse prior of the first state of a fitting span (one-sigma, mas; the rate in mas/day): wide against
#: anything the pole does, so the forecast depends on the data only (the excitation's prior is its own
#: stationary variance).
PRIOR_SD_MAS = {"wobble": 1000.0, "seasonal": 1000.0, "mean_pole": 1000.0, "mean_pole_rate": 1.0}


def prior(y0: complex, noise: NoiseParameters) -> tuple[np.ndarray, np.ndarray]:
    """(x0, P0): the prior of the first state of a span whose first value is ``y0``: the mean pole there, the
    rest zero; diffuse but for the excitation, whose prior is its stationary distribution."""
    p = noise.order
    mp = mean_pole_index(p)
    x0 = np.zeros(p + 7, dtype=complex)
    x0[mp] = y0
    sd = PRIOR_SD_MAS
    var = np.array(
        [sd["wobble"] ** 2 * _MAS**2]
        + [0.0] * p
        + [sd["seasonal"] ** 2 * _MAS**2] * 4
        + [sd["mean_pole"] ** 2 * _MAS**2, sd["mean_pole_rate"] ** 2 * _MAS**2]
    )
    P0 = np.diag(var).astype(complex)
    P0[1 : 1 + p, 1 : 1 + p] = stationary_covariance(noise.ar(), noise.excitation)
    return x0, P0


def stationary_covariance(phi, variance: float) -> np.ndarray:
    """Covariance of (chi_k .. chi_{k-p+1}) of the stationary autoregression with coefficients ``phi`` and
    innovation ``variance``: the discrete Lyapunov equation P = A P A^H + q e_1 e_1^T of its companion
    matrix A."""
    phi = np.asarray(phi)
    p = phi.size
    A = np.zeros((p, p), dtype=phi.dtype)
    A[0] = phi
    A[np.arange(1, p), np.arange(0, p - 1)] = 1.0
    G = np.zeros((p, p))
    G[0, 0] = variance
    return linalg.solve_discrete_lyapunov(A, G)


@dataclass(frozen=True, eq=False)
class KalmanSetup:
    """The model with its noise and the exact filter over a span of ``n`` daily values (shared by every span
    of that length).

    The filter runs from the diffuse :func:`prior` over the whole span (the exact,
    time-varying recursion), not with the steady-state gain: the slowest modes
    of the steady-state filter (the seasonal amplitudes, the mean pole's rate)
    have time constants of 50 to 1000 years, so over a ten-year span it never
    forgets where it started, and its errors at 90 days were 1.2 to 1.3 times
    the stated sigma on a record of the model itself; the exact filter's match it.
    """

    chandler_period: float
    q: float
    noise: NoiseParameters
    n: int
    sigma_c: complex
    F: np.ndarray
    Q: np.ndarray
    h: np.ndarray
    r: float
    window: kalman.WindowFilter

    @classmethod
    def build(cls, chandler_period: float, q: float, noise: NoiseParameters, n: int) -> KalmanSetup:
        """The model of T_c = ``chandler_period`` (s) and ``q`` with ``noise``, filtered over spans of ``n`` days."""
        sigma_c = chandler_frequency(chandler_period, q)
        F, Q, h, r = system(sigma_c, noise)
        _, P0 = prior(0.0, noise)
        return cls(
            float(chandler_period),
            float(q),
            noise,
            int(n),
            sigma_c,
            F,
            Q,
            h,
            r,
            kalman.window_filter(F, Q, h, r, P0, int(n)),
        )

    def last_states(self, spans: np.ndarray) -> np.ndarray:
        """Filtered last states (k, m) of ``k`` spans (k, n) of daily values: one matrix product."""
        spans = np.atleast_2d(spans)
        mp = mean_pole_index(self.noise.order)
        return spans @ self.window.weights + np.outer(spans[:, 0], self.window.prior_map[:, mp])

    def forecast(self, x_last: np.ndarray, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Means (k, steps) of the pole 1 .. ``steps`` days after each state, the deterministic part alone
        (no free wobble), and the error variances (steps,) E|p - mean|^2, the same for every state."""
        rows = kalman.forecast_map(self.F, self.h, steps)
        x = np.atleast_2d(x_last)
        base = x.copy()
        base[:, : 1 + self.noise.order] = 0.0  # without the free wobble and its excitation: seasons and mean pole
        _, var = kalman.forecast(
            self.F, self.Q, self.h, self.r, np.zeros(self.F.shape[0], dtype=complex), self.window.posterior, steps
        )
        return x @ rows.T, base @ rows.T, var


@one_blas_thread
def forecast_kalman(
    t,
    z,
    issued: float,
    horizon_days: int,
    *,
    chandler_period: float,
    q: float,
    latency: float = DAY,
    fit_span: float = FIT_SPAN,
    noise: NoiseParameters | None = None,
    setup: KalmanSetup | None = None,
) -> Forecast:
    """Forecast the pole 1 .. ``horizon_days`` days after ``issued`` with the state-space model.

    Parameters
    ----------
    t, z : ndarray
        The record: times (s) and the pole p = x_p - i y_p (rad), daily.
    issued : float
        Issue time, s; only samples up to ``issued - latency`` are used.
    horizon_days : int
        Number of daily lead times.
    chandler_period, q : float
        T_c (s) and Q of the free wobble.
    latency, fit_span : float
        Publication delay and the fitting span, s.
    noise : NoiseParameters, optional
        Use these instead of fitting them (the hindcast refits them now and then,
        always on data before the issue date).
    setup : KalmanSetup, optional
        The model and filter already built for these noise parameters and this
        span length (reused by hindcasts and calibrations).
    """
    ti, zi = information_set(t, z, issued, latency, fit_span, "Kalman")
    daily(ti, "Kalman")
    sigma_c = chandler_frequency(chandler_period, q)
    refit = noise is None and setup is None
    loglike = math.nan
    if setup is not None:
        noise = setup.noise
    elif refit:
        noise, loglike = fit_noise(ti, zi, sigma_c)
    if setup is None or setup.n != zi.size or setup.sigma_c != sigma_c:
        setup = KalmanSetup.build(chandler_period, q, noise, zi.size)
    lead = DAY * np.arange(1, horizon_days + 1)
    ahead = np.rint((issued + lead - ti[-1]) / DAY).astype(int)
    mean, base, var = setup.forecast(setup.last_states(zi), int(ahead[-1]))
    sigma = np.sqrt(var[ahead - 1] / 2.0)
    return Forecast(
        method="kalman",
        issued=float(issued),
        last_data=float(ti[-1]),
        lead=lead,
        mean=mean[0, ahead - 1],
        sigma_x=sigma,
        sigma_y=sigma.copy(),
        baseline=base[0, ahead - 1],
        details={
            "fit_span_days": fit_span / DAY,
            "chandler_period_days": chandler_period / DAY,
            "q": q,
            "noise_refitted": refit,
            "log_likelihood": loglike,
            "noise": noise,
        },
    )


_CHUNK = 128  # spans per matrix product (128 x 3653 complex values: 7.5 MB)


@one_blas_thread
def past_forecasts_kalman(
    t, z, issues, horizon_days: int, *, setup: KalmanSetup, latency: float = DAY, fit_span: float = FIT_SPAN
) -> PastForecasts:
    """The forecasts :func:`forecast_kalman` issues at each of ``issues`` with this ``setup``, at once.

    Every span of the same length is filtered by the same weights G_k, so the
    last filtered states of many spans are one matrix product (spans x
    weights, in chunks), and their forecasts another: the same arithmetic as
    :func:`forecast_kalman` issue by issue (a test checks it). Each state reads
    its own span only (an FFT convolution over the record would be faster but
    mixes every sample into every state at the rounding level).
    Returns a :class:`~.forecast.PastForecasts`.
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(z, dtype=complex)
    issues = np.asarray(issues, dtype=float)
    cutoff = issues - latency
    end = np.searchsorted(t, cutoff + 1e-6, side="right")  # one past the last sample of each information set
    start = np.searchsorted(t, cutoff - fit_span - 1e-6, side="left")
    if np.any(end - start != setup.n):
        # Spans of other lengths (the record's edges): one forecast at a time, which names the problem.
        fs = [
            forecast_kalman(
                t,
                z,
                s,
                horizon_days,
                chandler_period=setup.chandler_period,
                q=setup.q,
                latency=latency,
                fit_span=fit_span,
                setup=setup,
            )
            for s in issues
        ]
        mean = np.array([f.mean for f in fs], dtype=complex).reshape(issues.size, horizon_days)
        sigma = np.array([np.stack([f.sigma_x, f.sigma_y], axis=1) for f in fs]).reshape(issues.size, horizon_days, 2)
        return PastForecasts(issues, mean, sigma)
    daily(t[int(start.min()) : int(end.max())], "Kalman")
    states = np.empty((issues.size, setup.F.shape[0]), dtype=complex)
    offsets = np.arange(setup.n)
    for a in range(0, issues.size, _CHUNK):
        states[a : a + _CHUNK] = setup.last_states(z[start[a : a + _CHUNK, None] + offsets[None, :]])
    ahead = np.rint(
        (issues[:, None] + DAY * np.arange(1, horizon_days + 1)[None, :] - t[end - 1][:, None]) / DAY
    ).astype(int)
    mean, _, var = setup.forecast(states, int(ahead.max()))
    sigma = np.sqrt(var[ahead - 1] / 2.0)  # circular: the same for x_p and y_p
    return PastForecasts(issues, np.take_along_axis(mean, ahead - 1, axis=1), np.stack([sigma, sigma], axis=2))
