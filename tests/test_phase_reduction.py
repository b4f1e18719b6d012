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


def test_reduction_stays_exact_past_two_to_the_26_periods():
    """j times each 26-bit piece of the split period is exact only for |j| < 2^26 (6.7e7 periods):
    beyond, the reduction once kept only ulp(rate t), 4e-6 rad of a 1 rad/s spin after 1e11 s.
    j period is now Dekker's exact product there: r to a few ulps of the period (an mpmath
    reduction by the same double-double period) up to |j| ~ 2^47."""
    import mpmath as mp

    from wobble.models.top_closed_form import TWO_PI_DD

    rng = np.random.default_rng(5)
    with mp.workdps(60):
        for period in (TWO_PI_DD, hp.to_dd(hp.agm_k(0.3) * 2)):
            p = mp.mpf(period[0]) + mp.mpf(period[1])
            for rate_hi in (1.0, 0.5, float(mp.sqrt(2))):
                rate = (rate_hi, float(mp.sqrt(2) - mp.mpf(rate_hi)) if rate_hi > 1 else 0.0)
                t = 10.0 ** rng.uniform(6, 15, 40)
                r, j = reduce_phase(t, rate, period, 0.25)
                for ti, ri, ji in zip(t, r, j):
                    x = mp.mpf(ti) * (mp.mpf(rate[0]) + mp.mpf(rate[1])) + mp.mpf(0.25)
                    jj = mp.nint(x / p)
                    assert ji == float(jj)
                    assert abs(float(mp.mpf(ri) - (x - jj * p))) <= 2 * np.spacing(period[0])


def test_compiled_reduction_is_numpys_on_both_sides_of_two_to_the_26():
    from wobble.numerics import compiled

    if not compiled.available():
        return
    from wobble.numerics import taylor_table
    from wobble.numerics.phase import split_dd

    period = hp.to_dd(hp.agm_k(0.3) * 2)
    t = np.concatenate([np.linspace(0.0, 1e6, 50), 10.0 ** np.linspace(6, 15, 200), -(10.0 ** np.linspace(6, 15, 50))])
    lam = (0.7, 1e-17)
    r, j = reduce_phase(t, lam, period, 0.3)
    rc, jc = taylor_table.phase(t, lam, period, 0.3, split_dd(*period))
    assert np.any(np.abs(j) >= 2**26) and np.any(np.abs(j) < 2**26)
    np.testing.assert_array_equal(rc, r)
    np.testing.assert_array_equal(jc, j)


def test_a_free_body_spinning_for_1e13_seconds_keeps_its_attitude():
    """Past 2^26 turns (1 rad/s for 1e11 s and more) a steady spin's attitude stays within its
    stated error of mpmath's (was: 4e-6 rad at 1e11 s, 3e-4 rad at 3e13 s)."""
    import mpmath as mp

    from wobble.numerics import quaternion as Q

    t = np.array([1e9, 1e11, 1e12, 1e13])
    steady = free_rotation([1.0, 1.0, 2.0], [0.0, 0.0, 1.0])
    with mp.workdps(50):
        ang = np.array([float(mp.fmod(mp.mpf(x), 4 * mp.pi)) for x in t])
    want = np.stack([np.cos(ang / 2), 0 * ang, 0 * ang, np.sin(ang / 2)], axis=-1)
    d = Q.multiply(steady.attitude(t), Q.conjugate(want))
    err = 2 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))
    # the reference's own rounding (ang to a float, then cos and sin) is ~4e-16
    assert np.max(err) <= steady.error_estimate["attitude_rad"] + 4.5e-16
