"""Both Chandler estimators on synthetic records with known terms (ground truth), in SI floats."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, REFERENCE_PERIOD, TRUTH, record

from wobble.errors import InputError
from wobble.models import polar_motion as pm


@pytest.fixture(scope="module")
def deterministic_fits():
    """Six 30-year records (seed 2026): both estimators, autocorrelation error only (no excitation term)."""
    rng = np.random.default_rng(2026)
    out = []
    for _ in range(6):
        t, p = record(rng, 30)
        ls = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=None)
        sp = pm.fit_spectrum(t, p, reference_period=REFERENCE_PERIOD, excitation_q=None)
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
        assert (
            abs(f.annual_retrograde.amplitude - TRUTH["retrograde_amplitude"]) < 3 * f.annual_retrograde.amplitude_sigma
        )
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
    full = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=None)
    bare = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, uncertainty=False)  # variable projection alone
    assert full.chandler.rate == pytest.approx(bare.chandler.rate, rel=1e-8)
    assert full.details["solver"].startswith("variable projection")


def test_the_polish_finds_an_exact_period_to_rounding_and_the_search_alone_to_sqrt_eps():
    """A record of the model itself without noise (uneven sampling): the polished period is 433 d to
    rounding; the search by function values alone places a smooth maximum to sqrt(eps) of itself or
    better (3e-9 here)."""
    t, p = record(np.random.default_rng(1), 20, noise_rms=0.0)
    polished = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, uncertainty=False, polish=True)
    searched = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, uncertainty=False)
    assert polished.chandler.period == pytest.approx(TRUTH["period"], rel=1e-13)
    assert searched.chandler.period == pytest.approx(TRUTH["period"], rel=1.5e-8)  # sqrt(eps) = 1.5e-8


def test_mean_pole_drift_is_removed():
    rng = np.random.default_rng(6)
    t, p = record(rng, 20, noise_rms=0.1 * MAS, gaps=False)
    f = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=None)
    s = t - t.mean()
    tau = s / s.max()
    drift = (40 + 300j + (20 - 60j) * tau + (5 + 8j) * tau**2) * MAS
    assert np.max(np.abs(f.mean_pole(t) - drift)) < 1.0 * MAS
    assert f.residual_rms < 0.5 * MAS


def test_short_span_says_so_and_widens_the_uncertainty():
    rng = np.random.default_rng(8)
    t, p = record(rng, 4)
    long_t, long_p = record(np.random.default_rng(8), 30)
    short = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=None)
    long = pm.fit_least_squares(long_t, long_p, reference_period=REFERENCE_PERIOD, excitation_q=None)
    assert any("beat" in c for c in short.caveats)
    assert not long.caveats
    # 7.5 times shorter: a white-noise error would grow 7.5^1.5 = 20 times; the
    # drift-model term (large when the terms barely separate) adds to it.
    assert short.chandler.period_sigma > 10 * long.chandler.period_sigma
    assert short.period_uncertainty.model > 0.3 * short.period_uncertainty.autocorrelation
    assert abs(short.chandler.period - TRUTH["period"]) < 2 * short.chandler.period_sigma
    # With the default excitation term (Q = 100) the error is wider still.
    default = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, draws=16)
    assert default.chandler.period_sigma > 2 * short.chandler.period_sigma
    spec = pm.fit_spectrum(t, p, reference_period=REFERENCE_PERIOD, draws=16)
    assert spec.details["taper"] == "none"
    assert any("beat" in c for c in spec.caveats)
    assert abs(spec.chandler.period - TRUTH["period"]) < 2 * spec.chandler.period_sigma


def test_no_chandler_term_is_reported_as_unresolved():
    rng = np.random.default_rng(9)
    n = int(12 * 365.25)
    t = DAY * np.arange(n)
    s = t - t.mean()
    p = 90 * MAS * np.exp(1j * pm.ANNUAL_RATE * s) + rng.standard_normal(n) * 0.2 * MAS
    f = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=None)
    assert f.chandler.amplitude < 1 * MAS
    # A period found in pure noise is not a measurement: it is either flagged
    # at the band's edge or uncertain by far more than a real one.
    assert any("edge" in c for c in f.caveats) or f.chandler.period_sigma > 5 * DAY


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"t": np.arange(100) * DAY}, "at least 730.5 d"),
        ({"t": np.arange(1000)[::-1] * DAY}, "increasing"),
        ({"p": np.full(1000, np.nan)}, "finite"),
        ({"band": (300 * DAY, 500 * DAY)}, "band"),
        ({"drift_degree": 9}, "drift_degree"),
        ({"drift_degree": 1.5}, "drift_degree"),
        ({"excitation_q": 0.5}, "excitation_q"),
        ({"reference_period": 300 * DAY}, "reference_period: got 300 d"),
        ({"reference_period": math.nan}, "reference_period"),
    ],
)
def test_bad_input_is_an_input_error(kwargs, fragment):
    t = kwargs.pop("t", np.arange(1000) * DAY)
    p = kwargs.pop("p", np.exp(1j * 2 * math.pi * t / TRUTH["period"]))
    kwargs.setdefault("reference_period", REFERENCE_PERIOD)
    with pytest.raises(InputError, match=fragment):
        pm.fit_least_squares(t, p[: t.size], **kwargs)
