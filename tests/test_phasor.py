"""Block-rotated phasors on uniform grids (wobble.numerics.phasor) against direct evaluation."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wobble.numerics import nome_grid
from wobble.numerics.phasor import block_phasors, uniform_grid

# The NumPy test and the compiled one (wobble.numerics.nome_grid) decide alike.
GRID_TESTS = [uniform_grid, nome_grid.uniform_grid]


@pytest.mark.parametrize("uniform_grid", GRID_TESTS)
def test_uniform_grids_are_recognised(uniform_grid):
    assert uniform_grid(np.arange(36526) * 86400.0) == (0.0, 86400.0)
    t0, dt = uniform_grid(np.linspace(-3.0, 7.0, 1001))
    assert t0 == -3.0 and abs(dt - 0.01) < 1e-17


@pytest.mark.parametrize("uniform_grid", GRID_TESTS)
def test_other_arrays_are_not_grids(uniform_grid):
    t = np.linspace(0.0, 1.0, 1001)
    bumped = t.copy()
    bumped[500] += 1e-12
    assert uniform_grid(bumped) is None
    assert uniform_grid(t[:100]) is None  # too short to be worth it
    assert uniform_grid(t.reshape(7, 143)) is None
    assert uniform_grid(t[::-1]) is None  # decreasing
    assert uniform_grid(np.geomspace(1.0, 2.0, 1001)) is None
    with_nan = t.copy()
    with_nan[7] = np.nan
    assert uniform_grid(with_nan) is None


@settings(max_examples=30, deadline=None)
@given(
    rate=st.floats(1e-3, 50.0),
    phase=st.floats(-3.0, 3.0),
    t0=st.floats(-100.0, 100.0),
    dt=st.floats(1e-3, 1.0),
    n=st.integers(1, 5000),
)
def test_block_rotation_equals_exp_of_the_phase(rate, phase, t0, dt, n):
    """exp(i (rate t + phase)) on t0 + k dt: a few ulps of each sample, no growth along the grid."""

    def phasor(t):
        return np.exp(1j * (rate * t + phase))

    z = block_phasors(phasor, t0, dt, n)
    t = t0 + np.arange(n) * dt
    direct = np.exp(1j * (rate * t + phase))
    # The direct form and the phasor given both round the angle to eps |rate t + phase|: allow
    # that twice (block start and step each carry it), plus a few ulps of the products.
    tol = 1e-15 + 4.5e-16 * np.max(np.abs(rate * t + phase))
    assert z.shape == (n,)
    assert np.max(np.abs(z - direct)) <= tol


def test_a_century_of_days_against_mpmath():
    """A 433-day wobble sampled daily for 100 years, exact phasors given: every sample to 1e-15.

    The phasor at the block starts and first block is reduced exactly (double-double rate,
    :func:`wobble.numerics.phase.reduce_phase`), so the block rotation adds only the rounding of
    one complex product; checked against mpmath at 30 digits on every 97th day.
    """
    from wobble.numerics import highprec as hp
    from wobble.numerics.phase import reduce_phase

    mpmath.mp.dps = 30
    rate = hp.to_dd(2 * hp.PI / (433 * 86400))
    two_pi = hp.to_dd(2 * hp.PI)

    def phasor(t):
        r, _ = reduce_phase(t, rate, two_pi, 0.3)
        return np.cos(r) + 1j * np.sin(r)

    z = block_phasors(phasor, 0.0, 86400.0, 36526)
    exact_rate = mpmath.mpf(rate[0]) + mpmath.mpf(rate[1])
    for k in range(0, 36526, 97):
        ang = exact_rate * (k * 86400) + mpmath.mpf(0.3)
        want = complex(mpmath.cos(ang), mpmath.sin(ang))
        assert abs(z[k] - want) < 1e-15
