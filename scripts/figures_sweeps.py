"""Write the sweep figures (Mars histogram, top phase diagram, asteroid ensemble) into docs/figures/
from real runs of the shipped sweeps.

Usage: python scripts/figures_sweeps.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import wobble
from wobble.plot import sweep as sweep_plot

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    mars = wobble.run_sweep(ROOT / "data" / "sweeps" / "mars_chandler.toml")
    path = OUT / "sweep_mars_chandler.png"
    sweep_plot.histogram(mars, path, overwrite=True)
    print(f"wrote {path}")
    top = wobble.run_sweep(ROOT / "data" / "sweeps" / "top_phase_diagram.toml")
    path = OUT / "sweep_top_phase.png"
    sweep_plot.phase_diagram(top, path, overwrite=True)
    print(f"wrote {path}")
    asteroids = wobble.run_sweep(ROOT / "data" / "sweeps" / "tumbling_asteroids.toml")
    path = OUT / "sweep_tumbling_asteroids.png"
    sweep_plot.ensemble(asteroids, path, overwrite=True)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
