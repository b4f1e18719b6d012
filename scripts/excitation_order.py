"""Which order of autoregression should the Kalman model's excitation have?

The state-space model of ``wobble forecast --method kalman`` drives the free
wobble with a coloured excitation, an autoregression of order p
(``state_space.EXCITATION_ORDER``). This script measures, for p = 1 .. 8 and
all before the 2016-2020 hindcast is scored:

1. the maximum log-likelihood on the ten years before 2006-01-01 (the fitting
   span of a forecast issued then with a latency of one day; Chandler period
   from least squares of the 30 years before, Q = 81.6);
2. the 2-D RMS forecast errors of a hindcast of 2006-2015: forecasts issued
   every four weeks from 2006-01-01, each from the record up to a day before
   its issue date, the Chandler period and the noise refitted every 13 issues
   (a year) from the data before the refit, scored against the C04 record at
   1 to 365 days (the means only: the order changes the forecasts, the
   calibration then sizes the intervals).

The order is chosen by the forecasts, not the likelihood, which keeps rising
with p on the smoothed C04 series. Result: docs/figures/excitation_order.json,
quoted in docs/forecast.md and in the constant's comment.

Run from the repository root (about five minutes on two cores; one process):

    python scripts/excitation_order.py
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from wobble.api.polar_motion.record import MJD_J2000, read_record, record_series
from wobble.models.polar_motion import state_space as ss
from wobble.models.polar_motion.excitation import chandler_frequency
from wobble.models.polar_motion.forecast import information_set
from wobble.models.polar_motion.hindcast import PERIOD_SPAN, truth_at
from wobble.models.polar_motion.least_squares import fit_least_squares
from wobble.models.polar_motion.record import DAY

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


def fit(t, z, issued: float, order: int):
    """(period, noise, log-likelihood, n): the model of ``order`` fitted on the information set of ``issued``."""
    ti, zi = information_set(t, z, issued, DAY, ss.FIT_SPAN, "Kalman")
    period = chandler_period(t, z, ti[-1])
    noise, loglike = ss.fit_noise(ti, zi, chandler_frequency(period, Q_FACTOR), ss.DEFAULT_NOISE.with_order(order))
    return period, noise, loglike, zi.size


def hindcast(t, z, order: int) -> np.ndarray:
    """2-D RMS error (mas) at leads 1 .. HORIZON of the four-weekly 2006-2015 forecasts of ``order``."""
    issues = (np.arange(FIRST_MJD, END_MJD, EVERY_DAYS) - MJD_J2000) * DAY
    errors = []
    for a in range(0, issues.size, REFIT):
        block = issues[a : a + REFIT]
        period, noise, _, n = fit(t, z, float(block[0]), order)
        setup = ss.KalmanSetup.build(period, Q_FACTOR, noise, n)
        mean = ss.past_forecasts_kalman(t, z, block, HORIZON, setup=setup, latency=DAY).mean
        truth = truth_at(t, z, block[:, None] + DAY * np.arange(1, HORIZON + 1)[None, :])
        errors.append(mean - truth)
    e = np.concatenate(errors) / MAS
    return np.sqrt(np.mean(np.abs(e) ** 2, axis=0))


def main() -> None:
    _, t, z = record_series(read_record())
    issued = (FIRST_MJD - MJD_J2000) * DAY
    out = {"orders": {}}
    for order in ORDERS:
        t0 = time.perf_counter()
        _, noise, loglike, _ = fit(t, z, issued, order)
        rms = hindcast(t, z, order)
        out["orders"][str(order)] = {
            "log_likelihood_before_2006": loglike,
            "partial_autocorrelations": [math.exp(-DAY / noise.correlation_time), *noise.partial_autocorrelations],
            "excitation_mas": math.sqrt(noise.excitation) / MAS,
            "rms_2d_mas": {str(d): float(rms[d - 1]) for d in LEADS},
        }
        print(
            f"order {order}: log-likelihood {loglike:.1f}; 2-D RMS "
            + " / ".join(f"{rms[d - 1]:.2f}" for d in LEADS)
            + f" mas at {' / '.join(map(str, LEADS))} d ({time.perf_counter() - t0:.0f} s)",
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
