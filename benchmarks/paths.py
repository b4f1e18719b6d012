"""Where the committed references live: this source checkout (benchmarks/ sits beside wobble/)."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

from wobble.errors import InputError

__all__ = ["ROOT", "reference_file", "load_json"]

ROOT = Path(__file__).resolve().parents[1]


def reference_file(*parts: str) -> Path:
    """A committed reference file of the checkout (e.g. ``tests/references/heavy_top.json``)."""
    path = ROOT.joinpath(*parts)
    if not path.is_file():
        raise InputError(
            "reference",
            str(path),
            "a file of the wobble source checkout the benchmark runs from (the committed mpmath and Radau references)",
        )
    return path


@cache
def load_json(*parts: str) -> dict:
    """A committed JSON reference, read once."""
    return json.loads(reference_file(*parts).read_text())
