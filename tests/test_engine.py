"""Euler's equations with torques against ground truth: closed forms, conservation laws, mpmath."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wobble.errors import InputError
from wobble.models.engine import (
    BodyModel,
    ConstantTorque,
    CustomTorque,
    Engine,
    GravityGradient,
    LinearDamping,
    UniformGravity,
    attitude_angle,
    simulate,
)
from wobble.models.free import free_rotation
from wobble.numerics import quaternion as Q

REF = json.loads((Path(__file__).parent / "references" / "engine_torqued.json").read_text())
CASES = {c["name"]: c for c in REF["cases"]}
ID = np.array([1.0, 0.0, 0.0, 0.0])


def _floats(xs):
    return np.array([float(x) for x in xs])


def reference_case(name):
    """(engine, omega0, q0, t, omega_ref (T, 3), q_ref (T, 4)) from the mpmath file."""
    c = CASES[name]
    moments = _floats(c["moments"])
    if name == "asymmetric top":
        torques = [UniformGravity(float(c["mass"]), _floats(c["center_of_mass"]), _floats(c["gravity"]))]
    else:
        gm_d3 = float(c["gm_over_d3"])
        torques = [
            GravityGradient(
                gm_d3, 1.0, orbit_normal=[0, 0, 1], phase=float(c["phase"]), mean_motion=float(c["mean_motion"])
            )
        ]
    engine = Engine(BodyModel.from_moments(moments), torques)
    t = np.concatenate([[0.0], _floats(c["t"])])
    w = np.array([_floats(r) for r in c["omega"]])
    q = np.array([_floats(r) for r in c["attitude"]])
    return engine, _floats(c["omega0"]), _floats(c["attitude0"]), t, w, q


def errors(traj, w_ref, q_ref):
    """Per-component error relative to each component's largest value; attitude angle (rad)."""
    w = traj.omega[1:, 0]
    scale = np.max(np.abs(w_ref), axis=0)
    return np.max(np.abs(w - w_ref) / scale), np.max(attitude_angle(traj.attitude[1:, 0], q_ref))


# --------------------------------------------------------------------------
# Closed forms
# --------------------------------------------------------------------------
@pytest.mark.parametrize(
    "method, kw, tol", [("dop853", {"rtol": 1e-12}, 2e-10), ("splitting", {"step": 0.5, "order": 4}, 1e-13)]
)
def test_zero_torque_is_the_exact_free_motion(method, kw, tol):
    moments, omega0 = [1.0, 2.0, 3.0], [1.0, 0.1, 1.0]
    t = np.linspace(0, 20, 41)
    run = simulate(moments, omega0, ID, t, [ConstantTorque([0.0, 0.0, 0.0])], method=method, **kw)
    exact = free_rotation(moments, omega0)
    scale = np.max(np.abs(exact.omega(np.linspace(0, 20, 2001))), axis=0)
    assert np.max(np.abs(run.omega[:, 0] - exact.omega(t)) / scale) < tol
    assert np.max(attitude_angle(run.attitude[:, 0], exact.attitude(t))) < tol
    # ... and the run knows its error: the estimate is at least the error's order of magnitude
    assert run.error.omega_relative[0] < 10 * tol


@pytest.mark.parametrize("method, kw", [("dop853", {"rtol": 1e-12}), ("splitting", {"step": 0.3, "order": 2})])
def test_constant_body_torque_on_a_sphere_is_linear_in_time(method, kw):
    """I domega/dt = tau: omega = omega0 + tau t / I; about a fixed axis the angle is w0 t + tau t^2 / 2I."""
    inertia, tau = 2.0, 0.3
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    t = np.linspace(0, 10, 21)
    run = simulate([inertia] * 3, 0.5 * axis, ID, t, [ConstantTorque(tau * axis)], method=method, **kw)
    np.testing.assert_allclose(run.omega[:, 0], (0.5 + tau * t[:, None] / inertia) * axis, rtol=0, atol=1e-12)
    want = Q.from_axis_angle(axis, 0.5 * t + 0.5 * tau * t**2 / inertia)
    assert np.max(attitude_angle(run.attitude[:, 0], want)) < 1e-11


def test_inertial_torque_and_custom_torque_agree_with_built_ins():
    """A constant inertial torque, and the same torque written as a custom callable."""
    moments, w0 = [1.0, 1.3, 1.9], [0.2, 0.5, 1.0]
    q0 = Q.normalize(np.array([0.9, 0.2, -0.1, 0.3]))
    tau = np.array([0.05, -0.02, 0.1])
    t = np.linspace(0, 5, 11)
    a = simulate(moments, w0, q0, t, [ConstantTorque(tau, "inertial")], rtol=1e-12)
    custom = CustomTorque(lambda tt, w, q: np.broadcast_to(tau, w.shape), frame="inertial", uses_omega=False)
    b = simulate(moments, w0, q0, t, [custom], rtol=1e-12)
    c = simulate(moments, w0, q0, t, [custom], method="splitting", step=0.01, order=6)
    assert np.max(np.abs(a.omega - b.omega)) < 1e-12
    assert np.max(np.abs(a.omega - c.omega)) < 1e-9


def test_linear_damping_decays_exponentially():
    """A sphere with tau = -c omega: omega = omega0 exp(-c t / I) (the splitting's kick is exact)."""
    t = np.linspace(0, 4, 9)
    for method, kw in (("dop853", {"rtol": 1e-12}), ("splitting", {"step": 2.0, "order": 2})):
        run = simulate([2.0] * 3, [0.0, 0.0, 3.0], ID, t, [LinearDamping(0.5)], method=method, **kw)
        np.testing.assert_allclose(run.omega[:, 0, 2], 3.0 * np.exp(-0.25 * t), rtol=1e-11)


def test_gravity_gradient_torque_is_maccullaghs_formula():
    """tau = 3 GM / d^3 rho_b x I rho_b, with rho_b the direction to the mass in the body frame."""
    gm, d = 3.986004418e14, 7.0e6
    moments = np.array([0.9, 1.1, 1.4])
    direction = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    rng = np.random.default_rng(4)
    q = Q.normalize(rng.normal(size=(20, 4)))
    w = np.zeros((20, 3))
    engine20 = Engine(BodyModel.from_moments(moments), [GravityGradient(gm, d, direction=direction)], members=20)
    wi, qi = engine20.state_in(w, q)
    got = engine20.frame.vec_out(engine20.torque(0.0, wi, qi))
    rho_b = Q.rotate(Q.conjugate(q), direction)
    want = 3 * gm / d**3 * np.cross(rho_b, moments * rho_b)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-25)
    # along a principal axis: no torque (the equilibria of a gravity-gradient satellite)
    aligned = Engine(BodyModel.from_moments(moments), [GravityGradient(gm, d, direction=[0, 0, 1])])
    wa, qa = aligned.state_in([[0.0, 0.0, 0.0]], [ID])
    assert np.all(aligned.torque(0.0, wa, qa) == 0)


# --------------------------------------------------------------------------
# The heavy symmetric top: conservation laws and steady precession
# --------------------------------------------------------------------------
_THETA0 = np.radians(60)


def _top(theta0=_THETA0, spin=10.0, phidot=0.0):
    """I1 = I2 = 1, I3 = 0.5 about the pivot, M g l = 1 (the benchmarks' top)."""
    moments = [1.0, 1.0, 0.5]
    gravity = [UniformGravity(1.0, [0.0, 0.0, 1.0], [0.0, 0.0, -1.0])]
    q0 = Q.from_axis_angle(np.array([1.0, 0, 0]), theta0)
    w0 = np.array([phidot * np.sin(theta0) * 0, phidot * np.sin(theta0), phidot * np.cos(theta0) + spin])
    return moments, gravity, w0, q0


def _invariants(moments, run):
    """E, p_phi = L . z (inertial), p_psi = I3 omega3."""
    I = np.array(moments)
    w, q = run.omega[:, 0], run.attitude[:, 0]
    axis = Q.rotate(q, np.array([0.0, 0.0, 1.0]))
    energy = 0.5 * np.sum(I * w * w, axis=-1) + axis[:, 2]  # V = M g l cos(theta)
    p_phi = Q.rotate(q, I * w)[:, 2]
    return energy, p_phi, I[2] * w[:, 2]


@pytest.mark.parametrize(
    "method, kw, tol", [("dop853", {"rtol": 1e-12}, 1e-10), ("splitting", {"step": 0.01, "order": 6}, 1e-10)]
)
def test_heavy_top_conserves_energy_and_both_momenta(method, kw, tol):
    moments, gravity, w0, q0 = _top()
    run = simulate(moments, w0, q0, np.linspace(0, 20, 401), gravity, method=method, **kw)
    e, p_phi, p_psi = _invariants(moments, run)
    assert np.max(np.abs(e - e[0])) < tol * abs(e[0])
    assert np.max(np.abs(p_phi - p_phi[0])) < tol * np.linalg.norm(np.array(moments) * w0)
    assert np.max(np.abs(p_psi - p_psi[0])) < tol * abs(p_psi[0])
    # the tilt really nutates (this is not a trivial motion)
    tilt = np.degrees(np.arccos(Q.rotate(run.attitude[:, 0], np.array([0.0, 0, 1]))[:, 2]))
    assert np.ptp(tilt) > 1.0


def test_steady_precession_rate_matches_the_closed_form():
    """phi_dot = [I3 w3 - sqrt(I3^2 w3^2 - 4 I1 M g l cos theta)] / (2 I1 cos theta) keeps the tilt fixed."""
    i1, i3, mgl, theta, w3 = 1.0, 0.5, 1.0, np.radians(60), 10.0
    c = np.cos(theta)
    slow = (i3 * w3 - math.sqrt(i3**2 * w3**2 - 4 * i1 * mgl * c)) / (2 * i1 * c)
    fast = (i3 * w3 + math.sqrt(i3**2 * w3**2 - 4 * i1 * mgl * c)) / (2 * i1 * c)
    for phidot in (slow, fast):
        q0 = Q.from_axis_angle(np.array([1.0, 0, 0]), theta)
        w0 = np.array([0.0, phidot * np.sin(theta), w3])  # omega3 = w3 (total spin), body frame
        t = np.linspace(0, 4, 81)
        run = simulate([i1, i1, i3], w0, q0, t, [UniformGravity(1.0, [0, 0, 1.0], [0, 0, -mgl])], rtol=1e-13)
        axis = Q.rotate(run.attitude[:, 0], np.array([0.0, 0, 1]))
        assert np.max(np.abs(np.arccos(axis[:, 2]) - theta)) < 1e-9
        azimuth = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))
        rate = np.polyfit(t, azimuth, 1)[0]
        assert abs(rate - phidot) < 1e-9 * abs(phidot)


# --------------------------------------------------------------------------
# Against mpmath (torques with no exact solution)
# --------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(CASES))
def test_against_mpmath_taylor_reference(name):
    engine, w0, q0, t, w_ref, q_ref = reference_case(name)
    rk = engine.integrate(w0, q0, t, method="dop853", rtol=1e-12)
    err_w, err_q = errors(rk, w_ref, q_ref)
    assert err_w < 1e-9 and err_q < 1e-9, (err_w, err_q)
    assert err_w <= rk.error.omega_relative[0] and err_q <= rk.error.attitude[0]  # an upper bound
    sp = engine.integrate(w0, q0, t, method="splitting", step=0.02 if name == "asymmetric top" else 0.05, order=6)
    err_w, err_q = errors(sp, w_ref, q_ref)
    assert err_w < 1e-8 and err_q < 1e-8, (err_w, err_q)
    # Richardson is asymptotic, not a bound: within a factor of a few of the truth
    assert sp.error.omega_relative[0] / 5 < err_w < 5 * sp.error.omega_relative[0]


def test_measured_orders_on_a_torqued_problem():
    """Splitting 2, 4, 6 and DOP853 8 against the mpmath asymmetric top."""
    engine, w0, q0, t, w_ref, q_ref = reference_case("asymmetric top")
    tt, wr = t[:3], w_ref[:2]  # up to 1 s
    measured = {}
    for order, steps in ((2, (0.004, 0.002)), (4, (0.02, 0.01)), (6, (0.02, 0.01))):
        e = [
            np.max(
                np.abs(
                    engine.integrate(w0, q0, tt, method="splitting", step=h, order=order, estimate=False).omega[1:, 0]
                    - wr
                )
            )
            for h in steps
        ]
        measured[order] = math.log2(e[0] / e[1])
    from wobble.numerics.integrators import DOP853

    y0 = np.concatenate(engine.state_in(w0, q0), axis=1)
    e = []
    for h in (0.2, 0.1):
        y = DOP853(engine.rhs, 0.0, y0, rtol=1e-3, atol=1e-3, fixed_step=h).advance([0.0, 1.0])[-1]
        e.append(np.max(np.abs(engine.state_out(y[:, :3], None)[0][0] - w_ref[1])))
    measured[8] = math.log2(e[0] / e[1])
    for order, value in measured.items():
        assert abs(value - order) < 0.35, measured


# --------------------------------------------------------------------------
# Long runs and stiff-looking problems
# --------------------------------------------------------------------------
@pytest.mark.slow
def test_long_splitting_run_has_no_secular_energy_drift():
    """10^5 Strang steps of the heavy top (about 320 nutation periods): the energy and
    L.z errors stay bounded.

    (The benchmark, scripts/bench_engine.py, runs orders 2, 4 and 6 for 10^6 steps; the splitting
    is a Python loop, about 0.05 ms a step, so the suite keeps to a tenth of that: the whole suite
    must stay under 10 minutes on 2 cores.)
    """
    moments, gravity, w0, q0 = _top()
    n_steps, h = 100_000, 0.02
    t = np.linspace(0, n_steps * h, 201)
    run = simulate(moments, w0, q0, t, gravity, method="splitting", step=h, order=2, estimate=False)
    assert run.stats["steps"] == n_steps
    e, p_phi, _ = _invariants(moments, run)
    de = np.abs(e - e[0]) / abs(e[0])
    assert de.max() < 1e-3  # bounded at the level of the method's error (h^2)
    first, last = de[1:101].max(), de[101:].max()
    assert last < 1.5 * first  # no secular growth from the first half to the second
    assert np.max(np.abs(p_phi - p_phi[0])) < 1e-10  # a kick about z does not change L.z; drifts conserve L
    assert np.max(np.abs(np.linalg.norm(run.attitude, axis=-1) - 1)) < 1e-14


def test_fast_spin_slow_precession_splitting_beats_dop853_at_equal_error():
    """A gyroscope in steady precession (600 rad/s spin, 1.46 rad/s precession).

    The splitting integrates the spin and the free nutation exactly and kicks with the slow
    gravity torque; DOP853 must follow the spin. At equal (or better) error in the direction
    of the axis and in L, the splitting needs several times fewer torque evaluations. (Errors
    and evaluation counts are measured, not time.)
    """
    i1, i3, mgl, theta, w3 = 1.825e-4, 4.5e-5, 0.0392266, np.radians(80), 600.0
    c = np.cos(theta)
    phidot = (i3 * w3 - math.sqrt((i3 * w3) ** 2 - 4 * i1 * mgl * c)) / (2 * i1 * c)
    q0 = Q.from_axis_angle(np.array([1.0, 0, 0]), theta)
    w0 = np.array([0.0, phidot * np.sin(theta), w3])
    engine = Engine(BodyModel.from_moments([i1, i1, i3]), [UniformGravity(1.0, [0, 0, 1.0], [0, 0, -mgl])])
    t = np.linspace(0, 0.5, 3)
    ref = engine.integrate(w0, q0, t, method="dop853", rtol=1e-13, estimate=False)

    def errs(run):
        z = np.array([0.0, 0.0, 1.0])
        axis = np.max(np.linalg.norm(Q.rotate(run.attitude[:, 0], z) - Q.rotate(ref.attitude[:, 0], z), axis=-1))
        L = Q.rotate(run.attitude[:, 0], np.array([i1, i1, i3]) * run.omega[:, 0])
        L_ref = Q.rotate(ref.attitude[:, 0], np.array([i1, i1, i3]) * ref.omega[:, 0])
        return max(axis, np.max(np.abs(L - L_ref)) / np.linalg.norm(L_ref[0]))

    sp = engine.integrate(w0, q0, t, method="splitting", step=0.0025, order=6, estimate=False)
    rk = engine.integrate(w0, q0, t, method="dop853", rtol=3e-9, estimate=False)
    work_split = sp.stats["drifts"] + sp.stats["steps"]  # torque evaluations: one kick per drift, plus one
    work_rk = rk.stats["function_evaluations"]
    assert errs(sp) <= errs(rk) < 1e-8
    assert 3 * work_split < work_rk  # measured: 1600 against 6300 evaluations


# --------------------------------------------------------------------------
# Ensembles, frames, properties
# --------------------------------------------------------------------------
def test_ensemble_equals_member_by_member():
    moments, gravity, _, _ = _top()
    rng = np.random.default_rng(8)
    n = 6
    w0 = rng.normal(size=(n, 3)) + [0, 0, 8]
    q0 = Q.normalize(rng.normal(size=(n, 4)))
    t = np.linspace(0, 2, 5)
    for method, kw in (("dop853", {"rtol": 1e-11}), ("splitting", {"step": 0.01, "order": 4})):
        together = simulate(moments, w0, q0, t, gravity, method=method, **kw)
        for i in range(n):
            alone = simulate(moments, w0[i], q0[i], t, gravity, method=method, **kw)
            if method == "dop853":  # per-member steps: bit for bit
                np.testing.assert_array_equal(alone.omega[:, 0], together.omega[:, i])
            else:  # shared steps; one member runs in Python floats, many in NumPy: rounding apart
                assert np.max(np.abs(alone.omega[:, 0] - together.omega[:, i])) < 1e-12
            np.testing.assert_allclose(
                alone.error.omega_relative[0], together.error.omega_relative[i], rtol=1e-3, atol=1e-14
            )


def test_ensemble_of_bodies():
    """N different bodies (moments (N, 3)) in one call: each as if alone."""
    moments = np.array([[1.0, 2.0, 3.0], [1.0, 1.5, 2.0], [2.0, 2.0, 3.0]])
    w0 = np.array([[1.0, 0.1, 1.0], [0.2, 1.0, 0.3], [0.5, 0.0, 2.0]])
    t = np.linspace(0, 5, 6)
    run = simulate(moments, w0, ID, t, [ConstantTorque([0.0, 0.0, 0.0])], method="splitting", step=1.0, order=2)
    for i in range(3):
        exact = free_rotation(moments[i], w0[i])
        assert np.max(np.abs(run.omega[:, i] - exact.omega(t))) < 1e-13


def test_tensor_body_frame_gives_the_same_physics():
    """A body described in a rotated frame (tensor R diag R^T) moves the same way, seen in that frame."""
    rot = Q.to_matrix(Q.normalize(np.array([0.8, 0.3, -0.4, 0.2])))
    moments = np.array([1.0, 1.6, 2.1])
    tensor = rot @ np.diag(moments) @ rot.T
    r_cm = np.array([0.1, -0.2, 0.4])
    w0 = np.array([0.3, 0.8, 5.0])
    q0 = Q.normalize(np.array([0.9, 0.1, 0.2, -0.3]))
    t = np.linspace(0, 2, 5)
    principal = Engine(BodyModel.from_moments(moments), [UniformGravity(1.0, r_cm, [0, 0, -9.8])])
    a = principal.integrate(w0, q0, t, rtol=1e-12, estimate=False)
    rotated = Engine(BodyModel.from_tensor(tensor), [UniformGravity(1.0, rot @ r_cm, [0, 0, -9.8])])
    q_rot = Q.multiply(q0, Q.conjugate(Q.from_matrix(rot)))
    b = rotated.integrate(rot @ w0, q_rot, t, rtol=1e-12, estimate=False)
    np.testing.assert_allclose(b.omega[:, 0], a.omega[:, 0] @ rot.T, atol=1e-9)
    assert (
        np.max(attitude_angle(b.attitude[:, 0], Q.multiply(a.attitude[:, 0], Q.conjugate(Q.from_matrix(rot))))) < 1e-9
    )


def test_bad_input_names_the_parameter():
    with pytest.raises(InputError, match="moments"):
        BodyModel.from_moments([1.0, 1.0, 3.0])  # triangle inequality
    with pytest.raises(InputError, match="method"):
        simulate([1, 2, 3], [0, 0, 1], ID, [0, 1], [CustomTorque(lambda t, w, q: -w)], method="splitting", step=0.1)
    with pytest.raises(InputError, match="mass"):
        simulate([1, 2, 3], [0, 0, 1], ID, [0, 1], [UniformGravity(-1.0, [0, 0, 1])])
    with pytest.raises(InputError, match="direction"):
        simulate([1, 2, 3], [0, 0, 1], ID, [0, 1], [GravityGradient(1.0, 1.0)])


@settings(max_examples=15)
@given(st.floats(0.0, 2 * np.pi), st.floats(0.2, 1.2), st.floats(3.0, 12.0))
def test_top_properties(alpha, theta, spin):
    """Unit quaternions; E and L.z conserved; turning the start about the vertical turns the motion."""
    moments, gravity, _, _ = _top()
    q0 = Q.from_axis_angle(np.array([1.0, 0, 0]), theta)
    w0 = np.array([0.3, -0.2, spin])
    t = np.linspace(0, 1, 5)
    a = simulate(moments, w0, q0, t, gravity, rtol=1e-12, estimate=False)
    turn = Q.from_axis_angle(np.array([0.0, 0, 1]), alpha)
    b = simulate(moments, w0, Q.multiply(turn, q0), t, gravity, rtol=1e-12, estimate=False)
    assert np.max(np.abs(np.linalg.norm(a.attitude, axis=-1) - 1)) < 1e-14
    e, p_phi, _ = _invariants(moments, a)
    assert np.max(np.abs(e - e[0])) < 1e-9 * abs(e[0]) and np.max(np.abs(p_phi - p_phi[0])) < 1e-9 * spin
    assert np.max(np.abs(a.omega - b.omega)) < 1e-9 * spin
    assert np.max(attitude_angle(Q.multiply(turn, a.attitude[:, 0]), b.attitude[:, 0])) < 1e-9
