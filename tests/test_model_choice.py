"""The chooser between the integrators: predicted seconds from counted calls and each path's cost per call.

The pilots count calls (DOP853: evaluations per member; the splitting: stages of all members) and
wobble.models.scene.CALL_COST prices a call on the path that makes it (measured with
scripts/calibrate_chooser.py; docs/engine.md). Counting calls alone picks the splitting's main run for
the shipped satellite_gravity_gradient scene: 158,956 stages of the exact flow in Python floats (~50 us
each; 397,390 with its companion and rounding twins: 20 s) against 200,888 evaluations of the compiled
DOP853 (~0.15 us each; 295,000 with its companion: 0.04 s). No timing here:
the tests check the counted calls, the cost model's arithmetic and the reason's numbers.
"""

from __future__ import annotations

import astropy.units as u
import numpy as np
import pytest

import wobble
from wobble.api.scene import _as_scene
from wobble.errors import InputError
from wobble.models import engine as eng
from wobble.models import scene as S
from wobble.numerics import compiled

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s

needs_compiled = pytest.mark.skipif(not compiled.available(), reason="the compiled DOP853 needs Numba")


def _engine(scene):
    return eng.Engine(scene.body, scene.torques, members=scene.members)


def _counting_pilots(monkeypatch):
    counts = {"dop853": 0, "splitting": 0}
    pilot = S._pilot

    def counted(scene, method, settings):
        counts[method] += 1
        return pilot(scene, method, settings)

    monkeypatch.setattr(S, "_pilot", counted)
    return counts


@needs_compiled
def test_the_satellite_takes_the_compiled_dop853_and_says_why_in_seconds(monkeypatch):
    scene = _as_scene("satellite_gravity_gradient")
    pilots = _counting_pilots(monkeypatch)
    choice = S.choose_model(scene)
    assert choice.candidate.name == "dop853"
    plans = S._plans(scene)
    rk, split = plans["dop853"], plans["splitting"]
    assert (rk.path, split.path) == ("dop853 compiled", "splitting Python floats")
    # The prediction is the counted calls times the path's cost per call.
    engine = _engine(scene)
    assert rk.seconds == pytest.approx(rk.calls * S.call_seconds(engine, rk.path), rel=1e-12)
    assert split.seconds == pytest.approx(split.calls * S.call_seconds(engine, split.path), rel=1e-12)
    # The splitting's piloting stopped at its first failed step, already dearer than DOP853's whole
    # run (the step could only shrink from there): one pilot instead of the five that find its step.
    assert not split.complete and split.seconds > rk.seconds
    assert pilots == {"dop853": 1, "splitting": 1}
    # The reason gives the numbers that decided, and claims nothing else.
    assert choice.reason.startswith(
        f"adaptive Dormand-Prince 8(5,3) on Euler's equations (pilot run predicts {rk.seconds:.2g} s (compiled))"
    )
    assert (
        f"splitting: pilot runs predict at least {split.seconds:.2g} s (Python floats) against "
        f"{rk.seconds:.2g} s (compiled) for dop853" in choice.reason
    )
    assert "cheaper" not in choice.reason

    # Forcing the splitting redoes its piloting in full (the cut-short plan is no setting) and
    # makes no claim about cost.
    forced = S.choose_model(scene, "splitting")
    assert forced.reason == "forced (--model splitting): Touma-Wisdom splitting: exact free flow between torque kicks"
    full = S._plans(scene)["splitting"]
    assert full.complete and pilots["splitting"] > 1
    assert forced.run.settings == full.settings
    # Counted work of the full splitting: its pilots find a 0.64 s step (order 6), but each 0.5 s
    # output interval takes an even number of steps, two: 22,708 steps of 0.25 s, seven stages each,
    # the companion at twice the step and its two rounding twins: 397,390 stages. DOP853: ~200,900
    # evaluations in the main run and three quarters of that in its companion at 10 rtol.
    steps = S._split_steps(scene, full.settings["step_s"])
    assert steps == 2 * (scene.times.size - 1) and full.calls == 2.5 * steps * 7
    assert 330_000 < full.calls < 470_000 and 250_000 < rk.calls < 350_000
    # Fewer calls than DOP853 in the main run, but each ~300 times dearer: the splitting takes more than
    # ten times longer.
    assert full.calls / 2.5 < rk.calls / 1.75 and full.seconds > 10 * rk.seconds
    assert full.seconds >= split.seconds  # what stopped the piloting was a lower bound

    # The counted evaluations of the DOP853 run match its pilot's prediction.
    run = choice.run
    for _ in run.blocks(scene.times, scene.times.size):
        pass
    evals = run.stats()["function_evaluations"]
    assert 0.7 < 1.75 * evals / rk.calls < 1.4
    assert max(run.error_estimate()["omega_relative"], run.error_estimate()["attitude_rad"]) <= scene.accuracy


@needs_compiled
def test_the_splitting_is_chosen_where_it_needs_few_enough_calls():
    """A tumbling body under a very weak damping, three outputs over 10^4 s: the exact free flow takes
    long steps (the damping barely acts), DOP853 must follow the tumbling; 0.1 s against 0.3 s predicted."""
    scene = _as_scene(
        wobble.Scene(
            body=[1.0, 2.0, 3.0] * KGM2,
            omega0=[1.0, 0.1, 1.0] * RAD_S,
            torques=[wobble.Torque.damping(1e-9 * u.N * u.m * u.s)],
            t_end=1e4 * u.s,
            samples=3,
            accuracy=1e-6,
        )
    )
    choice = S.choose_model(scene)
    assert choice.candidate.name == "splitting"
    plans = S._plans(scene)
    rk, split = plans["dop853"], plans["splitting"]
    assert split.complete and split.seconds < rk.seconds
    assert split.calls * S.call_seconds(_engine(scene), split.path) < rk.calls * S.call_seconds(_engine(scene), rk.path)
    assert choice.reason.startswith(
        "Touma-Wisdom splitting: exact free flow between torque kicks (pilot runs predict "
        f"{split.seconds:.2g} s (Python floats) against {rk.seconds:.2g} s (compiled) for dop853)"
    )
    ds = wobble.run(scene)
    assert ds.attrs["model"].startswith("splitting-") and ds.attrs["error_estimate"] <= 1e-6


def test_each_path_is_priced_per_call_and_per_torque_kind(monkeypatch):
    scene = _as_scene("earth_precession")  # two third bodies on Keplerian orbits
    engine = _engine(scene)
    one = S.CALL_COST["splitting Python floats"].us(1) + 2 * S.KIND_COST["third_body"]["splitting Python floats"].us(1)
    assert S.call_seconds(engine, "splitting Python floats") == pytest.approx(1e-6 * one)
    ensemble = eng.Engine(scene.body, scene.torques, members=1000)
    assert S._split_path(ensemble) == "splitting NumPy"
    many = S.CALL_COST["dop853 compiled"].us(1000) + 2 * S.KIND_COST["third_body"]["dop853 compiled"].us(1000)
    assert S.call_seconds(ensemble, "dop853 compiled") == pytest.approx(1e-6 * many)
    # Without Numba (or with a torque that has no compiled form) DOP853 runs in Python floats.
    assert S._rk_path(engine) == ("dop853 compiled" if compiled.available() else "dop853 Python floats")
    monkeypatch.setattr(compiled, "available", lambda: False)
    assert S._rk_path(engine) == "dop853 Python floats" and S._rk_path(ensemble) == "dop853 NumPy"


@needs_compiled
def test_when_the_cheaper_integrator_misses_the_accuracy_the_other_one_runs():
    """An inverted top spinning steadily on its minor axis (body 1, 1.2, 0.5 kg m2, centre of mass above
    the pivot): DOP853, predicted ten times cheaper, cannot certify 1e-9 (its estimate, amplified from
    rounding by the unstable equilibrium, stays at 7e-8 down to its tolerance floor); the splitting,
    whose drift is the exact steady rotation, reaches 5e-14. Forced, DOP853 is an error."""
    scene = wobble.Scene(
        body=[1.0, 1.2, 0.5] * KGM2,
        omega0=[0, 0, 10.0] * RAD_S,
        t_end=1 * u.s,
        samples=3,
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, 1] * u.m, g=1 * u.m / u.s**2)],
        accuracy=1e-9,
    )
    assert S.choose_model(_as_scene(scene)).candidate.name == "dop853"
    ds = wobble.run(scene)
    assert ds.attrs["model"] == "splitting-6" and ds.attrs["error_estimate"] <= 1e-9
    # two DOP853 attempts (the second at its tolerance floor, its estimate still above), one splitting
    assert ds.attrs["attempts"] == 3
    reason = ds.attrs["model_reason"]
    assert reason.startswith(
        "Touma-Wisdom splitting: exact free flow between torque kicks, after dop853 did not reach the accuracy "
        "asked (1e-09: at least "
    )
    assert "first choice: adaptive Dormand-Prince 8(5,3) on Euler's equations (pilot run predicts" in reason
    with pytest.raises(wobble.InputError, match="accuracy.*with dop853"):
        wobble.run(scene, model="dop853")


def _spy_pilots(monkeypatch):
    calls = []
    pilot = S._pilot

    def spy(scene, method, settings):
        calls.append((method, settings.get("step_s")))
        return pilot(scene, method, settings)

    monkeypatch.setattr(S, "_pilot", spy)
    return calls


def test_no_splitting_pilot_dearer_than_the_dop853_run(monkeypatch):
    """A gravity-gradient scene (0-5 s, 101 outputs, 1e-9): DOP853 is predicted at 0.011 s, and the splitting's
    first guess of about 1e-4 s made pilots that each cost more than that, doubled pilot by pilot: 10 s under
    auto where the DOP853 it then chose took 0.6 s (a review finding). No such pilot runs now (predicted costs
    from the calibrated call costs, so the count does not depend on the machine)."""
    calls = _spy_pilots(monkeypatch)
    q0 = np.array([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])
    d = np.array([0.3, 0.4, 0.5]) / np.linalg.norm([0.3, 0.4, 0.5])
    scene = wobble.Scene(
        body=[1.0, 2.0, 3.0] * KGM2,
        omega0=[0.4, -0.7, 1.1] * RAD_S,
        attitude0=q0,
        torques=[wobble.Torque.gravity_gradient(1e4 * 7e6**3 / 3 * u.m**3 / u.s**2, 7e6 * u.m, direction=d)],
        t=np.linspace(0.0, 5.0, 101) * u.s,
        accuracy=1e-9,
    )
    ds = wobble.run(scene)
    assert ds.attrs["model"] == "dop853" and ds.attrs["error_estimate"] <= 1e-9
    assert [c for c in calls if c[0] == "splitting"] == []


def test_an_accuracy_out_of_dop853_s_reach_is_refused_without_endless_splitting_pilots(monkeypatch):
    """A small magnet tumbling in a lab field, 1e-6 asked: DOP853 reaches 4.1e-5 at its tolerance floor. The
    splitting tried next was piloted without a bound, at ever shorter steps, for over ten minutes. It is now
    piloted under ten times DOP853's predicted seconds (at least 1 s), and the refusal is DOP853's own."""
    calls = _spy_pilots(monkeypatch)
    scene = wobble.Scene(
        body=[1.0e-7, 2.0e-7, 2.5e-7] * KGM2,
        omega0=[10.0, 20.0, 30.0] * RAD_S,
        torques=[wobble.Torque.magnetic([0.1, 0, 0] * u.A * u.m**2, [0, 0, 0.01] * u.T)],
        t_end=2 * u.s,
        samples=11,
        accuracy=1e-6,
    )
    with pytest.raises(
        InputError, match=r"accuracy: got 1e-06; allowed: at least 4\.1\de-05 for this scene with dop853"
    ):
        wobble.run(scene)
    assert len([c for c in calls if c[0] == "splitting"]) <= 12
