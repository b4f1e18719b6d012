"""The rigid body as the engine and its torques see it: principal frame and small vector kernels (SI).

:class:`BodyModel` is the user's body (principal moments, principal axes in the user's
body frame); :class:`InternalFrame` is the frame every member is integrated in, its
principal axes sorted by increasing moment (a proper rotation P of the body frame,
``v_int = P v_body``), where the free motion has the form of :mod:`wobble.models.free`.
The vector kernels work component by component on (n, 3) arrays (cheaper than
``np.cross`` for few members) and, with the ``_one`` suffix, on tuples of Python floats
(a single trajectory pays NumPy's per-call cost at every stage otherwise).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wobble.numerics.floats import EPS
from wobble.errors import InputError
from wobble.models.principal_axes import proper_sort
from wobble.numerics import quaternion as quat

__all__ = [
    "BodyModel",
    "InternalFrame",
    "check_moments",
    "cross",
    "cross_one",
    "member_rows",
    "normalize",
    "qmul_one",
    "rotate",
    "rotate_one",
    "stack3",
    "take_rows",
    "to_body",
    "to_body_components",
]


# --------------------------------------------------------------------------
# Small vector kernels
# --------------------------------------------------------------------------
def cross(a, b):
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(a.shape if a.shape == b.shape else np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def normalize(q):
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))


def rotate(q, v, inverse=False):
    """R(q) v (or R(q)^T v): v + 2 w (u x v) + 2 u x (u x v), u the vector part (of q* if inverse)."""
    w = q[..., :1]
    u = -q[..., 1:] if inverse else q[..., 1:]
    t = 2.0 * cross(u, v)
    return v + w * t + cross(u, t)


def cross_one(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def rotate_one(q, v, inverse=False):
    """R(q) v (or R(q)^T v) in Python floats."""
    w = q[0]
    u = (-q[1], -q[2], -q[3]) if inverse else (q[1], q[2], q[3])
    t = cross_one(u, v)
    t = (2.0 * t[0], 2.0 * t[1], 2.0 * t[2])
    c = cross_one(u, t)
    return (v[0] + w * t[0] + c[0], v[1] + w * t[1] + c[1], v[2] + w * t[2] + c[2])


def qmul_one(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    )


def to_body_components(q, v0, v1, v2):
    """R(q)^T v component by component (q (n, 4); v components broadcastable to (n,))."""
    qw, ux, uy, uz = q[..., 0], -q[..., 1], -q[..., 2], -q[..., 3]
    tx = 2.0 * (uy * v2 - uz * v1)
    ty = 2.0 * (uz * v0 - ux * v2)
    tz = 2.0 * (ux * v1 - uy * v0)
    return (v0 + qw * tx + (uy * tz - uz * ty), v1 + qw * ty + (uz * tx - ux * tz), v2 + qw * tz + (ux * ty - uy * tx))


def stack3(a, b, c):
    out = np.empty(np.broadcast(a, b, c).shape + (3,))
    out[..., 0] = a
    out[..., 1] = b
    out[..., 2] = c
    return out


def to_body(q, v):
    """R(q)^T v: inertial vectors into the body frame."""
    return rotate(q, np.asarray(v, dtype=float), inverse=True)


def take_rows(a, idx):
    """Per-member parameter rows (leading axis N) or a shared row (leading axis 1)."""
    return a if a.shape[0] == 1 or idx is None else a[idx]


def member_rows(a, n, width, name):
    """As an (M, width) array with M in (1, n)."""
    arr = np.asarray(a, dtype=float)
    arr = arr.reshape((1, width)) if arr.shape == (width,) or (width == 1 and arr.ndim == 0) else arr
    if width == 1 and arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] != width or arr.shape[0] not in (1, n):
        raise InputError(name, arr.shape, f"shape ({width},) or ({n}, {width}) (one row per member)")
    if not np.all(np.isfinite(arr)):
        raise InputError(name, a, "finite values")
    return arr


@dataclass(frozen=True)
class BodyModel:
    """A rigid body for the engine: principal moments and principal axes (SI).

    Attributes
    ----------
    moments : numpy.ndarray, shape (3,) or (N, 3)
        Principal moments (kg m^2) about the reference point (the centre of
        mass, or the fixed pivot of a top).
    axes : numpy.ndarray, shape (3, 3) or (N, 3, 3)
        Row k is the principal axis of ``moments[k]`` in body-frame
        components (a proper rotation; identity when the body frame is the
        principal frame).
    mass : float or None
        kg; needed by :class:`UniformGravity` when it does not give its own.
    radius : float or None
        m, the body's outer (equatorial) radius when known (a catalogued planet): a
        perturber must stay outside it.
    """

    moments: np.ndarray
    axes: np.ndarray
    mass: float | None = None
    radius: float | None = None

    @classmethod
    def from_moments(cls, moments, mass=None) -> BodyModel:
        """Principal moments along the body axes 1, 2, 3 (kg m^2)."""
        m = np.asarray(moments, dtype=float)
        if m.shape[-1:] != (3,) or m.ndim > 2:
            raise InputError("moments", m.shape, "3 principal moments, or an (N, 3) array of them")
        check_moments(m)
        return cls(m, np.broadcast_to(np.eye(3), m.shape[:-1] + (3, 3)).copy(), mass)

    @classmethod
    def from_tensor(cls, tensor, mass=None) -> BodyModel:
        """An inertia tensor (kg m^2) in the body frame, (3, 3) or (N, 3, 3): diagonalised."""
        t = np.asarray(tensor, dtype=float)
        if t.shape[-2:] != (3, 3) or t.ndim > 3:
            raise InputError("tensor", t.shape, "a 3x3 inertia tensor, or an (N, 3, 3) array of them")
        if not np.all(np.isfinite(t)) or not np.allclose(t, np.swapaxes(t, -1, -2), rtol=1e-12, atol=0):
            raise InputError("tensor", t.tolist() if t.ndim == 2 else t.shape, "a finite, symmetric 3x3 tensor")
        vals, vecs = np.linalg.eigh(t)
        axes = np.swapaxes(vecs, -1, -2)  # rows = eigenvectors
        det = np.linalg.det(axes)
        axes[..., 2, :] *= np.sign(det)[..., None]  # proper rotation
        check_moments(vals)
        return cls(vals, axes, mass)

    @property
    def members(self) -> int:
        """1 for a single body, N for an (N, 3) ensemble of bodies."""
        return 1 if np.ndim(self.moments) == 1 else int(np.shape(self.moments)[0])


def check_moments(m):
    if not np.all(np.isfinite(m)) or np.any(m <= 0):
        raise InputError("moments", np.asarray(m).tolist(), "positive, finite principal moments (kg m2)")
    s = np.sort(m, axis=-1)
    if np.any(s[..., 0] + s[..., 1] < s[..., 2] * (1 - 8 * EPS)):
        raise InputError("moments", np.asarray(m).tolist(), "moments obeying the triangle inequality I1 + I2 >= I3")


@dataclass(frozen=True)
class InternalFrame:
    """The internal frame: principal axes sorted by increasing moment, per member."""

    moments: np.ndarray  # (M, 3) ascending
    P: np.ndarray  # (M, 3, 3), v_int = P v_body
    q_pt: np.ndarray  # (M, 4), quaternion of P^T: q_int = q_body * q_pt

    @classmethod
    def of(cls, body: BodyModel, n: int) -> InternalFrame:
        moments = body.moments.reshape(-1, 3)
        axes = body.axes.reshape(-1, 3, 3)
        if moments.shape[0] not in (1, n):
            raise InputError("moments", moments.shape, f"one body, or {n} bodies (one per member)")
        order, signs = proper_sort(moments)
        sorted_m = np.take_along_axis(moments, order, -1)
        P = signs[..., None] * np.take_along_axis(axes, order[..., None], axis=-2)
        return cls(sorted_m, P, quat.from_matrix(np.swapaxes(P, -1, -2)))

    def vec_in(self, v):
        return np.einsum("...ij,...j->...i", self.P, v)

    def vec_out(self, v):
        return np.einsum("...ji,...j->...i", self.P, v)

    def quat_in(self, q):
        return quat.multiply(q, self.q_pt)

    def quat_out(self, q):
        return quat.multiply(q, quat.conjugate(self.q_pt))
