"""The edges of the record's commands found by hand beside the fuzzer (seed 419 session): a start on the record's
last day, a two-year span whose Chandler and annual terms cannot be told apart, a one-day forecast's figure, a
horizon given in years. Each as the behaviour a user should meet."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
from astropy import units as u

import wobble
from cli_run import run_cli as _run
from wobble.errors import InputError

#: The last day of the C04 series shipped with astropy-iers-data that the tests run on.
LAST = "2026-09-29"


def _refused(argv, capsys, tmp_path, monkeypatch) -> str:
    """Run ``wobble ARGV`` in an empty folder; check the refusal's contract and return its message."""
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == "", (code, out, err)
    assert err.count("\n") == 1 and "Traceback" not in err and "Warning" not in err, err
    prefix = f"wobble {argv[0]}: error: "
    assert err.startswith(prefix), err
    return err[len(prefix) :].strip()


# -- F21: a start on (or near) the record's last day names --start ---------------------------------------------------


@pytest.mark.parametrize("command", ["polar-motion", "excitation"])
def test_a_start_on_the_last_day_names_start_and_the_last_day(command, capsys, tmp_path, monkeypatch):
    # Was: "--end: got None; allowed: a date after start (2026-09-29)": the option not typed, and Python's None.
    message = _refused([command, "--start", LAST], capsys, tmp_path, monkeypatch)
    assert message == (
        f"--start: got {LAST}; allowed: a date before {LAST}, the last day of the span of eopc04.1962-now"
    ), message
    assert "None" not in message


@pytest.mark.parametrize(
    ("command", "latest", "least"), [("polar-motion", "2024-09-26", "732.5 d"), ("excitation", "2024-09-27", "731.5 d")]
)
def test_a_start_too_near_the_end_is_told_the_latest_start_that_runs(
    command, latest, least, capsys, tmp_path, monkeypatch
):
    """A start a few days before the end (no --end) was refused as "--start/--end"; it is --start that is at fault,
    and the message gives the latest start, which runs (a day later is refused)."""
    message = _refused([command, "--start", "2026-09-20"], capsys, tmp_path, monkeypatch)
    assert message.startswith(f"--start: got 2026-09-20; allowed: a date on or before {latest}: "), message
    assert f"the span to the record's last day, {LAST}, must be at least {least}" in message
    day_after = str(np.datetime64(latest) + 1)
    assert _refused([command, "--start", day_after], capsys, tmp_path, monkeypatch).startswith("--start: ")
    code, out, err = _run([command, "--start", latest, "--json"], capsys)
    assert code == 0 and err == "", err


@pytest.mark.parametrize("command", ["polar-motion", "excitation"])
def test_an_end_alone_is_named_as_end(command, capsys, tmp_path, monkeypatch):
    assert _refused([command, "--end", "1962-01-01"], capsys, tmp_path, monkeypatch) == (
        "--end: got 1962-01-01; allowed: a date after 1962-01-01, the first day of the span of eopc04.1962-now"
    )
    message = _refused([command, "--end", "1963"], capsys, tmp_path, monkeypatch)
    assert message.startswith("--end: got 1963; allowed: a date on or after 1964-01-0"), message


def test_both_dates_given_still_name_both(capsys, tmp_path, monkeypatch):
    message = _refused(["polar-motion", "--start", "2020", "--end", "2021"], capsys, tmp_path, monkeypatch)
    assert message.startswith("--start/--end: got 2020-01-01 to 2021-01-01 (366 d); allowed: a span of at least")
    message = _refused(["polar-motion", "--start", "2020", "--end", "2019"], capsys, tmp_path, monkeypatch)
    assert message == "--end: got 2019; allowed: a date after start (2020-01-01)"


# -- --file that names no file: said so, naming --file, before any work ------------------------------------------------


@pytest.mark.parametrize("command", ["polar-motion", "excitation", "forecast"])
@pytest.mark.parametrize(
    ("typed", "why"),
    [(".", "it is a folder"), ("", "an empty path was given"), ("missing.txt", "there is no such file")],
)
def test_a_file_that_is_not_a_file_names_file_and_says_why(command, typed, why, capsys, tmp_path, monkeypatch):
    # Was: ".: no such file (the files of astropy-iers-data are found by name: ...)", of a folder, without --file.
    out = tmp_path / "out.nc"
    message = _refused([command, "--file", typed, "-o", str(out)], capsys, tmp_path, monkeypatch)
    assert message == (
        f"--file: got {typed or repr(typed)}; allowed: an IERS C04 or finals2000A file ({why}), "
        "or by name one of astropy-iers-data: eopc04.1962-now, finals2000A.all"
    ), message
    assert not out.exists()


# -- F24: a horizon in years is told its length in days ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("typed", "days", "whole"),
    [("3yr", "1095.75", "1095 d or 1096 d"), ("1yr", "365.25", "365 d or 366 d"), ("2yr", "730.5", "730 d or 731 d")],
)
def test_a_horizon_in_years_is_told_its_days_and_the_whole_days_beside_it(
    typed, days, whole, capsys, tmp_path, monkeypatch
):
    """'--horizon 3yr' was refused by a rule whose own words were "(three years)", without saying that 3 yr is
    1095.75 d: the lead times are whole days, and a Julian year is not."""
    message = _refused(["forecast", "--horizon", typed], capsys, tmp_path, monkeypatch)
    shown = typed.replace("yr", " yr")
    assert message == (
        f"--horizon: got {shown}; allowed: a whole number of days from 1 d to 1096 d (three years); the horizon "
        f"given is {days} d (a Julian year is 365.25 d), so give {whole}"
    ), message
    # What the message offers runs.
    code, out, err = _run(["forecast", "--horizon", whole.split(" or ")[1].replace(" ", ""), "--json"], capsys)
    assert code == 0 and err == "", err


def test_a_horizon_past_three_years_in_years_is_told_its_days_without_a_suggestion(capsys, tmp_path, monkeypatch):
    message = _refused(["forecast", "--horizon", "5yr"], capsys, tmp_path, monkeypatch)
    assert message.endswith("; the horizon given is 1826.25 d (a Julian year is 365.25 d)"), message
    assert _refused(["forecast", "--horizon", "36h"], capsys, tmp_path, monkeypatch).endswith(
        "; the horizon given is 1.5 d, so give 1 d or 2 d"
    )
    # In days, the rule alone (the value already says it in days).
    assert _refused(["forecast", "--horizon", "1097"], capsys, tmp_path, monkeypatch) == (
        "--horizon: got 1097 d; allowed: a whole number of days from 1 d to 1096 d (three years)"
    )


def test_a_calibration_span_in_years_runs_and_the_python_api_says_the_same(capsys):
    """A calibration span is a stretch of record (weekly past forecasts over it), not a count of lead days: 3 yr is
    a span like any other."""
    code, out, err = _run(["forecast", "--calibration-span", "3yr", "--horizon", "30", "--json"], capsys)
    assert code == 0 and err == "", err
    with pytest.raises(InputError, match=r"^horizon: got 3\.0 yr; .* the horizon given is 1095\.75 d"):
        wobble.forecast_polar_motion(horizon=3 * u.yr)
    with pytest.raises(InputError, match=r"^horizon: got 1\.0 yr; .* so give 365 d or 366 d"):
        wobble.hindcast_polar_motion(start="2019-01-01", end="2019-03-01", horizon=1 * u.yr)


# -- F22: the last two years, where the Chandler and annual terms cannot be told apart --------------------------------

LAST_TWO_YEARS = ["--start", "2024-09-26", "--end", LAST]


def test_the_last_two_years_say_no_chandler_term_is_resolved_in_text_and_json(capsys, tmp_path, monkeypatch):
    """Was: "least squares 365 +/- 76 d, 11907054 +/- 11906917 mas", an annual term of 11907109 mas, "differ by
    0.3 sigma (agree)", a caveat on the band's edge beside the 365 d, and a window row "nan +/- nan"."""
    monkeypatch.chdir(tmp_path)
    code, text, err = _run(["polar-motion", *LAST_TWO_YEARS], capsys)
    assert code == 0 and err == "", err
    rows = {line.split()[0]: line for line in text.splitlines() if line.startswith(("  least squares", "  spectrum "))}
    assert set(rows) == {"least", "spectrum"}
    assert all(line.rstrip().endswith("not resolved") for line in rows.values()), rows
    assert "the two methods are not compared: neither method resolves a Chandler term in this span" in text
    assert "(agree)" not in text and "DISAGREE" not in text and "nan" not in text
    assert "(prograde not separable from the Chandler term)" in text
    assert "2025-09-27  no Chandler term resolved" in text

    code, out, err = _run(["polar-motion", *LAST_TWO_YEARS, "--json"], capsys)
    d = json.loads(out)
    assert 390 <= d["chandler_period_days"] <= 500  # inside the search band it states (365.24 d before)
    assert d["chandler_amplitude_mas"] < 1000 and d["annual_prograde_amplitude_mas"] < 1000
    assert d["chandler_resolved"] is False and d["estimates"]["spectrum"]["chandler_resolved"] is False
    assert d["methods_agree"] is None and d["agreement_sigma"] is None
    assert [r["residual_days"] for r in d["comparison"]] == [None] * len(d["comparison"])
    caveats = " ".join(d["caveats"])
    assert "cannot be told from the annual terms" in caveats and "the spectral peak lies at the edge" in caveats


def test_the_whole_record_is_resolved_and_compared_as_before(capsys):
    code, out, err = _run(["polar-motion", "--json", "--excitation-q", "none", "--no-q"], capsys)
    d = json.loads(out)
    assert d["chandler_resolved"] is True and d["methods_agree"] is True and d["agreement_sigma"] < 2
    assert all(r["residual_days"] is not None for r in d["comparison"][1:])


@pytest.mark.parametrize(
    ("typed", "shown", "why"),
    [
        ("", "''", "an empty path was given"),
        (".", ".", "it is a folder"),
        (os.devnull, os.devnull, "it is not a regular file"),
    ],
)
def test_the_python_reader_says_why_a_path_is_not_a_file(typed, shown, why):
    """read_pole_file as the command line: "" read ".: it is a folder" (resolve_eop_path makes it Path(".")), and a
    device such as /dev/null "there is no such file"."""
    from wobble.errors import FileFormatError
    from wobble.io.eop import read_pole_file

    with pytest.raises(FileFormatError) as info:
        read_pole_file(typed)
    assert str(info.value).startswith(f"{shown}: {why} (")
