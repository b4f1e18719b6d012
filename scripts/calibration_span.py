"""How many years of past forecasts should calibrate each method's intervals? Chosen on 2006-2015.

``wobble forecast`` calibrates its 68 % and 95 % intervals on the same
method's forecasts issued every week over a span before the issue date
(``wobble.models.polar_motion.forecast_calibration``). A longer span holds
more past errors, so a steadier quantile, but follows a change in the errors'
size more slowly. This script runs the weekly hindcast of forecasts issued
2006-2015 (outcomes to 2016; nothing of the 2016-2020 hindcast the
documentation scores) for spans of 2 to 10 years, with the Rapid Service's
latency (1 d) and the C04's (30 d), and scores each method's intervals by

* their coverage: the share of outcomes inside the 68 % interval at every lead
  time from 1 to 365 days (the goal: 63-73 % at every lead), and
* their sharpness and calibration together: the interval score of Gneiting &
  Raftery (2007, J. Am. Stat. Assoc. 102, 359, eq. 43), for a central
  (1 - alpha) interval [l, u] and outcome y
  (u - l) + (2 / alpha) (l - y) [y < l] + (2 / alpha) (y - u) [y > u],
  a proper score (lower is better), averaged over the issues, the lead times,
  x_p and y_p, for the 68 % and the 95 % intervals.

The span chosen for each method is the one with the least sum of the two mean
interval scores, over both latencies, among the spans whose 68 % intervals held
63-73 % at every lead with both latencies. Result:
docs/figures/calibration_span.json, quoted in docs/forecast.md; the defaults
are ``forecast_calibration.SPANS``.

Run from the repository root (ten to fifteen minutes on two cores):

    python scripts/calibration_span.py
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
from astropy import units as u

import wobble
from wobble.api.polar_motion.record import RAD_PER_MAS
from wobble.models.polar_motion.forecast_calibration import P68, P95, SPANS

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures" / "calibration_span.json"
SPAN_YEARS = (2, 3, 4, 5, 6, 8, 10)
LATENCIES = (1, 30)
BAND = (0.63, 0.73)


def interval_score(err: np.ndarray, half: np.ndarray, p: float) -> np.ndarray:
    """Gneiting & Raftery's interval score of a central ``p`` interval +/- ``half`` about the forecast, for
    absolute errors ``err`` (the interval is symmetric, so l - y and y - u are both |error| - half)."""
    return 2.0 * half + (2.0 / (1.0 - p)) * np.maximum(err - half, 0.0)


def scores(h) -> dict:
    """Per method: mean interval scores (mas) and the 68 % and 95 % coverage (the hindcast's own scores)."""
    out = {}
    for k, m in enumerate(h.methods):
        rows = [row[k] for row in h.forecasts]
        d = np.array([f.mean for f in rows]) - h.truth
        err = np.stack([np.abs(d.real), np.abs(d.imag)])  # (component, issue, lead); |y error| = |Im|
        res = {}
        for level, p in ((68, P68), (95, P95)):
            half = np.stack([np.array([f.half_widths(level)[c] for f in rows]) for c in (0, 1)])
            cov = getattr(h.scores[m], f"coverage_{level}")
            res[f"interval_score_{level}_mas"] = float(interval_score(err, half, p).mean() / RAD_PER_MAS)
            res[f"coverage_{level}_range"] = [float(cov.min()), float(cov.max())]
        c68 = h.scores[m].coverage_68
        res["leads_outside_63_73"] = int(np.sum((c68 < BAND[0]) | (c68 > BAND[1])))
        out[m] = res
    return out


def main() -> None:
    table = {}
    for years in SPAN_YEARS:
        for lat in LATENCIES:
            t0 = time.perf_counter()
            h = wobble.hindcast_polar_motion(
                start="2006-01-01",
                end="2016-01-01",
                every=7 * u.day,
                horizon=365 * u.day,
                latency=lat * u.day,
                calibration_span=years * u.yr,
                workers=2,
            )
            s = scores(h)
            for m, res in s.items():
                table.setdefault(m, {}).setdefault(str(years), {})[f"latency_{lat}d"] = res
                print(
                    f"{m:6s} {years:2d} yr latency {lat:2d} d: interval score 68 % {res['interval_score_68_mas']:6.2f}"
                    f" 95 % {res['interval_score_95_mas']:7.2f} mas; 68 % coverage "
                    f"{100 * res['coverage_68_range'][0]:.1f}-{100 * res['coverage_68_range'][1]:.1f} % "
                    f"({res['leads_outside_63_73']} leads outside 63-73 %)  [{time.perf_counter() - t0:.0f} s]",
                    flush=True,
                )
    chosen = {}
    for m, rows in table.items():
        eligible = {
            y: sum(r["interval_score_68_mas"] + r["interval_score_95_mas"] for r in row.values())
            for y, row in rows.items()
            if all(r["leads_outside_63_73"] == 0 for r in row.values())
        }
        chosen[m] = int(min(eligible, key=eligible.get)) if eligible else None
        print(f"{m}: {chosen[m]} yr (shipped: {SPANS[m] / (365.25 * 86400):g} yr)")
    out = {
        "issued": ["2006-01-01", "2016-01-01"],
        "every_days": 7,
        "horizon_days": 365,
        "spans_years": list(SPAN_YEARS),
        "methods": table,
        "chosen_years": chosen,
        "rule": "least sum over both latencies of the mean 68 % and 95 % interval scores, among the spans whose "
        "68 % intervals held 63-73 % of the outcomes at every lead time 1-365 d with both latencies",
        "note": "weekly hindcast 2006-2015, calibrated intervals per span; scripts/calibration_span.py",
    }
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
