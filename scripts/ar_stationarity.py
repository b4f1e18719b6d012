"""The LS+AR's AR fits with and without the stationarity constraint, in a weekly hindcast of 1980-2005.

``wobble.numerics.autoregression.select_ar`` takes the least-AIC order whose fit is
stationary; until 2026-11-29 it took the least-AIC order, stationary or not. This script
runs the LS+AR hindcast of forecasts issued weekly in 1980-2005 (latency 1 d, the models'
own intervals: the means do not depend on the calibration) both ways, counts the AR fits
whose characteristic polynomial has a root on or outside the unit circle, and scores both:
docs/figures/ar_stationarity.json, quoted in docs/forecast.md.

Run from the repository root (two to three minutes on one core):

    python scripts/ar_stationarity.py
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from astropy import units as u

import wobble
import wobble.models.polar_motion.ls_ar as ls_ar
from wobble.api.polar_motion.record import RAD_PER_MAS
from wobble.numerics import autoregression as ar

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures" / "ar_stationarity.json"
LEADS = (10, 90, 365)


def least_aic(y, max_order):
    """The selection before 2026-11-29: the least-AIC order, its fit stationary or not (same AIC as select_ar)."""
    y = np.asarray(y, dtype=float)
    aic = [ar.fit_ar(y, p, skip=max_order).aic for p in range(1, max_order + 1)]
    return ar.fit_ar(y, 1 + int(np.argmin(aic)))


def run(select) -> dict:
    """The hindcast with ``select`` as the AR order selection: moduli of the chosen fits' largest roots, errors."""
    moduli = []

    def counted(y, max_order):
        fit = select(y, max_order)
        moduli.append(np.max(np.abs(np.roots(np.r_[1.0, -fit.coeffs]))) if fit.order else 0.0)
        return fit

    ls_ar.select_ar = counted
    try:
        h = wobble.hindcast_polar_motion(
            start="1980-01-01", end="2006-01-01", methods=("ls_ar",), latency=1 * u.day, calibrated=False, workers=1
        )
    finally:
        ls_ar.select_ar = ar.select_ar
    err = np.abs(np.array([row[0].mean for row in h.forecasts]) - h.truth) / RAD_PER_MAS
    moduli = np.array(moduli)
    return {
        "ar_fits": int(moduli.size),
        "fits_with_a_root_on_or_outside_the_unit_circle": int(np.sum(moduli >= 1.0)),
        "largest_root_modulus": float(moduli.max()),
        "rms_2d_mas": {str(d): float(np.sqrt(np.mean(err[:, d - 1] ** 2))) for d in LEADS},
        "largest_error_mas": float(err.max()),
    }


def main() -> None:
    out = {"issued": ["1980-01-01", "2006-01-01"], "every_days": 7, "latency_days": 1}
    for name, select in (("least_aic", least_aic), ("least_aic_stationary", ar.select_ar)):
        out[name] = r = run(select)
        print(
            f"{name}: {r['fits_with_a_root_on_or_outside_the_unit_circle']} of {r['ar_fits']} fits with a root on or "
            f"outside the unit circle (largest modulus {r['largest_root_modulus']:.4f}); 2-D RMS "
            + " / ".join(f"{v:.4g}" for v in r["rms_2d_mas"].values())
            + f" mas at {' / '.join(map(str, LEADS))} d; largest error {r['largest_error_mas']:.3g} mas",
            flush=True,
        )
    out["note"] = "LS+AR weekly hindcast 1980-2005, latency 1 d; scripts/ar_stationarity.py"
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
