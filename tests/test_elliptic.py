"""Jacobi functions and elliptic integrals against mpmath (tests/references/free_rotation.json).

The reference values were computed by mpmath at 40 digits from the very same
float inputs (u, and m1 = 1 - m as the exact parameter complement); see
tests/references/build_free_references.py.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.special as sp

from wobble.numerics import elliptic as ell

REF = json.loads((Path(__file__).parent / "references" / "free_rotation.json").read_text())
ROWS = REF["elliptic"]
INTEGRALS = REF["integrals"]


def _rows(pred):
    return [r for r in ROWS if pred(float(r["m1"]))]


def _evaluate(rows):
    m1 = np.array([float(r["m1"]) for r in rows])
    u = np.array([float(r["u"]) for r in rows])
    got = np.array([ell.jacobi(ui, 1.0 - mi, mi) for ui, mi in zip(u, m1)])
    want = np.array([[float(r[k]) for k in ("sn", "cn", "dn")] for r in rows])
    return m1, u, got, want


@pytest.mark.parametrize("m1", sorted({float(r["m1"]) for r in ROWS}))
def test_jacobi_absolute_accuracy_all_parameters(m1):
    """sn, cn, dn within 2e-15 absolute for every u on the grid, up to 1e6 K."""
    _, u, got, want = _evaluate(_rows(lambda x: x == m1))
    assert np.max(np.abs(got - want)) < 2e-15


def test_jacobi_near_unit_parameter_beyond_quarter_period():
    """m1 = 1e-12 ... 1e-16 and u > K: where scipy.special.ellipj fails (scipy #8480)."""
    rows = _rows(lambda x: 0 < x <= 1e-12)
    m1, u, got, want = _evaluate(rows)
    K = ell.ellipk(1.0 - m1, m1)
    beyond = u > K
    assert beyond.sum() >= 20
    assert np.max(np.abs(got[beyond] - want[beyond])) < 2e-15
    # Relative accuracy of cn and dn, which are of size sqrt(m1) near odd multiples of K.
    rel = np.abs(got[beyond, 1:] - want[beyond, 1:]) / np.abs(want[beyond, 1:])
    assert np.max(rel) < 1e-11
    # The point of the exercise: scipy with the same float m is wrong there.
    sc = np.array(sp.ellipj(u[beyond], 1.0 - m1[beyond])[:3]).T
    bad = ~np.isfinite(sc) | (np.abs(sc - want[beyond]) > 1e-3)
    assert bad.any()


def test_jacobi_relative_accuracy_inside_the_quarter_period():
    """For |u| < K, cn and dn keep relative accuracy (quarter-period folding)."""
    m1, u, got, want = _evaluate(_rows(lambda x: x < 1))
    K = ell.ellipk(1.0 - m1, m1)
    inside = (u < 0.999 * K) | ((u > K) & (u < 1.999 * K))
    rel = np.abs(got[inside, 1:] - want[inside, 1:]) / np.abs(want[inside, 1:])
    assert np.max(rel) < 5e-12


def test_jacobi_small_parameter_reduces_to_circular_functions():
    u = np.linspace(-50, 50, 1001)
    sn, cn, dn = ell.jacobi(u, 0.0, 1.0)
    np.testing.assert_allclose(sn, np.sin(u), atol=4e-15)
    np.testing.assert_allclose(cn, np.cos(u), atol=4e-15)
    assert np.all(dn == 1.0)


def test_jacobi_unit_parameter_is_hyperbolic():
    u = np.linspace(-30, 30, 601)
    sn, cn, dn = ell.jacobi(u, 1.0, 0.0)
    np.testing.assert_allclose(sn, np.tanh(u), atol=1e-16)
    np.testing.assert_allclose(cn, 1 / np.cosh(u), rtol=1e-15)
    np.testing.assert_allclose(dn, 1 / np.cosh(u), rtol=1e-15)


def test_jacobi_vectorised_over_parameter_arrays():
    m1 = np.array([1e-16, 1e-8, 0.3, 0.9])
    u = np.array([40.0, 11.0, 1.0, 2.0])
    got = np.array(ell.jacobi(u, 1 - m1, m1))
    one_by_one = np.array([ell.jacobi(ui, 1 - mi, mi) for ui, mi in zip(u, m1)]).T
    np.testing.assert_allclose(got, one_by_one, atol=1e-15)


def test_amplitude_is_continuous_and_matches_sn_cn():
    u = np.linspace(0, 200, 4001)
    am = ell.jacobi_am(u, 1 - 1e-12, 1e-12)
    sn, cn, _ = ell.jacobi(u, 1 - 1e-12, 1e-12)
    assert np.all(np.diff(am) > 0)
    np.testing.assert_allclose(np.sin(am), sn, atol=2e-15)
    np.testing.assert_allclose(np.cos(am), cn, atol=2e-15)


def _integral(kind):
    return [r for r in INTEGRALS if r["kind"] == kind]


def test_complete_integrals():
    for r in _integral("K"):
        m1 = float(r["m1"])
        want = float(r["value"]) if r["value"].strip() not in ("+inf", "inf") else np.inf
        got = ell.ellipk(1 - m1, m1)
        assert got == want if np.isinf(want) else abs(got / want - 1) < 4e-16
    for r in _integral("E"):
        m1 = float(r["m1"])
        assert abs(ell.ellipe(1 - m1, m1) / float(r["value"]) - 1) < 8e-16


@pytest.mark.parametrize("kind", ["F", "Einc"])
def test_incomplete_first_and_second_kind(kind):
    fn = ell.ellipf_inc if kind == "F" else ell.ellipe_inc
    for r in _integral(kind):
        m1, phi = float(r["m1"]), float(r["phi"])
        assert abs(fn(phi, 1 - m1, m1) / float(r["value"]) - 1) < 1e-15, r


def test_third_kind_negative_and_positive_characteristic():
    worst = 0.0
    for r in _integral("Pi"):
        m1, phi, n = float(r["m1"]), float(r["phi"]), float(r["n"])
        got = ell.ellippi_inc(n, phi, 1 - m1, m1)
        worst = max(worst, abs(got / float(r["value"]) - 1))
    assert worst < 3e-15


def test_bad_parameters_raise():
    with pytest.raises(ValueError):
        ell.jacobi(1.0, 1.5, -0.5)
    with pytest.raises(ValueError):
        ell.ellippi_inc(1.5, 0.3, 0.5)
    with pytest.raises(ValueError):
        ell.ellipf_inc(2.0, 0.5)
