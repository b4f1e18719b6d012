"""Q from the line shape of a randomly excited damped oscillator of known Q."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, TRUTH, damped_wobble

from wobble.errors import InputError
from wobble.models import polar_motion as pm


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


@pytest.mark.parametrize("true_log_q", [1.3, 1.71, 2.0, 2.64, 3.0])
def test_the_maximum_likelihood_q_lies_between_the_grid_points(true_log_q):
    """The profile is taken on a grid a factor 1.64 apart; the maximum-likelihood Q was the least grid point,
    up to 28 % off. On a deviance exactly quadratic in log Q the vertex of the three points about the least one
    is its minimum (closed form)."""
    from wobble.models.polar_motion.quality import _Q_GRID, _vertex

    logq = np.log10(np.where(np.isfinite(_Q_GRID), _Q_GRID, 1e6))
    dev = 3.7 * (logq - true_log_q) ** 2
    i = int(np.argmin(dev))
    assert _vertex(logq, dev - dev[i], i) == pytest.approx(10**true_log_q, rel=1e-12)
