"""Does the pole record ask for a second, slow excitation time scale in the Kalman model?

The state-space model of ``wobble forecast --method kalman`` drives the free
wobble with one coloured excitation (an autoregression of order
``state_space.EXCITATION_ORDER`` whose lag-one correlation time is near 7 days:
atmosphere and ocean). Continental water and
the ocean's slow circulation excite the pole over months, which a second AR(1)
process with its own variance and correlation time could carry into the 40-90
day forecasts. This script adds that process (one more complex state) and
compares the two models' maximum log-likelihoods on the ten years before
1996, 2006 and 2016 (the fitting spans of forecasts issued on those dates with
a one-day latency; all before the 2016-2020 hindcast), from nine starting
points of the slow process (correlation time 30, 90 and 300 days; variance
ratio e^-8, e^-5 and e^-3 of the fast one's).

Two more free parameters earn their place by the likelihood-ratio test
(Wilks) when the log-likelihood rises by more than about 3 (chi-squared with
two degrees of freedom, 95 %). Result: docs/figures/excitation_timescales.json,
quoted in docs/forecast.md.

Run from the repository root (three to four minutes on two cores):

    python scripts/excitation_timescales.py
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from scipy import optimize

from wobble.api.polar_motion.record import MJD_J2000, read_record, record_series
from wobble.models.polar_motion import state_space as ss
from wobble.models.polar_motion.excitation import chandler_frequency
from wobble.models.polar_motion.forecast import information_set
from wobble.models.polar_motion.hindcast import PERIOD_SPAN
from wobble.models.polar_motion.least_squares import fit_least_squares
from wobble.models.polar_motion.record import DAY

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures" / "excitation_timescales.json"
ISSUES = {"1996-01-01": 50083.0, "2006-01-01": 53736.0, "2016-01-01": 57388.0}
Q_FACTOR = 81.6  # the Chandler budget's anelastic Q, as the forecasts use it
STARTS = [(tau, lq) for tau in (30.0, 90.0, 300.0) for lq in (-8.0, -5.0, -3.0)]
SLOW_BOUNDS = [(math.log(20.0), math.log(3650.0)), (-20.0, 2.0)]


def two_timescale_system(sigma_c: complex, theta):
    """(F, Q, h, r) of the shipped model with a second AR(1) excitation appended as one more state.

    ``theta`` is the free parameters of :meth:`NoiseParameters.ratios` (the
    shipped excitation's order) followed by ln(tau_slow / 1 d) and
    ln(variance_slow / variance_fast).
    """
    Fb, Qb, hb, r = ss.system(sigma_c, ss.NoiseParameters.from_ratios(theta[:-2]))
    m = Fb.shape[0]
    lam = np.exp(1j * sigma_c * DAY)
    phi = math.exp(-1.0 / math.exp(theta[-2]))
    F = np.zeros((m + 1, m + 1), dtype=complex)
    F[:m, :m] = Fb
    F[0, m], F[m, m] = (1 - lam) * phi, phi
    g = np.zeros(m + 1, dtype=complex)
    g[0], g[m] = 1 - lam, 1.0
    Q = math.exp(theta[-1]) * np.outer(g, g.conj())
    Q[:m, :m] += Qb
    return F, Q, np.append(hb, 0.0), r


def neg_log_likelihood(theta, sigma_c, y, x0) -> float:
    """The concentrated -log-likelihood of the model with the slow state (state_space's, the scale in closed form)."""
    return ss.concentrated_likelihood(*two_timescale_system(sigma_c, theta), y, x0)[0]


def compare(t, z, mjd_issued: float) -> dict:
    """Both models' maximum log-likelihoods on the fitting span of a forecast issued at ``mjd_issued``."""
    issued = (mjd_issued - MJD_J2000) * DAY
    ti, zi = information_set(t, z, issued, DAY, ss.FIT_SPAN, "Kalman")
    use = (t <= ti[-1] + 1e-6) & (t >= ti[-1] - PERIOD_SPAN)
    period = fit_least_squares(t[use], z[use], reference_period=433 * DAY, uncertainty=False).chandler.period
    sigma_c = chandler_frequency(period, Q_FACTOR)
    one, loglike_one = ss.fit_noise(ti, zi, sigma_c)
    x0 = np.append(ss.initial_state(ti, zi, sigma_c, one.order), 0.0)
    bounds = ss.likelihood_bounds(one.order) + SLOW_BOUNDS
    fits = []
    for tau, lq in STARTS:
        res = optimize.minimize(
            neg_log_likelihood,
            np.concatenate([one.ratios(), [math.log(tau), lq]]),
            args=(sigma_c, zi, x0),
            method="L-BFGS-B",
            bounds=bounds,
            options={"maxiter": 100, "ftol": 1e-10, "eps": ss.GRADIENT_STEP},
        )
        fits.append(res)
        print(f"  start tau {tau:5.0f} d, ratio e^{lq:+.0f}: log-likelihood {-res.fun:.2f}")
    best = min(fits, key=lambda r: r.fun)
    return {
        "fit_span": [float(ti[0] / DAY + MJD_J2000), float(ti[-1] / DAY + MJD_J2000)],
        "chandler_period_days": period / DAY,
        "one_timescale": {
            "log_likelihood": loglike_one,
            "correlation_time_days": one.correlation_time / DAY,
            "excitation_mas_per_day": math.sqrt(one.excitation) * 648e6 / math.pi,
        },
        "two_timescales": {
            "log_likelihood": -float(best.fun),
            "fast_correlation_time_days": math.exp(best.x[0]),
            "slow_correlation_time_days": math.exp(best.x[-2]),
            "slow_over_fast_variance": math.exp(best.x[-1]),
            "log_likelihood_of_each_start": [-float(r.fun) for r in fits],
        },
        "log_likelihood_gain": -float(best.fun) - loglike_one,
    }


def main() -> None:
    _, t, z = record_series(read_record())
    out = {}
    for date, mjd in ISSUES.items():
        print(f"forecast issued {date} (latency 1 d): ten years of fitting span")
        out[date] = compare(t, z, mjd)
        print(f"  gain of the second time scale: {out[date]['log_likelihood_gain']:+.2f} (3.0 would be significant)")
    out["note"] = (
        "maximum log-likelihoods of the Kalman model with one and with two AR(1) excitation time scales; "
        "scripts/excitation_timescales.py"
    )
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
