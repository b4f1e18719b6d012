"""`wobble modes`: table, JSON, CF netCDF round trip, plot, and exit status 2 on bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
import xarray as xr

import wobble
from wobble.cli import main
from wobble.io.catalog import catalogue_file, load_planet

JSON_MODE_KEYS = {
    "mode",
    "period_days",
    "period_uncertainty_days",
    "frame",
    "sense",
    "observed_days",
    "observed_uncertainty_days",
}


def _run(capsys, *args):
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def test_table_lists_every_mode_with_its_observation(capsys):
    status, out, err = _run(capsys, "modes", "earth", "mars")
    assert status == 0 and not err
    for word in (
        "Earth: free rotational modes",
        "Mars: free rotational modes",
        "CW",
        "FCN",
        "terrestrial",
        "celestial",
        "prograde",
        "retrograde",
    ):
        assert word in out
    assert "Krasna, Boehm & Schuh 2013" in out and "Le Maistre et al. 2023" in out
    assert "the observed FCN requires e_f" in out and "Chandler budget" in out


def test_json_schema_scripts_rely_on(capsys):
    status, out, _ = _run(capsys, "modes", "earth", "mars", "--json")
    assert status == 0
    data = json.loads(out)
    assert [d["body"] for d in data] == ["earth", "mars"]
    for d in data:
        assert [(m["mode"], m["frame"]) for m in d["modes"]] == [
            ("CW", "terrestrial"),
            ("FCN", "terrestrial"),
            ("FCN", "celestial"),
        ]
        for m in d["modes"]:
            assert JSON_MODE_KEYS <= set(m)
        for key in (
            "core_flattening_hydrostatic",
            "core_flattening_hydrostatic_uncertainty",
            "core_flattening_required",
            "core_flattening_required_uncertainty",
        ):
            assert d[key] is not None
    earth = data[0]
    assert earth["modes"][2]["period_days"] < -450 and earth["modes"][2]["sense"] == "retrograde"
    assert 4 < earth["core_flattening_excess_percent"] < 6


def test_netcdf_round_trip_and_cf(tmp_path, capsys, assert_cf_compliant):
    path = tmp_path / "modes.nc"
    status, out, _ = _run(capsys, "modes", "earth", "mars", "-o", str(path))
    assert status == 0 and f"wrote {path}" in out
    ds = wobble.load(path)
    assert dict(ds.sizes) == {"body": 2, "mode": 3}
    assert ds["period"].attrs["units"] == "day"
    expected = wobble.modes_dataset([wobble.normal_modes("earth"), wobble.normal_modes("mars")])
    xr.testing.assert_identical(ds, expected.assign_attrs(ds.attrs))
    assert_cf_compliant(path)
    # Every uncertainty the JSON gives is in the file too (the hydrostatic e_f's and the excess's were not).
    status, out, _ = _run(capsys, "modes", "earth", "mars", "--json")
    for body in json.loads(out):
        row = ds.sel(body=body["body"])
        for key, var in (
            ("core_flattening_hydrostatic_uncertainty", "core_flattening_hydrostatic_uncertainty"),
            ("core_flattening_excess_uncertainty_percent", "core_flattening_excess_uncertainty"),
        ):
            assert float(row[var]) == pytest.approx(body[key], rel=1e-14, abs=0), (body["body"], key)  # 15 digits


@mp.workdps(30)  # a decorator, not mp.mp.dps = 30: that would leave mpmath at 30 digits for later tests
def _liouville_root(p, k2, e_f, guess):
    """A root omega (rad/s, signed) of det(i omega M + Omega K) = 0, the Liouville equations (M) of
    docs/modes.md section 1 for a triaxial mantle and a Poincare core, built here in mpmath from
    the catalogued J2, C22, S22, C/(Ma^2), GM, a and A_f (independent of wobble.models.modes)."""
    big_c = mp.mpf(p.c_factor)
    c22 = mp.sqrt(5 / mp.mpf(12)) * mp.hypot(p.c22.value if p.c22 else 0, p.s22.value if p.s22 else 0)
    ca = mp.mpf(p.flattening) + 2 * c22 / big_c  # (C - A)/C, units of C: Abar = (A + B)/2 and B - A = 4 C22 M a^2
    cb = mp.mpf(p.flattening) - 2 * c22 / big_c
    spin, a, gm = (mp.mpf(x) for x in (p.rotation_rate.value, p.equatorial_radius.value, p.gm.value))
    d = mp.mpf(k2) * a**3 * spin**2 / (3 * gm * big_c)  # D/C, D = k2 a^5 Omega^2/(3 G)
    af = mp.mpf(p.fluid_core_moment) / (big_c * gm / mp.mpf(p.gravitational_constant.value) * a**2)
    beta, gamma, ef = mp.mpf(p.core_compliance_beta.value), mp.mpf(p.core_compliance_gamma.value), mp.mpf(e_f)
    f = af * (1 + gamma)
    m = mp.matrix(
        [[1 - ca + d, 0, f, 0], [0, 1 - cb + d, 0, f], [1 + gamma, 0, 1 + beta, 0], [0, 1 + gamma, 0, 1 + beta]]
    )
    k = mp.matrix([[0, cb - d, 0, -f], [-(ca - d), 0, f, 0], [0, 0, 0, -(1 + ef)], [0, 0, 1 + ef, 0]])
    return mp.findroot(lambda w: mp.re(mp.det(1j * w * m + spin * k)), mp.mpf(guess))


def test_netcdf_values_against_independent_references(tmp_path, capsys):
    """The file's numbers against the physics, not against the API: the rates are roots of the
    Liouville equations solved here (mpmath), with Earth's core flattening from an independent
    Clairaut solution of PREM (tests/references/clairaut.json); the periods are 2 pi/rate in days of
    86400 s; the celestial FCN is the terrestrial one plus one turn; the observations are the
    published values (Krasna et al. 2013: -431.18 +- 0.10 sidereal days; Le Maistre et al. 2023)."""
    path = tmp_path / "modes.nc"
    assert _run(capsys, "modes", "earth", "mars", "-o", str(path))[0] == 0
    ds = wobble.load(path)
    assert ds["period"].attrs["units"] == "day" and ds["rate"].attrs["units"] == "rad s-1"
    clairaut = json.loads((Path(__file__).parent / "references" / "clairaut.json").read_text())
    prem = next(f for f in clairaut["figures"] if f["profile"] == "prem")
    earth = ds.sel(body="earth")
    assert float(earth["core_flattening_hydrostatic"]) == pytest.approx(
        float(prem["core_dynamical_ellipticity"]), rel=1e-11
    )
    assert float(earth["surface_flattening_hydrostatic"]) == pytest.approx(float(prem["surface_flattening"]), rel=1e-11)
    assert float(earth["dynamical_flattening_hydrostatic"]) == pytest.approx(
        float(prem["j2"]) / float(prem["moment_factor"]), rel=1e-11
    )
    spins = {"earth": 7.292115e-5, "mars": 350.891985307 * math.pi / 180 / 86400}
    for body, spin in spins.items():
        row = ds.sel(body=body)
        p, _ = load_planet(body)
        e_f = float(row["core_flattening_hydrostatic"])
        for label, sense in (("CW_terrestrial", 1), ("FCN_terrestrial", -1), ("FCN_celestial", -1)):
            rate, period = float(row["rate"].sel(mode=label)), float(row["period"].sel(mode=label))
            assert period == pytest.approx(2 * math.pi / rate / 86400, rel=1e-15)
            assert int(row["sense"].sel(mode=label)) == sense == np.sign(period)
        terrestrial = float(row["rate"].sel(mode="FCN_terrestrial"))
        assert float(row["rate"].sel(mode="FCN_celestial")) - terrestrial == pytest.approx(spin, rel=1e-13)
        for label, tolerance in (("CW_terrestrial", 1e-10), ("FCN_terrestrial", 1e-12)):
            rate, k2 = float(row["rate"].sel(mode=label)), float(row["love_number_k2"].sel(mode=label))
            assert rate == pytest.approx(float(_liouville_root(p, k2, e_f, rate)), rel=tolerance), (body, label)
    observed = ds["observed_period"].sel(mode="FCN_celestial")
    assert float(observed.sel(body="earth")) == pytest.approx(-431.18 * 86164.0905 / 86400, rel=1e-9)
    assert float(ds["observed_period_uncertainty"].sel(body="earth", mode="FCN_celestial")) == pytest.approx(
        0.10 * 86164.0905 / 86400, rel=1e-9
    )
    assert float(observed.sel(body="mars")) == -243.0


def test_body_file_runs_like_the_catalogue(tmp_path, capsys):
    path = tmp_path / "my_mars.toml"
    path.write_text(Path(str(catalogue_file("mars"))).read_text().replace('name = "mars"', 'name = "my_mars"'))
    status, out, _ = _run(capsys, "modes", "--body-file", str(path), "--profile", "mars_layered", "--json")
    assert status == 0
    mine = json.loads(out)[0]
    status, out, _ = _run(capsys, "modes", "mars", "--json")
    ref = json.loads(out)[0]
    assert [m["period_days"] for m in mine["modes"]] == [m["period_days"] for m in ref["modes"]]


def test_plot_option_draws_the_figure(tmp_path, capsys):
    path = tmp_path / "modes.png"
    status, out, _ = _run(capsys, "modes", "earth", "mars", "--plot", str(path))
    assert status == 0 and path.stat().st_size > 10_000


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["modes", "pluto"], "BODY: got pluto"),
        (["modes", "mars", "--profile", "prem"], "density profile mass"),
        # Said why the path is not read (it was told only the names, as for a folder).
        (
            ["modes", "earth", "--profile", "/nonexistent.toml"],
            "--profile: got /nonexistent.toml; allowed: one of mars_layered, prem, or the path of a density-profile "
            "file (there is no such file)",
        ),
        (
            ["modes", "earth", "--profile", "."],
            "--profile: got .; allowed: one of mars_layered, prem, or the path of a "
            "density-profile file (it is a folder)",
        ),
    ],
)
def test_bad_input_exit_2_one_line_nothing_written(tmp_path, capsys, args, fragment):
    out_file = tmp_path / "modes.nc"
    status, out, err = _run(capsys, *args, "-o", str(out_file))
    assert status == 2
    assert fragment in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out_file.exists()


def test_missing_parameter_for_a_requested_mode(tmp_path, capsys):
    text = Path(str(catalogue_file("mars"))).read_text()
    start = text.index("[parameters.core_compliance_beta]")
    end = text.index("[parameters.core_compliance_gamma]")
    path = tmp_path / "no_beta.toml"
    path.write_text(text[:start] + text[end:])
    status, _, err = _run(capsys, "modes", "--body-file", str(path), "--mode", "FCN")
    assert status == 2 and "core_compliance_beta" in err and err.count("\n") == 1
    status, out, _ = _run(capsys, "modes", "--body-file", str(path), "--json")
    assert status == 0 and [m["mode"] for m in json.loads(out)[0]["modes"]] == ["CW"]


def test_help_has_examples(capsys):
    with pytest.raises(SystemExit) as info:
        main(["modes", "--help"])
    assert info.value.code == 0
    assert "examples:" in capsys.readouterr().out


def test_dataset_marks_absent_modes():
    only_cw = wobble.normal_modes("earth", modes=("CW",))
    ds = wobble.modes_dataset([only_cw, wobble.normal_modes("mars")])
    assert np.isnan(ds["period"].sel(body="earth", mode="FCN_celestial"))
    assert int(ds["sense"].sel(body="earth", mode="FCN_celestial")) == 0


def test_bad_profile_file_exit_2_one_line_nothing_written(tmp_path, capsys):
    from wobble.io.density_profile import load_profile

    text = Path(load_profile("mars_layered")[1].path).read_text()
    bad = tmp_path / "heavy_mantle.toml"
    bad.write_text(text.replace("[[6.0, 0.0], [5.035803, -1.826654]]", "[[3.0, 0.0], [5.035803, -1.826654]]"))
    out_file = tmp_path / "modes.nc"
    status, _, err = _run(capsys, "modes", "mars", "--profile", str(bad), "-o", str(out_file))
    assert status == 2 and err.count("\n") == 1
    assert "heavy_mantle.toml" in err and "density" in err and "increase outward" in err
    assert not out_file.exists()


def _prem_text():
    from wobble.io.density_profile import load_profile

    return Path(load_profile("prem")[1].path).read_text()


_CORE = "[parameters.fluid_core_outer_radius]\nvalue = 3480.0"
_INNER = "[parameters.fluid_core_inner_radius]\nvalue = 1221.5"
_TOLERANCE = "[parameters.mass_tolerance]\nvalue = 1e-3"


@pytest.mark.parametrize(
    ("edit", "fragments"),
    [
        (("[2.600, 0.0, 0.0, 0.0]", "[-2.600, 0.0, 0.0, 0.0]"), ("(density)", "-2600 kg/m3", "positive density")),
        (
            ("[1221.5, 3480.0, 5701.0", "[1221.5, 5701.0, 3480.0"),
            ("(layer_top_radius)", "5701, 3480,", ") km", "increasing"),
        ),
        ((_CORE, _CORE.replace("3480.0", "7000.0")), ("(fluid_core_outer_radius)", "7000 km", "inside the planet")),
        ((_INNER, _INNER.replace("1221.5", "-5.0")), ("(fluid_core_inner_radius)", "-5 km", "at least 0")),
        (("[2.900, 0.0, 0.0, 0.0]", "[nan, 0.0, 0.0, 0.0]"), ("density_coefficients", "nan", "finite numbers")),
        (("6368.0, 6371.0]", "6368.0, nan]"), ("layer_top_radius", "nan", "finite numbers")),
        ((_CORE, _CORE.replace("3480.0", "nan")), ("fluid_core_outer_radius", "nan", "finite numbers")),
        # Read, then printed as the limit: "allowed: within -0.001".
        ((_TOLERANCE, _TOLERANCE.replace("1e-3", "-1e-3")), ("mass_tolerance", "got -0.001", "positive relative")),
    ],
)
def test_bad_profile_file_is_one_line_naming_file_parameter_value_and_rule(tmp_path, capsys, edit, fragments):
    text = _prem_text()
    assert edit[0] in text
    bad = tmp_path / "bad_prem.toml"
    bad.write_text(text.replace(edit[0], edit[1], 1))
    out_file = tmp_path / "modes.nc"
    status, _, err = _run(capsys, "modes", "earth", "--profile", str(bad), "-o", str(out_file))
    assert status == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert "bad_prem.toml" in err and all(f in err for f in fragments), err
    assert not out_file.exists()


def test_zero_rotation_is_one_line(tmp_path, capsys):
    from catalogue_edit import catalogue_with

    path = catalogue_with(tmp_path, "earth", "rotation_rate", "0.0", "still.toml")
    status, _, err = _run(capsys, "modes", "--body-file", str(path), "--profile", "prem")
    assert status == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "still.toml" in err and "rotation_rate" in err and "0.0" in err and "non-zero" in err


def test_a_tiny_liquid_core_runs_and_gives_the_closed_form(tmp_path, capsys):
    """A 3 km uniform core under a uniform mantle: the figure stopped with a StepLimitError traceback
    (step size underflow at the core-mantle boundary). Its e_f is the core's level-surface flattening,
    eps(b) = (P b^5 + Q)/(b^2 (rho_m b^3 + K)) scaled by the surface condition (mpmath)."""
    text = Path(str(catalogue_file("mars"))).read_text()
    b, a, rho_c, rho_m = 3.0e3, 3389.5e3, 8000.0, 3933.0
    profile = tmp_path / "tiny_core.toml"

    def param(name, value, unit):
        rest = 'uncertainty = 0.0\nsource = "test"\nstatus = "assumed"\n'
        return f'[parameters.{name}]\nvalue = {value}\nunit = "{unit}"\n' + rest

    profile.write_text(
        'schema = "wobble/1"\nkind = "density_profile"\nname = "tiny_core"\n\n'
        + "\n".join(
            [
                param("layer_top_radius", [b / 1e3, a / 1e3], "km"),
                param("density_coefficients", [[rho_c], [rho_m]], "kg m-3"),
                param("normalising_radius", a / 1e3, "km"),
                param("fluid_core_inner_radius", 0.0, "km"),
                param("fluid_core_outer_radius", b / 1e3, "km"),
                param("mass_tolerance", 0.1, ""),
            ]
        )
    )
    body = tmp_path / "mars_tiny.toml"
    body.write_text(text)
    status, out, err = _run(capsys, "modes", "--body-file", str(body), "--profile", str(profile), "--json")
    assert status == 0, err
    got = json.loads(out)[0]["core_flattening_hydrostatic"]
    p, _ = load_planet("mars")
    with mp.workdps(40):  # not mp.mp.dps = 40: that would leave mpmath at 40 digits for every later test
        bb, aa, rc, rm = (mp.mpf(x) for x in (b, a, rho_c, rho_m))
        k = (rc - rm) * bb**3
        q = (
            mp.mpf(p.rotation_rate.value) ** 2
            * aa**3
            / (mp.mpf(p.gravitational_constant.value) * 4 * mp.pi / 3 * (rm * aa**3 + k))
        )
        big_q = 3 * k * bb**5 / (5 * rm * bb**3 + 2 * k)  # eps'(b) = 0: the core is uniform

        def shape(r):
            return (r**5 + big_q) / (r**2 * (rm * r**3 + k))

        e_f = shape(bb) * (5 * q / 2) / (aa * mp.diff(shape, aa) + 2 * shape(aa))
    assert got == pytest.approx(float(e_f), rel=1e-10)


def test_hydrostatic_figure_netcdf_round_trip_and_cf(tmp_path, assert_cf_compliant):
    from astropy import units as u

    figure = wobble.hydrostatic_figure("prem", spin=1 * u.sday)
    ds = figure.to_dataset()
    assert ds["radius"].attrs["units"] == "km" and float(ds["radius"][-1]) == pytest.approx(6371.0)
    path = wobble.write_netcdf(ds, tmp_path / "prem_figure.nc")
    back = wobble.load(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert back.attrs["hydrostatic_core_dynamical_ellipticity"] == pytest.approx(
        figure.core_dynamical_ellipticity, rel=1e-15
    )
    assert_cf_compliant(path)
