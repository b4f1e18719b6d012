"""The getting-started page prints what it says it prints, and its script writes its figure."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import re
from pathlib import Path

from test_docs_examples import run_page

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "getting-started.md"


def test_three_scripts_print_what_the_page_shows(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))  # the scripts' mkdtemp() folders land here
    text = PAGE.read_text()
    shown = re.findall(r"^prints\n\n```text\n(.*?)^```", text, flags=re.S | re.M)
    assert len(shown) == 3 and text.count("```python") == 3
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        run_page(PAGE)
    assert out.getvalue() == "".join(shown)


def test_the_page_names_the_readme_commands():
    readme = (ROOT / "README.md").read_text()
    quickstart = re.search(r"<!-- quickstart:start -->\n```bash\n(.*?)```", readme, flags=re.S).group(1)
    assert f"```bash\n{quickstart}```" in PAGE.read_text()


def test_top_loops_script_writes_netcdf_and_figure(tmp_path):
    spec = importlib.util.spec_from_file_location("example_top_loops", ROOT / "scripts" / "example_top_loops.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    nc, png = script.main(tmp_path)
    assert nc.parent == tmp_path and nc.stat().st_size > 0
    assert png == tmp_path / "getting_started_top_loops.png" and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "getting_started_top_loops.png" in PAGE.read_text()
    assert (ROOT / "docs" / "figures" / "getting_started_top_loops.png").is_file()
