"""wobble.forecast_polar_motion, hindcasts and `wobble forecast`: JSON, CF netCDF, bad input with exit 2 and
nothing written."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr
from astropy import units as u

import wobble
from wobble.cli import main
from wobble.errors import InputError
from wobble.io.netcdf import open_wobble, write_netcdf


@pytest.fixture(scope="module")
def forecast():
    return wobble.forecast_polar_motion(issued="2018-03-01", horizon=60 * u.day, method="ls_ar", latency=1 * u.day)


def test_json_layout(forecast):
    d = forecast.to_dict()
    assert (d["issued"], d["horizon_days"], d["method"], d["latency_days"]) == ("2018-03-01", 60, "ls_ar", 1.0)
    assert d["last_data"] == "2018-02-28"
    first = d["forecast"][0]
    assert set(first) >= {"lead_days", "x_mas", "y_mas", "x_68_mas", "y_68_mas", "x_95_mas", "y_95_mas"}
    assert [r["lead_days"] for r in d["forecast"]] == list(range(1, 61))
    for r in d["forecast"]:
        assert r["x_95_mas"][0] < r["x_68_mas"][0] < r["x_mas"] < r["x_68_mas"][1] < r["x_95_mas"][1]
    # The pole moves a few mas a day: the first day's forecast is within 5 mas of the record.
    obs = wobble.load_polar_motion(start="2018-03-02", end="2018-03-03")
    assert abs(first["x_mas"] - float(obs["x_p"][0])) < 5  # the record in mas, as the forecast
    # Calibrated on 104 weekly past forecasts per lead (two years), issued up to a week before,
    # scored on outcomes up to the last day of data.
    cal = d["calibration"]
    assert cal["past_forecasts_per_lead"] == 104 and cal["step_days"] == 7
    assert (cal["last_issue"], cal["last_outcome"]) == ("2018-02-22", "2018-02-28")
    assert cal["first_issue"] == "2016-01-07"  # 104 + ceil(61 / 7) - 1 = 112 weeks (784 d) before
    assert "split-conformal" in d["intervals"]


def test_a_file_and_its_dataset_give_the_same_forecast(forecast):
    """The shipped record read into plain arrays (what the JSON uses, without xarray) and the same record
    as the Dataset of load_polar_motion give the same forecast, to the bit; so does the default latency
    (C04: 30 d), which the file's kind decides."""
    given = wobble.forecast_polar_motion(
        wobble.load_polar_motion(), issued="2018-03-01", horizon=60 * u.day, method="ls_ar", latency=1 * u.day
    )
    assert given.to_dict() == forecast.to_dict()
    a = wobble.forecast_polar_motion(issued="2018-03-01", horizon=5 * u.day, method="kalman", calibrated=False)
    b = wobble.forecast_polar_motion(
        wobble.load_polar_motion(), issued="2018-03-01", horizon=5 * u.day, method="kalman", calibrated=False
    )
    assert a.to_dict() == b.to_dict() and a.to_dict()["latency_days"] == 30.0
    # details.q repeated the top-level quality_factor (and q is Omega^2 a^3/(GM) in modes): an alias now.
    assert a.to_dict()["details"]["q"] == a.to_dict()["quality_factor"] == a.q
    assert a.to_dict()["deprecated_keys"] == {"details.q": "quality_factor"}
    # The fitted noise names the excitation's order and its partial autocorrelations, the first being
    # exp(-1 d / lag-one correlation time).
    noise = a.to_dict()["details"]["noise"]
    r = noise["excitation_partial_autocorrelations"]
    assert noise["excitation_order"] == len(r) == 3 and all(-1 < v < 1 for v in r)
    assert r[0] == pytest.approx(math.exp(-1.0 / noise["correlation_time_days"]), rel=1e-12)


def test_a_forecast_from_the_record_s_first_decade_runs():
    """Issued 1976-01-01 (latency 30 d), the ten-year fit reads 1965-1975, where the filter's mean-pole
    modes sit on the unit circle to rounding (1 + 5e-10): once refused as unstable, which escaped as a
    traceback from the command line. (A one-year calibration span: the default six years of past forecasts
    would reach before the record's first ten years.)"""
    f = wobble.forecast_polar_motion(
        issued="1976-01-01", horizon=90 * u.day, method="kalman", calibration_span=1 * u.yr
    )
    d = f.to_dict()
    assert d["last_data"] == "1975-12-02" and len(d["forecast"]) == 90
    assert all(np.isfinite([r["x_mas"], r["y_mas"], *r["x_68_mas"], *r["y_95_mas"]]).all() for r in d["forecast"])


def test_netcdf_round_trip_and_cf(forecast, tmp_path, assert_cf_compliant):
    ds = forecast.to_dataset()
    assert ds["lead_time"].attrs["standard_name"] == "forecast_period"
    assert ds["forecast_reference_time"].attrs["standard_name"] == "forecast_reference_time"
    assert ds["x_p_bounds_68"].dims == ("lead", "bounds")
    assert ds.attrs["forecast_method"] == forecast.method  # not only in the title
    assert ds.attrs["interval_calibration"] == "past_errors" and ds.attrs["calibration_past_forecasts_per_lead"] == 104
    path = write_netcdf(ds, tmp_path / "f.nc", command="test")
    back = open_wobble(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert_cf_compliant(path)


def test_small_hindcast_scores_and_file(tmp_path, assert_cf_compliant, capsys):
    h = wobble.hindcast_polar_motion(
        start="2019-01-01",
        end="2019-02-01",
        every=14 * u.day,
        horizon=30 * u.day,
        latency=1 * u.day,
        workers=1,
        calibration_span=1 * u.yr,
        progress=True,
    )
    assert "100.0% 3/3 issue dates" in capsys.readouterr().err
    d = h.to_dict()
    assert d["issues"] == 3 and set(d["methods"]) == {"ls_ar", "kalman"}
    for m in ("ls_ar", "kalman"):
        rms = d["methods"][m]["rms_2d_mas"]
        assert 0 < rms["1"] < rms["30"] < 100  # mas: errors grow with lead time
        assert 0 <= d["methods"][m]["coverage_68_fraction"]["10"] <= 1
        assert d["methods"][m]["rms_2d"] == rms  # the old name, for one release
    assert d["deprecated_keys"]["methods.*.rms_2d"] == "methods.*.rms_2d_mas"
    assert d["quality_factor"] is not None  # the Kalman model's Q (null when only LS+AR runs)
    assert d["anchors"][0]["values_mas"]["10"] == 2.32
    text = h.summary()  # leads beyond the 30-day horizon are left out
    assert "10 d" in text and "40 d" not in text and "Dill et al. 2023" in text
    row = next(line for line in text.splitlines() if line.strip().startswith("kalman 68 % interval coverage [%]"))
    assert row.split()[-1] == f"{100 * d['methods']['kalman']['coverage_68']['10']:.1f}"  # per cent, as the docs
    path = write_netcdf(h.to_dataset(), tmp_path / "h.nc", command="test")
    back = open_wobble(path)
    assert back["rms_2d"].dims == ("method", "lead") and back["x_p_forecast"].shape == (2, 3, 30)
    # Each forecast's valid time (MJD), as the forecast file's "time": issue time plus lead time.
    assert back["time"].dims == ("issue", "lead") and back["time"].attrs["standard_name"] == "time"
    np.testing.assert_array_equal(back["time"].values, back["issue_time"].values[:, None] + np.arange(1, 31))
    assert_cf_compliant(path)
    k = list(back["method"].values).index("kalman")
    np.testing.assert_allclose(back["rms_2d"].values[k, 9], d["methods"]["kalman"]["rms_2d_mas"]["10"], rtol=1e-12)
    # The coverage in the file is the fraction of outcomes inside the half-widths in the file.
    inside = (np.abs(back["x_p_forecast"] - back["x_p_observed"]) <= back["x_p_half_width_68"]).values.astype(float)
    inside += (np.abs(back["y_p_forecast"] - back["y_p_observed"]) <= back["y_p_half_width_68"]).values
    np.testing.assert_allclose(inside.mean(axis=1) / 2, back["coverage_68"].values, rtol=1e-12)
    # The outcomes are the record's own numbers (the files' decimals in mas, not an ulp off through radians).
    record = wobble.load_polar_motion(start="2019-01-02", end="2019-02-01")["x_p"]
    first = back["x_p_observed"].isel(issue=0).values
    np.testing.assert_array_equal(first, record.values[: first.size])
    # The hindcast scores the public forecast: its first issue (where the period and noise are
    # estimated, as a single forecast estimates them) is wobble.forecast_polar_motion's.
    f = wobble.forecast_polar_motion(
        issued="2019-01-01", horizon=30 * u.day, latency=1 * u.day, calibration_span=1 * u.yr
    )
    np.testing.assert_allclose(h.forecasts[0][k].mean, f.raw.mean, rtol=1e-12)
    np.testing.assert_allclose(h.forecasts[0][k].half_widths(95)[1], f.raw.half_widths(95)[1], rtol=1e-12)


def test_each_method_calibrates_on_its_own_span_by_default(tmp_path):
    """Six years of past forecasts for the Kalman model, two for LS+AR (chosen on 2006-2015,
    scripts/calibration_span.py); a hindcast with the default spans scores exactly the public forecasts."""
    k = wobble.forecast_polar_motion(issued="2018-03-01", horizon=10 * u.day, latency=1 * u.day).to_dict()
    cal = k["calibration"]
    # round(6 x 365.25 / 7) = 313 weekly forecasts per lead; the 10-day lead's newest is ceil(11 / 7) = 2 weeks
    # back, so the oldest is 2 + 313 - 1 = 314 weeks (2198 d) before 2018-03-01 (by hand).
    assert cal["past_forecasts_per_lead"] == 313 and cal["span_days"] == 6 * 365.25
    assert (cal["first_issue"], cal["last_issue"]) == ("2012-02-23", "2018-02-22")
    h = wobble.hindcast_polar_motion(
        start="2018-03-01", end="2018-03-02", horizon=10 * u.day, latency=1 * u.day, workers=1
    )
    d = h.to_dict()
    assert d["calibration_span_days"] == {"ls_ar": 730.5, "kalman": 2191.5}
    assert "issued weekly over the 2 yr (ls_ar) or 6 yr (kalman) before it" in d["intervals"]
    for j, m in enumerate(h.methods):
        f = wobble.forecast_polar_motion(issued="2018-03-01", horizon=10 * u.day, latency=1 * u.day, method=m)
        assert f.to_dict()["calibration"]["span_days"] == d["calibration_span_days"][m]
        np.testing.assert_allclose(h.forecasts[0][j].mean, f.raw.mean, rtol=1e-12)
        np.testing.assert_allclose(h.forecasts[0][j].half_widths(68)[0], f.raw.half_widths(68)[0], rtol=1e-12)
    ds = h.to_dataset()
    assert (ds.attrs["calibration_span_days_kalman"], ds.attrs["calibration_span_days_ls_ar"]) == (2191.5, 730.5)
    # LS+AR has no Q: a hindcast of it alone said Q = 81.6 where its forecast says null.
    alone = wobble.hindcast_polar_motion(
        start="2018-03-01", end="2018-03-02", horizon=10 * u.day, latency=1 * u.day, workers=1, methods=("ls_ar",)
    )
    assert alone.to_dict()["quality_factor"] is None and d["quality_factor"] == h.q


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"issued": "1950-01-01"}, "issued: got 1950-01-01"),
        ({"issued": "2099-01-01"}, "issued: got 2099-01-01"),
        ({"issued": "1965-01-01"}, "fitting span"),
        ({"horizon": 0 * u.day}, "horizon: got 0 d"),
        ({"horizon": 10 * u.yr}, "horizon: got"),
        ({"horizon": 30}, "horizon"),
        ({"method": "arima"}, "method: got arima"),
        ({"q": 0.0}, "q: got 0.0"),
        (
            {"issued": "1975-01-01", "calibration_span": 5 * u.yr},
            r"calibration_span: got 5 yr; allowed: at most 1\.\d\d yr",
        ),
        ({"issued": "1973-06-01"}, r"issued: got 1973-06-01; allowed: a date from 1979-02-26 .* uncalibrated"),
        ({"issued": "1973-06-01", "calibration_span": 2 * u.yr}, "calibration_span: got 2 yr; allowed: a later issue"),
        ({"calibration_span": 10 * u.day}, r"calibration_span: got 10.0 d; allowed: a span from 26 weeks \(182 d"),
        ({"calibration_span": 2.0}, "calibration_span"),
    ],
)
def test_bad_input(kwargs, fragment):
    with pytest.raises(InputError, match=fragment):
        wobble.forecast_polar_motion(**kwargs)


@pytest.mark.parametrize("function", [wobble.forecast_polar_motion, wobble.geodetic_excitation])
def test_a_record_given_twice_is_refused(function):
    """data and file together: the file was silently ignored (a forecast from C04 data given with a finals
    file took C04's 30-day latency)."""
    data = wobble.load_polar_motion(start="2000-01-01", end="2010-01-01")
    with pytest.raises(InputError, match=r"file: got finals2000A\.all; allowed: either data or file, not both"):
        function(data, file="finals2000A.all")


def test_the_first_issue_date_named_for_a_calibrated_forecast_is_the_first_that_works():
    """Kalman, 365 d, C04 latency 30 d: the record's start 1962-01-01 (MJD 37665) + the 3652.5-d fitting span
    + 30 d + the calibration's reach (round(6 x 365.25 / 7) = 313 weekly past forecasts behind the
    ceil(395 / 7) = 57 weeks of horizon and latency: 369 weeks, 2583 d), less half a day, is MJD 43930,
    1979-02-26 (by hand). LS+AR: its
    6-year fitting span (2191.5 d) and two years of past forecasts (160 weeks, 1120 d): MJD 41006, 1971-02-24."""
    with pytest.raises(InputError, match="issued: got 1979-02-25; allowed: a date from 1979-02-26"):
        wobble.forecast_polar_motion(issued="1979-02-25")
    assert wobble.forecast_polar_motion(issued="1979-02-26").to_dict()["issued"] == "1979-02-26"
    with pytest.raises(InputError, match="issued: got 1971-02-23; allowed: a date from 1971-02-24"):
        wobble.forecast_polar_motion(issued="1971-02-23", method="ls_ar")
    assert wobble.forecast_polar_motion(issued="1971-02-24", method="ls_ar").to_dict()["issued"] == "1971-02-24"


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--issued", "1950-01-01"], "issued: got 1950-01-01"),
        (["--issued", "1966-01-01"], "fitting span"),
        (["--horizon", "0"], "--horizon: got 0 d"),
        (["--horizon", "20yr"], "horizon: got"),
        (["--method", "arima"], "--method: got arima"),
        (["--q", "0"], "--q: got 0"),
        (["--hindcast", "1970-01-01:1971-01-01"], "--hindcast START: got 1970-01-01"),
        (["--hindcast", "2016-01-01"], "--hindcast: got 2016-01-01"),
        (["--issued", "1975-01-01", "--calibration-span", "5yr"], "--calibration-span: got 5 yr; allowed: at most"),
        (["--calibration-span", "3"], "--calibration-span: got 3 d"),
        (["--calibration-span", "two years"], "--calibration-span: got two years"),
        (["--hindcast", "1975-01-01:1975-03-01"], "the calibration's past forecasts"),
    ],
)
def test_cli_bad_input_exit_2_nothing_written(args, fragment, tmp_path, capsys):
    out_file = tmp_path / "f.nc"
    status = main(["forecast", *args, "-o", str(out_file)])
    out, err = capsys.readouterr()
    assert status == 2 and fragment in err and err.count("\n") == 1 and err.startswith("wobble forecast: error: ")
    assert not out_file.exists() and out == ""


def test_cli_json(tmp_path, capsys):
    png = tmp_path / "f.png"
    status = main(
        ["forecast", "--issued", "2020-06-01", "--horizon", "30d", "--latency", "1d", "--json", "--plot", str(png)]
    )
    out, err = capsys.readouterr()
    d = json.loads(out)
    assert status == 0 and d["method"] == "kalman" and d["horizon_days"] == 30 and d["latency_days"] == 1
    assert err == f"wrote {png}\n" and png.read_bytes()[:4] == b"\x89PNG"


def test_a_record_too_short_for_the_default_calibration_says_it_was_the_default(tmp_path, capsys):
    """Fifteen years of C04: a calibrated Kalman forecast at the record's end needs 17 (10 of fit, 6 of past
    forecasts, the horizon). The message names the span as the default, which the user did not type, and
    how long a span this record allows; with that span the forecast runs."""
    from wobble.io.eop import default_c04_path

    lines = default_c04_path().read_text().splitlines()
    head = [x for x in lines if x.startswith("#")]
    data = [x for x in lines if x.strip() and not x.startswith("#")]
    path = tmp_path / "c04_15yr.txt"
    path.write_text("\n".join(head + data[-int(15 * 365.25) :]) + "\n")
    assert main(["forecast", "--file", str(path), "-o", str(tmp_path / "f.nc")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(
        "wobble forecast: error: --calibration-span: got 6 yr (the Kalman default); allowed: at most 3."
    )
    assert "\n" not in err and not (tmp_path / "f.nc").exists()
    most = float(err.split("at most ")[1].split()[0])
    assert main(["forecast", "--file", str(path), "--calibration-span", f"{most}yr", "--json"]) == 0


def test_the_text_says_when_the_issue_date_is_the_default_one_in_the_past():
    """With no issue date the forecast is issued at the record's end plus its latency, a month before today for
    the C04 series; 'wobble forecast --horizon 90d' read as 90 days from today."""
    default = wobble.forecast_polar_motion(horizon=10 * u.day, calibrated=False)
    given = wobble.forecast_polar_motion(issued="2020-01-01", horizon=10 * u.day, calibrated=False)
    assert default.issued_by_default and not given.issued_by_default
    assert "by default issued at the data's end plus the latency, not today" in default.summary().splitlines()[0]
    assert given.summary().splitlines()[0].endswith("(latency 30 d)")


def test_the_hindcast_s_repr_says_what_it_holds():
    """It was the default <... object at 0x...>."""
    h = wobble.hindcast_polar_motion(
        start="2016-01-01", end="2016-03-01", horizon=30 * u.day, latency=1 * u.day, calibrated=False, workers=1
    )
    assert repr(h) == "PolarMotionHindcast(ls_ar, kalman, 9 issues 2016-01-01 to 2016-02-26, latency=1 d)"


@pytest.fixture(scope="module")
def gap_file(tmp_path_factory):
    """The shipped C04 record without 2015-03-10 (MJD 57091)."""
    from wobble.io.eop import default_c04_path

    lines = default_c04_path().read_text().splitlines(keepends=True)
    kept = [line for line in lines if not (line[:4] == "2015" and line.split()[:3] == ["2015", "3", "10"])]
    assert len(kept) == len(lines) - 1
    path = tmp_path_factory.mktemp("gap") / "c04_gap.txt"
    path.write_text("".join(kept))
    return path


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        # The gap lies only where the calibration's past forecasts read: it was "1 gaps in the Kalman fitting
        # span", which had none, and nothing said that --no-calibration runs. The stretch: the cut-off is the
        # issue date less C04's 30-d latency; the oldest past forecast is issued 7 (ceil(60/7) + 313 - 1) d
        # earlier (weekly, 313 a lead in 6 yr, the newest whose 30-d outcome is known), and reads 10 yr before.
        (
            ["--issued", "2026-01-01", "--horizon", "30"],
            "data: got 1 day missing (2015-03-10) from the record the past forecasts that calibrate the intervals "
            "read (each with its fitting span), 2009-10-07 to 2025-12-02; allowed: a daily record without gaps "
            "there; or the models' own Gaussian intervals",
        ),
        (
            ["--issued", "2022-01-01", "--horizon", "30", "--method", "ls_ar"],
            "1 day missing (2015-03-10) from the record the past forecasts that calibrate",
        ),
        (
            ["--issued", "2016-01-01", "--horizon", "30", "--no-calibration"],
            "1 day missing (2015-03-10) from the Kalman fitting span, 2005-12-01 to 2015-12-02; allowed: a daily "
            "record without gaps there\n",
        ),
        (
            ["--hindcast", "2019-01-01:2019-03-01", "--every", "7d", "--horizon", "30"],
            "1 day missing (2015-03-10) from the record the hindcast reads",
        ),
    ],
)
def test_a_missing_day_is_refused_by_date_where_it_is_read(gap_file, args, fragment, tmp_path, capsys):
    out_file = tmp_path / "f.nc"
    assert main(["forecast", "--file", str(gap_file), *args, "-o", str(out_file)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and fragment in err, err
    assert not out_file.exists()


def test_uncalibrated_intervals_do_not_read_a_gap_years_before(gap_file, capsys):
    assert (
        main(
            [
                "forecast",
                "--file",
                str(gap_file),
                "--issued",
                "2026-01-01",
                "--horizon",
                "30",
                "--no-calibration",
                "--json",
            ]
        )
        == 0
    )
    assert json.loads(capsys.readouterr().out)["issued"] == "2026-01-01"


def test_check_daily_names_missing_days_and_refuses_other_sampling():
    """MJD 51544 is 2000-01-01. Days 51547 and 51548 missing are one gap of two days; samples half a day apart
    are no whole number of missing days (the count had come out -1)."""
    from wobble.api.polar_motion.record import check_daily

    check_daily(np.arange(51544.0, 51560.0), 51544, 51559, "x")  # daily: nothing to say
    mjd = np.concatenate([np.arange(51544.0, 51547.0), np.arange(51549.0, 51560.0)])
    with pytest.raises(InputError, match=r"got 2 days missing \(2000-01-04 to 2000-01-05\) from x, 2000-01-01 to"):
        check_daily(mjd, 51544, 51559, "x")
    with pytest.raises(InputError, match=r"got samples 0\.5 d apart after 2000-01-02 in x; allowed: a daily record"):
        check_daily(np.array([51544.0, 51545.0, 51545.5, 51546.0]), 51544, 51546, "x")
