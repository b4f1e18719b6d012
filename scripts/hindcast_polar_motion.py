"""Figures and numbers of docs/forecast.md: the 2016-2020 weekly hindcast, the excitation, an example forecast.

Run from the repository root (no network; about a minute on two cores):

    python scripts/hindcast_polar_motion.py

Writes docs/figures/forecast_*.png, docs/figures/excitation.png and
docs/figures/forecast_hindcast.json (the scores quoted on the page, for the
latency of the Rapid Service, 1 d, and of the C04 series, 30 d).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from astropy import units as u

import wobble
from wobble.cli._output import clean
from wobble.plot.excitation import save_excitation_figure
from wobble.plot.forecast import save_forecast_figure, save_hindcast_figure

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    numbers = {}
    for latency in (1, 30):
        t0 = time.perf_counter()
        h = wobble.hindcast_polar_motion(start="2016-01-01", end="2021-01-01", every=7 * u.day, horizon=365 * u.day, latency=latency * u.day)
        numbers[f"latency_{latency}d"] = h.to_dict() | {"seconds": time.perf_counter() - t0}
        print(h.summary())
        if latency == 1:
            save_hindcast_figure(h, OUT / "forecast_hindcast.png", overwrite=True)
    ex = wobble.geodetic_excitation()
    numbers["excitation"] = ex.to_dict()
    print(ex.summary())
    save_excitation_figure(ex, OUT / "excitation.png", overwrite=True)
    f = wobble.forecast_polar_motion(issued="2019-01-01", horizon=365 * u.day, latency=1 * u.day)
    save_forecast_figure(f, OUT / "forecast_example.png", overwrite=True)
    numbers["example_forecast"] = {k: v for k, v in f.to_dict().items() if k != "forecast"}
    text = json.dumps(clean(numbers), indent=1) + "\n"
    source = str(f.source)
    (OUT / "forecast_hindcast.json").write_text(text.replace(json.dumps(source)[1:-1], Path(source).name))


if __name__ == "__main__":
    main()
