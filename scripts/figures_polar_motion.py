"""Figures and numbers of docs/polar-motion.md, from the IERS 20 C04 record shipped with astropy-iers-data.

Run from the repository root (no network; about a minute on one core):

    python scripts/figures_polar_motion.py

Writes docs/figures/polar_motion_*.png and docs/figures/polar_motion_summary.txt
(the text report of ``wobble polar-motion`` with the default settings, plus the
numbers quoted on the docs page).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from astropy import units as u
from matplotlib.figure import Figure

import wobble
from wobble.cli._polar_motion_report import report
from wobble.plot import polar_motion as figures

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    a = wobble.polar_motion_analysis()

    fig = Figure(figsize=(11, 5), layout="constrained")
    left, right = fig.subplots(1, 2)
    figures.pole_path(a.data, start="1988-06-01", end="1994-10-31", ax=left)
    left.set_title("1988-1994: large Chandler wobble, clear 6.4-yr beat", fontsize="medium")
    figures.pole_path(a.data, start="2020-01-01", ax=right)
    right.set_title("2020-: the Chandler wobble nearly gone", fontsize="medium")
    fig.savefig(OUT / "polar_motion_path.png", dpi=100)

    ax = figures.two_sided_spectrum(a.spectrum, chandler_period=a.spectral.period)
    ax.figure.savefig(OUT / "polar_motion_spectrum.png", dpi=100)

    e = a.estimate
    ax_a, _ = figures.windowed_wobble(
        a.windows,
        period=(e.period.to_value(u.day), e.period_uncertainty.to_value(u.day)),
        model_period=a.budget.period.to_value(u.day),
    )
    ax_a.figure.savefig(OUT / "polar_motion_windows.png", dpi=100)

    # Numbers quoted in the docs.
    w = a.windows
    years = 2000 + (w["window_time"].values - 51544.5) / 365.25
    amp = w["chandler_amplitude"].values
    numbers = {
        "analysis": a.to_dict() | {"windows": None, "source_file": Path(a.data.attrs["source_file"]).name},
        "window_amplitude_mean_1975_2005_mas": float(np.nanmean(amp[(years > 1975) & (years < 2005)])),
        "window_amplitude_max_mas": float(np.nanmax(amp)),
        "window_amplitude_max_centre": float(years[np.nanargmax(amp)]),
        "window_amplitude_min_mas": float(np.nanmin(amp)),
        "window_amplitude_min_centre": float(years[np.nanargmin(amp)]),
        "window_amplitude_after_2016_mean_mas": float(np.nanmean(amp[years > 2016])),
        "excitation_sensitivity_days": {},
    }
    for q in (50.0, 100.0, 200.0):
        est = wobble.chandler_wobble(a.data, excitation_q=q)
        numbers["excitation_sensitivity_days"][str(q)] = est.period_uncertainty_parts["excitation"].to_value(u.day)
    text = (
        report(a)
        + "\n\n"
        + json.dumps(
            numbers, indent=1, default=lambda x: None if isinstance(x, float) and not math.isfinite(x) else str(x)
        )
    )
    (OUT / "polar_motion_summary.txt").write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
