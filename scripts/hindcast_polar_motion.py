"""Figures and numbers of docs/forecast.md: the 2016-2020 weekly hindcast, the excitation, an example forecast.

Run from the repository root (no network; a few minutes on two cores):

    python scripts/hindcast_polar_motion.py               # 2016-2020, the page's numbers and figures
    python scripts/hindcast_polar_motion.py --selection   # 2006-2015, where the settings were chosen
    python scripts/hindcast_polar_motion.py --bulletin-a  # 2021, beside the IERS's operational Bulletin A

Writes docs/figures/forecast_*.png, docs/figures/excitation.png and
docs/figures/forecast_hindcast.json (the scores quoted on the page: calibrated
intervals for the latency of the Rapid Service, 1 d, and of the C04 series,
30 d, and the models' own Gaussian intervals for comparison); with
``--selection``, docs/figures/forecast_selection.json: the same hindcast over
2006-2015, the span on which the calibration's settings (weekly past forecasts,
standardised errors; the spans by scripts/calibration_span.py: six years for the
Kalman model, two for LS+AR) were chosen before 2016-2020 was scored; with
``--bulletin-a``, docs/figures/forecast_2021.json: forecasts issued weekly in 2021
(latency 1 d), their mean absolute errors beside those of the IERS Rapid Service's
operational predictions (Bulletin A) over 2021 as Wang & Zhang (2023) scored them.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np
from astropy import units as u

import wobble
from wobble.cli._output import clean
from wobble.plot.excitation import save_excitation_figure
from wobble.plot.forecast import save_forecast_figure, save_hindcast_figure

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures"
LEADS = (1, 2, 3, 5, 10, 20, 30, 40, 60, 90, 120, 150, 200, 270, 365)


def inside_68(h, k: int) -> np.ndarray:
    """(issues, leads): the share of x_p and y_p (0, 0.5 or 1) inside the 68 % interval, method ``k``."""
    rows = [row[k] for row in h.forecasts]
    d = np.array([f.mean for f in rows]) - h.truth
    half = [np.array(v) for v in zip(*(f.half_widths(68) for f in rows))]
    return ((np.abs(d.real) <= half[0]).astype(float) + (np.abs(d.imag) <= half[1])) / 2.0


def block_bootstrap_se(values: np.ndarray, block: int, draws: int = 2000, seed: int = 0) -> float:
    """Standard error of the mean of a serially correlated series by the moving-block bootstrap
    (Kuensch 1989): resamples made of random runs of ``block`` consecutive values."""
    rng = np.random.default_rng(seed)
    n = values.size
    block = min(block, n)
    starts = rng.integers(0, n - block + 1, size=(draws, -(-n // block)))
    idx = (starts[:, :, None] + np.arange(block)).reshape(draws, -1)[:, :n]
    return float(np.std(values[idx].mean(axis=1)))


def coverage_table(h) -> dict:
    """Per method: 68 % and 95 % coverage at LEADS, their range over every lead 1-365 d, the leads
    outside 63-73 %, and the 68 % coverage's standard error at LEADS (moving blocks of issues spanning
    the lead plus 60 days: forecasts whose outcomes overlap are resampled together)."""
    out = {}
    step = float(np.median(np.diff(h.issued_mjd)))
    for k, m in enumerate(h.methods):
        inside = inside_68(h, k)
        se = {str(d): block_bootstrap_se(inside[:, d - 1], int(np.ceil((d + 60) / step))) for d in LEADS}
        s = h.scores[m]
        assert np.allclose(inside.mean(axis=0), s.coverage_68), "the bootstrap's hits are not the scores'"
        c68, c95 = s.coverage_68, s.coverage_95
        outside = [int(d) for d in np.flatnonzero((c68 < 0.63) | (c68 > 0.73)) + 1]
        out[m] = {
            "coverage_68": {str(d): float(c68[d - 1]) for d in LEADS},
            "coverage_95": {str(d): float(c95[d - 1]) for d in LEADS},
            "coverage_68_range": [float(c68.min()), float(c68.max())],
            "coverage_95_range": [float(c95.min()), float(c95.max())],
            "leads_outside_63_73": outside,
            "coverage_68_standard_error": se,
            "coverage_68_every_lead": [float(v) for v in c68],
            "coverage_95_every_lead": [float(v) for v in c95],
        }
    return out


def hindcast(start, end, latency, calibrated=True):
    t0 = time.perf_counter()
    h = wobble.hindcast_polar_motion(
        start=start,
        end=end,
        every=7 * u.day,
        horizon=365 * u.day,
        latency=latency * u.day,
        calibrated=calibrated,
        workers=2,
    )
    seconds = time.perf_counter() - t0
    print(h.summary())
    return h, h.to_dict() | {"coverage": coverage_table(h), "seconds": seconds, "load_average": os.getloadavg()}


#: Wang C. & Zhang P. 2023, Improving the accuracy of polar motion prediction using a hybrid least squares
#: and long short-term memory model, Earth Planets Space 75, 153, doi:10.1186/s40623-023-01910-8, Table 2:
#: mean absolute errors (mas) over 2021 against IERS 14 C04, at these lead times (days), of IERS Bulletin
#: A's predictions and of their own least squares + autoregression (the baseline another group built).
WANG_ZHANG_2023 = {
    "source": "Wang & Zhang 2023, Earth Planets Space 75, 153, Table 2 (2021, against IERS 14 C04)",
    "lead_days": (1, 5, 10, 15, 20, 30, 45, 60, 90, 120, 180, 270, 320, 365),
    "bulletin_a": {
        "mae_x_mas": (0.269, 1.563, 2.892, 3.988, 5.033, 6.809, 9.227,
                      11.260, 14.619, 16.819, 19.148, 22.318, 24.096, 25.770),
        "mae_y_mas": (0.196, 1.073, 1.843, 2.480, 3.077, 4.261, 5.904,
                      7.454, 11.176, 15.500, 22.356, 25.066, 23.980, 25.107),
    },
    "their_ls_ar": {
        "mae_x_mas": (0.257, 1.603, 3.046, 4.593, 5.751, 7.995, 11.483,
                      14.915, 21.950, 27.506, 32.933, 33.364, 36.116, 37.491),
        "mae_y_mas": (0.197, 1.099, 1.940, 2.751, 3.607, 5.407, 8.292,
                      11.382, 17.785, 23.904, 31.231, 29.096, 30.430, 31.949),
    },
}  # fmt: skip


def bulletin_a() -> dict:
    """Forecasts issued weekly in 2021 (latency 1 d), their mean absolute errors at Wang & Zhang's lead times,
    beside Bulletin A's and their LS+AR's."""
    h, numbers = hindcast("2021-01-01", "2022-01-01", 1)
    leads = WANG_ZHANG_2023["lead_days"]
    keys = {"mae_x": "mae_x_mas", "mae_y": "mae_y_mas", "coverage_68": "coverage_68_fraction"}  # with their units
    ours = {
        m: {name: {str(d): v for d, v in h.at(key, m, leads).items()} for key, name in keys.items()} for m in h.methods
    }
    published = {
        column: {"source": WANG_ZHANG_2023["source"]}
        | {key: dict(zip(map(str, leads), values)) for key, values in WANG_ZHANG_2023[column].items()}
        for column in ("bulletin_a", "their_ls_ar")
    }
    return {"wobble": ours, **published, "hindcast": numbers}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--selection", action="store_true", help="the 2006-2015 hindcast of the settings' choice instead"
    )
    parser.add_argument("--bulletin-a", action="store_true", help="2021, beside the IERS's Bulletin A, instead")
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    if args.bulletin_a:
        numbers = bulletin_a()
        write(numbers, OUT / "forecast_2021.json", numbers["hindcast"]["source_file"])
        return
    if args.selection:
        numbers = {f"latency_{lat}d": hindcast("2006-01-01", "2016-01-01", lat)[1] for lat in (1, 30)}
        write(numbers, OUT / "forecast_selection.json", numbers["latency_1d"]["source_file"])
        return
    numbers = {}
    for lat in (1, 30):
        h, numbers[f"latency_{lat}d"] = hindcast("2016-01-01", "2021-01-01", lat)
        if lat == 1:
            save_hindcast_figure(h, OUT / "forecast_hindcast.png", overwrite=True)
    _, numbers["latency_1d_uncalibrated"] = hindcast("2016-01-01", "2021-01-01", 1, calibrated=False)
    ex = wobble.geodetic_excitation()
    numbers["excitation"] = ex.to_dict()
    print(ex.summary())
    save_excitation_figure(ex, OUT / "excitation.png", overwrite=True)
    f = wobble.forecast_polar_motion(issued="2019-01-01", horizon=365 * u.day, latency=1 * u.day)
    save_forecast_figure(f, OUT / "forecast_example.png", overwrite=True)
    numbers["example_forecast"] = {k: v for k, v in f.to_dict().items() if k != "forecast"}
    write(numbers, OUT / "forecast_hindcast.json", str(f.source))


def write(numbers, path, source) -> None:
    """JSON with the record's path shortened to its file name (no machine paths in the docs)."""
    text = json.dumps(clean(numbers), indent=1) + "\n"
    path.write_text(text.replace(json.dumps(source)[1:-1], Path(source).name))


if __name__ == "__main__":
    main()
