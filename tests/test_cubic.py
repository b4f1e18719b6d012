"""The heavy top's cubic (wobble.numerics.cubic) against mpmath, and its invariants.

References: tests/references/numerics_kernels.json ("cubic"), built by
tests/references/build_numerics_references.py: the roots of
g(x) = x (2 - x)(A + beta x) - (B + a x)^2 (course notes section 5.7, x = 1 - u) by
mpmath.polyroots at 100 digits, polished in x next to u = 1 and in y = 2 - x next to
u = -1, for exact decimal coefficients. The module computes in decimal at 60 digits; each
root keeps its digits in its own coordinate, so the test is relative in x for roots next
to the vertical and relative in y for roots next to the bottom.
"""

from __future__ import annotations

import decimal
import json
from decimal import Decimal
from pathlib import Path

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from wobble.numerics import cubic

REF = json.loads((Path(__file__).parent / "references" / "numerics_kernels.json").read_text())
CASES = {r["name"]: r for r in REF["cubic"]}
TOL = Decimal("1e-45")  # relative, in the root's own coordinate (60-digit arithmetic)


def _solve(r):
    cub = cubic.TopCubic(
        A=Decimal(r["A"]), B=Decimal(r["B"]), C=Decimal(r["C"]), a=Decimal(r["a"]), beta=Decimal(r["beta"])
    )
    return cub, cubic.top_roots(cub, Decimal(r["x0"]), Decimal(r["y0"]), Decimal(r["g0"]))


def _close(got: Decimal, want: str) -> bool:
    w = Decimal(want)
    return abs(got - w) <= TOL * abs(w) if w != 0 else abs(got) <= Decimal("1e-200")


@pytest.mark.parametrize("name", list(CASES))
def test_roots_against_mpmath(name):
    """Each root within 1e-45 relative, in x (next to the vertical) and in y (next to the bottom)."""
    r = CASES[name]
    _, roots = _solve(r)
    if Decimal(r["beta"]) == 0:
        x2, x1 = r["x"]
        y2, y1 = r["y"]
        assert roots.x3 == Decimal("-Infinity") and roots.y3 == Decimal("Infinity")
    else:
        x3, x2, x1 = r["x"]
        y3, y2, y1 = r["y"]
        assert _close(roots.x3, x3) and _close(roots.y3, y3), (roots.x3, x3)
    for got, want in ((roots.x1, x1), (roots.x2, x2), (roots.y1, y1), (roots.y2, y2)):
        assert _close(got, want), (name, got, want)


def test_roots_crowding_at_the_vertical_keep_relative_digits():
    """x2 = 5e-201 (a top passing 1e-100 rad from the vertical): all 45 digits, not 0."""
    r = CASES["near the vertical"]
    _, roots = _solve(r)
    assert Decimal("4e-201") < roots.x2 < Decimal("6e-201")
    assert _close(roots.x2, r["x"][1])


def test_roots_crowding_at_the_bottom_keep_relative_digits():
    r = CASES["near the bottom"]
    _, roots = _solve(r)
    assert 0 < roots.y1 < Decimal("1e-90")
    assert _close(roots.y1, r["y"][2])


def test_double_root_of_regular_precession_is_exact():
    _, roots = _solve(CASES["regular precession"])
    assert roots.x1 == roots.x2 == Decimal("0.4")


def test_beta_span_and_gap_without_cancellation():
    """beta (x1 - x3) and beta (x2 - x3) stay finite as beta -> 0 (-> A + a^2)."""
    for name in ("generic", "crowded pair", "nearly free"):
        r = CASES[name]
        _, roots = _solve(r)
        with decimal.localcontext(decimal.Context(prec=80)):
            beta = Decimal(r["beta"])
            x3, x2, x1 = (Decimal(v) for v in r["x"])
            assert abs(roots.beta_span - beta * (x1 - x3)) <= TOL * abs(beta * (x1 - x3))
            assert abs(roots.beta_gap - beta * (x2 - x3)) <= TOL * abs(beta * (x2 - x3))
    r = CASES["free (beta = 0)"]
    _, roots = _solve(r)
    assert roots.beta_span == Decimal(r["A"]) + Decimal(r["a"]) ** 2


def test_quadratic_roots_without_cancellation():
    with decimal.localcontext(decimal.Context(prec=60)):
        small, other = cubic.quadratic_roots(Decimal(3), -3 * (Decimal("1e-30") + 7), 3 * Decimal("7e-30"))
    assert abs(small - Decimal("1e-30")) <= Decimal("1e-85")
    assert abs(other - 7) <= Decimal("1e-55")
    assert cubic.quadratic_roots(Decimal(0), Decimal(2), Decimal(-1)) == (Decimal("0.5"), Decimal("-Infinity"))
    with pytest.raises(ValueError):
        cubic.quadratic_roots(Decimal(1), Decimal(0), Decimal(1))
    with pytest.raises(ValueError):
        cubic.quadratic_roots(Decimal(0), Decimal(0), Decimal(1))


def test_an_impossible_start_raises():
    cub, _ = _solve(CASES["generic"])
    with pytest.raises(ValueError):
        cubic.top_roots(cub, Decimal("0.5"), Decimal("1.5"), Decimal(-1))


decimals = st.decimals(min_value=Decimal("-5"), max_value=Decimal("5"), places=3, allow_nan=False, allow_infinity=False)


@settings(max_examples=60)
@given(
    decimals,
    decimals,
    decimals,
    st.decimals(min_value=Decimal("0.001"), max_value=Decimal("5"), places=3),
    st.decimals(min_value=Decimal("0.001"), max_value=Decimal("1.999"), places=3),
)
def test_roots_reproduce_the_polynomial(A, B, a, beta, x0):
    """Property: for any start with g(x0) > 0, g(x_i) = 0 and Vieta's relations hold to 1e-45."""
    with decimal.localcontext(decimal.Context(prec=60)):
        cub = cubic.TopCubic(A=A, B=B, C=B + 2 * a, a=a, beta=beta)
        g0 = cub.g(x0)
        assume(g0 > 0 and B != 0 and B + 2 * a != 0)
        roots = cubic.top_roots(cub, x0, 2 - x0, g0)
        x1, x2, x3 = roots.x1, roots.x2, roots.x3
        assert x3 <= 0 <= x2 <= x0 <= x1 <= 2
        scale = abs(A) + B * B + a * a + beta + 1
        for x in (x1, x2):
            assert abs(cub.g(x)) <= Decimal("1e-45") * scale
        # -beta (x - x1)(x - x2)(x - x3): product and sum of the roots
        assert abs(beta * x1 * x2 * x3 + B * B) <= Decimal("1e-45") * (B * B + beta * abs(x1 * x2 * x3))
        assert abs(beta * (x1 + x2 + x3) - cub.c2) <= Decimal("1e-45") * (abs(cub.c2) + beta * (abs(x3) + 2))
