"""The vectorised integrators on problems with closed forms: orders, error control, ensembles, blocks."""

from __future__ import annotations

import numpy as np
import pytest

from wobble.numerics.integrators import COMPOSITIONS, DOP853, Splitting, StepLimitError, composition


def oscillators(t, y, idx):
    """x'' = -k^2 x with k per member (the third state component)."""
    return np.stack([y[:, 1], -(y[:, 2] ** 2) * y[:, 0], 0 * y[:, 2]], -1)


def test_dop853_tracks_cosines_to_its_tolerance():
    k = np.array([0.5, 1.0, 3.0, 10.0])
    y0 = np.stack([np.ones(4), np.zeros(4), k], -1)
    solver = DOP853(oscillators, 0.0, y0, rtol=1e-11, atol=1e-13)
    t = np.linspace(0, 20, 401)
    y = solver.advance(t)
    err = np.abs(y[..., 0] - np.cos(k * t[:, None]))
    assert err.max() < 1e-8
    # per-member control: the fast member takes more steps, the slow ones are not dragged along
    assert solver.n_steps[0] < solver.n_steps[-1] / 5


def test_ensemble_members_are_integrated_as_if_alone():
    k = np.array([0.7, 2.0, 5.0])
    y0 = np.stack([np.ones(3), np.zeros(3), k], -1)
    t = np.linspace(0, 7, 50)
    together = DOP853(oscillators, 0.0, y0, rtol=1e-9, atol=1e-12).advance(t)
    for i in range(3):
        alone = DOP853(oscillators, 0.0, y0[i : i + 1], rtol=1e-9, atol=1e-12).advance(t)
        # bit for bit: results do not depend on which other members share the arrays
        # (issue 9: a sweep's numbers must not depend on its chunking)
        np.testing.assert_array_equal(alone[:, 0], together[:, i])


def test_blocks_continue_the_same_run():
    y0 = np.array([[1.0, 0.0, 2.0]])
    t = np.linspace(0, 10, 101)
    whole = DOP853(oscillators, 0.0, y0, rtol=1e-12, atol=1e-14).advance(t)
    solver = DOP853(oscillators, 0.0, y0, rtol=1e-12, atol=1e-14)
    parts = np.concatenate([solver.advance(t[:40]), solver.advance(t[40:])])
    assert np.max(np.abs(parts - whole)) < 1e-11


def test_dop853_is_of_order_eight():
    y0 = np.array([[1.0, 0.0, 1.0]])
    errors = []
    for h in (0.4, 0.2, 0.1):
        solver = DOP853(oscillators, 0.0, y0, rtol=1e-6, atol=1e-6, fixed_step=h)
        errors.append(abs(solver.advance([0.0, 8.0])[-1, 0, 0] - np.cos(8.0)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 8) < 0.6), orders


def test_step_budget_is_enforced():
    solver = DOP853(oscillators, 0.0, np.array([[1.0, 0.0, 50.0]]), rtol=1e-12, atol=1e-14, max_steps=10)
    with pytest.raises(StepLimitError):
        solver.advance([0.0, 100.0])


def test_output_times_must_increase():
    solver = DOP853(oscillators, 0.0, np.array([[1.0, 0.0, 1.0]]), rtol=1e-8, atol=1e-10)
    with pytest.raises(ValueError):
        solver.advance([1.0, 0.5])


@pytest.mark.parametrize("order", sorted(COMPOSITIONS))
def test_composition_coefficients_are_consistent(order):
    a, b = composition(order)
    assert np.isclose(a.sum(), 1.0, atol=1e-14) and np.isclose(b.sum(), 1.0, atol=1e-14)
    np.testing.assert_allclose(a, a[::-1], atol=1e-15)  # symmetric: even order
    if order > 2:
        assert abs(np.sum(a**3)) < 1e-13  # the third-order condition of compositions of a 2nd-order method
    if order > 4:
        assert abs(np.sum(a**5)) < 1e-13


def _pendulum_split():
    """A pendulum q'' = -sin q split into drift (q += h p) and kick (p -= h sin q): both exact."""

    def drift(state, t, h):
        q, p = state
        return q + h * p, p

    def kick(state, t, h):
        q, p = state
        return q, p - h * np.sin(q)

    return drift, kick


@pytest.mark.parametrize("order", [2, 4, 6])
def test_splitting_orders(order):
    drift, kick = _pendulum_split()
    y0 = (np.array([1.0]), np.array([0.0]))
    ref = Splitting(drift, kick, 0.0, y0, order=6, step=1e-3).advance([5.0])[0][0]
    errors = []
    for h in (0.2, 0.1, 0.05):
        errors.append(abs(Splitting(drift, kick, 0.0, y0, order=order, step=h).advance([5.0])[0][0] - ref)[0])
    measured = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(measured - order) < 0.3), measured


def test_splitting_lands_on_every_output_and_counts_steps():
    drift, kick = _pendulum_split()
    s = Splitting(drift, kick, 0.0, (np.array([0.5]), np.array([0.0])), order=2, step=0.3, multiple=2)
    states = s.advance([0.0, 0.1, 1.0])
    assert len(states) == 3 and s.t == 1.0
    assert s.n_steps == 2 + 4  # 0.1 s: two steps (a multiple of 2); 0.9 s: 4 steps of 0.225 s
