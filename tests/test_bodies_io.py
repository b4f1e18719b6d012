"""Rigid bodies to and from files: CF netCDF, the wobble/1 parameter schema, point-mass CSV."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import xarray as xr
from astropy import units as u
from scipy.spatial.transform import Rotation

import wobble
from wobble import FileFormatError, InputError, RigidBody
from wobble.io.netcdf import open_wobble, write_netcdf
from wobble.io.parameter_file import read_parameter_file
from wobble.io.point_masses import read_point_masses

KGM2 = u.kg * u.m**2


def _bodies():
    top = RigidBody.spinning_top(0.1 * u.kg, 3 * u.cm, 10 * u.g, 8 * u.cm, 5 * u.cm).shifted_to("origin")
    turned = (
        RigidBody.box(2 * u.kg, [1, 2, 3] * u.m)
        .rotated(Rotation.from_euler("xyz", [0.1, 0.7, -0.3]))
        .translated([1, 2, 3] * u.m)
    )
    earth = RigidBody.oblate_planet(
        5.9722e24 * u.kg, 6378136.6 * u.m, 0.3307, dynamical_flattening=3273795e-9, name="Earth"
    )
    no_mass = RigidBody.from_principal_moments([1, 2, 2.5] * u.g * u.cm**2, name="moments only")
    return {"top": top, "turned box": turned, "earth": earth, "no mass": no_mass}


@pytest.mark.parametrize("key", list(_bodies()))
def test_netcdf_round_trip_identical_and_cf_compliant(tmp_path, assert_cf_compliant, key):
    body = _bodies()[key]
    ds = body.to_dataset()
    path = write_netcdf(ds, tmp_path / "body.nc", command="test")
    back = open_wobble(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert_cf_compliant(path)
    again = RigidBody.from_dataset(back)
    np.testing.assert_array_equal(again.tensor, body.tensor)
    np.testing.assert_array_equal(again.principal_moments, body.principal_moments)
    np.testing.assert_allclose(again.principal_axes, body.principal_axes, rtol=0, atol=1e-15)  # re-normalised
    np.testing.assert_array_equal(again.principal_differences, body.principal_differences)
    np.testing.assert_array_equal(again.center_of_mass, body.center_of_mass)
    assert again.classification == body.classification
    assert (again.mass is None) == (body.mass is None)


def test_dataset_contents_and_attributes():
    ds = _bodies()["earth"].to_dataset()
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
    for name in ("tensor", "principal_moments", "principal_moment_differences"):
        assert ds[name].attrs["units"] == "kg m2"
    assert ds.attrs["classification"] == "oblate"
    assert ds.attrs["wobble_kind"] == "rigid_body"
    assert ds["principal_moments"].dims == ("principal",)
    assert ds["principal_axes"].dims == ("principal", "component")
    np.testing.assert_array_equal(np.diff(ds["principal_moments"].values) >= 0, True)


@pytest.mark.parametrize("key", list(_bodies()))
def test_parameter_file_round_trip(tmp_path, key):
    body = _bodies()[key]
    path = body.to_parameter_file(tmp_path / "body.toml")
    pf = read_parameter_file(path, kind="rigid_body")
    assert pf.parameters["principal_moments"].status == "derived"
    back = RigidBody.from_parameter_file(path)
    np.testing.assert_array_equal(back.tensor, body.tensor)
    np.testing.assert_array_equal(back.principal_moments, body.principal_moments)
    np.testing.assert_array_equal(back.principal_differences, body.principal_differences)
    np.testing.assert_allclose(back.principal_axes, body.principal_axes, atol=1e-15)
    np.testing.assert_array_equal(back.reference_point, body.reference_point)
    np.testing.assert_array_equal(back.center_of_mass, body.center_of_mass)
    assert back.moment_ratio(3, 1) == body.moment_ratio(3, 1)


def test_tiny_flattening_survives_the_parameter_file(tmp_path):
    planet = RigidBody.oblate_planet(1e24 * u.kg, 1e6 * u.m, 0.33, dynamical_flattening=1e-13)
    back = RigidBody.from_parameter_file(planet.to_parameter_file(tmp_path / "p.toml"))
    assert back.moment_ratio(3, 1) == pytest.approx(1e-13 / (1 - 1e-13), rel=1e-15, abs=0)


HAND_WRITTEN = """
schema = "wobble/1"
kind = "rigid_body"
name = "toy_top"
title = "Toy top"

[parameters.principal_moments]
value = [2.9, 2.9, 0.45]
uncertainty = 0.01
unit = "g cm2"
source = "measured on a torsion pendulum"
status = "read"

[parameters.mass]
value = 110.0
uncertainty = 0.1
unit = "g"
source = "kitchen scale"
status = "read"

[parameters.center_of_mass]
value = [0.0, 0.0, 4.9]
uncertainty = 0.0
unit = "mm"
source = "balance point"
status = "read"
"""


def test_hand_written_file_in_cgs_units(tmp_path):
    path = tmp_path / "top.toml"
    path.write_text(HAND_WRITTEN)
    top = RigidBody.from_parameter_file(path)
    np.testing.assert_allclose(top.principal_moments.to_value(u.g * u.cm**2), [0.45, 2.9, 2.9], rtol=1e-15)
    assert top.mass.to_value(u.g) == pytest.approx(110.0, rel=1e-15)
    assert top.name == "Toy top" and top.classification == "prolate"
    np.testing.assert_allclose(top.center_of_mass.to_value(u.mm), [0, 0, 4.9], rtol=1e-15)
    tip = top.shifted_to("origin")
    expected = (2.9 * u.g * u.cm**2 + 110 * u.g * (4.9 * u.mm) ** 2).to_value(KGM2)
    assert tip.principal("symmetry").moments[0].to_value(KGM2) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize(
    ("edit", "where", "message"),
    [
        (("value = [2.9, 2.9, 0.45]", "value = [2.9, 2.9, 9.0]"), "parameters.moments", "triangle"),
        (("value = [2.9, 2.9, 0.45]", "value = [2.9, -2.9, 0.45]"), "parameters.moments", "positive"),
        (('unit = "g cm2"', 'unit = "g cm"'), "parameters.moments", "moment of inertia"),
        (("[parameters.mass]", "[parameters.weight]"), "parameters.weight", "unknown parameter"),
        (('kind = "rigid_body"', 'kind = "planet"'), "kind", "rigid_body"),
    ],
)
def test_bad_parameter_files_name_the_key(tmp_path, edit, where, message):
    path = tmp_path / "bad.toml"
    path.write_text(HAND_WRITTEN.replace(*edit, 1))
    with pytest.raises(FileFormatError) as info:
        RigidBody.from_parameter_file(path)
    assert info.value.where == where
    assert message in str(info.value) and str(path) in str(info.value)


def test_inconsistent_tensor_and_moments_are_refused(tmp_path):
    path = tmp_path / "b.toml"
    tensor = """
[parameters.tensor]
value = [[2.9, 0.0, 0.0], [0.0, 2.9, 0.0], [0.0, 0.0, 0.5]]
uncertainty = 0.0
unit = "g cm2"
source = "a different measurement"
status = "read"
"""
    path.write_text(HAND_WRITTEN + tensor)
    with pytest.raises(FileFormatError, match="parameters.tensor"):
        RigidBody.from_parameter_file(path)
    path.write_text(HAND_WRITTEN + tensor.replace("0.5]]", "0.45]]"))
    assert RigidBody.from_parameter_file(path).principal_moments[0].to_value(u.g * u.cm**2) == pytest.approx(0.45)


def test_point_mass_csv_units_in_header_and_defaults(tmp_path):
    path = tmp_path / "pts.csv"
    path.write_text("# dumbbell\nx [cm], m [g], y [cm], z [mm]\n-5, 10, 0, 0\n\n5, 30, 0, 10\n")
    masses, positions = read_point_masses(path)
    np.testing.assert_allclose(masses.to_value(u.kg), [0.01, 0.03])
    np.testing.assert_allclose(positions.to_value(u.m), [[-0.05, 0, 0], [0.05, 0, 0.01]])
    bare = tmp_path / "bare.csv"
    bare.write_text("1, 0, 0, 1\n1, 0, 0, -1\n")
    masses, positions = read_point_masses(bare, mass_unit=u.g, length_unit=u.km)
    assert masses.unit == u.g
    np.testing.assert_allclose(positions.to_value(u.m), [[0, 0, 1000], [0, 0, -1000]])


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ("m, x, y\n1, 2, 3\n", "line 1", "missing column(s) z"),
        ("m, x, y, z, colour\n1, 2, 3, 4, 5\n", "line 1", "allowed: columns m, x, y, z"),
        ("m [g], x [s], y, z\n1, 2, 3, 4\n", "line 1", "unit of length"),
        ("m, x, y, z\n1, 2, 3\n", "line 2", "3 fields"),
        ("m, x, y, z\n1, 2, three, 4\n", "line 2", "numbers"),
        ("# nothing\n", None, "no point masses"),
    ],
)
def test_bad_csv_names_file_and_line(tmp_path, text, where, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(FileFormatError) as info:
        read_point_masses(path)
    assert info.value.where == where and message in str(info.value)


def test_header_unit_and_a_different_default_conflict(tmp_path):
    path = tmp_path / "pts.csv"
    path.write_text("m [g], x [cm], y [cm], z [cm]\n1, 0, 0, 1\n")
    with pytest.raises(InputError, match="--length-unit"):
        read_point_masses(path, length_unit=u.m)


def test_public_names_are_exported():
    assert "RigidBody" in wobble.__all__ and wobble.RigidBody is RigidBody


def test_a_parameter_without_its_uncertainty_and_an_unknown_top_level_key_are_refused(tmp_path):
    """Every number carries its uncertainty (0 when exact), and a misspelt top-level key is not dropped:
    both ran silently before (a walk with a planet file of one's own)."""
    from wobble.errors import FileFormatError
    from wobble.io.parameter_file import read_parameter_file

    entry = '[parameters.gm]\nvalue = 4.28e13\n{sigma}unit = "m3 s-2"\nsource = "test"\nstatus = "assumed"\n'
    head = 'schema = "wobble/1"\nkind = "planet"\nname = "ares"\n'
    path = tmp_path / "ares.toml"
    path.write_text(head + entry.format(sigma=""))
    with pytest.raises(FileFormatError, match=r"parameters.gm: missing field\(s\) uncertainty \(uncertainty = 0 for"):
        read_parameter_file(path, kind="planet")
    path.write_text(head + 'colour = "red"\n' + entry.format(sigma="uncertainty = 0\n"))
    with pytest.raises(FileFormatError, match="colour: unknown top-level key; allowed: schema, kind, name, title"):
        read_parameter_file(path, kind="planet")
    path.write_text(head + entry.format(sigma="uncertainty = 0\n"))
    assert read_parameter_file(path, kind="planet").parameters["gm"].uncertainty.value == 0.0


@pytest.mark.parametrize(
    ("key", "field", "typed", "message"),
    [
        # C/(M a^2) = 1.5 ran (a 910-day Chandler period); a negative radius was shown in SI without a unit.
        ("polar_moment_factor", "value", "1.5", "got 1.5; allowed: at most 2/3 (all the mass in a thin shell"),
        ("fluid_core_radius", "value", "-1830.0", "got -1830 km; allowed: a positive number"),
        # A unit read "got 'kg / m2'" for "kg m-2" typed, and "a unit of dimensionless" for a pure number.
        ("fluid_core_density", "unit", '"kg m-2"', "got 'kg m-2'; allowed: a unit of kg / m3"),
        ("love_number_k2", "unit", '"kg"', "got 'kg'; allowed: a pure number (unit = \"\")"),
    ],
)
def test_a_planet_entry_outside_nature_or_in_a_wrong_unit_is_refused_as_typed(tmp_path, key, field, typed, message):
    import re

    from wobble.errors import FileFormatError
    from wobble.io.catalog import catalogue_file, load_planet

    text = catalogue_file("mars").read_text()
    path = tmp_path / "ares.toml"
    path.write_text(re.sub(rf"(\[parameters\.{key}\]\n(?:.*\n)*?{field} = )[^\n]*", rf"\g<1>{typed}", text, count=1))
    with pytest.raises(FileFormatError, match=re.escape(f"ares.toml, parameters.{key}.{field}: {message}")):
        load_planet(path)


@pytest.mark.parametrize(
    ("body", "key", "typed", "message"),
    [
        # H = 1 crashed with a TypeError deep in the budget; H = 0.6 ran (a 0.67-day "Chandler period").
        ("earth", "dynamical_flattening", "1.0", "parameters.dynamical_flattening.value: got 1; allowed: at most 1/2"),
        (
            "earth",
            "dynamical_flattening",
            "0.6",
            "parameters.dynamical_flattening.value: got 0.6; allowed: at most 1/2",
        ),
        # H from J2 / (C/(M a^2)): C20 = -0.1 gives J2 = 0.224 and, with Mars's 0.364, H = 0.61.
        ("mars", "c20", "-0.1", "parameters (dynamical_flattening): H = 0.613"),
    ],
)
def test_a_figure_beyond_the_triangle_inequality_is_refused(tmp_path, body, key, typed, message):
    """H = (C - A)/C <= 1/2 for any body (A + B >= C), given or derived; every command reads planets this way."""
    import re

    from wobble.errors import FileFormatError
    from wobble.io.catalog import catalogue_file, load_planet

    text = catalogue_file(body).read_text()
    path = tmp_path / "ares.toml"
    path.write_text(re.sub(rf"(\[parameters\.{key}\]\n(?:.*\n)*?value = )[^\n]*", rf"\g<1>{typed}", text, count=1))
    with pytest.raises(FileFormatError, match=re.escape(f"ares.toml, {message}")):
        load_planet(path)


@pytest.mark.parametrize(("h", "ks"), [("0.0", "k_s = 3G(C-A)/(a^5 Omega^2), 0 here"), ("-1e-3", "Omega^2), -0.")])
def test_elastic_yielding_of_a_figure_that_is_not_oblate_is_refused(tmp_path, capsys, h, ks):
    """H <= 0 makes k_s <= 0: any k2 > 0 yields more than a fluid. H = 0 printed an "elastic" 953-day retrograde
    wobble of a sphere (wobble modes refused the same file); the rigid step alone still runs. (The example
    planet gives H and C/(M a^2).)"""
    from wobble.cli import main

    path = _example_with(tmp_path, "dynamical_flattening", "value", h)
    capsys.readouterr()
    assert main(["chandler", "--body-file", str(path)]) == 2
    err = capsys.readouterr().err
    # The parameter named is the figure's (it named love_number_k2, "below k_s = -0.29": below a negative number).
    assert "parameters.dynamical_flattening.value: got" in err and ks in err and err.count("\n") == 1
    assert "allowed: a positive value (an oblate figure, C > A)" in err
    assert main(["chandler", "--body-file", str(path), "--model", "rigid"]) == 0
    out = capsys.readouterr().out
    assert ("(no free wobble)" if h == "0.0" else "(retrograde wobble)") in out


@pytest.mark.parametrize("h", ["0.0", "-1e-3"])
def test_a_polar_moment_factor_from_j2_over_a_non_positive_h_is_refused(tmp_path, h):
    """Earth's file gives H and J2, so C/(M a^2) = J2 / H: H = 0 raised ZeroDivisionError, H < 0 ran with a
    negative C/(M a^2)."""
    import re

    from wobble.errors import FileFormatError
    from wobble.io.catalog import catalogue_file, load_planet

    text = catalogue_file("earth").read_text()
    path = tmp_path / "ares.toml"
    path.write_text(
        re.sub(r"(\[parameters\.dynamical_flattening\]\n(?:.*\n)*?value = )[^\n]*", rf"\g<1>{h}", text, count=1)
    )
    with pytest.raises(FileFormatError, match=re.escape("parameters (polar_moment_factor): C/(M a^2) = J2 / H")):
        load_planet(path)


def test_a_number_in_quotes_is_refused_as_text(tmp_path):
    from wobble.errors import FileFormatError
    from wobble.io.parameter_file import read_parameter_file

    path = tmp_path / "ares.toml"
    path.write_text(
        'schema = "wobble/1"\nkind = "planet"\nname = "ares"\n'
        '[parameters.gm]\nvalue = "4.28e13"\nuncertainty = 0\nunit = "m3 s-2"\nsource = "test"\nstatus = "assumed"\n'
    )
    with pytest.raises(FileFormatError, match=r"parameters.gm.value: got '4.28e13' \(text\); allowed: a number"):
        read_parameter_file(path)


def _example_with(tmp_path, key: str, field: str, typed: str):
    """The example planet file with one field of one parameter replaced (``value`` or ``uncertainty``)."""
    from wobble.cli import main

    assert main(["example", "my_planet.toml", str(tmp_path / "base.toml")]) == 0
    text = (tmp_path / "base.toml").read_text()
    path = tmp_path / "edited.toml"
    path.write_text(re.sub(rf"(\[parameters\.{key}\]\n(?:.*\n)*?{field} = )[^\n]*", rf"\g<1>{typed}", text, count=1))
    return path


@pytest.mark.parametrize(
    ("key", "typed", "command", "said"),
    [
        # Tracebacks: ZeroDivisionError and OverflowError forming the rate's uncertainty (2 pi sigma / P^2).
        ("rotation_period", "1e-300", "chandler", r"parameters \(rotation_period\): Omega\^2 = inf"),
        ("rotation_period", "1e300", "modes", r"parameters \(rotation_period\): Omega\^2 = 0"),
        ("rotation_period", "5e-324", "precession", r"rotation_period.value: got 4.94066e-324 h; .*finite float"),
        # A ValueError traceback: 1e300 AU is inf in metres.
        (
            "orbit_semi_major_axis",
            "1e300",
            "precession",
            r"orbit_semi_major_axis.value: got 1e\+300 AU; .*finite in SI",
        ),
        # NumPy's overflow warnings, then a refusal that blamed dynamical_flattening for k_s = 0.
        ("equatorial_radius", "1e300", "chandler", r"parameters \(gm, equatorial_radius, rotation_period\): Omega"),
        (
            "gm",
            "5e-324",
            "chandler",
            r"parameters \(gm, equatorial_radius, rotation_period\): Omega\^2 a\^3 / GM = inf",
        ),
        # Ran: "k_s = inf" printed with a divide-by-zero warning; a 300-digit k_s; periods of 150 digits, +/- inf.
        ("equatorial_radius", "1e-300", "chandler", r"parameters \(gm, equatorial_radius, rotation_period\)"),
        (
            "gm",
            "1e300",
            "modes",
            r"parameters \(gm, equatorial_radius, rotation_period\): Omega\^2 a\^3 / GM = 1.39e-288",
        ),
        ("rotation_period", "1e150", "chandler", r"parameters \(rotation_period\): Omega\^2 = 3.05e-306"),
    ],
)
def test_a_planet_file_whose_scales_leave_the_float_range_is_refused_naming_them(
    tmp_path, capsys, key, typed, command, said
):
    """Found by hand beside the CLI fuzzer (2026-11-29): a planet file's values whose combinations (Omega^2,
    Omega^2 a^3/GM, M a^2, the orbit's a^3) overflow or underflow, or whose squares would in the uncertainty
    propagation, are refused with one line naming the file and the parameters, before any model runs."""
    from wobble.cli import main

    path = _example_with(tmp_path, key, "value", typed)
    capsys.readouterr()
    assert main([command, "--body-file", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Warning" not in err, err
    assert re.search(rf"edited.toml, .*{said}", err), err


def test_a_valid_but_far_planet_prints_its_secular_love_number_in_powers_of_ten(tmp_path, capsys):
    """A rotation period of 1e70 h is inside the range: k_s = 3 GM J2/(a^3 Omega^2) is printed as 1.488e+137, not
    as 137 digits (it was '14877...176.0000'); checked against the formula with the file's values."""
    from wobble.cli import main

    path = _example_with(tmp_path, "rotation_period", "value", "1e70")
    capsys.readouterr()
    assert main(["chandler", "--body-file", str(path)]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    line = next(x for x in captured.out.splitlines() if "secular Love number" in x)
    omega = 2 * math.pi / (1e70 * 3600.0)
    gm, a, h, c = 4.0e14, 6400e3, 3.0e-3, 0.33  # the example planet's values (SI)
    ks = 3 * gm * h * c / (a**3 * omega**2)
    assert line == f"  secular Love number k_s = {ks:.4g}"


def test_an_uncertainty_that_leaves_no_physical_draw_gives_no_plus_minus(tmp_path, capsys):
    """An uncertainty of 1e300 on H left no physical Monte Carlo draw: NumPy's 'Degrees of freedom <= 0' warnings
    and 'model 511.89 +/- nan'. No warning now, and the line says why there is no +/-."""
    from wobble.cli import main

    path = _example_with(tmp_path, "dynamical_flattening", "uncertainty", "1e300")
    capsys.readouterr()
    assert main(["chandler", "--body-file", str(path)]) == 0
    captured = capsys.readouterr()
    assert captured.err == "" and "nan" not in captured.out
    assert "no +/-: no Monte Carlo draw was physical" in captured.out
    assert main(["chandler", "--body-file", str(path), "--json"]) == 0
    (d,) = json.loads(capsys.readouterr().out)
    assert d["period_uncertainty_days"] is None and d["monte_carlo_valid_fraction"] == 0.0


def _with_parameters(tmp_path, name, extra: str):
    """The example planet (H, C/(M a^2), GM, a 6400 km radius) with parameter tables appended."""
    from wobble.api.examples import example_path

    path = tmp_path / name
    path.write_text(example_path("my_planet.toml").read_text() + extra)
    return path


def _table(key, value, unit='""', sigma=0.0):
    return (
        f'\n[parameters.{key}]\nvalue = {value}\nuncertainty = {sigma}\nunit = {unit}\nsource = "test"\n'
        'status = "assumed"\n'
    )


def test_an_overdetermined_figure_must_agree_with_itself(tmp_path):
    """H, J2 and C/(M a^2) all given: the models read H and C/(M a^2) and never J2, so a J2 that disagreed was
    ignored without a word (H = 0.01 beside J2 / C = 0.00625 gave an 82.5-day rigid period from H alone). The
    example planet has H = 3.0e-3 +- 1e-5 and C/(M a^2) = 0.33 +- 0.005: J2 = H C/(M a^2) = 9.9e-4 agrees."""
    from wobble.io.catalog import load_planet

    planet, _ = load_planet(_with_parameters(tmp_path, "ok.toml", _table("j2", 9.9e-4, sigma=1e-7)))
    assert planet.flattening == 3.0e-3
    bad = _with_parameters(tmp_path, "bad.toml", _table("j2", 6.6e-4, sigma=1e-7))
    with pytest.raises(
        FileFormatError,
        match=re.escape(
            "bad.toml, parameters (dynamical_flattening, j2, "
            "polar_moment_factor): H = 0.003 but J2 / (C/(M a^2)) = "
            "0.00066 / 0.33 = 0.002"
        ),
    ):
        load_planet(bad)


def _uniform_core_and_planet_a(radius_km: float) -> tuple[float, float]:
    """A_f = (8 pi/15) rho R^5 of a uniform core at 13000 kg/m3, and the example planet's A = (1 - H) C with
    C = C/(M a^2) (GM/G) a^2 (H = 3.0e-3, C/(M a^2) = 0.33, GM = 4.0e14 m3/s2, a = 6400 km; G of CODATA 2018)."""
    core = 8 * math.pi / 15 * 13000.0 * (radius_km * 1e3) ** 5
    return core, (1 - 3.0e-3) * 0.33 * 4.0e14 / 6.67430e-11 * 6.4e6**2


@pytest.mark.parametrize("radius_km", [9000, 6300])
def test_a_liquid_core_larger_than_its_planet_is_refused_naming_the_file_and_keys(tmp_path, radius_km):
    """It was refused later by the model as 'fluid_core: got A_f/C = 5.44653', naming neither file nor key. A core
    past the planet's radius is named by its radius; one inside it but heavier than A by its moment."""
    from wobble.io.catalog import load_planet

    extra = _table("fluid_core_radius", radius_km, '"km"') + _table("fluid_core_density", 13000, '"kg m-3"')
    path = _with_parameters(tmp_path, "big_core.toml", extra)
    core, a = _uniform_core_and_planet_a(radius_km)
    if radius_km > 6400:
        message = f"parameters (fluid_core_radius): {radius_km} km; needs a radius smaller than the planet's equatorial"
    else:
        message = (
            f"parameters (fluid_core_radius, fluid_core_density): the core's moment A_f = {core:.4g} kg m2, "
            f"{core / a:.3g} times the planet's A = {a:.4g} kg m2"
        )
    with pytest.raises(FileFormatError, match=re.escape(f"big_core.toml, {message}")):
        load_planet(path)
    # A core of 3000 km (A_f / A well below 1) is a planet like any other.
    assert _uniform_core_and_planet_a(3000)[0] < 0.1 * a
    load_planet(
        _with_parameters(
            tmp_path,
            "core.toml",
            _table("fluid_core_radius", 3000, '"km"') + _table("fluid_core_density", 13000, '"kg m-3"'),
        )
    )
