"""Packaging: every subpackage ships, and the catalogue ships inside the package."""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_subpackage_is_listed_in_pyproject():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    on_disk = {
        ".".join(p.parent.relative_to(ROOT).parts)
        for p in (ROOT / "wobble").rglob("__init__.py")
        if "__pycache__" not in p.parts
    }
    data_dirs = {f"wobble._data.{d.name}" for d in (ROOT / "data").iterdir() if d.is_dir() and d.name != "__pycache__"}
    assert on_disk | {"wobble._data"} | data_dirs == listed


def test_catalogue_is_reachable_as_package_data():
    names = {p.name for p in (resources.files("wobble._data") / "bodies").iterdir()}
    assert {"earth.toml", "mars.toml"} <= names
    sweeps = {p.name for p in (resources.files("wobble._data") / "sweeps").iterdir()}
    assert {"mars_chandler.toml", "earth_chandler.toml"} <= sweeps
