"""Geodetic excitation: the exact discrete Liouville equation both ways, on synthetic records with known
excitation and on C04."""

from __future__ import annotations

import functools
import json
import math

import mpmath
import numpy as np
import pytest
import xarray as xr
from polar_synthetic import DAY, MAS

import wobble
from astropy import units as u
from wobble.cli import main
from wobble.errors import InputError
from wobble.io.netcdf import open_wobble, write_netcdf
from wobble.models.polar_motion import excitation as ex

SIGMA = ex.chandler_frequency(433.0 * DAY, 80.0)


def test_chandler_frequency_is_the_damped_prograde_mode():
    # sigma_c = 2 pi / T (1 + i/(2Q)): a free wobble exp(i sigma_c t) turns prograde and decays in 2Q/sigma.
    t = np.array([0.0, 2 * 80.0 / (2 * math.pi / (433.0 * DAY))])
    free = np.exp(1j * SIGMA * t)
    assert abs(free[1]) == pytest.approx(math.exp(-1.0), rel=1e-12)
    assert ex.chandler_frequency(433.0 * DAY, math.inf).imag == 0.0
    with pytest.raises(InputError, match="q: got 0"):
        ex.chandler_frequency(433.0 * DAY, 0.0)


def test_constant_excitation_gives_the_closed_form_relaxation():
    # p + (i/sigma) dp/dt = chi0 has p(t) = chi0 + (p0 - chi0) exp(i sigma t): the inverse returns chi0 at every step.
    t = np.sort(np.random.default_rng(1).uniform(0, 3000, 400)) * DAY  # uneven sampling
    chi0, p0 = (30 - 40j) * MAS, (150 + 80j) * MAS
    p = chi0 + (p0 - chi0) * np.exp(1j * SIGMA * (t - t[0]))
    chi = ex.excitation_from_pole(t, p, SIGMA)
    np.testing.assert_allclose(chi, chi0, rtol=0, atol=1e-6 * MAS)  # steps of minutes lose digits to 1 - lambda


def test_known_excitation_is_recovered_and_the_round_trip_is_exact():
    """A damped oscillator driven by a known coloured excitation (daily): inverse recovers it, forward rebuilds
    the pole."""
    rng = np.random.default_rng(20)
    n = 20 * 365
    t = DAY * np.arange(n)
    eta = (rng.standard_normal(n - 1) + 1j * rng.standard_normal(n - 1)) * 20 * MAS
    chi = np.empty(n - 1, dtype=complex)
    chi[0] = eta[0]
    for k in range(1, n - 1):
        chi[k] = 0.85 * chi[k - 1] + eta[k]
    p = ex.pole_from_excitation(t, chi, SIGMA, 120 * MAS)
    np.testing.assert_allclose(ex.excitation_from_pole(t, p, SIGMA), chi, rtol=0, atol=1e-9 * MAS)
    back = ex.pole_from_excitation(t, ex.excitation_from_pole(t, p, SIGMA), SIGMA, p[0])
    assert np.sqrt(np.mean(np.abs(back - p) ** 2)) < 1e-9 * MAS
    # Wilson's (1985) filter replaces 1 - lambda by -i sigma Delta exp(i sigma Delta / 2): (sigma Delta)^2 / 24 apart.
    lam = np.exp(1j * SIGMA * DAY)
    wilson = (p[1:] - lam * p[:-1]) * 1j * np.exp(-0.5j * SIGMA * DAY) / (SIGMA * DAY)
    rel = np.median(np.abs(wilson - chi) / np.abs(chi))
    assert rel == pytest.approx(abs(SIGMA * DAY) ** 2 / 24, rel=0.05)


@pytest.fixture(scope="module")
def c04():
    return wobble.geodetic_excitation(start="2000-01-01", end="2019-12-31")


def test_c04_round_trip_and_broadband_excitation(c04):
    d = c04.to_dict()
    assert d["round_trip_rms_mas"] < 0.01  # the target; in fact rounding only
    assert d["round_trip_rms_mas"] < 1e-6
    # The pole has a sharp Chandler peak; its excitation has none (broadband).
    assert d["chandler_peak_over_neighbours"]["pole"] > 5
    assert d["chandler_peak_over_neighbours"]["excitation"] < 2
    assert 430 < d["chandler_period_days"] < 436 and d["quality_factor"] > 0
    assert "Liouville" in d["method"]


@functools.lru_cache
def _main_lobe_days(half_width: float = 0.1) -> float:
    """Half the main lobe of an ideal band-pass's kernel, in days, for a band of +/- ``half_width`` cycles per
    Julian year: the first zero of its impulse response h(t) = int_{-B}^{B} cos(2 pi f t) df (the box's inverse
    Fourier transform), integrated and solved by mpmath at 30 digits. Also checks that the lobe holds 90 % of the
    kernel's energy (Parseval: int h^2 dt = 2B), which is why amplitudes count as known only beyond it."""
    with mpmath.workdps(30):
        b = mpmath.mpf(half_width) / mpmath.mpf("365.25")  # cycles per day

        def h(t):
            return mpmath.quad(lambda f: mpmath.cos(2 * mpmath.pi * f * t), [-b, b])

        lo = next(k for k in range(100, 10000, 100) if h(k) < 0) - 100  # h(0) = 2B > 0: the first sign change
        lobe = mpmath.findroot(h, (lo, lo + 100), solver="anderson")
        energy = mpmath.quad(lambda t: h(t) ** 2, [0, lobe / 2, lobe]) * 2 / (2 * b)
        assert 0.90 < energy < 0.91
        return float(lobe)


@pytest.mark.parametrize(("end", "resolved"), [("1979-03-03", False), ("1986-01-01", False), ("1986-01-02", True)])
def test_chandler_band_only_where_the_span_resolves_it(end, resolved, tmp_path):
    """The band-pass's amplitudes are known where its kernel's main lobe (+/- 5 years for +/- 0.1 cycle per year,
    measured here by mpmath) lies inside the record, and a year of them is the least: 11 years of excitation (a
    day shorter than the pole) from 1975-01-01 end on 1986-01-02 (its earlier band-pass drew zeros on a log axis,
    with a warning, for 1975-1979: fuzz run of 2026-11-28). The known samples are counted on the record's own
    times against the measured lobe: 365 on 1986-01-02, 364 a day earlier."""
    ex = wobble.geodetic_excitation(start="1975-01-01", end=end, chandler_period=433 * u.day)
    lobe = _main_lobe_days()
    assert ex.band_reach.to_value(u.day) == pytest.approx(lobe, rel=1e-12)
    pole = ex.time_mjd - ex.time_mjd[0]  # days; the excitation starts a day after the pole
    excitation = ex.time_mjd[1:] - ex.time_mjd[1]
    np.testing.assert_array_equal(np.diff(ex.time_mjd), 1.0)  # daily: a year of amplitudes is 365 samples

    def inside(days):  # the samples whose kernel's main lobe lies inside the record
        return (days >= lobe) & (days <= days[-1] - lobe)

    assert (np.count_nonzero(inside(excitation)) >= 365) == resolved
    assert (ex.band_chi is not None) == resolved and (ex.band_pole is not None) == resolved
    if resolved:
        np.testing.assert_array_equal(np.isfinite(ex.band_chi), inside(excitation))
        np.testing.assert_array_equal(np.isfinite(ex.band_pole), inside(pole))
        assert np.all(ex.band_pole[inside(pole)] > 0) and np.all(ex.band_chi[inside(excitation)] > 0)
    else:
        assert ex.to_dict()["chandler_band_collapse"] is None
    from wobble.plot.excitation import save_excitation_figure

    save_excitation_figure(ex, tmp_path / "excitation.png")  # warnings are errors in the tests


def test_the_band_pass_keeps_the_chandler_line_rejects_the_annual_and_does_not_wrap_around():
    """Closed forms over 60 years of daily samples: a sinusoid at the centre keeps its amplitude (to the
    Gibbs ripple of the record's truncation, 4 % in the middle and 12 % next to the unknown ends), the annual
    line 0.16 cycle per year away is rejected (a Gaussian band of the same half-width passed a fifth of it),
    and a wobble that stops half-way does not reappear at the record's end, as the circular band-pass used
    until 2026-11-29 made it (0.45 of its amplitude there)."""
    year = 365.25 * DAY
    t = DAY * np.arange(int(60 * year / DAY))
    centre, half = 2 * math.pi / (433 * DAY), 0.1 * 2 * math.pi / year
    assert ex.band_reach(half) == pytest.approx(5 * year, rel=1e-12)  # the sinc's main lobe, 1/(2 x 0.1) years
    middle = np.abs(t - t[-1] / 2) < 10 * year
    known = (t > t[0] + 5 * year) & (t < t[-1] - 5 * year)
    chandler = ex.band_amplitude(t, 7.0 * np.exp(1j * centre * t), centre, half)
    assert np.all(np.isnan(chandler[~known])) and np.all(np.isfinite(chandler[known]))
    np.testing.assert_allclose(chandler[middle], 7.0, rtol=0.05)
    np.testing.assert_allclose(chandler[known], 7.0, rtol=0.12)
    annual = ex.band_amplitude(t, 7.0 * np.exp(2j * math.pi * t / year), centre, half)
    assert np.max(annual[middle]) < 0.04 * 7.0 and np.nanmax(annual) < 0.1 * 7.0
    # Removed by least squares first, as the excitation's seasons are, it leaves nothing in the band.
    removed = ex.band_amplitude(t, 7.0 * np.exp(2j * math.pi * t / year), centre, half, lines=[2 * math.pi / year])
    assert np.nanmax(removed) < 1e-9 * 7.0
    # and the Chandler line is untouched by removing the annual one
    kept = ex.band_amplitude(t, 7.0 * np.exp(1j * centre * t), centre, half, lines=[2 * math.pi / year])
    np.testing.assert_allclose(kept[middle], 7.0, rtol=0.05)
    stops = np.where(t < t[-1] / 2, 7.0, 0.0) * np.exp(1j * centre * t)
    late = known & (t > 0.75 * t[-1])
    assert np.max(ex.band_amplitude(t, stops, centre, half)[late]) < 0.1 * 7.0


def test_the_whole_record_period_is_polar_motion_s_to_the_last_digit():
    """Both say "the least-squares period of the whole record"; they differed in the 10th digit
    (432.601783452 against 432.601783247 d) while the excitation's search went unpolished."""
    ex_period = wobble.geodetic_excitation().to_dict()["chandler_period_days"]
    assert ex_period == wobble.polar_motion_analysis().to_dict()["chandler_period_days"]
    assert ex_period == pytest.approx(433.0, abs=2.0)  # the published 433 d (Gross 2000; 432-434 d)


def test_a_file_and_its_dataset_give_the_same_excitation(c04):
    """The shipped record read into plain arrays (no Dataset: what the JSON and the text use) and the
    same record as the Dataset of load_polar_motion give the same excitation, to the bit."""
    given = wobble.geodetic_excitation(wobble.load_polar_motion(), start="2000-01-01", end="2019-12-31")
    a, b = c04.to_dict(), given.to_dict()
    assert a == b
    ds_a, ds_b = c04.to_dataset(), given.to_dataset()
    assert list(ds_a.data_vars) == list(ds_b.data_vars)
    for name in ds_a.data_vars:
        np.testing.assert_array_equal(ds_a[name].values, ds_b[name].values, err_msg=name)


def test_the_observed_pole_merges_with_the_record(c04):
    """The excitation's x_p, y_p came back from radians an ulp off the record's (-37.49799999999999 against
    -37.498 mas): xr.merge of the two refused them as conflicting. Now both hold the files' decimals."""
    record = wobble.load_polar_motion(start="2000-01-01", end="2019-12-31")[["x_p", "y_p"]]
    merged = xr.merge([record, c04.to_dataset()[["x_p", "y_p"]]], join="inner", compat="no_conflicts")
    assert merged.sizes["time"] == record.sizes["time"]
    xr.testing.assert_equal(merged, record)


def test_netcdf_round_trip_and_cf(c04, tmp_path, assert_cf_compliant):
    ds = c04.to_dataset()
    assert ds["chi_1"].attrs["units"] == "milliarcsecond" and math.isnan(float(ds["chi_1"][0]))
    # Both components are unknown at the first sample (chi_2 was 0.0 there, from nan + 0j, and that zero
    # entered chi_2_rms_mas), and the RMS of the JSON is that of the rest.
    assert math.isnan(float(ds["chi_2"][0])) and math.isnan(c04.chi_2[0].value)
    rest = ds["chi_2"].values[1:]
    assert np.isfinite(rest).all()
    assert c04.to_dict()["chi_2_rms_mas"] == pytest.approx(float(np.sqrt(np.mean(rest**2))), rel=1e-14)
    # Cycles per Julian year (365.25 d): UDUNITS' "year" is the tropical year, 2.1e-5 shorter, so "year-1"
    # (written until 2026-11-29) misread every frequency by that much in a UDUNITS reader (cf_units, pint).
    assert ds["frequency"].attrs["units"] == "julian_year-1"
    # The band amplitudes are NaN within the band-pass kernel's reach of the ends, and the file says so.
    for name in ("chandler_band_pole", "chandler_band_chi"):
        assert "NaN within 5.0 yr of the record's ends" in ds[name].attrs["comment"]
        assert np.isnan(ds[name].values[:365]).all() and np.isnan(ds[name].values[-365:]).all()
    path = write_netcdf(ds, tmp_path / "chi.nc", command="test")
    back = open_wobble(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert_cf_compliant(path)


def test_cli_json_and_bad_q(tmp_path, capsys):
    status = main(["excitation", "--start", "2010", "--end", "2014", "--q", "100", "--period", "433d", "--json"])
    out, err = capsys.readouterr()
    d = json.loads(out)
    assert status == 0 and d["quality_factor"] == 100 and d["chandler_period_days"] == 433
    assert d["round_trip_rms_mas"] < 0.01
    nc = tmp_path / "chi.nc"
    status = main(["excitation", "--start", "2010", "--end", "2014", "--q", "-3", "-o", str(nc)])
    _, err = capsys.readouterr()
    assert status == 2 and err.startswith("wobble excitation: error: --q: got -3") and err.count("\n") == 1
    assert not nc.exists()


def test_the_repr_says_what_the_excitation_holds():
    """It was the default <... object at 0x...>."""
    ex = wobble.geodetic_excitation(start="1990-01-01", end="2000-01-01", chandler_period=433 * u.day, q=80)
    assert repr(ex) == "GeodeticExcitation(1990-01-01 to 2000-01-01, 3653 days, T_c=433.0 d, Q=80)"
