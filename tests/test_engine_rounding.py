"""The splitting's error estimate sees rounding amplified by the motion.

Ground truth: a chaotic heavy body integrated by mpmath at 30 digits
(``tests/references/build_engine_chaotic_reference.py``), and the torque-free body's exact
solution. Richardson's difference of two runs divided by 2^p - 1 measures truncation only; on
a chaotic motion the rounding of 10^4 steps, amplified 10^5-fold, dominates the error, and an
estimate blind to it was 2 to 8 times below the error (the test cases below).
"""

from __future__ import annotations

import json
from pathlib import Path

import astropy.units as u
import numpy as np
import pytest

import wobble
from wobble.errors import InputError
from wobble.models.engine import BodyModel, ConstantTorque, Engine, UniformGravity, attitude_angle, simulate
from wobble.models.free import free_rotation

REF = json.loads((Path(__file__).parent / "references" / "engine_chaotic.json").read_text())["cases"][0]
ID = np.array([1.0, 0.0, 0.0, 0.0])


def _floats(xs):
    return np.array([float(x) for x in xs])


def _chaotic():
    """(engine, omega0, q0, t (0 and the reference's times), omega_ref, q_ref)."""
    engine = Engine(
        BodyModel.from_moments(_floats(REF["moments"])),
        [UniformGravity(float(REF["mass"]), _floats(REF["center_of_mass"]), _floats(REF["gravity"]))],
    )
    t = np.concatenate([[0.0], _floats(REF["t"])])
    w = np.array([_floats(r) for r in REF["omega"]])
    q = np.array([_floats(r) for r in REF["attitude"]])
    return engine, _floats(REF["omega0"]), _floats(REF["attitude0"]), t, w, q


@pytest.mark.slow
@pytest.mark.parametrize(
    "step",
    # A step whose truncation alone (Richardson's part of the estimate) meets 1e-8 in omega and in the
    # attitude, where the rounding is larger than the truncation: Richardson alone was 0.22 times the
    # error. (Steps of 0.0075 s and 0.0035 s, 0.55 and 0.07 times, behave alike (docs/engine.md); they are
    # left out for the suite's time: the splitting runs in Python, and 0.0035 s takes 1.4 times as long.)
    [0.005],
)
def test_chaotic_estimate_bounds_the_error_against_mpmath(step):
    engine, w0, q0, t, w_ref, q_ref = _chaotic()
    run = engine.integrate(w0, q0, t, method="splitting", step=step, order=6)
    scale = np.max(np.abs(w_ref), axis=0)
    err_w = np.max(np.abs(run.omega[1:, 0] - w_ref) / scale)
    err_q = np.max(attitude_angle(run.attitude[1:, 0], q_ref))
    est_w, est_q = run.error.omega_relative[0], run.error.attitude[0]
    assert err_w <= est_w < 1e3 * err_w, (err_w, est_w)
    assert err_q <= est_q < 1e3 * err_q, (err_q, est_q)
    # the part of the estimate that a shorter step cannot lower is reported
    assert 0 < run.error.rounding[0] <= max(est_w, est_q)


@pytest.mark.slow
def test_chaotic_scene_refuses_an_accuracy_below_its_rounding_floor():
    """Forced onto the splitting at 1e-11 over 20 s (its rounding floor there is about 1e-10; over the
    reference's 50 s it is 2e-7, and 1e-9 is refused alike), the scene is refused, saying why, instead
    of claiming it."""
    scene = wobble.Scene(
        body=_floats(REF["moments"]) * u.kg * u.m**2,
        omega0=_floats(REF["omega0"]) * u.rad / u.s,
        torques=[wobble.Torque.gravity(2 * u.kg, _floats(REF["center_of_mass"]) * u.m, g=9.80665 * u.m / u.s**2)],
        t_end=20 * u.s,
        samples=21,
        accuracy=1e-11,
        outputs=["omega", "attitude"],
    )
    with pytest.raises(InputError, match="rounding floor") as info:
        wobble.run(scene, model="splitting")
    assert info.value.parameter == "accuracy"


@pytest.mark.parametrize(
    "moments, omega0",
    [([1.0, 1.0, 2.0], [0.3, 0.0, 2.0]), ([1.0, 2.0, 3.0], [1.0, 0.1, 1.0])],
    ids=["symmetric", "asymmetric"],
)
def test_free_body_estimate_bounds_its_rounding_and_is_not_inflated(moments, omega0):
    """Torque-free: every drift is exact, so the error is rounding alone, which the estimate must
    bound; a motion that does not amplify rounding keeps its estimate within 1e3 of the error."""
    t = np.linspace(0.0, 2000.0, 201)
    run = simulate(moments, omega0, ID, t, [ConstantTorque([0.0, 0.0, 0.0])], method="splitting", step=0.5, order=2)
    exact = free_rotation(moments, omega0)
    scale = np.max(np.abs(exact.omega(np.linspace(0.0, 2000.0, 20001))), axis=0)
    err_w = np.max(np.abs(run.omega[:, 0] - exact.omega(t)) / scale)
    err_q = np.max(attitude_angle(run.attitude[:, 0], exact.attitude(t)))
    assert err_w <= run.error.omega_relative[0] < 1e3 * err_w
    assert err_q <= run.error.attitude[0] < 1e3 * err_q


def test_the_rounding_floor_is_written_beside_the_estimate(tmp_path):
    """The splitting's rounding part reaches the file's attributes and the summary (JSON), and is
    part of the estimate (added in quadrature); DOP853 does not measure it: no attribute, None."""
    scene = wobble.Scene(
        body=[1.0, 2.0, 3.0] * u.kg * u.m**2,
        omega0=[1.0, 0.1, 1.0] * u.rad / u.s,
        t_end=20 * u.s,
        samples=21,
        accuracy=1e-6,
        outputs=["omega"],
    )
    split = wobble.run_to_netcdf(scene, tmp_path / "split.nc", model="splitting")
    attrs = wobble.load(tmp_path / "split.nc").attrs
    assert 0 < attrs["error_estimate_rounding"] == split["error_estimate_rounding"] <= attrs["error_estimate"]
    dop = wobble.run_to_netcdf(scene, tmp_path / "dop.nc", model="dop853")
    assert dop["error_estimate_rounding"] is None
    assert "error_estimate_rounding" not in wobble.load(tmp_path / "dop.nc").attrs
