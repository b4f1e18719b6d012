"""Scenes: the model-choice rule, the heavy-top seam, accuracy met or refused, outputs, every example runs."""

from __future__ import annotations

import astropy.units as u
import numpy as np
import pytest

import wobble
from wobble.errors import FileFormatError, InputError
from wobble.models import scene as S
from wobble.models.engine import attitude_angle
from wobble.models.free import free_rotation
from wobble.numerics import quaternion as Q

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s


def free_scene(moments, omega, **kw):
    kw.setdefault("t_end", 10 * u.s)
    kw.setdefault("samples", 11)
    return wobble.Scene(body=moments * KGM2, omega0=omega * RAD_S, **kw)


def top_scene(**kw):
    theta = np.radians(60)
    kw.setdefault("t_end", 3 * u.s)
    kw.setdefault("samples", 31)
    return wobble.Scene(
        body=[1.0, 1.0, 0.5] * KGM2,
        omega0=[0.0, 0.0, 10.0] * RAD_S,
        attitude0=[np.cos(theta / 2), np.sin(theta / 2), 0, 0],
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, 1] * u.m, g=1 * u.m / u.s**2)],
        **kw,
    )


def test_free_symmetric_body_gets_the_closed_form():
    ds = wobble.run(free_scene([1, 1, 2], [0.3, 0.1, 1.0]))
    assert ds.attrs["model"] == "free-symmetric"
    assert ds.attrs["error_estimate"] < 1e-14


def test_free_asymmetric_body_gets_elliptic_functions_and_is_exact():
    ds = wobble.run(free_scene([1, 2, 3], [1.0, 0.1, 1.0], accuracy=1e-12))
    assert ds.attrs["model"] == "free-elliptic"
    assert "free-symmetric: no two principal moments are equal" in ds.attrs["model_reason"]
    exact = free_rotation([1, 2, 3], [1.0, 0.1, 1.0])
    np.testing.assert_allclose(ds["omega"].values, exact.omega(ds["time"].values), atol=1e-15)


def test_a_zero_torque_still_gets_the_exact_model():
    scene = free_scene([1, 2, 3], [1.0, 0.1, 1.0], torques=[wobble.Torque.constant([0, 0, 0] * u.N * u.m)])
    assert wobble.run(scene).attrs["model"] == "free-elliptic"


def _top_reference(ds, center_of_mass=(0.0, 0.0, 1.0)):
    """DOP853 at rtol 1e-13 on Euler's equations with gravity: independent of the exact top."""
    from wobble.models.engine import UniformGravity, simulate

    theta = np.radians(60)
    return simulate(
        [1.0, 1.0, 0.5],
        [0, 0, 10.0],
        [np.cos(theta / 2), np.sin(theta / 2), 0, 0],
        ds["time"].values,
        [UniformGravity(1.0, list(center_of_mass), [0, 0, -1.0])],
        rtol=1e-13,
        estimate=False,
    )


def _assert_matches(ds, ref, tol):
    w, wr = ds["omega"].values[:, 0] if ds["omega"].ndim == 3 else ds["omega"].values, ref.omega[:, 0]
    assert np.max(np.abs(w - wr) / np.max(np.abs(wr), axis=0)) <= tol
    q = ds["attitude"].values[:, 0] if ds["attitude"].ndim == 3 else ds["attitude"].values
    assert np.max(attitude_angle(q, ref.attitude[:, 0])) <= tol


def test_symmetric_top_under_gravity_gets_the_exact_heavy_top():
    """Notes 5.7: the engine hands a top on a pivot to the exact elliptic solution of issue 5."""
    ds = wobble.run(top_scene(accuracy=1e-12))
    assert ds.attrs["model"] == "heavy-top"
    assert ds.attrs["error_estimate"] <= 1e-12
    _assert_matches(ds, _top_reference(ds), 1e-10)


def test_a_hanging_top_is_the_same_top_with_turned_body_axes():
    """Centre of mass below the pivot on body axis 3 (M g l < 0 along +z): the exact top, axes turned back."""
    theta = np.radians(60)
    scene = wobble.Scene(
        body=[1.0, 1.0, 0.5] * KGM2,
        omega0=[0.0, 0.0, 10.0] * RAD_S,
        attitude0=[np.cos(theta / 2), np.sin(theta / 2), 0, 0],
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, -1] * u.m, g=1 * u.m / u.s**2)],
        t_end=3 * u.s,
        samples=31,
    )
    ds = wobble.run(scene)
    assert ds.attrs["model"] == "heavy-top"
    np.testing.assert_allclose(
        ds["attitude"].values[0], [np.cos(theta / 2), np.sin(theta / 2), 0, 0], rtol=0, atol=2e-16
    )
    _assert_matches(ds, _top_reference(ds, (0.0, 0.0, -1.0)), 1e-10)


def test_a_top_ensemble_integrates_and_says_why():
    omega = [[0.0, 0.0, 10.0], [0.0, 0.0, 11.0]] * RAD_S
    theta = np.radians(60)
    scene = wobble.Scene(
        body=[1.0, 1.0, 0.5] * KGM2,
        omega0=omega,
        attitude0=[np.cos(theta / 2), np.sin(theta / 2), 0, 0],
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, 1] * u.m, g=1 * u.m / u.s**2)],
        t_end=1 * u.s,
        samples=11,
    )
    ds = wobble.run(scene)
    assert ds.attrs["model"] in ("splitting-4", "splitting-6", "dop853")
    assert "heavy-top: an ensemble" in ds.attrs["model_reason"]
    assert ds.attrs["error_estimate"] <= ds.attrs["accuracy_requested"]


def test_what_is_not_a_heavy_top():
    """An asymmetric body or an off-axis centre of mass is integrated."""
    off = wobble.Scene(
        body=[1.0, 1.2, 0.5] * KGM2,
        omega0=[0, 0, 10.0] * RAD_S,
        t_end=1 * u.s,
        samples=3,
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, 1] * u.m, g=1 * u.m / u.s**2)],
    )
    assert wobble.run(off).attrs["model"] != "heavy-top"
    side = wobble.Scene(
        body=[1.0, 1.0, 0.5] * KGM2,
        omega0=[0, 0, 10.0] * RAD_S,
        t_end=1 * u.s,
        samples=3,
        torques=[wobble.Torque.gravity(1 * u.kg, [0.1, 0, 1] * u.m, g=1 * u.m / u.s**2)],
    )
    assert wobble.run(side).attrs["model"] != "heavy-top"


def test_forcing_a_model():
    ds = wobble.run(free_scene([1, 2, 3], [1.0, 0.1, 1.0]), model="dop853")
    assert ds.attrs["model"] == "dop853" and ds.attrs["model_reason"].startswith("forced")
    with pytest.raises(InputError, match="model"):
        wobble.run(top_scene(), model="free-elliptic")
    with pytest.raises(InputError, match="model"):
        wobble.run(top_scene(), model="euler")
    with pytest.raises(InputError, match="model"):
        wobble.run(free_scene([1, 2, 3], [1.0, 0.1, 1.0]), model="heavy-top")  # no gravity: not a top
    assert wobble.run(top_scene(), model="heavy-top").attrs["model"] == "heavy-top"
    custom = wobble.Torque.custom(lambda t, w, q: -0.01 * w)
    with pytest.raises(InputError, match="model"):
        wobble.run(free_scene([1, 2, 3], [1.0, 0.1, 1.0], torques=[custom]), model="splitting")


def test_accuracy_asked_is_met_for_a_torqued_scene():
    """The run's error against a tight reference is within the accuracy asked (and the estimate)."""
    from wobble.models.engine import UniformGravity, simulate

    for model in (None, "dop853"):
        ds = wobble.run(top_scene(accuracy=1e-8), model=model)
        theta = np.radians(60)
        ref = simulate(
            [1.0, 1.0, 0.5],
            [0, 0, 10.0],
            [np.cos(theta / 2), np.sin(theta / 2), 0, 0],
            ds["time"].values,
            [UniformGravity(1.0, [0, 0, 1.0], [0, 0, -1.0])],
            rtol=1e-13,
            estimate=False,
        )
        w, wr = ds["omega"].values, ref.omega[:, 0]
        err = np.max(np.abs(w - wr) / np.max(np.abs(wr), axis=0))
        assert err <= 1e-8
        assert np.max(attitude_angle(ds["attitude"].values, ref.attitude[:, 0])) <= 1e-8


def test_unreachable_accuracy_names_the_field():
    with pytest.raises(InputError, match="accuracy"):
        wobble.run(top_scene(accuracy=1e-16))
    with pytest.raises(InputError, match="accuracy"):
        wobble.run(free_scene([1, 2, 3], [1.0, 0.1, 1.0], accuracy=1e-17))


@pytest.mark.parametrize(
    ("kwargs", "parameter", "allowed"),
    [
        (dict(t_end=1.0), "t_end", "unit of time"),
        (dict(t_end=-1 * u.s), "t_end", "a time after t_start (0.0 s)"),
        (dict(t_start=1.0), "t_start", "unit of time"),
        (dict(t_end=None, samples=None, t=[0, 1, 2] * u.m), "t", "unit of time"),
        (dict(samples=0), "samples", "(1 when t_end = t_start)"),
        (dict(omega0=[0, 0, 1] * u.Hz), "omega0", "angular speed"),
        (dict(attitude0=[1, 1, 0]), "attitude0", "4 components"),
        (dict(epoch="yesterday"), "epoch", "ISO 8601"),
    ],
)
def test_python_scene_errors_name_the_python_parameter(kwargs, parameter, allowed):
    """Scene builds a scene file's mapping: its errors named the file's keys (time.stop for t_end)."""
    kw = dict(body=[1, 2, 3] * KGM2, omega0=[1.0, 0.1, 1.0] * RAD_S, t_end=10 * u.s, samples=11)
    with pytest.raises(InputError) as info:
        wobble.Scene(**{**kw, **kwargs})
    assert info.value.parameter == parameter
    assert str(info.value).startswith(f"{parameter}: got ") and allowed in info.value.allowed


@pytest.mark.parametrize("g", [9.8, [0, 0, -9.8], 9.8 * u.m, [0, -9.8] * u.m / u.s**2])
def test_gravity_errors_name_the_keyword_g(g):
    """A vector g is the scene file's "gravity" key: its errors named that, not the Python keyword."""
    with pytest.raises(InputError) as info:
        wobble.Torque.gravity(0.5 * u.kg, [0, 0, 0.2] * u.m, g=g)
    assert info.value.parameter == "g"


def test_only_the_outputs_asked_for_are_computed(monkeypatch):
    def no_attitude(*a, **k):
        raise AssertionError("the attitude was computed but not asked for")

    monkeypatch.setattr("wobble.models.free.FreeRotationModel.attitude", no_attitude)
    ds = wobble.run(free_scene([1, 2, 3], [1.0, 0.1, 1.0], outputs=["omega", "kinetic_energy"]))
    assert set(ds.data_vars) == {"omega", "kinetic_energy"}
    np.testing.assert_allclose(ds["kinetic_energy"].values, 0.5 * (1 + 2 * 0.01 + 3), rtol=1e-14)


def test_energy_of_a_non_conservative_torque_is_refused():
    scene = free_scene(
        [1, 2, 3],
        [1.0, 0.1, 1.0],
        torques=[wobble.Torque.damping(0.1 * u.N * u.m * u.s)],
        outputs=["omega", "total_energy"],
    )
    with pytest.raises(InputError, match="outputs"):
        wobble.run(scene)


def test_every_output_of_a_top():
    names = list(S.OUTPUTS)
    ds = wobble.run(top_scene(outputs=names))
    assert set(ds.data_vars) == set(names)
    assert np.ptp(ds["total_energy"].values) < 1e-8
    np.testing.assert_allclose(ds["tilt"].values[0], np.radians(60), rtol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(ds["axis_direction"].values, axis=-1), 1.0, rtol=1e-14)
    np.testing.assert_allclose(ds["wobble_angle"].values[0], 0.0, atol=1e-15)


def test_ensemble_scene_has_a_member_dimension_and_matches_single_runs():
    omega = [[1.0, 0.1, 1.0], [0.1, 1.0, 0.2], [0.5, 0.5, 0.5]] * RAD_S
    ds = wobble.run(wobble.Scene(body=[1, 2, 3] * KGM2, omega0=omega, t_end=20 * u.s, samples=21))
    assert ds.sizes["member"] == 3 and ds.attrs["model"] == "free-elliptic"
    for i in range(3):
        exact = free_rotation([1, 2, 3], omega[i].value)
        assert np.max(np.abs(ds["omega"].values[:, i] - exact.omega(ds["time"].values))) < 1e-13
        assert np.max(attitude_angle(ds["attitude"].values[:, i], exact.attitude(ds["time"].values))) < 1e-12
    assert ds.attrs["error_estimate"] < 1e-12


def test_initial_attitude_and_tensor_bodies():
    """A body given by a tensor in a rotated frame, with an initial attitude: the exact free motion."""
    rot = Q.to_matrix(Q.normalize(np.array([0.8, 0.3, -0.4, 0.2])))
    tensor = rot @ np.diag([1.0, 2.0, 3.0]) @ rot.T
    w_body = rot @ np.array([1.0, 0.1, 1.0])
    q0 = Q.normalize(np.array([0.9, 0.1, 0.2, -0.3]))
    scene = wobble.Scene(body={"tensor": tensor * KGM2}, omega0=w_body * RAD_S, attitude0=q0, t_end=5 * u.s, samples=6)
    ds = wobble.run(scene)
    exact = free_rotation([1, 2, 3], [1.0, 0.1, 1.0])
    t = ds["time"].values
    np.testing.assert_allclose(ds["omega"].values, exact.omega(t) @ rot.T, atol=1e-13)
    q_rot = Q.from_matrix(rot)
    want = Q.multiply(q0, Q.multiply(q_rot, Q.multiply(exact.attitude(t), Q.conjugate(q_rot))))
    assert np.max(attitude_angle(ds["attitude"].values, want)) < 1e-13


@pytest.mark.parametrize("name", wobble.example_scenes())
def test_every_example_scene_runs(name):
    ds = wobble.run(name)
    assert ds.attrs["error_estimate"] <= ds.attrs["accuracy_requested"]
    assert ds.sizes["time"] > 1
    if "attitude" in ds:
        assert np.max(np.abs(np.linalg.norm(ds["attitude"].values, axis=-1) - 1)) < 1e-14


def test_example_scene_physics():
    """The examples do what they say: the racket flips; Earth's rigid wobble period; a steady gyroscope."""
    racket = wobble.run("tennis_racket")
    w2 = racket["omega"].sel(axis="2").values
    assert w2.max() > 11.9 and w2.min() < -11.9
    earth = wobble.run("earth_free_wobble")
    w1 = earth["omega"].sel(axis="1").values
    crossings = np.flatnonzero(np.diff(np.sign(w1)) > 0)
    days = np.diff(earth["time"].values[crossings]).mean() / 86400
    assert 300 < days < 308  # the rigid Euler period, ~304 sidereal days (not the observed 433 d)
    gyro = wobble.run("gyroscope")
    assert np.ptp(gyro["tilt"].values) < 1e-9


def test_scene_file_errors_name_the_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        'schema = "wobble-scene/1"\naccuracy = 1e-17\n[body]\nmoments = "1 kg m2"\n'
        '[initial]\nomega = { value = [1, 0.1, 1], unit = "rad/s" }\n[time]\nstop = "1 s"\nsamples = 3\n'
    )
    with pytest.raises(FileFormatError, match="bad.toml"):
        wobble.run(path)


def test_a_torque_free_scene_forced_onto_the_splitting_uses_the_shortest_composition():
    # Without torque every composition is exact (the drifts are the exact free flow): Strang's
    # costs least. (With order 6, a century of daily Earth outputs ran past the fuzzer's bound.)
    import wobble

    scene = {
        "schema": "wobble-scene/1",
        "name": "spin",
        "accuracy": 1e-10,
        "outputs": ["omega"],
        "body": {"moments": {"value": [1.0, 2.0, 3.0], "unit": "kg m2"}},
        "initial": {"omega": {"value": [0.01, 0.0, 1.0], "unit": "rad/s"}},
        "time": {"stop": "20 s", "samples": 201},
    }
    ds = wobble.run(scene, model="splitting")
    assert ds.attrs["model"] == "splitting-2"
    assert ds.attrs["error_estimate"] < 1e-10
    exact = wobble.run(scene)  # the exact free body
    assert exact.attrs["model"] == "free-elliptic"
    assert float(abs(ds["omega"] - exact["omega"]).max()) < 1e-10


def test_a_splitting_named_with_its_order_is_refused_with_where_the_order_comes_from():
    # The output names the model splitting-6; --model splitting-6 was refused without saying why.
    with pytest.raises(InputError, match=r"model: got splitting-6; allowed: auto or one of .*picks its order"):
        wobble.run("satellite_gravity_gradient", model="splitting-6")


@pytest.mark.parametrize(
    ("kwargs", "given"), [({}, "neither"), ({"direction": [1, 0, 0], "orbit_normal": [0, 0, 1]}, "both")]
)
def test_a_gravity_gradient_needs_exactly_one_direction(kwargs, given):
    """Without a direction the refusal showed the mapping's keys as the value: got ['distance', 'gm', ...]."""
    with pytest.raises(InputError, match=rf"^direction: got {given}; allowed: exactly one of direction"):
        wobble.Torque.gravity_gradient(3.986e14 * u.m**3 / u.s**2, 7e6 * u.m, **kwargs)


def test_a_span_of_zero_takes_one_sample():
    """t_end = t_start with several samples repeated one time ([0, 0, 0]); the CF checker refuses a time
    coordinate that does not increase strictly (a review finding). One sample is the instant itself."""
    scene = dict(body=[1, 2, 3] * u.kg * u.m**2, omega0=[0.1, 1, 0.1] * u.rad / u.s, t_end=0 * u.s)
    with pytest.raises(InputError, match=r"samples: got 3; allowed: a whole number >= 2 \(1 when t_end = t_start\)"):
        wobble.run(wobble.Scene(**scene, samples=3))
    assert wobble.run(wobble.Scene(**scene, samples=1)).time.values.tolist() == [0.0]


def test_a_python_scene_runs_again_from_its_record():
    """The ``scene`` attribute of a run built in Python held each torque as {"kind", "python"} only, and running
    it again was refused (torques[0].python); it holds the torque's arguments now, and gives the same motion."""
    import json

    q0 = np.array([0.99, 0.1, 0.0, 0.0]) / np.linalg.norm([0.99, 0.1])
    scene = wobble.Scene(
        body=[1.0, 1.0, 0.5] * u.kg * u.m**2,
        omega0=[0.1, 0.2, 20.0] * u.rad / u.s,
        attitude0=q0,
        torques=[
            wobble.Torque.gravity(0.5 * u.kg, [0, 0, 0.2] * u.m),
            wobble.Torque.damping(1e-3 * u.kg * u.m**2 / u.s),
        ],
        t_end=2 * u.s,
        samples=5,
    )
    first = wobble.run(scene)
    record = json.loads(first.attrs["scene"])
    assert record["torques"][1] == {"kind": "damping", "coefficient": {"value": 0.001, "unit": "m2 kg / s"}}
    again = wobble.run(record)
    assert again.attrs["model"] == first.attrs["model"]
    np.testing.assert_array_equal(again.omega.values, first.omega.values)
    # Torques given as a generator are read once: the record still holds them.
    kwargs = dict(body=[1.0, 1.0, 0.5] * u.kg * u.m**2, omega0=[0.1, 0.2, 20.0] * u.rad / u.s, t_end=2 * u.s, samples=5)
    lazy = wobble.Scene(**kwargs, torques=(t for t in [wobble.Torque.damping(1e-3 * u.kg * u.m**2 / u.s)]))
    assert [t["kind"] for t in lazy.model.mapping["torques"]] == ["damping"]
