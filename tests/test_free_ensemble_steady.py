"""Steady spins of the tumbling-body ensemble against their closed form and the single-body model.

A spin about a principal axis (any of the three, the intermediate one included), or within the plane
of two equal moments, or of a sphere, is an equilibrium of Euler's equations: omega stays omega0 and L
stays along it (Landau & Lifshitz, Mechanics, sec. 37). The ensemble called a spin about the
intermediate axis of an asymmetric body "separatrix", with no precession rate and wobble angles of
45-90 deg, where :func:`wobble.models.free.free_rotation` said "steady".
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from wobble.api.sweep import run_sweep
from wobble.models.free import free_rotation
from wobble.models.free_ensemble import REGIMES, free_ensemble

BODIES = {
    "asymmetric": (3.0, 4.0, 6.0),
    "asymmetric, intermediate moment first": (4.0, 6.0, 3.0),
    "oblate": (3.0, 3.0, 6.0),
    "prolate": (3.0, 6.0, 6.0),
    "sphere": (4.0, 4.0, 4.0),
}
SPIN = 0.7  # rad/s
T = 5.0  # s, the time of omega_final


def _steady_cases():
    for (name, moments), axis, sign in itertools.product(BODIES.items(), range(3), (1.0, -1.0)):
        omega = np.zeros(3)
        omega[axis] = sign * SPIN
        yield pytest.param(moments, omega, id=f"{name}-axis{axis}-{'+' if sign > 0 else '-'}")
    # A spin in the plane of two equal moments is along a principal axis too (any axis of that plane is one).
    yield pytest.param((3.0, 3.0, 6.0), np.array([0.6, -0.8, 0.0]) * SPIN, id="oblate-equatorial")
    yield pytest.param((3.0, 6.0, 6.0), np.array([0.0, 0.8, 0.6]) * SPIN, id="prolate-equatorial")
    yield pytest.param((4.0, 4.0, 4.0), np.array([2.0, -3.0, 6.0]) / 7.0 * SPIN, id="sphere-oblique")


@pytest.mark.parametrize(("moments", "omega"), list(_steady_cases()))
def test_a_steady_spin_is_steady_with_its_closed_form(moments, omega):
    res = free_ensemble([moments], [omega], T)
    assert res["invalid_reason"][0] == 0
    # The single-body model's word for it, in the ensemble's vocabulary.
    model = free_rotation(moments, omega)
    assert model.regime == "steady"
    assert REGIMES[res["regime"][0]] == "steady"
    # Closed form: omega(t) = omega0; L = I omega0 is parallel to omega0, so the spin axis is L's
    # direction (wobble angle 0 throughout); omega in the body never changes (no nutation period),
    # and the body turns uniformly about L at |omega| (the single-body precession rate of a steady spin).
    assert res["nutation_period"][0] == np.inf
    assert res["wobble_angle_min"][0] == 0.0 and res["wobble_angle_max"][0] == 0.0
    assert res["precession_rate"][0] == pytest.approx(SPIN, rel=1e-15)
    assert res["precession_period"][0] == pytest.approx(2 * np.pi / SPIN, rel=1e-15)
    assert model.precession_rate == pytest.approx(res["precession_rate"][0], rel=1e-15)
    np.testing.assert_allclose(res["omega_final"][0], omega, rtol=0, atol=1e-15 * SPIN)


def test_near_the_intermediate_axis_it_is_not_steady():
    """The steady case is the exact axis only: a nudge off it circulates about the axis the single body says."""
    moments = np.array([[3.0, 4.0, 6.0]] * 3)
    omega = np.array([[0.0, 2.0, 1e-8], [1e-8, 2.0, 0.0], [1e-8, 2.0, 1e-8 * np.sqrt(0.5)]])
    res = free_ensemble(moments, omega)
    for j in range(3):
        model = free_rotation(moments[j], omega[j])
        assert REGIMES[res["regime"][j]] == model.regime != "steady"
    assert np.all(res["wobble_angle_max"] > 1.0)  # swings far from the circulation axis (a flip)


def test_a_sweep_spinning_about_the_intermediate_axis_is_steady():
    """Through the public sweep target: body axis a is the intermediate one (I = 4, 3, 6 kg m2) and omega0 lies
    along it (colatitude 90 deg from c, longitude 0), which the target forms exactly."""

    def value(x, unit="1"):
        return {"value": x, "unit": unit}

    spec = {
        "schema": "wobble-sweep/1",
        "name": "intermediate_axis",
        "target": "free_rotation",
        "members": 5,
        "seed": 3,
        "base": {
            "moment_a": value(4.0, "kg m2"),
            "moment_ratio_ba": value(0.75),
            "moment_ratio_cb": value(2.0),
            "spin_cos_colatitude": value(0.0),
            "final_time": value(T, "s"),
        },
        "vary": {"spin_period": {"distribution": "uniform", "low": 1.0, "high": 10.0, "unit": "s"}},
    }
    ds = run_sweep(spec)
    rate = 2 * np.pi / ds.spin_period.values
    assert [REGIMES[k] for k in ds.regime.values] == ["steady"] * 5
    np.testing.assert_allclose(ds.precession_rate.values, rate, rtol=1e-15)
    np.testing.assert_array_equal(ds.wobble_angle_min.values, 0.0)
    np.testing.assert_array_equal(ds.wobble_angle_max.values, 0.0)
    np.testing.assert_array_equal(ds.nutation_period.values, np.inf)
    np.testing.assert_allclose(ds.omega_final.values[:, 0], rate, rtol=1e-15)
    np.testing.assert_array_equal(ds.omega_final.values[:, 1:], 0.0)


@pytest.mark.parametrize("omega", [(1e-200, 2.0, 1e-200), (0.0, 2.0, 1e-170), (1e-170, 2.0, 0.0)])
def test_a_spin_off_the_intermediate_axis_by_less_than_squares_resolve_is_not_steady(omega):
    """Steady spin about the intermediate axis is omega_0 = omega_2 = 0 exactly: a component of 1e-170 rad/s, whose
    square underflows, leaves the axis (the body never returns to it), so it is not steady; the test had read the
    squares I_i omega_i^2 and called it steady."""
    out = free_ensemble(np.array([[3.0, 4.0, 6.0]]), np.array([omega]))
    assert out["regime"][0] != 0
