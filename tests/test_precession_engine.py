"""Precession by brute force: the engine's third bodies against the averaged model (issue 18, phase 2).

Ground truth: the first-order averaged rate written out here from its formula
(-(3/2) sum G M/a^3 (1 - e^2)^(-3/2) P2(cos i) (H/omega) cos eps; Goldstein, Poole & Safko
2002, sec. 5.8; Woolard 1953) and the first-order nodal nutation (Woolard 1953; Kinoshita
1977); the shipped scene's numbers against the catalogue; its Sun and Moon against ERFA's
epv00 (VSOP87) and moon98 (ELP-2000/82, abridged). The 20-year run itself is
scripts/bench_precession.py's (docs/performance-precession.md); here a 4-year run with the
Moon's node turning in 0.72 years (so that nutation and precession separate in a short span).
"""

from __future__ import annotations

import copy
import math
import tomllib

import astropy.units as u
import erfa
import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st

import wobble
from wobble.errors import FileFormatError, InputError
from wobble.io.perturbers import load_perturber, measured
from wobble.io.scene_file import example_scene_path, scene_from_mapping
from wobble.models.precession_averaged import averaged_precession, averaging_applies

ARCSEC = math.pi / 180 / 3600
CENTURY = 36525 * 86400.0
YEAR = 365.25 * 86400.0


def _shipped() -> dict:
    with open(example_scene_path("earth_precession"), "rb") as fh:
        return tomllib.load(fh)


def _formula(scene) -> float:
    """The first-order averaged rate of a scene, written out (rad/s)."""
    m = np.asarray(scene.body.moments).reshape(3)
    h = (m[2] - 0.5 * (m[0] + m[1])) / m[2]
    spin = float(np.linalg.norm(scene.omega0[0]))
    axis = wobble.numerics.quaternion.rotate(scene.attitude0[0], np.array([0.0, 0.0, 1.0]))
    total = sum(
        t.gm
        / t.orbit.semi_major_axis**3
        * (1 - t.orbit.eccentricity**2) ** -1.5
        * (1 - 1.5 * math.sin(t.orbit.inclination) ** 2)
        for t in scene.torques
    )
    return -1.5 * total * h / spin * axis[2]


# --------------------------------------------------------------------------
# The shipped scene
# --------------------------------------------------------------------------
def test_the_shipped_scene_takes_its_numbers_from_the_catalogue():
    scene = scene_from_mapping(_shipped())
    sun, moon = scene.torques
    earth = wobble.load_planet("earth").parameters
    for spec, name in ((sun, "sun"), (moon, "moon")):
        pf = load_perturber(name)
        assert spec.name == name and spec.gm == measured(pf, "gm", u.m**3 / u.s**2).value
    pf = load_perturber("moon")
    assert moon.orbit.semi_major_axis == pytest.approx(measured(pf, "semi_major_axis", u.m).value, rel=1e-15)
    assert moon.orbit.eccentricity == measured(pf, "eccentricity", u.one).value
    assert moon.orbit.inclination == pytest.approx(measured(pf, "inclination", u.rad).value, rel=1e-15)
    assert sun.orbit.semi_major_axis == pytest.approx(earth.orbit_semi_major_axis.value, rel=1e-15)
    assert sun.orbit.eccentricity == earth.orbit_eccentricity.value
    # the Moon's node: the catalogued rate from the moving equinox plus the equinox's motion in
    # this frame, the Keplerian model's analytic rate (the budget without the solar perturbation)
    budget = wobble.precession_rate("earth")
    # (the Sun and the Moon only: the planets' terms are not in the scene)
    lunisolar = budget.lunisolar.to_value(u.rad / u.s)
    keplerian = lunisolar - next(t.rate for t in budget.raw.terms if t.name == "moon_solar_perturbation")
    assert moon.orbit.node_rate == pytest.approx(measured(pf, "node_rate", u.rad / u.s).value + keplerian, rel=1e-10)
    assert keplerian == pytest.approx(_formula(scene), rel=1e-12)
    # a symmetric Earth with the catalogue's H and spin, at the J2000 obliquity
    m = np.asarray(scene.body.moments)
    assert m[0] == m[1] and (m[2] - m[0]) / m[2] == pytest.approx(earth.dynamical_flattening.value, rel=1e-12)
    assert np.linalg.norm(scene.omega0[0]) == earth.rotation_rate.value
    axis = wobble.numerics.quaternion.rotate(scene.attitude0[0], np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(axis, [0, math.sin(earth.obliquity.value), math.cos(earth.obliquity.value)], atol=1e-15)
    assert scene.times[-1] >= 20 * YEAR


def _ecliptic(v):
    """ICRS (equatorial) axes to the ecliptic of J2000 (IAU 2006 obliquity; frame bias < 0.03 arcsec)."""
    eps = 84381.406 * ARCSEC
    c, s = math.cos(eps), math.sin(eps)
    return np.stack([v[..., 0], c * v[..., 1] + s * v[..., 2], -s * v[..., 1] + c * v[..., 2]], axis=-1)


def _angle(a, b):
    return np.degrees(
        np.arccos(np.clip(np.sum(a * b, -1) / np.linalg.norm(a, axis=-1) / np.linalg.norm(b, axis=-1), -1, 1))
    )


def test_the_scene_s_sun_and_moon_are_where_erfa_puts_them():
    """The Keplerian Sun within 0.02 deg of VSOP87 (erfa.epv00) over a year; the Keplerian Moon within
    the size of the Sun's perturbations of the lunar orbit (evection 1.27 deg, variation 0.66 deg, ...)
    of ELP-2000/82 (erfa.moon98) over a month: the epochs, angles, rates and frames are the catalogue's."""
    sun, moon = scene_from_mapping(_shipped()).torques
    au = u.au.to(u.m)
    t = np.linspace(0.0, YEAR, 25)
    ref = np.array([-_ecliptic(erfa.epv00(2451545.0, tk / 86400)[0][0]) for tk in t]) * au
    assert np.max(_angle(sun.orbit.position(t)[0], ref)) < 0.02
    t = np.linspace(0.0, 27.3 * 86400, 55)
    ref = np.array([_ecliptic(erfa.moon98(2451545.0, tk / 86400)[0]) for tk in t]) * au
    r = moon.orbit.position(t)[0]
    assert np.max(_angle(r, ref)) < 2.5
    np.testing.assert_allclose(np.linalg.norm(r, axis=-1), np.linalg.norm(ref, axis=-1), rtol=0.02)


# --------------------------------------------------------------------------
# Averaged and integrated
# --------------------------------------------------------------------------
def _short_case() -> dict:
    """Earth, Sun and Moon for 4 years with the Moon's node turning in 0.72 years."""
    data = copy.deepcopy(_shipped())
    data["torques"][1]["node_rate"] = "-500 deg / yr"  # 0.72 yr: apart from the Sun's annual and semi-annual terms
    data["time"] = {"stop": "4 yr", "step": "1 d", "epoch": "2000-01-01 12:00:00"}
    return data


def test_averaged_and_integrated_models_agree_on_a_short_case():
    ds = wobble.run(_short_case())
    assert ds.attrs["model"] == "dop853" and ds.attrs["error_estimate"] <= ds.attrs["accuracy_requested"]
    m = wobble.measure_precession(ds)
    assert m.axis == "angular_momentum" and m.perturber == "moon"
    scene = scene_from_mapping(_short_case())
    assert m.analytic_rate.to_value(u.rad / u.s) == pytest.approx(_formula(scene), rel=1e-12)
    assert abs(m.rate_difference) < 1e-3
    # first-order nodal nutation, written out, with the node from the moving equinox
    moon = scene.torques[1].orbit
    nu = moon.node_rate - _formula(scene)
    mm = np.asarray(scene.body.moments)
    h, spin = (mm[2] - mm[0]) / mm[2], float(np.linalg.norm(scene.omega0[0]))
    eps = 84381.406 * ARCSEC
    p = 1.5 * scene.torques[1].gm / moon.semi_major_axis**3 * (1 - moon.eccentricity**2) ** -1.5 * h / spin
    tilt = math.sin(moon.inclination) * math.cos(moon.inclination)
    lon, obl = -p / abs(nu) * tilt * math.cos(2 * eps) / math.sin(eps), p / abs(nu) * tilt * math.cos(eps)
    assert m.analytic_nutation_longitude.to_value(u.rad) == pytest.approx(lon, rel=1e-12)
    assert m.analytic_nutation_obliquity.to_value(u.rad) == pytest.approx(obl, rel=1e-12)
    assert m.nutation_longitude.to_value(u.rad) == pytest.approx(lon, rel=0.01)
    assert m.nutation_obliquity.to_value(u.rad) == pytest.approx(obl, rel=0.01)
    assert m.nutation_period.to_value(u.yr) == pytest.approx(360 / 500, rel=1e-3)
    # the figure axis gives the same precession; a path and the Dataset give the same measurement
    fig = wobble.measure_precession(ds, axis="axis_direction")
    assert fig.rate.value == pytest.approx(m.rate.value, rel=1e-4)


def test_a_scene_asking_only_for_the_mean_rate_gets_the_averaged_model():
    data = _shipped()
    data.update(outputs=["mean_precession_rate"], accuracy=1e-3)
    data.pop("model")
    ds = wobble.run(data)
    assert (
        ds.attrs["model"] == "averaged-precession" and "only for the mean precession rate" in ds.attrs["model_reason"]
    )
    assert ds["mean_precession_rate"].attrs["cell_methods"] == "time: mean"
    np.testing.assert_allclose(ds["time_bounds"].values, [[0.0, 7305 * 86400.0]])
    assert float(ds["mean_precession_rate"].values[0]) == pytest.approx(_formula(scene_from_mapping(data)), rel=1e-12)
    assert ds.attrs["error_estimate"] < 1e-3
    # the triaxial Earth has the same mean rate (H counts the mean equatorial moment)
    data["body"] = {"planet": "earth"}
    tri = wobble.run(data)
    assert float(tri["mean_precession_rate"].values[0]) == pytest.approx(
        float(ds["mean_precession_rate"].values[0]), rel=1e-9
    )


@pytest.mark.parametrize(
    "change, key, match",
    [
        ({"outputs": ["mean_precession_rate", "angular_momentum"]}, "outputs", "alone"),
        ({"accuracy": 1e-9}, "accuracy", "first-order averaging"),
        ({"torques": "table"}, "outputs", "Keplerian orbits only"),
        ({"model": "dop853"}, "model", "averaged-precession"),
    ],
)
def test_the_mean_rate_is_refused_where_the_averaged_model_cannot_give_it(change, key, match):
    data = _shipped()
    data.update(outputs=["mean_precession_rate"], accuracy=1e-3)
    data.pop("model")
    if change.get("torques") == "table":
        t = np.linspace(0.0, 7306 * 86400.0, 8)
        pos = np.stack([np.cos(t * 1e-7), np.sin(t * 1e-7), 0 * t], -1) * 1.5e11
        data["torques"] = [
            data["torques"][1],
            {
                "kind": "third_body",
                "name": "sun",
                "gm": "1.327e20 m3 s-2",
                "ephemeris": {"times": t * u.s, "positions": pos * u.m},
            },
        ]
    else:
        data.update(change)
    with pytest.raises(InputError, match=f"{key}: .*{match}"):
        wobble.run(data)


@settings(max_examples=20, deadline=None)
@given(st.floats(0.0, 2 * math.pi), st.floats(0.05, 1.5))
def test_the_averaged_rate_does_not_depend_on_where_longitudes_start(turn, obliquity):
    """Turning the inertial frame about z (every node and the body's equator) leaves the rate alone."""
    data = _shipped()
    data["initial"] = {
        "spin_rate": "catalogue",
        "euler_angles": {"value": [math.pi + turn, obliquity, 0.0], "unit": "rad"},
    }
    base = scene_from_mapping(data)
    for t in data["torques"]:
        t["longitude_of_node"] = f"{float(u.Quantity(t['longitude_of_node']).to_value(u.rad)) + turn} rad"
    turned = scene_from_mapping(data)
    a = averaged_precession(base.body, base.omega0, base.attitude0, base.torques)
    b = averaged_precession(turned.body, turned.omega0, turned.attitude0, turned.torques)
    assert averaging_applies(turned.body, turned.omega0, turned.attitude0, turned.torques) is None
    assert b.rate[0] == pytest.approx(a.rate[0], rel=1e-13)
    assert b.obliquity[0] == pytest.approx(obliquity, rel=1e-12)


# --------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------
def _month() -> dict:
    data = _shipped()
    data["time"] = {"stop": "30 d", "step": "1 d", "epoch": "2000-01-01 12:00:00"}
    return data


@pytest.mark.parametrize("outputs", [["axis_direction", "angular_momentum"], ["mean_precession_rate"]])
def test_runs_round_trip_through_netcdf_and_are_cf_compliant(outputs, tmp_path, assert_cf_compliant):
    data = _month()
    data["outputs"] = outputs
    if outputs == ["mean_precession_rate"]:
        data.update(accuracy=1e-3)
        data.pop("model")
    ds = wobble.run(data)
    path = wobble.write_netcdf(ds, tmp_path / "a.nc")
    back = wobble.load(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert_cf_compliant(path)
    wobble.run_to_netcdf(data, tmp_path / "b.nc")
    streamed = wobble.load(tmp_path / "b.nc")
    xr.testing.assert_allclose(streamed, ds, rtol=1e-12)
    assert_cf_compliant(tmp_path / "b.nc")


def test_the_measurement_reads_files_and_speaks_the_result_vocabulary(tmp_path, assert_cf_compliant):
    data = _short_case()
    data["time"]["stop"] = "2 yr"
    path = tmp_path / "run.nc"
    wobble.run_to_netcdf(data, path)
    m = wobble.measure_precession(path)
    d = m.to_dict()
    assert d["axis"] == "angular_momentum" and d["samples"] == 732 and d["perturber"] == "moon"
    assert abs(d["rate_difference"]) < 2e-3 and d["rate_arcsec_per_century"] < 0
    assert "averaged model" in m.summary() and "principal nutation" in m.summary()
    out = wobble.write_netcdf(m.to_dataset(), tmp_path / "m.nc")
    assert_cf_compliant(out)
    back = wobble.load(out)
    assert float(back["precession_rate"]) == pytest.approx(m.rate.to_value(u.rad / u.s), rel=1e-15)
    with pytest.raises(InputError, match="node_rate: .*no Keplerian perturber"):
        wobble.measure_precession(wobble.run("tennis_racket"))
    with pytest.raises(FileFormatError):
        wobble.measure_precession(tmp_path / "missing.nc")
    # member=5 of this one-member run had been accepted, and measured member 0.
    assert wobble.measure_precession(path, member=0).rate == m.rate
    for member, allowed in [(5, r"0 \(the run has one member\)"), (-1, "0 "), ("0", "0 "), (True, "0 "), (0.0, "0 ")]:
        with pytest.raises(InputError, match=f"member: got .*; allowed: {allowed}"):
            wobble.measure_precession(path, member=member)


def test_a_span_shorter_than_the_principal_term_says_so():
    """Over 4 years the Moon's node turning in 36 years (from the moving equinox) cannot be told from the
    secular rate: the fit still returns them, with formal errors far smaller than their real ones, so the
    measurement says so (it said nothing; a 15-year Earth run measured -5046.49 +/- 0.08 "/cy against the
    model's -5040.04)."""
    data = _short_case()
    data["torques"][1]["node_rate"] = "-10 deg / yr"
    m = wobble.measure_precession(wobble.run(data))
    assert any("shorter than the principal term's period (36.1 yr)" in c for c in m.caveats)
    assert m.to_dict()["caveats"] == m.caveats and "caveat: the span (4.0 yr)" in m.summary()
    # The claim itself: the rate is off the averaged model by many of its formal errors.
    assert abs(m.rate - m.analytic_rate) > 5 * m.rate_sigma
    # With the node turning in 0.72 years the same span separates it: no such caveat.
    short = wobble.measure_precession(wobble.run(_short_case()))
    assert not any("principal term" in c for c in short.caveats)


def _q(text, unit) -> float:
    return float(u.Quantity(text).to_value(unit))


def _solar_lines(data: dict, samples: int = 4096) -> dict:
    """The Sun's nutation lines of a scene, from its inputs alone: name -> (psi sin, psi cos, eps sin, eps cos),
    arcsec, in the IAU convention (Delta psi = -(psi - mean)) and against the arguments measure_precession
    names (l: the mean anomaly M; 2L = 2M + 2 varpi and 2L + l = 3M + 2 varpi, varpi the Sun's longitude of
    perigee from the equinox, the x axis of the shipped scene).

    The torque on a symmetric body of axis s, (3 GM / r^3)(C - A)(r.s)(r x s) (MacCullagh; Goldstein, Poole &
    Safko 2002, sec. 5.8), turns its angular momentum C omega s; with s = (sin eps sin psi, -sin eps cos psi,
    cos eps) and the Sun in the reference plane at longitude lambda from the equinox,

        dpsi/dt = -K cos eps sin^2 lambda,   deps/dt = -K sin eps sin lambda cos lambda,   K = 3 GM H / (r^3 omega),

    with H = (C - A)/C. Over one Kepler orbit (M to E by Newton's method, the true anomaly, r = a (1 - e cos E))
    both are periodic in M: each harmonic's coefficients, divided by the line's rate, are the line. Every order
    in e is kept; to first order they are the classical terms (the next test writes them out): in longitude,
    2L's -(3/4)(GM/a^3)(H/omega) cos eps / (dL/dt), -1.27 arcsec for the Earth, and the annual line, r^-3's
    3e sin M with 2L - l's e/2 at the same rate.
    """
    sun = data["torques"][0]
    assert _q(sun["inclination"], u.rad) == 0
    gm, a, e = _q(sun["gm"], u.m**3 / u.s**2), _q(sun["semi_major_axis"], u.m), float(sun["eccentricity"])
    n, perigee_rate = _q(sun["mean_motion"], u.rad / u.s), _q(sun["periapsis_rate"], u.rad / u.s)
    perigee = _q(sun["longitude_of_node"], u.rad) + _q(sun["argument_of_periapsis"], u.rad)
    earth = wobble.load_planet("earth").parameters
    h, spin = earth.dynamical_flattening.value, earth.rotation_rate.value
    eps = _q(data["initial"]["obliquity"], u.rad)
    psi_rate = _formula(scene_from_mapping(data))  # the mean precession: the equinox's motion
    m = 2 * np.pi * np.arange(samples) / samples
    ecc = m + e * np.sin(m)
    for _ in range(8):
        ecc = ecc - (ecc - e * np.sin(ecc) - m) / (1 - e * np.cos(ecc))
    lam = perigee + 2 * np.arctan2(math.sqrt(1 + e) * np.sin(ecc / 2), math.sqrt(1 - e) * np.cos(ecc / 2))
    k = 3 * gm / a**3 * h / spin / (1 - e * np.cos(ecc)) ** 3
    dpsi = -k * math.cos(eps) * np.sin(lam) ** 2
    deps = -k * math.sin(eps) * np.sin(lam) * np.cos(lam)
    lines = {}
    for name, harmonic, shift in (("l_sun", 1, 0.0), ("2L_sun", 2, 2 * perigee), ("2L+l_sun", 3, 2 * perigee)):
        # the line's rate: 2L's from the moving equinox, dL/dt = n + dvarpi/dt - dpsi/dt
        rate = harmonic * n + (2 * (perigee_rate - psi_rate) if shift else 0.0)
        phi = harmonic * m + shift
        cp, sp = 2 * np.mean(np.cos(phi) * dpsi), 2 * np.mean(np.sin(phi) * dpsi)
        ce, se = 2 * np.mean(np.cos(phi) * deps), 2 * np.mean(np.sin(phi) * deps)
        # the rate cp cos phi + sp sin phi integrates to (cp sin phi - sp cos phi) / rate
        lines[name] = np.array([-cp, sp, ce, -se]) / rate * u.rad.to(u.arcsec)
    return lines


def test_the_sun_s_lines_are_the_classical_first_order_terms():
    """_solar_lines, the reference of the tests below, against the classical terms written out to first order in
    e (Woolard 1953; Kinoshita 1977): they differ by O(e^2) of the 2L term."""
    data = _sun_only()
    lines = _solar_lines(data)
    sun = data["torques"][0]
    e, n = float(sun["eccentricity"]), _q(sun["mean_motion"], u.rad / u.s)
    earth = wobble.load_planet("earth").parameters
    eps = _q(data["initial"]["obliquity"], u.rad)
    p = 1.5 * _q(sun["gm"], u.m**3 / u.s**2) / _q(sun["semi_major_axis"], u.m) ** 3
    p *= earth.dynamical_flattening.value / earth.rotation_rate.value * u.rad.to(u.arcsec)  # rad/s -> arcsec/s
    two_l = 2 * (n + _q(sun["periapsis_rate"], u.rad / u.s) - _formula(scene_from_mapping(data)))
    varpi = _q(sun["longitude_of_node"], u.rad) + _q(sun["argument_of_periapsis"], u.rad)
    c, s = math.cos(eps), math.sin(eps)
    # (a/r)^3 cos 2 lambda = cos 2L + (7e/2) cos(2L + l) - (e/2) cos(2L - l) + O(e^2), 2L - l = l + 2 varpi
    first = {
        "2L_sun": [-p * c / two_l, 0, 0, p * s / two_l],
        "2L+l_sun": [-3.5 * e * p * c / (two_l + n), 0, 0, 3.5 * e * p * s / (two_l + n)],
        "l_sun": [
            (3 * e + 0.5 * e * math.cos(2 * varpi)) * p * c / n,
            0.5 * e * math.sin(2 * varpi) * p * c / n,
            0.5 * e * math.sin(2 * varpi) * p * s / n,
            -0.5 * e * math.cos(2 * varpi) * p * s / n,
        ],
    }
    for name, terms in first.items():
        np.testing.assert_allclose(lines[name], terms, rtol=0, atol=3 * e**2 * abs(first["2L_sun"][0]))


def test_a_user_s_terms_come_first_and_those_the_span_cannot_separate_are_refused():
    """measure_precession's left-out check ignored a user's node_rate and extra terms: a perturber's term at a
    user's term's rate was fitted beside it (two near-identical columns), and a user's term at the node's rate
    went in unchecked. The user's terms now come first, a perturber's term the span cannot tell from one of
    them is left out and named, and a user's term the span cannot tell from another is refused."""
    ds = wobble.run(_short_case())
    auto = wobble.measure_precession(ds)
    assert "l_sun" in auto.terms  # the Sun's mean anomaly: the annual term
    year = 2 * np.pi / (365.25 * 86400) * u.rad / u.s
    annual = {"annual": (0.999 * year, 0 * u.rad)}  # 0.004 cycles apart over the 4 years
    mine = wobble.measure_precession(ds, extra=annual)
    assert "annual" in mine.terms and "l_sun" not in mine.terms
    assert any("left out" in c and "l_sun" in c for c in mine.caveats)
    # The annual line, found either way, against the Sun's torque over its Kepler orbit (_solar_lines): the
    # perturber's argument is the mean anomaly M; the user's, 0.999 / yr from phase 0, sees the line turned
    # by the phase M - theta has at mid-span (the two arguments drift 0.004 cycles apart over the span).
    ref = _solar_lines(_short_case())["l_sun"]
    np.testing.assert_allclose(auto.terms["l_sun"], ref, rtol=0, atol=5e-4)  # arcsec, of 0.108
    sun, span = _short_case()["torques"][0], _q(_short_case()["time"]["stop"], u.s)
    turn = _q(sun["mean_anomaly"], u.rad) + (_q(sun["mean_motion"], u.rad / u.s) - 0.999 * year.value) * span / 2
    c, s = math.cos(turn), math.sin(turn)
    turned = [ref[0] * c - ref[1] * s, ref[0] * s + ref[1] * c, ref[2] * c - ref[3] * s, ref[2] * s + ref[3] * c]
    np.testing.assert_allclose(mine.terms["annual"], turned, rtol=0, atol=5e-4)
    assert mine.rate.to_value(u.arcsec / u.yr) == pytest.approx(auto.rate.to_value(u.arcsec / u.yr), abs=0.01)
    # A user's node in place of the Moon's: the Moon's node is then a term like any other, here left out.
    moon = scene_from_mapping(_short_case()).torques[1].orbit
    nu = (moon.node_rate - auto.rate.to_value(u.rad / u.s)) * u.rad / u.s
    given = wobble.measure_precession(ds, node_rate=nu, node_phase=0 * u.rad)
    assert given.perturber is None and given.nutation_longitude is not None
    assert any("left out" in c and "Omega_moon" in c for c in given.caveats)  # its node: the user's, here
    # The principal term's period from the inputs, in Julian years of 365.25 d (the unit the result names):
    # a user's node, 2 pi/|nu| of the rate given; the Moon's, 2 pi/|Omega_dot - psi_dot| from the scene's node rate
    # (-500 deg/yr) against the equinox moving at the first-order averaged rate written out (_formula), which
    # the measured rate meets to 1e-3 of 50 arcsec/yr: 3e-8 of the node's 500 deg/yr.
    julian_year = 365.25 * 86400.0
    assert given.nutation_period.to_value(u.yr) == pytest.approx(2 * math.pi / abs(nu.value) / julian_year, rel=1e-14)
    node_rate = _q(_short_case()["torques"][1]["node_rate"], u.rad / u.s)
    from_inputs = 2 * math.pi / abs(node_rate - _formula(scene_from_mapping(_short_case()))) / julian_year
    assert auto.nutation_period.to_value(u.yr) == pytest.approx(from_inputs, rel=1e-7)
    with pytest.raises(
        InputError, match=r"extra: got 'twice' at .* rad/s; allowed: terms whose rates differ from 'annual'"
    ):
        wobble.measure_precession(ds, extra={**annual, "twice": (year, 0 * u.rad)})
    with pytest.raises(InputError, match="extra: .*allowed: terms whose rates differ from node_rate"):
        wobble.measure_precession(ds, node_rate=nu, extra={"node again": (nu, 0 * u.rad)})
    with pytest.raises(InputError, match="extra: .*allowed: terms whose rates differ from the secular rate"):
        wobble.measure_precession(ds, extra={"slow": (1e-12 * u.rad / u.s, 0 * u.rad)})


def test_run_to_netcdf_counts_the_times_it_wrote(tmp_path):
    """An averaged run writes one time, the mean over its span; its summary (and wobble run's 'members x
    times') said 7306, the scene's times, which the file does not hold."""
    data = _shipped()
    data.update(outputs=["mean_precession_rate"], accuracy=1e-3)
    data.pop("model")
    summary = wobble.run_to_netcdf(data, tmp_path / "mean.nc")
    assert summary["model"] == "averaged-precession"
    assert summary["times"] == wobble.load(tmp_path / "mean.nc").sizes["time"] == 1
    data.update(outputs=["angular_momentum"], time={"stop": "30 d", "step": "1 d", "epoch": "2000-01-01 12:00:00"})
    summary = wobble.run_to_netcdf(data, tmp_path / "full.nc")
    assert summary["times"] == wobble.load(tmp_path / "full.nc").sizes["time"] == 31


def _sun_only(years: float = 4.0) -> dict:
    data = copy.deepcopy(_shipped())
    data["torques"] = [data["torques"][0]]  # the Sun: an orbit in the reference plane, no regressing node
    data["time"] = {"stop": f"{years} yr", "step": "1 d", "epoch": "2000-01-01 12:00:00"}
    return data


def test_without_a_node_every_fitted_term_is_reported_and_a_user_s_term_is_kept():
    """Without a node (the Sun alone), the first term carries the fit's principal argument: it was dropped from
    the result, and since a user's terms come first, a user's term vanished. It is now reported with the
    others, whichever term carries the argument, each with the Sun's line computed from the scene's inputs
    (_solar_lines: 1e-5 arcsec of 1.27 measured)."""
    ds = wobble.run(_sun_only())
    sun = _solar_lines(_sun_only())
    rate = 2 * np.pi / (365.25 * 86400) * u.rad / u.s
    mine = {"mine": (3.3 * rate, 0 * u.rad)}
    alone = wobble.measure_precession(ds)
    assert next(iter(alone.terms)) == "2L_sun" and alone.nutation_longitude is None  # the stand-in, reported
    with_mine = wobble.measure_precession(ds, extra=mine)
    assert "mine" in with_mine.terms and set(alone.terms) <= set(with_mine.terms)
    # The Sun's torque has no line at 3.3 cycles a year: that term fits to nothing beside the Sun's own.
    assert np.hypot(*with_mine.terms["mine"][:2]) < 1e-3 * np.hypot(*sun["2L_sun"][:2])
    # The stand-in first, a user's term first, and either of two: each term the Sun's line.
    other = {"other": (5.5 * rate, 0 * u.rad)}
    first = wobble.measure_precession(ds, extra={**mine, **other})
    second = wobble.measure_precession(ds, extra={**other, **mine})
    assert set(alone.terms) == set(sun) and set(first.terms) == set(second.terms) == set(sun) | {"mine", "other"}
    for fit in (alone, with_mine, first, second):
        for term, line in sun.items():  # arcsec
            np.testing.assert_allclose(fit.terms[term], line, rtol=0, atol=5e-5, err_msg=term)
    # and the same least squares whichever of the two carries the argument: 1e-8 arcsec is 5e-14 rad, rounding
    for term in first.terms:
        np.testing.assert_allclose(first.terms[term], second.terms[term], rtol=0, atol=1e-8)


def test_a_user_s_term_at_the_principal_node_or_a_bad_term_is_refused_naming_it():
    """A user's term at the Moon's node rate went in beside the node (a nutation of -7318 +/- 16020 arcsec
    came out); one sample with a term divided by zero; a NaN rate reached LAPACK; a plain number, a rate in
    metres or a lone value raised AttributeError, UnitConversionError or TypeError."""
    ds = wobble.run(_short_case())
    auto = wobble.measure_precession(ds)
    moon = scene_from_mapping(_short_case()).torques[1].orbit
    nu = (moon.node_rate - auto.rate.to_value(u.rad / u.s)) * u.rad / u.s
    with pytest.raises(
        InputError, match=r"extra: got 'mynode' at .*allowed: terms whose rates differ from the principal node"
    ):
        wobble.measure_precession(ds, extra={"mynode": (nu, 0 * u.rad)})
    with pytest.raises(InputError, match=r"times: got 1 samples; allowed: at least 8"):
        wobble.measure_precession(ds.isel(time=[0]), extra={"a": (1e-7 * u.rad / u.s, 0 * u.rad)})
    for bad, where in [
        ({"a": (np.nan * u.rad / u.s, 0 * u.rad)}, r"extra\['a'\] rate: got nan"),
        ({"a": (1e-7, 0 * u.rad)}, r"extra\['a'\] rate: got 1e-07"),
        ({"a": (1e-7 * u.m, 0 * u.rad)}, r"extra\['a'\] rate: got 1e-07 m"),
        ({"a": 1e-7 * u.rad / u.s}, r"extra\['a'\]: got "),
        ([1, 2], r"extra: got \[1, 2\]"),
    ]:
        with pytest.raises(InputError, match=where):
            wobble.measure_precession(ds, extra=bad)
    with pytest.raises(InputError, match="node_rate: got 1e-07"):
        wobble.measure_precession(ds, node_rate=1e-7)
    # A user's term named as a perturber's is fitted in its place, and the caveats say so.
    named = wobble.measure_precession(ds, extra={"l_sun": (2 * np.pi / (365.25 * 86400) * u.rad / u.s, 0 * u.rad)})
    assert "left out, a term of yours has their names: l_sun" in named.caveats
    # Rates the daily samples cannot see (past pi / day: an alias), arrays, odd names, a lone phase.
    nyquist = np.pi / 86400 * u.rad / u.s
    for kw, where in [
        ({"node_rate": nyquist}, r"node_rate: got 3.63610?e-05 rad/s; allowed: rates below the samples' Nyquist"),
        (
            {"extra": {"fast": (1.5 * nyquist, 0 * u.rad)}},
            r"extra\['fast'\] rate: got 5.45415e-05 rad/s; allowed: rates below",
        ),
        ({"node_rate": [1e-7, 2e-7] * u.rad / u.s}, r"node_rate: got "),
        ({"extra": {"a": ([1e-7, 2e-7] * u.rad / u.s, 0 * u.rad)}}, r"extra\['a'\] rate: got "),
        (
            {"extra": {1: (1e-7 * u.rad / u.s, 0 * u.rad)}},
            r"extra: got a term named 1; allowed: terms named by strings",
        ),
        ({"node_phase": 1 * u.rad}, r"node_phase: got 1.0 rad; allowed: a phase only with node_rate"),
    ]:
        with pytest.raises(InputError, match=where):
            wobble.measure_precession(ds, **kw)
    # A user's node is not the Moon's: no comparison with the model's Moon nutation.
    year = 2 * np.pi / (365.25 * 86400) * u.rad / u.s
    mine = wobble.measure_precession(ds, node_rate=2.7 * year)
    assert mine.analytic_nutation_longitude is None and "None's node" not in mine.summary()


def test_a_perturber_s_terms_past_the_samples_nyquist_rate_are_left_out_and_named():
    """Ten-day samples see the Moon's fortnightly terms (2L, 13.7 d) as slower aliases; they were fitted as
    if seen, a second column for what the alias's own term fits. They are left out and named."""
    data = _short_case()
    data["time"]["step"] = "10 d"
    m = wobble.measure_precession(wobble.run(data))
    (caveat,) = [c for c in m.caveats if "Nyquist" in c]
    assert "2L_moon" in caveat and "2L_moon" not in m.terms
    nyquist = np.pi / (10 * 86400)
    assert f"({nyquist:.3g} rad/s)" in caveat
    daily = wobble.measure_precession(wobble.run(_short_case()))
    assert "2L_moon" in daily.terms and not any("Nyquist" in c for c in daily.caveats)


@pytest.mark.parametrize("block_bytes", ["x", -1, 0, 1.5, True])
def test_run_to_netcdf_refuses_a_block_size_that_is_not_a_positive_whole_number(tmp_path, block_bytes):
    """'x' raised a bare TypeError; -1, 0 and 1.5 were accepted (a file was written with -1)."""
    with pytest.raises(InputError, match="block_bytes: got .*; allowed: a positive whole number of bytes"):
        wobble.run_to_netcdf("tennis_racket", tmp_path / "r.nc", block_bytes=block_bytes)
    assert not (tmp_path / "r.nc").exists()
