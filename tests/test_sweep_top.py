"""The heavy-top phase-diagram sweep against the exact scalar model and the notes' closed forms."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

import wobble
from wobble.api.sweep import run_sweep
from wobble.cli import main
from wobble.errors import FileFormatError
from wobble.io.netcdf import write_netcdf
from wobble.models.top import NUTATION_CLASSES, heavy_top, regular_precession_rates
from wobble.models.top_phase import phase_analysis

I1, I3, MGL = 1.0, 0.5, 1.0


def _value(v):
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_value(x)}" for k, x in v.items()) + " }"
    return json.dumps(v)


def write_toml(path, spec: dict):
    """A sweep dict as TOML (scalars, lists, one level of tables whose entries may be inline tables)."""
    lines = [f"{k} = {_value(v)}" for k, v in spec.items() if not isinstance(v, dict)]
    for k, table in spec.items():
        if isinstance(table, dict):
            lines.append(f"[{k}]")
            lines += [f"{name} = {_value(v)}" for name, v in table.items()]
    path.write_text("\n".join(lines) + "\n")


def _spec(**vary):
    return {
        "schema": "wobble-sweep/1",
        "name": "top_test",
        "target": "heavy_top",
        "base": {
            "I1": {"value": I1, "unit": "kg m2"},
            "I3": {"value": I3, "unit": "kg m2"},
            "mgl": {"value": MGL, "unit": "J"},
        },
        "vary": vary,
    }


GRID = _spec(
    theta0={"distribution": "grid", "start": 0.0, "stop": 180.0, "num": 19, "unit": "deg"},
    omega3={"distribution": "grid", "values": [-6.0, 0.0, 1.0, 4.0, 8.0, 15.0], "unit": "rad/s"},
    phidot0={"distribution": "grid", "values": [-0.5, 0.0, 0.25, 0.5, 1.0], "unit": "rad/s"},
)


@pytest.fixture(scope="module")
def grid():
    return run_sweep(GRID, chunk_size=97)


def test_every_grid_point_agrees_with_the_exact_model(grid):
    codes = grid.nutation_class.attrs["flag_values"].tolist()
    meanings = grid.nutation_class.attrs["flag_meanings"].split()
    names = dict(zip(codes, meanings))
    assert names[1] == "cusps" and names[3] == "regular"
    vectorised = 0
    for idx in np.ndindex(grid.nutation_class.shape):
        th = math.radians(float(grid.theta0[idx[0]]))  # written in deg, as the sweep gave it
        w = float(grid.omega3[idx[1]])
        pd = float(grid.phidot0[idx[2]])
        pt = grid.isel(theta0=idx[0], omega3=idx[1], phidot0=idx[2])
        try:
            model = heavy_top(I1, I3, MGL, th, phidot0=pd, omega3=w)
        except wobble.InputError:
            assert int(pt.invalid_reason) == 3
            continue
        assert int(pt.invalid_reason) == 0
        expected = model.nutation
        assert names[int(pt.nutation_class)] == expected, (th, w, pd)
        assert int(pt.sleeping_stable) == int(model.sleeping_stable)
        vectorised += int(pt.scalar_fallback) == 0
        for key in ("nutation_period", "theta_min", "theta_max", "mean_precession_rate"):
            want = getattr(model, key)
            np.testing.assert_allclose(float(pt[key]), want, rtol=1e-8, atol=1e-12, err_msg=f"{key} at {(th, w, pd)}")
    assert vectorised > 0.7 * grid.nutation_class.size  # most members take the numpy path


def test_released_top_traces_cusps_exactly_when_phidot0_and_thetadot0_vanish(grid):
    interior = grid.isel(theta0=slice(1, -1)).sel(omega3=[1.0, 4.0, 8.0, 15.0])
    assert (interior.nutation_class.sel(phidot0=0.0) == 1).all()
    # phidot0 != 0 gives cusps only on the curve b = a u at the far turning point
    # (phidot0 = beta / a = 2 M g l / (I3 omega3)); elsewhere never.
    for pd in (-0.5, 0.25, 1.0):
        for w in (1.0, 15.0):
            assert (interior.nutation_class.sel(phidot0=pd, omega3=w) != 1).all()
    assert (interior.nutation_class.sel(phidot0=0.5, omega3=8.0) == 1).all()  # 2 x 1 / (0.5 x 8) = 0.5


def test_regular_precession_at_the_notes_rates_and_sleeping_stability():
    theta = np.radians([20.0, 50.0, 80.0, 110.0])
    omega3 = np.array([8.0, 12.0, 20.0, 30.0])
    slow = np.array([regular_precession_rates(I1, I3, MGL, w, t)[0] for w, t in zip(omega3, theta)])
    fast = np.array([regular_precession_rates(I1, I3, MGL, w, t)[1] for w, t in zip(omega3, theta)])
    res = phase_analysis(I1, I3, MGL, np.r_[theta, theta], np.r_[omega3, omega3], np.r_[slow, fast])
    assert (res["nutation_class"] == 3).all()  # f(u0) = 0 and f'(u0) = 0
    np.testing.assert_allclose(res["mean_precession_rate"], np.r_[slow, fast], rtol=1e-12)
    np.testing.assert_allclose(res["theta_min"], np.r_[theta, theta], rtol=1e-12)
    # Sleeping top (theta0 = 0): stable iff I3^2 omega3^2 > 4 M g l I1, here |omega3| > 4 rad/s.
    w = np.array([-5.0, -4.0, 0.0, 3.9, 4.0, np.nextafter(4.0, 5.0), 10.0])
    sleep = phase_analysis(I1, I3, MGL, 0.0, w)
    assert (sleep["nutation_class"] == 4).all()
    np.testing.assert_array_equal(sleep["sleeping_stable"], [True, False, False, False, False, True, True])


def test_chunking_does_not_change_the_numbers(grid):
    xr.testing.assert_identical(grid, run_sweep(GRID, chunk_size=10_000, scheduler="synchronous"))


def test_bad_members_are_flagged_and_the_sweep_goes_on():
    spec = _spec(
        I3={"distribution": "grid", "values": [0.5, 2.5], "unit": "kg m2"},  # I3 > 2 I1: no real top
        theta0={"distribution": "grid", "values": [30.0, 60.0], "unit": "deg"},
    )
    del spec["base"]["I3"]
    spec["base"]["omega3"] = {"value": 5.0, "unit": "rad/s"}
    ds = run_sweep(spec)
    np.testing.assert_array_equal(ds.invalid_reason.values, [[0, 0], [1, 1]])
    assert (ds.nutation_class.values[1] == -1).all() and np.isnan(ds.nutation_period.values[1]).all()
    assert (ds.nutation_class.values[0] == 1).all()


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"base": {"I1": {"value": 1.0, "unit": "kg m2"}, "I2": {"value": 1.0, "unit": "kg m2"}}}, "base.I2"),
        ({"base": {"I1": {"value": 1.0, "unit": "m"}}}, "base.I1.unit"),
        ({"base": {"I1": {"value": 1.0, "unit": "kg m2", "sigma": 0.1}}}, "base.I1.sigma"),
        ({"vary": {"tilt": {"distribution": "grid", "values": [1.0]}}}, "vary.tilt"),
        ({"outputs": ["nutation"]}, "outputs"),
        ({"body": "mars"}, "body"),
    ],
)
def test_bad_keys_are_named_with_the_file_before_any_work(tmp_path, change, key):
    spec = {**GRID, **change}
    path = tmp_path / "bad.toml"
    write_toml(path, spec)
    with pytest.raises(FileFormatError) as err:
        wobble.sweep(path)
    assert key in str(err.value) and "bad.toml" in str(err.value)
    assert main(["sweep", str(path), "--quiet"]) == 2


def test_cli_writes_a_file_that_round_trips(tmp_path, capsys, assert_cf_compliant):
    small = tmp_path / "small.toml"
    spec = _spec(
        theta0={"distribution": "grid", "start": 0.0, "stop": 180.0, "num": 7, "unit": "deg"},
        omega3={"distribution": "grid", "values": [0.0, 5.0, 10.0], "unit": "rad/s"},
    )
    write_toml(small, spec)
    out = tmp_path / "x.nc"
    assert main(["sweep", str(small), "-o", str(out), "--quiet", "--plot", str(tmp_path / "p.png")]) == 0
    text = capsys.readouterr().out
    assert "cusps:" in text and "sleeping:" in text
    back = wobble.load(out)
    assert back.nutation_class.attrs["flag_meanings"] == "invalid undulating cusps loops regular sleeping"
    assert_cf_compliant(out)
    again = tmp_path / "again.nc"
    write_netcdf(back, again)
    reopened = wobble.load(again)
    for ds in (back, reopened):
        ds.attrs.pop("history")  # each write appends its own line
    xr.testing.assert_identical(back, reopened)
    assert (tmp_path / "p.png").stat().st_size > 10_000


def test_shipped_phase_diagram_file_is_valid():
    ds = wobble.sweep("data/sweeps/top_phase_diagram.toml")
    assert ds.nutation_class.shape == (91, 101, 5)
    assert set(NUTATION_CLASSES) == {"undulating", "cusps", "loops", "regular", "sleeping"}


def test_the_phase_diagram_s_classes_stay_apart_for_colour_blind_readers():
    """Simulated deuteranopia and protanopia (Machado, Oliveira & Fernandes 2009, IEEE TVCG 15, 1291, severity
    1; applied to linear RGB) made cusps and loops both olive and undulating and regular both blue (sRGB
    distance 0.04-0.10); every pair of classes is now at least 0.2 apart under both."""
    import itertools

    import matplotlib.colors as mcolors

    from wobble.plot.sweep import _CLASS_COLOURS

    machado = {
        "deuteranopia": [
            [0.367322, 0.860646, -0.227968],
            [0.280085, 0.672501, 0.047413],
            [-0.011820, 0.042940, 0.968881],
        ],
        "protanopia": [
            [0.152286, 1.052583, -0.204868],
            [0.114503, 0.786281, 0.099216],
            [-0.003882, -0.048116, 1.051998],
        ],
    }

    def seen(colour, matrix):
        c = np.asarray(mcolors.to_rgb(colour))
        linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
        out = np.clip(np.asarray(matrix) @ linear, 0, 1)
        return np.where(out <= 0.0031308, 12.92 * out, 1.055 * out ** (1 / 2.4) - 0.055)

    classes = {k: v for k, v in _CLASS_COLOURS.items() if k != "invalid"}
    for matrix in machado.values():
        for (a, ca), (b, cb) in itertools.combinations(classes.items(), 2):
            assert np.linalg.norm(seen(ca, matrix) - seen(cb, matrix)) >= 0.2, (a, b)


def test_the_grid_speaks_the_files_unit_and_the_diagram_reads_it():
    """theta0 given in degrees is written in degrees (it was written in rad); the same grid given in rad is
    written in rad, the numbers of both are the same tops, and the phase diagram draws both in degrees."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from wobble.plot.sweep import phase_diagram

    omega3 = {"distribution": "grid", "values": [2.0, 6.0], "unit": "rad/s"}
    deg = run_sweep(_spec(theta0={"distribution": "grid", "values": [30.0, 60.0], "unit": "deg"}, omega3=omega3))
    rad = run_sweep(
        _spec(theta0={"distribution": "grid", "values": [math.pi / 6, math.pi / 3], "unit": "rad"}, omega3=omega3)
    )
    assert deg.theta0.attrs["units"] == "degree" and deg.theta0.values.tolist() == [30.0, 60.0]
    assert rad.theta0.attrs["units"] == "rad"
    np.testing.assert_allclose(deg.theta_min.values, rad.theta_min.values, rtol=1e-14)
    meshes = []
    for ds in (deg, rad):
        fig = phase_diagram(ds)
        meshes.append(fig.axes[0].collections[0].get_coordinates()[:, 0, 1])  # the y of the cells' corners
        plt.close(fig)
    np.testing.assert_allclose(meshes[0], meshes[1], rtol=1e-12)
    np.testing.assert_allclose(meshes[0], [15.0, 45.0, 75.0], rtol=1e-12)  # cells centred on 30 and 60 deg
