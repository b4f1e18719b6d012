"""Scene files: the schema, units everywhere, and errors that name the file and the key."""

from __future__ import annotations

import datetime as _dt
import json
import math

import cftime

import numpy as np
import pytest
import xarray as xr
from astropy import units as u
from astropy.time import Time

import wobble

from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import load_planet
from wobble.io.scene_file import example_scenes, read_scene, scene_from_mapping
from wobble.models import engine as eng
from wobble.numerics import quaternion as Q

BASE = """schema = "wobble-scene/1"
name = "test"
accuracy = 1e-9
outputs = ["omega"]

[body]
moments = { value = [1, 2, 3], unit = "kg m2" }

[initial]
omega = { value = [1, 0.1, 1], unit = "rad/s" }

[time]
stop = "10 s"
samples = 11
"""


def write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_minimal_scene(tmp_path):
    scene = read_scene(write(tmp_path, BASE))
    np.testing.assert_array_equal(scene.body.moments, [1, 2, 3])
    np.testing.assert_array_equal(scene.omega0, [[1, 0.1, 1]])
    np.testing.assert_array_equal(scene.attitude0, [[1, 0, 0, 0]])
    np.testing.assert_allclose(scene.times, np.linspace(0, 10, 11))
    assert scene.outputs == ("omega",) and not scene.ensemble and scene.source.endswith("scene.toml")


def test_quantities_in_every_form_and_unit(tmp_path):
    text = BASE.replace(
        'moments = { value = [1, 2, 3], unit = "kg m2" }', 'moments = { value = [10000, 20000, 30000], unit = "g cm2" }'
    )
    text = text.replace(
        'omega = { value = [1, 0.1, 1], unit = "rad/s" }', 'omega = { value = [360, 36, 360], unit = "deg / s" }'
    )
    text = text.replace('stop = "10 s"', 'stop = "0.5 min"')
    scene = read_scene(write(tmp_path, text))
    np.testing.assert_allclose(scene.body.moments, [1e-3, 2e-3, 3e-3])
    np.testing.assert_allclose(scene.omega0, [[2 * np.pi, 0.2 * np.pi, 2 * np.pi]])
    assert scene.times[-1] == 30.0


@pytest.mark.parametrize(
    "change, key",
    [
        (('[body]\nmoments = { value = [1, 2, 3], unit = "kg m2" }\n', ""), "body"),  # missing section
        (
            ('moments = { value = [1, 2, 3], unit = "kg m2" }', 'moments = { value = [1, 2, 3], unit = "kg" }'),
            "body.moments.unit",
        ),
        (('moments = { value = [1, 2, 3], unit = "kg m2" }', "moments = [1, 2, 3]"), "body.moments"),
        (
            ('moments = { value = [1, 2, 3], unit = "kg m2" }', 'moments = { value = [1, 1, 3], unit = "kg m2" }'),
            "body.moments",
        ),
        (
            ('omega = { value = [1, 0.1, 1], unit = "rad/s" }', 'omega = { value = [1, 0.1, 1], unit = "m/s" }'),
            "initial.omega.unit",
        ),
        (
            ('omega = { value = [1, 0.1, 1], unit = "rad/s" }', 'omega = { value = [1, 0.1], unit = "rad/s" }'),
            "initial.omega",
        ),
        (('stop = "10 s"', 'stop = "-10 s"'), "time.stop"),
        (('stop = "10 s"', 'stop = "10 kg"'), "time.stop"),
        (('stop = "10 s"\nsamples = 11', 'values = { value = [0, 2, 1], unit = "s" }'), "time.values"),
        (('stop = "10 s"\nsamples = 11', 'stop = "10 s"\nstep = "-1 s"'), "time.step"),
        (("samples = 11", "samples = 0"), "time.samples"),
        # A grid beyond memory: samples = 1e30 raised NumPy's "Maximum allowed size exceeded" (fuzz seed 277), and
        # a step of 1e-300 s overflowed int(floor(inf)).
        (("samples = 11", "samples = 1000000000000000000000000000000"), "time.samples"),
        (('stop = "10 s"\nsamples = 11', 'stop = "10 s"\nstep = "1e-300 s"'), "time.step"),
        (("samples = 11", "samples = 11\nfrequency = 3"), "time.frequency"),
        (("accuracy = 1e-9", "accuracy = 2"), "accuracy"),
        (('outputs = ["omega"]', 'outputs = ["omega", "spin_angle"]'), "outputs[1]"),
        (('name = "test"', 'name = "test"\ncolour = "red"'), "colour"),
        (("accuracy = 1e-9", 'accuracy = 1e-9\nmodel = "rk4"'), "model"),
        (("[time]", '[[torques]]\nkind = "electrostatic"\n\n[time]'), "torques[0].kind"),
        (("[time]", '[[torques]]\ntorque = { value = [0, 0, 1], unit = "N m" }\n\n[time]'), "torques[0].kind"),
        (
            ("[time]", '[[torques]]\nkind = "constant"\ntorque = { value = [0, 0, 1], unit = "N" }\n\n[time]'),
            "torques[0].torque.unit",
        ),
        (
            ("[time]", '[[torques]]\nkind = "gravity"\ncenter_of_mass = { value = [0, 0, 1], unit = "m" }\n\n[time]'),
            "torques[0].mass",
        ),
        (
            ("[time]", '[[torques]]\nkind = "gravity_gradient"\ngm = "1 m3/s2"\ndistance = "1 km"\n\n[time]'),
            "torques[0].direction",
        ),
        (("[time]", '[[torques]]\nkind = "damping"\ncoefficient = "-1 N m s"\n\n[time]'), "torques[0].coefficient"),
        (('omega = { value = [1, 0.1, 1], unit = "rad/s" }', 'spin_rate = "catalogue"'), "initial.spin_rate"),
        (('schema = "wobble-scene/1"', 'schema = "wobble-scene/9"'), "schema"),
    ],
)
def test_errors_name_the_file_and_the_key(tmp_path, change, key):
    old, new = change
    assert old in BASE
    path = write(tmp_path, BASE.replace(old, new))
    with pytest.raises(FileFormatError) as info:
        read_scene(path)
    message = str(info.value)
    assert message.startswith(str(path)) and f", {key}" in message, message
    assert "\n" not in message


def test_unreadable_and_missing_files(tmp_path):
    with pytest.raises(FileFormatError, match="no such file"):
        read_scene(tmp_path / "nope.toml")
    with pytest.raises(FileFormatError, match="not valid TOML"):
        read_scene(write(tmp_path, "[body\nmoments = 1"))


def test_a_mapping_without_a_file_raises_input_error_naming_the_key():
    with pytest.raises(InputError, match=r"^time\.stop"):
        scene_from_mapping(
            {
                "body": {"moments": "1 kg m2"},
                "initial": {"omega": {"value": [0, 0, 1], "unit": "rad/s"}},
                "time": {"samples": 3},
            }
        )


def test_euler_angles_and_rates():
    """z-x-z angles: R = Rz(phi) Rx(theta) Rz(psi); body omega from the rates (Goldstein 4.125)."""
    data = {
        "body": {"moments": {"value": [1, 1, 0.5], "unit": "kg m2"}},
        "initial": {
            "euler_angles": {"value": [30, 60, 45], "unit": "deg"},
            "euler_rates": {"value": [0.5, -0.2, 10], "unit": "rad/s"},
        },
        "time": {"stop": "1 s", "samples": 2},
    }
    scene = scene_from_mapping(data)
    phi, theta, psi = np.radians([30, 60, 45])

    def rz(a):
        return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])

    def rx(a):
        return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])

    np.testing.assert_allclose(Q.to_matrix(scene.attitude0[0]), rz(phi) @ rx(theta) @ rz(psi), atol=1e-15)
    # omega from the time derivative of R: [omega]_x = R^T dR/dt, by finite differences
    rates = np.array([0.5, -0.2, 10.0])
    dt = 1e-6

    def r(a):
        return rz(a[0]) @ rx(a[1]) @ rz(a[2])

    angles = np.array([phi, theta, psi])
    skew = r(angles).T @ (r(angles + rates * dt) - r(angles - rates * dt)) / (2 * dt)
    np.testing.assert_allclose(scene.omega0[0], [skew[2, 1], skew[0, 2], skew[1, 0]], rtol=1e-8)


def test_planet_bodies_come_from_the_catalogue():
    """Earth's A < B < C from its file, and its spin rate: nothing retyped."""
    scene = scene_from_mapping(
        {
            "body": {"planet": "earth"},
            "initial": {"spin_rate": "catalogue", "wobble_angle": "0.2 arcsec"},
            "time": {"stop": "1 d", "samples": 2},
        }
    )
    planet, _ = load_planet("earth")
    a, b, c = scene.body.moments
    assert a < b < c
    # Earth's file gives J2 and H: C/(M a^2) = J2/H, M = GM/G.
    c_ref = (
        (planet.j2.value / planet.dynamical_flattening.value)
        * planet.gm.value
        / planet.gravitational_constant.value
        * planet.equatorial_radius.value**2
    )
    assert math.isclose(c, c_ref, rel_tol=1e-15)
    assert math.isclose((c - (a + b) / 2) / c, planet.flattening, rel_tol=1e-9)
    assert math.isclose(np.linalg.norm(scene.omega0), planet.rotation_rate.value, rel_tol=1e-15)
    assert math.isclose(
        np.arctan2(np.hypot(*scene.omega0[0, :2]), scene.omega0[0, 2]), np.radians(0.2 / 3600), rel_tol=1e-12
    )


def test_gravity_gradient_primary_from_the_catalogue():
    scene = scene_from_mapping(
        {
            "body": {"moments": "1 kg m2"},
            "initial": {"omega": {"value": [0, 0, 1], "unit": "rad/s"}},
            "torques": [
                {"kind": "gravity_gradient", "primary": "earth", "distance": "7000 km", "orbit_normal": [0, 0, 1]}
            ],
            "time": {"stop": "1 s", "samples": 2},
        }
    )
    assert scene.torques[0].gm == load_planet("earth")[0].gm.value


def test_named_solids_come_from_the_bodies_library(tmp_path):
    """A box of edges (a, b, c): I = m (b^2 + c^2)/12 and cyclic (closed form, notes 5.1)."""
    text = BASE.replace(
        'moments = { value = [1, 2, 3], unit = "kg m2" }',
        'solid = "box"\nmass = "1 kg"\nedges = { value = [0.2, 0.1, 0.03], unit = "m" }',
    )
    scene = read_scene(write(tmp_path, text))
    a, b, c = 0.2, 0.1, 0.03
    expected = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 12
    np.testing.assert_allclose(np.sort(np.ravel(scene.body.moments)), np.sort(expected), rtol=1e-14)


def test_ensembles_from_lists_of_states(tmp_path):
    text = BASE.replace(
        'omega = { value = [1, 0.1, 1], unit = "rad/s" }',
        'omega = { value = [[1, 0.1, 1], [0, 1, 0.1]], unit = "rad/s" }',
    )
    scene = read_scene(write(tmp_path, text))
    assert scene.members == 2 and scene.ensemble
    bad = text.replace("[initial]", "[initial]\nattitude = [[1, 0, 0, 0], [1, 0, 0, 0], [1, 0, 0, 0]]")
    with pytest.raises(FileFormatError, match="initial.attitude"):
        read_scene(write(tmp_path, bad, "bad.toml"))


def test_epoch_sets_the_time_units(tmp_path):
    scene = read_scene(write(tmp_path, BASE.replace('stop = "10 s"', 'epoch = "2024-03-20T03:06:00Z"\nstop = "10 s"')))
    assert scene.epoch == "2024-03-20 03:06:00"
    with pytest.raises(FileFormatError, match="time.epoch"):
        read_scene(write(tmp_path, BASE.replace('stop = "10 s"', 'epoch = "spring"\nstop = "10 s"'), "b.toml"))


@pytest.mark.parametrize("name", example_scenes())
def test_example_scenes_parse(name):
    """Every example: every physical number with a unit (a bare number is refused), and a description."""
    from wobble.io.scene_file import example_scene_path

    scene = read_scene(example_scene_path(name))
    assert scene.description and scene.title
    assert all(
        isinstance(t, (eng.ConstantTorque, eng.UniformGravity, eng.GravityGradient, eng.ThirdBody, eng.LinearDamping))
        for t in scene.torques
    )


@pytest.mark.parametrize(
    ("epoch", "reference"),
    [
        ("2020-01-01 06:00:00.5", "2020-01-01T06:00:00.5"),  # the half second was cut
        ("0001-01-01", "0001-01-01T00:00:00"),  # written "1-01-01"
        (Time("2020-01-01T00:01:09.184", scale="tt"), "2020-01-01T00:00:00"),  # TT - UTC = 69.184 s in 2020
        (_dt.datetime(2024, 3, 20, 3, 6, 0, 250000), "2024-03-20T03:06:00.25"),
    ],
)
def test_the_file_s_times_decode_to_the_epoch_plus_t(tmp_path, epoch, reference):
    """The CF times of a scene's file, decoded by xarray, are the epoch (in UTC) plus t, to the microsecond."""
    kgm2, rad_s = u.kg * u.m**2, u.rad / u.s
    scene = wobble.Scene([1, 2, 3] * kgm2, [1e-3, 1, 1e-3] * rad_s, t_end=2 * u.s, samples=3, epoch=epoch)
    path = tmp_path / "epoch.nc"
    wobble.run_to_netcdf(scene, path)
    with xr.open_dataset(path, decode_times=False) as ds:
        time = ds["time"]
        # Before 1582-10-15 CF's "standard" calendar is the Julian one: wobble's dates are proleptic Gregorian.
        assert time.attrs["calendar"] == ("proleptic_gregorian" if reference < "1582-10-15" else "standard")
        decoded = cftime.num2date(
            time.values, time.attrs["units"], time.attrs["calendar"], only_use_cftime_datetimes=True
        )
    got = [np.datetime64(d.isoformat(), "us") for d in decoded]  # cftime's proleptic Gregorian is numpy's calendar
    want = np.datetime64(reference, "us") + np.array([0, 1, 2]) * np.timedelta64(1, "s")
    assert np.all(np.array(got) == want)


def test_an_array_of_times_is_not_an_epoch():
    with pytest.raises(InputError, match="epoch.*one date-time"):
        wobble.Scene(
            [1, 2, 3] * u.kg * u.m**2, [0, 0, 1] * u.rad / u.s, t_end=1 * u.s, samples=2, epoch=Time(["2020-01-01"] * 2)
        )


def test_explicit_times_of_a_linspace_grid_are_kept_as_start_stop_samples():
    """A Scene given t = np.linspace(0, 100, 200001) s wrote all 200,001 times into the file's 'scene'
    attribute (2 MB of JSON). linspace's own grid is now kept as start, stop and samples, which give back
    exactly those times; uneven times are kept as given (a step grid, start + k step: the next test)."""
    body, w0 = [1.0, 2.0, 3.0] * u.kg * u.m**2, [1.0, 0.1, 1.0] * u.rad / u.s
    t = np.linspace(0.0, 100.0, 200_001) * u.s
    scene = wobble.Scene(body=body, omega0=w0, t=t)
    assert np.array_equal(scene._scene.times, t.value)
    ds = wobble.run(wobble.Scene(body=body, omega0=w0, t=t[:2001]))
    assert len(ds.attrs["scene"]) < 1000
    assert json.loads(ds.attrs["scene"])["time"]["samples"] == 2001
    assert np.array_equal(ds["time"].values, t[:2001].value)  # seconds since the epoch, the same bits
    for given in (np.geomspace(1.0, 100.0, 50) * u.s, [0.0, 1.0, 3.0, 7.0] * u.s):
        kept = json.loads(wobble.run(wobble.Scene(body=body, omega0=w0, t=given)).attrs["scene"])["time"]
        assert "values" in kept and len(kept["values"]["value"]) == len(given)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_explicit_times_of_a_step_grid_are_kept_as_start_stop_step(seed):
    """Times made as start + k step (np.arange's way) that linspace does not give exactly (7.25 s + k 0.1 s
    for 100 samples, and about one in twelve random grids) were copied into the 'scene' attribute; they are
    now kept as start, stop and step, which the scene reader turns back into the same bits."""
    body, w0 = [1.0, 2.0, 3.0] * u.kg * u.m**2, [1.0, 0.1, 1.0] * u.rad / u.s
    t = (7.25 + 0.1 * np.arange(100)) * u.s
    assert not np.array_equal(np.linspace(7.25, t[-1].value, 100), t.value)  # not linspace's grid
    ds = wobble.run(wobble.Scene(body=body, omega0=w0, t=t))
    kept = json.loads(ds.attrs["scene"])["time"]
    assert set(kept) == {"start", "stop", "step"} and len(ds.attrs["scene"]) < 1000
    assert np.array_equal(ds["time"].values, t.value)
    rng = np.random.default_rng(seed)
    for _ in range(50):
        start, step, n = rng.uniform(-10, 10), rng.uniform(1e-3, 3), int(rng.integers(3, 3000))
        grid = (start + step * np.arange(n)) * u.s
        scene = wobble.Scene(body=body, omega0=w0, t=grid)
        assert "values" not in scene._scene.mapping["time"], (start, step, n)
        assert np.array_equal(scene._scene.times, grid.value)
