"""`wobble polar-motion`: JSON, table, netCDF and figure; exit status 2 with one line on bad input."""

from __future__ import annotations

import json

import pytest

from wobble.cli import main
from wobble.io.netcdf import open_wobble

# A short span without the Monte-Carlo term and Q keeps these runs quick.
FAST = ["--start", "2000-01-01", "--end", "2012-12-31", "--window", "6", "--step", "2", "--excitation-q", "none", "--no-q"]


def _run(capsys, *args):
    status = main(["polar-motion", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_json_outputs_and_files(tmp_path, capsys):
    nc, png = tmp_path / "pm.nc", tmp_path / "pm.png"
    status, out, err = _run(capsys, *FAST, "--json", "-o", str(nc), "--plot", str(png))
    assert status == 0 and err == ""  # no progress text when stderr is not a terminal
    d = json.loads(out)
    for key in (
        "chandler_period_days",
        "chandler_period_uncertainty_days",
        "chandler_amplitude_mas",
        "annual_amplitude_mas",
        "start",
        "end",
        "method",
        "estimates",
        "windows",
        "comparison",
    ):
        assert key in d
    assert d["start"] == "2000-01-01" and d["end"] == "2012-12-31" and d["method"] == "least_squares"
    assert 420 < d["chandler_period_days"] < 445
    assert set(d["estimates"]) == {"least_squares", "spectrum"}
    assert d["estimates"]["least_squares"]["chandler_period_uncertainty_parts_days"]["excitation"] is None
    assert [r["kind"] for r in d["comparison"]][0] == "observed" and d["comparison"][-1]["kind"] == "published"
    ds = open_wobble(nc)
    assert "polar-motion" in ds.attrs["history"]
    assert {"x_p", "x_p_model", "x_p_residual", "chandler_amplitude", "amplitude_spectrum"} <= set(ds.variables)
    # (CF compliance of this layout: tests/test_polar_motion_api.py, on the whole record.)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_table_shows_the_estimate_beside_the_model(capsys):
    status, out, _ = _run(capsys, *FAST)
    assert status == 0
    for word in ("least squares", "spectrum", "period [d]", "model: rigid", "model: anelastic", "Vicente & Wilson 1997", "Windows of 6 yr"):
        assert word in out


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--start", "1900-01-01"], "start: got 1900-01-01; allowed: a date from 1962-01-01"),
        (["--end", "2999"], "end: got 2999"),
        (["--start", "2010", "--end", "2005"], "a date after start"),
        (["--start", "2000", "--end", "2012", "--window", "0.5"], "window: got 0.5 yr"),
        (["--start", "2000", "--end", "2012", "--window", "40"], "window: got 40.0 yr"),
        (["--window", "eight"], "--window: got eight"),
        (["--excitation-q", "lots"], "--excitation-q: got lots"),
        (["--file", "/nonexistent/eop.txt"], "/nonexistent/eop.txt: no such file"),
        (["--start", "2000-01-01", "--end", "2001-01-01"], "at least 730 d"),
    ],
)
def test_bad_input_exit_2_one_line(capsys, args, fragment):
    status, out, err = _run(capsys, *args)
    assert status == 2
    assert fragment in err and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("wobble polar-motion: error: ")


def test_bad_file_names_the_line(tmp_path, capsys):
    from wobble.io.eop import default_c04_path

    lines = default_c04_path().read_text().splitlines()[:3000]
    lines[2500] = lines[2500][:80]
    path = tmp_path / "cut.txt"
    path.write_text("\n".join(lines) + "\n")
    status, _, err = _run(capsys, "--file", str(path))
    assert status == 2 and "line 2501: truncated" in err and err.count("\n") == 1


def test_existing_output_refused_before_the_work(tmp_path, capsys):
    path = tmp_path / "pm.nc"
    path.write_bytes(b"keep me")
    status, out, err = _run(capsys, "-o", str(path))
    assert status == 2 and "--overwrite" in err and out == ""
    assert path.read_bytes() == b"keep me"


def test_help_has_examples(capsys):
    with pytest.raises(SystemExit) as info:
        main(["polar-motion", "--help"])
    assert info.value.code == 0
    text = capsys.readouterr().out
    assert "examples:" in text and "wobble polar-motion --start" in text
