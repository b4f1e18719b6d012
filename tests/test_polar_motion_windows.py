"""Sliding-window fits: bad lengths refused, a decaying amplitude followed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, REFERENCE_PERIOD, TRUTH, YEAR, record

from wobble.errors import InputError
from wobble.models import polar_motion as pm


@pytest.mark.parametrize(("window", "fragment"), [(1 * YEAR, "window"), (40 * YEAR, "window"), (math.nan, "window")])
def test_bad_window_lengths(window, fragment):
    rng = np.random.default_rng(10)
    t, p = record(rng, 10)
    with pytest.raises(InputError, match=fragment):
        pm.sliding_windows(t, p, window, reference_period=REFERENCE_PERIOD)


def test_windows_follow_a_decaying_amplitude():
    """A wobble whose amplitude halves every 5 years: the windows see it, at the right epochs."""
    rng = np.random.default_rng(11)
    n = int(30 * 365.25)
    t = DAY * np.arange(n)
    s = t - t.mean()
    amp = 150 * MAS * np.exp(-np.log(2) * t / (5 * YEAR))
    p = amp * np.exp(1j * 2 * math.pi / TRUTH["period"] * s) + 90 * MAS * np.exp(1j * pm.ANNUAL_RATE * s)
    p = p + rng.standard_normal(n) * 0.5 * MAS
    w = pm.sliding_windows(t, p, 6 * YEAR, 2 * YEAR, reference_period=REFERENCE_PERIOD)
    expected = 150 * MAS * np.exp(-np.log(2) * w.centre / (5 * YEAR))
    # The window sees the mean of an exponential over +/- 3 yr: cosh-like factor, under 10 %.
    np.testing.assert_allclose(w.amplitude, expected, rtol=0.1)
    assert np.all(np.diff(w.amplitude) < 0)
    np.testing.assert_allclose(w.period, TRUTH["period"], atol=2 * DAY)


def test_old_annual_names_are_deprecated_aliases():
    rng = np.random.default_rng(10)
    t, p = record(rng, 10)
    w = pm.sliding_windows(t, p, 6 * YEAR, 2 * YEAR, reference_period=REFERENCE_PERIOD)
    with pytest.warns(DeprecationWarning, match="annual_prograde_amplitude"):
        np.testing.assert_array_equal(w.annual_amplitude, w.annual_prograde_amplitude)
    with pytest.warns(DeprecationWarning, match="annual_retrograde_amplitude"):
        np.testing.assert_array_equal(w.retrograde_annual_amplitude, w.annual_retrograde_amplitude)
