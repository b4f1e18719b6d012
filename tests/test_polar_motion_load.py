"""Loading the IERS record: a CF Dataset with units; dates in every form; dates outside the data refused."""

from __future__ import annotations

import pytest
from astropy.time import Time

import wobble
from wobble.api.polar_motion import MJD_UNITS
from wobble.errors import InputError


def test_load_gives_a_cf_dataset_with_units():
    ds = wobble.load_polar_motion(start="2010-01-01", end="2010-12-31")
    assert ds.sizes["time"] == 365
    assert ds["time"].attrs["units"] == MJD_UNITS and ds["time"].attrs["calendar"] == "standard"
    assert ds["time"].values[0] == Time("2010-01-01", scale="utc").mjd
    for name in ("x_p", "y_p", "x_p_error", "y_p_error"):
        assert ds[name].attrs["units"] == "milliarcsecond" and ds[name].attrs["long_name"]
    assert ds["x_p"].attrs["ancillary_variables"] == "x_p_error"


def test_the_pole_in_mas_is_the_files_decimal():
    """The file's arcsec (6 decimals) times 1000 is written as the double nearest the decimal in mas, not an
    ulp beside it (0.098670 * 1000 is 98.67 exactly in decimal; in floats the product can miss it)."""
    from decimal import Decimal

    from wobble.io.eop import default_c04_path

    ds = wobble.load_polar_motion(start="2010-01-01", end="2010-12-31")
    rows = {}
    with open(default_c04_path()) as fh:
        for line in fh:
            fields = line.split()
            if len(fields) > 6 and fields[4].replace(".", "").isdigit() and 55197 <= float(fields[4]) <= 55561:
                rows[float(fields[4])] = (fields[5], fields[6])
    assert len(rows) == 365
    for k, mjd in enumerate(ds["time"].values):
        x, y = rows[float(mjd)]
        assert ds["x_p"].values[k] == float(Decimal(x) * 1000) and ds["y_p"].values[k] == float(Decimal(y) * 1000)
    assert "C04" in ds.attrs["references"] and "x_p - i y_p" in ds.attrs["comment"]


def test_load_finals_file():
    from wobble.io.eop import default_c04_path

    ds = wobble.load_polar_motion(default_c04_path().parent / "finals2000A.all", start="2001-01-01", end="2001-03-01")
    assert ds.attrs["source_format"] == "finals2000A" and ds.sizes["time"] == 60


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"start": "1950-01-01"}, "start: got 1950-01-01; allowed: a date from 1962-01-01 to"),
        ({"end": "2099-01-01"}, "end: got 2099-01-01; allowed: a date from 1962-01-01"),
        ({"start": "2010-01-01", "end": "2009-01-01"}, "a date after start"),
        ({"start": "yesterday"}, "start: got yesterday; allowed: a UTC date"),
        # A number is refused, saying why: the help lists 2015 and 2015.5 as text.
        ({"start": 2015}, r"allowed: a UTC date .*; a year as text \('2015'\), not a number \(a year or an MJD\?\)"),
    ],
)
def test_dates_outside_the_data_are_errors(kwargs, fragment):
    with pytest.raises(InputError, match=fragment):
        wobble.load_polar_motion(**kwargs)


def test_date_forms():
    a = wobble.load_polar_motion(start="2015", end="2015-06")
    assert a["time"].values[0] == Time("2015-01-01").mjd and a["time"].values[-1] == Time("2015-06-01").mjd
    b = wobble.load_polar_motion(start=Time("2015-01-01"), end="2015.5")
    assert b["time"].values[0] == a["time"].values[0]
    import datetime

    c = wobble.load_polar_motion(start=datetime.date(2015, 1, 1), end=datetime.date(2015, 2, 1))
    assert c.sizes["time"] == 32
