"""The IERS record itself: the published Chandler period, the methods' agreement, the post-2015 decline."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from astropy import units as u
from polar_synthetic import DAY, MAS, TRUTH, record

import wobble
from wobble.api.polar_motion import MJD_UNITS, published_chandler_period
from wobble.errors import InputError
from wobble.io.netcdf import open_wobble, write_netcdf


@pytest.fixture(scope="module")
def analysis():
    """The whole IERS 20 C04 record, 1962 to the file's end (16 Monte-Carlo draws and 2-yr window steps: a fast
    suite)."""
    return wobble.polar_motion_analysis(draws=16, step=2 * u.yr)


# ---------------------------------------------------------------------------
# The real record
# ---------------------------------------------------------------------------


def test_full_record_period_is_in_the_published_range(analysis):
    e = analysis.estimate
    assert e.method == "least_squares"
    assert e.start.iso[:10] == "1962-01-01"
    # Vicente & Wilson (1997): 433.1 d (data/bodies/earth.toml); the published range is about 430-435 d.
    published = published_chandler_period()
    assert 430 * u.day < e.period < 435 * u.day
    assert abs(e.period - published["period"]) < 2 * np.hypot(e.period_uncertainty, published["uncertainty"])
    # Honest error: days, not the hundredths of a day of white noise.
    parts = e.period_uncertainty_parts
    assert parts["formal"] < 0.05 * u.day
    assert 1 * u.day < e.period_uncertainty < 10 * u.day
    assert e.period_uncertainty >= max(parts["autocorrelation"], parts["subspans"])
    # Amplitude of about 0.12 arcsec over 1962-; the prograde annual term about 0.09 arcsec,
    # the retrograde one a few mas (e.g. Gross 2007, Treatise on Geophysics 3, sec. 11).
    assert 80 * u.mas < e.amplitude < 160 * u.mas
    assert 70 * u.mas < e.annual_prograde_amplitude < 110 * u.mas
    assert e.annual_retrograde_amplitude < 15 * u.mas


def test_chandler_wobble_is_prograde_in_the_data(analysis):
    spec = analysis.spectrum
    cpy = spec["frequency"].values  # cycles per Julian year
    amp = spec["amplitude_spectrum"].values
    band = (np.abs(cpy) > 0.75) & (np.abs(cpy) < 0.92)
    pro = amp[band & (cpy > 0)].max()
    retro = amp[band & (cpy < 0)].max()
    assert pro > 20 * retro
    assert cpy[band & (cpy > 0)][np.argmax(amp[band & (cpy > 0)])] == pytest.approx(365.25 / 433.0, abs=0.01)


def test_the_two_methods_agree(analysis):
    ls, sp = analysis.least_squares, analysis.spectral
    assert ls.method == "least_squares" and sp.method == "spectrum"
    assert analysis.methods_agree
    assert abs(ls.period - sp.period) < np.hypot(ls.period_uncertainty, sp.period_uncertainty)
    assert abs(ls.amplitude - sp.amplitude) < 2 * np.hypot(ls.amplitude_uncertainty, sp.amplitude_uncertainty)


def test_the_amplitude_declines_after_2015(analysis):
    w = analysis.windows
    years = 2000 + (w["window_time"].values - 51544.5) / 365.25
    amp = w["chandler_amplitude"].values
    before = amp[(years > 1975) & (years < 2005)]
    after = amp[years > 2016]
    assert before.min() > 100 and after.max() < 50  # mas
    assert after.mean() < 0.25 * before.mean()
    # ... far beyond the windows' own uncertainties.
    sig = w["chandler_amplitude_uncertainty"].values[years > 2016]
    assert np.all(after + 3 * sig < before.min())


def test_quality_factor_has_caveats(analysis):
    q = analysis.quality_factor_estimate
    assert q is not None and q.caveats
    assert 10 < q.lower_bound_95 < q.low
    assert any("flat excitation" in c for c in q.caveats)


def test_old_quality_factor_name_is_a_deprecated_alias(analysis):
    # Elsewhere quality_factor is the number Q; here the estimate object is quality_factor_estimate (as in the JSON).
    with pytest.warns(DeprecationWarning, match="quality_factor_estimate"):
        old = analysis.quality_factor
    assert old is analysis.quality_factor_estimate


def test_side_by_side_with_the_model(analysis):
    rows = analysis.comparison()
    budget = wobble.chandler_budget("earth")
    model_rows = [r for r in rows if r["kind"] == "model"]
    assert [r["name"] for r in model_rows] == [f"model: {s.name}" for s in budget.steps]
    obs = analysis.estimate.period
    for row, step in zip(model_rows, budget.steps):
        assert row["period"] == step.period
        assert row["residual"].to_value(u.day) == pytest.approx((step.period - obs).to_value(u.day))
    expected = np.hypot(budget.period_uncertainty, analysis.estimate.period_uncertainty)
    assert model_rows[-1]["residual_uncertainty"].to_value(u.day) == pytest.approx(expected.to_value(u.day))
    # The JSON's names; the older ones ("sigma" read as a number of sigmas) are kept beside them.
    assert all(r["sigma"] is r["residual_uncertainty"] and r["uncertainty"] is r["period_uncertainty"] for r in rows)
    assert rows[-1]["kind"] == "published"
    text = analysis.summary()
    for word in ("least squares", "spectrum", "annual wobble", "model", "Vicente & Wilson 1997"):
        assert word in text


# ---------------------------------------------------------------------------
# Quantities in, errors out
# ---------------------------------------------------------------------------


def test_chandler_wobble_on_a_synthetic_dataset():
    rng = np.random.default_rng(3)
    t, p = record(rng, 20)
    mjd = 51544.5 + t / DAY
    ds = xr.Dataset(
        {
            "x_p": ("time", p.real / MAS, {"units": "milliarcsecond"}),
            "y_p": ("time", -p.imag / MAS, {"units": "milliarcsecond"}),
        },
        coords={"time": ("time", mjd, {"units": MJD_UNITS})},
    )
    e = wobble.chandler_wobble(ds, excitation_q=None)
    assert abs(e.period - TRUTH["period"] / DAY * u.day) < 3 * e.period_uncertainty
    assert abs(e.amplitude - 150 * u.mas) < 3 * e.amplitude_uncertainty
    s = wobble.chandler_wobble(ds, method="spectrum", excitation_q=None)
    assert abs(s.period - e.period) < 2 * np.hypot(s.period_uncertainty, e.period_uncertainty)
    d = e.to_dict()
    assert d["chandler_period_days"] == pytest.approx(e.period.value) and d["start"] == e.start.iso[:10]


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"method": "wavelet"}, "method: got wavelet"),
        ({"band": [390, 500]}, "band: got"),
        ({"band": [1, 2, 3] * u.day}, "band"),
        ({"draws": 2}, "draws"),
        ({"excitation_q": "high"}, "excitation_q"),
        ({"data": 42}, "data: got int"),
    ],
)
def test_chandler_wobble_bad_arguments(kwargs, fragment):
    ds = wobble.load_polar_motion(start="2000", end="2010")
    kwargs.setdefault("data", ds)
    with pytest.raises(InputError, match=fragment):
        wobble.chandler_wobble(**kwargs)


@pytest.mark.parametrize(
    ("window", "fragment"),
    [
        (1 * u.yr, "window: got 1.0 yr"),
        (30 * u.yr, "to the span analysed"),
        (8, "a plain number has no unit"),
        (-3 * u.yr, "window: got -3.0 yr; allowed: a length from 2.005 yr"),
    ],
)
def test_bad_window_lengths(window, fragment):
    with pytest.raises(InputError, match=fragment):
        wobble.polar_motion_analysis(start="2000", end="2010", window=window, excitation_q=None, quality_factor=False)


def test_short_span_analysis_says_so():
    a = wobble.polar_motion_analysis(
        start="2018-01-01", end="2022-12-31", window=3 * u.yr, excitation_q=None, quality_factor=True
    )
    joined = " ".join(a.caveats)
    assert "beat" in joined and "no Q estimate" in joined
    assert a.quality_factor_estimate is None
    # A five-year span in the low-amplitude years: days of error even without the excitation term.
    assert a.estimate.period_uncertainty > 5 * u.day
    assert a.estimate.period_uncertainty_parts["model"] > 1 * u.day


def test_chandler_wobble_on_too_short_a_span_names_the_dates_given():
    """The estimators' own check named their argument 'series', which the caller of chandler_wobble never saw."""
    with pytest.raises(
        InputError,
        match=r"^start/end: got 2018-01-01 to 2019-01-01 \(365 d\); allowed: a span of "
        r"at least 730.5 d \(two Julian years\)",
    ):
        wobble.chandler_wobble(start="2018-01-01", end="2019-01-01")
    with pytest.raises(InputError, match=r"^start: got 2026-01-01; allowed: a date on or before [-0-9]{10}: the span"):
        wobble.chandler_wobble(start="2026-01-01")


# ---------------------------------------------------------------------------
# netCDF
# ---------------------------------------------------------------------------


def test_netcdf_round_trip_and_cf(analysis, tmp_path, assert_cf_compliant):
    ds = analysis.to_dataset()
    for name in (
        "x_p",
        "x_p_model",
        "x_p_residual",
        "chandler_amplitude",
        "amplitude_spectrum",
        "chandler_period",
        "model_period",
    ):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    np.testing.assert_allclose(ds["x_p_model"] + ds["x_p_residual"], ds["x_p"], atol=1e-12)
    assert ds["window_time"].attrs["bounds"] == "window_time_bounds"
    path = write_netcdf(ds, tmp_path / "pm.nc", command="test")
    back = open_wobble(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert list(back["method"].values) == ["least_squares", "spectrum"]
    assert_cf_compliant(path)
    # CF 7.1: the boundary variable is the coordinate's metadata: no long_name differing from the coordinate's,
    # no _FillValue (IOOS's checker warned of both), and each window's centre lies between its ends.
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        assert nc["window_time_bounds"].ncattrs() == []
        # No global 'coordinates' (xarray's place for a coordinate no variable names; CF defines none), and one
        # standard_name "time", so that cf_xarray's ds.cf["T"] finds the record's axis alone.
        assert "coordinates" not in nc.ncattrs()
        assert [v for v in nc.variables if getattr(nc[v], "standard_name", "") == "time"] == ["time"]
    lo, hi = back["window_time_bounds"].values.T
    assert np.all((lo < back["window_time"].values) & (back["window_time"].values < hi))
    assert math.isinf(float(back["quality_factor_high"])) or float(back["quality_factor_high"]) > 0


def test_a_window_without_a_chandler_term_in_the_band_is_left_out_and_said():
    """Two-year windows found their best 'Chandler' period at 365.2 d, past the 390-500 d search band, with
    amplitudes of 6e9 mas cancelling the annual term's, and printed them unflagged. A window whose best period
    lies at or past the band's edge is left NaN and the caveats count them; 6-yr windows of 1980-2010 keep all."""
    short = wobble.polar_motion_analysis(
        start="2015", end="2020", window=733 * u.day, excitation_q=None, quality_factor=False
    )
    w = short.windows
    n = w.sizes["window"]
    assert np.isnan(w["chandler_amplitude"].values).all() and np.isnan(w["annual_prograde_amplitude"].values).all()
    assert f"{n} of {n} windows found no Chandler term inside the search band (390-500 d)" in " ".join(short.caveats)
    full = wobble.polar_motion_analysis(
        start="1980", end="2010", window=6 * u.yr, excitation_q=None, quality_factor=False
    )
    periods = full.windows["chandler_period"].values
    assert np.isfinite(periods).all() and ((390 < periods) & (periods < 500)).all()
    assert not any("no Chandler term inside" in c for c in full.caveats)


def test_no_attribute_of_the_dataset_is_empty(analysis):
    """chandler_resolved carried comment = '' when the span had no caveat (a compliance checker's complaint)."""
    ds = analysis.to_dataset()
    empty = [
        (name, key)
        for name, var in [("", ds), *ds.variables.items()]
        for key, value in var.attrs.items()
        if isinstance(value, str) and not value.strip()
    ]
    assert empty == []
    # docs/netcdf.md: every numeric variable has units (chandler_resolved, a flag, had none); bounds take theirs
    # from their coordinate.
    bounds = {v.attrs["bounds"] for v in ds.variables.values() if "bounds" in v.attrs}
    missing = [
        n for n, v in ds.variables.items() if v.dtype.kind in "biuf" and n not in bounds and "units" not in v.attrs
    ]
    assert missing == []


def test_the_chandler_estimate_s_repr_says_what_was_measured():
    """The dataclass repr ran to 3,000 characters of raw SI fit; now the span and the term, in the text's digits."""
    from wobble.io.text import with_uncertainty

    e = wobble.chandler_wobble(start="2000-01-01", end="2010-01-01")
    period = with_uncertainty(e.period.to_value(u.day), e.period_uncertainty.to_value(u.day))
    assert repr(e).startswith(
        f"<ChandlerEstimate (least_squares) 2000-01-01 to 2010-01-01, {e.n_samples} samples: "
        f"period {period} d, amplitude "
    )
    assert len(repr(e)) < 200 and e.resolved and "not resolved" not in repr(e)
