"""Corner plots of the shipped inversions (docs/inversion.md, docs/gallery.md).

Usage: python scripts/figures_inversion.py

Runs ``wobble.invert("mars")`` and ``wobble.invert("earth")`` at their default settings
(their default seeds: the figures are reproducible) and draws each posterior with
:func:`wobble.plot.inversion.corner_plot` into docs/figures/. About a minute on one core.
"""

from __future__ import annotations

from pathlib import Path

import wobble
from wobble.plot.inversion import corner_plot

FIGURES = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main() -> None:
    for name in ("mars", "earth"):
        result = wobble.invert(name)
        path = corner_plot(result, FIGURES / f"inversion_{name}_corner.png", overwrite=True)
        print(f"wrote {path}")
        for w in result.warnings:
            print(f"  WARNING ({name}): {w}")


if __name__ == "__main__":
    main()
