"""The batched bounded Brent against SciPy's own loop, problem by problem (ground truth: scipy.optimize).

The functions are rational (only +, -, *, /), so their values at a point do not
depend on whether they are computed for one problem or for many at once: every
problem must then end at SciPy's ``x`` and ``fun`` exactly, and after as many
function values.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize

from wobble.numerics.bounded_brent import minimize_bounded


def _family(kind: str, c: np.ndarray):
    """f(x, k) for problem k of a family (coefficients c[k]); vectorised over x and k."""

    def f(x, k):
        c0, c1, c2 = c[k, 0], c[k, 1], c[k, 2]
        d = x - c0
        if kind == "quadratic":
            return c1 * d * d + c2
        if kind == "quartic":  # two minima: Brent finds one of them, as SciPy does
            return d * d * (d - c1) * (d + c2) + 0.1 * d
        if kind == "lorentzian":  # a spectral line: the shape of the Fourier peaks searched
            return -1.0 / (1.0 + (d / (0.1 + abs(c1))) ** 2)
        if kind == "monotone":  # the minimum at a bound
            return c1 * x
        if kind == "flat":  # every value ties
            return 0.0 * x + c2
        raise AssertionError(kind)

    return f


def _scipy(f, k, lo, hi, xatol, maxiter):
    calls = []

    def one(x):
        calls.append(x)
        return float(f(np.array([x]), np.array([k]))[0])

    res = optimize.minimize_scalar(one, bounds=(lo, hi), method="bounded", options={"xatol": xatol, "maxiter": maxiter})
    return float(res.x), float(res.fun), len(calls)


@pytest.mark.parametrize("kind", ["quadratic", "quartic", "lorentzian", "monotone", "flat"])
def test_each_problem_ends_where_scipy_does(kind):
    rng = np.random.default_rng(7)
    m = 60
    c = rng.normal(size=(m, 3))
    lo = rng.uniform(-3.0, 0.0, m)
    hi = lo + rng.uniform(1e-6, 4.0, m)
    xatol = 10.0 ** rng.uniform(-12, -2, m)
    f = _family(kind, c)
    counts = np.zeros(m, dtype=int)

    def batched(x, k):
        counts[k] += 1
        return f(x, k)

    x, fun = minimize_bounded(batched, lo, hi, xatol)
    for k in range(m):
        sx, sfun, scalls = _scipy(f, k, lo[k], hi[k], xatol[k], 500)
        assert (x[k], fun[k], counts[k]) == (sx, sfun, scalls), k


def test_maxiter_stops_every_problem_as_scipy_does():
    c = np.array([[0.3, 1.0, 0.0], [-0.2, 2.0, 1.0]])
    f = _family("lorentzian", c)
    x, fun = minimize_bounded(f, [-1.0, -1.0], [1.0, 1.0], 1e-14, maxiter=5)
    for k in range(2):
        assert (x[k], fun[k]) == _scipy(f, k, -1.0, 1.0, 1e-14, 5)[:2]


@settings(max_examples=40, deadline=None)
@given(
    centre=st.floats(-10, 10),
    width=st.floats(1e-9, 1e3),
    lo=st.floats(-20, 20),
    length=st.floats(0, 50),
    log_tol=st.floats(-14, 0),
)
def test_one_problem_is_scipy(centre, width, lo, length, log_tol):
    c = np.array([[centre, width, 0.0]])
    f = _family("lorentzian", c)
    x, fun = minimize_bounded(f, [lo], [lo + length], 10.0**log_tol)
    assert (x[0], fun[0]) == _scipy(f, 0, lo, lo + length, 10.0**log_tol, 500)[:2]


def test_bad_bounds_are_refused_naming_the_problem_and_its_bounds():
    with pytest.raises(ValueError, match=r"^bounds of problem 1: got \(1.0, 0.0\); allowed: finite, lower <= upper$"):
        minimize_bounded(lambda x, k: x, [0.0, 1.0], [1.0, 0.0], 1e-5)
    with pytest.raises(ValueError, match=r"^bounds of problem 0: got \(0.0, inf\)"):
        minimize_bounded(lambda x, k: x, [0.0], [np.inf], 1e-5)
