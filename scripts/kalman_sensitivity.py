"""How much do the Kalman model's fixed settings matter? Fitting span, Chandler period and Q, measured before 2016-2020.

The state-space model of ``wobble forecast --method kalman`` estimates its noise and
filters its state on the last ``state_space.FIT_SPAN`` (10 years) of record, with the
Chandler period from least squares of the 30 years before and Q from wobble's
Chandler budget (81.6). This script repeats the selection hindcast of
``scripts/excitation_order.py`` (forecasts issued every four weeks in 2006-2015, a
latency of one day, the noise refitted yearly from the data before the refit, the
shipped third-order excitation) with one setting changed at a time:

* fitting spans of 10, 15 and 20 years;
* the Chandler period held at 428, 433 and 438 days instead of the least-squares one;
* Q of 50 and 150 instead of 81.6;

and reports the 2-D RMS errors at 1 to 365 days. It also splits the model's own forecast
variance, for a forecast issued 2016-01-01 (no outcome used), into the part the
excitation still to come makes and the part from the uncertainty of the filtered state
(wobble, seasons, mean pole): the first is the floor no better estimate of the state
can lower. Result:
docs/figures/kalman_sensitivity.json, quoted in docs/forecast.md.

Run from the repository root (about a minute on one core, more on a loaded machine):

    OMP_NUM_THREADS=1 python scripts/kalman_sensitivity.py
"""

from __future__ import annotations

import json
import time

import numpy as np
from excitation_order import HORIZON, LEADS, MAS, Q_FACTOR, ROOT, fit, hindcast, rms_text

from wobble.api.polar_motion.record import MJD_J2000, read_record, record_series
from wobble.io.dates import iso_date
from wobble.models.polar_motion import state_space as ss
from wobble.models.polar_motion.record import DAY
from wobble.numerics import kalman

OUT = ROOT / "docs" / "figures" / "kalman_sensitivity.json"
YEAR = 365.25 * DAY
VARIANTS = {
    "fit_span_years": {"10": {}, "15": {"span": 15 * YEAR}, "20": {"span": 20 * YEAR}},
    "chandler_period_days": {str(p): {"period": p * DAY} for p in (428, 433, 438)},
    "quality_factor": {str(q): {"q": float(q)} for q in (50, 150)},
}


def variance_budget(t, z, issued_mjd: float = 57388.0) -> dict:
    """The model's 2-D forecast sigma (mas) at LEADS for a forecast issued ``issued_mjd`` (default 2016-01-01),
    whole and from the excitation to come alone (the filtered state taken as known)."""
    tc, noise, _, n = fit(t, z, (issued_mjd - MJD_J2000) * DAY, ss.EXCITATION_ORDER)
    s = ss.KalmanSetup.build(tc, Q_FACTOR, noise, n)
    x0 = np.zeros(s.F.shape[0], dtype=complex)
    _, whole = kalman.forecast(s.F, s.Q, s.h, s.r, x0, s.window.posterior, HORIZON + 1)
    _, future = kalman.forecast(s.F, s.Q, s.h, s.r, x0, 0 * s.window.posterior, HORIZON + 1)
    ahead = {d: d + 1 for d in LEADS}  # one day of latency: a lead of d days is d + 1 steps past the data
    return {
        "issued": iso_date(issued_mjd),
        "sigma_2d_mas": {str(d): float(np.sqrt(whole[k - 1]) / MAS) for d, k in ahead.items()},
        "excitation_to_come_mas": {str(d): float(np.sqrt(future[k - 1]) / MAS) for d, k in ahead.items()},
    }


def main() -> None:
    _, t, z = record_series(read_record())
    out = {}
    for setting, values in VARIANTS.items():
        out[setting] = {}
        for label, kwargs in values.items():
            t0 = time.perf_counter()
            rms = hindcast(t, z, ss.EXCITATION_ORDER, **kwargs)
            out[setting][label] = {"rms_2d_mas": {str(d): float(rms[d - 1]) for d in LEADS}}
            print(f"{setting} {label}: 2-D RMS {rms_text(rms)} ({time.perf_counter() - t0:.0f} s)", flush=True)
    out["variance_budget"] = budget = variance_budget(t, z)
    print(
        "model sigma, whole / excitation to come: "
        + ", ".join(
            f"{budget['sigma_2d_mas'][str(d)]:.2f} / {budget['excitation_to_come_mas'][str(d)]:.2f}" for d in LEADS
        )
        + f" mas at {' / '.join(map(str, LEADS))} d",
        flush=True,
    )
    out["note"] = (
        "Kalman model (third-order excitation), one setting changed at a time: 2-D RMS errors of forecasts "
        "issued every 28 days in 2006-2015 (latency 1 d, refitted yearly); the shipped settings are a 10-year "
        "span, the least-squares Chandler period of the 30 years before and Q = 81.6; scripts/kalman_sensitivity.py"
    )
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
