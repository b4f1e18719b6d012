"""Unit quaternions, scalar first ``(w, x, y, z)``, vectorised over leading axes.

Convention: ``q`` rotates vectors actively, ``v' = q v q*``; the product
``q1 * q2`` applies ``q2`` first, like the matrix product ``R(q1) R(q2)``.
A rotation and its negative are the same rotation; functions here never flip
the sign on their own, so a time series stays continuous. Plain float64, no units.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "multiply",
    "conjugate",
    "normalize",
    "rotate",
    "to_matrix",
    "from_matrix",
    "from_axis_angle",
    "to_axis_angle",
    "exp",
    "log",
    "shortest_arc",
    "identity",
]


def identity(shape=()) -> np.ndarray:
    """The identity rotation ``(1, 0, 0, 0)`` with leading ``shape``."""
    shape = (shape,) if isinstance(shape, int) else tuple(shape)
    q = np.zeros(shape + (4,))
    q[..., 0] = 1.0
    return q


def multiply(p, q) -> np.ndarray:
    """Hamilton product ``p * q`` (apply q, then p)."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    pw, px, py, pz = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    qw, qx, qy, qz = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    # Component by component into one output (moveaxis and stack cost more than the
    # arithmetic for the few members of a single trajectory).
    out = np.empty(p.shape if p.shape == q.shape else np.broadcast_shapes(p.shape, q.shape))
    out[..., 0] = pw * qw - px * qx - py * qy - pz * qz
    out[..., 1] = pw * qx + px * qw + py * qz - pz * qy
    out[..., 2] = pw * qy - px * qz + py * qw + pz * qx
    out[..., 3] = pw * qz + px * qy - py * qx + pz * qw
    return out


def conjugate(q) -> np.ndarray:
    """``q* = (w, -x, -y, -z)``, the inverse rotation of a unit quaternion."""
    q = np.array(q, dtype=float)
    q[..., 1:] *= -1.0
    return q


def normalize(q) -> np.ndarray:
    """``q / |q|``."""
    q = np.asarray(q, dtype=float)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def rotate(q, v) -> np.ndarray:
    """Rotate vectors ``v`` (..., 3) by unit quaternions ``q`` (..., 4): ``q v q*``.

    Uses ``v + 2 w (u x v) + 2 u x (u x v)`` with ``u = (x, y, z)``.
    """
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    w = q[..., :1]
    u = q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def to_matrix(q) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of unit quaternions."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def from_matrix(r) -> np.ndarray:
    """Unit quaternions (w >= 0) of rotation matrices (..., 3, 3).

    Shepperd's method: the largest of the four squared components is taken
    from the diagonal, the others from off-diagonal sums, so no branch loses
    accuracy (S. W. Shepperd, J. Guidance Control 1, 223 (1978)).
    """
    r = np.asarray(r, dtype=float)
    tr = np.trace(r, axis1=-2, axis2=-1)
    d = np.stack([tr, r[..., 0, 0], r[..., 1, 1], r[..., 2, 2]], axis=-1)
    k = np.argmax(d, axis=-1)
    sq = np.stack([1 + tr, 1 + 2 * r[..., 0, 0] - tr, 1 + 2 * r[..., 1, 1] - tr, 1 + 2 * r[..., 2, 2] - tr], axis=-1)
    big = np.sqrt(np.maximum(np.take_along_axis(sq, k[..., None], -1)[..., 0], 0.0)) * 0.5
    f = 0.25 / big
    a = (r[..., 2, 1] - r[..., 1, 2]) * f
    b = (r[..., 0, 2] - r[..., 2, 0]) * f
    c = (r[..., 1, 0] - r[..., 0, 1]) * f
    xy = (r[..., 0, 1] + r[..., 1, 0]) * f
    xz = (r[..., 0, 2] + r[..., 2, 0]) * f
    yz = (r[..., 1, 2] + r[..., 2, 1]) * f
    cand = np.stack(
        [
            np.stack([big, a, b, c], -1),
            np.stack([a, big, xy, xz], -1),
            np.stack([b, xy, big, yz], -1),
            np.stack([c, xz, yz, big], -1),
        ],
        axis=-2,
    )
    q = np.take_along_axis(cand, k[..., None, None], -2)[..., 0, :]
    return q * np.where(q[..., :1] < 0, -1.0, 1.0)


def from_axis_angle(axis, angle) -> np.ndarray:
    """``(cos(angle/2), sin(angle/2) n)`` for unit axes ``n`` (..., 3) and angles (rad)."""
    axis = np.asarray(axis, dtype=float)
    half = 0.5 * np.asarray(angle, dtype=float)[..., None]
    return np.concatenate([np.cos(half), np.sin(half) * axis], axis=-1)


def exp(v) -> np.ndarray:
    """Quaternion exponential of rotation vectors ``v`` (rad): rotation by |v| about v/|v|."""
    v = np.asarray(v, dtype=float)
    angle = np.linalg.norm(v, axis=-1, keepdims=True)
    # sin(a/2)/a stays accurate near 0 through np.sinc.
    half_sinc = 0.5 * np.sinc(angle / (2.0 * np.pi))
    return np.concatenate([np.cos(0.5 * angle), half_sinc * v], axis=-1)


def log(q) -> np.ndarray:
    """Rotation vectors (rad, |v| <= 2 pi) of unit quaternions; the inverse of :func:`exp`.

    ``angle = 2 atan2(|u|, w)`` keeps full accuracy at small and large angles.
    """
    q = np.asarray(q, dtype=float)
    u = q[..., 1:]
    s = np.linalg.norm(u, axis=-1, keepdims=True)
    w = q[..., :1]
    angle = 2.0 * np.arctan2(s, w)
    # Each branch divides only where it is selected: where s == 0 a unit
    # quaternion has |w| = 1, so neither division can overflow (w may be
    # subnormal where s > 0).
    has_axis = s > 0
    factor = np.where(has_axis, angle / np.where(has_axis, s, 1.0), 2.0 / np.where(has_axis, 1.0, w))
    return factor * u


def to_axis_angle(q):
    """``(axis, angle)`` of unit quaternions; the axis is (1, 0, 0) for the identity."""
    v = log(q)
    angle = np.linalg.norm(v, axis=-1)
    safe = np.where(angle > 0, angle, 1.0)[..., None]
    axis = np.where(angle[..., None] > 0, v / safe, np.array([1.0, 0.0, 0.0]))
    return axis, angle


def shortest_arc(a, b) -> np.ndarray:
    """The rotation by the smallest angle taking unit vector ``a`` to unit vector ``b``.

    ``normalize(1 + a.b, a x b)``; accurate while ``a.b > -1`` (undefined for
    opposite vectors).
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    w = 1.0 + np.sum(a * b, axis=-1, keepdims=True)
    return normalize(np.concatenate([w, np.cross(a, b)], axis=-1))
