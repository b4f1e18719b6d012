"""The blocked linear recurrence against the step-by-step one and its closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from wobble.numerics.recurrence import BLOCK, linear_recurrence

A = (1j * 2 * np.pi / 86.6 - 0.0036) * 1.0  # a 433-day wobble of Q = 100, five-day steps (in steps)


@pytest.mark.parametrize("n", [1, 2, BLOCK, BLOCK + 1, 3 * BLOCK + 17, 4730])
def test_equals_the_step_by_step_recurrence(n):
    rng = np.random.default_rng(n)
    first = rng.standard_normal(5) + 1j * rng.standard_normal(5)
    kicks = rng.standard_normal((n - 1, 5)) + 1j * rng.standard_normal((n - 1, 5))
    want = np.empty((n, 5), dtype=complex)
    want[0] = first
    lam = np.exp(A)
    for k in range(1, n):
        want[k] = lam * want[k - 1] + kicks[k - 1]
    got = linear_recurrence(first, A, kicks)
    assert got.shape == (n, 5)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())


def test_closed_forms():
    """No kicks: x_k = lambda^k x_0. A constant kick c from x_0 = 0: x_k = c (1 - lambda^k) / (1 - lambda)."""
    k = np.arange(1000)
    free = linear_recurrence([2.0 - 1.0j], A, np.zeros((999, 1)))
    np.testing.assert_allclose(free[:, 0], (2.0 - 1.0j) * np.exp(A * k), rtol=1e-13)
    forced = linear_recurrence([0.0], A, np.full((999, 1), 0.5 + 0.25j))
    np.testing.assert_allclose(forced[:, 0], (0.5 + 0.25j) * np.expm1(A * k) / np.expm1(A), rtol=1e-12)
