"""The main entry points carry a runnable Examples section (run by pytest --doctest-modules)."""

from __future__ import annotations

import inspect

import pytest

import wobble

ENTRY_POINTS = [
    "chandler_budget",
    "euler_period",
    "rigid_wobble",
    "FreeRotation",
    "HeavyTop",
    "RigidBody",
    "run",
    "load_polar_motion",
    "load",
]


@pytest.mark.parametrize("name", ENTRY_POINTS)
def test_entry_point_has_a_doctest(name):
    doc = inspect.getdoc(getattr(wobble, name)) or ""
    assert "Examples\n--------" in doc and ">>> " in doc, f"wobble.{name} needs a runnable Examples section"
