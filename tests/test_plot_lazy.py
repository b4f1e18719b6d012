"""``wobble.plot``'s modules load on first use, so every ``wobble.plot.MODULE.NAME`` the README and
docs mention works after a plain ``import wobble`` (a fresh-user review found
``wobble.plot.chandler`` raising AttributeError as the README printed it)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def _mentioned() -> list[str]:
    found = set()
    for page in PAGES:
        found.update(re.findall(r"\bwobble\.plot\.([a-z_]+\.[A-Za-z_]+)", page.read_text()))
    return sorted(found)


def test_every_module_is_listed():
    import wobble.plot

    files = {p.stem for p in (ROOT / "wobble" / "plot").glob("*.py") if not p.stem.startswith("_")}
    assert set(wobble.plot.__all__) == files


def test_mentioned_figures_resolve_after_import_wobble():
    names = _mentioned()
    assert "chandler.budget_figure" in names  # the README's list is found
    probe = "import sys, wobble\n" + "".join(f"assert callable(wobble.plot.{n}), {n!r}\n" for n in names)
    probe += "import wobble.plot\n"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT / "tests")
    assert done.returncode == 0, done.stderr[-2000:]


def test_import_wobble_plot_loads_no_matplotlib():
    probe = "import sys, wobble.plot; print('matplotlib' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
