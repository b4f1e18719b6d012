"""Chandler-wobble estimation on synthetic records with known terms (ground truth), in SI floats."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, TRUTH, YEAR, damped_wobble, record

from wobble.errors import InputError
from wobble.models import polar_motion as pm
from wobble.numerics.spectral import dtft, dtft_at

# ---------------------------------------------------------------------------
# The Fourier kernel against closed forms
# ---------------------------------------------------------------------------


def test_dtft_grid_matches_the_geometric_sum():
    # sum_{n<N} exp(i a n) exp(-i w n) = (1 - e^{i(a-w)N}) / (1 - e^{i(a-w)}): closed form.
    n, a = 500, 0.3
    t = np.arange(n, dtype=float)
    z = np.exp(1j * a * t)
    omega0, step, count = -1.0, 0.013, 200  # 200 > RESEED: the recurrence is re-seeded on the way
    got = dtft(t, z, omega0, step, count)
    w = omega0 + step * np.arange(count)
    d = a - w
    expected = (1 - np.exp(1j * d * n)) / (1 - np.exp(1j * d))
    np.testing.assert_allclose(got, expected, rtol=1e-11, atol=1e-10)
    np.testing.assert_allclose(dtft_at(t, z, w[[3, 150]]), expected[[3, 150]], rtol=1e-12)


def test_dtft_transforms_columns_together():
    rng = np.random.default_rng(1)
    t = np.sort(rng.uniform(-50, 50, 300))  # uneven
    z = rng.standard_normal((300, 3)) + 1j * rng.standard_normal((300, 3))
    got = dtft(t, z, -0.5, 0.01, 90)
    for j in range(3):
        np.testing.assert_allclose(got[:, j], dtft_at(t, z[:, j], -0.5 + 0.01 * np.arange(90)), rtol=1e-10, atol=1e-10)


# ---------------------------------------------------------------------------
# Sign convention
# ---------------------------------------------------------------------------


def test_prograde_circle_is_at_positive_frequency():
    # A counter-clockwise circle seen from above the north pole: with x toward
    # Greenwich and y toward 90 W, that is x = cos, y = -sin (y is a clockwise axis).
    t = np.arange(0, 20 * YEAR, DAY)
    w = 2 * math.pi / TRUTH["period"]
    x, y = np.cos(w * t), -np.sin(w * t)
    p = pm.complex_pole(x, y)
    np.testing.assert_allclose(p, np.exp(1j * w * t), atol=1e-12)
    np.testing.assert_allclose(pm.pole_xy(p), (x, y), atol=1e-15)
    spec = pm.two_sided_spectrum(t, p * MAS, drift_degree=0)
    assert spec.rate[np.argmax(spec.amplitude)] > 0
    assert spec.amplitude.max() == pytest.approx(MAS, rel=0.01)  # a circle of radius 1 mas


# ---------------------------------------------------------------------------
# Ground truth: constant terms in coloured noise, gaps and uneven sampling
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def deterministic_fits():
    """Six 30-year records (seed 2026): both estimators, autocorrelation error only (no excitation term)."""
    rng = np.random.default_rng(2026)
    out = []
    for _ in range(6):
        t, p = record(rng, 30)
        ls = pm.fit_least_squares(t, p, excitation_q=None)
        sp = pm.fit_spectrum(t, p, excitation_q=None)
        out.append((ls, sp))
    return out


@pytest.mark.parametrize("which", [0, 1], ids=["least_squares", "spectrum"])
def test_terms_recovered_within_stated_uncertainties(deterministic_fits, which):
    for fits in deterministic_fits:
        f = fits[which]
        assert not f.caveats
        assert abs(f.chandler.period - TRUTH["period"]) < 3 * f.chandler.period_sigma
        assert abs(f.chandler.amplitude - TRUTH["chandler_amplitude"]) < 3 * f.chandler.amplitude_sigma
        # phase at the epoch (mid-span, which is where the truth's phase is set)
        dphi = math.remainder(f.chandler.phase - TRUTH["chandler_phase"], 2 * math.pi)
        assert abs(dphi) < 3 * f.chandler.phase_sigma + 1e-3
        assert abs(f.annual_prograde.amplitude - TRUTH["annual_amplitude"]) < 3 * f.annual_prograde.amplitude_sigma
        assert abs(f.annual_retrograde.amplitude - TRUTH["retrograde_amplitude"]) < 3 * f.annual_retrograde.amplitude_sigma
        assert f.annual_retrograde.rate < 0 < f.annual_prograde.rate


@pytest.mark.parametrize("which", [0, 1], ids=["least_squares", "spectrum"])
def test_stated_uncertainties_are_honest_not_white(deterministic_fits, which):
    """Coverage over six noise realisations: the errors scale with the stated sigma.

    The white-noise (formal) sigma is far too small for AR(1) noise with a
    200-day correlation time; the autocorrelation-corrected one is not.
    """
    err = np.array([f[which].chandler.period - TRUTH["period"] for f in deterministic_fits])
    sigma = np.array([f[which].chandler.period_sigma for f in deterministic_fits])
    formal = np.array([f[which].period_uncertainty.formal for f in deterministic_fits])
    ratio = np.sqrt(np.mean(err**2)) / np.sqrt(np.mean(sigma**2))
    assert 0.3 < ratio < 2.0, ratio
    assert np.sqrt(np.mean(err**2)) > 2.5 * np.sqrt(np.mean(formal**2))
    assert np.all(sigma > 3 * formal)


def test_the_two_methods_agree_within_their_uncertainties(deterministic_fits):
    for ls, sp in deterministic_fits:
        diff = abs(ls.chandler.period - sp.chandler.period)
        assert diff < 2 * math.hypot(ls.chandler.period_sigma, sp.chandler.period_sigma)


def test_least_squares_polish_confirms_the_profile_optimum():
    rng = np.random.default_rng(5)
    t, p = record(rng, 12, gaps=False)
    full = pm.fit_least_squares(t, p, excitation_q=None)
    bare = pm.fit_least_squares(t, p, uncertainty=False)  # variable projection alone
    assert full.chandler.rate == pytest.approx(bare.chandler.rate, rel=1e-8)
    assert full.details["solver"].startswith("variable projection")


def test_mean_pole_drift_is_removed():
    rng = np.random.default_rng(6)
    t, p = record(rng, 20, noise_rms=0.1 * MAS, gaps=False)
    f = pm.fit_least_squares(t, p, excitation_q=None)
    s = t - t.mean()
    tau = s / s.max()
    drift = (40 + 300j + (20 - 60j) * tau + (5 + 8j) * tau**2) * MAS
    assert np.max(np.abs(f.mean_pole(t) - drift)) < 1.0 * MAS
    assert f.residual_rms < 0.5 * MAS


# ---------------------------------------------------------------------------
# A randomly excited wobble: the excitation term makes the error honest
# ---------------------------------------------------------------------------


def test_coverage_for_a_randomly_excited_wobble():
    """Damped free mode of Q = 100 (seed 7, six 30-year records): the mode's period within the stated sigma.

    Without the Monte-Carlo excitation term the errors would be several
    times the stated ones (the record's mean frequency wanders about the
    mode's frequency); with it the normalised errors have unit scale.
    """
    rng = np.random.default_rng(7)
    z, z_auto = [], []
    for _ in range(6):
        t, p = record(rng, 30, chandler="damped", q=100.0)
        f = pm.fit_least_squares(t, p, excitation_q=100.0, draws=16)
        err = f.chandler.period - TRUTH["period"]
        z.append(err / f.chandler.period_sigma)
        z_auto.append(err / f.period_uncertainty.autocorrelation)
    z = np.array(z)
    assert np.all(np.abs(z) < 3.0), z
    assert 0.1 < np.mean(z**2) < 3.0, z
    assert np.mean(np.square(z_auto)) > 4 * np.mean(z**2)


# ---------------------------------------------------------------------------
# Hard cases
# ---------------------------------------------------------------------------


def test_short_span_says_so_and_widens_the_uncertainty():
    rng = np.random.default_rng(8)
    t, p = record(rng, 4)
    long_t, long_p = record(np.random.default_rng(8), 30)
    short = pm.fit_least_squares(t, p, excitation_q=None)
    long = pm.fit_least_squares(long_t, long_p, excitation_q=None)
    assert any("beat" in c for c in short.caveats)
    assert not long.caveats
    # 7.5 times shorter: a white-noise error would grow 7.5^1.5 = 20 times; the
    # drift-model term (large when the terms barely separate) adds to it.
    assert short.chandler.period_sigma > 10 * long.chandler.period_sigma
    assert short.period_uncertainty.model > 0.3 * short.period_uncertainty.autocorrelation
    assert abs(short.chandler.period - TRUTH["period"]) < 2 * short.chandler.period_sigma
    # With the default excitation term (Q = 100) the error is wider still.
    default = pm.fit_least_squares(t, p, draws=16)
    assert default.chandler.period_sigma > 2 * short.chandler.period_sigma
    spec = pm.fit_spectrum(t, p, draws=16)
    assert spec.details["taper"] == "none"
    assert any("beat" in c for c in spec.caveats)
    assert abs(spec.chandler.period - TRUTH["period"]) < 2 * spec.chandler.period_sigma


def test_no_chandler_term_is_reported_as_unresolved():
    rng = np.random.default_rng(9)
    n = int(12 * 365.25)
    t = DAY * np.arange(n)
    s = t - t.mean()
    p = 90 * MAS * np.exp(1j * pm.ANNUAL_RATE * s) + rng.standard_normal(n) * 0.2 * MAS
    f = pm.fit_least_squares(t, p, excitation_q=None)
    assert f.chandler.amplitude < 1 * MAS
    # A period found in pure noise is not a measurement: it is either flagged
    # at the band's edge or uncertain by far more than a real one.
    assert any("edge" in c for c in f.caveats) or f.chandler.period_sigma > 5 * DAY


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"t": np.arange(100) * DAY}, "at least 730 d"),
        ({"t": np.arange(1000)[::-1] * DAY}, "increasing"),
        ({"p": np.full(1000, np.nan)}, "finite"),
        ({"band": (300 * DAY, 500 * DAY)}, "band"),
        ({"drift_degree": 9}, "drift_degree"),
        ({"drift_degree": 1.5}, "drift_degree"),
        ({"excitation_q": 0.5}, "excitation_q"),
    ],
)
def test_bad_input_is_an_input_error(kwargs, fragment):
    t = kwargs.pop("t", np.arange(1000) * DAY)
    p = kwargs.pop("p", np.exp(1j * 2 * math.pi * t / TRUTH["period"]))
    with pytest.raises(InputError, match=fragment):
        pm.fit_least_squares(t, p[: t.size], **kwargs)


@pytest.mark.parametrize(("window", "fragment"), [(1 * YEAR, "window"), (40 * YEAR, "window"), (math.nan, "window")])
def test_bad_window_lengths(window, fragment):
    rng = np.random.default_rng(10)
    t, p = record(rng, 10)
    with pytest.raises(InputError, match=fragment):
        pm.sliding_windows(t, p, window)


def test_windows_follow_a_decaying_amplitude():
    """A wobble whose amplitude halves every 5 years: the windows see it, at the right epochs."""
    rng = np.random.default_rng(11)
    n = int(30 * 365.25)
    t = DAY * np.arange(n)
    s = t - t.mean()
    amp = 150 * MAS * np.exp(-np.log(2) * t / (5 * YEAR))
    p = amp * np.exp(1j * 2 * math.pi / TRUTH["period"] * s) + 90 * MAS * np.exp(1j * pm.ANNUAL_RATE * s)
    p = p + rng.standard_normal(n) * 0.5 * MAS
    w = pm.sliding_windows(t, p, 6 * YEAR, 2 * YEAR)
    expected = 150 * MAS * np.exp(-np.log(2) * w.centre / (5 * YEAR))
    # The window sees the mean of an exponential over +/- 3 yr: cosh-like factor, under 10 %.
    np.testing.assert_allclose(w.amplitude, expected, rtol=0.1)
    assert np.all(np.diff(w.amplitude) < 0)
    np.testing.assert_allclose(w.period, TRUTH["period"], atol=2 * DAY)


# ---------------------------------------------------------------------------
# Q from the line shape
# ---------------------------------------------------------------------------


def test_quality_factor_interval_covers_a_known_q():
    rng = np.random.default_rng(12)
    n = int(40 * 365.25)
    t = DAY * np.arange(n)
    y = damped_wobble(rng, n, TRUTH["period"], 30.0, 150 * MAS) + rng.standard_normal(n) * 2 * MAS
    q = pm.quality_factor(t, y, 2 * math.pi / TRUTH["period"])
    assert q.resolved
    assert q.low <= 30.0 <= q.high
    assert q.lower_bound_95 < q.low < q.value < q.high
    assert any("flat excitation" in c for c in q.caveats)


def test_quality_factor_needs_decades():
    t = DAY * np.arange(int(10 * 365.25))
    with pytest.raises(InputError, match="at least 20 yr"):
        pm.quality_factor(t, np.exp(1j * t / 1e7), 1e-7)
