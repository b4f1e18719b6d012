"""Unit quaternions: algebraic identities (exact ground truth) and round trips."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from wobble.numerics import quaternion as Q

finite = st.floats(-10, 10, allow_nan=False)
vec3 = arrays(float, 3, elements=finite)


def _unit(v):
    q = np.asarray(v, dtype=float)
    n = np.linalg.norm(q)
    return q / n if n > 1e-3 else np.array([1.0, 0.0, 0.0, 0.0])


quats = arrays(float, 4, elements=finite).map(_unit)


def test_rotation_about_z_by_quarter_turn():
    q = Q.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2)
    np.testing.assert_allclose(Q.rotate(q, [1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(Q.to_matrix(q), [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_identity_shape():
    assert Q.identity().tolist() == [1.0, 0.0, 0.0, 0.0]
    assert Q.identity(5).shape == (5, 4)


@given(quats, quats, vec3)
def test_product_composes_rotations(p, q, v):
    np.testing.assert_allclose(Q.rotate(Q.multiply(p, q), v), Q.rotate(p, Q.rotate(q, v)), atol=1e-12)
    np.testing.assert_allclose(Q.to_matrix(Q.multiply(p, q)), Q.to_matrix(p) @ Q.to_matrix(q), atol=1e-13)


@given(quats)
def test_matrix_round_trip_and_orthogonality(q):
    r = Q.to_matrix(q)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
    assert np.isclose(np.linalg.det(r), 1.0, atol=1e-14)
    back = Q.from_matrix(r)
    assert min(np.linalg.norm(back - q), np.linalg.norm(back + q)) < 1e-14


@given(quats)
def test_exp_log_round_trip(q):
    back = Q.exp(Q.log(q))
    assert min(np.linalg.norm(back - q), np.linalg.norm(back + q)) < 1e-14
    axis, angle = Q.to_axis_angle(q)
    again = Q.from_axis_angle(axis, angle)
    assert min(np.linalg.norm(again - q), np.linalg.norm(again + q)) < 1e-14


@given(quats, vec3)
def test_conjugate_inverts(q, v):
    np.testing.assert_allclose(Q.rotate(Q.conjugate(q), Q.rotate(q, v)), v, atol=1e-12)


@given(vec3, vec3)
def test_shortest_arc_maps_a_to_b(a, b):
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    if na < 1e-3 or nb < 1e-3 or np.dot(a, b) / (na * nb) < -0.99:
        return
    a, b = a / na, b / nb
    np.testing.assert_allclose(Q.rotate(Q.shortest_arc(a, b), a), b, atol=1e-12)


def test_vectorised_over_leading_axes():
    rng = np.random.default_rng(1)
    q = Q.normalize(rng.normal(size=(4, 5, 4)))
    v = rng.normal(size=(4, 5, 3))
    assert Q.rotate(q, v).shape == (4, 5, 3)
    np.testing.assert_allclose(np.linalg.norm(Q.rotate(q, v), axis=-1), np.linalg.norm(v, axis=-1), rtol=1e-14)
