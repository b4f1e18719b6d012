"""``wobble.plot.save``: every figure wobble writes goes through one writer, which checks the path
first, writes atomically (nothing half-written, nothing existing destroyed without ``overwrite``)
and releases pyplot's figures without importing pyplot for a bare ``Figure``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from wobble.errors import InputError, OutputExistsError

ROOT = Path(__file__).resolve().parents[1]


def test_every_figure_writer_is_the_one_writer():
    import inspect

    import wobble.plot.excitation
    import wobble.plot.forecast
    import wobble.plot.inversion
    import wobble.plot.polar_motion
    from wobble.plot.save import save_figure

    assert wobble.plot.polar_motion.save_figure is save_figure
    assert wobble.plot.excitation.save_figure is save_figure
    assert wobble.plot.forecast.save_figure is save_figure
    # No module of wobble.plot calls savefig itself.
    for path in (ROOT / "wobble" / "plot").glob("*.py"):
        if path.name != "save.py":
            assert ".savefig(" not in path.read_text(), path.name
    assert "save_figure" in inspect.getsource(wobble.plot.inversion.corner_plot)


def test_a_bare_figure_is_written_with_the_umask_mode_and_without_pyplot(tmp_path):
    probe = (
        "import os, sys\n"
        "from matplotlib.figure import Figure\n"
        "from wobble.plot.save import save_figure\n"
        "os.umask(0o022)\n"
        "fig = Figure()\n"
        "fig.add_subplot().plot([0, 1])\n"
        f"p = save_figure(fig, {str(tmp_path / 'a.svg')!r})\n"
        "print(oct(os.stat(p).st_mode & 0o777), 'matplotlib.pyplot' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["0o644", "False"]
    assert (tmp_path / "a.svg").read_text().lstrip().startswith("<?xml")


def test_a_pyplot_figure_is_closed_after_saving(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from wobble.plot.save import save_figure

    fig = plt.figure()
    number = fig.number
    save_figure(fig, tmp_path / "a.png")
    assert not plt.fignum_exists(number)
    assert (tmp_path / "a.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_failed_draw_leaves_the_existing_file_and_no_temporary(tmp_path):
    from matplotlib.figure import Figure

    from wobble.plot.save import save_figure

    target = tmp_path / "a.pdf"
    target.write_text("the user's own file")

    class Broken(Figure):
        def savefig(self, fname, **kw):
            Path(fname).write_bytes(b"%PDF-half")  # a draw that fails half-way through its file
            raise RuntimeError("drawing failed")

    with pytest.raises(RuntimeError, match="drawing failed"):
        save_figure(Broken(), target, overwrite=True)
    assert target.read_text() == "the user's own file"
    assert sorted(os.listdir(tmp_path)) == ["a.pdf"]


@pytest.mark.parametrize(
    ("name", "error", "words"),
    [
        ("a.txt", InputError, "path: got a.txt; allowed: a file name ending in .png, .pdf or .svg"),
        ("missing/a.png", InputError, "path: got missing/a.png"),
        ("exists.png", OutputExistsError, "exists.png"),
    ],
)
def test_a_bad_path_is_refused_before_drawing(tmp_path, name, error, words):
    from wobble.plot.save import save_figure

    (tmp_path / "exists.png").write_text("keep")

    class Unused:
        def savefig(self, *a, **k):
            raise AssertionError("drew a figure for a path that was refused")

    with pytest.raises(error) as caught:
        save_figure(Unused(), tmp_path / name)
    assert words in str(caught.value).replace(str(tmp_path) + os.sep, "")
    assert (tmp_path / "exists.png").read_text() == "keep"


def test_a_refused_path_releases_a_pyplot_figure(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from wobble.plot.save import save_figure

    fig = plt.figure()
    with pytest.raises(InputError):
        save_figure(fig, tmp_path / "a.txt")
    assert not plt.fignum_exists(fig.number)


def test_wobble_invert_names_plot_for_a_bad_figure_path(tmp_path, capsys):
    """It named -o/--output (its own copy of the output check), for --plot /nonexistent/x.png."""
    from cli_run import run_cli

    code, out, err = run_cli(["invert", "mars", "--plot", str(tmp_path / "missing" / "x.png")], capsys)
    assert code == 2 and out == "" and err.startswith("wobble invert: error: --plot: got ")
