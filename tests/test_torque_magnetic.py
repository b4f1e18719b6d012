"""The magnetic dipole torque, added by the four-step recipe (a class, a compiled branch, a
scene-file entry, this test), against ground truth.

A symmetric body whose dipole lies on its symmetry axis, in a uniform field pointing down,
has the potential V = -mu . B = mu B cos(theta): it is the heavy symmetric top with
M g l = mu B (Goldstein, Poole & Safko 2002, sec. 5.7), whose motion wobble knows exactly
(elliptic functions, tested against mpmath). Every integrator must reproduce it.
"""

from __future__ import annotations

import astropy.units as u
import numpy as np
import pytest

import wobble
from wobble.io.scene_file import scene_from_mapping
from wobble.models.engine import BodyModel, Engine, MagneticDipole, attitude_angle
from wobble.models.top import heavy_top

I1, I3 = 2.0e-3, 1.0e-3  # kg m2 about the centre (the pivot: a magnet pivoted at its middle)
MU, B = 0.8, 2.5e-3  # A m2 and T: mu B = 2e-3 J
THETA0, OMEGA3, PHIDOT0 = np.radians(50.0), 60.0, -0.5


def _exact_and_engine():
    top = heavy_top(I1, I3, MU * B, THETA0, omega3=OMEGA3, phidot0=PHIDOT0)
    engine = Engine(BodyModel.from_moments([I1, I1, I3]), [MagneticDipole([0.0, 0.0, MU], [0.0, 0.0, -B])])
    return top, engine


@pytest.mark.parametrize(
    "method, kw",
    [
        ("dop853", {"rtol": 1e-12, "backend": "compiled"}),
        ("dop853", {"rtol": 1e-12, "backend": "python"}),
        ("splitting", {"step": 2e-3, "order": 6}),
    ],
)
def test_a_magnetised_top_is_the_exact_heavy_top(method, kw):
    top, engine = _exact_and_engine()
    t = np.linspace(0.0, 6 * top.nutation_period, 241)
    w_exact, q_exact = top.evaluate(t)
    run = engine.integrate(w_exact[0], q_exact[0], t, method=method, **kw)
    assert np.max(np.abs(run.omega[:, 0] - w_exact)) < 1e-8 * OMEGA3
    assert np.max(attitude_angle(run.attitude[:, 0], q_exact)) < 1e-8
    # not a trivial motion: the axis nutates by degrees between the turning angles
    assert np.degrees(top.theta_max - top.theta_min) > 1.0


def test_energy_with_the_dipole_potential_is_conserved():
    top, engine = _exact_and_engine()
    t = np.linspace(0.0, 4 * top.nutation_period, 101)
    w_exact, q_exact = top.evaluate(t)
    run = engine.integrate(w_exact[0], q_exact[0], t, rtol=1e-12)
    w, q = engine.frame.vec_in(run.omega[:, 0]), engine.frame.quat_in(run.attitude[:, 0])
    energy = engine.energy(t, w, q)
    # T + V with V = -mu . B: the heavy top's energy, E = (I1/2)(thetadot^2 + ...) + M g l cos(theta)
    assert np.max(np.abs(energy - top.energy)) < 1e-10 * abs(top.energy)


def test_scene_file_and_api_give_the_same_torque():
    from_file = scene_from_mapping(
        {
            "body": {"moments": {"value": [I1, I1, I3], "unit": "kg m2"}},
            "initial": {"omega": {"value": [0, 0, OMEGA3], "unit": "rad/s"}},
            "torques": [
                {
                    "kind": "magnetic",
                    "dipole": {"value": [0, 0, 800], "unit": "mA m2"},
                    "field": {"value": [0, 0, -2500], "unit": "uT"},
                }
            ],
            "time": {"stop": "1 s", "samples": 3},
        }
    ).torques[0]
    from_api = wobble.Torque.magnetic([0, 0, MU] * u.A * u.m**2, [0, 0, -B] * u.T).spec
    for spec in (from_file, from_api):
        assert isinstance(spec, MagneticDipole)
        np.testing.assert_allclose(spec.dipole, [0, 0, MU], rtol=1e-15)
        np.testing.assert_allclose(spec.field, [0, 0, -B], rtol=1e-15)


def test_bad_magnetic_input_names_the_key():
    with pytest.raises(wobble.InputError, match="field: got"):
        wobble.Torque.magnetic([0, 0, MU] * u.A * u.m**2, [0, 0, -B] * u.m)
    with pytest.raises(wobble.InputError, match="dipole: missing"):
        scene_from_mapping(
            {
                "body": {"moments": {"value": [1, 1, 1], "unit": "kg m2"}},
                "initial": {"omega": {"value": [0, 0, 1], "unit": "rad/s"}},
                "torques": [{"kind": "magnetic", "field": {"value": [0, 0, 1], "unit": "T"}}],
                "time": {"stop": "1 s", "samples": 2},
            }
        )
