"""The lockstep Nelder-Mead against SciPy's own, search by search (ground truth: scipy.optimize).

The functions are rational (only +, -, *, /), so their values at a point do not
depend on whether they are computed for one search or for many at once: every
search must end at SciPy's ``x`` and ``fun`` exactly.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize

from wobble.numerics.nelder_mead import minimize_nelder_mead

LOWER = np.array([-3.0, -30.0, -30.0])
UPPER = np.array([3.0, 30.0, 30.0])
OFFSETS = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])


def _family(kind, c):
    def f(x, k):
        x = np.atleast_2d(x)
        a, b, d = c[k, 0], c[k, 1], c[k, 2]
        u, v, w = x[:, 0] - a, x[:, 1] - b, x[:, 2] - d
        if kind == "bowl":  # the minimum inside the box
            return u * u + 3.0 * v * v + 0.5 * w * w + u * v
        if kind == "rosenbrock":  # a curved valley: many contractions and shrinks
            return 100.0 * (v - u * u) ** 2 + (1.0 - u) ** 2 + 0.01 * w * w
        if kind == "corner":  # the minimum outside the box: clipped points, a vertex on the bound
            return (x[:, 0] - 5.0) ** 2 + (x[:, 1] + 40.0) ** 2 + w * w
        if kind == "plateau":  # ties everywhere on one side (the sort's order matters)
            return np.where(u > 0, 1.0, u * u) + 0.0 * v + 0.0 * w
        raise AssertionError(kind)

    return f


def _scipy(f, simplex, xatol, fatol, maxfev, k):
    res = optimize.minimize(
        lambda v: float(f(v, np.array([k]))[0]),
        simplex[0],
        method="Nelder-Mead",
        bounds=list(zip(LOWER, UPPER)),
        options={"initial_simplex": simplex, "xatol": xatol, "fatol": fatol, "maxfev": maxfev},
    )
    return res.x, res.fun


@pytest.mark.parametrize("kind", ["bowl", "rosenbrock", "corner", "plateau"])
@pytest.mark.parametrize("maxfev", [2000, 150, 40])  # 150, 40: some or all reach the limit (handed to SciPy)
def test_each_search_ends_where_scipy_does(kind, maxfev):
    rng = np.random.default_rng(3)
    m = 25
    c = rng.normal(size=(m, 3))
    starts = np.column_stack([rng.uniform(-2.5, 2.4, m), rng.uniform(-20, 20, m), rng.uniform(-20, 20, m)])
    simplexes = starts[:, None, :] + OFFSETS[None]
    simplexes[0, 1, 0] = 3.2  # above the upper bound: SciPy reflects it into the box
    f = _family(kind, c)
    x, fun = minimize_nelder_mead(f, simplexes, LOWER, UPPER, xatol=1e-4, fatol=1e-6, maxfev=maxfev)
    for k in range(m):
        sx, sfun = _scipy(f, simplexes[k], 1e-4, 1e-6, maxfev, k)
        np.testing.assert_array_equal(x[k], sx)
        assert fun[k] == sfun


def test_a_start_outside_the_box_is_refused():
    f = _family("bowl", np.zeros((1, 3)))
    with pytest.raises(ValueError, match=r"^initial_simplex\[0, 0\] \(x0 of search 0\): got \[4\. .*; allowed: within"):
        minimize_nelder_mead(
            f, (np.array([4.0, 0, 0]) + OFFSETS)[None], LOWER, UPPER, xatol=1e-4, fatol=1e-6, maxfev=100
        )
