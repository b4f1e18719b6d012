"""The 50-digit scalar constants of wobble.numerics.highprec against mpmath.

References: tests/references/numerics_kernels.json ("highprec"), built by
tests/references/build_numerics_references.py at 80 digits from the exact float inputs.
The module works at DIGITS = 50 significant digits; the bounds here are 1e-46 relative
(a few units in the 50th digit), next to the zeros of sin and cos included.
"""

from __future__ import annotations

import decimal
import json
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from wobble.numerics import highprec as hp

REF = json.loads((Path(__file__).parent / "references" / "numerics_kernels.json").read_text())["highprec"]
TOL = Decimal("1e-46")


def _rel(got: Decimal, want: str) -> Decimal:
    w = Decimal(want)
    return abs(got - w) / abs(w) if w != 0 else abs(got)


def test_square_roots():
    for r in REF["sqrt"]:
        assert _rel(hp.sqrt(float(r["x"])), r["value"]) <= TOL, r


def test_agm_quarter_period():
    for r in REF["agm_k"]:
        assert _rel(hp.agm_k(float(r["m1"])), r["value"]) <= TOL, r


@pytest.mark.parametrize("kind", ["K", "E", "Pi"])
def test_bulirsch_cel(kind):
    """K = cel(k', 1, 1, 1), E = cel(k', 1, 1, k'^2), Pi(n | m) = cel(k', 1 - n, 1, 1)."""
    rows = [r for r in REF["cel"] if r["kind"] == kind]
    assert rows
    for r in rows:
        m1 = float(r["m1"])
        kc = hp.sqrt(m1)
        if kind == "K":
            got = hp.cel(kc, 1, 1, 1)
        elif kind == "E":
            got = hp.cel(kc, 1, 1, hp.dec(m1))
        else:
            got = hp.cel(kc, 1 - hp.exact(float(r["n"])), 1, 1)
        assert _rel(got, r["value"]) <= TOL, r


def test_cel_domain():
    with pytest.raises(ValueError):
        hp.cel(0.5, 0, 1, 1)
    with pytest.raises(ValueError):
        hp.cel(0, 1, 1, 1)


def test_sin_cos_keep_relative_digits_next_to_their_zeros():
    """46 digits, and next to a zero 1e-59 absolute: the fold uses pi to 60 digits, so
    cos(float(pi/2)) = 6.1e-17 and sin(float(pi)) = 1.2e-16 keep 43-44 digits, not 50."""
    for r in REF["sin_cos"]:
        s, c = hp.sin_cos(float(r["x"]))
        for got, want in ((s, r["sin"]), (c, r["cos"])):
            assert abs(got - Decimal(want)) <= TOL * abs(Decimal(want)) + Decimal("1e-59"), r
    with pytest.raises(ValueError):
        hp.sin_cos(3.2)


def test_double_double_conversion():
    for r in REF["agm_k"]:
        d = Decimal(r["value"])
        hi, lo = hp.to_dd(d)
        assert hi == float(d)  # correctly rounded
        with decimal.localcontext(decimal.Context(prec=80)):
            assert abs(Decimal(hi) + Decimal(lo) - d) <= Decimal("1e-32") * d
    assert hp.to_dd(Decimal("Infinity")) == (float("inf"), 0.0)
    assert hp.to_dd(0.0) == (0.0, 0.0)


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_floats_enter_exactly(x):
    """exact() is the float's binary value; dec() keeps its first 50 significant digits."""
    assert hp.exact(x) == Fraction(x)
    d = hp.dec(x)
    if x == 0:
        assert d == 0
    else:
        assert abs(Fraction(d) - Fraction(x)) <= abs(Fraction(x)) * Fraction(1, 10**49)
    assert hp.dec(7) == 7 and hp.dec(Decimal("0.1")) == Decimal("0.1")


@pytest.mark.parametrize(
    "args",
    [(0.3, 0.7, 1.0), (1e-30, 0.5, 1.0), (0.0, 1e-20, 1.0), (2.0, 3.0, 4.0), (1.0, 1.0, 1.0), (0.999999, 1.0, 1.0)],
)
def test_carlson_rf_against_mpmath(args):
    """R_F at 60 digits against mpmath's elliprf at 80, to 1e-57 relative (the top's start phase uses it)."""
    import decimal

    import mpmath

    ctx = hp.make_context(60)
    got = hp.carlson_rf(*args, ctx)
    with mpmath.workdps(80):
        want = mpmath.elliprf(*(mpmath.mpf(a) for a in args))
        assert abs(mpmath.mpf(str(got)) / want - 1) < mpmath.mpf("1e-57")
    assert isinstance(got, decimal.Decimal)


@pytest.mark.parametrize(
    "args", [(-1e-30, 0.5, 1.0), (0.0, 0.0, 1.0), (float("nan"), 1.0, 1.0), (float("inf"), 1.0, 1.0)]
)
def test_carlson_rf_outside_its_domain_is_refused(args):
    """A negative or non-finite argument, or two zeros (where R_F is infinite), is an error that names the
    arguments, not a Decimal InvalidOperation from a square root or a loop that quarters to underflow."""
    with pytest.raises(ValueError, match=r"carlson_rf takes finite x, y, z >= 0 with at most one zero"):
        hp.carlson_rf(*args)
