"""Write the free-rotation figures of docs/free-rotation.md into docs/figures/ from real runs.

Usage: python scripts/figures_free.py
"""

from __future__ import annotations

from pathlib import Path

import astropy.units as u

from wobble.plot.free import flip_figure, polhode_figure

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    moments = [1, 2, 3] * u.kg * u.m**2
    starts = (
        [(1, 0.1, a) for a in (0.4, 0.7, 1.0, 1.5)]
        + [(a, 0.1, 0.2) for a in (1.5, 2.5)]
        + [(1e-6, 1, 1e-6), (3e-6, 1, 1e-6)]
    )
    fig = polhode_figure(moments, [w * u.rad / u.s for w in starts])
    fig.savefig(OUT / "free_polhode.png", dpi=120)
    fig = flip_figure(moments, [1e-6, 1, 1e-6] * u.rad / u.s, 200 * u.s)
    fig.savefig(OUT / "free_flip.png", dpi=120)
    print(f"wrote {OUT / 'free_polhode.png'} and {OUT / 'free_flip.png'}")


if __name__ == "__main__":
    main()
