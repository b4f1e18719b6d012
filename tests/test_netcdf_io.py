"""The netCDF writer: CF layout, atomic writes, round trips."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest
import xarray as xr
from astropy import units as u

import wobble
from wobble.errors import FileFormatError, InputError, OutputExistsError
from wobble.io import cf
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


def test_a_run_past_the_cf_calendar_range_keeps_a_file_xarray_opens(tmp_path):
    """cftime and xarray decode a CF calendar time as 64-bit microseconds from its epoch (292,000 years):
    a torque-free run over a million years wrote 'seconds since 2000-01-01 12:00:00' that
    xr.open_dataset refused to open (fuzz run of 2026-11-28). Past that reach the coordinate is elapsed
    time in s, the epoch kept in time_origin; inside it, calendar time as before. The decoder itself
    is the judge: xarray's default open, on each side of the bound."""
    scene = wobble.Scene(
        body=[1, 1, 2] * u.kg * u.m**2, omega0=[0.1, 0, 1] * u.rad / u.s, t_end=1 * u.Myr, samples=11, outputs=["omega"]
    )
    ds = wobble.run(scene)
    path = write_netcdf(ds, tmp_path / "long.nc")
    with xr.open_dataset(path) as plain:  # default decoding
        assert plain["time"].dtype == np.float64 and plain["time"].attrs["units"] == "s"
        np.testing.assert_array_equal(plain["time"].values, ds["time"].values)
    back = open_wobble(path)
    xr.testing.assert_identical(back, ds.assign_attrs(back.attrs))
    assert back.wobble.epoch == "2000-01-01 12:00:00"
    assert back.wobble.quantity("time")[-1].to_value(u.yr) == pytest.approx(1e6, rel=1e-15)
    # The checker takes any variable named time for a calendar time axis (a name heuristic, medium
    # priority): its one remark. To CF a time coordinate needs a reference time, which no reader decodes
    # this far, so the coordinate is a plain one in s.
    from conftest import cf_problems

    assert cf_problems(path) == [
        "§5.1 Independent Latitude, Longitude, Vertical, and Time Axes: Coordinate variable 'time' should have "
        "standard_name='time', found: 'None'"
    ]
    for reach, calendar in ((9.0e12, True), (9.3e12, False)):
        coord = cf.time_coordinate(np.array([0.0, reach]))
        assert ("calendar" in coord[2]) == calendar
        small = tmp_path / f"reach_{reach:g}.nc"
        xr.Dataset(coords={"time": coord}).to_netcdf(small)
        with warnings.catch_warnings():
            # xarray's notice that dates past 2262 become cftime objects, not numpy datetimes.
            warnings.simplefilter("ignore", xr.SerializationWarning)
            with xr.open_dataset(small) as plain:
                assert (plain["time"].dtype != np.float64) == calendar


@pytest.mark.parametrize(
    "unit",
    ["mas / yr", "1 / yr", "yr", "mas", "arcsec", "arcsec / yr", "kg / m3", "rad / s", "d", "deg", "km3 / s2", "J"],
)
def test_every_units_attribute_wobble_writes_reads_back_as_its_unit(unit):
    """udunits() writes astropy's yr as Julian_year and mas as milliarcsecond; wobble.quantity refused
    its own 'Julian_year-1' (the excitation file's frequency) and 'milliarcsecond Julian_year-1'."""
    from wobble.io.cf import udunits

    var = xr.DataArray([1.5, 2.5], dims="x", name="v", attrs={"units": udunits(unit)})
    got = wobble.quantity(var)
    assert got.unit == u.Unit(unit) and list(got.value) == [1.5, 2.5]


def test_the_julian_year_is_written_as_pint_and_udunits_read_it_and_older_files_still_read():
    """'Julian_year' (files before 2026-11-30) is not a pint unit, so cf_xarray's registry refused the
    excitation's frequency; 'julian_year' is 365.25 d in UDUNITS and in pint alike."""
    from wobble.io.cf import udunits

    assert udunits("mas / yr") == "milliarcsecond julian_year-1"
    for text in ("milliarcsecond julian_year-1", "milliarcsecond Julian_year-1"):
        var = xr.DataArray([1.0], dims="x", attrs={"units": text})
        assert wobble.quantity(var).unit == u.mas / u.yr
    cf_units = pytest.importorskip("cf_units")
    assert cf_units.Unit("julian_year").convert(1.0, "day") == 365.25


def test_a_folder_is_not_a_netcdf_file_and_says_what_opens_it(tmp_path):
    """A Zarr store of wobble sweep is a folder: wobble.load said "no such file" for one that exists."""
    store = tmp_path / "sweep.zarr"
    store.mkdir()
    with pytest.raises(FileFormatError, match=r"a folder, not a netCDF file .*open_wobble_zarr or xarray\.open_zarr"):
        wobble.load(store)


def test_what_is_not_a_dataset_or_a_variable_is_named(tmp_path):
    """write_netcdf of a dict or a DataArray, and quantity of a bare number, raised AttributeError from
    inside; an xarray Variable (ds.variables['x']) has no name and is read all the same."""
    for bad, fragment in (({"a": 1}, "got dict; allowed: an xarray Dataset$"), (xr.DataArray([1.0]), "to_dataset")):
        with pytest.raises(InputError, match=f"^ds: {fragment}" if fragment.startswith("got") else fragment):
            wobble.write_netcdf(bad, tmp_path / "x.nc")
    assert list(tmp_path.iterdir()) == []
    var = xr.Variable("x", [1.0, 2.0], {"units": "km"})
    assert list(wobble.quantity(var).to_value(u.m)) == [1000.0, 2000.0]
    with pytest.raises(InputError, match=r"^var: got int; allowed: a variable of a Dataset"):
        wobble.quantity(3)
