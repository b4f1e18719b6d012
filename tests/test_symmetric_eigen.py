"""Eigen-decomposition of symmetric 3x3 matrices (wobble.numerics.symmetric_eigen).

Eigenvalues and eigenvectors against mpmath.eigsy at 50 digits
(tests/references/numerics_kernels.json, "eigen", built by
tests/references/build_numerics_references.py), then the frame's promises as properties:
orthonormal, right-handed, A = V^T diag(lambda) V, invariant under rotations and under
scaling by powers of two, and stable where eigenvalues (nearly) coincide.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from wobble.numerics.symmetric_eigen import canonical_frame, degenerate_pairs, symmetric_eigen3

REF = json.loads((Path(__file__).parent / "references" / "numerics_kernels.json").read_text())
EPS = np.finfo(float).eps


def _rotation(angles):
    """Proper rotation from three angles (z-y-z)."""
    a, b, c = angles

    def rz(t):
        return np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])

    def ry(t):
        return np.array([[np.cos(t), 0.0, np.sin(t)], [0.0, 1.0, 0.0], [-np.sin(t), 0.0, np.cos(t)]])

    return rz(a) @ ry(b) @ rz(c)


def _check_frame(axes):
    np.testing.assert_allclose(axes @ axes.T, np.eye(3), atol=4 * EPS)
    assert abs(np.linalg.det(axes) - 1.0) <= 4 * EPS


@pytest.mark.parametrize("row", REF["eigen"], ids=[r["name"] for r in REF["eigen"]])
def test_against_mpmath(row):
    """Eigenvalues within 8 eps max|lambda|; eigenvectors within 1e-14 (up to sign), frame proper."""
    a = np.array([[float(v) for v in r] for r in row["matrix"]])
    values, axes = symmetric_eigen3(a, rtol=1e-12)
    want = np.array([float(v) for v in row["values"]])
    scale = np.max(np.abs(want))
    assert np.max(np.abs(values - want)) <= 8 * EPS * scale
    vectors = np.array([[float(v) for v in r] for r in row["vectors"]])
    for got, ref in zip(axes, vectors):
        assert abs(abs(got @ ref) - 1.0) <= 1e-14
    _check_frame(axes)
    # axes 1 and 3: largest component positive (the canonical sign rule)
    for k in (0, 2):
        assert axes[k][np.argmax(np.abs(axes[k]))] > 0


def test_diagonal_matrix_is_exact():
    values, axes = symmetric_eigen3(np.diag([3.0, 1e-300, -2.0]), rtol=1e-12)
    assert list(values) == [-2.0, 1e-300, 3.0]
    _check_frame(axes)
    assert np.all(np.abs(axes) @ np.ones(3) == 1.0)  # a permutation (signed)


def test_zero_and_isotropic_matrices():
    values, axes = symmetric_eigen3(np.zeros((3, 3)), rtol=1e-12)
    assert np.all(values == 0) and np.all(axes == np.eye(3))
    r = _rotation((0.3, 1.1, -0.4))
    values, axes = symmetric_eigen3(r @ (2.5 * np.eye(3)) @ r.T, rtol=1e-12)
    np.testing.assert_allclose(values, 2.5, rtol=4 * EPS)
    assert np.all(axes == np.eye(3))  # all three coincide: the input frame


def test_degenerate_pair_frame_is_stable():
    """A symmetric top's two equal moments: the frame does not jump under a one-ulp change."""
    r = _rotation((0.7, 0.4, 1.9))
    a = r @ np.diag([1.0, 1.0, 3.0]) @ r.T
    _, axes = symmetric_eigen3(a, rtol=1e-12)
    b = a.copy()
    b[0, 1] = b[1, 0] = np.nextafter(a[0, 1], np.inf)
    b[2, 2] = np.nextafter(a[2, 2], -np.inf)
    _, axes_b = symmetric_eigen3(b, rtol=1e-12)
    np.testing.assert_allclose(axes_b, axes, atol=1e-14)
    # the unique axis is R e_z (up to sign), the pair spans its orthogonal plane
    assert abs(abs(axes[2] @ r[:, 2]) - 1) <= 1e-14
    assert degenerate_pairs(np.subtract.outer([1.0, 1.0, 3.0], [1.0, 1.0, 3.0]), np.array([1.0, 1.0, 3.0]), 1e-12) == (
        True,
        False,
    )


def test_canonical_frame_of_a_given_basis():
    vectors = -np.eye(3)[[2, 0, 1]]  # a signed, permuted basis of three distinct values
    values = np.array([1.0, 2.0, 3.0])
    frame = canonical_frame(values, vectors, np.subtract.outer(values, values), 1e-12)
    _check_frame(frame)
    assert frame[0] @ np.array([0.0, 0.0, 1.0]) == 1.0 and frame[2] @ np.array([0.0, 1.0, 0.0]) == 1.0


symmetric = arrays(np.float64, (3, 3), elements=st.floats(-1.0, 1.0)).map(lambda m: m + m.T)
angles = st.tuples(st.floats(-np.pi, np.pi), st.floats(0.0, np.pi), st.floats(-np.pi, np.pi))


@settings(max_examples=80)
@given(symmetric, st.integers(-300, 300))
def test_frame_is_orthonormal_and_reconstructs_the_matrix(a, exponent):
    a = np.ldexp(a, exponent)
    values, axes = symmetric_eigen3(a, rtol=1e-12)
    _check_frame(axes)
    assert np.all(np.diff(values) >= 0)
    norm = np.max(np.abs(a))
    np.testing.assert_allclose(axes.T @ np.diag(values) @ axes, a, atol=16 * EPS * norm + 1e-300)


@settings(max_examples=80)
@given(symmetric, st.integers(-60, 60))
def test_scaling_by_a_power_of_two_is_exact(a, exponent):
    values, axes = symmetric_eigen3(a, rtol=1e-12)
    values2, axes2 = symmetric_eigen3(np.ldexp(a, exponent), rtol=1e-12)
    np.testing.assert_array_equal(values2, np.ldexp(values, exponent))
    np.testing.assert_array_equal(axes2, axes)


@settings(max_examples=80)
@given(symmetric, angles)
def test_rotation_invariance(a, ang):
    """Eigenvalues of R A R^T are those of A; well-separated axes rotate with R (up to sign)."""
    r = _rotation(ang)
    values, axes = symmetric_eigen3(a, rtol=1e-12)
    values_r, axes_r = symmetric_eigen3(r @ a @ r.T, rtol=1e-12)
    norm = max(np.max(np.abs(a)), 1e-300)
    np.testing.assert_allclose(values_r, values, atol=32 * EPS * norm)
    gaps = np.diff(values)
    for k in range(3):
        neighbours = [gaps[k - 1]] if k == 2 else ([gaps[0]] if k == 0 else list(gaps))
        gap = min(neighbours)
        if gap > 1e-3 * norm:  # eigenvector conditioning ~ eps |A| / gap
            assert abs(abs(axes_r[k] @ (r @ axes[k])) - 1) <= 1e-10
