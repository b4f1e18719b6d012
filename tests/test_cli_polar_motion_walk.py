"""What a fresh-user walk through `wobble excitation`, `wobble forecast` and `wobble polar-motion` found,
each as a test of the behaviour a user should meet: periods the analysis cannot use refused (not NaN
and NumPy warnings), bare numbers whose unit each option's help states and errors show, options named
as typed, the Q caveats in the text, the span of the forecast's Chandler period, and values to the
digits of their uncertainty."""

from __future__ import annotations

import argparse
import json
import re

import numpy as np
import pytest
from astropy import units as u

import wobble
from cli_run import run_cli as _run
from wobble.cli import build_parser
from wobble.errors import InputError

OUTPUTS = ["-o", "out.nc", "--plot", "out.png"]


def _refused(argv, capsys, tmp_path, monkeypatch):
    """Run ``wobble ARGV -o out.nc --plot out.png`` in an empty folder; check the refusal's contract and
    return its message (after "error: ")."""
    monkeypatch.chdir(tmp_path)
    code, out, err = _run([*argv, *OUTPUTS], capsys)
    assert code == 2 and out == "", (code, out, err)
    assert err.count("\n") == 1 and "Traceback" not in err and "Warning" not in err, err
    assert list(tmp_path.iterdir()) == []  # nothing written
    prefix = f"wobble {argv[0]}: error: "
    assert err.startswith(prefix), err
    message = err[len(prefix) :].strip()
    # The parameter is named as the user typed it on the command line, never by its Python name.
    assert message.split(":")[0].startswith("--"), message
    return message


def _parser(command: str) -> argparse.ArgumentParser:
    return next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)).choices[command]


def _help(command: str) -> dict[str, str]:
    """Each option's help text of ``wobble COMMAND`` (argparse's own, before line wrapping)."""
    return {s: a.help for a in _parser(command)._actions for s in a.option_strings}


# -- 1. periods the daily record and the analysis cannot use -------------------------------------------


@pytest.mark.parametrize(
    ("period", "shown"),
    [
        ("433 s", "433 s"),  # was: exit 0, "pole nanx, excitation nanx" and RuntimeWarnings
        ("1 d", "1 d"),
        ("135", "135 d"),  # a bare number is days
        ("1218", "1218 d"),
        ("10yr", "10 yr"),
        ("-4yr", "-4 yr"),
        ("nan", "nan d"),
    ],
)
def test_excitation_refuses_periods_outside_what_the_analysis_supports(period, shown, capsys, tmp_path, monkeypatch):
    message = _refused(["excitation", "--period", period], capsys, tmp_path, monkeypatch)
    assert message.startswith(f"--period: got {shown}; allowed: a Chandler period from 136 d to 1217 d"), message
    assert "0.3 to 2.7 cycles per year" in message


@pytest.mark.parametrize("period", ["136", "1217d"])
def test_excitation_at_the_edges_of_the_period_range_is_finite_and_quiet(period, capsys):
    # Two years of record (the shortest allowed: the coarsest spectrum) at either end of the range.
    # Warnings are errors in the tests: NumPy's "Mean of empty slice" would fail this.
    code, out, err = _run(
        ["excitation", "--start", "2020", "--end", "2022-01-02", "--period", period, "--json"], capsys
    )
    assert code == 0 and err == "", err
    d = json.loads(out)
    assert d["chandler_period_source"] == "given"
    peaks = d["chandler_peak_over_neighbours"]
    assert peaks["pole"] is not None and peaks["excitation"] is not None  # NaN would be null


def test_the_python_api_names_its_parameters():
    with pytest.raises(InputError, match=r"^chandler_period: got 433\.0 s; allowed: a Chandler period from 136 d"):
        wobble.geodetic_excitation(chandler_period=433 * u.s)
    with pytest.raises(InputError, match=r"^q: got 0\.5; allowed: a quality factor Q >= 1"):
        wobble.geodetic_excitation(q=0.5)
    with pytest.raises(InputError, match=r"^start/end: got 2020-01-01 to 2020-01-10 \(9 d\); allowed: a span of at"):
        wobble.geodetic_excitation(start="2020-01-01", end="2020-01-10")
    with pytest.raises(InputError, match=r"^latency: got 1\.5 d; allowed: a whole number of days"):
        wobble.forecast_polar_motion(latency=1.5 * u.day)


@pytest.mark.parametrize("command", ["excitation", "forecast"])
# -inf, -Infinity and -nan reach the option's own check (argparse took them for options: "argument --q: expected one
# argument"), as -1 and -1e3 do.
@pytest.mark.parametrize("q", ["0.5", "0", "-1", "-1e3", "nan", "-nan", "-inf", "-Infinity", "lots"])
def test_q_below_one_is_refused(command, q, capsys, tmp_path, monkeypatch):
    message = _refused([command, "--q", q], capsys, tmp_path, monkeypatch)
    assert message.startswith(f"--q: got {q}; allowed: a quality factor Q >= 1"), message


def test_excitation_span_too_short_names_start_and_end(capsys, tmp_path, monkeypatch):
    # Was: "series: got a span of 9 d" (the spectra's internal name).
    message = _refused(["excitation", "--start", "2020-01-01", "--end", "2020-01-10"], capsys, tmp_path, monkeypatch)
    assert message == (
        "--start/--end: got 2020-01-01 to 2020-01-10 (9 d); allowed: a span of at least 731.5 d: two Julian years "
        "(730.5 d) of excitation, which begins a sample after the pole, for the spectra and the Chandler peak"
    )


@pytest.mark.parametrize(("command", "shortest"), [("excitation", "731.5 d"), ("polar-motion", "732.5 d")])
def test_the_least_span_stated_is_the_one_that_runs(capsys, tmp_path, monkeypatch, command, shortest):
    """The spans told "at least 730 d" (730.5 rounded) and accepted 731 d, which the spectrum (excitation: 'series:
    got a span of 730 d') or the window (polar-motion) then refused: the span a day short of the stated least is
    refused naming --start/--end, the span a day past it runs."""
    days = float(shortest.split()[0])
    short_end = "2020-01-02" if command == "excitation" else "2020-01-03"  # 731 d and 732 d after 2018-01-01
    message = _refused([command, "--start", "2018-01-01", "--end", short_end], capsys, tmp_path, monkeypatch)
    assert message.startswith("--start/--end: got 2018-01-01 to ") and f"at least {shortest}" in message
    monkeypatch.chdir(tmp_path)
    end = np.datetime64("2018-01-01") + np.timedelta64(int(days) + 1, "D")
    code, out, err = _run([command, "--start", "2018-01-01", "--end", str(end), "--json"], capsys)
    assert code == 0, err
    if command == "polar-motion":  # its default window (8 yr) is the span instead, and says so
        assert any("the default window of 8 yr is longer than the span" in c for c in json.loads(out)["caveats"])


# -- 2. bare numbers: each option's help says their unit, and errors show the unit meant ----------------


@pytest.mark.parametrize(
    ("command", "option", "unit"),
    [
        ("excitation", "--period", "days"),
        ("forecast", "--horizon", "days"),
        ("forecast", "--latency", "days"),
        ("forecast", "--calibration-span", "days"),
        ("forecast", "--every", "days"),
        ("polar-motion", "--window", "years"),
        ("polar-motion", "--step", "years"),
    ],
)
def test_help_says_what_a_bare_number_means(command, option, unit):
    assert f"a bare number is {unit}" in _help(command)[option]


@pytest.mark.parametrize(
    ("argv", "start"),
    [
        # Was "got 3.0 d" beside a default written "2yr", with no word that a bare 3 is days.
        (
            ["forecast", "--calibration-span", "3"],
            "--calibration-span: got 3 d; allowed: a span from 26 weeks (182 d",
        ),
        (["forecast", "--calibration-span", "0.1yr"], "--calibration-span: got 0.1 yr; allowed: a span from 26 weeks"),
        (
            ["forecast", "--horizon", "5yr"],
            "--horizon: got 5 yr; allowed: a whole number of days from 1 d to 1096 d",
        ),  # was 1826.25 d
        (["forecast", "--horizon", "-5d"], "--horizon: got -5 d; allowed:"),
        (["forecast", "--latency", "1.5"], "--latency: got 1.5 d; allowed: a whole number of days from 0 d to 365 d"),
        (["forecast", "--latency", "1yr"], "--latency: got 1 yr; allowed: a whole number of days"),  # was "data: ..."
        (["forecast", "--issued", "2019.5"], "--issued: got 2019.5 (2019-07-02 12:00 UTC); allowed: a day"),
        (["polar-motion", "--window", "1"], "--window: got 1 yr; allowed: a length from 2.005 yr"),
        (["polar-motion", "--window", "10m"], "--window: got 10m; allowed: a time such as"),
        (["polar-motion", "--step", "0.001"], "--step: got 0.001 yr; allowed: at least 1 d"),  # was 64,000 windows
        (["polar-motion", "--step", "12h"], "--step: got 12 h; allowed: at least 1 d"),
        (["polar-motion", "--start", "2020", "--end", "2022-06", "--window", "8"], "--window: got 8 yr; allowed:"),
    ],
)
def test_errors_show_the_value_in_the_unit_meant(argv, start, capsys, tmp_path, monkeypatch):
    message = _refused(argv, capsys, tmp_path, monkeypatch)
    assert message.startswith(start), message


def test_a_window_with_a_unit_is_read():
    # --window and --step take a unit as the other options do (a bare number stays years).
    from wobble.cli.excitation import parse_time

    read = parse_time("2920d", "--window", "yr")
    assert read.quantity.to_value(u.yr) == pytest.approx(8.0 * 365 / 365.25) and read.shown == "2920 d"
    assert parse_time("8", "--window", "yr").quantity == 8 * u.yr


# -- 6. errors name the option typed, not the Python parameter ------------------------------------------


@pytest.mark.parametrize(
    ("argv", "start"),
    [
        (["forecast", "--hindcast", "1962-06-01:1963-01-01"], "--hindcast START: got 1962-06-01; allowed:"),
        (["forecast", "--hindcast", "2030-01-01:2031-01-01"], "--hindcast END: got 2031-01-01; allowed:"),
        (["forecast", "--hindcast", "2019.5:2020"], "--hindcast START: got 2019.5; allowed: a day"),
        (
            ["forecast", "--hindcast", "2019-01-01:2019-03-01", "--every", "7.5"],
            "--every: got 7.5 d; allowed: a whole number of days",
        ),
        (["forecast", "--issued", "1975-01-01", "--calibration-span", "5yr"], "--calibration-span: got 5 yr; allowed:"),
        (["forecast", "--every", "14"], "--every: got 14; allowed: only with --hindcast"),  # was silently ignored
        (["forecast", "--q", "50", "--method", "ls_ar"], "--q: got 50; allowed: no --q with --method ls_ar"),
        (["polar-motion", "--drift-degree", "9"], "--drift-degree: got 9; allowed: an integer from 0"),
        (["polar-motion", "--start", "2020", "--end", "2021"], "--start/--end: got 2020-01-01 to 2021-01-01 (366 d);"),
        (
            ["polar-motion", "--excitation-q", "0.5"],
            "--excitation-q: got 0.5; allowed: a finite quality factor above 1",
        ),
    ],
)
def test_errors_name_the_option_typed(argv, start, capsys, tmp_path, monkeypatch):
    message = _refused(argv, capsys, tmp_path, monkeypatch)
    assert message.startswith(start), message
    assert "or None" not in message  # the command line's word is 'none'


def test_the_highest_drift_degree_runs(capsys):
    # Was: "--drift-degree: got 7" for --drift-degree 6 (the model check tried one degree more).
    code, out, err = _run(
        ["polar-motion", "--start", "2000", "--end", "2010", "--drift-degree", "6", "--excitation-q", "none", "--no-q"],
        capsys,
    )
    assert code == 0 and err == "", err


# -- 3. Q's caveats are in the text that points to them ---------------------------------------------------


def test_polar_motion_text_prints_the_q_caveats(capsys):
    code, out, err = _run(["polar-motion", "--start", "1990", "--end", "2015", "--excitation-q", "none"], capsys)
    assert code == 0 and err == "", err
    lines = out.splitlines()
    (k,) = [i for i, line in enumerate(lines) if line.startswith("  Q (line shape")]
    assert "see caveats" not in out
    assert lines[k].startswith("  Q (line shape; caveats below): ML ")
    assert lines[k + 1].startswith("    - assumes a flat excitation spectrum near the Chandler frequency")


# -- 4. the span of the Chandler period is said ------------------------------------------------------------


def test_forecast_says_where_its_chandler_period_comes_from(capsys):
    code, out, err = _run(["forecast", "--horizon", "100", "--latency", "1"], capsys)
    assert code == 0 and err == "", err
    head, period_line = out.splitlines()[:2]
    last_data = re.search(r"data to (\d{4}-\d\d-\d\d)", head)[1]
    m = re.fullmatch(
        r"  Chandler period 4\d\d\.\d d \(least squares of the 30 years of record (\d{4}-\d\d-\d\d) to (\S+)\)",
        period_line,
    )
    assert m and m[2] == last_data and int(m[1][:4]) == int(last_data[:4]) - 30, period_line
    assert "by least squares in the 30 years of record before the issue date" in " ".join(
        _parser("forecast").epilog.split()
    )


def test_forecast_json_gives_the_span_or_none_when_given():
    f = wobble.forecast_polar_motion(issued="2019-01-01", horizon=5 * u.day, latency=1 * u.day, calibrated=False)
    assert f.to_dict()["chandler_period_span"] == ["1988-12-31", "2018-12-31"]
    g = wobble.forecast_polar_motion(
        issued="2019-01-01", horizon=5 * u.day, latency=1 * u.day, calibrated=False, chandler_period=433 * u.day
    )
    assert g.to_dict()["chandler_period_span"] is None and "Chandler period 433.0 d (given)" in g.summary()


def test_excitation_of_a_part_says_its_period_is_the_whole_records(capsys):
    code, out, err = _run(["excitation", "--start", "1990-01-01", "--end", "2019-12-31"], capsys)
    assert code == 0 and err == "", err
    assert re.search(
        r"T_c = 43\d\.\d d \(least squares of the whole record, 1962-01-01 to \d{4}-\d\d-\d\d\), Q = 81\.6", out
    ), out
    assert "also for a part of it chosen by --start/--end" in _help("excitation")["--period"]


# -- 5. digits matched to the uncertainty --------------------------------------------------------------------


def test_forecast_values_carry_the_digits_of_their_uncertainty(capsys):
    # Was "142.00 +/- 9.41": now the +/- to two significant digits and the value to the same place.
    code, out, err = _run(["forecast", "--horizon", "100"], capsys)
    assert code == 0 and err == "", err
    pairs = re.findall(r"(-?\d+(?:\.(\d+))?) \+/- (\d+(?:\.(\d+))?)", out)
    assert len(pairs) == 12  # 6 lead times, x_p and y_p
    for value, value_decimals, sigma, sigma_decimals in pairs:
        assert len(value_decimals) == len(sigma_decimals), (value, sigma)
        assert len(sigma.replace(".", "").lstrip("0")) == 2, sigma  # two significant digits


def test_a_horizon_is_whole_days_and_no_calibration_takes_no_span(capsys):
    # Was: --horizon 36h and 1.5 silently forecast 1 d; --no-calibration --calibration-span 3yr ignored the span.
    for text in ("36h", "1.5"):
        code, out, err = _run(["forecast", "--horizon", text], capsys)
        assert code == 2 and "allowed: a whole number of days from 1 d to 1096 d" in err
    code, out, err = _run(["forecast", "--no-calibration", "--calibration-span", "3yr"], capsys)
    assert code == 2 and err == (
        "wobble forecast: error: --calibration-span: got 3yr; allowed: no span with --no-calibration "
        "(it calibrates nothing)\n"
    )


def test_an_issue_date_too_early_names_the_first_usable_day(capsys):
    # Was: "a date from 1962-01-01 ..." although no date before 1972-02-01 could be issued (Kalman).
    # Then: 1972-02-01 was named although a calibrated forecast could not be issued before 1975-02-24 (its past
    # forecasts reach 1120 d further back); the first day named is now the first that works (since the Kalman
    # calibration's six years, 1979-02-26: 2583 d of past forecasts).
    code, out, err = _run(["forecast", "--issued", "1900-01-01", "--no-calibration"], capsys)
    assert code == 2 and "allowed: a date from 1972-02-01 to " in err and "for Kalman" in err
    code, out, err = _run(["forecast", "--issued", "1900-01-01"], capsys)
    assert code == 2 and "allowed: a date from 1979-02-26 to " in err and "2583 d of past forecasts" in err
    code, out, err = _run(["forecast", "--issued", "1965-01-01", "--method", "ls_ar", "--no-calibration"], capsys)
    assert code == 2 and "allowed: a date from 1968-02-01 to " in err and "for LS+AR" in err
    code, out, err = _run(["forecast", "--issued", "1965-01-01", "--method", "ls_ar"], capsys)
    assert code == 2 and "allowed: a date from 1971-02-24 to " in err and "for LS+AR" in err
