"""Reference rigid-body equations written out for the tests, independent of wobble (NumPy only).

Conventions as wobble's: omega in the body frame, the unit quaternion (w, x, y, z) turns body vectors into
inertial ones, q' = q (x) (0, omega) / 2 (notes, "Euler's equations"; Goldstein, Poole & Safko 2002, sec. 4.9).
"""

from __future__ import annotations

import numpy as np


def quaternion_product(a, b):
    """Hamilton's product a (x) b of quaternions (w, x, y, z) on the last axis."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    aw, av = a[..., :1], a[..., 1:]
    bw, bv = b[..., :1], b[..., 1:]
    w = aw * bw - np.sum(av * bv, axis=-1, keepdims=True)
    v = aw * bv + bw * av + np.cross(av, bv)
    return np.concatenate([w, v], axis=-1)


def attitude_angle(q1, q2):
    """The rotation angle (rad) between unit quaternions, either sign of each: 2 atan2(|v|, |w|) of q1 (x) q2*."""
    conj = np.asarray(q2, dtype=float) * np.array([1.0, -1.0, -1.0, -1.0])
    d = quaternion_product(q1, conj)
    return 2 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def to_body(q, v):
    """An inertial vector ``v`` in the body frame of the attitude ``q`` (body -> inertial): q* (x) (0, v) (x) q."""
    conj = np.asarray(q, dtype=float) * np.array([1.0, -1.0, -1.0, -1.0])
    return quaternion_product(quaternion_product(conj, np.concatenate([[0.0], v])), q)[1:]


def euler_quaternion_rhs(moments, torque=None):
    """Right-hand side f(t, y) of Euler's equations with the quaternion kinematics, y = (omega, q).

    ``moments`` are the principal moments (kg m2) on the body axes; ``torque(t, omega, q)`` (N m, body frame)
    is optional. I1 w1' = (I2 - I3) w2 w3 + tau1 and cyclically; q' = q (x) (0, omega) / 2. Plain arithmetic
    on the elements, so that mpmath numbers pass through (mpmath.odefun) as well as floats.
    """
    i1, i2, i3 = moments

    def f(t, y):
        w1, w2, w3, a, b, c, d = y
        t1, t2, t3 = (0 * w1, 0 * w2, 0 * w3) if torque is None else torque(t, (w1, w2, w3), (a, b, c, d))
        return [
            ((i2 - i3) * w2 * w3 + t1) / i1,
            ((i3 - i1) * w3 * w1 + t2) / i2,
            ((i1 - i2) * w1 * w2 + t3) / i3,
            (-b * w1 - c * w2 - d * w3) / 2,
            (a * w1 + c * w3 - d * w2) / 2,
            (a * w2 - b * w3 + d * w1) / 2,
            (a * w3 + b * w2 - c * w1) / 2,
        ]

    return f
