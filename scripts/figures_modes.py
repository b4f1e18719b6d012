"""Write the free-modes figure of docs/modes.md into docs/figures/ from a real run.

Usage: python scripts/figures_modes.py

One row per planet (Earth with PREM, Mars with its two-layer profile): the
hydrostatic flattening eps(r) from Clairaut's equation, the free core nutation
in space and the Chandler wobble against the core's dynamical ellipticity e_f,
with the observed periods, the hydrostatic e_f and the e_f the observed FCN
requires marked.
"""

from __future__ import annotations

from pathlib import Path

import wobble
from wobble.plot.modes import modes_figure

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "modes_core_flattening.png"
    modes_figure([wobble.normal_modes("earth"), wobble.normal_modes("mars")], path, overwrite=True)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
