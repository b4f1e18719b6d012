"""The compiled DOP853 (wobble.numerics.rigid_dop853) against ground truth and against the NumPy DOP853.

Ground truth: the mpmath Taylor references (tests/references/engine_torqued.json), closed
forms (constant torque on a sphere, linear damping). The compiled and the NumPy integrators
are the same method step for step, so they must also take the same steps and agree to
rounding on every built-in torque (a check that the compiled torque program is the torque).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_engine import CASES, ID, errors, reference_case

from wobble.errors import InputError
from wobble.models.engine import (
    BodyModel,
    ConstantTorque,
    CustomTorque,
    Engine,
    GravityGradient,
    LinearDamping,
    MagneticDipole,
    ThirdBody,
    UniformGravity,
    attitude_angle,
    simulate,
)
from wobble.models.orbit import KeplerOrbit
from wobble.numerics import quaternion as Q
from wobble.numerics.integrators import StepLimitError
from wobble.numerics.rigid_dop853 import RigidDOP853

BACKENDS = ("compiled", "python")


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("name", sorted(CASES))
def test_both_backends_against_mpmath(name, backend):
    engine, w0, q0, t, w_ref, q_ref = reference_case(name)
    run = engine.integrate(w0, q0, t, method="dop853", rtol=1e-12, backend=backend)
    assert run.stats["backend"] == backend
    err_w, err_q = errors(run, w_ref, q_ref)
    assert err_w < 1e-9 and err_q < 1e-9, (err_w, err_q)
    assert err_w <= run.error.omega_relative[0] and err_q <= run.error.attitude[0]


@pytest.mark.parametrize("backend", BACKENDS)
def test_constant_torque_on_a_sphere_and_damping_closed_forms(backend):
    """omega = omega0 + tau t / I about a fixed axis; omega = omega0 exp(-c t / I) with damping."""
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    t = np.linspace(0, 10, 21)
    run = simulate([2.0] * 3, 0.5 * axis, ID, t, [ConstantTorque(0.3 * axis)], rtol=1e-12, backend=backend)
    np.testing.assert_allclose(run.omega[:, 0], (0.5 + 0.3 * t[:, None] / 2.0) * axis, rtol=0, atol=1e-12)
    want = Q.from_axis_angle(axis, 0.5 * t + 0.5 * 0.3 * t**2 / 2.0)
    assert np.max(attitude_angle(run.attitude[:, 0], want)) < 1e-11
    t = np.linspace(0, 4, 9)
    damped = simulate(
        [2.0] * 3, [0.0, 0.0, 3.0], ID, t, [LinearDamping(0.5)], rtol=1e-12, attitude=False, backend=backend
    )
    np.testing.assert_allclose(damped.omega[:, 0, 2], 3.0 * np.exp(-0.25 * t), rtol=1e-11)


def _every_kind(n):
    rng = np.random.default_rng(5)
    return [
        ConstantTorque([0.01, -0.02, 0.005]),
        ConstantTorque(0.01 * rng.normal(size=(n, 3)), frame="inertial"),
        UniformGravity(rng.uniform(0.5, 1.5, n), [0.05, -0.02, 0.1]),
        UniformGravity(0.3, [0.0, 0.1, 0.0], gravity=[0.0, 1.0, -3.0]),
        GravityGradient(3.986004418e14, 6.9e6, orbit_normal=[0.1, 0.2, 1.0], phase=0.4),
        GravityGradient(4.0e13, 6.0e6, direction=[0.3, -0.5, 0.8]),
        MagneticDipole(0.02 * rng.normal(size=(n, 3)), [1e-3, -2e-3, 0.5]),
        ThirdBody(3.0e14, orbit=KeplerOrbit(6.5e6, 0.4, 0.6, 0.3, 1.2, 0.1, 0.5, 0.02, -0.03)),
        LinearDamping([0.001, 0.002, 0.003]),
    ]


def test_compiled_takes_the_numpy_integrators_steps_for_every_torque_kind():
    n = 5
    rng = np.random.default_rng(2)
    moments = np.sort(rng.uniform(0.8, 1.6, size=(n, 3)), axis=-1)
    w0 = rng.normal(size=(n, 3)) + [0.0, 0.0, 2.0]
    q0 = Q.normalize(rng.normal(size=(n, 4)))
    t = np.linspace(0.0, 8.0, 9)
    engine = Engine(BodyModel.from_moments(moments), _every_kind(n), members=n)
    a = engine.integrate(w0, q0, t, rtol=1e-10, backend="compiled")
    b = engine.integrate(w0, q0, t, rtol=1e-10, backend="python")
    for k in ("steps", "rejected", "function_evaluations"):
        assert a.stats[k] == b.stats[k], k
    scale = np.max(np.abs(b.omega), axis=0)
    assert np.max(np.abs(a.omega - b.omega) / scale) < 1e-12
    assert np.max(attitude_angle(a.attitude, b.attitude)) < 1e-12
    np.testing.assert_allclose(a.error.omega_relative, b.error.omega_relative, rtol=0, atol=1e-13)


@pytest.mark.parametrize("backend", BACKENDS)
def test_conservative_torque_program_conserves_energy(backend):
    """Gravity about a pivot (per-member masses) plus a fixed-direction tidal torque: both have a
    potential, so E = T + V is constant (ground truth independent of either integrator)."""
    n = 3
    moments = np.array([1.0, 1.4, 1.9])
    torques = [
        UniformGravity([0.6, 0.8, 1.0], [0.05, -0.1, 0.2]),
        GravityGradient(2.0, 1.0, direction=[0.3, -0.5, 0.8]),
    ]  # k = 6 s^-2: as strong as gravity
    engine = Engine(BodyModel.from_moments(moments), torques, members=n)
    w0 = np.array([[0.3, -0.2, 5.0], [1.0, 0.5, 2.0], [-0.4, 2.0, 0.7]])
    q0 = Q.normalize(np.array([[0.9, 0.2, -0.1, 0.3], [0.5, 0.5, 0.5, 0.5], [1.0, 0.0, 0.0, 0.0]]))
    t = np.linspace(0.0, 20.0, 41)
    run = engine.integrate(w0, q0, t, rtol=1e-12, backend=backend)
    energy = np.array([engine.energy(tk, *engine.state_in(run.omega[k], run.attitude[k])) for k, tk in enumerate(t)])
    drift = np.max(np.abs(energy - energy[0]), axis=0) / np.abs(energy[0])
    assert np.all(drift < 1e-10), drift


def test_omega_only_when_no_torque_needs_the_attitude():
    """A body-frame torque and damping: the state is omega alone (3 components)."""
    t = np.linspace(0.0, 3.0, 4)
    torques = [ConstantTorque([0.0, 0.1, 0.0]), LinearDamping(0.2)]
    a = simulate([1.0, 2.0, 2.5], [0.3, 0.1, 1.0], ID, t, torques, attitude=False, backend="compiled")
    b = simulate([1.0, 2.0, 2.5], [0.3, 0.1, 1.0], ID, t, torques, attitude=False, backend="python")
    assert a.attitude is None and b.attitude is None
    assert np.max(np.abs(a.omega - b.omega)) < 1e-14


def test_threads_do_not_change_a_bit():
    """Members are split in blocks between threads; each member's steps are its own."""
    n = 600
    rng = np.random.default_rng(9)
    engine = Engine(BodyModel.from_moments([1.0, 1.5, 2.0]), [UniformGravity(1.0, [0.1, 0.0, 0.3])], members=n)
    w, q = engine.state_in(rng.normal(size=(n, 3)) + [0, 0, 6], Q.normalize(rng.normal(size=(n, 4))))
    y0 = np.concatenate([w, q], axis=1)
    t = np.linspace(0.0, 2.0, 5)
    runs = [RigidDOP853(engine.program(), 0.0, y0, rtol=1e-9, atol=1e-9, workers=k).advance(t) for k in (1, 2, 3)]
    np.testing.assert_array_equal(runs[0], runs[1])
    np.testing.assert_array_equal(runs[0], runs[2])


def test_advance_continues_where_it_stopped():
    """Two calls give what one call gives at the same outputs (the state carries over)."""
    engine = Engine(BodyModel.from_moments([1.0, 1.5, 2.0]), [UniformGravity(1.0, [0.1, 0.0, 0.3])])
    w, q = engine.state_in([0.2, 0.1, 7.0], [0.9, 0.3, 0.0, 0.1])
    y0 = np.concatenate([w, q], axis=1)
    t = np.linspace(0.0, 4.0, 9)
    whole = RigidDOP853(engine.program(), 0.0, y0, rtol=1e-11, atol=1e-11).advance(t)
    split = RigidDOP853(engine.program(), 0.0, y0, rtol=1e-11, atol=1e-11)
    parts = np.concatenate([split.advance(t[:5]), split.advance(t[5:])])
    assert np.max(np.abs(parts - whole)) < 1e-9


def test_custom_torques_run_in_numpy_and_refuse_the_compiled_backend():
    custom = [CustomTorque(lambda tt, w, q: -0.1 * w)]
    run = simulate([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], ID, [0.0, 1.0], custom)
    assert run.stats["backend"] == "python"
    np.testing.assert_allclose(run.omega[-1, 0, 2], np.exp(-0.1 / 3.0), rtol=1e-9)
    with pytest.raises(InputError, match="backend"):
        simulate([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], ID, [0.0, 1.0], custom, backend="compiled")
    with pytest.raises(InputError, match="backend"):
        simulate([1.0, 2.0, 3.0], [0.0, 0.0, 1.0], ID, [0.0, 1.0], backend="fortran")


def test_step_budget_and_bad_tolerances_are_reported():
    engine = Engine(BodyModel.from_moments([1.0, 1.5, 2.0]), [UniformGravity(1.0, [0.1, 0.0, 0.3])])
    w, q = engine.state_in([0.2, 0.1, 7.0], ID)
    y0 = np.concatenate([w, q], axis=1)
    with pytest.raises(StepLimitError, match="more than 5 steps"):
        RigidDOP853(engine.program(), 0.0, y0, rtol=1e-10, atol=1e-10, max_steps=5).advance([0.0, 100.0])
    with pytest.raises(ValueError, match="rtol"):
        RigidDOP853(engine.program(), 0.0, y0, rtol=1e-17, atol=1e-10)
    with pytest.raises(ValueError, match="output times"):
        RigidDOP853(engine.program(), 1.0, y0, rtol=1e-10, atol=1e-10).advance([0.0, 2.0])
