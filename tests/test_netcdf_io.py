"""The netCDF writer: CF layout, atomic writes, round trips."""

from __future__ import annotations

import os

import numpy as np
import pytest
import xarray as xr

from wobble.errors import FileFormatError, InputError, OutputExistsError
from wobble.io.netcdf import SIMULATION_TIME_UNITS, open_wobble, write_netcdf


def _sample() -> xr.Dataset:
    return xr.Dataset(
        {
            "period": (
                ("body", "step"),
                np.array([[303.6, 443.0], [190.3, 219.5]]),
                {"units": "day", "long_name": "Chandler wobble period after each model step"},
            ),
            "series": (("time",), np.linspace(0, 1, 5000), {"units": "1", "long_name": "ramp"}),
        },
        coords={
            "body": ("body", ["earth", "mars"], {"long_name": "body name"}),
            "step": ("step", ["rigid", "elastic"], {"long_name": "model step"}),
            "time": (
                "time",
                np.arange(5000.0),
                {"units": SIMULATION_TIME_UNITS, "long_name": "time", "standard_name": "time", "calendar": "standard"},
            ),
        },
        attrs={"title": "sample", "references": "none"},
    )


def test_round_trip_is_identical_and_cf_compliant(tmp_path, assert_cf_compliant):
    ds = _sample()
    path = write_netcdf(ds, tmp_path / "out.nc", command="test")
    back = open_wobble(path)
    for key in ("Conventions", "history", "source"):
        assert key in back.attrs
    assert back.attrs["Conventions"] == "CF-1.10"
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert_cf_compliant(path)


def test_plain_xarray_reads_the_same_numbers(tmp_path):
    path = write_netcdf(_sample(), tmp_path / "out.nc")
    with xr.open_dataset(path) as raw:
        np.testing.assert_array_equal(raw["period"].values, _sample()["period"].values)
        assert list(raw["body_name"].values) == ["earth", "mars"]


def test_existing_file_is_kept_without_overwrite(tmp_path):
    target = tmp_path / "out.nc"
    target.write_bytes(b"precious")
    with pytest.raises(OutputExistsError, match="overwrite=True"):
        write_netcdf(_sample(), target)
    assert target.read_bytes() == b"precious"
    write_netcdf(_sample(), target, overwrite=True)
    assert open_wobble(target)["period"].shape == (2, 2)


def test_failed_write_leaves_no_partial_file_and_keeps_the_old_one(tmp_path):
    target = tmp_path / "out.nc"
    target.write_bytes(b"precious")
    bad = _sample().assign(broken=(("body",), np.array([object(), object()])))
    with pytest.raises((TypeError, ValueError)):  # xarray cannot serialise an object array
        write_netcdf(bad, target, overwrite=True)
    assert target.read_bytes() == b"precious"
    assert os.listdir(tmp_path) == ["out.nc"]


def test_missing_folder_and_foreign_files_are_refused(tmp_path):
    with pytest.raises(InputError, match="existing folder"):
        write_netcdf(_sample(), tmp_path / "no" / "out.nc")
    foreign = tmp_path / "foreign.nc"
    xr.Dataset({"x": ("t", [1.0])}).to_netcdf(foreign)
    with pytest.raises(FileFormatError, match="written by wobble"):
        open_wobble(foreign)
    with pytest.raises(FileFormatError, match="no such file"):
        open_wobble(tmp_path / "absent.nc")


def test_written_files_get_the_usual_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        path = write_netcdf(_sample(), tmp_path / "out.nc")
    finally:
        os.umask(old)
    assert (path.stat().st_mode & 0o777) == 0o644
