"""Torques for the engine: a written contract and the built-in kinds (SI, body frame in).

The contract
------------
A torque *kind* is two classes.

:class:`TorqueSpec` (a frozen dataclass) is what a user or a scene file gives: the
parameters in SI, vectors in the user's body frame or the inertial frame, one value or one
row per ensemble member. A kind must

* set the class attribute ``kind`` (its name in scene files and the API),
* implement ``bind(frame, members) -> BoundTorque``: check the parameters against the body
  and return the torque in the engine's internal frame (:class:`wobble.models.rigid_frame.InternalFrame`).

:class:`BoundTorque` is the torque the integrators call, in the internal frame. A kind must
implement

* ``torque(t, w, q, idx) -> (n, 3)``: vectorised over members (``w`` (n, 3) rad/s,
  ``q`` (n, 4) body -> inertial, or None when no torque needs the attitude; ``idx`` the
  members' rows of per-member parameters, or None for all);

and may implement

* ``torque_one(t, w, q) -> (tx, ty, tz)``: one member in Python floats (a single
  trajectory's splitting kicks and the NumPy DOP853's stages run ~20 times faster than
  through NumPy); the default says there is none, and the vectorised path runs;
* ``potential(t, q, idx) -> (n,)`` when ``conservative`` (time-independent potential: the
  engine reports and tests the total energy);
* ``program_terms() -> [(field, arrays), ...]``: the torque as terms of the compiled
  kernel's :class:`~wobble.numerics.torque_program.TorqueProgram` (None: no compiled
  form, the run takes the NumPy DOP853);

A spec may also implement ``check_scene(moments, mass, radius, start, stop)`` for checks that
need the body or the run's span (:class:`ThirdBody`: a perturber inside the body, an
ephemeris table that does not cover the run); the scene reader calls it.

The bound torque sets the flags ``uses_omega`` (only torques that do not depend on omega, or linear
damping, have an exact splitting kick), ``uses_attitude``, ``time_dependent``,
``conservative`` and ``damping`` ((M, 3) diagonal in the internal frame, for the exact
damped kick; None otherwise).

Adding a kind is the four-step recipe of DEVELOPERS.md: one class here, one compiled
branch (:mod:`wobble.numerics.rigid_dop853`, with its field in
:mod:`wobble.numerics.torque_program`), one scene-file entry (:mod:`wobble.io.scene_file`,
which the API's ``wobble.Torque`` constructors go through too), one test.

The kinds
---------
:class:`ConstantTorque`, :class:`UniformGravity` (about a pivot: the heavy top, Goldstein,
Poole & Safko 2002 sec. 5.7), :class:`GravityGradient` (MacCullagh's tidal torque),
:class:`ThirdBody` (the same torque from a body moving on a Keplerian orbit, an
ephemeris table or a callable: the Sun and the Moon on Earth's bulge),
:class:`MagneticDipole` (a body-fixed dipole in a uniform field), :class:`LinearDamping`
and :class:`CustomTorque` (any vectorised callable).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from wobble.errors import InputError
from wobble.models.orbit import EphemerisTable, KeplerOrbit, rms_radius
from wobble.models.rigid_frame import (
    InternalFrame,
    cross,
    cross_one,
    member_rows,
    rotate,
    rotate_one,
    stack3,
    take_rows,
    to_body,
    to_body_components,
)
from wobble.numerics import quaternion as quat
from wobble.numerics.kepler import position_one as kepler_position_one

__all__ = [
    "STANDARD_GRAVITY",
    "TorqueSpec",
    "BoundTorque",
    "ConstantTorque",
    "UniformGravity",
    "GravityGradient",
    "ThirdBody",
    "MagneticDipole",
    "LinearDamping",
    "CustomTorque",
    "KINDS",
]

STANDARD_GRAVITY = 9.80665  # m s^-2 (CGPM 1901, exact)


class BoundTorque(ABC):
    """A torque in the engine's internal frame (see the module docstring for the contract)."""

    uses_omega: bool = False
    uses_attitude: bool = True
    time_dependent: bool = False
    conservative: bool = False
    damping: np.ndarray | None = None

    @abstractmethod
    def torque(self, t, w, q, idx):
        """Torque (n, 3) in the internal frame at times ``t`` for states ``w``, ``q``."""

    def torque_one(self, t, w, q):
        """One member in Python floats, or None when the kind has no scalar form."""
        return None

    @property
    def has_scalar_form(self) -> bool:
        """Whether :meth:`torque_one` is implemented (overridden) by the kind."""
        return type(self).torque_one is not BoundTorque.torque_one

    def potential(self, t, q, idx):
        """Potential energy (n,) in J, for a conservative torque."""
        raise NotImplementedError(f"{type(self).__name__} is not conservative")

    def program_terms(self):
        """Terms of the compiled kernel's program, or None (no compiled form)."""
        return None


class TorqueSpec(ABC):
    """A torque as given (SI): a frozen dataclass with a ``kind`` and :meth:`bind`."""

    kind: ClassVar[str]

    @abstractmethod
    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        """Check the parameters against the body and return the torque in the internal frame."""

    def field_rate(self) -> float | None:
        """The fastest angular frequency (rad/s) of the torque's own time dependence, at a fixed attitude.

        0 for a field fixed in space (or in the body, or no field: damping); a perturber's tide,
        quadratic in its direction and going as ``1/r^3``, at up to twice its orbital rate and the
        harmonics of an eccentric orbit; None where it cannot be known before the run (a callable). A
        figure's check against aliasing adds it to the rates the body's own turning gives
        (:mod:`wobble.plot._sampling`).
        """
        return None

    def through_figure_axis(self) -> bool:
        """Whether, on a body symmetric about its axis 3, this torque depends on the attitude through that
        axis alone, so that it changes only as fast as the axis moves (and the field): a tide (the inertia
        tensor is ``A 1 + (C - A) e3 e3``), or a lever whose arm lies on the axis. False where it cannot
        be said (a torque fixed in the body, damping, a callable)."""
        return False


# --------------------------------------------------------------------------
# Constant torque
# --------------------------------------------------------------------------
class _BodyConstant(BoundTorque):
    uses_attitude = False

    def __init__(self, tau):
        self.tau = tau  # (M, 3), internal frame
        self.one = tuple(float(x) for x in tau[0])

    def torque(self, t, w, q, idx):
        return np.broadcast_to(take_rows(self.tau, idx), w.shape)

    def torque_one(self, t, w, q):
        return self.one

    def program_terms(self):
        return [("body", self.tau)]


class _InertialConstant(BoundTorque):
    def __init__(self, tau):
        self.tau = tau  # (M, 3), inertial frame
        self.one = tuple(float(x) for x in tau[0])

    def torque(self, t, w, q, idx):
        return to_body(q, take_rows(self.tau, idx))

    def torque_one(self, t, w, q):
        return rotate_one(q, self.one, inverse=True)

    def program_terms(self):
        return [("inertial", self.tau)]


@dataclass(frozen=True)
class ConstantTorque(TorqueSpec):
    """A constant torque (N m), fixed in the body frame or in the inertial frame.

    ``torque`` has shape (3,) or (N, 3). A body-frame torque on a sphere
    gives ``omega(t) = omega0 + tau t / I`` (tested).
    """

    torque: np.ndarray
    frame: str = "body"
    kind: ClassVar[str] = "constant"

    def through_figure_axis(self) -> bool:
        """A torque fixed in space does not depend on the attitude at all; one fixed in the body does."""
        return self.frame == "inertial"

    def field_rate(self) -> float:
        """0: the torque's field does not move in space (:meth:`TorqueSpec.field_rate`)."""
        return 0.0

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        if self.frame not in ("body", "inertial"):
            raise InputError("frame", self.frame, "'body' or 'inertial'")
        tau = member_rows(self.torque, members, 3, "torque")
        return _BodyConstant(frame.vec_in(tau)) if self.frame == "body" else _InertialConstant(tau)


# --------------------------------------------------------------------------
# Lever torques: gravity about a pivot, a magnetic dipole in a field (arm x R^T force)
# --------------------------------------------------------------------------
class _Lever(BoundTorque):
    """``arm x R(q)^T force``, arm fixed in the body, force fixed in space; V = -force . (R arm)."""

    conservative = True

    def __init__(self, arm, force, program_kind: str):
        self.arm, self.force = arm, force  # (M, 3): arm in the internal frame, force inertial
        self.shared = arm.shape[0] == 1 and force.shape[0] == 1
        self.arm_one = tuple(float(x) for x in arm[0])
        self.force_one = tuple(float(x) for x in force[0])
        self.program_kind = program_kind

    def torque(self, t, w, q, idx):
        if not self.shared:
            return cross(take_rows(self.arm, idx), to_body(q, take_rows(self.force, idx)))
        r, f = self.arm[0], self.force[0]
        g0, g1, g2 = to_body_components(q, f[0], f[1], f[2])
        return stack3(r[1] * g2 - r[2] * g1, r[2] * g0 - r[0] * g2, r[0] * g1 - r[1] * g0)

    def torque_one(self, t, w, q):
        return cross_one(self.arm_one, rotate_one(q, self.force_one, inverse=True))

    def potential(self, t, q, idx):
        return -np.sum(take_rows(self.force, idx) * rotate(q, take_rows(self.arm, idx)), axis=-1)

    def program_terms(self):
        return [(self.program_kind, (self.arm, self.force))]


@dataclass(frozen=True)
class UniformGravity(TorqueSpec):
    """Gravity about a fixed pivot (the heavy top, Goldstein, Poole & Safko 2002 sec. 5.7; any body).

    ``tau = r x (m R^T g)``, potential ``V = -m g . (R r)``.

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
    kind: ClassVar[str] = "gravity"

    def through_figure_axis(self) -> bool:
        """With the centre of mass on axis 3 (every member's), the arm is that axis."""
        arm = np.asarray(self.center_of_mass, dtype=float).reshape(-1, 3)
        return bool(np.all(arm[:, :2] == 0))

    def field_rate(self) -> float:
        """0: the torque's field does not move in space (:meth:`TorqueSpec.field_rate`)."""
        return 0.0

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        mass = member_rows(self.mass, members, 1, "mass")
        if np.any(mass <= 0):
            raise InputError("mass", self.mass, "a positive mass (kg)")
        r = frame.vec_in(member_rows(self.center_of_mass, members, 3, "center_of_mass"))
        g = member_rows(self.gravity, members, 3, "gravity")
        return _Lever(r, mass * g, "gravity")


@dataclass(frozen=True)
class MagneticDipole(TorqueSpec):
    """A magnetic dipole fixed in the body in a uniform magnetic field: ``tau = mu x B``.

    The torque of a compass needle, a bar magnet or a satellite's magnetorquer, with the
    potential ``V = -mu . B`` (Jackson 1999, *Classical Electrodynamics*, sec. 5.7). A
    symmetric body whose dipole lies on its axis, in a field pointing down, is a heavy
    top with ``M g l = |mu| |B|`` (tested against the exact top).

    Attributes
    ----------
    dipole : array (3,) or (N, 3)
        Magnetic dipole moment in the body frame (A m^2).
    field : array (3,) or (N, 3)
        Magnetic flux density in the inertial frame (T).
    """

    dipole: np.ndarray
    field: np.ndarray
    kind: ClassVar[str] = "magnetic"

    def through_figure_axis(self) -> bool:
        """With the dipole along axis 3 (every member's), the arm is that axis."""
        arm = np.asarray(self.dipole, dtype=float).reshape(-1, 3)
        return bool(np.all(arm[:, :2] == 0))

    def field_rate(self) -> float:
        """0: the torque's field does not move in space (:meth:`TorqueSpec.field_rate`)."""
        return 0.0

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        mu = frame.vec_in(member_rows(self.dipole, members, 3, "dipole"))
        b = member_rows(self.field, members, 3, "field")
        return _Lever(mu, b, "magnetic")


# --------------------------------------------------------------------------
# Gravity gradient
# --------------------------------------------------------------------------
class _Gradient(BoundTorque):
    """``k rho_b x (I rho_b)``, rho a fixed or uniformly turning inertial direction."""

    def __init__(self, k, e1, e2, rate, phase, moments):
        self.k, self.e1, self.e2, self.rate, self.phase = k, e1, e2, rate, phase
        self.moments = moments  # (M, 3) ascending
        self.time_dependent = e2 is not None
        self.conservative = e2 is None
        self.m_one = tuple(float(x) for x in moments[0])
        self.e1_one = tuple(float(x) for x in e1)
        self.e2_one = None if e2 is None else tuple(float(x) for x in e2)

    def _direction(self, t):
        if self.e2 is None:
            return self.e1[0], self.e1[1], self.e1[2]
        ang = self.rate * np.asarray(t, dtype=float) + self.phase
        c, s = np.cos(ang), np.sin(ang)
        e1, e2 = self.e1, self.e2
        return c * e1[0] + s * e2[0], c * e1[1] + s * e2[1], c * e1[2] + s * e2[2]

    def torque(self, t, w, q, idx):
        r0, r1, r2 = to_body_components(q, *self._direction(t))
        m, k = take_rows(self.moments, idx), self.k
        # rho x I rho = ((I3 - I2) r1 r2, (I1 - I3) r2 r0, (I2 - I1) r0 r1)
        return stack3(
            k * (m[:, 2] - m[:, 1]) * r1 * r2, k * (m[:, 0] - m[:, 2]) * r2 * r0, k * (m[:, 1] - m[:, 0]) * r0 * r1
        )

    def torque_one(self, t, w, q):
        if self.e2_one is None:
            rho = self.e1_one
        else:
            ang = self.rate * float(t) + self.phase
            c, s = math.cos(ang), math.sin(ang)
            e1, e2 = self.e1_one, self.e2_one
            rho = (c * e1[0] + s * e2[0], c * e1[1] + s * e2[1], c * e1[2] + s * e2[2])
        rb = rotate_one(q, rho, inverse=True)
        m = self.m_one
        tq = cross_one(rb, (m[0] * rb[0], m[1] * rb[1], m[2] * rb[2]))
        return (self.k * tq[0], self.k * tq[1], self.k * tq[2])

    def potential(self, t, q, idx):
        rb = to_body(q, np.stack(np.broadcast_arrays(*self._direction(t)), -1))
        return 0.5 * self.k * np.sum(rb * take_rows(self.moments, idx) * rb, axis=-1)

    def program_terms(self):
        moving = self.e2 is not None
        row = np.concatenate(
            [
                [self.k],
                self.e1,
                self.e2 if moving else np.zeros(3),
                [self.rate if moving else 0.0, self.phase if moving else 0.0],
            ]
        )
        return [("gradient", row)]


@dataclass(frozen=True)
class GravityGradient(TorqueSpec):
    """The tidal torque of a distant point mass (MacCullagh): satellites, equinox precession.

    ``tau = (3 GM / d^3) rho_b x (I rho_b)``, potential ``V = (3 GM / 2 d^3) rho_b . I rho_b``
    up to a constant.

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
    kind: ClassVar[str] = "gravity_gradient"

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

    def through_figure_axis(self) -> bool:
        """A tide: through the inertia tensor, ``A 1 + (C - A) e3 e3`` on a symmetric body."""
        return True

    def field_rate(self) -> float:
        """Twice the direction's mean motion, ``2 |n|``: the torque is quadratic in the direction, which
        turns uniformly on its circle (either way)."""
        return 2.0 * abs(self.rate())

    def rate(self) -> float:
        """The mean motion n (rad/s) of the direction (0 for a fixed direction)."""
        if self.orbit_normal is None:
            return 0.0
        return float(self.mean_motion) if self.mean_motion is not None else float(np.sqrt(self.gm / self.distance**3))

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        if not (np.isfinite(self.gm) and self.gm > 0):
            raise InputError("gm", self.gm, "a positive gravitational parameter (m3 s-2)")
        if not (np.isfinite(self.distance) and self.distance > 0):
            raise InputError("distance", self.distance, "a positive distance (m)")
        e1, e2 = self.unit_vectors()
        return _Gradient(3.0 * self.gm / self.distance**3, e1, e2, self.rate(), float(self.phase), frame.moments)


# --------------------------------------------------------------------------
# A third body on an orbit: Kepler, a table, or a callable
# --------------------------------------------------------------------------
class _ThirdBody(BoundTorque):
    """``(3 GM / r^3) u_b x (I u_b)``, u the unit vector to the perturber at r(t); V = (3 GM / 2 r^3) u_b . I u_b."""

    def __init__(self, spec: ThirdBody, moments):
        self.spec = spec
        self.gm = float(spec.gm)
        self.moments = moments  # (M, 3) ascending
        self.m_one = tuple(float(x) for x in moments[0])
        self.orbit, self.table, self.function = spec.orbit, spec.ephemeris, spec.position
        self.elements_one = None if self.orbit is None else tuple(float(x) for x in self.orbit.elements)
        fixed = self.orbit is not None and not self.orbit.moving
        self.time_dependent = not fixed
        self.conservative = fixed

    def _positions(self, t):
        """(r (n, 3) inertial, |r| (n,)) at times t (any shape)."""
        if self.orbit is not None:
            return self.orbit.position(t)
        if self.table is not None:
            return self.table.position(t)
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        r = np.asarray(self.function(tt), dtype=float)
        if r.shape != tt.shape + (3,):
            raise InputError(
                f"{self.spec.name}.position", r.shape, f"a callable returning positions of shape {tt.shape + (3,)} (m)"
            )
        r = r.reshape(np.shape(t) + (3,))
        return r, np.sqrt(np.sum(r * r, axis=-1))

    def _unit_and_strength(self, t):
        r, d = self._positions(t)
        k = 3.0 * self.gm / (d * d * d)
        return r[..., 0] / d, r[..., 1] / d, r[..., 2] / d, k

    def torque(self, t, w, q, idx):
        u0, u1, u2, k = self._unit_and_strength(t)
        r0, r1, r2 = to_body_components(q, u0, u1, u2)
        m = take_rows(self.moments, idx)
        # u x I u = ((I3 - I2) u1 u2, (I1 - I3) u2 u0, (I2 - I1) u0 u1), MacCullagh
        return stack3(
            k * (m[:, 2] - m[:, 1]) * r1 * r2, k * (m[:, 0] - m[:, 2]) * r2 * r0, k * (m[:, 1] - m[:, 0]) * r0 * r1
        )

    def torque_one(self, t, w, q):
        if self.elements_one is not None:
            x, y, z, d = kepler_position_one(float(t), self.elements_one)
        elif self.table is not None:
            x, y, z, d = self.table.position_one(float(t))
        else:
            r, dist = self._positions(np.array([float(t)]))
            x, y, z, d = float(r[0, 0]), float(r[0, 1]), float(r[0, 2]), float(dist[0])
        k = 3.0 * self.gm / (d * d * d)
        ub = rotate_one(q, (x / d, y / d, z / d), inverse=True)
        m = self.m_one
        tq = cross_one(ub, (m[0] * ub[0], m[1] * ub[1], m[2] * ub[2]))
        return (k * tq[0], k * tq[1], k * tq[2])

    def potential(self, t, q, idx):
        """The attitude-dependent part of the tidal potential, J: time-dependent unless the perturber is fixed."""
        u0, u1, u2, k = self._unit_and_strength(t)
        ub = to_body(q, np.stack(np.broadcast_arrays(u0, u1, u2), -1))
        return 0.5 * k * np.sum(ub * take_rows(self.moments, idx) * ub, axis=-1)

    def program_terms(self):
        if self.orbit is None:
            return None  # a table or a callable: the NumPy integrators
        return [("third_body", np.concatenate([[self.gm], self.orbit.elements]))]


@dataclass(frozen=True)
class ThirdBody(TorqueSpec):
    """The tidal torque of a third body moving on a given orbit: the Sun and the Moon on Earth's bulge.

    ``tau = (3 GM / r^5) r_b x (I r_b)`` (MacCullagh's formula; Goldstein, Poole & Safko
    2002, sec. 5.8), with r_b the perturber's position in the body frame, from

    * a Keplerian ``orbit`` (:class:`wobble.models.orbit.KeplerOrbit`: elements at t = 0,
      mean motion, secular node and periapsis rates; Kepler's equation at each evaluation:
      Murray & Dermott 1999, sec. 2.4), compiled; or
    * an ``ephemeris`` table (:class:`wobble.models.orbit.EphemerisTable`, cubic splines),
      which must cover the run; or
    * a ``position`` callable ``f(t) -> (n, 3)`` (t (n,) in s, positions in m).

    The last two have no compiled form (the run takes the NumPy DOP853 or the splitting).
    The torque does not depend on omega, so the splitting's kick is exact. Its potential
    ``V = (3 GM / 2 r^3) u_b . I u_b`` (up to terms independent of the attitude) is
    time-dependent unless the perturber stands still (``mean_motion`` and rates zero:
    then the energy is conserved).

    Attributes
    ----------
    gm : float
        G M of the perturber, m^3 s^-2 (positive).
    orbit, ephemeris, position
        Exactly one of them (see above); positions relative to the body's centre in the
        inertial frame.
    name : str
        For messages and outputs (``"moon"``).
    """

    gm: float
    orbit: KeplerOrbit | None = None
    ephemeris: EphemerisTable | None = None
    position: Callable | None = None
    name: str = "third_body"
    kind: ClassVar[str] = "third_body"

    def __post_init__(self):
        if not (np.ndim(self.gm) == 0 and math.isfinite(float(self.gm)) and float(self.gm) > 0):
            raise InputError("gm", self.gm, "a positive G M (m3 s-2; a negative mass is unphysical)")
        given = [k for k in ("orbit", "ephemeris", "position") if getattr(self, k) is not None]
        if len(given) != 1:
            raise InputError("orbit, ephemeris, position", given or "none", "exactly one of them")
        if self.position is not None and not callable(self.position):
            raise InputError("position", self.position, "a callable f(t) -> positions (n, 3) in m")

    def through_figure_axis(self) -> bool:
        """A tide: through the inertia tensor, ``A 1 + (C - A) e3 e3`` on a symmetric body."""
        return True

    def field_rate(self) -> float | None:
        """The tide's fastest frequency, from the orbit or the table (``tide_rate`` of
        :class:`wobble.models.orbit.KeplerOrbit` or :class:`~wobble.models.orbit.EphemerisTable`); None for a
        ``position`` callable."""
        if self.orbit is not None:
            return self.orbit.tide_rate()
        if self.ephemeris is not None:
            return self.ephemeris.tide_rate()
        return None

    @property
    def closest_approach(self) -> float | None:
        """The smallest distance of the perturber (m), when known in advance (an orbit, a table)."""
        if self.orbit is not None:
            return self.orbit.periapsis
        if self.ephemeris is not None:
            return self.ephemeris.closest
        return None

    def check_scene(self, moments, mass, radius, start: float, stop: float) -> None:
        """Refuse a perturber inside the body, or a table that does not cover [start, stop] s.

        ``radius`` (m) is the body's radius when known; otherwise, with its ``mass``, the
        RMS radius of its mass (:func:`wobble.models.orbit.rms_radius`), which some of the
        body's mass certainly exceeds.
        """
        size = radius if radius is not None else (rms_radius(moments, mass) if mass else None)
        near = self.closest_approach
        if size is not None and near is not None and not near > size:
            key = "semi_major_axis" if self.orbit is not None else "ephemeris.positions"
            raise InputError(
                key,
                f"closest approach {near:.6g} m",
                f"an orbit outside the body (closest approach above its radius {size:.6g} m)",
            )
        if self.ephemeris is not None:
            self.ephemeris.check_covers(start, stop)

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        return _ThirdBody(self, frame.moments)


# --------------------------------------------------------------------------
# Linear damping
# --------------------------------------------------------------------------
class _Damping(BoundTorque):
    uses_omega = True
    uses_attitude = False

    def __init__(self, diag):
        self.damping = diag  # (M, 3), internal frame

    def torque(self, t, w, q, idx):
        return -take_rows(self.damping, idx) * w

    def program_terms(self):
        return [("damping", self.damping)]


@dataclass(frozen=True)
class LinearDamping(TorqueSpec):
    """``tau = -c omega`` with c (N m s) a scalar or one value per body axis.

    Per-axis values need a body frame along principal axes (a diagonal
    damping in the principal frame), so that the splitting's kick is exact.
    The engine carries the damping itself in every integrator (the exact damped
    kick of the splitting, the scalar path), so the kind has no scalar form.
    """

    coefficient: np.ndarray | float
    kind: ClassVar[str] = "damping"

    def field_rate(self) -> float:
        """0: the torque's field does not move in space (:meth:`TorqueSpec.field_rate`)."""
        return 0.0

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        c = np.asarray(self.coefficient, dtype=float)
        if c.ndim == 0 or (c.ndim == 1 and c.shape[0] != 3):
            c = c[..., None] * np.ones(3)  # one coefficient (per member): isotropic
        c3 = member_rows(c, members, 3, "coefficient")
        rows = max(c3.shape[0], frame.P.shape[0])
        P = np.broadcast_to(frame.P, (rows, 3, 3))
        mat = np.einsum("mij,mj,mkj->mik", P, np.broadcast_to(c3, (rows, 3)), P)
        diag = np.diagonal(mat, axis1=-2, axis2=-1).copy()
        off = mat - diag[..., None] * np.eye(3)
        if np.any(np.abs(off) > 1e-12 * np.max(np.abs(diag), initial=0.0)):
            raise InputError("coefficient", self.coefficient, "one value, or per-axis values along principal axes")
        return _Damping(diag)


# --------------------------------------------------------------------------
# A user's function
# --------------------------------------------------------------------------
class _Custom(BoundTorque):
    time_dependent = True

    def __init__(self, spec: CustomTorque, frame: InternalFrame):
        self.spec, self.frame = spec, frame
        self.inertial = spec.frame == "inertial"
        self.uses_omega = bool(spec.uses_omega)
        self.uses_attitude = bool(spec.uses_attitude) or self.inertial

    def torque(self, t, w, q, idx):
        P = take_rows(self.frame.P, idx)
        w_body = np.einsum("...ji,...j->...i", P, w)
        q_body = quat.multiply(q, quat.conjugate(take_rows(self.frame.q_pt, idx))) if q is not None else None
        tt = np.broadcast_to(np.asarray(t, dtype=float), w.shape[:-1])
        tau = np.asarray(self.spec.function(tt, w_body, q_body), dtype=float)
        if tau.shape != w.shape:
            raise InputError(self.spec.name, tau.shape, f"a custom torque returning shape {w.shape} (N m)")
        if self.inertial:
            return to_body(q, tau)
        return np.einsum("...ij,...j->...i", P, tau)


@dataclass(frozen=True)
class CustomTorque(TorqueSpec):
    """A torque from your own function, vectorised over members.

    ``function(t, omega, q)`` receives times ``t`` (n,), body-frame angular
    velocities ``omega`` (n, 3) in rad/s and attitudes ``q`` (n, 4) (body to
    inertial), and returns torques (n, 3) in N m in ``frame``. Say whether
    it depends on omega (``uses_omega``): only torques that do not can be
    integrated by the splitting. It has no compiled form (the run takes the
    NumPy DOP853).
    """

    function: Callable
    frame: str = "body"
    uses_omega: bool = True
    uses_attitude: bool = True
    name: str = "custom"
    kind: ClassVar[str] = "custom"

    def bind(self, frame: InternalFrame, members: int) -> BoundTorque:
        if self.frame not in ("body", "inertial"):
            raise InputError("frame", self.frame, "'body' or 'inertial'")
        if not callable(self.function):
            raise InputError("function", self.function, "a callable f(t, omega, q) -> torque (N m)")
        return _Custom(self, frame)


#: Every built-in kind by its name (scene files, the API).
KINDS = {
    cls.kind: cls
    for cls in (ConstantTorque, UniformGravity, GravityGradient, ThirdBody, MagneticDipole, LinearDamping, CustomTorque)
}
