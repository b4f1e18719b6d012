"""Every ```python block in docs/*.md and README.md runs (no example may rot).

A page's blocks run in order in one namespace, the way a reader runs them.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "docs").rglob("*.md")) + [ROOT / "README.md"]


def run_page(page: Path) -> dict:
    """Execute the page's python blocks in order; return the namespace."""
    namespace: dict = {"__name__": "__docs__"}
    for n, block in enumerate(re.findall(r"^```python\n(.*?)^```", page.read_text(), flags=re.S | re.M)):
        exec(compile(block, f"{page.name}[block {n}]", "exec"), namespace)
    return namespace


@pytest.mark.parametrize("page", [p for p in PAGES if "```python" in p.read_text()], ids=lambda p: p.name)
def test_documented_examples_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))  # and their tempfile.mkdtemp() folders too
    run_page(page)
