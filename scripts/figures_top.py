"""Write the heavy-top figures of docs/heavy-top.md into docs/figures/ from real runs.

Usage: python scripts/figures_top.py
"""

from __future__ import annotations

from pathlib import Path

import astropy.units as u

from wobble import HeavyTop
from wobble.plot.top import cubic_figure, effective_potential_figure, nutation_classes_figure

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"
KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    common = dict(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=50 * u.deg, omega3=6 * RAD_S)
    fig = nutation_classes_figure(**common, phidots=[0.2 * RAD_S, 0 * RAD_S, -0.3 * RAD_S], periods=8)
    fig.savefig(OUT / "top_nutation.png", dpi=110)
    top = HeavyTop(**common, phidot0=-0.3 * RAD_S)
    effective_potential_figure(top).savefig(OUT / "top_potential.png", dpi=110)
    cubic_figure(top).savefig(OUT / "top_cubic.png", dpi=110)
    print(f"wrote {OUT / 'top_nutation.png'}, {OUT / 'top_potential.png'} and {OUT / 'top_cubic.png'}")


if __name__ == "__main__":
    main()
