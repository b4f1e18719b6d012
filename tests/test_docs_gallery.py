"""The gallery shows every figure in docs/figures/, and each is made by a script figures_all.py runs."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "docs" / "figures"
GALLERY = (ROOT / "docs" / "gallery.md").read_text()


def _figures_all():
    spec = importlib.util.spec_from_file_location("figures_all", ROOT / "scripts" / "figures_all.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_figure_is_in_the_gallery():
    shown = set(re.findall(r"figures/([\w.-]+\.png)", GALLERY))
    # The work-precision diagrams live on the performance page, next to their numbers.
    existing = {p.name for p in FIGURES.glob("*.png") if not p.name.startswith("work_precision")}
    assert existing - shown == set(), "figures missing from docs/gallery.md"
    assert shown - existing == set(), "the gallery shows figures that do not exist"


def test_every_figure_names_the_script_that_draws_it():
    scripts = {p.name for p in (ROOT / "scripts").glob("*.py")}
    for name in re.findall(r"`scripts/([\w.-]+\.py)`", GALLERY):
        assert name in scripts
    for block in re.findall(r"```\{figure\}(.*?)```", GALLERY, flags=re.S):
        assert "scripts/" in block or "polar_motion" in block, block  # polar-motion figures share one caption


def test_figures_all_runs_every_figures_script():
    names = {name for name, _ in _figures_all().jobs()}
    for script in (ROOT / "scripts").glob("figures_*.py"):
        if script.name != "figures_all.py":
            assert script.stem in names
    assert "example_top_loops" in names
    # The Mars histogram: drawn by a figures_sweep*.py script when there is one, else by the CLI job.
    assert "sweep_mars_chandler" in names or any(n.startswith("figures_sweep") for n in names)
