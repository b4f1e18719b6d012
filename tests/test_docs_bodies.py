"""docs/bodies.md: its worked top example against the closed form."""

from __future__ import annotations

from pathlib import Path

from test_docs_examples import run_page

DOC = Path(__file__).resolve().parents[1] / "docs" / "bodies.md"


def test_top_example_gives_the_textbook_moment(tmp_path, monkeypatch):
    """The heavy-top block's I1 about the tip is the textbook disc-on-axle value."""
    monkeypatch.chdir(tmp_path)
    namespace = run_page(DOC)
    md, rd, ma, ell, h = 0.1, 0.03, 0.01, 0.08, 0.05
    i1 = md * rd**2 / 4 + md * h**2 + ma * ell**2 / 3
    assert abs(namespace["i1"].to_value("kg m2") / i1 - 1) < 1e-14
