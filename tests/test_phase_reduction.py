"""reduce_phase keeps |r| <= period/2 (callers rely on it), and what broke when it did not."""

from __future__ import annotations

import numpy as np

from wobble.models.free import free_rotation
from wobble.numerics import highprec as hp
from wobble.numerics.phase import reduce_phase


def test_reduced_phase_stays_within_half_a_period():
    """Phases landing on odd multiples of half a period, 1e5 periods out: rint of the rounded
    quotient used to miss by one and return |r| up to ~|j| eps period beyond period/2."""
    period = hp.to_dd(hp.agm_k(0.3) * 2)
    rate = (1.0, 0.0)
    j = np.arange(100001, 100501)
    t = (j + 0.5) * period[0]
    r, jj = reduce_phase(t, rate, period)
    assert np.all(np.abs(r) <= 0.5 * period[0])
    # The reduction is still exact: t = jj period + r to the rounding of t.
    assert np.max(np.abs((jj * period[0] + r) - t) / t) < 4e-16


def test_free_attitude_is_smooth_at_the_reduction_boundary():
    """Regression: Pi(n; am r | m) from sn and |cn| is mirrored, not continued, past r = K,
    which put errors of 6e-11 rad into the free body's attitude at such times after 1e5 periods."""
    model = free_rotation([1.0, 2.0, 3.0], [1.0, 0.1, 1.0])
    e = model._impl
    lam, k = e.lam[0] + e.lam[1], e.K[0] + e.K[1]
    j = np.arange(100001, 100101)
    t = ((2 * j + 1) * k - e.u0) / lam
    d = 1e-7
    q, qa, qb = model.attitude(t), model.attitude(t - d), model.attitude(t + d)
    assert np.max(np.abs(q - 0.5 * (qa + qb))) < 1e-13
