"""`wobble polar-motion`: JSON, table, netCDF and figure; exit status 2 with one line on bad input."""

from __future__ import annotations

import json

import pytest

from wobble.api.polar_motion.analysis import JSON_RENAMES
from wobble.cli import main
from wobble.io.json_keys import values_at
from wobble.io.netcdf import open_wobble

# A short span without the Monte-Carlo term and Q keeps these runs quick.
FAST = [
    "--start",
    "2000-01-01",
    "--end",
    "2012-12-31",
    "--window",
    "6",
    "--step",
    "2",
    "--excitation-q",
    "none",
    "--no-q",
]


def _run(capsys, *args):
    status = main(["polar-motion", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_json_outputs_and_files(tmp_path, capsys):
    nc, png = tmp_path / "pm.nc", tmp_path / "pm.png"
    status, out, err = _run(capsys, *FAST, "--json", "-o", str(nc), "--plot", str(png))
    # No progress text when stderr is not a terminal; under --json the files are announced there.
    assert status == 0 and err.splitlines() == [f"wrote {nc}", f"wrote {png}"]
    d = json.loads(out)
    for key in (
        "chandler_period_days",
        "chandler_period_uncertainty_days",
        "chandler_amplitude_mas",
        "annual_prograde_amplitude_mas",
        "annual_amplitude_mas",  # deprecated alias, one release
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
    assert d["annual_amplitude_mas"] == d["annual_prograde_amplitude_mas"]
    assert d["deprecated_keys"] == {
        "annual_amplitude_mas": "annual_prograde_amplitude_mas",
        "annual_amplitude_uncertainty_mas": "annual_prograde_amplitude_uncertainty_mas",
        **JSON_RENAMES,
    }
    # Every alias holds the new key's value, wherever it is nested (estimates.*, windows, comparison[]).
    for old, new in d["deprecated_keys"].items():
        assert values_at(d, old) == values_at(d, new) != [], old
    assert d["quality_factor_estimate"] is None or isinstance(d["quality_factor_estimate"], dict)
    # Vicente & Wilson (1997): 433.1 +- 1.7 d, the published comparison row (data/bodies/earth.toml).
    assert d["published"]["period_days"] == 433.1 and d["comparison"][-1]["period_uncertainty_days"] == 1.7
    assert set(d["estimates"]) == {"least_squares", "spectrum"}
    assert d["estimates"]["least_squares"]["chandler_period_uncertainty_parts_days"]["excitation"] is None
    assert [r["kind"] for r in d["comparison"]][0] == "observed" and d["comparison"][-1]["kind"] == "published"
    ds = open_wobble(nc)
    assert "polar-motion" in ds.attrs["history"]
    assert {"x_p", "x_p_model", "x_p_residual", "chandler_amplitude", "amplitude_spectrum"} <= set(ds.variables)
    # The windowed estimates are in the file beside the whole-span ones, not hidden by them.
    assert ds["window_chandler_amplitude"].dims == ("window",) and ds["chandler_amplitude"].dims == ("method",)
    assert ds["window_annual_prograde_amplitude"].attrs["units"] == "milliarcsecond"
    # (CF compliance of this layout: tests/test_polar_motion_api.py, on the whole record.)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # Every output gets the umask's mode: the figure like the netCDF file (0644 under umask 022).
    assert (png.stat().st_mode & 0o777) == (nc.stat().st_mode & 0o777)


def test_outputs_respect_the_umask(tmp_path, capsys):
    import os

    old = os.umask(0o022)
    try:
        png = tmp_path / "pm.png"
        status, out, _ = _run(capsys, *FAST, "--plot", str(png))
    finally:
        os.umask(old)
    assert status == 0 and out.rstrip().endswith(f"wrote {png}")
    assert (png.stat().st_mode & 0o777) == 0o644
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left behind


def test_help_example_with_a_shipped_file_runs_from_any_folder(tmp_path, monkeypatch, capsys):
    """`--file finals2000A.all` names the copy of astropy-iers-data when there is none in the working folder."""
    monkeypatch.chdir(tmp_path)
    status, out, err = _run(capsys, "--file", "finals2000A.all", *FAST, "--json")
    assert status == 0, err
    d = json.loads(out)
    assert d["source_file"].endswith("finals2000A.all") and d["start"] == "2000-01-01"


def test_table_shows_the_estimate_beside_the_model(capsys):
    status, out, _ = _run(capsys, *FAST)
    assert status == 0
    for word in (
        "least squares",
        "spectrum",
        "period [d]",
        "model: rigid",
        "model: anelastic",
        "Vicente & Wilson 1997",
        "Windows of 6 yr",
    ):
        assert word in out
    assert "wrote" not in out


def test_bad_plot_name_refused_before_the_work(tmp_path, capsys):
    status, out, err = _run(capsys, *FAST, "--plot", str(tmp_path / "pm.txt"))
    assert status == 2 and ".png, .pdf or .svg" in err and out == ""


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--start", "1900-01-01"], "start: got 1900-01-01; allowed: a date from 1962-01-01"),
        (["--end", "2999"], "end: got 2999"),
        (["--start", "2010", "--end", "2005"], "a date after start"),
        (["--start", "2000", "--end", "2012", "--window", "0.5"], "window: got 0.5 yr"),
        (["--start", "2000", "--end", "2012", "--window", "40"], "window: got 40 yr"),
        (["--window", "eight"], "--window: got eight"),
        (["--excitation-q", "lots"], "--excitation-q: got lots"),
        (
            ["--file", "/nonexistent/eop.txt"],
            "--file: got /nonexistent/eop.txt; allowed: an IERS C04 or finals2000A file (there is no such file)",
        ),
        (["--start", "2000-01-01", "--end", "2001-01-01"], "at least 732.5 d"),
        # 1e400 reads as inf: it was told "at least 1 d", which it is.
        (
            ["--step", "1e400"],
            "--step: got 1e400 yr; allowed: a finite time (not NaN, inf, or past the largest double of seconds, "
            "1.798e+308 s), at least 1 d (the sampling of the record)",
        ),
        (["--step", "0.001"], "--step: got 0.001 yr; allowed: at least 1 d (the sampling of the record)"),
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


def test_report_estimates_carry_two_significant_digits_of_their_uncertainty():
    """The amplitude column printed whole mas whatever its uncertainty: 173 +/- 8 for 8.13 (1980-2010)."""
    from astropy import units as u

    from wobble.cli._polar_motion_report import _pair

    assert _pair(173.24 * u.mas, 8.13 * u.mas) == ("173.2", "8.1")
    assert _pair(162.3 * u.mas, 10.4 * u.mas) == ("162", "10")
    assert _pair(432.6187 * u.day, 0.553 * u.day) == ("432.62", "0.55")
    assert _pair(122.0 * u.mas, None) == ("122.0", "-")
