"""HeavyTop (Quantities, duck-typed bodies, Dataset, netCDF) and `wobble top` on the command line."""

from __future__ import annotations

import json
import re

import astropy.units as u
import numpy as np
import pytest
import xarray as xr

import wobble
from wobble import HeavyTop, InputError
from wobble.cli import main
from wobble.io.netcdf import SIMULATION_TIME_UNITS, open_wobble, write_netcdf
from wobble.models.top import heavy_top

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s


def benchmark_top(**kw):
    base = dict(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
    base.update(kw)
    return HeavyTop(**base)


def test_public_name():
    assert "HeavyTop" in wobble.__all__


def test_analysis_properties_carry_units():
    top = benchmark_top()
    assert top.nutation == "cusps"
    assert top.nutation_period.unit == u.s
    assert top.theta_min.to_value(u.deg) == pytest.approx(60.0, rel=1e-15)
    assert top.theta_max.unit == u.deg and top.theta_max > top.theta_min
    assert top.a.to_value(1 / u.s) == 5.0 and top.beta.to_value(u.s**-2) == 2.0
    assert top.p_psi.to(u.kg * u.m**2 / u.s).value == 5.0
    assert top.energy_prime.to_value(u.J) == pytest.approx(0.5, rel=1e-15)
    u1, u2, u3 = top.roots
    assert u1 < u2 <= 1 < u3
    assert top.f([u1, u2]).unit == u.s**-2
    assert np.all(np.abs(top.f([u1, u2]).value) < 1e-14)
    slow, fast = top.regular_precession_rates()
    assert slow.unit == RAD_S and 0 < slow < fast
    # The slow rate ~ M g l / (I3 omega3), the fast ~ I3 omega3 / (I1 cos theta) (notes p. 72).
    assert slow.value == pytest.approx(1 / 5, rel=0.03) and fast.value == pytest.approx(10, rel=0.03)
    assert top.sleeping_stable
    v = top.effective_potential([30, 60, 90] * u.deg)
    assert v.unit == u.J and np.all(np.isfinite(v.value))
    # At the turning points V'(theta) = E' (thetadot = 0 there).
    turning = top.effective_potential(u.Quantity([top.theta_min, top.theta_max]))
    np.testing.assert_allclose(turning.to_value(u.J), top.energy_prime.to_value(u.J), rtol=1e-13)


def test_units_and_spellings_give_the_same_top():
    a = benchmark_top()
    b = HeavyTop(
        I1=1e7 * u.g * u.cm**2,
        I3=5e6 * u.g * u.cm**2,
        mgl=1 * u.N * u.m,
        theta0=(np.pi / 3) * u.rad,
        omega3=(10 * RAD_S).to(u.deg / u.s),
    )
    assert b.nutation_period.value == pytest.approx(a.nutation_period.value, rel=1e-14)
    # psidot0 instead of omega3: omega3 = psidot0 + phidot0 cos theta0.
    c = benchmark_top(omega3=None, psidot0=10 * RAD_S - 0.3 * RAD_S * np.cos(np.pi / 3), phidot0=0.3 * RAD_S)
    d = benchmark_top(phidot0=0.3 * RAD_S)
    assert c.nutation_period.value == pytest.approx(d.nutation_period.value, rel=1e-14)
    # M, l, g instead of mgl (g defaults to standard gravity).
    e = HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, M=0.5 * u.kg, l=0.2 * u.m, theta0=60 * u.deg, omega3=10 * RAD_S)
    assert e.mgl.to_value(u.J) == pytest.approx(0.5 * 9.80665 * 0.2, rel=1e-15)


class _StandIn:
    """A stand-in for the bodies library's RigidBody about its tip (duck typing)."""

    def __init__(self, mass, com, ref, tensor):
        self.mass = mass * u.kg
        self.center_of_mass = np.asarray(com, dtype=float) * u.m
        self.reference_point = np.asarray(ref, dtype=float) * u.m
        self.tensor = np.asarray(tensor, dtype=float) * KGM2


def test_body_by_duck_typing():
    """A disc on an axle about its tip: I1, I3, M, l read from mass, com, reference point, tensor."""
    m, l, i1, i3 = 0.3, 0.05, 2.0e-4, 1.5e-4
    body = _StandIn(m, [0, 0, l], [0, 0, 0], np.diag([i1, i1, i3]))
    top = HeavyTop(body=body, theta0=20 * u.deg, omega3=100 * RAD_S)
    assert top.I1.value == pytest.approx(i1, rel=1e-15) and top.I3.value == pytest.approx(i3, rel=1e-15)
    assert top.mgl.to_value(u.J) == pytest.approx(m * 9.80665 * l, rel=1e-15)
    ref = HeavyTop(I1=i1 * KGM2, I3=i3 * KGM2, mgl=m * 9.80665 * l * u.J, theta0=20 * u.deg, omega3=100 * RAD_S)
    assert top.nutation_period.value == pytest.approx(ref.nutation_period.value, rel=1e-14)
    # The same body turned in its input frame (axis along x) and shifted: still the same top.
    rot = np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]], dtype=float)
    turned = _StandIn(m, rot @ [0, 0, l] + 1.0, [1.0, 1.0, 1.0], rot @ np.diag([i1, i1, i3]) @ rot.T)
    t2 = HeavyTop(body=turned, theta0=20 * u.deg, omega3=100 * RAD_S)
    assert t2.nutation_period.value == pytest.approx(ref.nutation_period.value, rel=1e-13)


def test_body_from_the_bodies_library():
    """RigidBody.spinning_top about its tip: I1, I3, M, l match the hand-worked parallel axes."""
    from wobble import RigidBody

    md, rd, ma, la, h = 0.2, 0.03, 0.02, 0.06, 0.04
    body = RigidBody.spinning_top(md * u.kg, rd * u.m, ma * u.kg, la * u.m, h * u.m).shifted_to("origin")
    top = HeavyTop(body=body, g=9.81 * u.m / u.s**2, theta0=30 * u.deg, omega3=200 * RAD_S)
    # Thin disc (I = m r^2/4 about a diameter) at height h; thin rod from 0 to la about its end.
    i1 = md * rd**2 / 4 + md * h**2 + ma * la**2 / 3
    i3 = md * rd**2 / 2
    mass = md + ma
    ell = (md * h + ma * la / 2) / mass
    assert top.I1.to_value(KGM2) == pytest.approx(i1, rel=1e-14)
    assert top.I3.to_value(KGM2) == pytest.approx(i3, rel=1e-14)
    assert top.mgl.to_value(u.J) == pytest.approx(mass * 9.81 * ell, rel=1e-14)


@pytest.mark.parametrize(
    "body, match",
    [
        (_StandIn(1.0, [0, 0, 0.1], [0, 0, 0], np.diag([1.0, 2.0, 0.5])), "symmetric"),
        (_StandIn(1.0, [0, 0, 0], [0, 0, 0], np.diag([1.0, 1.0, 0.5])), "off the fixed point"),
        (object(), "rigid body with mass"),
    ],
)
def test_bad_bodies(body, match):
    with pytest.raises(InputError, match=match):
        HeavyTop(body=body, theta0=10 * u.deg, omega3=1 * RAD_S)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(I1=0 * KGM2), "I1"),
        (dict(I1=-1 * KGM2), "I1"),
        (dict(I3=0 * KGM2), "I3"),
        (dict(I3=3 * KGM2), "I3"),
        (dict(mgl=-1 * u.J), "mgl"),
        (dict(theta0=200 * u.deg), "theta0"),
        (dict(theta0=-1 * u.deg), "theta0"),
        (dict(theta0=60), "theta0"),
        (dict(thetadot0=np.nan * RAD_S), "thetadot0"),
        (dict(phidot0=1 * u.m), "phidot0"),
        (dict(psidot0=1 * RAD_S), "omega3, psidot0"),
        (dict(omega3=None), "omega3, psidot0"),
        (dict(mgl=None, M=1 * u.kg, l=2 * u.m), "I1"),  # I1 = 1 < M l^2 = 4: not about the tip
        (dict(mgl=1 * u.J, M=1 * u.kg, l=1 * u.m), "mgl"),
        (dict(I1=1 * u.kg), "I1"),
        # Hz is cycles per second: read as rad/s (astropy's dimensionless_angles) it was 2 pi off. A rate needs an
        # angle unit, as FreeRotation's and Scene's do: 1/s is refused too, 10 cycle / s is 20 pi rad / s.
        (dict(omega3=10 * u.Hz), "omega3"),
        (dict(omega3=10 / u.s), "omega3"),
        (dict(omega3=None, psidot0=1 * u.Hz), "psidot0"),
        (dict(phidot0=1 * u.Hz), "phidot0"),
        (dict(thetadot0=1 / u.s), "thetadot0"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, name):
    with pytest.raises(InputError) as err:
        benchmark_top(**kwargs)
    assert err.value.parameter == name
    assert str(err.value).startswith(name)


def test_a_rate_in_cycles_per_second_is_two_pi_radians_per_second():
    top = benchmark_top(omega3=(10 / (2 * np.pi)) * u.cycle / u.s)
    assert top.omega3.to_value(RAD_S) == pytest.approx(10.0, rel=1e-15)
    with pytest.raises(InputError, match="^omega0"):
        HeavyTop.from_state([0, 0, 10] * u.Hz, [1, 0, 0, 0], 1 * KGM2, 0.5 * KGM2, mgl=1 * u.J)


def test_functions_of_u_take_scalars_and_refuse_cosines_no_angle_has():
    """f, phidot and psidot at u = cos theta against the notes' formulas (p. 71-72) with alpha, beta, a, b
    from the initial state, for a scalar and an array; a scalar f raised a raw astropy TypeError, and
    phidot(2.0) gave 2.5 rad/s for a cosine no angle has."""
    I1, I3, mgl, w3, th0 = 1.0, 0.5, 1.0, 10.0, np.radians(60.0)
    top = HeavyTop(I1 * KGM2, I3 * KGM2, mgl=mgl * u.J, theta0=60 * u.deg, omega3=w3 * RAD_S)
    a = I3 * w3 / I1
    b = a * np.cos(th0)  # released from rest: p_phi = p_psi cos theta0
    alpha, beta = 2 * mgl * np.cos(th0) / I1, 2 * mgl / I1  # E' = M g l cos theta0 at rest

    def f(x):
        return (1 - x * x) * (alpha - beta * x) - (b - a * x) ** 2

    for x in (0.3, np.array([-0.2, 0.4, 0.9])):
        assert top.f(x).unit == u.s**-2
        np.testing.assert_allclose(top.f(x).to_value(u.s**-2), f(x), rtol=1e-13, atol=1e-13)
        np.testing.assert_allclose(top.phidot(x).to_value(RAD_S), (b - a * x) / (1 - x * x), rtol=1e-14)
        np.testing.assert_allclose(
            top.psidot(x).to_value(RAD_S), I1 * a / I3 - x * (b - a * x) / (1 - x * x), rtol=1e-14
        )
    for bad in (2.0, -1.5, [0.5, float("nan")]):
        for method in (top.f, top.phidot, top.psidot):
            with pytest.raises(
                InputError, match=r"u_values: got .*allowed: u = cos\(theta\): plain numbers in \[-1, 1\]"
            ):
                method(bad)


def test_phidot_at_the_pole_a_top_passes_through_is_the_limit():
    """A sleeping top (theta0 = 0: b = a) has phidot = (b - a u)/(1 - u^2) = a/(1 + u), a/2 at u = 1, where
    the formula is 0/0; a pole the top cannot reach gives the formula's infinity, without a warning."""
    top = HeavyTop(1 * KGM2, 0.5 * KGM2, mgl=1 * u.J, theta0=0 * u.deg, omega3=10 * RAD_S)
    a = 0.5 * 10.0 / 1.0
    assert top.phidot(1.0).to_value(RAD_S) == a / 2
    # psidot = I1 a/I3 - u phidot, and omega3 = psidot + phidot cos(theta) = 10 rad/s at the vertical.
    assert top.psidot(1.0).to_value(RAD_S) == pytest.approx(1.0 * a / 0.5 - a / 2, rel=1e-15)
    assert (top.psidot(1.0) + top.phidot(1.0)).to_value(RAD_S) == pytest.approx(10.0, rel=1e-15)
    assert top.phidot(0.25).to_value(RAD_S) == pytest.approx(a / 1.25, rel=1e-15)
    tilted = HeavyTop(1 * KGM2, 0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
    assert np.isinf(tilted.phidot(-1.0).value) and np.isinf(tilted.phidot(1.0).value)


def test_dataset_layout_and_conservation():
    top = benchmark_top(phidot0=-0.3 * RAD_S, thetadot0=0.1 * RAD_S, phi0=10 * u.deg)
    ds = top.to_dataset(t_end=20 * u.s, samples=2001)
    assert {
        "theta",
        "phi",
        "psi",
        "thetadot",
        "phidot",
        "psidot",
        "omega",
        "attitude",
        "symmetry_axis",
        "energy",
        "energy_drift",
        "p_phi",
        "p_phi_drift",
        "p_psi",
        "p_psi_drift",
    } == set(ds.data_vars)
    assert ds.omega.dims == ("time", "axis") and ds.symmetry_axis.dims == ("time", "inertial_axis")
    assert ds.time.attrs["units"] == SIMULATION_TIME_UNITS and ds.time.dtype == np.float64
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
        if name not in ("axis", "inertial_axis", "component"):
            assert "units" in var.attrs, name
    assert float(ds.theta[0]) == pytest.approx(np.pi / 3, rel=1e-15)
    assert float(ds.phi[0]) == pytest.approx(np.radians(10), rel=1e-14)
    e_scale = float(top.energy.to_value(u.J))
    assert float(abs(ds.energy_drift).max()) < 1e-13 * e_scale
    assert float(abs(ds.p_phi_drift).max()) < 1e-13 * float(top.p_psi.value)
    assert float(abs(ds.p_psi_drift).max()) < 1e-14 * float(top.p_psi.value)
    th = ds.theta.values
    assert th.min() >= top.model.theta_min * (1 - 1e-13) and th.max() <= top.model.theta_max * (1 + 1e-13)
    # The axis trace is on the unit sphere and makes the notes' angle with the vertical.
    np.testing.assert_allclose(np.linalg.norm(ds.symmetry_axis, axis=1), 1, rtol=1e-14)
    np.testing.assert_allclose(ds.symmetry_axis.sel(inertial_axis="Z"), np.cos(th), atol=1e-15)
    assert ds.attrs["nutation"] == "loops"
    # Explicit times (motion) give the same values.
    again = top.motion(ds.time.values * u.s)
    xr.testing.assert_allclose(again.theta, ds.theta, rtol=1e-15, atol=0)


def test_netcdf_round_trip(tmp_path, assert_cf_compliant):
    top = benchmark_top(theta0=1e-6 * u.rad)
    ds = top.to_dataset(t_end=30 * u.s, samples=3001)
    path = write_netcdf(ds, tmp_path / "top.nc")
    back = open_wobble(path)
    for key in ("history", "Conventions", "source"):
        back.attrs.pop(key, None)
    xr.testing.assert_identical(back, ds)
    assert_cf_compliant(path)


def test_from_state_matches_euler_angle_construction():
    top = benchmark_top(phidot0=0.3 * RAD_S, thetadot0=-0.2 * RAD_S)
    w, q = top.model.evaluate(np.array([0.0]))
    again = HeavyTop.from_state(w[0] * RAD_S, q[0], I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J)
    assert again.nutation_period.value == pytest.approx(top.nutation_period.value, rel=1e-14)
    assert again.nutation == top.nutation


def test_to_dict_has_the_cli_keys_and_summary_is_text():
    top = benchmark_top()
    s = top.to_dict()
    for key in (
        "u1",
        "u2",
        "u3",
        "theta_min_deg",
        "theta_max_deg",
        "nutation",
        "nutation_period_s",
        "mean_precession_rate_rad_per_s",
        "sleeping_stable",
    ):
        assert key in s
    json.dumps(s)  # plain numbers only
    assert top.summary().startswith(s["nutation"]) and "deg" in top.summary()


def test_memory_and_time_requests():
    top = benchmark_top()
    with pytest.raises(InputError, match="samples"):
        top.to_dataset(t_end=1 * u.s, samples=10**15)
    with pytest.raises(InputError, match="samples"):
        top.to_dataset(t_end=1 * u.s, samples=0)
    with pytest.raises(InputError, match="either"):
        top.to_dataset()


# --- command line ------------------------------------------------------------
def test_cli_json(capsys):
    status = main(["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "60 deg", "--omega3", "10", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert status == 0
    mdl = heavy_top(1.0, 0.5, 1.0, np.radians(60.0), omega3=10.0)
    assert out["nutation"] == "cusps" and out["sleeping_stable"] is True
    # JSON keeps 15 significant digits, all a double promises.
    assert [out[k] for k in ("u1", "u2", "u3")] == pytest.approx([mdl.u1, mdl.u2, mdl.u3], rel=1e-14)
    assert out["theta_min_deg"] == pytest.approx(60.0, rel=1e-15)
    assert out["nutation_period_s"] == pytest.approx(mdl.nutation_period, rel=1e-14)
    assert out["mean_precession_rate_rad_per_s"] == pytest.approx(mdl.mean_precession_rate, rel=1e-14)


def test_cli_sleeping_and_units(capsys):
    assert (
        main(["top", "--I1", "1 kg m2", "--I3", "0.5", "--mgl", "1 N m", "--theta0", "0", "--omega3", "1", "--json"])
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert out["nutation"] == "sleeping" and out["sleeping_stable"] is False and out["nutation_period_s"] is None


def test_cli_writes_netcdf(tmp_path, capsys):
    path = tmp_path / "loops.nc"
    args = [
        "top",
        "--I1",
        "1",
        "--I3",
        "0.5",
        "--mgl",
        "1",
        "--theta0",
        "60 deg",
        "--phidot0",
        "-0.3",
        "--omega3",
        "10",
        "-o",
        str(path),
        "--t-end",
        "20",
        "--samples",
        "201",
        "--json",
    ]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    ds = open_wobble(path)
    assert ds.sizes["time"] == 201 and float(ds.time[-1]) == 20.0 and out["output"] == str(path)
    assert "wobble top" in ds.attrs["history"]
    assert main(args) == 2  # exists, no --overwrite
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--overwrite" in err
    assert main(args + ["--overwrite"]) == 0


@pytest.mark.parametrize(
    "argv, match",
    [
        (["--I1", "1", "--I3", "3", "--mgl", "1", "--theta0", "1", "--omega3", "1"], "--I3"),
        (["--I1", "0", "--I3", "0.5", "--mgl", "1", "--theta0", "1", "--omega3", "1"], "--I1"),
        (["--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "200 deg", "--omega3", "1"], "--theta0"),
        (["--I1", "1", "--I3", "0.5", "--mgl", "1 kg", "--theta0", "1", "--omega3", "1"], "--mgl"),
        (["--I1", "1", "--I3", "0.5", "--mgl", "-1", "--theta0", "1", "--omega3", "1"], "--mgl"),
        (
            [
                "--I1",
                "1",
                "--I3",
                "0.5",
                "--mgl",
                "1",
                "--theta0",
                "1",
                "--omega3",
                "1",
                "-o",
                "x.nc",
                "--samples",
                "0",
            ],
            "--samples",
        ),
    ],
)
def test_cli_bad_input_one_line_exit_2(argv, match, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["top", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and match in err and "Traceback" not in err


def test_times_past_the_closed_form_s_reach_are_refused(capsys, tmp_path, monkeypatch):
    """The phases are reduced exactly for 2^50 nutation periods (2^26 until 2026-11-29, where the
    secular phases' three-piece products stopped being exact); 1e20 s (7.7e19 periods of this top) ran
    and gave meaningless phases (1e300 s: NaN, with NumPy's warnings on stderr)."""
    top = benchmark_top()
    period = top.nutation_period.to_value(u.s)
    assert top.max_time.to_value(u.s) == (2**50 - 1) * period
    top.model.motion(np.array([-top.max_time.to_value(u.s), top.max_time.to_value(u.s)]))  # the limit itself runs
    with pytest.raises(InputError, match=r"^t: got 1e\+20 s; allowed: \|t\| up to .*, 2\^50 nutation periods"):
        top.model.motion(np.array([0.0, 1e20]))
    with pytest.raises(InputError, match="^t_end: got 1e\\+20 s"):
        top.to_dataset(t_end=1e20 * u.s, samples=11)
    # theta constant: 2^50 turns of phi or psi; a top at rest has no limit
    assert benchmark_top(theta0=0 * u.deg).max_time.to_value(u.s) == pytest.approx((2**50 - 1) * 2 * np.pi / 10)
    monkeypatch.chdir(tmp_path)
    argv = ["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "60", "--omega3", "10", "--t-end", "1e20"]
    assert main([*argv, "-o", "x.nc"]) == 2
    err = capsys.readouterr().err
    assert (
        err.startswith(
            "wobble top: error: --t-end: got 1e20; allowed: |t| up to 1.46888e+15 s, "
            "2^50 nutation periods (1.30463 s each): beyond"
        )
        and err.count("\n") == 1
    )
    assert not (tmp_path / "x.nc").exists()


def test_cli_usage_error_is_one_line_exit_2(capsys):
    """argparse usage errors (both spins given) exit with status 2 and one line."""
    with pytest.raises(SystemExit) as ex:
        main(["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "1", "--omega3", "1", "--psidot0", "1"])
    assert ex.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not allowed with" in err


def test_cli_table_output(capsys):
    assert main(["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "60 deg", "--omega3", "10"]) == 0
    out = capsys.readouterr().out
    assert "cusps" in out and "nutation period" in out and "steady precession" in out


def test_plots_build_from_real_runs():
    """The figures of docs/heavy-top.md build (scripts/figures_top.py writes them)."""
    import matplotlib.pyplot as plt

    from wobble.plot.top import cubic_figure, effective_potential_figure, nutation_classes_figure

    fig = nutation_classes_figure(
        1 * KGM2, 0.5 * KGM2, 1 * u.J, 50 * u.deg, 6 * RAD_S, [0.2 * RAD_S, 0 * RAD_S, -0.3 * RAD_S], periods=2
    )
    assert len(fig.axes) == 3 and [a.get_title().split(":")[0] for a in fig.axes] == ["undulating", "cusps", "loops"]
    top = benchmark_top()
    for f in (fig, effective_potential_figure(top), cubic_figure(top)):
        plt.close(f)


def _same_dataset(fast, general):
    """Two Datasets equal in every respect a user or a file can see: values, attributes, the
    order of variables, dimensions and coordinates, the indexes and the variables' types."""
    xr.testing.assert_identical(fast, general)
    assert list(fast.variables) == list(general.variables)
    assert list(fast.dims) == list(general.dims) and dict(fast.sizes) == dict(general.sizes)
    assert list(fast.coords) == list(general.coords) and list(fast.data_vars) == list(general.data_vars)
    assert list(fast.xindexes) == list(general.xindexes)
    for name, index in fast.xindexes.items():
        other = general.xindexes[name]
        assert type(index) is type(other) and index.equals(other), name
        assert index.index.dtype == other.index.dtype and index.coord_dtype == other.coord_dtype, name
    for name, var in fast.variables.items():
        other = general.variables[name]
        assert type(var) is type(other) and type(var._data) is type(other._data), name
        assert var.dtype == other.dtype and list(var.attrs) == list(other.attrs) and var.encoding == other.encoding
    assert list(fast.attrs) == list(general.attrs) and fast.encoding == general.encoding


def test_direct_dataset_builder_equals_the_general_constructor(monkeypatch):
    """wobble.api.dataset.build skips xarray's merge: the heavy top's and the free body's
    Datasets are the ones xr.Dataset(...) builds from the same CF entries."""
    from wobble.api import dataset

    build = dataset.build

    def general(data_vars, coords, attrs=None):
        return dataset._general(data_vars, coords, attrs)

    t = np.linspace(0.0, 20.0, 1501) * u.s
    made = [
        lambda: benchmark_top().motion(t),
        lambda: benchmark_top(theta0=1e-4 * u.rad).to_dataset(t[:5]),
        lambda: wobble.FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S).to_dataset(t),
        lambda: wobble.FreeRotation([1, 1, 2] * KGM2, [0, 0, 0] * RAD_S).to_dataset(t[:3]),
    ]
    fast = [make() for make in made]
    # Shared label indexes, not shared variables: one Dataset's attributes are its own.
    fast[0]["axis"].attrs["note"] = "mine"
    assert "note" not in benchmark_top().motion(t[:3])["axis"].attrs and "note" not in fast[2]["axis"].attrs
    del fast[0]["axis"].attrs["note"]
    monkeypatch.setattr(dataset, "build", general)
    for got, make in zip(fast, made):
        _same_dataset(got, make())
    # Not the builder's kind of input: the general constructor decides (here it refuses).
    with pytest.raises(ValueError):
        build({"a": (("x",), np.zeros(2), {})}, {"x": (("x",), np.zeros(3), {})})


@pytest.mark.parametrize(("theta0", "phidot0", "which"), [(60 * u.deg, 0.0, "min"), (60 * u.deg, 3.0, "max")])
def test_a_start_at_a_turning_point_reads_as_typed(theta0, phidot0, which):
    """A top released with thetadot0 = 0 turns at its start (g(u0) = 0 exactly): that turning angle is
    the angle typed, 60 deg, not the 59.99999999999999 deg of the float round trip through rad (at rest in
    precession it falls from there; precessing at 3 rad/s, faster than steady, it rises from there)."""
    top = HeavyTop(
        I1=1 * u.kg * u.m**2,
        I3=0.5 * u.kg * u.m**2,
        mgl=1 * u.J,
        theta0=theta0,
        omega3=10 * u.rad / u.s,
        phidot0=phidot0 * u.rad / u.s,
    )
    turning = top.theta_min if which == "min" else top.theta_max
    assert turning.unit == u.deg and turning.value == theta0.to_value(u.deg)
    assert str(turning) == f"{theta0.to_value(u.deg)} deg"


def test_a_refused_value_is_shown_with_the_unit_it_was_given_in():
    """The model works in SI floats: mgl=-1 J was shown as 'mgl: got -1.0', and 2500 g m2 as '2.5'."""
    with pytest.raises(InputError, match=r"^mgl: got -1\.0 J; allowed: M g l >= 0"):
        HeavyTop(1 * KGM2, 0.5 * KGM2, mgl=-1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
    i3 = 2500 * u.g * u.m**2
    with pytest.raises(
        InputError, match=rf"^I3: got {re.escape(str(i3))}; allowed: I3 <= 2 I1"
    ):  # astropy's "2500.0 m2 g"
        HeavyTop(1 * KGM2, i3, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
