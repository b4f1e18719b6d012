"""``wobble.models.euler_rates`` against closed forms (the symmetric body of notes 5.6), the exact
elliptic solution (its derivative and its period), and the invariants of Euler's equations."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wobble.models.euler_rates import omega_dot, polhode_turn_rate, wobble_angle_rate
from wobble.models.free import free_rotation

EYE = np.eye(3)


def _rotation(a, b, c):
    """A proper rotation from three angles (z-y-z Euler angles)."""

    def rz(t):
        return np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]])

    def ry(t):
        return np.array([[np.cos(t), 0, np.sin(t)], [0, 1, 0], [-np.sin(t), 0, np.cos(t)]])

    return rz(a) @ ry(b) @ rz(c)


moments = st.tuples(*[st.floats(0.5, 2.0)] * 3).filter(lambda m: 2 * max(m) <= sum(m))
omegas = st.tuples(*[st.floats(-3.0, 3.0)] * 3)
angles = st.tuples(*[st.floats(-np.pi, np.pi)] * 3)


@pytest.mark.parametrize("C", [1.3, 0.7])  # oblate and prolate
def test_symmetric_body_turns_at_the_euler_frequency(C):
    # Notes 5.6 (p. 69): omega_1' = -Omega omega_2, omega_2' = Omega omega_1, omega_3' = 0,
    # Omega = (C - A)/A omega_3.
    A, w = 1.0, np.array([0.3, -0.2, 2.5])
    big = (C - A) / A * w[2]
    np.testing.assert_allclose(omega_dot([A, A, C], EYE, w), [-big * w[1], big * w[0], 0.0], rtol=1e-15, atol=1e-16)
    assert polhode_turn_rate([A, A, C], EYE, w) == pytest.approx(abs(big), rel=1e-14)


@pytest.mark.parametrize("w", [[0.0, 0.0, 2.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
def test_a_spin_about_a_principal_axis_and_rest_do_not_turn(w):
    m = [1.0, 2.0, 3.0]
    np.testing.assert_array_equal(omega_dot(m, EYE, w), 0.0)
    assert polhode_turn_rate(m, EYE, w) == 0.0


@pytest.mark.parametrize(
    ("m", "w0"),
    [([1.0, 2.0, 3.0], [0.1, 0.2, 1.0]), ([1.0, 2.0, 3.0], [1.0, 0.3, 0.05]), ([3.0, 1.0, 2.5], [0.4, 0.9, -0.2])],
)
def test_omega_dot_is_the_derivative_of_the_exact_solution(m, w0):
    model = free_rotation(m, w0)
    t = np.linspace(0.0, model.period, 37)
    h = 1e-3 * model.period / (2 * np.pi)
    # Five-point central difference of the exact elliptic omega(t): error ~ h^4 |omega^(5)| ~ 1e-12.
    numeric = (-model.omega(t + 2 * h) + 8 * model.omega(t + h) - 8 * model.omega(t - h) + model.omega(t - 2 * h)) / (
        12 * h
    )
    scale = np.max(np.abs(numeric))
    np.testing.assert_allclose(omega_dot(m, EYE, model.omega(t)), numeric, rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize(
    ("m", "w0", "regime"),
    [([1.0, 2.0, 3.0], [0.1, 0.2, 1.0], "major-axis"), ([1.0, 2.0, 3.0], [1.0, 0.3, 0.05], "minor-axis")],
)
def test_omega_goes_once_round_its_polhode_in_a_period(m, w0, regime):
    model = free_rotation(m, w0)
    assert model.regime == regime
    n = 4096
    t = model.period * np.arange(n) / n  # one period, uniformly: the mean of a periodic rate converges spectrally
    mean = np.mean(polhode_turn_rate(m, EYE, model.omega(t)))
    assert mean == pytest.approx(2 * np.pi / model.period, rel=1e-10)


@settings(max_examples=80, deadline=None)
@given(moments, omegas, angles)
def test_rates_do_not_depend_on_the_frame_omega_is_given_in(m, wp, ang):
    R = _rotation(*ang)  # rows of R.T are the principal axes in the frame of omega = R wp
    w = R @ np.asarray(wp)
    np.testing.assert_allclose(omega_dot(m, R.T, w), R @ omega_dot(m, EYE, wp), rtol=0, atol=1e-12)
    assert polhode_turn_rate(m, R.T, w) == pytest.approx(polhode_turn_rate(m, EYE, wp), rel=1e-9, abs=1e-12)


@settings(max_examples=80, deadline=None)
@given(moments, omegas)
def test_energy_and_angular_momentum_are_constant(m, w):
    # dT/dt = sum I w w' and d|L|^2/dt / 2 = sum I^2 w w' vanish for torque-free motion.
    m, w = np.asarray(m), np.asarray(w)
    wd = omega_dot(m, EYE, w)
    scale = np.max(m) ** 2 * np.sum(w**2) ** 1.5
    assert abs(np.sum(m * w * wd)) <= 1e-14 * scale
    assert abs(np.sum(m**2 * w * wd)) <= 1e-14 * scale * np.max(m)


def test_broadcasts_over_samples_and_bodies():
    m = np.array([[1.0, 2.0, 3.0], [2.0, 2.0, 3.0]])  # two bodies
    axes = np.stack([EYE, _rotation(0.3, 0.4, 0.5).T])
    w = np.random.default_rng(1).normal(size=(5, 2, 3))  # five samples of each
    out = omega_dot(m, axes, w)
    assert out.shape == (5, 2, 3)
    np.testing.assert_allclose(out[3, 1], omega_dot(m[1], axes[1], w[3, 1]), rtol=1e-15, atol=1e-16)
    assert polhode_turn_rate(m, axes, w).shape == (5, 2)


def test_a_wobble_far_above_rounding_turns_at_the_euler_frequency_however_small():
    """A 1e-12 |omega| wobble is a wobble (omega's components carry 1e-16 of |omega|): the old 1e-9 cut
    reported it as a spin that does not turn."""
    A, C, w3 = 1.0, 1.3, 1e4
    w = [1e-12 * w3, 0.0, w3]
    assert polhode_turn_rate([A, A, C], EYE, w) == pytest.approx((C - A) / A * w3, rel=1e-9)
    assert polhode_turn_rate([A, A, C], EYE, [1e-15 * w3, 0.0, w3]) == 0.0  # within rounding: no turn


def test_omega_that_is_not_finite_has_no_rate():
    rates = polhode_turn_rate([1.0, 2.0, 3.0], EYE, [[np.nan, 0.1, 1.0], [0.1, 0.2, 1.0]])
    assert np.isnan(rates[0]) and np.isfinite(rates[1])


def test_the_separatrix_rate_is_about_the_axis_its_comparison_picks():
    """On the separatrix omega turns about no axis: a change in its last bit picks the largest or the
    smallest moment's axis. With omega = (w1, 0, w3), Euler gives w1' = w3' = 0 and
    w2' = (I3 - I1)/I2 w3 w1, so the rate is (I3 - I1)/I2 w3 about axis 3 and (I3 - I1)/I2 w1 about axis 1."""
    m = np.array([1.0, 2.0, 3.0])
    w3 = 1.0
    w1 = np.sqrt(m[2] * (m[2] - m[1]) / (m[0] * (m[1] - m[0]))) * w3  # L^2 = 2 T I2
    k = (m[2] - m[0]) / m[1]
    # A larger w1 lowers L^2 - 2 T I2 = sum I_i (I_i - I2) w_i^2: omega then circles the smallest axis.
    assert polhode_turn_rate(m, EYE, [w1 * (1 + 1e-15), 0.0, w3]) == pytest.approx(k * w1, rel=1e-12)
    assert polhode_turn_rate(m, EYE, [w1 * (1 - 1e-15), 0.0, w3]) == pytest.approx(k * w3, rel=1e-12)


@pytest.mark.parametrize(("m", "w0"), [([1.0, 2.0, 3.0], [0.1, 0.2, 1.0]), ([3.0, 1.0, 2.5], [0.4, 0.9, -0.2])])
def test_the_wobble_angle_rate_is_the_derivative_of_the_exact_wobble_angle(m, w0):
    model = free_rotation(m, w0)
    t = np.linspace(0.0, model.period, 37)
    h = 1e-3 * model.period / (2 * np.pi)

    def angle(times):
        w = model.omega(times)
        return np.arctan2(np.hypot(w[:, 0], w[:, 1]), w[:, 2])

    numeric = (-angle(t + 2 * h) + 8 * angle(t + h) - 8 * angle(t - h) + angle(t - 2 * h)) / (12 * h)
    scale = np.max(np.abs(numeric))
    np.testing.assert_allclose(wobble_angle_rate(m, EYE, model.omega(t)), numeric, rtol=0, atol=1e-8 * scale)
    assert scale > 0


def test_a_symmetric_body_s_wobble_angle_is_constant_and_a_body_at_rest_has_no_rate():
    # Notes 5.6: omega turns about axis 3 at a fixed angle for A = B.
    w = np.array([[0.3, -0.2, 2.5], [0.1, 0.0, 1.0]])
    np.testing.assert_allclose(wobble_angle_rate([1.0, 1.0, 1.3], EYE, w), 0.0, atol=1e-16)
    assert wobble_angle_rate([1.0, 2.0, 3.0], EYE, [0.0, 0.0, 0.0]) == 0.0
