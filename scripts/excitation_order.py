"""Which order of autoregression should the Kalman model's excitation have?

The state-space model of ``wobble forecast --method kalman`` drives the free
wobble with a coloured excitation, an autoregression of order p
(``state_space.EXCITATION_ORDER``). This script measures, for p = 1 .. 8 and
all before the 2016-2020 hindcast is scored:

1. the maximum log-likelihood on the ten years before 2006-01-01 (the fitting
   span of a forecast issued then with a latency of one day; Chandler period
   from least squares of the 30 years before, Q = 81.6), the better of the fits
   from the shipped start and from the order below's optimum;
2. the 2-D RMS forecast errors of a hindcast of 2006-2015: forecasts issued
   every four weeks from 2006-01-01, each from the record up to a day before
   its issue date, the Chandler period and the noise refitted every 13 issues
   (a year) from the data before the refit, scored against the C04 record at
   1 to 365 days (the means only: the order changes the forecasts, the
   calibration then sizes the intervals).

The order is chosen by the forecasts, not the likelihood, which keeps rising
with p on the smoothed C04 series. The same two measures are taken for one
variant the likelihood favours: order 3 with complex coefficients (complex
partial autocorrelations r_k = |r_k| exp(i theta_k), stationary for |r_k| < 1:
the excitation may turn in the complex plane from day to day, prograde and
retrograde excitation differing). Result: docs/figures/excitation_order.json,
quoted in docs/forecast.md and in the constant's comment.

Run from the repository root (about fifteen minutes on two cores; one process):

    python scripts/excitation_order.py
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
from scipy import optimize

from wobble.api.polar_motion.record import MJD_J2000, read_record, record_series
from wobble.models.polar_motion import state_space as ss
from wobble.models.polar_motion.excitation import chandler_frequency
from wobble.models.polar_motion.forecast import information_set
from wobble.models.polar_motion.hindcast import PERIOD_SPAN, truth_at
from wobble.models.polar_motion.least_squares import fit_least_squares
from wobble.models.polar_motion.record import DAY
from wobble.numerics import kalman

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures" / "excitation_order.json"
ORDERS = (1, 2, 3, 4, 5, 6, 8)
FIRST_MJD, END_MJD = 53736.0, 57388.0  # 2006-01-01, 2016-01-01
EVERY_DAYS, REFIT = 28, 13
HORIZON = 365
Q_FACTOR = 81.6  # the Chandler budget's anelastic Q, as the forecasts use it
LEADS = (1, 5, 10, 30, 40, 90, 365)
MAS = math.pi / 648e6


def chandler_period(t, z, cutoff: float) -> float:
    """The least-squares Chandler period of the 30 years up to ``cutoff`` (as the hindcast measures it)."""
    use = (t <= cutoff + 1e-6) & (t >= cutoff - PERIOD_SPAN)
    return fit_least_squares(t[use], z[use], reference_period=433 * DAY, uncertainty=False).chandler.period


def fit(
    t,
    z,
    issued: float,
    order: int,
    start: ss.NoiseParameters | None = None,
    *,
    span: float = ss.FIT_SPAN,
    period: float | None = None,
    q: float = Q_FACTOR,
):
    """(period, noise, log-likelihood, n): the model of ``order`` fitted on the information set of ``issued``
    from ``start`` (default: the shipped starting point at this order, as a forecast fits it), over ``span`` s,
    with the Chandler period ``period`` s (default: least squares of the 30 years before) and ``q``."""
    ti, zi = information_set(t, z, issued, DAY, span, "Kalman")
    period = chandler_period(t, z, ti[-1]) if period is None else period
    start = ss.DEFAULT_NOISE.with_order(order) if start is None else start
    noise, loglike = ss.fit_noise(ti, zi, chandler_frequency(period, q), start)
    return period, noise, loglike, zi.size


def nested_fit(t, z, issued: float, order: int, lower: ss.NoiseParameters | None):
    """The better of two fits of ``order``: from the shipped start and from the optimum of the order below
    (padded with a zero partial autocorrelation), so that the likelihood cannot fall with the order, whose
    models nest (a single start ended in a local optimum at order 5)."""
    fits = [fit(t, z, issued, order)]
    if lower is not None:
        fits.append(fit(t, z, issued, order, lower.with_order(order)))
    return max(fits, key=lambda f: f[2])


def hindcast(t, z, order: int, **settings) -> np.ndarray:
    """2-D RMS error (mas) at leads 1 .. HORIZON of the four-weekly 2006-2015 forecasts of ``order``;
    ``settings``: ``span``, ``period`` and ``q`` of :func:`fit` (default: the shipped ones)."""
    span, q = settings.get("span", ss.FIT_SPAN), settings.get("q", Q_FACTOR)
    issues = (np.arange(FIRST_MJD, END_MJD, EVERY_DAYS) - MJD_J2000) * DAY
    errors = []
    for a in range(0, issues.size, REFIT):
        block = issues[a : a + REFIT]
        period, noise, _, n = fit(t, z, float(block[0]), order, **settings)
        setup = ss.KalmanSetup.build(period, q, noise, n)
        mean = ss.past_forecasts_kalman(t, z, block, HORIZON, setup=setup, latency=DAY, fit_span=span).mean
        truth = truth_at(t, z, block[:, None] + DAY * np.arange(1, HORIZON + 1)[None, :])
        errors.append(mean - truth)
    e = np.concatenate(errors) / MAS
    return np.sqrt(np.mean(np.abs(e) ** 2, axis=0))


def rotating_system(sigma_c, theta, order: int):
    """(F, Q, h, r, phi) of the shipped model of ``order`` whose excitation coefficients are complex:
    ``theta`` is NoiseParameters.ratios() followed by the ``order`` phases (rad) of r_1 .. r_p."""
    noise = ss.NoiseParameters.from_ratios(theta[:-order])
    F, Q, h, r = ss.system(sigma_c, noise)
    moduli = np.array([math.exp(-DAY / noise.correlation_time), *noise.partial_autocorrelations])
    phi = ss.ar_coefficients(moduli * np.exp(1j * np.asarray(theta[-order:])))
    F[0, 1 : 1 + order] = (1 - F[0, 0]) * phi
    F[1, 1 : 1 + order] = phi
    return F, Q, h, r, phi


def fit_rotating(t, z, issued: float, order: int = 3):
    """(setup, theta, log-likelihood, the real fit's log-likelihood) of the rotating model on the information
    set of ``issued``: a KalmanSetup whose transition and filter are the rotating model's."""
    period, real, loglike_real, n = fit(t, z, issued, order)
    ti, zi = information_set(t, z, issued, DAY, ss.FIT_SPAN, "Kalman")
    sigma_c = chandler_frequency(period, Q_FACTOR)
    x0 = ss.initial_state(ti, zi, sigma_c, order)
    with np.errstate(invalid="ignore", over="ignore"):
        res = optimize.minimize(
            lambda th: ss.concentrated_likelihood(*rotating_system(sigma_c, th, order)[:4], zi, x0)[0],
            np.r_[real.ratios(), np.zeros(order)],
            method="L-BFGS-B",
            bounds=ss.likelihood_bounds(order) + [(-math.pi, math.pi)] * order,
            options={"maxiter": 100, "ftol": 1e-10, "eps": ss.GRADIENT_STEP},
        )
    F, Q, h, r, phi = rotating_system(sigma_c, res.x, order)
    nll, scale = ss.concentrated_likelihood(F, Q, h, r, zi, x0)
    noise = ss.NoiseParameters.from_ratios(res.x[:-order], scale)
    _, P0 = ss.prior(0.0, noise)
    P0[1 : 1 + order, 1 : 1 + order] = ss.stationary_covariance(phi, scale)
    window = kalman.window_filter(F, scale * Q, h, scale * r, P0, n)
    setup = ss.KalmanSetup(period, Q_FACTOR, noise, n, sigma_c, F, scale * Q, h, scale * r, window)
    return setup, res.x, -nll, loglike_real


def hindcast_rotating(t, z, order: int = 3) -> np.ndarray:
    """As :func:`hindcast` for the rotating model (the exact filter from the shipped prior, its excitation
    block the stationary covariance of the complex autoregression)."""
    issues = (np.arange(FIRST_MJD, END_MJD, EVERY_DAYS) - MJD_J2000) * DAY
    errors = []
    for a in range(0, issues.size, REFIT):
        block = issues[a : a + REFIT]
        setup = fit_rotating(t, z, float(block[0]), order)[0]
        mean = ss.past_forecasts_kalman(t, z, block, HORIZON, setup=setup, latency=DAY).mean
        truth = truth_at(t, z, block[:, None] + DAY * np.arange(1, HORIZON + 1)[None, :])
        errors.append(mean - truth)
    e = np.concatenate(errors) / MAS
    return np.sqrt(np.mean(np.abs(e) ** 2, axis=0))


def rms_text(rms) -> str:
    """The 2-D RMS at LEADS as one line of the report."""
    return " / ".join(f"{rms[d - 1]:.2f}" for d in LEADS) + f" mas at {' / '.join(map(str, LEADS))} d"


def main() -> None:
    _, t, z = record_series(read_record())
    issued = (FIRST_MJD - MJD_J2000) * DAY
    out = {"orders": {}}
    lower = None
    for order in ORDERS:
        t0 = time.perf_counter()
        _, noise, loglike, _ = nested_fit(t, z, issued, order, lower)
        lower = noise
        rms = hindcast(t, z, order)
        out["orders"][str(order)] = {
            "log_likelihood_before_2006": loglike,
            "partial_autocorrelations": [math.exp(-DAY / noise.correlation_time), *noise.partial_autocorrelations],
            "excitation_mas": math.sqrt(noise.excitation) / MAS,
            "rms_2d_mas": {str(d): float(rms[d - 1]) for d in LEADS},
        }
        seconds = time.perf_counter() - t0
        print(f"order {order}: log-likelihood {loglike:.1f}; 2-D RMS {rms_text(rms)} ({seconds:.0f} s)", flush=True)
    t0 = time.perf_counter()
    _, theta, loglike, loglike_real = fit_rotating(t, z, issued)
    rms = hindcast_rotating(t, z)
    out["order_3_complex"] = {
        "log_likelihood_before_2006": loglike,
        "gain_over_real_coefficients": loglike - loglike_real,
        "phases_rad": [float(v) for v in theta[-3:]],
        "rms_2d_mas": {str(d): float(rms[d - 1]) for d in LEADS},
    }
    print(
        f"order 3, complex coefficients: log-likelihood {loglike:.1f} ({loglike - loglike_real:+.1f}); "
        f"2-D RMS {rms_text(rms)} ({time.perf_counter() - t0:.0f} s)",
        flush=True,
    )
    out["note"] = (
        "Kalman model with excitation autoregressions of each order: maximum log-likelihood on the ten years "
        "before 2006-01-01 and 2-D RMS errors of forecasts issued every 28 days in 2006-2015 (latency 1 d, "
        "refitted yearly); scripts/excitation_order.py"
    )
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
