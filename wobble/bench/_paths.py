"""Where the committed references live: the source checkout, not the installed package."""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

from wobble.errors import InputError

ROOT = Path(__file__).resolve().parents[2]


def reference_file(*parts: str) -> Path:
    """A committed reference file of the source tree (e.g. ``tests/references/heavy_top.json``)."""
    path = ROOT.joinpath(*parts)
    if not path.is_file():
        raise InputError(
            "reference", str(path), "a file of a wobble source checkout (the benchmark reads the committed "
            "mpmath and Radau references, which are not installed with the package)"
        )
    return path


@lru_cache(maxsize=None)
def load_json(*parts: str) -> dict:
    return json.loads(reference_file(*parts).read_text())
