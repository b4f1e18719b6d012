"""The wobble/1 parameter-file schema: reading, validation messages, round trip."""

from __future__ import annotations

import numpy as np
import pytest
from astropy import units as u

from wobble.errors import FileFormatError, OutputExistsError
from wobble.io.parameter_file import read_parameter_file, write_parameter_file

GOOD = """
schema = "wobble/1"
kind = "planet"
name = "testworld"
title = "Test World"

[parameters.gm]
value = 3.986004418e14
uncertainty = 8e5
unit = "m3 s-2"
source = "IERS Conventions (2010), Table 1.1"
status = "read"

[parameters.moments]
value = [1.0, 2.0, 3.0]
uncertainty = 0.0
unit = "kg m2"
source = "made up"
status = "assumed"
note = "a test"
"""


def _write(tmp_path, text, name="p.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_reads_values_units_uncertainties(tmp_path):
    pf = read_parameter_file(_write(tmp_path, GOOD), kind="planet")
    gm = pf.parameters["gm"]
    assert gm.value == 3.986004418e14 * u.m**3 / u.s**2
    assert gm.uncertainty.to_value(u.km**3 / u.s**2) == pytest.approx(8e-4)
    assert gm.relative_uncertainty == pytest.approx(8e5 / 3.986004418e14)
    np.testing.assert_array_equal(pf.parameters["moments"].value.to_value(u.kg * u.m**2), [1, 2, 3])
    assert pf.title == "Test World" and pf.parameters["moments"].note == "a test"


def test_round_trip(tmp_path):
    pf = read_parameter_file(_write(tmp_path, GOOD))
    out = write_parameter_file(pf, tmp_path / "copy.toml")
    again = read_parameter_file(out)
    assert again.parameters.keys() == pf.parameters.keys()
    for key in pf.parameters:
        a, b = pf.parameters[key], again.parameters[key]
        np.testing.assert_array_equal(a.value.to_value(b.value.unit), b.value.value)
        assert (a.source, a.status, a.note) == (b.source, b.status, b.note)
    with pytest.raises(OutputExistsError):
        write_parameter_file(pf, out)


@pytest.mark.parametrize(
    ("edit", "where", "message"),
    [
        (('status = "read"', 'status = "guessed"'), "parameters.gm.status", "allowed: read, secondary"),
        (('unit = "m3 s-2"', 'unit = "furlongs^^"'), "parameters.gm.unit", "astropy can parse"),
        (("value = 3.986004418e14", 'value = "big"'), "parameters.gm.value", "numbers"),
        (("uncertainty = 8e5", "uncertainty = -1"), "parameters.gm.uncertainty", ">= 0"),
        (('source = "IERS Conventions (2010), Table 1.1"', ""), "parameters.gm", "missing field(s) source"),
        (('kind = "planet"', 'kind = "moon"'), "kind", "allowed: 'planet'"),
    ],
)
def test_malformed_fields_are_named(tmp_path, edit, where, message):
    path = _write(tmp_path, GOOD.replace(*edit, 1))
    with pytest.raises(FileFormatError) as info:
        read_parameter_file(path, kind="planet")
    assert info.value.where == where and message in str(info.value)
    assert str(path) in str(info.value)


def test_unknown_parameter_and_bad_toml(tmp_path):
    with pytest.raises(FileFormatError, match=r"parameters\.gm: unknown parameter; allowed: radius"):
        read_parameter_file(_write(tmp_path, GOOD), known={"radius"})
    with pytest.raises(FileFormatError, match="not valid TOML"):
        read_parameter_file(_write(tmp_path, "schema = ", "bad.toml"))
    with pytest.raises(FileFormatError, match="no such file"):
        read_parameter_file(tmp_path / "absent.toml")
