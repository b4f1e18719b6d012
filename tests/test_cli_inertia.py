"""``wobble inertia``: JSON against closed forms, files in and out, one-line errors."""

from __future__ import annotations

import json
from fractions import Fraction

import numpy as np
import pytest
import xarray as xr

from wobble.cli import main
from wobble.io.netcdf import open_wobble


def _run(capsys, *argv):
    status = main(["inertia", *argv])
    out, err = capsys.readouterr()
    return status, out, err


def _json(capsys, *argv):
    status, out, err = _run(capsys, *argv, "--json")
    assert status == 0, err
    # Under --json, stdout is one JSON document; files written are announced on stderr.
    assert all(line.startswith("wrote ") for line in err.splitlines()), err
    return json.loads(out)


def _error(capsys, *argv):
    status, out, err = _run(capsys, *argv)
    assert status == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("wobble inertia: error: ")
    return err


def _right_handed(axes):
    a = np.array(axes)
    return np.allclose(a @ a.T, np.eye(3), atol=1e-14) and abs(np.linalg.det(a) - 1) < 1e-14


def test_ellipsoid_json_matches_the_closed_form(capsys):
    report = _json(capsys, "--solid", "ellipsoid", "--mass", "2", "--axes", "3", "2", "1")
    # I = M/5 (b^2 + c^2, a^2 + c^2, a^2 + b^2) = (2, 4, 5.2) kg m2
    np.testing.assert_allclose(report["tensor_kg_m2"], np.diag([2.0, 4.0, 5.2]), rtol=1e-15, atol=0)
    np.testing.assert_allclose(report["principal_moments_kg_m2"], [2.0, 4.0, 5.2], rtol=1e-15)
    assert _right_handed(report["principal_axes"])
    assert report["classification"] == "asymmetric"
    assert report["mass_kg"] == 2.0 and report["center_of_mass_m"] == [0.0, 0.0, 0.0]


def test_units_on_the_command_line(capsys):
    report = _json(capsys, "--solid", "ellipsoid", "--mass", "2 g", "--axes", "3 cm", "2 cm", "1 cm")
    np.testing.assert_allclose(report["principal_moments_kg_m2"], np.array([2.0, 4.0, 5.2]) * 1e-7, rtol=1e-15)
    same = _json(
        capsys,
        "--solid",
        "ellipsoid",
        "--mass",
        "2",
        "--mass-unit",
        "g",
        "--axes",
        "3",
        "2",
        "1",
        "--length-unit",
        "cm",
    )
    np.testing.assert_allclose(same["principal_moments_kg_m2"], report["principal_moments_kg_m2"], rtol=1e-15)


def test_top_about_its_tip(capsys):
    md, rd, ma, ell, h = 0.1, 0.03, 0.01, 0.08, 0.05
    report = _json(
        capsys, "--solid", "top", "--disc-mass", str(md), "--disc-radius", str(rd), "--axle-mass", str(ma),
        "--axle-length", str(ell), "--disc-height", str(h), "--about", "origin",
    )  # fmt: skip
    i1 = md * rd**2 / 4 + md * h**2 + ma * ell**2 / 3
    np.testing.assert_allclose(report["principal_moments_kg_m2"], [md * rd**2 / 2, i1, i1], rtol=1e-14)
    assert report["classification"] == "prolate"
    assert report["reference_point_m"] == [0.0, 0.0, 0.0]
    assert report["center_of_mass_m"][2] == pytest.approx((md * h + ma * ell / 2) / (md + ma), rel=1e-15)


def test_points_csv_against_exact_arithmetic(capsys, tmp_path):
    rng = np.random.default_rng(5)
    masses = rng.integers(1, 100, 12).astype(float)
    pos = rng.integers(-50, 50, (12, 3)).astype(float)
    path = tmp_path / "pts.csv"
    lines = ["m [g], x [cm], y [cm], z [cm]"] + [f"{m}, {x}, {y}, {z}" for m, (x, y, z) in zip(masses, pos)]
    path.write_text("\n".join(lines) + "\n")
    report = _json(capsys, "--points", str(path), "--about", "1", "2", "-3", "--length-unit", "cm")
    # Exact: I about (1, 2, -3) cm, in g cm2, then to kg m2 (1e-7).
    ref = [Fraction(1), Fraction(2), Fraction(-3)]
    exact = [[Fraction(0)] * 3 for _ in range(3)]
    for m, p in zip(masses, pos):
        d = [Fraction(float(c)) - r for c, r in zip(p, ref)]
        for j in range(3):
            for k in range(3):
                exact[j][k] += Fraction(float(m)) * ((sum(c * c for c in d) if j == k else 0) - d[j] * d[k])
    expected = np.array([[float(x) * 1e-7 for x in row] for row in exact])
    np.testing.assert_allclose(report["tensor_kg_m2"], expected, rtol=0, atol=1e-14 * np.abs(expected).max())
    assert report["mass_kg"] == pytest.approx(masses.sum() / 1000, rel=1e-15)
    np.testing.assert_allclose(report["reference_point_m"], [0.01, 0.02, -0.03], rtol=1e-15)


def _density_file(tmp_path, spacing_ok=True):
    c = np.linspace(-0.5, 0.5, 21)
    x = c.copy()
    if not spacing_ok:
        x[3] += 0.01
    xx, yy, zz = np.meshgrid(x, c, c, indexing="ij")
    rho = 3.0 + xx + 0.5 * yy * zz  # g/cm3, smooth
    ds = xr.Dataset(
        {
            "rho": (("x", "y", "z"), rho, {"units": "g cm-3"}),
            "temperature": (("x", "y", "z"), rho * 0 + 300.0, {"units": "K"}),
        },
        coords={
            "x": ("x", x * 100, {"units": "cm"}),
            "y": ("y", c * 100, {"units": "cm"}),
            "z": ("z", c * 100, {"units": "cm"}),
        },
    )
    path = tmp_path / "grid.nc"
    ds.to_netcdf(path)
    return path


def test_density_file_and_netcdf_output(capsys, tmp_path, assert_cf_compliant):
    path = _density_file(tmp_path)
    out = tmp_path / "inertia.nc"
    report = _json(capsys, "--density", str(path), "--var", "rho", "--rule", "simpson", "-o", str(out))
    # rho = 3 + x (g/cm3) on a 1 m cube: M = 3000 kg; the linear term moves the centre of mass to
    # x = (1/12 m^2 * 1000 kg/m3 ... ) / M: integral x^2 = 1/12 m^5 -> com_x = 1000/12/3000 m.
    assert report["mass_kg"] == pytest.approx(3000.0, rel=1e-13)
    assert report["center_of_mass_m"][0] == pytest.approx(1000 / 12 / 3000, rel=1e-12)
    ds = open_wobble(out)
    # JSON carries 15 significant digits (what a double promises), the file every bit.
    np.testing.assert_allclose(ds["tensor"].values, report["tensor_kg_m2"], rtol=1e-14, atol=1e-300)
    assert_cf_compliant(out)
    capsys.readouterr()  # the compliance checker talks on stderr
    assert "wobble inertia --density" in ds.attrs["history"]
    # Writing again needs --overwrite; the file is untouched until then.
    err = _error(capsys, "--density", str(path), "--var", "rho", "-o", str(out))
    assert "--overwrite" in err
    assert _json(capsys, "--density", str(path), "--var", "rho", "-o", str(out), "--overwrite")["output"] == str(out)


def test_human_output(capsys):
    status, out, err = _run(capsys, "--solid", "disc", "--mass", "1", "--radius", "2")
    assert status == 0 and err == ""
    assert "principal moments (kg m2, ascending)" in out
    assert "I3 = 2 " in out
    assert "classification      oblate" in out


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (("--solid", "sphere", "--mass", "2"), "--radius: missing"),
        (("--solid", "sphere", "--mass", "2", "--radius", "1", "--axes", "1", "2", "3"), "--axes: got 1 2 3"),
        (("--solid", "sphere", "--mass", "2 m", "--radius", "1"), "--mass: got 2 m"),
        (("--solid", "sphere", "--mass", "-2", "--radius", "1"), "mass: got"),
        (("--solid", "sphere", "--mass", "2", "--radius", "1", "--about", "1", "2"), "--about: got 1 2"),
        (("--solid", "sphere", "--mass", "2", "--radius", "1", "--mass-unit", "furlong"), "--mass-unit: got furlong"),
        (("--solid", "sphere", "--mass", "2", "--radius", "1", "--tolerance", "2"), "--tolerance"),
        (
            ("--solid", "hollow-sphere", "--mass", "2", "--radius", "1", "--inner-radius", "3"),
            "--inner-radius: got 3;",
        ),  # the option and its value as typed, not the API name and float
        (("--points", "/nonexistent/pts.csv"), "no such file"),
        (("--density", "/nonexistent/grid.nc"), "no such file"),
    ],
)
def test_bad_input_is_one_line_and_status_2(capsys, argv, needle):
    assert needle in _error(capsys, *argv)


def test_bad_files_are_one_line_errors(capsys, tmp_path):
    bad_grid = _density_file(tmp_path, spacing_ok=False)
    assert "density.x: got spacings" in _error(capsys, "--density", str(bad_grid), "--var", "rho")
    assert "several density candidates" in _error(capsys, "--density", str(bad_grid))
    # Was "PATH, variable 'rhp': not in the file; allowed: ...": the option not named.
    assert _error(capsys, "--density", str(bad_grid), "--var", "rhp") == (
        "wobble inertia: error: --var: got rhp; allowed: a data variable of grid.nc: rho, temperature\n"
    )
    # A coordinate is in the file but is not a density; an empty name is shown as typed.
    assert "--var: got x; allowed: a data variable of grid.nc" in _error(
        capsys, "--density", str(bad_grid), "--var", "x"
    )
    assert "--var: got ''; allowed: a data variable of planet.nc: rho" in _error(
        capsys, "--density", "planet.nc", "--var", ""
    )
    pts = tmp_path / "p.csv"
    pts.write_text("m, x, y, z\n1, 0, 0, 0\n-1, 1, 0, 0\n")
    assert f"{pts}, line 3, column 'm': got '-1'; allowed: a positive mass" in _error(capsys, "--points", str(pts))
    pts.write_text("m, x, y, z\n1, 0, 0\n")
    assert f"{pts}, line 2" in _error(capsys, "--points", str(pts))


@pytest.mark.parametrize(
    ("row", "where"),
    [("1, nan, 0, 1", "line 3, column 'x': got 'nan'"), ("inf, 0, 0, 1", "line 3, column 'm': got 'inf'")],
)
def test_a_value_that_is_not_finite_names_the_file_as_typed_its_line_and_column(
    capsys, tmp_path, monkeypatch, row, where
):
    # Was "positions: got (0, 0, 0, nan, 0, 1) m; allowed: finite values": neither the file nor where in it.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.csv").write_text(f"m [g], x [cm], y [cm], z [cm]\n1, 0, 0, 0\n{row}\n")
    err = _error(capsys, "--points", "./p.csv", "-o", "out.nc")
    assert err == f"wobble inertia: error: ./p.csv, {where}; allowed: a finite number\n"
    assert not (tmp_path / "out.nc").exists()


@pytest.mark.parametrize("mass", ["-1", "0"])
def test_a_mass_that_is_not_positive_names_the_file_its_line_and_column(capsys, tmp_path, monkeypatch, mass):
    # Was "masses: got (1, -1) kg; allowed: positive values": neither the file nor the line.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.csv").write_text(f"m, x, y, z\n1, 0, 0, 1\n{mass}, 0, 0, -1\n")
    err = _error(capsys, "--points", "./p.csv")
    assert err == f"wobble inertia: error: ./p.csv, line 3, column 'm': got '{mass}'; allowed: a positive mass\n"


def test_usage_errors_exit_2_with_one_line(capsys):
    with pytest.raises(SystemExit) as info:
        main(["inertia", "--solid", "dodecahedron"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("wobble inertia: error:")
    with pytest.raises(SystemExit) as info:
        main(["inertia", "--points", "a.csv", "--solid", "sphere"])
    assert info.value.code == 2


def test_help_lists_the_command(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--help"])
    assert info.value.code == 0
    assert "inertia" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["inertia", "--help"])
    assert "--solid ellipsoid --mass 2 --axes 3 2 1" in capsys.readouterr().out
