"""The exact free flow as a map (omega, q) -> (omega, q): against the exact solution free_rotation.

free_rotation is itself checked against mpmath (tests/test_free_model.py); the flow
map shares its formulas but starts from a state, in floats, vectorised.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, reject, settings
from hypothesis import strategies as st
from reference_odes import attitude_angle as angle

from wobble.errors import InputError
from wobble.models.free import free_rotation
from wobble.models.free_flow import flow_many, flow_one, flow_sorted, free_flow
from wobble.numerics import quaternion as Q

EPS = np.finfo(float).eps


CASES = [
    ("major axis", [1, 2, 3], [1, 0.1, 1]),
    ("minor axis", [1, 2, 3], [1, 0.2, 0.1]),
    ("axes permuted", [3, 1, 2], [0.3, 1, 0.2]),
    ("another order", [2, 3, 1], [1, -1, 0.5]),
    ("near separatrix", [1, 2, 3], [1e-6, 1, 1e-6]),
    ("oblate symmetric", [1, 1, 2], [0.3, 0.1, 1]),
    ("prolate symmetric", [2, 1, 1], [1, 0.2, 0.3]),
    ("principal axis", [1, 2, 3], [0, 0, 1]),
    ("intermediate axis exactly", [1, 2, 3], [0, 1, 0]),
    ("sphere", [1, 1, 1], [1, 2, 3]),
    ("at rest", [1, 2, 3], [0, 0, 0]),
    ("exact separatrix", [2, 5, 6], [1, 0, 1]),
    ("exact separatrix, other branch", [2, 5, 6], [1, 0.3, -1]),
    ("negative components", [1, 2, 3], [-1, 0.1, -1]),
]
STEPS = np.array([1e-4, 0.1, 1.0, 7.3, 50.0, -3.0])


@pytest.mark.parametrize("name, moments, omega", CASES, ids=[c[0] for c in CASES])
def test_flow_from_t0_is_the_exact_solution(name, moments, omega):
    exact = free_rotation(moments, omega)
    n = STEPS.size
    w1, q1 = free_flow(moments, np.tile(omega, (n, 1)), np.tile([1.0, 0, 0, 0], (n, 1)), STEPS)
    scale = max(np.max(np.abs(omega)), 1e-300)
    assert np.max(np.abs(w1 - exact.omega(STEPS))) <= 64 * EPS * scale
    assert np.max(angle(q1, exact.attitude(STEPS))) < 1e-13


@pytest.mark.parametrize("name, moments, omega", [c for c in CASES if "separatrix" not in c[0]], ids=lambda c: str(c))
def test_chained_steps_follow_the_exact_solution(name, moments, omega):
    """Steps started from the state at t0 = 5 s land on the exact solution at 5 s + h."""
    exact = free_rotation(moments, omega)
    t0 = np.array([5.0])
    n = STEPS.size
    w0 = np.tile(exact.omega(t0)[0], (n, 1))
    q0 = np.tile(exact.attitude(t0)[0], (n, 1))
    w1, q1 = free_flow(moments, w0, q0, STEPS)
    scale = max(np.max(np.abs(omega)), 1e-300)
    assert np.max(np.abs(w1 - exact.omega(t0 + STEPS))) <= 1e-13 * scale
    assert np.max(angle(q1, exact.attitude(t0 + STEPS))) < 1e-13


def test_many_small_steps_accumulate_only_rounding():
    """1000 steps of 0.1 s reproduce the exact solution at 100 s (generic body)."""
    moments, omega = [1.0, 2.0, 3.0], [1.0, 0.1, 1.0]
    exact = free_rotation(moments, omega)
    w, q = np.array([omega]), np.array([[1.0, 0, 0, 0]])
    for _ in range(1000):
        w, q = free_flow(moments, w, q, 0.1)
    t = np.array([100.0])
    assert np.max(np.abs(w - exact.omega(t))) < 1e-12
    assert angle(q, exact.attitude(t))[0] < 1e-12


def test_long_step_error_grows_like_the_float_phase():
    """One step over many periods: the error stays within 64 eps (1 + |omega| t) (the ensemble bound)."""
    moments, omega = [1.0, 2.0, 3.0], [1.0, 0.1, 1.0]
    exact = free_rotation(moments, omega)
    h = np.array([1e2, 1e3, 1e4])
    w, q = free_flow(moments, np.tile(omega, (3, 1)), np.tile([1.0, 0, 0, 0], (3, 1)), h)
    bound = 64 * EPS * (1 + np.linalg.norm(omega) * h)
    amp = np.max(np.abs(exact.omega(np.linspace(0, 20, 2001))), axis=0)
    assert np.all(np.max(np.abs(w - exact.omega(h)) / amp, axis=1) <= bound)
    assert np.all(angle(q, exact.attitude(h)) <= bound)


def test_one_member_path_equals_the_vectorised_path():
    """Python-float single member and the NumPy path: the same formulas to rounding."""
    rng = np.random.default_rng(5)
    n = 400
    moments = np.sort(rng.uniform(0.5, 2.0, (n, 3)), axis=1)
    moments[:20] = [1.0, 1.0, 2.0]
    moments[20:40] = [1.0, 2.0, 2.0]
    omega = rng.normal(size=(n, 3))
    omega[40] = [0, 0, 1]
    omega[41] = [0, 1, 0]
    h = rng.uniform(-20, 20, n)
    with np.errstate(all="ignore"):
        w_all, dq_all = flow_many(moments, omega, h, True)
    for k in range(n):
        w1, dq1 = flow_sorted(moments[k : k + 1], omega[k : k + 1], h[k : k + 1], True)
        assert np.max(np.abs(w1[0] - w_all[k])) <= 1e-13 * np.max(np.abs(omega[k]))
        assert abs(abs(np.dot(dq1[0], dq_all[k])) - 1) < 1e-14


def test_ensemble_of_bodies_equals_member_by_member():
    rng = np.random.default_rng(2)
    n = 50
    moments = rng.uniform(1.0, 2.0, (n, 3))
    omega = rng.normal(size=(n, 3))
    q = Q.normalize(rng.normal(size=(n, 4)))
    w_all, q_all = free_flow(moments, omega, q, 2.5)
    for k in range(n):
        w1, q1 = free_flow(moments[k], omega[k : k + 1], q[k : k + 1], 2.5)
        assert np.allclose(w1[0], w_all[k], rtol=0, atol=1e-13 * np.max(np.abs(omega[k])))
        assert angle(q1[0], q_all[k]) < 1e-13


@settings(max_examples=60)
@given(
    st.lists(st.floats(0.5, 2.0), min_size=3, max_size=3),
    st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3),
    st.floats(-30.0, 30.0),
)
def test_invariants_and_unit_quaternion(moments, omega, h):
    """Energy and |L| are those of the initial state; the attitude is a unit quaternion; L is fixed in space."""
    s = sorted(moments)
    if s[0] + s[1] < s[2]:
        moments = [s[0], s[1], s[0] + s[1]]
    I = np.array(moments)
    w0 = np.array([omega])
    q0 = Q.normalize(np.array([[0.9, 0.1, -0.3, 0.2]]))
    try:
        w1, q1 = free_flow(I, w0, q0, h)
    except InputError:
        reject()  # within ~1e-75 of the separatrix: refused by design (test_the_float64_limit_...)
    e0, e1 = 0.5 * np.sum(I * w0**2), 0.5 * np.sum(I * w1**2)
    l0, l1 = Q.rotate(q0, I * w0), Q.rotate(q1, I * w1)
    big = max(np.linalg.norm(I * w0), 1e-300)
    assert abs(e1 - e0) <= 1e-13 * max(e0, 1e-300) + 1e-300
    assert np.max(np.abs(l1 - l0)) <= 1e-12 * big
    assert abs(np.linalg.norm(q1) - 1) < 4 * EPS


@settings(max_examples=40)
@given(st.floats(-np.pi, np.pi), st.floats(0.1, 3.0), st.floats(-10.0, 10.0))
def test_rotation_invariance(angle_z, spin, h):
    """Turning the initial attitude turns the whole motion: omega unchanged, q rotated."""
    I = [1.0, 1.7, 2.3]
    w0 = np.array([[0.3, -0.2, spin]])
    q0 = np.array([[1.0, 0, 0, 0]])
    r = Q.from_axis_angle(np.array([0.0, 0.0, 1.0]), angle_z)[None]
    w_a, q_a = free_flow(I, w0, q0, h)
    w_b, q_b = free_flow(I, w0, Q.multiply(r, q0), h)
    assert np.allclose(w_a, w_b, rtol=0, atol=1e-15)
    assert angle(Q.multiply(r, q_a), q_b)[0] < 1e-14


# The two implementations of the flow map (flow_many in NumPy, flow_one in Python floats) are
# the same formulas written twice for speed; generated states of every regime hold them equal.
_moments = st.lists(st.floats(0.5, 2.0), min_size=3, max_size=3).map(sorted)


@st.composite
def _states(draw):
    kind = draw(st.sampled_from(["generic", "symmetric", "steady", "separatrix"]))
    if kind == "separatrix":
        # I = (2, 5, 6), omega = (s, w, s): L^2 = 2 E I2 exactly for any s, w (s a short binary fraction).
        s = draw(st.integers(1, 64)) / 16 * draw(st.sampled_from([1.0, -1.0]))
        return [2.0, 5.0, 6.0], [s, draw(st.floats(-2.0, 2.0)), s]
    moments = draw(_moments)
    if moments[0] + moments[1] < moments[2]:
        moments[2] = moments[0] + moments[1]
    if kind == "symmetric":
        moments[1] = moments[draw(st.sampled_from([0, 2]))]
    # Components are zero or at least 1e-12 of the largest: states nearer the separatrix than
    # 1 - m ~ 1e-24 reach Carlson integrals at arguments near the underflow threshold, where
    # SciPy's R_F, R_C and R_J return inf or NaN: a limit of the kernels, not of this equivalence.
    omega = draw(
        st.lists(st.one_of(st.just(0.0), st.floats(1e-6, 2.0), st.floats(-2.0, -1e-6)), min_size=3, max_size=3)
    )
    if kind == "steady":
        axis = draw(st.integers(0, 2))
        omega = [omega[k] if k == axis else 0.0 for k in range(3)]
    return moments, omega


@settings(max_examples=200)
@given(_states(), st.floats(-40.0, 40.0), st.booleans())
def test_one_member_flow_equals_the_vectorised_flow_in_every_regime(state, h, attitude):
    moments, omega = state
    I, w = np.array([moments]), np.array([omega])
    outcomes = []
    for run in (
        lambda: flow_many(I, w, np.array([h]), attitude),
        lambda: flow_one(tuple(moments), tuple(omega), h, attitude),
    ):
        try:
            with np.errstate(all="ignore"):
                outcomes.append(run())
        except InputError as exc:
            outcomes.append(exc)
    refused = [isinstance(o, InputError) for o in outcomes]
    assert refused[0] == refused[1], outcomes  # both refuse a state beyond float64, or neither
    if refused[0]:
        return
    (w_many, dq_many), (w_one, dq_one) = outcomes
    scale = max(np.max(np.abs(omega)), 1e-300)
    assert np.max(np.abs(np.array(w_one) - w_many[0])) <= 1e-13 * scale
    if attitude:
        assert abs(abs(np.dot(dq_one, dq_many[0])) - 1) < 1e-13
    else:
        assert dq_one is None and dq_many is None


@pytest.mark.parametrize("tiny", [1e-80, 1e-100, 5.9e-155, 4e-177])
def test_the_float64_limit_next_to_the_separatrix_is_a_clear_error(tiny):
    """A spin within ~1e-75 of the intermediate axis has 1 - m below 1e-150 (or below the
    float range): the integrals of the third kind leave double precision there. Refused with
    the reason, by the exact solution and by both flow implementations, never NaN or a crash."""
    state = [0.0, 1.0, tiny]
    with pytest.raises(InputError, match="separatrix"):
        free_rotation([1.0, 1.5, 2.0], state)
    with pytest.raises(InputError, match="omega"):
        free_flow([1.0, 1.5, 2.0], np.array([state]), np.array([[1.0, 0, 0, 0]]), np.array([3.0]))
    with pytest.raises(InputError, match="omega"):
        flow_one((1.0, 1.5, 2.0), tuple(state), 3.0)


def test_the_nearest_computed_state_to_the_separatrix_is_exact():
    """1 - m = 2.7e-140, just inside the limit: the flow is the exact solution, to rounding."""
    moments, state = [1.0, 1.5, 2.0], [0.0, 1.0, 1e-70]
    exact = free_rotation(moments, state)
    t = np.array([0.5, 3.0, 300.0])
    w1, q1 = free_flow(moments, np.tile(state, (3, 1)), np.tile([1.0, 0, 0, 0], (3, 1)), t)
    assert np.all(np.isfinite(exact.attitude(t))) and np.all(np.isfinite(q1))
    assert np.max(np.abs(w1 - exact.omega(t))) < 1e-13
    assert np.max(angle(q1, exact.attitude(t))) < 1e-12
