"""FreeRotation (Quantities, Dataset, netCDF) and `wobble free` on the command line."""

from __future__ import annotations

import json
import shlex

import astropy.units as u
import numpy as np
import pytest
import xarray as xr

import wobble
from wobble import FreeRotation, InputError
from wobble.cli import main
from wobble.io.netcdf import SIMULATION_TIME_UNITS, open_wobble, write_netcdf

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s


def test_public_name():
    assert "FreeRotation" in wobble.__all__


def test_summary_properties_and_units():
    body = FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    assert body.regime == "major-axis"
    assert body.period.unit == u.s and body.period.value == pytest.approx(6.929607063094395, rel=1e-15)
    assert body.energy.to_value(u.J) == pytest.approx(2.01, rel=1e-15)
    assert body.parameter + body.complementary_parameter == pytest.approx(1.0, rel=1e-16)
    assert body.modulus == pytest.approx(np.sqrt(body.parameter))
    # It wobbles about its major axis (the intermediate axis swings by less than 90 deg): no flips.
    assert not body.flips and body.time_between_flips is None and body.flip_times(100 * u.s).size == 0
    racket = FreeRotation([1, 2, 3] * KGM2, [0.01, 1, 0.01] * RAD_S)
    assert racket.flips and racket.time_between_flips == racket.period / 2
    assert racket.flip_times(racket.period).size == 2
    # The files say the same (a fresh-user review found time_between_flips_s on a wobbling Earth's file).
    assert "time_between_flips_s" not in body.to_dataset(t_end=10 * u.s, samples=3).attrs
    assert racket.to_dataset(t_end=10 * u.s, samples=3).attrs["time_between_flips_s"] == racket.period.value / 2
    # Units other than SI give the same body.
    other = FreeRotation([1e7, 2e7, 3e7] * u.g * u.cm**2, ([1, 0.1, 1] * RAD_S).to(u.deg / u.s))
    assert other.period.value == pytest.approx(body.period.value, rel=1e-14)


def test_accepts_an_object_with_principal_moments():
    class Body:
        principal_moments = [3, 1, 2] * KGM2

    body = FreeRotation(Body(), [0.1, 0.2, 1.0] * RAD_S)
    np.testing.assert_array_equal(body.moments.value, [3, 1, 2])


def test_dataset_layout():
    body = FreeRotation([3, 1, 2] * KGM2, [0.3, -0.5, 1.2] * RAD_S)
    ds = body.to_dataset(t_end=20 * u.s, samples=201)
    assert set(ds.data_vars) == {
        "omega",
        "angular_momentum",
        "attitude",
        "kinetic_energy",
        "kinetic_energy_drift",
        "angular_momentum_magnitude",
        "angular_momentum_magnitude_drift",
    }
    assert ds.omega.dims == ("time", "axis") and ds.attitude.dims == ("time", "component")
    assert list(ds.component.values) == ["w", "x", "y", "z"]
    assert ds.time.attrs["units"] == SIMULATION_TIME_UNITS and ds.time.dtype == np.float64
    np.testing.assert_allclose(ds.attitude.isel(time=0), [1, 0, 0, 0], atol=0)
    np.testing.assert_allclose(ds.omega.isel(time=0), [0.3, -0.5, 1.2], rtol=1e-15)
    np.testing.assert_allclose(ds.angular_momentum, [0.9, -0.5, 2.4])
    assert float(abs(ds.kinetic_energy_drift).max()) < 1e-14
    assert float(abs(ds.angular_momentum_magnitude_drift).max()) < 1e-14
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
        if name not in ("axis", "inertial_axis", "component"):
            assert "units" in var.attrs, name
    # Explicit times give the same values.
    again = body.to_dataset(ds.time.values * u.s)
    xr.testing.assert_equal(again.omega, ds.omega)


def test_netcdf_round_trip(tmp_path, assert_cf_compliant):
    body = FreeRotation([1, 2, 3] * KGM2, [1e-6, 1, 1e-6] * RAD_S)
    ds = body.to_dataset(t_end=200 * u.s, samples=5001)
    path = write_netcdf(ds, tmp_path / "free.nc")
    back = open_wobble(path)
    for key in ("history", "Conventions", "source"):
        back.attrs.pop(key, None)
    xr.testing.assert_identical(back, ds)
    assert_cf_compliant(path)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(moments=[1, 2, 3], omega0=[1, 0, 0] * RAD_S), "plain number"),
        (dict(moments=[1, 2, 3] * u.kg, omega0=[1, 0, 0] * RAD_S), "moment of inertia"),
        (dict(moments=[1, 2, 3] * KGM2, omega0=[1, 0] * RAD_S), "shape"),
        (dict(moments=[1, 2, 4] * KGM2, omega0=[1, 0, 0] * RAD_S), "triangle"),
        (dict(moments=[1, 2, 3] * KGM2, omega0=[np.nan, 0, 0] * RAD_S), "finite"),
        (dict(moments=[0, 2, 3] * KGM2, omega0=[1, 0, 0] * RAD_S), "positive"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(InputError, match=match):
        FreeRotation(**kwargs)


def test_refuses_a_request_that_does_not_fit_in_memory():
    body = FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    with pytest.raises(InputError, match=r"samples.*need about .*B of memory"):
        body.to_dataset(t_end=1 * u.s, samples=10**15)
    with pytest.raises(InputError, match="samples"):
        body.to_dataset(t_end=1 * u.s, samples=0)
    with pytest.raises(InputError, match="either"):
        body.to_dataset()


def test_zero_angular_velocity_is_allowed():
    body = FreeRotation([1, 2, 3] * KGM2, [0, 0, 0] * RAD_S)
    ds = body.to_dataset(t_end=10 * u.s, samples=3)
    assert body.regime == "steady"
    assert np.all(ds.omega.values == 0) and np.all(ds.attitude.values == [1, 0, 0, 0])


# --- command line ------------------------------------------------------------
def test_cli_json_summary(capsys):
    status = main(["free", "--inertia", "1", "2", "3", "--omega", "1e-6", "1", "1e-6", "--t-end", "200", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert status == 0
    assert out["regime"] == "major-axis"
    assert out["complementary_parameter_1_minus_m"] == pytest.approx(2e-12, rel=1e-3)
    assert len(out["flip_times_s"]) == 4
    assert out["time_between_flips_s"] == pytest.approx(51.46003083930758, rel=1e-14)


def test_cli_writes_netcdf_with_units(tmp_path, capsys):
    path = tmp_path / "out.nc"
    args = [
        "free",
        "--inertia",
        "8.01012e37 kg m2",
        "8.01032e37",
        "8.03652e37",
        "--omega",
        "7.292115e-11",
        "0",
        "360.98 deg / d",
        "--t-end",
        "2 d",
        "--samples",
        "49",
        "-o",
        str(path),
        "--json",
    ]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    ds = open_wobble(path)
    assert ds.sizes["time"] == 49 and float(ds.time[-1]) == 2 * 86400.0
    assert out["output"] == str(path)
    assert ds.attrs["history"].endswith("wobble " + " ".join(shlex.quote(a) for a in args))  # the command as typed
    assert main(args) == 2  # exists, no --overwrite
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--overwrite" in err
    assert main(args + ["--overwrite"]) == 0


@pytest.mark.parametrize(
    "argv, match",
    [
        (["--inertia", "1", "2", "4", "--omega", "1", "0", "0"], "triangle"),
        (["--inertia", "1", "2", "3", "--omega", "1", "nan", "0"], "finite"),
        (["--inertia", "1 kg", "2", "3", "--omega", "1", "0", "0"], "inertia"),
        (["--inertia", "1", "2", "3", "--omega", "1", "0", "0", "--t-end", "3 m"], "t-end"),
        (["--inertia", "1", "2", "3", "--omega", "1", "0", "0", "--samples", "0", "-o", "x.nc"], "samples"),
    ],
)
def test_cli_bad_input_one_line_exit_2(argv, match, capsys):
    assert main(["free", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and match in err and "Traceback" not in err


def test_cli_table_output(capsys):
    assert main(["free", "--inertia", "2", "2", "3", "--omega", "0.3", "0.1", "1"]) == 0
    out = capsys.readouterr().out
    assert "symmetric" in out and "period of omega" in out


def test_flip_figure_refuses_a_body_that_does_not_flip():
    # Was: AttributeError ('NoneType' has no 'to_value') once time_between_flips became None for a wobble.
    from wobble.errors import InputError
    from wobble.plot.free import flip_figure

    with pytest.raises(InputError, match=r"^omega0: got .*; allowed: a spin that flips the body \(its intermediate"):
        flip_figure([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S, 100 * u.s)


def test_times_beyond_the_phase_reductions_reach_are_refused_by_name(capsys, tmp_path, monkeypatch):
    """The public names for the limit of FreeRotationModel.max_time: ``t`` for omega and attitude,
    ``t_end`` for to_dataset, ``--t-end`` for the command line (one line, exit 2, nothing written)."""
    body = FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)
    reach = body.max_time.to_value(u.s)
    assert reach == (2.0**50 - 1) * body.model.time_between_flips  # the half-period of omega
    with pytest.raises(InputError, match=r"^t: got 1e\+20 s"):
        body.attitude(1e20 * u.s)
    with pytest.raises(InputError, match=r"^t_end: got 1e\+20 s; allowed: \|t\| up to 3\.90102e\+15 s"):
        body.to_dataset(t_end=1e20 * u.s, samples=3)
    assert body.to_dataset(t_end=reach * u.s, samples=3).sizes["time"] == 3
    monkeypatch.chdir(tmp_path)
    argv = ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "--t-end", "1e20", "-o", "x.nc"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("wobble free: error: --t-end: got 1e20; allowed: |t| up to 3.90102e+15 s, 2^50 turns")
    assert err.count("\n") == 1 and not (tmp_path / "x.nc").exists()


@pytest.mark.parametrize(
    ("inertia", "omega", "says"),
    [
        ("1 2 3", "0 1 0", "about axis 2, the intermediate one: unstable"),  # Euler: the middle axis is unstable
        ("1 2 3", "0 0 2", "about axis 3, of the largest moment: stable"),
        ("3 1 2", "1 0 0", "about axis 1, of the largest moment: stable"),  # the axis, not its place in the list
        ("1 2 3", "3 0 0", "about axis 1, of the smallest moment: stable"),
        ("2 2 3", "1 0 0", "steady spin about a principal axis"),  # a shared moment: any axis of its plane
    ],
)
def test_the_table_says_which_axis_a_steady_spin_is_about_and_if_it_is_stable(capsys, inertia, omega, says):
    """'steady spin about a principal axis' did not say that a spin about the intermediate axis flips."""
    assert main(["free", "--inertia", *inertia.split(), "--omega", *omega.split()]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("regime") and says in first


def test_a_rigid_body_s_omega0_is_in_its_own_frame_as_wobble_run_reads_it():
    """Given a RigidBody, omega0 was taken as components on its principal axes (ascending), while wobble.run
    reads it in the body's own frame: the same body and omega0 gave 5.2538 J against the body's own kinetic
    energy 1/2 w.I.w = 5.1984 J, and another motion. Ground truth: 1/2 w.I.w from the tensor, and the torque-free
    integration of the full tensor by the scene engine."""
    import wobble

    body = wobble.RigidBody.from_point_masses(
        [1, 2, 1.5, 0.7, 3] * u.kg,
        [[0.3, 0.1, 0], [-0.2, 0.4, 0.1], [0, -0.3, 0.5], [0.6, 0.2, -0.4], [-0.1, -0.2, -0.2]] * u.m,
    )
    w = [0.5, 3.0, 0.4] * RAD_S
    spin = FreeRotation(body, w)
    tensor = body.central_tensor.to_value(KGM2)
    assert spin.energy.to_value(u.J) == pytest.approx(0.5 * w.value @ tensor @ w.value, rel=1e-14)
    t = np.linspace(0.0, 10.0, 11) * u.s
    ds = wobble.run(wobble.Scene(body, w, t_end=10 * u.s, samples=11, outputs=["omega"], accuracy=1e-11))
    back = spin.omega(t).to_value(RAD_S) @ spin.principal_axes  # principal components -> the body's frame
    np.testing.assert_allclose(back, ds["omega"].values, rtol=0, atol=1e-9)
    # A box spun about its x edge spins about x: the ascending order lists x (the largest moment) last.
    box = wobble.RigidBody.box(mass=1 * u.kg, edges=[1, 2, 3] * u.m)
    about_x = FreeRotation(box, [1.0, 0, 0] * RAD_S)
    assert about_x.regime == "steady" and abs(about_x.omega0.to_value(RAD_S)[2]) == 1.0
