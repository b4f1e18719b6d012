"""A randomly excited wobble: the Monte-Carlo excitation term makes the period error honest."""

from __future__ import annotations

import numpy as np
import pytest
from polar_synthetic import REFERENCE_PERIOD, TRUTH, record

from wobble.models import polar_motion as pm


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
        f = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=100.0, draws=16)
        err = f.chandler.period - TRUTH["period"]
        z.append(err / f.chandler.period_sigma)
        z_auto.append(err / f.period_uncertainty.autocorrelation)
    z = np.array(z)
    assert np.all(np.abs(z) < 3.0), z
    assert 0.1 < np.mean(z**2) < 3.0, z
    assert np.mean(np.square(z_auto)) > 4 * np.mean(z**2)


@pytest.mark.parametrize(("n", "lag_days", "gaps"), [(400, 50, False), (731, 365, True), (64, 63, False)])
def test_hac_meat_is_the_bartlett_sum_of_autocovariances(n, lag_days, gaps):
    """hac_meat (FFTs of the half spectrum) against its definition, sum over |k| <= L of (1 - |k|/(L+1)) x
    the lag-k cross products of the scores, with the missing days as zeros (Newey & West 1987)."""
    from wobble.models.polar_motion.uncertainty import hac_meat

    rng = np.random.default_rng(n)
    days = np.arange(n)
    if gaps:
        days = days[(rng.random(n) > 0.2) | (days == 0) | (days == n - 1)]
    scores = rng.standard_normal((days.size, 5))
    full = np.zeros((n, 5))
    full[days] = scores
    want = np.zeros((5, 5))
    for k in range(-lag_days, lag_days + 1):
        a, b = (full[k:], full[: n - k]) if k >= 0 else (full[: n + k], full[-k:])
        want += (1 - abs(k) / (lag_days + 1)) * a.T @ b
    got = hac_meat(days * 86400.0, scores, lag_days * 86400.0)
    np.testing.assert_allclose(got, 0.5 * (want + want.T), rtol=0, atol=1e-12 * np.abs(want).max())
