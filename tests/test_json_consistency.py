"""The second review of the ``--json`` outputs (2026-11-29): units in key names, ``unit`` beside a summary, the
hindcast's anchors joined to the scores, the same keys for every body in ``modes``, uncertainties named
``<quantity>_uncertainty_<unit>``, and ``deprecated_keys`` at the root of every command that renames a key.
Each test reads the JSON a script reads (``--json``, or ``to_dict()``); the old keys must still hold their
values (one release, wobble.io.json_keys)."""

from __future__ import annotations

import json
import math
import tomllib

import mpmath as mp
import pytest
from astropy import units as u

from json_listings import listings as _listings
from wobble.cli import main
from wobble.io.catalog import catalogue_file
from wobble.io.json_keys import values_at


def _json(capsys, *args):
    assert main([*args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _check_listings(doc):
    """Every listing's old path holds exactly what its new path holds (and there is one)."""
    for listing in _listings(doc):
        for old, new in listing["deprecated_keys"].items():
            assert values_at(listing, old) == values_at(listing, new) != [], (old, new)


# --- 1. inertia: units in the keys ------------------------------------------------------------------------------------


def test_inertia_names_its_units_in_its_keys_and_keeps_the_old_ones(capsys):
    """A uniform ellipsoid of 2 kg, semi-axes 3, 2, 1 m: I = m (b^2 + c^2)/5, ... = 2, 4 and 5.2 kg m2."""
    d = _json(capsys, "inertia", "--solid", "ellipsoid", "--mass", "2", "--axes", "3", "2", "1")
    assert d["mass_kg"] == 2.0 and d["center_of_mass_m"] == [0.0, 0.0, 0.0] == d["reference_point_m"]
    assert d["principal_moments_kg_m2"] == pytest.approx([2.0, 4.0, 5.2], rel=1e-15)
    assert d["tensor_kg_m2"] == [pytest.approx(row, rel=1e-15, abs=0) for row in ([2, 0, 0], [0, 4, 0], [0, 0, 5.2])]
    assert d["principal_moment_differences_kg_m2"] == pytest.approx([2.0, 1.2, 3.2], rel=1e-15)
    assert d["principal_axes"] == [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]  # unit vectors, no unit
    renames = {
        "mass": "mass_kg",
        "center_of_mass": "center_of_mass_m",
        "reference_point": "reference_point_m",
        "tensor": "tensor_kg_m2",
        "principal_moments": "principal_moments_kg_m2",
        "principal_moment_differences": "principal_moment_differences_kg_m2",
    }
    assert d["deprecated_keys"] == renames
    _check_listings(d)
    # The units map stays one release (deprecated_keys cannot list it: no new key holds its value). It names the
    # old keys with a unit, and the pure-number axes, each unit the one its new key's suffix spells, so a script's
    # units["tensor"] still reads "kg m2"; and each unit is one astropy reads as the quantity's own.
    assert set(d["units"]) == set(renames) | {"principal_axes"} and d["units"]["principal_axes"] == "1"
    for old, new in renames.items():
        assert new == f"{old}_{d['units'][old].replace(' ', '_')}"
    assert u.Unit(d["units"]["tensor"]) == u.kg * u.m**2 and u.Unit(d["units"]["center_of_mass"]) == u.m


def test_inertia_about_a_point_gives_the_point_in_metres(capsys):
    d = _json(capsys, "inertia", "--solid", "cone", "--mass", "250 g", "--radius", "3 cm", "--height", "8 cm")
    about = _json(
        capsys, "inertia", "--solid", "cone", "--mass", "250 g", "--radius", "3 cm", "--height", "8 cm",
        "--about", "0", "0", "-0.06",
    )  # fmt: skip
    assert about["reference_point_m"] == about["reference_point"] == [0.0, 0.0, -0.06] and d["mass_kg"] == 0.25
    # The cone's closed form about its centre of mass, 3/80 M (4 r^2 + h^2), and the parallel axes, + M d^2.
    m, r, h, dist = 0.25, 0.03, 0.08, 0.06
    assert d["tensor_kg_m2"][0][0] == pytest.approx(3 / 80 * m * (4 * r * r + h * h), rel=1e-14)
    assert about["tensor_kg_m2"][0][0] == pytest.approx(3 / 80 * m * (4 * r * r + h * h) + m * dist**2, rel=1e-14)
    assert set(about) == set(d)


# --- 2. sweep: unit, as astropy writes it -----------------------------------------------------------------------------


def test_sweep_gives_its_unit_as_astropy_writes_it(capsys):
    d = _json(capsys, "sweep", "mars_chandler", "--members", "40", "--quiet")
    assert d["unit"] == "d" and u.Unit(d["unit"]) == u.day and u.Unit(d["unit"]).to_string() == d["unit"]
    # The old key keeps its old value for one release (a script may compare it with "day"), so it is no alias.
    assert d["units"] == "day" and "deprecated_keys" not in d
    assert 190 < d["percentiles"]["50"] < 220  # in that unit: Mars' Chandler period in days
    _check_listings(d)


@pytest.mark.parametrize(("cf", "astropy_string"), [("s", "s"), ("day", "d"), ("1", ""), ("rad s-1", "rad / s")])
def test_a_sweep_summary_s_unit_is_astropy_s_spelling(cf, astropy_string):
    from wobble.api.sweep import SweepSummary

    summary = SweepSummary(
        variable="x", units=cf, members=2, valid=2, mean=1.0, std=0.0, percentiles={}, observed=math.nan,
        invalid_reasons={},
    )  # fmt: skip
    d = summary.to_dict()
    assert d["unit"] == astropy_string and u.Unit(d["unit"]) == u.Unit(cf) and d["units"] == cf
    assert summary.units == cf  # the Python attribute keeps the file's spelling


# --- 3. forecast --hindcast: the anchors name the key of their score --------------------------------------------------


def test_hindcast_anchors_join_the_scores_by_their_current_key(capsys):
    d = _json(
        capsys, "forecast", "--hindcast", "2019-01-01:2019-02-01", "--every", "14d", "--horizon", "10d",
        "--latency", "1d", "--scheduler", "synchronous",
    )  # fmt: skip
    assert d["anchors"] and d["methods"]
    for anchor in d["anchors"]:
        # metric is the old name of the score's key, metric_key the key: deprecated_keys maps the one to the other.
        assert d["deprecated_keys"][f"methods.*.{anchor['metric']}"] == f"methods.*.{anchor['metric_key']}"
        assert anchor["metric_key"].endswith("_mas")  # the anchors' values are in mas, as the scores so named
        for scores in d["methods"].values():
            assert anchor["metric_key"] in scores
    assert [a["metric_key"] for a in d["anchors"]] == ["rms_2d_mas", "rms_x_mas", "rms_y_mas", "mae_x_mas", "mae_y_mas"]
    _check_listings(d)


# --- 4. modes: the same figure keys for every body --------------------------------------------------------------------


def test_modes_gives_every_body_the_same_figure_keys(capsys):
    earth, mars = _json(capsys, "modes", "earth", "mars")
    figure_e, figure_m = earth["hydrostatic_figure"], mars["hydrostatic_figure"]
    assert set(figure_e) == set(figure_m) and set(earth) == set(mars)
    # Mars's profile ships no published flattening: null, as the README says of what does not apply.
    assert figure_m["observed_flattening"] is None and figure_m["reference_hydrostatic_flattening"] is None
    # Earth's are the IERS 1/f = 298.25642 and Chambat et al.'s hydrostatic 1/f = 299.8 (within its 0.05 %).
    assert figure_e["observed_flattening"]["value"] == pytest.approx(1 / 298.25642, rel=1e-7)
    assert figure_e["reference_hydrostatic_flattening"]["value"] == pytest.approx(1 / 299.8, rel=5e-4)
    assert set(figure_e["observed_flattening"]) == {"value", "uncertainty", "source"}


# --- 5. modes: <quantity>_uncertainty_<unit> --------------------------------------------------------------------------


_ROUND_EARTH_KEYS = (
    "gm",
    "equatorial_radius",
    "rotation_rate",
    "dynamical_flattening",
    "j2",
    "love_number_k2",
    "fluid_core_equatorial_moment",
    "core_compliance_beta",
    "core_compliance_gamma",
    "observed_fcn_period",
)
# A uniform liquid core under a uniform mantle, Earth's size (PREM's radii), the mantle's density giving Earth's
# GM/G (to 1e-8): its hydrostatic core flattening has a closed form.
_CORE_RADIUS, _RADIUS, _CORE_DENSITY, _MANTLE_DENSITY = 3480e3, 6371e3, 11000.0, 4445.153


def _toml_table(key: str, value, unit: str, uncertainty=0.0, source="a test's two-layer body", status="assumed"):
    """One parameter's table of a wobble/1 file; the value a number or a (nested) list of numbers."""
    lines = [f"[parameters.{key}]", f"value = {json.dumps(value)}", f"uncertainty = {json.dumps(uncertainty)}"]
    lines += [f"unit = {json.dumps(unit)}", f"source = {json.dumps(source)}", f"status = {json.dumps(status)}", ""]
    return "\n".join(lines)


def _round_earth_files(tmp_path):
    """A body file of Earth's catalogued FCN numbers without its triaxiality and anelasticity (so that the FCN is
    the root of the 2 x 2 determinant of Sasao, Okubo & Saito 1980, below), G written in it (CODATA 2018), and a
    two-layer density profile; returns their paths."""
    from astropy import constants

    earth = tomllib.loads(catalogue_file("earth").read_text())["parameters"]
    tables = [
        _toml_table(k, float(e["value"]), e["unit"], float(e["uncertainty"]), e["source"], e["status"])
        for k, e in ((k, earth[k]) for k in _ROUND_EARTH_KEYS)
    ]
    g = constants.G.si
    tables.append(_toml_table("gravitational_constant", g.value, "m3 kg-1 s-2", g.uncertainty, "CODATA 2018", "read"))
    body = tmp_path / "round_earth.toml"
    body.write_text('schema = "wobble/1"\nkind = "planet"\nname = "round_earth"\n\n' + "\n".join(tables))
    core, radius = _CORE_RADIUS / 1e3, _RADIUS / 1e3
    tables = [
        _toml_table("layer_top_radius", [core, radius], "km"),
        _toml_table("density_coefficients", [[_CORE_DENSITY / 1e3], [_MANTLE_DENSITY / 1e3]], "g cm-3"),
        _toml_table("normalising_radius", radius, "km"),
        _toml_table("fluid_core_inner_radius", 0.0, "km"),
        _toml_table("fluid_core_outer_radius", core, "km"),
    ]
    profile = tmp_path / "two_layer.toml"
    profile.write_text('schema = "wobble/1"\nkind = "density_profile"\nname = "two_layer"\n\n' + "\n".join(tables))
    return body, profile


def _two_layer_core_flattening(spin, g):
    """e_f of the uniform core of the two-layer body, first-order Clairaut in closed form: in the mantle the level
    surfaces have eps(r) = s (r^5 + Q)/(r^2 (rho_m r^3 + K)), K = (rho_c - rho_m) b^3, Q = 3 K b^5/(5 rho_m b^3
    + 2 K) (eps'(b) = 0, the core homogeneous), s from a eps'(a) + 2 eps(a) = 5q/2; e_f = eps(b) (Jeffreys 1976,
    The Earth, sec. 4.03; as tests/test_hydrostatic.py)."""
    b, a, rho_c, rho_m = (mp.mpf(x) for x in (_CORE_RADIUS, _RADIUS, _CORE_DENSITY, _MANTLE_DENSITY))
    k = (rho_c - rho_m) * b**3
    q = spin**2 * a**3 / (g * 4 * mp.pi / 3 * (rho_m * a**3 + k))
    big_q = 3 * k * b**5 / (5 * rho_m * b**3 + 2 * k)

    def shape(r):
        return (r**5 + big_q) / (r**2 * (rho_m * r**3 + k))

    return (5 * q / 2) / (a * mp.diff(shape, a) + 2 * shape(a)) * shape(b)


def _fcn_space_rate(p: dict, e_f):
    """The FCN's rate in space (rad/s) of an axisymmetric planet with an elastic mantle: (sigma + 1) Omega, sigma
    the nearly diurnal retrograde root of (sigma - e + (1 + sigma) kappa)(1 + e_f + sigma (1 + beta))
    - sigma (1 + gamma)(1 + sigma)(A_f/A + xi) = 0 (Sasao, Okubo & Saito 1980), e = H/(1 - H), C = (J2/H) M a^2,
    M = GM/G, kappa = k2 a^3 Omega^2/(3 GM (J2/H)) / (A/C), xi = gamma A_f/A (reciprocity)."""
    h, omega = p["dynamical_flattening"], p["rotation_rate"]
    c_factor = p["j2"] / h
    mass = p["gm"] / p["gravitational_constant"]
    a_over_c = 1 - h
    e = h / (1 - h)
    kappa = p["love_number_k2"] * p["equatorial_radius"] ** 3 * omega**2 / (3 * p["gm"] * c_factor) / a_over_c
    af = p["fluid_core_equatorial_moment"] / (c_factor * mass * p["equatorial_radius"] ** 2 * a_over_c)
    beta, gamma = p["core_compliance_beta"], p["core_compliance_gamma"]
    coupling = (1 + gamma) * (af + gamma * af)
    c2 = (1 + kappa) * (1 + beta) - coupling
    c1 = (1 + kappa) * (1 + e_f) + (kappa - e) * (1 + beta) - coupling
    c0 = (kappa - e) * (1 + e_f)
    root = mp.sqrt(c1**2 - 4 * c2 * c0)
    sigma = max([(-c1 + root) / (2 * c2), (-c1 - root) / (2 * c2)], key=abs)
    return (sigma + 1) * omega


def _excess_uncertainty_percent(body_path) -> tuple:
    """(e_f required, its uncertainty, e_f hydrostatic, the excess's uncertainty in per cent) from the body file's
    numbers at 40 digits, as docs/modes.md defines them: the e_f for which the FCN turns in space at 2 pi / the
    observed period; its uncertainty the linear propagation, central differences over +-1 sigma of every
    parameter at that e_f (each moves it by -dF/(dF/de_f)) and of the observed period (by its dF/(dF/de_f)),
    added in quadrature; the excess required/hydrostatic - 1 moves by that over the hydrostatic e_f, which a
    fixed profile does not move."""
    with mp.workdps(40):
        entries = tomllib.loads(body_path.read_text())["parameters"]
        value = {k: mp.mpf(float(u.Quantity(e["value"], e["unit"]).si.value)) for k, e in entries.items()}
        sigma = {k: mp.mpf(float(u.Quantity(e["uncertainty"], e["unit"]).si.value)) for k, e in entries.items()}
        period, period_sigma = value.pop("observed_fcn_period"), sigma.pop("observed_fcn_period")
        required = mp.findroot(lambda e: _fcn_space_rate(value, e) - 2 * mp.pi / period, mp.mpf("0.0027"))
        slope = mp.diff(lambda e: _fcn_space_rate(value, e), required)
        moves = [
            -(
                _fcn_space_rate({**value, k: value[k] + s}, required)
                - _fcn_space_rate({**value, k: value[k] - s}, required)
            )
            / 2
            / slope
            for k, s in sigma.items()
            if s > 0
        ]
        moves.append(abs(2 * mp.pi / (period + period_sigma) - 2 * mp.pi / (period - period_sigma)) / 2 / slope)
        required_sigma = mp.sqrt(sum(m**2 for m in moves))
        hydrostatic = _two_layer_core_flattening(value["rotation_rate"], value["gravitational_constant"])
        return float(required), float(required_sigma), float(hydrostatic), float(100 * required_sigma / hydrostatic)


def test_modes_names_the_excess_uncertainty_as_every_uncertainty_is(capsys):
    # The key's name and its unit (per cent), and the old name holding the same number; its value is checked
    # against the propagation written out in the next test.
    for d in _json(capsys, "modes", "earth", "mars"):
        assert 0 < d["core_flattening_excess_uncertainty_percent"] < 10
        assert d["core_flattening_excess_percent_uncertainty"] == d["core_flattening_excess_uncertainty_percent"]
        assert d["deprecated_keys"] == {
            "core_flattening_excess_percent_uncertainty": "core_flattening_excess_uncertainty_percent",
            "hydrostatic_figure.q": "hydrostatic_figure.centrifugal_ratio",
        }
        assert d["hydrostatic_figure"]["deprecated_keys"] == {"q": "centrifugal_ratio"}
        _check_listings(d)


def test_modes_excess_uncertainty_is_the_propagation_of_the_body_file_s_numbers(capsys, tmp_path):
    """core_flattening_excess_uncertainty_percent against the linear propagation written out from the body file's
    numbers (Earth's FCN parameters, made axisymmetric and elastic so that the FCN is the Sasao-Okubo-Saito
    quadratic) and a two-layer profile's closed-form hydrostatic core flattening, at 40 digits. It was compared
    with the API's own attribute (plumbing: a wrong propagation passed). To 1e-6: the code's dF/de_f is a central
    difference over 1e-6 of e_f, a few ulp of the FCN's rate apart (1.4e-7 here); e_f itself to 1e-12."""
    body, profile = _round_earth_files(tmp_path)
    (d,) = _json(capsys, "modes", "--body-file", str(body), "--profile", str(profile))
    required, required_sigma, hydrostatic, excess_sigma = _excess_uncertainty_percent(body)
    assert d["core_flattening_hydrostatic"] == pytest.approx(hydrostatic, rel=1e-10)
    assert d["core_flattening_required"] == pytest.approx(required, rel=1e-12)
    assert d["core_flattening_required_uncertainty"] == pytest.approx(required_sigma, rel=1e-6)
    assert d["core_flattening_excess_uncertainty_percent"] == pytest.approx(excess_sigma, rel=1e-6)
    assert d["core_flattening_excess_percent_uncertainty"] == d["core_flattening_excess_uncertainty_percent"]


def test_modes_without_a_figure_lists_only_what_it_holds(capsys, tmp_path):
    """A body with no density profile has no hydrostatic figure: its root lists no rename inside one."""
    path = tmp_path / "ares.toml"
    path.write_text(catalogue_file("mars").read_text().replace('name = "mars"', 'name = "ares"', 1))
    (d,) = _json(capsys, "modes", "--body-file", str(path))
    assert d["hydrostatic_figure"] is None and d["core_flattening_excess_uncertainty_percent"] is None
    assert d["deprecated_keys"] == {
        "core_flattening_excess_percent_uncertainty": "core_flattening_excess_uncertainty_percent"
    }
    assert d["core_flattening_excess_percent_uncertainty"] is None


# --- 6. deprecated_keys at the root of every command that renames -----------------------------------------------------


def _roots(doc):
    """The objects a command's JSON is made of: the object, or each body's object of a list."""
    return doc if isinstance(doc, list) else [doc]


def _check_root_lists_every_rename(root):
    """The root's listing holds every nested object's renames, by their path from the root."""
    listed = root["deprecated_keys"].items()
    for listing in _listings(root):
        if listing is root:
            continue
        for old, new in listing["deprecated_keys"].items():
            # Under the path that reaches the nested object (hydrostatic_figure.q, estimates.*.annual_amplitude_mas).
            assert any(o.endswith(f".{old}") and n.endswith(f".{new}") for o, n in listed), (old, new)


RENAMING_RUNS = {
    "chandler": ["chandler", "earth", "mars"],
    "chandler --sources": ["chandler", "mars", "--sources"],
    "chandler rigid": ["chandler", "mars", "--model", "rigid"],
    "modes": ["modes"],
    "modes --mode CW": ["modes", "earth", "--mode", "CW"],
    "precession": ["precession", "earth"],
    "polar-motion": ["polar-motion", "--start", "2000-01-01", "--end", "2012-12-31"],
    "forecast": ["forecast", "--issued", "2019-01-01", "--horizon", "10d"],
    "inertia": ["inertia", "--points", "dumbbell.csv", "--length-unit", "cm"],
    "free": ["free", "--inertia", "1", "2", "3", "--omega", "0.1", "0", "1"],
    "top": ["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "60", "--omega3", "10"],
    "invert": ["invert", "mars", "--prior-only", "--steps", "20", "--burn", "10", "--walkers", "16", "--quiet"],
}


@pytest.mark.parametrize("run", list(RENAMING_RUNS))
def test_every_renaming_command_lists_its_renames_at_the_root_in_every_run(capsys, run):
    doc = _json(capsys, *RENAMING_RUNS[run])
    for root in _roots(doc):
        assert isinstance(root["deprecated_keys"], dict), run
        _check_root_lists_every_rename(root)
    _check_listings(doc)
    if run == "chandler":  # no parameters, chandler's only renamed key: nothing to list, but the key is there
        assert [r["deprecated_keys"] for r in doc] == [{}, {}]


def test_invert_lists_its_diagnostics_renames_at_the_root(capsys):
    d = _json(capsys, *RENAMING_RUNS["invert"])
    assert d["deprecated_keys"] == {
        "diagnostics.r_hat_max": "diagnostics.r_hat_threshold",
        "diagnostics.ess_min": "diagnostics.ess_threshold",
    }
    assert d["diagnostics"]["r_hat_max"] == d["diagnostics"]["r_hat_threshold"] == 1.01


@pytest.mark.parametrize(
    "argv",
    [
        ["excitation", "--start", "1990", "--end", "2020"],
        ["example", "--list"],
        ["sweep", "earth_chandler", "--members", "20", "--quiet"],  # its old units is kept as it was, not renamed
    ],
)
def test_commands_that_rename_nothing_list_nothing(capsys, argv):
    """excitation, run, example and bench have renamed no key, and print no deprecated_keys (run and bench, slower
    to run, are left out here)."""
    assert not list(_listings(_json(capsys, *argv)))
