"""The engine's netCDF files: CF compliance, round trips, streaming, atomic writes, units back."""

from __future__ import annotations

import astropy.units as u
import netCDF4
import numpy as np
import pytest
import xarray as xr

import wobble
from wobble.errors import FileFormatError, InputError, OutputExistsError

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s


def top(**kw):
    theta = np.radians(60)
    kw.setdefault("t_end", 2 * u.s)
    kw.setdefault("samples", 41)
    return wobble.Scene(
        body=[1.0, 1.0, 0.5] * KGM2,
        omega0=[0.0, 0.0, 10.0] * RAD_S,
        attitude0=[np.cos(theta / 2), np.sin(theta / 2), 0, 0],
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, 1] * u.m, g=1 * u.m / u.s**2)],
        accuracy=1e-8,
        **kw,
    )


KINDS = {
    "free single (exact)": lambda: "tennis_racket",
    "free ensemble, epoch": lambda: "tumbling_asteroid",
    "torqued, every output": lambda: top(outputs=list(wobble.models.scene.OUTPUTS)),
    "planet, epoch, daily": lambda: "mars_free_wobble",
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_each_kind_of_file_round_trips_and_is_cf_compliant(kind, tmp_path, assert_cf_compliant):
    scene = KINDS[kind]()
    ds = wobble.run(scene)
    path = wobble.write_netcdf(ds, tmp_path / "a.nc")
    back = wobble.load(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert_cf_compliant(path)
    for key in (
        "model",
        "model_reason",
        "error_estimate",
        "scene",
        "accuracy_requested",
        "Conventions",
        "history",
        "source",
        "references",
        "title",
    ):
        assert key in back.attrs
    # streamed: the same layout, the same numbers, also CF
    summary = wobble.run_to_netcdf(scene, tmp_path / "b.nc", block_bytes=4096)
    streamed = wobble.load(tmp_path / "b.nc")
    assert summary["model"] == ds.attrs["model"]
    assert set(streamed.data_vars) == set(ds.data_vars) and dict(streamed.sizes) == dict(ds.sizes)
    if ds.attrs["model"].startswith("free") or ds.attrs["model"].startswith("splitting"):
        # exact models and fixed steps do not depend on the blocks
        xr.testing.assert_allclose(streamed, ds, rtol=0, atol=1e-14)
    else:
        xr.testing.assert_allclose(streamed, ds, rtol=1e-8)
    assert_cf_compliant(tmp_path / "b.nc")


def test_time_units_carry_the_scene_epoch(tmp_path):
    ds = wobble.run("earth_free_wobble")
    assert ds["time"].attrs["units"] == "seconds since 2000-01-01 12:00:00"
    assert ds.wobble.epoch == "2000-01-01 12:00:00"
    plain = wobble.run(top())
    assert plain["time"].attrs["units"] == wobble.io.netcdf.SIMULATION_TIME_UNITS
    decoded = xr.open_dataset(wobble.write_netcdf(ds, tmp_path / "e.nc"))  # CF decoding gives dates
    assert str(decoded["time"].values[1])[:10] == "2000-01-02"
    decoded.close()


def test_units_come_back_as_quantities(tmp_path):
    ds = wobble.load(
        wobble.write_netcdf(wobble.run(top(outputs=["omega", "total_energy", "tilt", "attitude"])), tmp_path / "q.nc")
    )
    assert ds.wobble.quantity("omega").unit == RAD_S
    assert ds.wobble.quantity("total_energy").unit == u.J
    assert ds.wobble.quantity("tilt").to(u.deg)[0].value == pytest.approx(60.0, rel=1e-13)
    assert ds.wobble.quantity("attitude").unit == u.dimensionless_unscaled
    assert ds.wobble.quantity("time")[-1] == 2 * u.s
    assert set(ds.wobble.quantities()) == {"omega", "total_energy", "tilt", "attitude"}
    assert ds.wobble.model == "heavy-top"
    assert wobble.quantity(ds["omega"]).unit == RAD_S
    with pytest.raises(InputError, match="name"):
        ds.wobble.quantity("spin")


def test_streamed_files_are_compressed_and_chunked_along_time(tmp_path):
    wobble.run_to_netcdf("tumbling_asteroid", tmp_path / "c.nc", block_bytes=8192)
    with netCDF4.Dataset(tmp_path / "c.nc") as nc:
        var = nc.variables["omega"]
        assert var.filters()["zlib"] and var.dimensions[0] == "time"
        assert nc.dimensions["time"].isunlimited()
        assert var.chunking()[0] >= 1 and var.chunking()[1:] == [4, 3]


def test_existing_file_is_replaced_only_with_overwrite(tmp_path):
    path = tmp_path / "x.nc"
    path.write_text("precious")
    with pytest.raises(OutputExistsError):
        wobble.run_to_netcdf("tennis_racket", path)
    assert path.read_text() == "precious" and sorted(p.name for p in tmp_path.iterdir()) == ["x.nc"]
    wobble.run_to_netcdf("tennis_racket", path, overwrite=True)
    assert wobble.load(path).attrs["model"] == "free-elliptic"


def test_a_failing_run_leaves_nothing_behind(tmp_path):
    """A torque that fails half-way through a streamed run: no file, no temporary file, old file intact."""
    calls = {"n": 0}

    def flaky(t, w, q):
        calls["n"] += 1
        if calls["n"] > 3000:
            raise RuntimeError("sensor failure")
        return np.zeros_like(w)

    scene = wobble.Scene(
        body=[1, 2, 3] * KGM2,
        omega0=[1, 0.1, 1] * RAD_S,
        t_end=200 * u.s,
        samples=2001,
        torques=[wobble.Torque.custom(flaky)],
        accuracy=1e-6,
    )
    path = tmp_path / "y.nc"
    path.write_text("old")
    with pytest.raises(RuntimeError, match="sensor"):
        wobble.run_to_netcdf(scene, path, overwrite=True, block_bytes=4096)
    assert path.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["y.nc"]


def test_load_refuses_files_that_are_not_wobbles(tmp_path):
    foreign = tmp_path / "f.nc"
    xr.Dataset({"x": ("t", [1.0, 2.0])}, attrs={"source": "someone else"}).to_netcdf(foreign)
    with pytest.raises(FileFormatError, match="not.*wobble|written by wobble"):
        wobble.load(foreign)
    junk = tmp_path / "j.nc"
    junk.write_text("not netcdf")
    with pytest.raises(FileFormatError, match="j.nc"):
        wobble.load(junk)
    with pytest.raises(FileFormatError, match="no such file"):
        wobble.load(tmp_path / "missing.nc")


def test_outputs_too_large_for_memory_are_sent_to_the_streaming_writer(monkeypatch):
    monkeypatch.setattr("wobble.api.scene._MEMORY_LIMIT", 1000)
    with pytest.raises(InputError, match="run_to_netcdf"):
        wobble.run("tennis_racket")


def test_flags_are_not_quantities():
    """ds.wobble.quantities() turned a sweep's invalid_reason codes (int8, units "1") into floats 0.0, 3.0;
    flags (CF flag_values) are labels and are left out; the numbers keep their units."""
    from wobble.api.sweep import run_sweep

    spec = {
        "schema": "wobble-sweep/1", "name": "f", "target": "chandler", "body": "mars", "members": 20, "seed": 1,
        "outputs": ["chandler_period"], "vary": {"love_number_k2": {"distribution": "normal"}},
    }  # fmt: skip
    ds = run_sweep(spec)
    got = ds.wobble.quantities()
    assert "invalid_reason" not in got and "flag_values" in ds["invalid_reason"].attrs
    assert got["chandler_period"].unit == u.day and got["love_number_k2"].unit == u.dimensionless_unscaled
