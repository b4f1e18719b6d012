"""Euler's equations with torques, for one body or an ensemble (SI float64).

Goldstein, Poole & Safko (2002) sec. 5.5 (the course notes' sec. 5.5): in the body (principal-axis) frame

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

Torques
-------
Every torque follows the contract of :mod:`wobble.models.torques` (a specification that
binds to the internal frame; vectorised, scalar and compiled forms; its potential where
conservative): constant, uniform gravity about a pivot, gravity gradient, a third body on an
orbit, a magnetic dipole in a uniform field, linear damping, or any vectorised callable.

Integration
-----------
``method="dop853"``: Dormand & Prince 8(5,3) on ``(omega, q)`` (quaternion
renormalised after each step), compiled (:mod:`wobble.numerics.rigid_dop853`,
every built-in torque, ~200 ns per evaluation, ensembles on all CPUs) or, with
a custom torque, in NumPy (:class:`wobble.numerics.integrators.DOP853`); the
two are the same method, step for step (``backend=``).
``method="splitting"``: Touma & Wisdom (1994): exact free flow
(:func:`wobble.models.free_flow.flow_sorted`) between torque kicks; the kick
``domega/dt = I^-1 (tau(t, q) - D omega)`` at fixed attitude and time is
solved exactly (torques that depend on omega other than linear damping are
refused: their kick has no exact solution). Orders 2, 4, 6.

Each run can carry a companion run (looser tolerance, or twice the step)
whose difference from the main run is the global error estimate reported
(:class:`ErrorEstimate`). The splitting's Richardson estimate sees truncation
only; two more runs, the companion with extra rounding-level noise after every
drift, measure how much the motion amplifies rounding (its floor,
:class:`CheckedRun`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wobble.numerics.floats import EPS
from wobble.errors import InputError
from wobble.models.free_flow import flow_one, flow_sorted
from wobble.models.rigid_frame import BodyModel, InternalFrame, normalize, qmul_one, take_rows
from wobble.models.torques import (
    STANDARD_GRAVITY,
    BoundTorque,
    ConstantTorque,
    CustomTorque,
    GravityGradient,
    LinearDamping,
    MagneticDipole,
    ThirdBody,
    TorqueSpec,
    UniformGravity,
)
from wobble.numerics import compiled as compiled_kernels
from wobble.numerics import quaternion as quat
from wobble.numerics.integrators import DOP853, Splitting, StepLimitError
from wobble.numerics.torque_program import TorqueProgram, pack

__all__ = [
    # the body and the torques live in wobble.models.rigid_frame and wobble.models.torques;
    # they are named here too because an engine run is built from them
    "BodyModel",
    "TorqueSpec",
    "BoundTorque",
    "ConstantTorque",
    "UniformGravity",
    "GravityGradient",
    "ThirdBody",
    "MagneticDipole",
    "LinearDamping",
    "CustomTorque",
    "Engine",
    "ErrorAccumulator",
    "ErrorEstimate",
    "error_estimate_method",
    "CheckedRun",
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
#: The splitting's rounding twins add ``ROUNDING_GAIN`` eps of relative noise to every component after
#: every drift (:class:`CheckedRun`), a few times a run's own rounding: one realisation of amplified noise
#: is a Gaussian draw along the growing direction (10 times below its spread about 8 % of the time), and
#: the gain lets the root-mean-square of two twins bound the main run's own draw. On a chaotic heavy body
#: (24 rounding realisations of the main run, 12 of a twin at gain 1) gain 4 misses 1 % of the pairs and
#: is 6 times the error at the median; a larger gain inflates the estimate of a motion whose own flows round
#: less than eps a drift (a torque-free symmetric body: about 400 times its rounding-level error).
ROUNDING_GAIN = 4.0
#: Seeds of the twins' signs: fixed, so that a run and its estimate are reproducible.
ROUNDING_SEEDS = (853, 854)


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
    rounding : numpy.ndarray (N,) or None
        The part of the estimate that is amplified rounding (the larger of its omega and
        attitude parts; included in both estimates above): a shorter step cannot lower it.
        None where not measured (DOP853, whose companion's own rounding is in its difference).
    """

    omega_relative: np.ndarray
    attitude: np.ndarray
    method: str
    rounding: np.ndarray | None = None

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


class ErrorAccumulator:
    """Running maxima for the global error estimate (a run against its companion run)."""

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

    def relative(self, size=None):
        """Largest difference of each member's omega components, each relative to its own largest value."""
        size = self.size if size is None else size
        floor = COMPONENT_FLOOR * np.max(size, axis=-1, keepdims=True)
        scale = np.maximum(size, floor)
        with np.errstate(invalid="ignore", divide="ignore"):
            rel = np.where(scale > 0, self.diff / scale, 0.0)
        return np.max(rel, axis=-1)

    def result(self, method):
        return ErrorEstimate(self.factor * self.relative(), self.factor * self.angle, method)

    def with_rounding(self, twins, method):
        """This (truncation) estimate and the rounding one of the ``twins``, added in quadrature.

        Each is the size of an independent part of the main run's error (truncation, which
        Richardson measures, and rounding amplified by the motion, which its division by
        ``2^p - 1`` hides), so their root-sum-square estimates the whole. The rounding part is
        the root-mean-square over the twins (accumulators of their differences from the companion).
        """
        rnd_w = np.sqrt(np.mean([(t.factor * t.relative(self.size)) ** 2 for t in twins], axis=0))
        rnd_q = np.sqrt(np.mean([(t.factor * t.angle) ** 2 for t in twins], axis=0))
        return ErrorEstimate(
            np.hypot(self.factor * self.relative(), rnd_w),
            np.hypot(self.factor * self.angle, rnd_q),
            method,
            np.maximum(rnd_w, rnd_q),
        )


class _Jitter:
    """Wraps a drift: each component of its result times ``1 + size s`` (s = +-1), the attitude renormalised.

    It mimics rounding, which is relative per component (a component that is exactly zero stays zero, so a
    steady rotation stays steady), at a chosen size. The signs come from a fixed seed, one draw per drift
    shared by all members (a member's twin is the same alone or in an ensemble).
    """

    _ROWS = 4096

    def __init__(self, size, seed):
        self.size = float(size)
        self.rng = np.random.default_rng(seed)
        self.rows = []

    def _factors(self):
        if not self.rows:
            draw = 1.0 + self.size * self.rng.choice([-1.0, 1.0], size=(self._ROWS, 7))
            self.rows = [tuple(r) for r in draw[::-1].tolist()]  # Python floats: NumPy scalars slow the drift
        return self.rows.pop()

    def one(self, drift):
        """``drift`` for one member in Python floats (tuples), jittered."""

        def jittered(state, t, h):
            w, q = drift(state, t, h)
            f = self._factors()
            w = (w[0] * f[0], w[1] * f[1], w[2] * f[2])
            if q is not None:
                q = (q[0] * f[3], q[1] * f[4], q[2] * f[5], q[3] * f[6])
                n = 1.0 / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
                q = (q[0] * n, q[1] * n, q[2] * n, q[3] * n)
            return w, q

        return jittered

    def many(self, drift):
        """``drift`` for arrays of members, jittered."""

        def jittered(state, t, h):
            w, q = drift(state, t, h)
            f = np.array(self._factors())
            return w * f[:3], (None if q is None else normalize(q * f[3:]))

        return jittered


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
        self.frame = InternalFrame.of(body, self.n)
        self.specs = tuple(torques)
        for i, spec in enumerate(self.specs):
            if not isinstance(spec, TorqueSpec):
                raise InputError(f"torques[{i}]", spec, "a torque specification (wobble.models.torques)")
        self.torques: list[BoundTorque] = [t.bind(self.frame, self.n) for t in self.specs]
        self.moments = self.frame.moments  # (M, 3) ascending
        self.damping = None
        for b in self.torques:
            if b.damping is not None:
                self.damping = b.damping if self.damping is None else self.damping + b.damping
        self.kicked = [b for b in self.torques if b.damping is None]
        self._scalar = (
            self.n == 1
            and self.moments.shape[0] == 1
            and all(b.has_scalar_form or b.damping is not None for b in self.torques)
        )
        self._program = None
        self._moments_one = tuple(float(x) for x in self.moments[0])
        self._damping_one = (
            None if self.damping is None else tuple(float(x) for x in np.reshape(self.damping, (-1, 3))[0])
        )

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
        I = take_rows(self.moments, idx)
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
        I = self.moments
        if self.damping is None:
            return w + (h / I) * tau, q
        x = self.damping * h / I
        with np.errstate(divide="ignore", invalid="ignore"):
            phi1 = np.where(x == 0, 1.0, -np.expm1(-x) / np.where(x == 0, 1.0, x))
        return w + (h / I) * (tau - self.damping * w) * phi1, q

    def drift(self, state, t, h):
        """Exact free flow over h (Touma & Wisdom's drift)."""
        w, q = state
        I = np.broadcast_to(self.moments, w.shape)
        w1, dq = flow_sorted(I, w, np.full(w.shape[0], h), attitude=q is not None)
        if q is None:
            return w1, None
        return w1, normalize(quat.multiply(q, dq))

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
        I = self._moments_one
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
        q1 = qmul_one(q, dq)
        n = 1.0 / math.sqrt(q1[0] * q1[0] + q1[1] * q1[1] + q1[2] * q1[2] + q1[3] * q1[3])
        return w1, (q1[0] * n, q1[1] * n, q1[2] * n, q1[3] * n)

    # -- the compiled integrator ---------------------------------------------------
    @property
    def compilable(self) -> bool:
        """Whether every torque has a compiled form (all built-in kinds; not a custom torque)."""
        return all(b.program_terms() is not None for b in self.torques)

    def program(self) -> TorqueProgram:
        """The torque program of :mod:`wobble.numerics.rigid_dop853` (internal frame, float64; built once)."""
        if self._program is None:
            if not self.compilable:
                raise InputError(
                    "torques", [s.kind for s in self.specs], "built-in torques only for the compiled backend"
                )
            self._program = pack(self.moments, [term for b in self.torques for term in b.program_terms()])
        return self._program

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
            turn = np.where(
                big_l > 0, np.linalg.norm(tau, axis=-1) / big_l, np.sqrt(np.linalg.norm(tau, axis=-1) / imin)
            )
        damp = 0.0 if self.damping is None else np.max(self.damping / self.moments)
        return float(np.max(np.sqrt(stiff / imin) + turn) + damp)

    # -- integration ---------------------------------------------------------------
    def propagator(
        self,
        omega0,
        q0,
        t0,
        *,
        method,
        rtol=None,
        step=None,
        order=6,
        attitude=True,
        multiple=1,
        backend="auto",
        jitter=0.0,
        jitter_seed=0,
    ):
        """A propagator with ``advance(t_out) -> (omega, q)`` in the body frame.

        ``jitter`` (splitting only): relative noise added after every drift, its signs drawn
        from ``jitter_seed`` (:class:`_Jitter`), for the rounding twins of :class:`CheckedRun`.
        """
        need_q = attitude or self.needs_attitude
        w, q = self.state_in(omega0, q0)
        if backend not in BACKENDS:
            raise InputError("backend", backend, f"one of {', '.join(BACKENDS)}")
        if method == "dop853":
            if rtol is None:
                raise InputError("rtol", rtol, "a relative tolerance for dop853")
            if backend == "compiled" and not self.compilable:
                raise InputError(
                    "backend", backend, "'auto' or 'python' with a custom torque (it has no compiled form)"
                )
            compiled = backend == "compiled" or (backend == "auto" and self.compilable and compiled_kernels.available())
            return _RKPropagator(self, w, q if need_q else None, t0, float(rtol), attitude, compiled)
        if method == "splitting":
            if not self.splittable:
                raise InputError(
                    "method", "splitting", "dop853 for torques that depend on omega (other than linear damping)"
                )
            if step is None:
                raise InputError("step", step, "a step (s) for the splitting")
            return _SplitPropagator(
                self, w, q if need_q else None, t0, float(step), int(order), attitude, multiple, jitter, jitter_seed
            )
        raise InputError("method", method, f"one of {', '.join(METHODS)}")

    def integrate(
        self,
        omega0,
        q0,
        t,
        *,
        method="dop853",
        rtol=1e-10,
        step=None,
        order=6,
        attitude=True,
        estimate=True,
        backend="auto",
    ):
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
            2^order - 1 for the splitting, Richardson) as :class:`ErrorEstimate`;
            the splitting adds its rounding floor (:class:`CheckedRun`).
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
        run = CheckedRun(
            self,
            omega0,
            q0,
            t,
            method=method,
            rtol=rtol,
            step=step,
            order=order,
            attitude=attitude,
            estimate=estimate,
            backend=backend,
        )
        w, q = run.advance(t)
        return Trajectory(t, w, q, run.error(), run.stats())


class CheckedRun:
    """A run with the companions that estimate its global error, advanced block by block.

    DOP853: a companion at ten times the tolerance; the difference is the estimate (the
    companion's own rounding, independent of the main run's, is in it). Splitting: a companion
    at twice the step, whose difference divided by ``2^p - 1`` (Richardson) estimates the
    truncation, and two *rounding twins*: the companion again, with ``ROUNDING_GAIN`` eps of
    relative noise of random sign added to every component after every drift (:class:`_Jitter`,
    seeds :data:`ROUNDING_SEEDS`). A twin and the companion share their truncation, so their
    difference is rounding amplified by the motion, the part Richardson's division by
    ``2^p - 1`` hides (in a chaotic motion it dominates: a Lyapunov growth of 10^5 to 10^6 in
    50 s turns the rounding of some 10^4 steps into 10^-8). The estimate is the root-sum-square
    of the truncation part and the twins' root-mean-square (:meth:`ErrorAccumulator.with_rounding`).
    Each twin costs half a main run: the estimate costs 2.5 main runs instead of 1.5.

    Parameters
    ----------
    engine : Engine
    omega0, q0 : array
        Body-frame start, as :meth:`Engine.integrate`.
    times : array (T,)
        The output times the run will be advanced through (only the first is used: the start).
    method, rtol, step, order, attitude, estimate, backend
        As :meth:`Engine.integrate`.
    rounding : bool
        Run the splitting's rounding twins (False: Richardson's truncation part alone, for
        choosing a step, which cannot lower the rounding part).
    """

    def __init__(
        self,
        engine: Engine,
        omega0,
        q0,
        times,
        *,
        method="dop853",
        rtol=1e-10,
        step=None,
        order=6,
        attitude=True,
        estimate=True,
        backend="auto",
        rounding=True,
    ):
        times = np.asarray(times, dtype=float).reshape(-1)
        self.method = method
        self.order = order
        split = method == "splitting"
        kw = dict(method=method, order=order, attitude=attitude, backend=backend)
        self.main = engine.propagator(
            omega0, q0, times[0], rtol=rtol, step=step, multiple=2 if (estimate and split) else 1, **kw
        )
        self.comp = None
        loose = dict(rtol=None if rtol is None else min(10 * rtol, 1e-3), step=None if step is None else 2 * step)
        if estimate:
            self.comp = engine.propagator(omega0, q0, times[0], **loose, **kw)
        self.acc = ErrorAccumulator(engine.n, 1.0 if method == "dop853" else 1.0 / (2**order - 1))
        self.twins = []
        if estimate and split and rounding:
            self.twins = [
                engine.propagator(omega0, q0, times[0], **loose, **kw, jitter=ROUNDING_GAIN * EPS, jitter_seed=seed)
                for seed in ROUNDING_SEEDS
            ]
        self.twin_accs = [ErrorAccumulator(engine.n, 1.0) for _ in self.twins]

    def advance(self, t_out):
        """(omega, q) of the main run at ``t_out`` (body frame), advancing the companions alongside."""
        w, q = self.main.advance(t_out)
        if self.comp is not None:
            wc, qc = self.comp.advance(t_out)
            self.acc.add(w, wc, q, qc)
            for twin, acc in zip(self.twins, self.twin_accs):
                wt, qt = twin.advance(t_out)
                acc.add(wc, wt, qc, qt)
        return w, q

    def error(self) -> ErrorEstimate | None:
        """The estimate so far (None without companions)."""
        if self.comp is None:
            return None
        how = error_estimate_method(self.method, self.order)
        if not self.twins:
            return self.acc.result(how)
        return self.acc.with_rounding(self.twin_accs, how)

    def stats(self):
        return self.main.stats()


def error_estimate_method(method, order) -> str:
    """How a run's global error was estimated, in words (for the output's attributes)."""
    if method == "dop853":
        return "difference from a companion run at 10 times the tolerance (an upper bound)"
    return (
        f"Richardson: difference from a companion run at twice the step, / (2^{order} - 1), and in quadrature "
        "the rounding floor: the companion's difference from two twins with extra rounding noise"
    )


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
        atol[:, :3] = ((rtol * COMPONENT_FLOOR + 32 * EPS) * char)[:, None]
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
    def __init__(self, engine: Engine, w, q, t0, step, order, attitude, multiple=1, jitter=0.0, jitter_seed=0):
        self.engine = engine
        self.attitude = attitude
        self.scalar = engine.scalar
        noise = _Jitter(jitter, jitter_seed) if jitter else None
        if self.scalar:
            state = (tuple(float(x) for x in w[0]), None if q is None else tuple(float(x) for x in q[0]))
            drift = engine.drift_one if noise is None else noise.one(engine.drift_one)
            self.solver = Splitting(drift, engine.kick_one, t0, state, order=order, step=step, multiple=multiple)
        else:
            drift = engine.drift if noise is None else noise.many(engine.drift)
            self.solver = Splitting(drift, engine.kick, t0, (w, q), order=order, step=step, multiple=multiple)

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


def simulate(
    moments,
    omega0,
    q0,
    t,
    torques=(),
    *,
    method="dop853",
    rtol=1e-10,
    step=None,
    order=6,
    attitude=True,
    estimate=True,
    backend="auto",
):
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
    return engine.integrate(
        omega0,
        q0,
        t,
        method=method,
        rtol=rtol,
        step=step,
        order=order,
        attitude=attitude,
        estimate=estimate,
        backend=backend,
    )
