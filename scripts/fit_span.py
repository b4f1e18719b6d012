"""How long a span should the Kalman model fit and filter? 10, 15 or 20 years, measured before 2016-2020.

The state-space model of ``wobble forecast --method kalman`` estimates its noise
and filters its state on the last ``state_space.FIT_SPAN`` (10 years) of record.
This script repeats the selection hindcast of ``scripts/excitation_order.py``
(forecasts issued every four weeks in 2006-2015, a latency of one day, the
Chandler period and the noise refitted yearly from the data before the refit,
the third-order excitation of the shipped model) with fitting spans of 10, 15
and 20 years, and reports the 2-D RMS errors at 1 to 365 days.
Result: docs/figures/fit_span.json, quoted in docs/forecast.md.

Run from the repository root (half a minute to a few minutes, with the load):

    python scripts/fit_span.py
"""

from __future__ import annotations

import json
import time

import numpy as np
from excitation_order import END_MJD, EVERY_DAYS, FIRST_MJD, HORIZON, LEADS, MAS, Q_FACTOR, REFIT, ROOT
from excitation_order import chandler_period, rms_text

from wobble.api.polar_motion.record import MJD_J2000, read_record, record_series
from wobble.models.polar_motion import state_space as ss
from wobble.models.polar_motion.excitation import chandler_frequency
from wobble.models.polar_motion.forecast import information_set
from wobble.models.polar_motion.hindcast import truth_at
from wobble.models.polar_motion.record import DAY

OUT = ROOT / "docs" / "figures" / "fit_span.json"
SPANS_YEARS = (10, 15, 20)


def hindcast(t, z, span: float) -> np.ndarray:
    """2-D RMS error (mas) at leads 1 .. HORIZON of the four-weekly 2006-2015 forecasts fitted on ``span`` s."""
    issues = (np.arange(FIRST_MJD, END_MJD, EVERY_DAYS) - MJD_J2000) * DAY
    errors = []
    for a in range(0, issues.size, REFIT):
        block = issues[a : a + REFIT]
        ti, zi = information_set(t, z, float(block[0]), DAY, span, "Kalman")
        period = chandler_period(t, z, ti[-1])
        noise, _ = ss.fit_noise(ti, zi, chandler_frequency(period, Q_FACTOR))
        setup = ss.KalmanSetup.build(period, Q_FACTOR, noise, zi.size)
        mean = ss.past_forecasts_kalman(t, z, block, HORIZON, setup=setup, latency=DAY, fit_span=span).mean
        truth = truth_at(t, z, block[:, None] + DAY * np.arange(1, HORIZON + 1)[None, :])
        errors.append(mean - truth)
    e = np.concatenate(errors) / MAS
    return np.sqrt(np.mean(np.abs(e) ** 2, axis=0))


def main() -> None:
    _, t, z = record_series(read_record())
    out = {"spans_years": {}}
    for years in SPANS_YEARS:
        t0 = time.perf_counter()
        rms = hindcast(t, z, years * 365.25 * DAY)
        out["spans_years"][str(years)] = {"rms_2d_mas": {str(d): float(rms[d - 1]) for d in LEADS}}
        print(f"{years} years: 2-D RMS {rms_text(rms)} ({time.perf_counter() - t0:.0f} s)", flush=True)
    out["note"] = (
        "Kalman model (third-order excitation) fitted and filtered on 10, 15 or 20 years: 2-D RMS errors of "
        "forecasts issued every 28 days in 2006-2015 (latency 1 d, refitted yearly); scripts/fit_span.py"
    )
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
