"""Write the figures of docs/precession.md into docs/figures/ from real runs.

Usage: python scripts/figures_precession.py
"""

from __future__ import annotations

from pathlib import Path

import wobble
from wobble.plot.precession import budget_figure, nutation_ellipse_figure

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    earth, mars = wobble.precession_rate("earth"), wobble.precession_rate("mars")
    for name, draw in (
        ("precession_budget.png", lambda p: budget_figure([earth, mars], p, overwrite=True)),
        ("precession_nutation.png", lambda p: nutation_ellipse_figure(earth, p, overwrite=True)),
    ):
        path = OUT / name
        draw(path)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
