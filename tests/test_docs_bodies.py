"""docs/bodies.md: every ``python`` code block runs, in order, in one namespace."""

from __future__ import annotations

import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "bodies.md"


def test_every_code_block_runs(tmp_path, monkeypatch):
    blocks = re.findall(r"^```python\n(.*?)^```", DOC.read_text(), flags=re.S | re.M)
    assert len(blocks) >= 8
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for i, block in enumerate(blocks):
        exec(compile(block, f"{DOC.name}[block {i}]", "exec"), namespace)
    # The heavy-top block's numbers are the textbook ones.
    md, rd, ma, ell, h = 0.1, 0.03, 0.01, 0.08, 0.05
    i1 = md * rd**2 / 4 + md * h**2 + ma * ell**2 / 3
    assert abs(namespace["i1"].to_value("kg m2") / i1 - 1) < 1e-14
