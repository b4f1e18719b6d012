"""The third-body torque, added by the four-step recipe (a class, a compiled branch, a scene-file
entry, these tests), against ground truth.

* Kepler's equation against mpmath at 30 digits; the position against the rotation of the
  orbit-plane ellipse (Murray & Dermott 1999, eqs. 2.41 and 2.122) and the time average of
  r r^T / r^5 over an orbit against its closed form (1 - e^2)^(-3/2) (1 - n n^T) / (2 a^3).
* The orbit-averaged torque of the kind on an oblate body against the closed form
  3 G M (C - A) / (2 a^3 (1 - e^2)^(3/2)) (s . n)(s x n) (Goldstein, Poole & Safko 2002, sec. 5.8).
* The balances of the torqued body: dL/dt = tau (L(t) - L(0) against the integral of the
  inertial torque along the run), dE/dt = dV/dt at fixed attitude for a moving perturber,
  and E = T + V constant for a perturber standing still; on the compiled and the NumPy DOP853
  and the splitting.
* The ephemeris table and the callable give the Keplerian run; a table that is not monotone or
  does not cover the run, a hyperbolic orbit, an orbit inside the body, a negative mass and
  an obliquity outside [0, 180] deg are refused naming the key, by the CLI with exit 2 and
  nothing written.
"""

from __future__ import annotations

import math

import astropy.units as u
import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import simpson

import wobble
from wobble.errors import FileFormatError, InputError
from wobble.io.scene_file import scene_from_mapping
from wobble.models.engine import BodyModel, Engine, attitude_angle
from wobble.models.orbit import EphemerisTable, KeplerOrbit, tide_harmonic
from wobble.models.precession import averaged_tidal_torque
from wobble.models.torques import ThirdBody
from wobble.numerics import kepler
from wobble.numerics import quaternion as Q


# --------------------------------------------------------------------------
# Kepler's equation and the position
# --------------------------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(st.floats(-50.0, 50.0), st.floats(0.0, 0.995))
def test_kepler_equation_against_mpmath(m, e):
    mpmath.mp.dps = 30
    mr = m - 2 * math.pi * round(m / (2 * math.pi))
    ref = mpmath.findroot(lambda x: x - e * mpmath.sin(x) - mr, mpmath.mpf(mr) + e * mpmath.sin(mr))
    assert abs(kepler.solve_kepler(np.array([m]), e)[0] - float(ref)) < 4e-15 / (1 - e)
    assert kepler.solve_kepler_one(m, e) == pytest.approx(float(ref), abs=4e-15 / (1 - e))


def _rot(axis, angle):
    c, s = math.cos(angle), math.sin(angle)
    if axis == "z":
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def test_position_is_the_rotated_ellipse_with_turning_node_and_periapsis():
    orbit = KeplerOrbit(2.0e8, 0.3, 0.4, 1.0, 2.0, 0.5, 1e-5, -3e-7, 2e-7)
    t = np.linspace(0.0, 3e6, 37)
    r, d = orbit.position(t)
    for k, tk in enumerate(t):
        E = float(kepler.solve_kepler(0.5 + 1e-5 * tk, 0.3))
        plane = np.array([2.0e8 * (math.cos(E) - 0.3), 2.0e8 * math.sqrt(1 - 0.09) * math.sin(E), 0.0])
        want = _rot("z", 1.0 - 3e-7 * tk) @ _rot("x", 0.4) @ _rot("z", 2.0 + 2e-7 * tk) @ plane
        np.testing.assert_allclose(r[k], want, rtol=0, atol=1e-7 * 2e8)
        assert d[k] == pytest.approx(np.linalg.norm(want), rel=1e-14)
        assert kepler.position_one(tk, orbit.elements) == pytest.approx((*r[k], d[k]), rel=1e-13, abs=1e-6)


@pytest.mark.parametrize("e", [0.0, 0.0549, 0.6])
def test_time_average_of_the_tidal_tensor_over_an_orbit(e):
    """<r r^T / r^5> = (1 - e^2)^(-3/2) (1 - n n^T) / (2 a^3): Kepler's time law, not only the ellipse."""
    a, n = 3.0e8, 2.6e-6
    orbit = KeplerOrbit(a, e, 0.3, 0.7, 1.9, 0.0, n)
    t = np.arange(4096) * (2 * math.pi / n) / 4096  # uniform in time: spectral for a periodic integrand
    r, d = orbit.position(t)
    mean = np.einsum("ti,tj->ij", r, r / d[:, None] ** 5) / t.size
    normal = orbit.normal
    want = (1 - e * e) ** -1.5 * (np.eye(3) - np.outer(normal, normal)) / (2 * a**3)
    np.testing.assert_allclose(mean, want, rtol=0, atol=1e-12 * np.max(np.abs(want)))


# --------------------------------------------------------------------------
# The torque of the kind, averaged over an orbit
# --------------------------------------------------------------------------
@pytest.mark.parametrize("e", [0.0, 0.2])
def test_orbit_averaged_torque_has_the_closed_form(e):
    a_mom, c_mom = 8.0e37, 8.0263e37
    gm, a, n = 4.9e12, 3.844e8, 2.66e-6
    spec = ThirdBody(gm, orbit=KeplerOrbit(a, e, 0.09, 2.2, 5.5, 2.4, n))
    engine = Engine(BodyModel.from_moments([a_mom, a_mom, c_mom]), [spec])
    q = Q.normalize(np.array([0.97, 0.2, -0.1, 0.05]))  # any fixed attitude
    t = np.arange(2048) * (2 * math.pi / n) / 2048
    tau = engine.torque(t, np.zeros((t.size, 3)), np.broadcast_to(q, (t.size, 4)))
    mean_inertial = Q.rotate(q, tau.mean(axis=0))
    axis = Q.rotate(q, np.array([0.0, 0.0, 1.0]))
    want = averaged_tidal_torque(gm, c_mom - a_mom, axis, spec.orbit.normal, a, e)
    np.testing.assert_allclose(mean_inertial, want, rtol=0, atol=1e-12 * np.linalg.norm(want))


# --------------------------------------------------------------------------
# Balances of the torqued body
# --------------------------------------------------------------------------
MOMENTS = np.array([1.0, 1.6, 2.1])  # ascending: the internal frame is the body frame
W0 = np.array([0.3, -0.5, 2.0])
Q0 = Q.normalize(np.array([0.9, 0.3, -0.2, 0.25]))


def _perturber(moving=True):
    # k = 3 GM / a^3 ~ 0.5 s^-2: the torque turns the body by radians in the run
    orbit = KeplerOrbit(
        1.0e3, 0.3, 0.6, 0.4, 1.0, 0.2, 0.7 if moving else 0.0, 0.05 if moving else 0.0, -0.04 if moving else 0.0
    )
    return ThirdBody(1.6e8, orbit=orbit)


RUNS = [
    ("dop853", {"rtol": 1e-12, "backend": "compiled"}),
    ("dop853", {"rtol": 1e-12, "backend": "python"}),
    ("splitting", {"step": 5e-3, "order": 6}),
]


@pytest.mark.parametrize("method, kw", RUNS)
def test_angular_momentum_changes_by_the_integral_of_the_torque(method, kw):
    engine = Engine(BodyModel.from_moments(MOMENTS), [_perturber()])
    t = np.linspace(0.0, 6.0, 1201)
    run = engine.integrate(W0, Q0, t, method=method, estimate=False, **kw)
    w, q = run.omega[:, 0], run.attitude[:, 0]
    big_l = Q.rotate(q, MOMENTS * w)
    tau = Q.rotate(q, engine.torque(t, w, q))
    integral = simpson(tau, x=t, axis=0)
    np.testing.assert_allclose(big_l[-1] - big_l[0], integral, rtol=0, atol=1e-8 * np.linalg.norm(big_l[0]))
    assert np.linalg.norm(integral) > 0.05 * np.linalg.norm(big_l[0])  # not a weak torque: L changes by 8 %


@pytest.mark.parametrize("method, kw", RUNS)
def test_energy_changes_by_the_explicit_time_derivative_of_the_potential(method, kw):
    """dE/dt = dV/dt at fixed attitude (the perturber moves; E = T + V with V = (3GM/2r^3) u.Iu)."""
    engine = Engine(BodyModel.from_moments(MOMENTS), [_perturber()])
    bound = engine.torques[0]
    t = np.linspace(0.0, 6.0, 1201)
    run = engine.integrate(W0, Q0, t, method=method, estimate=False, **kw)
    w, q = run.omega[:, 0], run.attitude[:, 0]
    energy = 0.5 * np.sum(MOMENTS * w * w, axis=-1) + bound.potential(t, q, None)
    h = 1e-5
    dv_dt = (bound.potential(t + h, q, None) - bound.potential(t - h, q, None)) / (2 * h)
    change = np.concatenate([[0.0], [simpson(dv_dt[: k + 1], x=t[: k + 1]) for k in range(1, t.size)]])
    assert np.ptp(energy) > 0.05 * abs(energy[0])  # the energy does change
    np.testing.assert_allclose(energy - energy[0], change, rtol=0, atol=1e-7 * abs(energy[0]))


@pytest.mark.parametrize("method, kw", RUNS)
def test_energy_is_conserved_when_the_perturber_stands_still(method, kw):
    engine = Engine(BodyModel.from_moments(MOMENTS), [_perturber(moving=False)])
    assert engine.conservative and not engine.torques[0].time_dependent
    t = np.linspace(0.0, 20.0, 201)
    run = engine.integrate(W0, Q0, t, method=method, estimate=False, **kw)
    e = np.array([engine.energy(tk, *engine.state_in(run.omega[k], run.attitude[k])) for k, tk in enumerate(t)])
    assert np.max(np.abs(e - e[0])) < 1e-9 * abs(e[0])


# --------------------------------------------------------------------------
# The table and the callable give the Keplerian run
# --------------------------------------------------------------------------
def _spin_run(torque, backend="python", t_end=2.0):
    engine = Engine(BodyModel.from_moments(MOMENTS), [torque])
    t = np.linspace(0.0, t_end, 41)
    return engine.integrate(W0, Q0, t, rtol=1e-12, backend=backend, estimate=False)


def test_ephemeris_table_and_callable_reproduce_the_keplerian_run():
    kep = _perturber()
    exact = _spin_run(kep, backend="compiled")
    grid = np.linspace(-0.1, 2.1, 2201)  # h n = 7e-4: spline error (5/384)(h n)^4 ~ 1e-14 of r
    table = ThirdBody(kep.gm, ephemeris=EphemerisTable(grid, kep.orbit.position(grid)[0]))
    callable_ = ThirdBody(kep.gm, position=lambda tt: kep.orbit.position(tt)[0])
    for other in (table, callable_):
        run = _spin_run(other)
        assert np.max(np.abs(run.omega - exact.omega)) < 1e-9 * np.linalg.norm(W0)
        assert np.max(attitude_angle(run.attitude, exact.attitude)) < 1e-9
    engine = Engine(BodyModel.from_moments(MOMENTS), [table])
    with pytest.raises(InputError, match="backend"):
        engine.integrate(W0, Q0, [0.0, 1.0], backend="compiled")
    assert not engine.compilable and engine.splittable


def test_a_table_is_refused_outside_its_span_and_when_not_monotone():
    kep = _perturber()
    grid = np.linspace(0.0, 1.0, 11)
    pos = kep.orbit.position(grid)[0]
    with pytest.raises(InputError, match="ephemeris.times.*monotone"):
        EphemerisTable(grid[::-1], pos)
    table = ThirdBody(kep.gm, ephemeris=EphemerisTable(grid, pos))
    engine = Engine(BodyModel.from_moments(MOMENTS), [table])
    with pytest.raises(InputError, match="ephemeris.times.*covering"):
        engine.integrate(W0, Q0, [0.0, 2.0])


# --------------------------------------------------------------------------
# Scene file and API
# --------------------------------------------------------------------------
MOON = {
    "kind": "third_body",
    "name": "moon",
    "gm": "4.902800118e12 m3 s-2",
    "semi_major_axis": "384399 km",
    "eccentricity": 0.0549,
    "inclination": "5.145396 deg",
    "longitude_of_node": "125.04455501 deg",
    "argument_of_periapsis": "318.30868811 deg",
    "mean_anomaly": "134.96340251 deg",
    "mean_motion": "1717915923.2178 arcsec / hyr",
    "node_rate": "-6967930.5815 arcsec / hyr",
    "periapsis_rate": "21611339.63 arcsec / hyr",
}


def _earth_scene(torque, **initial):
    return {
        "body": {"planet": "earth", "symmetric": True},
        "initial": {"spin_rate": "catalogue", "obliquity": "23.44 deg", **initial},
        "torques": [torque],
        "time": {"stop": "2 d", "step": "1 d"},
        "outputs": ["angular_momentum"],
    }


def test_scene_file_and_api_give_the_same_torque():
    from_file = scene_from_mapping(_earth_scene(MOON)).torques[0]
    arcsec_cy = u.arcsec / (100 * u.yr)
    from_api = wobble.Torque.third_body(
        4.902800118e12 * u.m**3 / u.s**2,
        semi_major_axis=384399 * u.km,
        eccentricity=0.0549,
        inclination=5.145396 * u.deg,
        longitude_of_node=125.04455501 * u.deg,
        argument_of_periapsis=318.30868811 * u.deg,
        mean_anomaly=134.96340251 * u.deg,
        mean_motion=1717915923.2178 * arcsec_cy,
        node_rate=-6967930.5815 * arcsec_cy,
        periapsis_rate=21611339.63 * arcsec_cy,
        name="moon",
    ).spec
    for spec in (from_file, from_api):
        assert isinstance(spec, ThirdBody) and spec.name == "moon"
        np.testing.assert_allclose(spec.orbit.elements, from_file.orbit.elements, rtol=1e-15)
    assert from_file.orbit.node_rate == pytest.approx(-2 * math.pi / (18.6 * 365.25 * 86400), rel=1e-3)


@pytest.mark.parametrize(
    "change, key",
    [
        ({"eccentricity": 1.2}, "torques[0].eccentricity"),
        ({"semi_major_axis": "6000 km"}, "torques[0].semi_major_axis"),
        ({"gm": "-4.9e12 m3 s-2"}, "torques[0].gm"),
        (
            {
                "ephemeris": {
                    "times": {"value": [0, 1, 3, 2], "unit": "d"},
                    "positions": {"value": [[4e5, 0, 0], [0, 4e5, 0], [-4e5, 0, 0], [0, -4e5, 0]], "unit": "km"},
                }
            },
            "torques[0].ephemeris.times",
        ),
        (
            {
                "ephemeris": {
                    "times": {"value": [0, 0.5, 1, 1.5], "unit": "d"},
                    "positions": {"value": [[4e5, 0, 0], [0, 4e5, 0], [-4e5, 0, 0], [0, -4e5, 0]], "unit": "km"},
                }
            },
            "torques[0].ephemeris.times",
        ),
    ],
)
def test_bad_perturbers_are_refused_naming_the_key(change, key):
    torque = {k: v for k, v in MOON.items() if not ("ephemeris" in change and k not in ("kind", "name", "gm"))}
    torque.update(change)
    with pytest.raises(InputError, match=key.replace("[", r"\[").replace("]", r"\]")):
        scene_from_mapping(_earth_scene(torque))


def test_an_obliquity_outside_0_180_deg_is_refused():
    with pytest.raises(InputError, match=r"initial.obliquity: got 200.0 deg; allowed: an angle in \[0, 180\] deg"):
        scene_from_mapping(_earth_scene(MOON, obliquity="200 deg"))


@pytest.mark.parametrize(
    "line, key",
    [
        ("eccentricity = 1.5", "eccentricity"),
        ('semi_major_axis = "3000 km"', "semi_major_axis"),
        ('gm = "-1 m3 s-2"', "gm"),
        ('obliquity = "-5 deg"', "initial.obliquity"),
    ],
)
def test_cli_refuses_bad_scenes_with_exit_2_and_writes_nothing(tmp_path, capsys, line, key):
    from wobble.cli import main

    scene = tmp_path / "bad.toml"
    text = (
        '[body]\nplanet = "earth"\nsymmetric = true\n[initial]\nspin_rate = "catalogue"\n'
        'obliquity = "23.44 deg"\n'
        '[[torques]]\nkind = "third_body"\nname = "moon"\ngm = "4.9e12 m3 s-2"\nsemi_major_axis = "384399 km"\n'
        'eccentricity = 0.0549\nmean_motion = "13.06 deg / d"\n[time]\nstop = "1 d"\nstep = "1 d"\n'
    )
    name = line.split(" =")[0]
    text = "\n".join(line if row.startswith(name + " =") else row for row in text.splitlines()) + "\n"
    scene.write_text(text)
    out = tmp_path / "out.nc"
    assert main(["run", str(scene), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and key in err[0] and "bad.toml" in err[0]
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


@pytest.mark.parametrize("times, problem", [("[0, 1, 3, 2]", "monotone"), ("[0, 0.2, 0.4, 0.6]", "covering")])
def test_cli_refuses_a_bad_ephemeris_table_with_exit_2(tmp_path, capsys, times, problem):
    from wobble.cli import main

    scene = tmp_path / "table.toml"
    scene.write_text(
        '[body]\nplanet = "earth"\n[initial]\nspin_rate = "catalogue"\nobliquity = "23.44 deg"\n'
        '[[torques]]\nkind = "third_body"\nname = "moon"\ngm = "4.9e12 m3 s-2"\n'
        f'ephemeris = {{ times = {{ value = {times}, unit = "d" }}, positions = {{ value = [[4e5, 0, 0], [0, 4e5, 0], '
        '[-4e5, 0, 0], [0, -4e5, 0]], unit = "km" } }\n[time]\nstop = "1 d"\nstep = "0.5 d"\n'
    )
    out = tmp_path / "out.nc"
    assert main(["run", str(scene), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "table.toml, torques[0].ephemeris.times" in err[0] and problem in err[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.toml"]


def test_a_scene_file_cannot_hold_a_callable_and_elements_need_an_orbit(tmp_path):
    with pytest.raises(InputError, match="position"):
        scene_from_mapping(_earth_scene({"kind": "third_body", "gm": "1 m3 s-2", "position": "moon.csv"}))
    table = {
        "times": {"value": [0, 1, 2, 3], "unit": "d"},
        "positions": {"value": [[4e5, 0, 0], [0, 4e5, 0], [-4e5, 0, 0], [0, -4e5, 0]], "unit": "km"},
    }
    with pytest.raises(InputError, match="eccentricity"):
        scene_from_mapping(
            _earth_scene({"kind": "third_body", "gm": "1 m3 s-2", "ephemeris": table, "eccentricity": 0.1})
        )
    path = tmp_path / "x.toml"
    path.write_text(
        '[body]\nmoments = "1 kg m2"\n[initial]\nomega = { value = [0, 0, 1], unit = "rad/s" }\n'
        '[[torques]]\nkind = "third_body"\ngm = "1 m3 s-2"\n[time]\nstop = "1 s"\nsamples = 2\n'
    )
    with pytest.raises(FileFormatError, match="x.toml, torques.0..semi_major_axis"):
        wobble.run(path)


def _tide_highest_harmonic(orbit: KeplerOrbit, count: int = 2**16, periods: int = 1) -> float:
    """The highest frequency, in units of the mean motion, in the inertial tide tensor u u^T / r^3 over
    ``periods`` orbital periods (``count`` samples), from the orbit's 3-D positions (kepler.position: its own
    path to u and r, with its turning node and periapsis), above 1e-3 of the largest line: a whole harmonic
    for one period, in steps of 1 / periods (exact lines when the secular rates complete whole turns too)."""
    t = np.arange(count) * (2 * math.pi * periods / orbit.mean_motion / count)
    r, d = orbit.position(t)
    u = r / d[:, None]
    tide = np.einsum("ti,tj->tij", u, u).reshape(count, 9) / d[:, None] ** 3
    amplitude = np.max(np.abs(np.fft.rfft(tide, axis=0)), axis=1)
    amplitude[0] = 0.0
    return int(np.flatnonzero(amplitude >= 1e-3 * np.max(amplitude))[-1]) / periods


@pytest.mark.parametrize("e", [0.0, 0.0549, 0.3, 0.6, 0.9, 0.95])
def test_a_tide_s_fastest_frequency_is_its_highest_harmonic(e):
    """The tide of a perturber (quadratic in its direction, 1/r^3) runs at harmonics of the mean motion: 2 for
    a circle, up to the periapsis passage's width for an eccentric orbit; a turning node and periapsis shift
    them. The orbit's tide_rate is not below what the inertial tensor's own FFT counts, and within 10 % (and one
    harmonic) of it, for an orbit standing still and one whose node and periapsis turn (its tensor repeats after
    20 periods: the FFT over 20 sees every line); a table of the orbit measures the same (the figures' alias
    bound uses them)."""
    n = 2 * math.pi / 86400.0
    still = KeplerOrbit(1e7, e, 0.3, 0.2, 1.1, 0.0, mean_motion=n)
    measured = _tide_highest_harmonic(still)
    assert measured <= tide_harmonic(e) <= 1.1 * measured + 1
    assert measured * n <= still.tide_rate() <= (1.1 * measured + 1) * n
    # The node turns once in 10 periods and the periapsis once in 20, the same way: the fastest line moves up
    # by twice both (2 (n + dw/dt) + 2 dOmega/dt for a circle), to 2.3 n; to e = 0.3 the rate is that line.
    turning = KeplerOrbit(1e7, e, 0.3, 0.2, 1.1, 0.0, mean_motion=n, node_rate=0.1 * n, periapsis_rate=0.05 * n)
    moving = _tide_highest_harmonic(turning, count=20 * 2**14, periods=20)
    assert moving == pytest.approx(measured + 0.3, abs=1e-9) if e <= 0.3 else moving > measured
    assert moving * n <= turning.tide_rate() * (1 + 1e-12) and turning.tide_rate() <= (1.1 * moving + 1) * n
    if e <= 0.6:  # a table of 30 periods, 48 rows a period (the Moon's would be 6-hourly)
        grid = np.linspace(0.0, 30 * 86400.0, 30 * 48 + 1)
        table = EphemerisTable(grid, still.position(grid)[0])
        assert measured * n <= table.tide_rate() <= (1.1 * measured + 1) * n
        assert ThirdBody(1e12, ephemeris=table).field_rate() == table.tide_rate()
    assert ThirdBody(1e12, orbit=turning).field_rate() == turning.tide_rate()
    assert ThirdBody(1e12, position=lambda t: still.position(t)[0]).field_rate() is None


def test_a_gravity_gradient_s_rate_is_twice_its_mean_motion_either_way():
    """A retrograde orbit (negative mean motion) lowered the figures' bound: its field turned at -n."""
    from wobble.models.torques import GravityGradient

    for n in (1e-3, -1e-3):
        spec = GravityGradient(gm=3.986e14, distance=7e6, orbit_normal=np.array([0.0, 0.0, 1.0]), mean_motion=n)
        assert spec.field_rate() == 2e-3
    fixed = GravityGradient(gm=3.986e14, distance=7e6, direction=np.array([1.0, 0.0, 0.0]))
    assert fixed.field_rate() == 0.0


def test_a_long_dense_table_is_not_aliased_and_a_still_one_has_no_tide():
    """Past 2^19 samples the table was sampled more coarsely than its rows, and a 1.2-million-row table of an
    e = 0.3 orbit read 8.5 n against its 13 n; a perturber that stands still read about 2 pi / h."""
    n = 2 * math.pi / 86400.0
    orbit = KeplerOrbit(1e7, 0.3, 0.3, 0.2, 1.1, 0.0, mean_motion=n)
    grid = np.linspace(0.0, 40 * 86400.0, 1_200_001)
    measured = _tide_highest_harmonic(orbit)
    assert measured * n <= EphemerisTable(grid, orbit.position(grid)[0]).tide_rate() <= 1.25 * measured * n
    still = EphemerisTable(np.linspace(0.0, 864000.0, 100), np.tile([1e8, 0.0, 0.0], (100, 1)))
    assert still.tide_rate() == 0.0


def test_the_tide_harmonic_of_a_nearly_parabolic_orbit_is_not_below_the_tensor_s():
    """Past 2^20 samples (e above about 0.997) the harmonic is the periapsis passage's width, not an FFT's
    count: at e = 0.998 it must still be at least what the inertial tide tensor's own FFT counts (125,944),
    and not far above it."""
    n = 2 * math.pi / 86400.0
    measured = _tide_highest_harmonic(KeplerOrbit(1e7, 0.998, 0.3, 0.2, 1.1, 0.0, mean_motion=n), count=2**20)
    assert measured <= tide_harmonic(0.998) <= 1.6 * measured
