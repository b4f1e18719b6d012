"""Write the Chandler budget figure of docs/chandler.md into docs/figures/ from a real run.

Usage: python scripts/figures_chandler.py
"""

from __future__ import annotations

from pathlib import Path

import wobble
from wobble.plot.chandler import budget_figure

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / "chandler_budget.png"
    budget_figure([wobble.chandler_budget("earth"), wobble.chandler_budget("mars")], path, overwrite=True)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
