"""Euler's equations with torques, for one body or an ensemble (SI float64).

Course notes section 5.5: in the body (principal-axis) frame

    tau = dL/dt + omega x L,   L = I omega,
    I_1 domega_1/dt = tau_1 + (I_2 - I_3) omega_2 omega_3   (and cyclic),

with the attitude a unit quaternion q (scalar first) rotating body vectors
into the inertial frame, ``dq/dt = q * (0, omega) / 2``.

State and frames
----------------
The user describes the body in a *body frame* of their choice: principal
moments along its axes, or an inertia tensor in it (the principal axes are
then found by diagonalisation). Initial states (omega0 in the body frame,
q0 body -> inertial), torque parameters given in the body frame and all
outputs are in that frame. Internally every member is integrated in its
*principal frame sorted by increasing moment* (a proper rotation P of the
body frame: ``v_int = P v_body``), where the free motion has the form of
:mod:`wobble.models.free`.

Torques (all vectorised over members; parameters may be per member)
-------------------------------------------------------------------
:class:`ConstantTorque`
    Fixed vector in the body or the inertial frame.
:class:`UniformGravity`
    ``tau = r x (m R^T g)`` about a fixed pivot, ``r`` the centre of mass
    from the pivot in the body frame (notes section 5.7, any body);
    potential ``V = -m g . (R r)``.
:class:`GravityGradient`
    A distant point mass GM at distance d in direction ``rho`` (unit,
    inertial; fixed, or turning uniformly on a circular orbit):
    ``tau = (3 GM / d^3) rho_b x (I rho_b)``, the torque behind the
    precession of the equinoxes and the gravity-gradient attitude
    dynamics of satellites (MacCullagh's formula; potential
    ``V = (3 GM / 2 d^3) rho_b . I rho_b`` up to a constant).
:class:`LinearDamping`
    ``tau = -c omega`` (c per body axis).
:class:`CustomTorque`
    Any callable ``f(t, omega, q) -> tau`` (body or inertial frame).

Integration
-----------
``method="dop853"``: Dormand & Prince 8(5,3) on ``(omega, q)`` (quaternion
renormalised after each step), compiled (:mod:`wobble.numerics.rigid_dop853`,
every built-in torque, ~200 ns per evaluation, ensembles on all CPUs) or, with
a custom torque, in NumPy (:class:`wobble.numerics.integrators.DOP853`); the
two are the same method, step for step (``backend=``).
``method="splitting"``: Touma & Wisdom (1994): exact free flow
(:func:`wobble.models.free.flow_sorted`) between torque kicks; the kick
``domega/dt = I^-1 (tau(t, q) - D omega)`` at fixed attitude and time is
solved exactly (torques that depend on omega other than linear damping are
refused: their kick has no exact solution). Orders 2, 4, 6.

Each run can carry a companion run (looser tolerance, or twice the step)
whose difference from the main run is the global error estimate reported
(:class:`ErrorEstimate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from wobble.errors import InputError
from wobble.models.free import flow_one, flow_sorted, proper_sort
from wobble.numerics import compiled as compiled_kernels
from wobble.numerics import quaternion as quat
from wobble.numerics.integrators import DOP853, Splitting, StepLimitError

__all__ = [
    "BodyModel",
    "ConstantTorque",
    "UniformGravity",
    "GravityGradient",
    "LinearDamping",
    "CustomTorque",
    "Engine",
    "ErrorEstimate",
    "Trajectory",
    "simulate",
    "METHODS",
    "STANDARD_GRAVITY",
]

METHODS = ("dop853", "splitting")
BACKENDS = ("auto", "compiled", "python")
#: Each omega component's error is measured against its largest value, or against this
#: fraction of |omega| if it stays smaller (float64 cannot resolve a component that is
#: zero up to rounding relative to itself).
COMPONENT_FLOOR = 1e-6
STANDARD_GRAVITY = 9.80665  # m s^-2 (CGPM 1901, exact)
_EPS = np.finfo(float).eps


# --------------------------------------------------------------------------
# Small vector kernels (component-wise: cheaper than np.cross for few members)
# --------------------------------------------------------------------------
def _cross(a, b):
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(a.shape if a.shape == b.shape else np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _normalize(q):
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))


def _rotate(q, v, inverse=False):
    """R(q) v (or R(q)^T v): v + 2 w (u x v) + 2 u x (u x v), u the vector part (of q* if inverse)."""
    w = q[..., :1]
    u = -q[..., 1:] if inverse else q[..., 1:]
    t = 2.0 * _cross(u, v)
    return v + w * t + _cross(u, t)


def _cross_one(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _rotate_one(q, v, inverse=False):
    """R(q) v (or R(q)^T v) in Python floats."""
    w = q[0]
    u = (-q[1], -q[2], -q[3]) if inverse else (q[1], q[2], q[3])
    t = _cross_one(u, v)
    t = (2.0 * t[0], 2.0 * t[1], 2.0 * t[2])
    c = _cross_one(u, t)
    return (v[0] + w * t[0] + c[0], v[1] + w * t[1] + c[1], v[2] + w * t[2] + c[2])


def _qmul_one(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    )


def _to_body_components(q, v0, v1, v2):
    """R(q)^T v component by component (q (n, 4); v components broadcastable to (n,))."""
    qw, ux, uy, uz = q[..., 0], -q[..., 1], -q[..., 2], -q[..., 3]
    tx = 2.0 * (uy * v2 - uz * v1)
    ty = 2.0 * (uz * v0 - ux * v2)
    tz = 2.0 * (ux * v1 - uy * v0)
    return (v0 + qw * tx + (uy * tz - uz * ty), v1 + qw * ty + (uz * tx - ux * tz), v2 + qw * tz + (ux * ty - uy * tx))


def _stack3(a, b, c):
    out = np.empty(np.broadcast(a, b, c).shape + (3,))
    out[..., 0] = a
    out[..., 1] = b
    out[..., 2] = c
    return out


def _to_body(q, v):
    """R(q)^T v: inertial vectors into the body frame."""
    return _rotate(q, np.asarray(v, dtype=float), inverse=True)


def _take(a, idx):
    """Per-member parameter rows (leading axis N) or a shared row (leading axis 1)."""
    return a if a.shape[0] == 1 or idx is None else a[idx]


def _members(a, n, width, name):
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


# --------------------------------------------------------------------------
# The body
# --------------------------------------------------------------------------
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
    """

    moments: np.ndarray
    axes: np.ndarray
    mass: float | None = None

    @classmethod
    def from_moments(cls, moments, mass=None) -> BodyModel:
        """Principal moments along the body axes 1, 2, 3 (kg m^2)."""
        m = np.asarray(moments, dtype=float)
        if m.shape[-1:] != (3,) or m.ndim > 2:
            raise InputError("moments", m.shape, "3 principal moments, or an (N, 3) array of them")
        _check_moments(m)
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
        _check_moments(vals)
        return cls(vals, axes, mass)

    @property
    def members(self) -> int:
        """1 for a single body, N for an (N, 3) ensemble of bodies."""
        return 1 if np.ndim(self.moments) == 1 else int(np.shape(self.moments)[0])


def _check_moments(m):
    if not np.all(np.isfinite(m)) or np.any(m <= 0):
        raise InputError("moments", np.asarray(m).tolist(), "positive, finite principal moments (kg m2)")
    s = np.sort(m, axis=-1)
    if np.any(s[..., 0] + s[..., 1] < s[..., 2] * (1 - 8 * _EPS)):
        raise InputError("moments", np.asarray(m).tolist(), "moments obeying the triangle inequality I1 + I2 >= I3")


@dataclass(frozen=True)
class _Frame:
    """The internal frame: principal axes sorted by increasing moment, per member."""

    moments: np.ndarray  # (M, 3) ascending
    P: np.ndarray  # (M, 3, 3), v_int = P v_body
    q_pt: np.ndarray  # (M, 4), quaternion of P^T: q_int = q_body * q_pt

    @classmethod
    def of(cls, body: BodyModel, n: int) -> _Frame:
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


# --------------------------------------------------------------------------
# Torques: user-facing specifications (body frame, SI) bound to the internal frame
# --------------------------------------------------------------------------
class _Bound:
    uses_omega = False
    uses_attitude = True
    time_dependent = False
    conservative = False
    damping = None  # (M, 3) diagonal damping in the internal frame
    # (kind, arrays) for the compiled integrator (wobble.numerics.rigid_dop853), None if
    # the torque has no compiled form (a custom torque)
    program = None

    def torque(self, t, w, q, idx):  # pragma: no cover - interface
        raise NotImplementedError

    def potential(self, t, q, idx):  # pragma: no cover - interface
        raise NotImplementedError


@dataclass(frozen=True)
class ConstantTorque:
    """A constant torque (N m), fixed in the body frame or in the inertial frame.

    ``torque`` has shape (3,) or (N, 3). A body-frame torque on a sphere
    gives ``omega(t) = omega0 + tau t / I`` (tested).
    """

    torque: np.ndarray
    frame: str = "body"
    kind = "constant"

    def bind(self, frame: _Frame, n: int) -> _Bound:
        if self.frame not in ("body", "inertial"):
            raise InputError("frame", self.frame, "'body' or 'inertial'")
        tau = _members(self.torque, n, 3, "torque")
        b = _Bound()
        if self.frame == "body":
            tau_int = frame.vec_in(tau)
            b.uses_attitude = False
            b.torque = lambda t, w, q, idx: np.broadcast_to(_take(tau_int, idx), w.shape)
            one = tuple(float(x) for x in tau_int[0])
            b.torque_one = lambda t, w, q: one
            b.program = ("body", tau_int)
        else:
            b.torque = lambda t, w, q, idx: _to_body(q, _take(tau, idx))
            one = tuple(float(x) for x in tau[0])
            b.torque_one = lambda t, w, q: _rotate_one(q, one, inverse=True)
            b.program = ("inertial", tau)
        return b


@dataclass(frozen=True)
class UniformGravity:
    """Gravity about a fixed pivot (the heavy top, notes section 5.7; any body).

    Attributes
    ----------
    mass : float or array (N,)
        kg.
    center_of_mass : array (3,) or (N, 3)
        Centre of mass from the pivot in the body frame (m); the moments of
        the body must be about the pivot.
    gravity : array (3,)
        Acceleration of gravity in the inertial frame (m s^-2); default
        ``(0, 0, -9.80665)``.
    """

    mass: float
    center_of_mass: np.ndarray
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -STANDARD_GRAVITY]))
    kind = "gravity"

    def bind(self, frame: _Frame, n: int) -> _Bound:
        mass = _members(self.mass, n, 1, "mass")
        if np.any(mass <= 0):
            raise InputError("mass", self.mass, "a positive mass (kg)")
        r = frame.vec_in(_members(self.center_of_mass, n, 3, "center_of_mass"))
        g = _members(self.gravity, n, 3, "gravity")
        mg = mass * g
        b = _Bound()
        b.conservative = True
        shared = r.shape[0] == 1 and mg.shape[0] == 1
        r_s, mg_s = r[0], mg[0]

        def torque(t, w, q, idx):
            if not shared:
                return _cross(_take(r, idx), _to_body(q, _take(mg, idx)))
            g0, g1, g2 = _to_body_components(q, mg_s[0], mg_s[1], mg_s[2])
            return _stack3(r_s[1] * g2 - r_s[2] * g1, r_s[2] * g0 - r_s[0] * g2, r_s[0] * g1 - r_s[1] * g0)

        b.torque = torque
        b.potential = lambda t, q, idx: -np.sum(_take(mg, idx) * _rotate(q, _take(r, idx)), axis=-1)
        b.mgl = mass[:, 0] * np.linalg.norm(g, axis=-1) * np.linalg.norm(r, axis=-1)
        r1 = tuple(float(x) for x in r[0])
        mg1 = tuple(float(x) for x in mg[0])
        b.torque_one = lambda t, w, q: _cross_one(r1, _rotate_one(q, mg1, inverse=True))
        b.program = ("gravity", r, mg)
        return b


@dataclass(frozen=True)
class GravityGradient:
    """The tidal torque of a distant point mass (MacCullagh): satellites, equinox precession.

    Attributes
    ----------
    gm : float
        Gravitational parameter of the attracting mass (m^3 s^-2).
    distance : float
        Distance between the centres (m), much larger than the body.
    direction : array (3,) or None
        Fixed unit vector towards the mass, inertial frame.
    orbit_normal : array (3,) or None
        Instead of ``direction``: the direction turns on a circular orbit
        about this inertial axis, ``rho(t) = cos(n t + phase) e1 + sin(n t + phase) e2``
        with e1 the inertial x axis projected on the orbit plane (y if the
        normal is along x) and ``e2 = normal x e1``.
    phase : float
        rad, at t = 0.
    mean_motion : float or None
        n (rad/s); default ``sqrt(gm / distance^3)`` (a satellite's orbit;
        give the relative orbit's n for a planet around the Sun).
    """

    gm: float
    distance: float
    direction: np.ndarray | None = None
    orbit_normal: np.ndarray | None = None
    phase: float = 0.0
    mean_motion: float | None = None
    kind = "gravity_gradient"

    def unit_vectors(self):
        """(e1, e2) of the orbit plane (or (direction, None) for a fixed direction)."""
        if (self.direction is None) == (self.orbit_normal is None):
            raise InputError("direction, orbit_normal", (self.direction, self.orbit_normal), "exactly one of them")
        if self.direction is not None:
            d = np.asarray(self.direction, dtype=float)
            if d.shape != (3,) or not np.linalg.norm(d) > 0:
                raise InputError("direction", self.direction, "a non-zero 3-vector (inertial frame)")
            return d / np.linalg.norm(d), None
        nrm = np.asarray(self.orbit_normal, dtype=float)
        if nrm.shape != (3,) or not np.linalg.norm(nrm) > 0:
            raise InputError("orbit_normal", self.orbit_normal, "a non-zero 3-vector (inertial frame)")
        nrm = nrm / np.linalg.norm(nrm)
        ref = np.array([1.0, 0.0, 0.0]) if abs(nrm[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = ref - np.dot(ref, nrm) * nrm
        e1 /= np.linalg.norm(e1)
        return e1, np.cross(nrm, e1)

    def rate(self) -> float:
        """The mean motion n (rad/s) of the direction (0 for a fixed direction)."""
        if self.orbit_normal is None:
            return 0.0
        return float(self.mean_motion) if self.mean_motion is not None else float(np.sqrt(self.gm / self.distance**3))

    def bind(self, frame: _Frame, n: int) -> _Bound:
        if not (np.isfinite(self.gm) and self.gm > 0):
            raise InputError("gm", self.gm, "a positive gravitational parameter (m3 s-2)")
        if not (np.isfinite(self.distance) and self.distance > 0):
            raise InputError("distance", self.distance, "a positive distance (m)")
        e1, e2 = self.unit_vectors()
        k = 3.0 * self.gm / self.distance**3
        moments = frame.moments
        rate = self.rate()
        phase = float(self.phase)

        def rho(t):
            if e2 is None:
                return e1
            ang = rate * np.asarray(t, dtype=float) + phase
            return np.cos(ang)[..., None] * e1 + np.sin(ang)[..., None] * e2

        b = _Bound()
        b.time_dependent = e2 is not None
        b.conservative = e2 is None

        def torque(t, w, q, idx):
            if e2 is None:
                v0, v1, v2 = e1[0], e1[1], e1[2]
            else:
                ang = rate * np.asarray(t, dtype=float) + phase
                c, s_ = np.cos(ang), np.sin(ang)
                v0, v1, v2 = c * e1[0] + s_ * e2[0], c * e1[1] + s_ * e2[1], c * e1[2] + s_ * e2[2]
            r0, r1, r2 = _to_body_components(q, v0, v1, v2)
            m = _take(moments, idx)
            # rho x I rho = ((I3 - I2) r1 r2, (I1 - I3) r2 r0, (I2 - I1) r0 r1)
            return _stack3(
                k * (m[:, 2] - m[:, 1]) * r1 * r2, k * (m[:, 0] - m[:, 2]) * r2 * r0, k * (m[:, 1] - m[:, 0]) * r0 * r1
            )

        def potential(t, q, idx):
            rb = _to_body(q, rho(t))
            return 0.5 * k * np.sum(rb * _take(moments, idx) * rb, axis=-1)

        b.torque = torque
        b.potential = potential
        b.stiffness = k * (moments[:, 2] - moments[:, 0])
        m1 = tuple(float(x) for x in moments[0])
        e1t = tuple(float(x) for x in e1)
        e2t = None if e2 is None else tuple(float(x) for x in e2)

        def torque_one(t, w, q):
            if e2t is None:
                rho1 = e1t
            else:
                ang = rate * float(t) + phase
                c, s_ = math.cos(ang), math.sin(ang)
                rho1 = (c * e1t[0] + s_ * e2t[0], c * e1t[1] + s_ * e2t[1], c * e1t[2] + s_ * e2t[2])
            rb = _rotate_one(q, rho1, inverse=True)
            tq = _cross_one(rb, (m1[0] * rb[0], m1[1] * rb[1], m1[2] * rb[2]))
            return (k * tq[0], k * tq[1], k * tq[2])

        b.torque_one = torque_one
        moving = e2 is not None
        b.program = ("gradient", np.concatenate([
            [k], e1, e2 if moving else np.zeros(3), [rate if moving else 0.0, phase if moving else 0.0]
        ]))
        return b


@dataclass(frozen=True)
class LinearDamping:
    """``tau = -c omega`` with c (N m s) a scalar or one value per body axis.

    Per-axis values need a body frame along principal axes (a diagonal
    damping in the principal frame), so that the splitting's kick is exact.
    """

    coefficient: np.ndarray | float
    kind = "damping"

    def bind(self, frame: _Frame, n: int) -> _Bound:
        c = np.asarray(self.coefficient, dtype=float)
        if c.ndim == 0 or (c.ndim == 1 and c.shape[0] != 3):
            c = c[..., None] * np.ones(3)  # one coefficient (per member): isotropic
        c3 = _members(c, n, 3, "coefficient")
        rows = max(c3.shape[0], frame.P.shape[0])
        P = np.broadcast_to(frame.P, (rows, 3, 3))
        mat = np.einsum("mij,mj,mkj->mik", P, np.broadcast_to(c3, (rows, 3)), P)
        diag = np.diagonal(mat, axis1=-2, axis2=-1).copy()
        off = mat - diag[..., None] * np.eye(3)
        if np.any(np.abs(off) > 1e-12 * np.max(np.abs(diag), initial=0.0)):
            raise InputError("coefficient", self.coefficient, "one value, or per-axis values along principal axes")
        b = _Bound()
        b.uses_omega = True
        b.uses_attitude = False
        b.damping = diag
        b.torque = lambda t, w, q, idx: -_take(diag, idx) * w
        b.program = ("damping", diag)
        return b


@dataclass(frozen=True)
class CustomTorque:
    """A torque from your own function, vectorised over members.

    ``function(t, omega, q)`` receives times ``t`` (n,), body-frame angular
    velocities ``omega`` (n, 3) in rad/s and attitudes ``q`` (n, 4) (body to
    inertial), and returns torques (n, 3) in N m in ``frame``. Say whether
    it depends on omega (``uses_omega``): only torques that do not can be
    integrated by the splitting.
    """

    function: Callable
    frame: str = "body"
    uses_omega: bool = True
    uses_attitude: bool = True
    name: str = "custom"
    kind = "custom"

    def bind(self, frame: _Frame, n: int) -> _Bound:
        if self.frame not in ("body", "inertial"):
            raise InputError("frame", self.frame, "'body' or 'inertial'")
        if not callable(self.function):
            raise InputError("function", self.function, "a callable f(t, omega, q) -> torque (N m)")
        fn, inertial = self.function, self.frame == "inertial"
        b = _Bound()
        b.uses_omega = bool(self.uses_omega)
        b.uses_attitude = bool(self.uses_attitude) or inertial
        b.time_dependent = True

        def torque(t, w, q, idx):
            P = _take(frame.P, idx)
            qpt = _take(frame.q_pt, idx)
            w_body = np.einsum("...ji,...j->...i", P, w)
            q_body = quat.multiply(q, quat.conjugate(qpt)) if q is not None else None
            tt = np.broadcast_to(np.asarray(t, dtype=float), w.shape[:-1])
            tau = np.asarray(fn(tt, w_body, q_body), dtype=float)
            if tau.shape != w.shape:
                raise InputError(self.name, tau.shape, f"a custom torque returning shape {w.shape} (N m)")
            if inertial:
                return _to_body(q, tau)
            return np.einsum("...ij,...j->...i", P, tau)

        b.torque = torque
        return b


# --------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------
@dataclass
class ErrorEstimate:
    """Global error estimate of a run, per member.

    Attributes
    ----------
    omega_relative : numpy.ndarray (N,)
        max over time and components of ``|omega_i - omega_i,ref| / max_t |omega_i|``:
        each component relative to its own largest value (a planet's wobble
        components relative to the wobble, not to the spin), or to
        ``COMPONENT_FLOOR * max_t |omega|`` for a component that stays smaller.
    attitude : numpy.ndarray (N,)
        max over time of the rotation angle between the attitudes (rad).
    method : str
        How it was obtained.
    """

    omega_relative: np.ndarray
    attitude: np.ndarray
    method: str

    @property
    def worst(self) -> float:
        """The largest of both estimates over all members."""
        return float(max(np.max(self.omega_relative, initial=0.0), np.max(self.attitude, initial=0.0)))


@dataclass
class Trajectory:
    """Angular velocity and attitude at the output times, body frame (SI).

    Attributes
    ----------
    t : numpy.ndarray (T,)
    omega : numpy.ndarray (T, N, 3)
        rad/s, body frame.
    attitude : numpy.ndarray (T, N, 4) or None
        Unit quaternions body -> inertial.
    error : ErrorEstimate or None
    stats : dict
        Steps, function evaluations, settings.
    """

    t: np.ndarray
    omega: np.ndarray
    attitude: np.ndarray | None
    error: ErrorEstimate | None
    stats: dict


def attitude_angle(q1, q2):
    """Rotation angle (rad) between unit quaternions, sign-blind."""
    d = quat.multiply(q1, quat.conjugate(q2))
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


class _Accumulator:
    """Running maxima for the global error estimate (companion comparison)."""

    def __init__(self, n, factor):
        self.diff = np.zeros((n, 3))
        self.size = np.zeros((n, 3))
        self.angle = np.zeros(n)
        self.factor = factor

    def add(self, w, wc, q, qc):
        self.diff = np.maximum(self.diff, np.max(np.abs(w - wc), axis=0))
        self.size = np.maximum(self.size, np.max(np.abs(w), axis=0))
        if q is not None:
            self.angle = np.maximum(self.angle, np.max(attitude_angle(q, qc), axis=0))

    def result(self, method):
        floor = COMPONENT_FLOOR * np.max(self.size, axis=-1, keepdims=True)
        scale = np.maximum(self.size, floor)
        with np.errstate(invalid="ignore", divide="ignore"):
            rel = np.where(scale > 0, self.diff / scale, 0.0)
        return ErrorEstimate(self.factor * np.max(rel, axis=-1), self.factor * self.angle, method)


# --------------------------------------------------------------------------
# The engine
# --------------------------------------------------------------------------
class Engine:
    """Euler's equations with torques for N members (SI).

    Parameters
    ----------
    body : BodyModel
        One body, or N bodies (moments (N, 3)).
    torques : sequence
        Torque specifications (:class:`ConstantTorque`, ...).
    members : int
        N, the number of initial states that will be integrated.
    """

    def __init__(self, body: BodyModel, torques=(), members: int = 1):
        self.n = int(members)
        self.body = body
        self.frame = _Frame.of(body, self.n)
        self.specs = tuple(torques)
        self.torques = [t.bind(self.frame, self.n) for t in self.specs]
        self.moments = self.frame.moments  # (M, 3) ascending
        self.damping = None
        for b in self.torques:
            if b.damping is not None:
                self.damping = b.damping if self.damping is None else self.damping + b.damping
        self.kicked = [b for b in self.torques if b.damping is None]
        self._scalar = (
            self.n == 1
            and self.moments.shape[0] == 1
            and all(hasattr(b, "torque_one") or b.damping is not None for b in self.torques)
        )
        self._program = None
        self._moments_one = tuple(float(x) for x in self.moments[0])
        self._damping_one = None if self.damping is None else tuple(float(x) for x in np.reshape(self.damping, (-1, 3))[0])

    # -- what the torques need ---------------------------------------------------
    @property
    def needs_attitude(self) -> bool:
        """Whether any torque depends on the attitude (else omega evolves on its own)."""
        return any(b.uses_attitude for b in self.torques)

    @property
    def splittable(self) -> bool:
        """Whether every kick has an exact solution (no omega dependence but linear damping)."""
        return all((not b.uses_omega) or b.damping is not None for b in self.torques)

    @property
    def conservative(self) -> bool:
        """Whether every torque has a time-independent potential (energy is conserved)."""
        return all(b.conservative for b in self.torques)

    # -- states in and out -------------------------------------------------------
    def state_in(self, omega0, q0):
        """(omega, q) from the body frame into the internal frame, shapes (N, 3), (N, 4)."""
        w = np.broadcast_to(np.asarray(omega0, dtype=float), (self.n, 3))
        q = np.broadcast_to(np.asarray(q0, dtype=float), (self.n, 4))
        return self.frame.vec_in(w), quat.normalize(self.frame.quat_in(q))

    def state_out(self, w, q):
        """Back to the body frame (any leading shape ending in N)."""
        wo = self.frame.vec_out(w)
        qo = None if q is None else self.frame.quat_out(q)
        return wo, qo

    # -- physics in the internal frame -------------------------------------------
    def torque(self, t, w, q, idx=None):
        """Total torque (internal frame), shape of w."""
        if not self.torques:
            return np.zeros_like(w)
        tau = self.torques[0].torque(t, w, q, idx)
        for b in self.torques[1:]:
            tau = tau + b.torque(t, w, q, idx)
        return tau

    def rhs(self, t, y, idx=None):
        """d(omega, q)/dt for states ``y`` (n, 7) (or (n, 3) when no torque needs q)."""
        if self._scalar and y.shape[0] == 1:
            return self._rhs_one(float(t[0]) if np.ndim(t) else float(t), y)
        w = y[:, :3]
        q = y[:, 3:7] if y.shape[1] == 7 else None
        I = _take(self.moments, idx)  # noqa: E741
        tau = self.torque(t, w, q, idx)
        w0, w1, w2 = w[:, 0], w[:, 1], w[:, 2]
        i0, i1, i2 = I[:, 0], I[:, 1], I[:, 2]
        out = np.empty(y.shape)
        # (I w) x w = ((I2 - I3) w2 w3, (I3 - I1) w3 w1, (I1 - I2) w1 w2): Euler's equations, notes 5.5
        out[:, 0] = (tau[:, 0] + (i1 - i2) * w1 * w2) / i0
        out[:, 1] = (tau[:, 1] + (i2 - i0) * w2 * w0) / i1
        out[:, 2] = (tau[:, 2] + (i0 - i1) * w0 * w1) / i2
        if q is None:
            return out
        qw, qx, qy, qz = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
        out[:, 3] = -0.5 * (qx * w0 + qy * w1 + qz * w2)
        out[:, 4] = 0.5 * (qw * w0 + qy * w2 - qz * w1)
        out[:, 5] = 0.5 * (qw * w1 - qx * w2 + qz * w0)
        out[:, 6] = 0.5 * (qw * w2 + qx * w1 - qy * w0)
        return out

    def kick(self, state, t, h):
        """Exact flow of ``I domega/dt = tau(t, q) - D omega`` at frozen t and q over h."""
        w, q = state
        if not self.torques or h == 0:
            return state
        tau = 0.0
        for b in self.kicked:
            tau = tau + b.torque(t, w, q, None)
        I = self.moments  # noqa: E741
        if self.damping is None:
            return w + (h / I) * tau, q
        x = self.damping * h / I
        with np.errstate(divide="ignore", invalid="ignore"):
            phi1 = np.where(x == 0, 1.0, -np.expm1(-x) / np.where(x == 0, 1.0, x))
        return w + (h / I) * (tau - self.damping * w) * phi1, q

    def drift(self, state, t, h):
        """Exact free flow over h (Touma & Wisdom's drift)."""
        w, q = state
        I = np.broadcast_to(self.moments, w.shape)  # noqa: E741
        w1, dq = flow_sorted(I, w, np.full(w.shape[0], h), attitude=q is not None)
        if q is None:
            return w1, None
        return w1, _normalize(quat.multiply(q, dq))

    # -- one member in Python floats (NumPy's per-call cost dominates a single trajectory)
    @property
    def scalar(self) -> bool:
        """Whether a single member can run in Python floats (every torque has a scalar form)."""
        return self._scalar

    def _rhs_one(self, t, y):
        """:meth:`rhs` for one member in Python floats."""
        row = y[0].tolist()
        w = (row[0], row[1], row[2])
        q = (row[3], row[4], row[5], row[6]) if len(row) == 7 else None
        tx = ty = tz = 0.0
        for b in self.kicked:
            a = b.torque_one(t, w, q)
            tx, ty, tz = tx + a[0], ty + a[1], tz + a[2]
        i0, i1, i2 = self._moments_one
        if self._damping_one is not None:
            d0, d1, d2 = self._damping_one
            tx, ty, tz = tx - d0 * w[0], ty - d1 * w[1], tz - d2 * w[2]
        w0, w1, w2 = w
        out = [
            (tx + (i1 - i2) * w1 * w2) / i0,
            (ty + (i2 - i0) * w2 * w0) / i1,
            (tz + (i0 - i1) * w0 * w1) / i2,
        ]
        if q is not None:
            qw, qx, qy, qz = q
            out += [
                -0.5 * (qx * w0 + qy * w1 + qz * w2),
                0.5 * (qw * w0 + qy * w2 - qz * w1),
                0.5 * (qw * w1 - qx * w2 + qz * w0),
                0.5 * (qw * w2 + qx * w1 - qy * w0),
            ]
        return np.array([out])

    def kick_one(self, state, t, h):
        """:meth:`kick` for one member, tuples in and out."""
        w, q = state
        if not self.torques or h == 0:
            return state
        tx = ty = tz = 0.0
        for b in self.kicked:
            a = b.torque_one(t, w, q)
            tx, ty, tz = tx + a[0], ty + a[1], tz + a[2]
        I = self._moments_one  # noqa: E741
        if self.damping is None:
            return (w[0] + h * tx / I[0], w[1] + h * ty / I[1], w[2] + h * tz / I[2]), q
        out = []
        for wi, ti, ii, di in zip(w, (tx, ty, tz), I, self._damping_one):
            x = di * h / ii
            phi1 = 1.0 if x == 0 else -math.expm1(-x) / x
            out.append(wi + (h / ii) * (ti - di * wi) * phi1)
        return tuple(out), q

    def drift_one(self, state, t, h):
        """:meth:`drift` for one member, tuples in and out."""
        w, q = state
        w1, dq = flow_one(self._moments_one, w, h, q is not None)
        if q is None:
            return w1, None
        q1 = _qmul_one(q, dq)
        n = 1.0 / math.sqrt(q1[0] * q1[0] + q1[1] * q1[1] + q1[2] * q1[2] + q1[3] * q1[3])
        return w1, (q1[0] * n, q1[1] * n, q1[2] * n, q1[3] * n)

    # -- the compiled integrator ---------------------------------------------------
    @property
    def compilable(self) -> bool:
        """Whether every torque has a compiled form (all built-in kinds; not a custom torque)."""
        return all(b.program is not None for b in self.torques)

    def program(self) -> tuple:
        """The torque program of :mod:`wobble.numerics.rigid_dop853` (internal frame, float64; built once)."""
        if self._program is None:
            self._program = self._pack_program()
        return self._program

    def _pack_program(self) -> tuple:
        if not self.compilable:
            raise InputError("torques", [s.kind for s in self.specs], "built-in torques only for the compiled backend")

        def summed(kind):
            rows = [b.program[1] for b in self.torques if b.program[0] == kind]
            return sum(rows[1:], rows[0]) if rows else np.zeros((1, 3))

        grav = [b.program[1:] for b in self.torques if b.program[0] == "gravity"]
        rows = max([1] + [max(r.shape[0], mg.shape[0]) for r, mg in grav])
        grav_r = np.array([np.broadcast_to(r, (rows, 3)) for r, _ in grav]).reshape(-1, rows, 3)
        grav_mg = np.array([np.broadcast_to(mg, (rows, 3)) for _, mg in grav]).reshape(-1, rows, 3)
        gg = np.array([b.program[1] for b in self.torques if b.program[0] == "gradient"]).reshape(-1, 9)
        damp = self.damping if self.damping is not None else np.zeros((0, 3))
        parts = (self.moments, summed("body"), summed("inertial"), grav_r, grav_mg, gg, damp)
        return tuple(np.ascontiguousarray(a, dtype=float) for a in parts)

    def energy(self, t, w, q):
        """Kinetic + potential energy (J) in the internal frame; potential only where defined."""
        T = 0.5 * np.sum(self.moments * w * w, axis=-1)
        V = np.zeros_like(T)
        for b in self.torques:
            if b.conservative:
                V = V + b.potential(t, q, None)
        return T + V

    # -- rates used to choose steps ----------------------------------------------
    def torque_rate(self, omega0, q0, t0=0.0) -> float:
        """A rate (1/s) characterising how fast the torques change the motion.

        ``sqrt(k / I_min) + |tau| / |L|`` over members: ``k`` the stiffness
        of the torque against a small rotation (numerical, 1e-4 rad about
        each axis) and ``|tau| / |L|`` the rate at which it turns L. Zero
        without torques. Used for the splitting's first step guess only.
        """
        if not self.torques:
            return 0.0
        w, q = self.state_in(omega0, q0)
        tau = self.torque(t0, w, q)
        stiff = np.zeros(self.n)
        if self.needs_attitude:
            for axis in np.eye(3):
                dq = quat.from_axis_angle(axis, 1e-4)
                tau2 = self.torque(t0, w, quat.multiply(q, dq))
                stiff = np.maximum(stiff, np.linalg.norm(tau2 - tau, axis=-1) / 1e-4)
        imin = np.min(self.moments, axis=-1)
        big_l = np.linalg.norm(self.moments * w, axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.where(big_l > 0, np.linalg.norm(tau, axis=-1) / big_l, np.sqrt(np.linalg.norm(tau, axis=-1) / imin))
        damp = 0.0 if self.damping is None else np.max(self.damping / self.moments)
        return float(np.max(np.sqrt(stiff / imin) + turn) + damp)

    # -- integration ---------------------------------------------------------------
    def propagator(self, omega0, q0, t0, *, method, rtol=None, step=None, order=6, attitude=True, multiple=1,
                   backend="auto"):
        """A propagator with ``advance(t_out) -> (omega, q)`` in the body frame."""
        need_q = attitude or self.needs_attitude
        w, q = self.state_in(omega0, q0)
        if backend not in BACKENDS:
            raise InputError("backend", backend, f"one of {', '.join(BACKENDS)}")
        if method == "dop853":
            if rtol is None:
                raise InputError("rtol", rtol, "a relative tolerance for dop853")
            if backend == "compiled" and not self.compilable:
                raise InputError("backend", backend, "'auto' or 'python' with a custom torque (it has no compiled form)")
            compiled = backend == "compiled" or (backend == "auto" and self.compilable and compiled_kernels.available())
            return _RKPropagator(self, w, q if need_q else None, t0, float(rtol), attitude, compiled)
        if method == "splitting":
            if not self.splittable:
                raise InputError(
                    "method", "splitting", "dop853 for torques that depend on omega (other than linear damping)"
                )
            if step is None:
                raise InputError("step", step, "a step (s) for the splitting")
            return _SplitPropagator(self, w, q if need_q else None, t0, float(step), int(order), attitude, multiple)
        raise InputError("method", method, f"one of {', '.join(METHODS)}")

    def integrate(self, omega0, q0, t, *, method="dop853", rtol=1e-10, step=None, order=6, attitude=True, estimate=True,
                  backend="auto"):
        """Integrate N members to the output times ``t`` (s), with a global error estimate.

        Parameters
        ----------
        omega0 : array (3,) or (N, 3)
            rad/s, body frame.
        q0 : array (4,) or (N, 4)
            Unit quaternions body -> inertial.
        t : array (T,)
            Increasing output times (s); integration starts at ``t[0]``.
        method : {"dop853", "splitting"}
        rtol : float
            DOP853's relative tolerance.
        step : float
            The splitting's step (s).
        order : {2, 4, 6}
            The splitting's order.
        attitude : bool
            Whether to return the attitude.
        estimate : bool
            Run the companion (DOP853 at 10 rtol; splitting at twice the
            step, the main run then taking an even number of steps in each
            output interval) and report their difference (divided by
            2^order - 1 for the splitting, Richardson) as :class:`ErrorEstimate`.
        backend : {"auto", "compiled", "python"}
            DOP853 only: the compiled integrator (:mod:`wobble.numerics.rigid_dop853`,
            the same method, every built-in torque) or the NumPy one (any torque,
            :class:`wobble.numerics.integrators.DOP853`). "auto" compiles unless a
            custom torque is present. The splitting always runs in Python.

        Returns
        -------
        Trajectory
        """
        t = np.asarray(t, dtype=float).reshape(-1)
        split_multiple = 2 if (estimate and method == "splitting") else 1
        prop = self.propagator(
            omega0, q0, t[0], method=method, rtol=rtol, step=step, order=order, attitude=attitude, multiple=split_multiple,
            backend=backend,
        )
        comp = None
        if estimate:
            comp = self.propagator(
                omega0, q0, t[0], method=method,
                rtol=None if rtol is None else min(10 * rtol, 1e-3),
                step=None if step is None else 2 * step, order=order, attitude=attitude, backend=backend,
            )
        acc = _Accumulator(self.n, 1.0 if method == "dop853" else 1.0 / (2**order - 1))
        w, q = prop.advance(t)
        if comp is not None:
            wc, qc = comp.advance(t)
            acc.add(w, wc, q, qc)
        err = acc.result(_estimate_name(method, order)) if comp is not None else None
        return Trajectory(t, w, q, err, prop.stats())


def _estimate_name(method, order):
    if method == "dop853":
        return "difference from a companion run at 10 times the tolerance (an upper bound)"
    return f"Richardson: difference from a companion run at twice the step, / (2^{order} - 1)"


class _RKPropagator:
    def __init__(self, engine: Engine, w, q, t0, rtol, attitude, compiled=False):
        self.engine = engine
        self.attitude = attitude
        y0 = w if q is None else np.concatenate([w, q], axis=1)
        scale_w = np.max(np.abs(w), axis=-1)
        # The scale of omega: the spin, or what the torque reaches in a second from rest.
        # Components below COMPONENT_FLOOR of it are controlled at that level, never
        # below rounding (32 eps): a component that is zero up to rounding must not
        # drive the step to nothing.
        tau0 = np.linalg.norm(engine.torque(t0, w, q), axis=-1) / np.min(engine.moments, axis=-1)
        char = np.maximum(np.maximum(scale_w, tau0), 1e-300)
        atol = np.empty_like(y0)
        atol[:, :3] = ((rtol * COMPONENT_FLOOR + 32 * _EPS) * char)[:, None]
        if q is not None:
            atol[:, 3:] = rtol

        def project(y):
            if y.shape[1] == 7:
                y = y.copy()
                y[:, 3:] = quat.normalize(y[:, 3:])
            return y

        self.rtol = rtol
        self.backend = "compiled" if compiled else "python"
        if compiled:
            from wobble.numerics.rigid_dop853 import RigidDOP853

            self.solver = RigidDOP853(engine.program(), t0, y0, rtol=rtol, atol=atol)
        else:
            self.solver = DOP853(engine.rhs, t0, y0, rtol=rtol, atol=atol, project=project)

    def advance(self, t_out):
        try:
            y = self.solver.advance(t_out)
        except StepLimitError as exc:
            raise InputError("accuracy", self.rtol, f"a tolerance the adaptive integrator can meet ({exc})") from None
        w = y[..., :3]
        q = y[..., 3:] if y.shape[-1] == 7 else None
        wo, qo = self.engine.state_out(w, q)
        return wo, (qo if self.attitude else None)

    def stats(self):
        s = self.solver
        return {
            "method": "dop853",
            "backend": self.backend,
            "rtol": self.rtol,
            "steps": int(s.n_steps.sum()),
            "steps_max_member": int(s.n_steps.max()),
            "rejected": int(s.n_rejected.sum()),
            "function_evaluations": int(s.nfev),
        }


class _SplitPropagator:
    def __init__(self, engine: Engine, w, q, t0, step, order, attitude, multiple=1):
        self.engine = engine
        self.attitude = attitude
        self.scalar = engine.scalar
        if self.scalar:
            state = (tuple(float(x) for x in w[0]), None if q is None else tuple(float(x) for x in q[0]))
            self.solver = Splitting(engine.drift_one, engine.kick_one, t0, state, order=order, step=step, multiple=multiple)
        else:
            self.solver = Splitting(engine.drift, engine.kick, t0, (w, q), order=order, step=step, multiple=multiple)

    def advance(self, t_out):
        states = self.solver.advance(t_out)
        if self.scalar:
            w = np.array([[s[0]] for s in states]).reshape(len(states), 1, 3)
            q = None if states[0][1] is None else np.array([[s[1]] for s in states]).reshape(len(states), 1, 4)
        else:
            w = np.stack([s[0] for s in states])
            q = None if states[0][1] is None else np.stack([s[1] for s in states])
        wo, qo = self.engine.state_out(w, q)
        return wo, (qo if self.attitude else None)

    def stats(self):
        s = self.solver
        return {
            "method": "splitting",
            "order": s.order,
            "step_s": s.step_size,
            "steps": int(s.n_steps),
            "drifts": int(s.n_steps * len(s.a)),
        }


def simulate(moments, omega0, q0, t, torques=(), *, method="dop853", rtol=1e-10, step=None, order=6, attitude=True, estimate=True,
             backend="auto"):
    """Array-in, array-out ensemble integration (SI): the engine for sweeps and scripts.

    Parameters
    ----------
    moments : array (3,) or (N, 3)
        Principal moments (kg m^2) along the body axes.
    omega0 : array (3,) or (N, 3)
        rad/s, body frame.
    q0 : array (4,) or (N, 4)
        Attitudes body -> inertial.
    t : array (T,)
        Output times (s).
    torques : sequence
        Torque specifications.
    method, rtol, step, order, attitude, estimate, backend
        As :meth:`Engine.integrate`.

    Returns
    -------
    Trajectory
        ``omega`` (T, N, 3), ``attitude`` (T, N, 4), ``error`` per member.

    Examples
    --------
    >>> import numpy as np
    >>> from wobble.models.engine import simulate, ConstantTorque
    >>> run = simulate([2.0, 2.0, 2.0], np.zeros((4, 3)), [1, 0, 0, 0], [0.0, 1.0, 2.0],
    ...                [ConstantTorque([0.0, 0.0, 1.0])])
    >>> run.omega[-1, :, 2]          # omega_3 = tau t / I
    array([1., 1., 1., 1.])
    """
    omega0 = np.asarray(omega0, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    n = max(omega0.reshape(-1, 3).shape[0], q0.reshape(-1, 4).shape[0], np.reshape(moments, (-1, 3)).shape[0])
    engine = Engine(BodyModel.from_moments(moments), torques, members=n)
    return engine.integrate(omega0, q0, t, method=method, rtol=rtol, step=step, order=order, attitude=attitude, estimate=estimate,
                            backend=backend)
