"""Units at the boundary: Quantities in, SI floats to the models, clear errors."""

from __future__ import annotations

import json

import numpy as np
import pytest
from astropy import units as u
from hypothesis import given
from hypothesis import strategies as st

from wobble.api.units import dimensionless, parse_quantity, spin_rate_si, to_si
from wobble.errors import InputError


def test_plain_float_is_refused_where_a_dimension_is_required():
    with pytest.raises(InputError, match=r"spin_period: got 1\.0; allowed: a Quantity with units of time"):
        to_si(1.0, "spin_period", u.s)


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("433 d", r"got '433 d'; .*a string is not a Quantity \(u.Quantity\('433 d'\) makes one\)"),
        (None, "got None; .*None is not a Quantity"),
        ([1 * u.d, 2 * u.d], r"a list of Quantities is not one \(u.Quantity\(...\) makes one\)"),
        ({"a": 1}, "a dict is not a Quantity"),
        (np.float32(2), "a plain number has no unit"),
        ([1, 2], "a plain number has no unit"),
    ],
)
def test_what_is_not_a_quantity_is_told_what_it_is(value, said):
    """A string was told "a plain number has no unit" and shown unquoted (got 433 d), as if it had a unit."""
    with pytest.raises(InputError, match=f"period: (got .*)?{said}"):
        to_si(value, "period", u.s)


def test_incompatible_unit_names_parameter_value_and_allowed():
    with pytest.raises(InputError) as info:
        to_si(3 * u.m, "spin_period", u.s)
    assert info.value.parameter == "spin_period"
    assert "3.0 m" in str(info.value) and "time" in str(info.value)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_values_are_refused(bad):
    with pytest.raises(InputError, match="finite"):
        to_si(bad * u.s, "t", u.s)


def test_sign_checks():
    with pytest.raises(InputError, match="positive"):
        to_si(0 * u.kg * u.m**2, "I1", u.kg * u.m**2, positive=True)
    assert to_si(0 * u.s, "t", u.s, nonnegative=True) == 0.0


def test_huge_and_tiny_moments_keep_relative_precision():
    # 1e-6 kg m2 (a toy top) to 1e38 kg m2 (Earth), and astronomical units.
    assert to_si(1e-6 * u.kg * u.m**2, "I", u.kg * u.m**2) == pytest.approx(1e-6, rel=1e-15)
    assert to_si(8.0e44 * u.g * u.cm**2, "I", u.kg * u.m**2) == pytest.approx(8.0e37, rel=1e-15)
    msun_au2 = (1 * u.Msun * u.au**2).to_value(u.kg * u.m**2)
    assert msun_au2 == pytest.approx(1.988409870698051e30 * 149597870700.0**2, rel=1e-15)


@given(st.floats(min_value=1e-300, max_value=1e300))
def test_unit_round_trip_days_seconds(x):
    q = x * u.day
    assert to_si(q, "t", u.s) / 86400.0 == pytest.approx(x, rel=1e-15)


def test_spin_accepts_rate_or_period():
    assert spin_rate_si(1 * u.sday) == pytest.approx(2 * np.pi / 86164.0905, rel=1e-9)
    assert spin_rate_si(7.292115e-5 * u.rad / u.s) == 7.292115e-5
    assert spin_rate_si(360 * u.deg / u.day) == pytest.approx(2 * np.pi / 86400, rel=1e-15)
    with pytest.raises(InputError, match="spin"):
        spin_rate_si(1 * u.m)
    with pytest.raises(InputError, match="positive"):
        spin_rate_si(-1 * u.day)


def test_dimensionless_ratio_bounds():
    assert dimensionless(0.5, "H", low=-1, high=1) == 0.5
    with pytest.raises(InputError, match=r"H: got 1; allowed: a number in \(-1, 1\)"):
        dimensionless(1, "H", low=-1, high=1)
    with pytest.raises(InputError, match="dimensionless"):
        dimensionless(1 * u.s, "H")


def test_parse_quantity_defaults_to_si_and_checks_units():
    assert parse_quantity("3", "t", u.s) == 3 * u.s
    assert parse_quantity("2 d", "t", u.s).to_value(u.s) == 172800.0
    with pytest.raises(InputError, match="t: got 2 m"):
        parse_quantity("2 m", "t", u.s)
    with pytest.raises(InputError, match="t: got abc"):
        parse_quantity("abc", "t", u.s)


@pytest.mark.parametrize(
    ("plural", "singular"),
    [
        ("90 days", "90 d"),
        ("3 years", "3 yr"),
        ("2 hours", "2 h"),
        ("100 seconds", "100 s"),
        ("60 degrees", "60 deg"),
        ("2 weeks", "2 wk"),
        ("5 minutes", "5 min"),
        ("3 yrs", "3 yr"),
        ("360 degrees / days", "360 deg / d"),
        ("2 mas", "2 mas"),  # known as it is: never made singular ("ma")
        ("3 Ms", "3 Ms"),  # megaseconds, not "M"
    ],
)
def test_units_in_the_plural_read_as_people_write_them(plural, singular):
    """'--horizon 90 days' was refused, with a suggestion ('90days' or '90 days' in quotes) that was refused too:
    astropy knows "day" but not "days"."""
    from wobble.io.quantity_values import quantity_from_text

    got, want = quantity_from_text(plural), u.Quantity(singular)
    assert got.unit == want.unit and got.value == want.value


def test_the_command_line_reads_a_horizon_in_days(capsys):
    from wobble.cli import main

    assert main(["forecast", "--horizon", "30 days", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["horizon_days"] == 30
