"""Geodetic excitation: the exact discrete Liouville equation both ways, on synthetic records with known
excitation and on C04."""

from __future__ import annotations

import json
import math

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


@pytest.mark.parametrize(("end", "resolved"), [("1979-03-03", False), ("1983-01-01", True)])
def test_chandler_band_only_where_the_span_resolves_it(end, resolved, tmp_path):
    """The band amplitudes come from an FFT band-pass of +/- 0.1 cycle per year: over 1975-01-01 to
    1979-03-03 no FFT frequency falls in the band (their spacing is 0.24 cycle per year), and the
    band was drawn as zeros on a log axis with a warning (fuzz run of 2026-11-28); now it is left out."""
    ex = wobble.geodetic_excitation(start="1975-01-01", end=end, chandler_period=433 * u.day)
    years = (ex.time_mjd[-1] - ex.time_mjd[0]) / 365.25
    frequencies = np.fft.fftfreq(ex.time_mjd.size, 1 / 365.25)  # cycles per year
    in_band = np.count_nonzero(np.abs(frequencies - 365.25 / 433) <= 0.1)
    assert (in_band >= 2) == resolved and (years < 5) != resolved
    assert (ex.band_chi is not None) == resolved and (ex.band_pole is not None) == resolved
    if resolved:
        assert np.all(ex.band_pole[365:-365] > 0)
    else:
        assert ex.to_dict()["chandler_band_collapse"] is None
    from wobble.plot.excitation import save_excitation_figure

    save_excitation_figure(ex, tmp_path / "excitation.png")  # warnings are errors in the tests


def test_the_whole_record_period_is_polar_motion_s_to_the_last_digit():
    """Both say "the least-squares period of the whole record"; they differed in the 10th digit
    (432.601783452 against 432.601783247 d) while the excitation's search went unpolished."""
    ex_period = wobble.geodetic_excitation().to_dict()["chandler_period_days"]
    assert ex_period == wobble.polar_motion_analysis().to_dict()["chandler_period_days"]


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


def test_netcdf_round_trip_and_cf(c04, tmp_path, assert_cf_compliant):
    ds = c04.to_dataset()
    assert ds["chi_1"].attrs["units"] == "milliarcsecond" and math.isnan(float(ds["chi_1"][0]))
    # Cycles per Julian year (365.25 d): UDUNITS' "year" is the tropical year, 2.1e-5 shorter, so "year-1"
    # (written until 2026-11-29) misread every frequency by that much in a UDUNITS reader (cf_units, pint).
    assert ds["frequency"].attrs["units"] == "Julian_year-1"
    # The band amplitudes' first and last year depend on where the record ends (the band-pass wraps around).
    for name in ("chandler_band_pole", "chandler_band_chi"):
        assert "depend on where the record ends" in ds[name].attrs["comment"]
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
