"""Does the Kalman model's maximum likelihood need more than one starting point on older data?

``fit_noise`` (wobble.models.polar_motion.state_space) runs L-BFGS-B from one
starting point, the optimum of 2006-2015. On the ten years before 1996 the
likelihood of the first-order excitation had several optima: this script (1)
profiles the likelihood of the shipped model there over the excitation's
lag-one correlation time (the other parameters optimised at each of eight values,
Chandler period 433 d, Q 81.6) and (2) runs the weekly 1996-1999 hindcast of the
Kalman model twice, once as shipped and once with the best of four starts
(the shipped one and correlation times of 2, 20 and 200 days) at every refit,
and compares the fits' log-likelihoods and the forecasts' 2-D RMS errors.
Result: docs/figures/noise_multistart.json, quoted in docs/forecast.md.

Run from the repository root (about a minute on two cores):

    python scripts/noise_multistart.py
"""

from __future__ import annotations

import json
import math
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np
from astropy import units as u
from scipy import optimize

import wobble
from wobble.api.polar_motion.record import MJD_J2000, read_record, record_series
from wobble.models.polar_motion import forecast_calibration as fcal
from wobble.models.polar_motion import state_space as ss
from wobble.models.polar_motion.excitation import chandler_frequency
from wobble.models.polar_motion.forecast import information_set
from wobble.models.polar_motion.record import DAY

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures" / "noise_multistart.json"
ISSUED_MJD = 50083.0  # 1996-01-01
PROFILE_DAYS = (1.5, 3.0, 6.7, 15.0, 40.0, 100.0, 300.0, 1000.0)
RESTART_DAYS = (2.0, 20.0, 200.0)
LEADS = ("5", "10", "40", "90", "365")


def profile(t, z) -> dict:
    """The log-likelihood with the correlation time held at each of PROFILE_DAYS, and the shipped fit's."""
    issued = (ISSUED_MJD - MJD_J2000) * DAY
    ti, zi = information_set(t, z, issued, DAY, ss.FIT_SPAN, "Kalman")
    sigma_c = chandler_frequency(433.0 * DAY, 81.6)
    y = zi.astype(complex)
    x0 = ss.initial_state(ti, y, sigma_c, ss.DEFAULT_NOISE.order)
    shipped, loglike = ss.fit_noise(ti, zi, sigma_c)
    out = {"shipped_fit": {"correlation_time_days": shipped.correlation_time / DAY, "log_likelihood": loglike}}
    rest = ss.DEFAULT_NOISE.ratios()[1:]
    for tau in PROFILE_DAYS:
        res = optimize.minimize(
            lambda r, tau=tau: ss.concentrated_likelihood(
                *ss.system(sigma_c, ss.NoiseParameters.from_ratios(np.r_[math.log(tau), r])), y, x0
            )[0],
            rest,
            method="L-BFGS-B",
            bounds=ss.likelihood_bounds(ss.DEFAULT_NOISE.order)[1:],
            options={"maxiter": 60, "ftol": 1e-9, "eps": ss.GRADIENT_STEP},
        )
        out[f"tau_{tau:g}d"] = -float(res.fun)
        print(f"  correlation time held at {tau:6.1f} d: log-likelihood {-res.fun:.1f}")
    return out


@contextmanager
def fitting(best_of_starts: bool, log: list):
    """Swap the hindcast's noise fit for one that records its result (and, optionally, tries more starts)."""
    shipped = fcal.fit_noise

    def fit(t, z, sigma_c, start=ss.DEFAULT_NOISE, burn=ss.BURN_IN):
        taus = (None, *RESTART_DAYS) if best_of_starts else (None,)
        fits = []
        for tau in taus:
            s = start if tau is None else ss.NoiseParameters(**{**start.__dict__, "correlation_time": tau * DAY})
            fits.append(shipped(t, z, sigma_c, s, burn))
        best = max(fits, key=lambda f: f[1])
        log.append(
            {
                "span_end_mjd": t[-1] / DAY + MJD_J2000,
                "correlation_time_days": best[0].correlation_time / DAY,
                "log_likelihood": best[1],
            }
        )
        return best

    fcal.fit_noise = fit
    try:
        yield
    finally:
        fcal.fit_noise = shipped


def hindcast(best_of_starts: bool) -> dict:
    log: list = []
    t0 = time.perf_counter()
    with fitting(best_of_starts, log):
        h = wobble.hindcast_polar_motion(
            start="1996-01-01",
            end="2000-01-01",
            every=7 * u.day,
            horizon=365 * u.day,
            latency=1 * u.day,
            methods=("kalman",),
            scheduler="synchronous",
        )
    seconds = time.perf_counter() - t0
    print(h.summary())
    rms = h.to_dict()["methods"]["kalman"]["rms_2d_mas"]
    return {"rms_2d_mas": {lead: rms[lead] for lead in LEADS}, "fits": log, "seconds": seconds}


def main() -> None:
    _, t, z = record_series(read_record())
    print("ten years before 1996-01-01, profile over the correlation time:")
    out = {"profile_before_1996": profile(t, z)}
    for name, multi in (("one_start", False), ("best_of_four_starts", True)):
        print(f"1996-1999 weekly hindcast, {name.replace('_', ' ')}:")
        out[name] = hindcast(multi)
    gains = [
        b["log_likelihood"] - a["log_likelihood"]
        for a, b in zip(out["one_start"]["fits"], out["best_of_four_starts"]["fits"])
    ]
    out["log_likelihood_gains"] = gains
    out["note"] = "Kalman noise fits with one and with four starting points; scripts/noise_multistart.py"
    print(
        f"restarts raised the log-likelihood in {sum(g > 0.01 for g in gains)} of {len(gains)} fits, "
        f"by up to {max(gains):.1f}"
    )
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
