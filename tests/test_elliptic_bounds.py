"""Every accuracy bound documented in wobble.numerics.elliptic holds on the worst rows.

The rows (tests/references/elliptic_kernels.json, built by
tests/references/build_elliptic_references.py with mpmath at 40+ digits) are the worst
rows of Boost.Math's elliptic-function tables for wobble's kernels (as found by
scripts/check_reference_tables.py) and grids over the parameter from m1 = 2.2e-308 to 1.
One test per documented bound; errors in eps = 2^-52 relative to the exact value at the
float inputs.
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wobble.numerics import double_double as dd
from wobble.numerics import elliptic as ell
from wobble.numerics.phase import reduce_phase

REF = json.loads((Path(__file__).parent / "references" / "elliptic_kernels.json").read_text())
EPS = 2.0**-52
INTEGRALS = REF["integrals"]
JACOBI = REF["jacobi"]


def _kind(kind):
    return [r for r in INTEGRALS if r["kind"] == kind]


def _rel(got, want):
    want = float(want)
    return abs(float(got) - want) / abs(want) if want != 0 else abs(float(got))


def _pi_inc(n, phi, m1):
    """Pi(n; phi | m) through the documented large-phi reduction."""
    r, j = ell.reduce_amplitude(phi)
    whole = 2.0 * j * ell.ellippi(n, 1 - m1, m1) if j != 0 else 0.0
    return whole + ell.ellippi_inc(n, r, 1 - m1, m1)


# The corner where SciPy's R_J loses digits (documented): cos^2 phi, m1 and 1 - n all tiny.
def _rj_corner(n, phi, m1):
    return np.cos(phi) ** 2 < 1e-20 and m1 < 1e-10 and 0 < 1 - n < 1e-4


# ---------------------------------------------------------------------------
# Complete integrals: correctly rounded (half an ulp)
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("kind, fn", [("K", ell.ellipk), ("E", ell.ellipe)])
def test_complete_first_and_second_kind_within_half_an_ulp(kind, fn):
    rows = _kind(kind)
    assert len(rows) >= 20
    worst = max(_rel(fn(1 - float(r["m1"]), float(r["m1"])), r["value"]) for r in rows)
    assert worst <= 1.2e-16, worst


def test_complete_third_kind_within_half_an_ulp():
    rows = _kind("Pi")
    assert len(rows) >= 70
    worst = max(_rel(ell.ellippi(float(r["n"]), 1 - float(r["m1"]), float(r["m1"])), r["value"]) for r in rows)
    assert worst <= 1.2e-16, worst


def test_complete_integrals_vectorised_as_per_row():
    rows = _kind("Pi")
    n = np.array([float(r["n"]) for r in rows])
    m1 = np.array([float(r["m1"]) for r in rows])
    per = np.array([ell.ellippi(a, 1 - b, b) for a, b in zip(n, m1)], dtype=float)
    np.testing.assert_array_equal(ell.ellippi(n, 1 - m1, m1), per)
    np.testing.assert_array_equal(ell.ellipe(1 - m1, m1), [ell.ellipe(1 - b, b) for b in m1])


def test_quarter_period_double_double():
    """ellipk_dd: hi + lo within 1e-31 relative, from m1 = 2.2e-308 (and subnormal) to 1."""
    import mpmath as mp

    for r in REF["agm"]:
        m1 = float(r["m1"])
        hi, lo = ell.ellipk_dd(1 - m1, m1)
        with mp.workdps(50):
            err = abs(mp.mpf(float(hi)) + mp.mpf(float(lo)) - mp.mpf(r["K"])) / mp.mpf(r["K"])
        assert err < 1e-31 or (m1 < 2.2e-308 and err < 1e-20), (m1, err)
        s_hi, s_lo = dd.sqrt_float(np.float64(m1))
        with mp.workdps(50):
            assert abs(mp.mpf(float(s_hi)) + mp.mpf(float(s_lo)) - mp.mpf(r["sqrt"])) <= 1e-31 * mp.mpf(r["sqrt"])


# ---------------------------------------------------------------------------
# Incomplete integrals
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["F", "Einc"])
def test_incomplete_first_and_second_kind_within_1e_15(kind):
    """F(phi | m), E(phi | m) within 1e-15, through reduce_amplitude for |phi| > pi/2."""
    worst = 0.0
    for r in _kind(kind):
        m1, phi = float(r["m1"]), float(r["phi"])
        red, j = ell.reduce_amplitude(phi)
        if kind == "F":
            got = 2 * j * ell.ellipk(1 - m1, m1) + ell.ellipf_inc(red, 1 - m1, m1)
        else:
            got = 2 * j * ell.ellipe(1 - m1, m1) + ell.ellipe_inc(red, 1 - m1, m1)
        worst = max(worst, _rel(got, r["value"]))
    assert worst <= 1e-15, worst


def test_third_kind_within_3e_15_outside_the_rj_corner():
    worst, count = 0.0, 0
    for r in _kind("Pi_inc"):
        n, phi, m1 = float(r["n"]), float(r["phi"]), float(r["m1"])
        if _rj_corner(n, phi, m1):
            continue
        worst = max(worst, _rel(_pi_inc(n, phi, m1), r["value"]))
        count += 1
    assert count >= 250
    assert worst <= 3e-15, worst


def test_third_kind_in_the_rj_corner_within_2e_14():
    """The documented exception: SciPy's R_J loses up to ~100 eps for x << y << p << 1."""
    rows = [r for r in _kind("Pi_inc") if _rj_corner(float(r["n"]), float(r["phi"]), float(r["m1"]))]
    assert rows
    worst = max(_rel(_pi_inc(float(r["n"]), float(r["phi"]), float(r["m1"])), r["value"]) for r in rows)
    assert worst <= 2e-14, worst


def test_issue_row_near_the_pole_of_the_integrand():
    """n sin^2 phi -> 1: 84.6 eps when 1 - n sin^2 phi was formed directly; now a few eps."""
    n, phi, k = 0.9964613318443298, 1.5652378797531128, 0.9171178936958313
    m1 = float(1 - Fraction(k) ** 2)
    (row,) = [r for r in _kind("Pi_inc") if float(r["n"]) == n and float(r["phi"]) == phi and float(r["m1"]) == m1]
    assert _rel(ell.ellippi_inc(n, phi, 1 - m1, m1), row["value"]) <= 4 * EPS
    s, c = np.sin(phi), np.cos(phi)
    assert _rel(ell.pi_positive_scd(n, 1 - n, s, c, c * c + m1 * s * s), row["value"]) <= 4 * EPS


def test_pi_from_sine_cosine_within_3e_15():
    """pi_positive_scd (n > 0) and pi_negative_scd (n <= 0), the top's and the free body's forms."""
    worst = 0.0
    for r in _kind("Pi_inc"):
        n, phi, m1 = float(r["n"]), float(r["phi"]), float(r["m1"])
        if abs(phi) > 0.5 * np.pi or _rj_corner(n, phi, m1):
            continue
        s, c = np.sin(phi), np.cos(phi)
        d2 = c * c + m1 * s * s
        got = ell.pi_positive_scd(n, 1 - n, s, c, d2) if n > 0 else ell.pi_negative_scd(-n, s, c, d2, m1)
        worst = max(worst, _rel(got, r["value"]))
    assert worst <= 3e-15, worst


def test_reduce_amplitude_is_exact_to_an_ulp():
    for r in REF["reduce_amplitude"]:
        red, j = ell.reduce_amplitude(float(r["phi"]))
        want = float(r["r"])
        assert int(j) == r["j"]
        assert abs(float(red)) <= 0.5 * np.pi
        assert abs(float(red) - want) <= 0.5 * np.spacing(abs(want)) + 1e-300


@pytest.mark.parametrize(("m", "m1"), [(0.5, 0.5), (0.75, 0.25), (1 - 2.0**-30, 2.0**-30)])
def test_jacobi_keeps_its_digits_past_two_to_the_26_quarter_periods(m, m1):
    """sn, cn, dn to a few ulps relative (mpmath, 60 digits, reduced modulo 4K there) for u up to
    1e14, 6e13 quarter periods: past 2^26 of them q K is Dekker's exact product (was: 8e-7 off at
    u = 1e10, 7e-3 at 1e14), and reduce_amplitude likewise for phi up to 1e15."""
    import mpmath as mp

    u = 10.0 ** np.linspace(3, 14, 23)
    got = ell.jacobi(u, m, m1)
    with mp.workdps(60):
        k = mp.ellipk(mp.mpf(m))
        for i, ui in enumerate(u):
            r = mp.mpf(ui) - 4 * k * mp.nint(mp.mpf(ui) / (4 * k))
            for row, name in enumerate(("sn", "cn", "dn")):
                want = float(mp.ellipfun(name, r, m=mp.mpf(m)))
                assert abs(got[row][i] - want) <= 4 * np.spacing(abs(want)), (ui, name)
        phi = 10.0 ** np.linspace(3, 15, 25)
        red, j = ell.reduce_amplitude(phi)
        for p, ri, ji in zip(phi, red, j):
            jj = mp.nint(mp.mpf(p) / mp.pi)
            assert ji == float(jj) and abs(ri - float(mp.mpf(p) - jj * mp.pi)) <= np.spacing(np.pi)


def test_minus_multiple_against_exact_rationals():
    """x - j (hi + lo) by dd.minus_multiple, for j past 2^26, to a few ulps of hi (Fractions)."""
    rng = np.random.default_rng(3)
    hi, lo = dd.two_sum(np.pi, 1.2246467991473532e-16)
    for _ in range(200):
        j = float(rng.integers(2**26, 2**48))
        x = float(j * hi + rng.uniform(-0.5, 0.5) * hi)
        r, r_lo = dd.minus_multiple(x, j, hi, lo)
        exact = Fraction(x) - Fraction(j) * (Fraction(hi) + Fraction(lo))
        assert abs(Fraction(float(r)) + Fraction(float(r_lo)) - exact) <= 2 * Fraction(float(np.spacing(hi)))


# ---------------------------------------------------------------------------
# Jacobi functions
# ---------------------------------------------------------------------------
def _jacobi_rows():
    u = np.array([float(r["u"]) for r in JACOBI])
    m1 = np.array([float(r["m1"]) for r in JACOBI])
    want = np.array([[float(r[f]) for f in ("sn", "cn", "dn", "am")] for r in JACOBI])
    near = np.array([r["near_zero"] for r in JACOBI])
    return u, m1, want, near


U, M1, WANT, NEAR = _jacobi_rows()
PER_ROW = np.array([ell.jacobi(a, 1 - b, b) for a, b in zip(U, M1)], dtype=float)
AM_PER_ROW = np.array([ell.jacobi_am(a, 1 - b, b) for a, b in zip(U, M1)], dtype=float)


def test_jacobi_relative_accuracy_within_4_eps():
    """sn, cn, dn within 4 eps relative for m1 in [2.2e-308, 1] and |u| up to 2^25 K,
    next to the zeros of cn included (cn = sech x for m next to 1; sqrt(k') at K/2)."""
    far = ~NEAR
    assert far.sum() >= 300
    rel = np.abs(PER_ROW[far] - WANT[far, :3]) / np.abs(WANT[far, :3])
    assert rel.max() <= 4 * EPS, rel.max() / EPS


def test_jacobi_next_to_a_multiple_of_k_absolute():
    """u = float(q K): within 1e-30 |q| K absolute (the double-double K's floor)."""
    assert NEAR.sum() >= 20
    k = np.array([ell.ellipk(1 - b, b) for b in M1[NEAR]])
    q = np.maximum(np.abs(np.rint(U[NEAR] / k)), 1.0)
    err = np.abs(PER_ROW[NEAR] - WANT[NEAR, :3]).max(axis=1)
    assert np.all(err <= 1e-30 * q * k), (err / (q * k)).max()


def test_jacobi_amplitude_within_4_eps():
    rel = np.abs(AM_PER_ROW - WANT[:, 3]) / np.maximum(np.abs(WANT[:, 3]), 1e-300)
    assert rel[~NEAR].max() <= 4 * EPS
    # next to u = q K the amplitude is q pi/2 plus a tiny angle: relative to am, still tight
    assert rel[NEAR].max() <= 4 * EPS


def test_jacobi_vectorised_returns_the_per_row_floats():
    """One array call (one parameter per element, 2.2e-308 <= m1 <= 1) = one call per row."""
    got = np.array(ell.jacobi(U, 1 - M1, M1)).T
    np.testing.assert_array_equal(got, PER_ROW)
    np.testing.assert_array_equal(ell.jacobi_am(U, 1 - M1, M1), AM_PER_ROW)


@settings(max_examples=60)
@given(st.lists(st.tuples(st.floats(-300.0, 300.0), st.floats(-300.0, 0.0)), min_size=1, max_size=12))
def test_jacobi_vectorised_agrees_with_per_row(rows):
    """Property: any mix of parameters (m1 = 10^e) and arguments, vectorised = per row to 2 eps."""
    u = np.array([r[0] for r in rows])
    m1 = 10.0 ** np.array([r[1] for r in rows])
    got = np.array(ell.jacobi(u, 1 - m1, m1)).T
    per = np.array([ell.jacobi(a, 1 - b, b) for a, b in zip(u, m1)], dtype=float)
    scale = np.maximum(np.abs(per), 1e-300)
    assert np.all(np.abs(got - per) <= 2 * EPS * scale)


def test_landen_paths_absolute_accuracy():
    """jacobi_quarter (the flow map's) and jacobi_reduced after reduce_phase (the free body's and
    the heavy top's): within 4e-16 absolute; their relative accuracy of cn, dn is bounded by
    eps (2 + m1^(-1/4)) (the cosine of a rounded amplitude near pi/2, documented)."""
    worst_abs = 0.0
    for u, m1, want, near in zip(U, M1, WANT, NEAR):
        if m1 == 0:
            continue
        lv = ell.landen_levels(1 - m1, m1)
        k_hi, k_lo = (float(v) for v in ell.ellipk_dd(1 - m1, m1))
        x, q = ell.reduce_quarter_period(u, k_hi, k_lo)
        (sn, cn, dn), _ = ell.jacobi_quarter(q, x, lv)
        got = np.array([sn, cn, dn], dtype=float)
        worst_abs = max(worst_abs, np.abs(got - want[:3]).max())
        if not near:
            rel = np.abs(got[1:] - want[1:3]) / np.abs(want[1:3])
            assert rel.max() <= EPS * (2.0 + m1**-0.25), (u, m1, rel.max() / EPS)
        lv.K = np.asarray(k_hi)
        r, j = reduce_phase(np.asarray(u), (1.0, 0.0), (2 * k_hi, 2 * k_lo))
        sn, cn, dn = ell.jacobi_reduced(r, lv, k_lo)
        odd = np.floor(0.5 * j) != 0.5 * j
        got = np.array([-sn if odd else sn, -cn if odd else cn, dn], dtype=float)
        worst_abs = max(worst_abs, np.abs(got - want[:3]).max())
    assert worst_abs <= 4e-16, worst_abs


# ---------------------------------------------------------------------------
# Double-double arithmetic (exact rational ground truth)
# ---------------------------------------------------------------------------
finite = st.floats(min_value=-1e100, max_value=1e100, allow_nan=False).filter(lambda x: x == 0 or abs(x) > 1e-100)
positive = st.floats(min_value=1e-100, max_value=1e100)


def _dd(hi, lo):
    return Fraction(float(hi)) + Fraction(float(lo))


@given(finite, finite)
def test_error_free_sum_and_product(a, b):
    s, e = dd.two_sum(a, b)
    assert Fraction(s) + Fraction(e) == Fraction(a) + Fraction(b)
    p, e = dd.two_prod(a, b)
    assert Fraction(p) + Fraction(e) == Fraction(a) * Fraction(b)


@given(
    st.floats(min_value=2.0**990, max_value=1.7e308),
    st.floats(min_value=1e-300, max_value=1e-2),
    st.sampled_from([(1, 1), (1, -1), (-1, 1), (-1, -1)]),
)
def test_error_free_product_of_the_largest_doubles(a, b, signs):
    """Operands above 2^996, where Veltkamp's splitting constant times a overflows, are split
    scaled: the product stays exact, without warnings (a heavy top's phase over 1e305 s)."""
    a, b = signs[0] * a, signs[1] * b
    p, e = dd.two_prod(np.array([a, 1.0]), np.array([b, 1.0]))
    assert Fraction(float(p[0])) + Fraction(float(e[0])) == Fraction(a) * Fraction(b)
    p, e = dd.two_prod(a, b)  # NumPy scalars and Python floats take the same path
    assert Fraction(float(p)) + Fraction(float(e)) == Fraction(a) * Fraction(b)


@given(positive, positive, st.floats(-0.5, 0.5), st.floats(-0.5, 0.5))
def test_double_double_operations_to_1e_30(ah, bh, fa, fb):
    """add, add_same_sign, mul, div and sqrt of double-doubles within 1e-30 relative."""
    al = fa * float(np.spacing(ah))
    bl = fb * float(np.spacing(bh))
    a, b = _dd(ah, al), _dd(bh, bl)
    tol = Fraction(1, 10**30)
    for got, want in (
        (dd.add(ah, al, bh, bl), a + b),
        (dd.add_same_sign(ah, al, bh, bl), a + b),
        (dd.mul(ah, al, bh, bl), a * b),
        (dd.div(ah, al, bh, bl), a / b),
    ):
        assert abs(_dd(*got) - want) <= tol * abs(want)
    s = _dd(*dd.sqrt(ah, al))
    assert abs(s * s - a) <= 2 * tol * a


@given(positive, positive)
def test_accurate_addition_under_cancellation(a, b):
    """add (not add_same_sign) stays within 1e-30 of |a| + |b| when the operands cancel."""
    got = _dd(*dd.add(a, 0.0, -b, 0.0))
    assert abs(got - (Fraction(a) - Fraction(b))) <= Fraction(1, 10**30) * (Fraction(a) + Fraction(b))


@given(st.floats(-1e6, 1e6).filter(lambda v: v == 0 or abs(v) > 1e-280))
def test_split3_pieces(x):
    """p1 + p2 + p3 = hi + lo to 2^-104 |hi|, and j p1, j p2 exact for |j| < 2^26 (<= 27 bits)."""
    hi, lo = dd.two_sum(x, x * 1e-17)
    p1, p2, p3 = (float(p) for p in dd.split3(hi, lo))
    err = Fraction(p1) + Fraction(p2) + Fraction(p3) - (Fraction(hi) + Fraction(lo))
    assert abs(err) <= Fraction(abs(hi)) / 2**104
    for p in (p1, p2):
        if p != 0:
            mant = Fraction(p) / Fraction(2) ** int(np.floor(np.log2(abs(p))))
            assert (mant * 2**26).denominator == 1
