"""Scenes and the rule "model only what a scene needs" (SI float64).

A :class:`Scene` says what is simulated: a body, initial states (one or an
ensemble), torques, output times, the accuracy wanted and the outputs wanted.
:func:`choose_model` walks the table :data:`CANDIDATES`, cheapest first, and
takes the first model that applies to the scene and can reach its accuracy:

0. ``averaged-precession`` -- the scene asks only for ``mean_precession_rate``
   and every torque is a third body on a Keplerian orbit: the first-order
   averaged rate of :mod:`wobble.models.precession_averaged` (no integration;
   model only what the scene needs).
1. ``free-symmetric`` -- no torque, two equal principal moments: the closed
   form of notes section 5.6 (:func:`wobble.models.free.free_rotation`).
2. ``free-elliptic`` -- no torque: Jacobi elliptic functions and the exact
   attitude (Landau & Lifshitz section 37).
3. ``heavy-top`` -- a symmetric body (I1 = I2 about body axis 3) under
   uniform gravity about a pivot on that axis, and nothing else: the exact
   heavy top of :mod:`wobble.models.top` (notes 5.7), a hanging top included
   (body axes turned by pi about axis 1).
4. ``splitting`` -- every torque kicks exactly (depends on time and attitude
   only, or is linear damping) and pilot runs predict it takes less time than
   DOP853: Touma & Wisdom's splitting (exact free flow between kicks). The
   prediction is the calls each pilot counted times a measured cost per call of
   the path that makes them (:data:`CALL_COST`): the compiled DOP853 costs
   ~0.15 us an evaluation, the splitting's exact flow in Python floats ~50 us a
   stage, so the splitting must take hundreds of times fewer calls.
5. ``dop853`` -- anything: adaptive Runge-Kutta on Euler's equations.

(An ensemble -- several members in one scene -- uses the vectorised flow map
for the free candidates: :func:`wobble.models.free_flow.free_flow` from t0 to every
output time.)

The choice, the reason and the error estimate are recorded in the
:class:`RunRecord`. A forced model (``--model``) must apply to the scene.
The numerical models pick their tolerance or step from the accuracy, run with
a companion (see :mod:`wobble.models.engine`), and tighten and rerun when the
estimate exceeds the accuracy; an integrator the chooser took that still misses
it hands over to the other one (the reason says so); an accuracy that no model
can reach is an :class:`~wobble.errors.InputError` naming the ``accuracy`` field.

Outputs are computed block by block in time and handed to a *sink* (the
caller's: an in-memory collector, or a streaming netCDF writer), so that a
run whose output exceeds memory never holds it all.
"""

from __future__ import annotations

import functools
import math
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from wobble.numerics.floats import EPS
from wobble.errors import FileFormatError, InputError
from wobble.models import engine as eng
from wobble.models import free as _free
from wobble.models.free_flow import flow_sorted
from wobble.numerics import compiled as compiled_kernels
from wobble.numerics import quaternion as quat

__all__ = [
    "Scene",
    "Candidate",
    "Choice",
    "RunRecord",
    "CANDIDATES",
    "OUTPUTS",
    "SUMMARY_OUTPUTS",
    "ALL_OUTPUTS",
    "ATTITUDE_OUTPUTS",
    "ModelUnavailable",
    "choose_model",
    "execute",
    "derived_outputs",
    "MODEL_NAMES",
    "CALL_COST",
    "KIND_COST",
    "call_seconds",
]

#: Every time-series output a scene may ask for (names of the netCDF variables).
OUTPUTS = (
    "omega",
    "attitude",
    "angular_momentum",
    "angular_momentum_magnitude",
    "kinetic_energy",
    "potential_energy",
    "total_energy",
    "axis_direction",
    "tilt",
    "wobble_angle",
)
#: Outputs that summarise the whole run (one value per member, no time series): they come
#: from the averaged model, alone.
SUMMARY_OUTPUTS = frozenset({"mean_precession_rate"})
#: Every name a scene's ``outputs`` may hold.
ALL_OUTPUTS = OUTPUTS + tuple(sorted(SUMMARY_OUTPUTS))
#: Outputs that need the attitude.
ATTITUDE_OUTPUTS = frozenset(
    {"attitude", "angular_momentum", "axis_direction", "tilt", "potential_energy", "total_energy"}
)
# Integrators are not asked for less than this (relative): rounding over a run.
_INTEGRATOR_FLOOR = 1e-13
_MAX_ATTEMPTS = 5


class ModelUnavailable(Exception):
    """A candidate model applies to the scene but cannot be built here (e.g. missing module)."""


@dataclass(frozen=True)
class Scene:
    """A simulation request in SI (see docs/scenes.md for the file form).

    Attributes
    ----------
    body : wobble.models.engine.BodyModel
        One body, or one per member.
    omega0 : numpy.ndarray (N, 3)
        Initial body-frame angular velocities (rad/s).
    attitude0 : numpy.ndarray (N, 4)
        Initial attitudes, unit quaternions body -> inertial.
    torques : tuple
        Torque specifications (:mod:`wobble.models.engine`).
    times : numpy.ndarray (T,)
        Increasing output times (s); the run starts at ``times[0]``.
    accuracy : float
        Wanted bound on each omega component's error relative to that
        component's largest value, and on the attitude angle (rad).
    outputs : tuple of str
        Names from :data:`ALL_OUTPUTS`.
    ensemble : bool
        Whether the outputs carry a ``member`` dimension.
    name, title, description : str
    epoch : str or None
        ISO date-time of t = 0 (UTC) for the CF time units; None: nominal.
    source : str or None
        The scene file, for error messages naming it.
    mapping : dict
        The scene as a plain mapping (recorded in output files).
    """

    body: eng.BodyModel
    omega0: np.ndarray
    attitude0: np.ndarray
    torques: tuple
    times: np.ndarray
    accuracy: float = 1e-9
    outputs: tuple = ("omega", "attitude")
    ensemble: bool = False
    name: str = "scene"
    title: str = ""
    description: str = ""
    epoch: str | None = None
    source: str | None = None
    mapping: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def members(self) -> int:
        """N, the number of initial states."""
        return int(self.omega0.shape[0])

    @property
    def needs_attitude(self) -> bool:
        """Whether an output asked for needs the attitude."""
        return bool(ATTITUDE_OUTPUTS & set(self.outputs))

    def error(self, key: str, value, allowed: str) -> Exception:
        """An error about field ``key``: FileFormatError for a scene file, else InputError."""
        if self.source:
            return FileFormatError(self.source, key, f"got {value!r}; allowed: {allowed}")
        return InputError(key, value, allowed)


# --------------------------------------------------------------------------
# Model runs: what a chosen candidate produces
# --------------------------------------------------------------------------
class _ModelRun:
    """Produces (omega, attitude) block by block; knows its error estimate."""

    name = ""
    settings: dict = {}

    def blocks(self, times, block):  # pragma: no cover - interface
        raise NotImplementedError

    def error_estimate(self) -> dict:  # pragma: no cover - interface
        raise NotImplementedError


def _blocks_of(times, block):
    for start in range(0, times.size, block):
        yield times[start : start + block]


class _FreeSingle(_ModelRun):
    """One member, exact: :func:`wobble.models.free.free_rotation` composed with the initial attitude."""

    def __init__(self, scene: Scene, name: str):
        self.name = name
        self.scene = scene
        body = scene.body
        self.axes = np.asarray(body.axes).reshape(3, 3)
        w_principal = self.axes @ scene.omega0[0]
        self.model = _free.free_rotation(np.asarray(body.moments).reshape(3), w_principal)
        self.q_axes = quat.from_matrix(self.axes.T)  # principal -> body
        self.settings = {"regime": self.model.regime}

    def blocks(self, times, block):
        t0 = self.scene.times[0]
        q0 = self.scene.attitude0[0]
        for tb in _blocks_of(times, block):
            w_p = self.model.omega(tb - t0)
            w = (w_p @ self.axes)[:, None, :]
            q = None
            if self.scene.needs_attitude:
                # q(t) = q0 * Qa * A(t) * Qa^-1, A the principal-frame attitude with A(0) = 1.
                a = self.model.attitude(tb - t0)
                q = quat.multiply(q0, quat.multiply(self.q_axes, quat.multiply(a, quat.conjugate(self.q_axes))))
                q = quat.normalize(q)[:, None, :]
            yield tb, w, q

    def error_estimate(self):
        e = self.model.error_estimate
        return {
            "omega_relative": float(e["omega_relative"]),
            "attitude_rad": float(e["attitude_rad"]),
            "method": "a priori bound of the exact solution (elliptic functions in double-double arithmetic)",
        }


class _FreeEnsemble(_ModelRun):
    """N members, exact flow map from t0 to every output time (vectorised)."""

    def __init__(self, scene: Scene, name: str):
        self.name = name
        self.scene = scene
        self.engine = eng.Engine(scene.body, (), members=scene.members)
        self.w0, self.q0 = self.engine.state_in(scene.omega0, scene.attitude0)
        self.settings = {"evaluation": "exact flow map from t0, vectorised over members and times"}

    def blocks(self, times, block):
        n = self.scene.members
        t0 = self.scene.times[0]
        attitude = self.scene.needs_attitude
        moments = np.broadcast_to(self.engine.moments, (n, 3))
        for tb in _blocks_of(times, max(1, block)):
            T = tb.size
            I = np.broadcast_to(moments, (T, n, 3)).reshape(-1, 3)
            w = np.broadcast_to(self.w0, (T, n, 3)).reshape(-1, 3)
            h = np.repeat(tb - t0, n)
            w1, dq = flow_sorted(I, w, h, attitude=attitude)
            w1 = w1.reshape(T, n, 3)
            q = None
            if attitude:
                q = quat.normalize(quat.multiply(np.broadcast_to(self.q0, (T, n, 4)), dq.reshape(T, n, 4)))
            wo, qo = self.engine.state_out(w1, q)
            yield tb, wo, qo

    def error_estimate(self):
        bound = _free_ensemble_bound(self.scene)
        return {
            "omega_relative": bound,
            "attitude_rad": bound,
            "method": "a priori bound of the exact flow map (float phase)",
        }


class _Numerical(_ModelRun):
    """DOP853 or the splitting, with a companion run for the error estimate."""

    def __init__(self, scene: Scene, method: str, settings: dict, rounding: bool = True):
        self.scene = scene
        self.method = method
        self.rounding = rounding
        self.name = method if method == "dop853" else f"splitting-{settings['order']}"
        self.settings = dict(settings)
        self.engine = eng.Engine(scene.body, scene.torques, members=scene.members)
        self._run = None
        self._stats = {}

    def blocks(self, times, block):
        s = self.scene
        if self.method == "dop853":
            kw = dict(rtol=self.settings["rtol"])
        else:
            kw = dict(rtol=None, step=self.settings["step_s"], order=self.settings["order"])
        self._run = eng.CheckedRun(
            self.engine,
            s.omega0,
            s.attitude0,
            times,
            method=self.method,
            attitude=s.needs_attitude,
            rounding=self.rounding,
            **kw,
        )
        for tb in _blocks_of(times, block):
            w, q = self._run.advance(tb)
            yield tb, w, q
        self._stats = self._run.stats()

    def error_estimate(self):
        e = self._run.error()
        out = {
            "omega_relative": float(np.max(e.omega_relative)),
            "attitude_rad": float(np.max(e.attitude)),
            "method": e.method,
        }
        if e.rounding is not None:
            out["rounding"] = float(np.max(e.rounding))
        return out

    def stats(self):
        return dict(self._stats)


class _AveragedRun(_ModelRun):
    """The first-order averaged precession (:mod:`wobble.models.precession_averaged`): no time series."""

    name = "averaged-precession"

    def __init__(self, scene: Scene):
        from wobble.models.precession_averaged import averaged_precession

        self.scene = scene
        self.model = averaged_precession(scene.body, scene.omega0, scene.attitude0, scene.torques)
        self.settings = {
            "dynamical_flattening": [float(x) for x in self.model.dynamical_flattening],
            "obliquity_rad": [float(x) for x in self.model.obliquity],
            "perturbers": [p.name for p in self.model.perturbers],
        }

    def summary(self):
        """(time (1,): the middle of the span, outputs {name: (1, N)})."""
        t = self.scene.times
        return np.array([0.5 * (t[0] + t[-1])]), {"mean_precession_rate": self.model.rate[None, :]}

    def error_estimate(self):
        return {
            "omega_relative": self.model.error,
            "attitude_rad": 0.0,
            "method": "a priori: the precession rate over the fastest motion averaged over (first-order averaging)",
        }


def _applies_averaged(scene):
    from wobble.models.precession_averaged import averaging_applies

    if not set(scene.outputs) <= SUMMARY_OUTPUTS:
        return "the scene asks for the motion (" + ", ".join(o for o in scene.outputs if o not in SUMMARY_OUTPUTS) + ")"
    return averaging_applies(scene.body, scene.omega0, scene.attitude0, scene.torques)


def _floor_averaged(scene):
    from wobble.models.precession_averaged import averaging_applies

    if averaging_applies(scene.body, scene.omega0, scene.attitude0, scene.torques) is not None:
        return np.inf
    return _AveragedRun(scene).model.error


def _check_summary_outputs(scene, force):
    """A scene asking for the mean precession rate gets the averaged model, alone, or an error saying why."""
    summary = SUMMARY_OUTPUTS & set(scene.outputs)
    if not summary:
        return
    name = sorted(summary)[0]
    if set(scene.outputs) - SUMMARY_OUTPUTS:
        raise scene.error(
            "outputs",
            list(scene.outputs),
            f"{name} alone (the averaged model), or the motion (axis_direction, angular_momentum) "
            "without it: measure the rate from the motion with wobble.measure_precession",
        )
    if force not in (None, "averaged-precession"):
        raise InputError("model", force, f"averaged-precession for a scene whose only output is {name}")
    from wobble.models.precession_averaged import averaging_applies

    why = averaging_applies(scene.body, scene.omega0, scene.attitude0, scene.torques)
    if why is not None:
        raise scene.error(
            "outputs",
            list(scene.outputs),
            f"{name} from the averaged model, which does not apply here ({why}); ask for "
            "angular_momentum and measure it with wobble.measure_precession",
        )
    floor = _floor_averaged(scene)
    if scene.accuracy < floor:
        raise scene.error(
            "accuracy",
            scene.accuracy,
            f"at least {floor:.3g} for {name} from first-order averaging (integrate the motion and "
            "measure it with wobble.measure_precession for more)",
        )


# --------------------------------------------------------------------------
# The candidate table
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class Candidate:
    """A model the chooser may pick.

    Attributes
    ----------
    name : str
    kind : {"averaged", "exact", "numerical"}
    applies : callable
        ``applies(scene) -> str | None``: None when the model applies, else
        why not (recorded in the reason when a later model is chosen).
    build : callable
        ``build(scene) -> model run``; may raise :class:`ModelUnavailable`.
    floor : callable
        ``floor(scene) -> float``: the best accuracy the model can promise.
    summary : str
        One line for the reason and the docs.
    detail : callable or None
        ``detail(scene) -> str``, added to the summary when the chooser picked the model
        (not when it was forced): the predicted seconds that decided between the integrators.
    """

    name: str
    kind: str
    applies: Callable
    build: Callable
    floor: Callable
    summary: str
    detail: Callable | None = None


def _torque_free(scene: Scene) -> bool:
    """No torque, or only torques that are exactly zero."""
    for t in scene.torques:
        if isinstance(t, eng.ConstantTorque) and not np.any(np.asarray(t.torque)):
            continue
        if isinstance(t, eng.LinearDamping) and not np.any(np.asarray(t.coefficient)):
            continue
        return False
    return True


def _symmetric(scene: Scene) -> bool:
    m = np.asarray(scene.body.moments).reshape(-1, 3)
    s = np.sort(m, axis=-1)
    return bool(np.all((s[:, 0] == s[:, 1]) | (s[:, 1] == s[:, 2])))


def _applies_free_symmetric(scene):
    if not _torque_free(scene):
        return "torques act"
    if not _symmetric(scene):
        return "no two principal moments are equal"
    return None


def _applies_free(scene):
    return None if _torque_free(scene) else "torques act"


def _build_free(name):
    def build(scene):
        if _exact_single(scene):
            return _FreeSingle(scene, name)
        return _FreeEnsemble(scene, name)

    return build


def _exact_single(scene) -> bool:
    """Whether one member takes free_rotation's exact solution: a span within its reach
    (FreeRotationModel.max_time); else the flow map, whose float phase states its own growing bound.
    The separatrix, entered with either sign of omega_a, is among the exact solutions."""
    if scene.members != 1:
        return False
    body = scene.body
    model = _free.free_rotation(
        np.asarray(body.moments).reshape(3), np.asarray(body.axes).reshape(3, 3) @ scene.omega0[0]
    )
    return float(np.max(np.abs(scene.times - scene.times[0]))) <= model.max_time


def _free_ensemble_bound(scene) -> float:
    """A float phase lambda t carries eps * lambda t (docs/engine.md; tests/test_free_flow.py)."""
    span = float(np.max(np.abs(scene.times - scene.times[0])))
    rate = float(np.max(np.linalg.norm(scene.omega0, axis=-1)))
    return 64 * EPS * (1.0 + rate * span)


def _floor_free(scene):
    if _exact_single(scene):
        e = _FreeSingle(scene, "free").error_estimate()
        return max(e["omega_relative"], e["attitude_rad"])
    return _free_ensemble_bound(scene)


def _heavy_top_geometry(scene):
    """(I1, I3, Mgl) when the scene is a symmetric top on a pivot under uniform gravity, else a reason."""
    gravity = [t for t in scene.torques if isinstance(t, eng.UniformGravity)]
    others = [t for t in scene.torques if not isinstance(t, eng.UniformGravity)]
    if len(gravity) != 1 or any(not _zero_torque(t) for t in others):
        return None, "not a single uniform-gravity torque"
    if scene.members != 1:
        return None, "an ensemble (the exact top is built per member; ensembles integrate)"
    g = gravity[0]
    axes = np.asarray(scene.body.axes).reshape(3, 3)
    m = np.asarray(scene.body.moments).reshape(3)
    tensor = axes.T @ np.diag(m) @ axes  # body frame
    if not (tensor[0, 0] == tensor[1, 1] and tensor[0, 1] == 0 and tensor[0, 2] == 0 and tensor[1, 2] == 0):
        return None, "the body is not symmetric about its axis 3 (I1 = I2, axis 3 principal)"
    r = np.asarray(g.center_of_mass, dtype=float).reshape(3)
    if r[0] != 0 or r[1] != 0:
        return None, "the centre of mass is off the symmetry axis"
    grav = np.asarray(g.gravity, dtype=float).reshape(3)
    if grav[0] != 0 or grav[1] != 0:
        return None, "gravity is not along the inertial z axis"
    # M g l with l the signed position of the centre of mass on axis 3 (negative: a hanging top)
    mgl = float(np.asarray(g.mass).reshape(-1)[0]) * (-grav[2]) * r[2]
    return (float(tensor[0, 0]), float(tensor[2, 2]), mgl), None


def _zero_torque(t):
    return (isinstance(t, eng.ConstantTorque) and not np.any(np.asarray(t.torque))) or (
        isinstance(t, eng.LinearDamping) and not np.any(np.asarray(t.coefficient))
    )


def _applies_heavy_top(scene):
    _, why = _heavy_top_geometry(scene)
    if why is not None:
        return why
    # The closed form holds to 2^50 periods (HeavyTopModel.max_time); a longer span integrates.
    model = _build_heavy_top(scene).model
    span = float(np.max(np.abs(np.asarray(scene.times, dtype=float) - scene.times[0])))
    if span > model.max_time:
        return f"the span, {span:.6g} s, reaches past 2^50 {model.limiting_period[1]} ({model.max_time:.6g} s)"
    return None


def _floor_heavy_top(scene) -> float:
    """What the exact top promises for this scene: its own error estimate, at least 1e-13 (a constant floor
    would hide a set-up whose own estimate is larger)."""
    return max(1e-13, _build_heavy_top(scene).error_estimate()["omega_relative"])  # the larger of its two


def _build_heavy_top(scene):
    """The exact heavy top of ``wobble.models.top`` (notes 5.7) for this scene.

    The engine's conventions are the top's: symmetry axis = body axis 3, pivot
    at the origin, gravity along -z in space, q rotating body to inertial. A
    hanging top (centre of mass at negative body z) is the same top seen with
    body axes turned by pi about axis 1, so that axis 3 points to the centre of
    mass: omega' = (w1, -w2, -w3), q' = q (x) (0, 1, 0, 0); :class:`_TopRun` turns back.
    """
    (i1, i3, mgl), _ = _heavy_top_geometry(scene)
    w0 = np.asarray(scene.omega0[0], dtype=float).reshape(3)
    q0 = np.asarray(scene.attitude0[0], dtype=float).reshape(4)
    flip = mgl < 0
    if flip:
        w0 = w0 * _FLIP_W
        q0 = quat.multiply(q0, _FLIP_Q)
    # Keyed by the floats' bits (hex): -0.0 == 0.0 would share a key, while the set-up's atan2 sees a zero's
    # sign; a run must not take another scene's model, whatever ran before it.
    key = tuple(float(v).hex() for v in (i1, i3, abs(mgl), *w0.tolist(), *q0.tolist()))
    return _TopRun(_exact_top(key), scene, flip)


@functools.lru_cache(maxsize=16)
def _exact_top(key: tuple[str, ...]):
    """The exact top from its state (I1, I3, M g l, omega0, q0 as float.hex strings), kept for the few calls
    of one model choice: the chooser asks whether it applies (its span), what it promises (its estimate) and
    then runs it, and each set-up takes some 10 ms of 60-digit arithmetic. The model is immutable."""
    from wobble.models import top

    i1, i3, mgl, *state = (float.fromhex(v) for v in key)
    return top.heavy_top_from_state(i1, i3, mgl, np.array(state[:3]), np.array(state[3:]))


_FLIP_W = np.array([1.0, -1.0, -1.0])
_FLIP_Q = np.array([0.0, 1.0, 0.0, 0.0])


class _TopRun(_ModelRun):
    """Adapter for the exact heavy top (:func:`wobble.models.top.heavy_top_from_state`)."""

    name = "heavy-top"

    def __init__(self, model, scene, flip=False):
        self.model = model
        self.scene = scene
        self.flip = flip
        self.settings = {}

    def blocks(self, times, block):
        t0 = self.scene.times[0]
        for tb in _blocks_of(times, block):
            w, q = self.model.evaluate(tb - t0)
            w, q = np.asarray(w), np.asarray(q)
            if self.flip:  # back to the scene's body axes (see _build_heavy_top)
                w = w * _FLIP_W
                q = quat.multiply(q, quat.conjugate(_FLIP_Q))
            yield tb, w[:, None, :], q[:, None, :]

    def error_estimate(self):
        e = self.model.error_estimate
        # The top bounds theta and the attitude angle; omega is built from the same angles
        # and rates, so its relative error is of the larger of the two.
        worst = max(float(e["theta_rad"]), float(e["attitude_rad"]))
        return {"omega_relative": worst, "attitude_rad": float(e["attitude_rad"]), "method": "exact heavy top"}


# --------------------------------------------------------------------------
# Numerical models: settings from a pilot run, cost in predicted seconds
# --------------------------------------------------------------------------
# The pilots count calls: DOP853 evaluations of Euler's equations (one per member), splitting
# stages (a kick and an exact free drift of all members). What a call costs depends on the path
# that makes it, by two orders of magnitude: the DOP853 runs compiled (every built-in torque,
# Numba installed: wobble.numerics.rigid_dop853), the splitting never does (its exact flow runs
# in Python floats for one member, NumPy for an ensemble). Counting calls alone took the
# splitting for satellite_gravity_gradient (238,434 stages at ~50 us: 11 s) over the compiled
# DOP853 (295,000 evaluations at ~0.15 us: 0.05 s). So each path has a measured cost per call,
# and a plan's cost is its calls times that: predicted seconds of the run and its companion
# (not the start-up, the pilots or the writing). Measured with scripts/calibrate_chooser.py on
# the shipped torqued scenes (2 CPUs, min over repeats; the table is in docs/engine.md), in us
# per call with n members:
#
#   path                          model          measured
#   dop853 compiled               0.15 n         0.17 (n = 1), 0.06-0.11 n (n = 1000, 10^4; threads)
#   dop853 Python floats (n = 1)  18             16.9-19.7
#   dop853 NumPy                  100 + 0.15 n   101-178 (n = 100), 224-271 (n = 1000)
#   splitting Python floats       50             42.9-56.8; 45.0-47.7 (2026-11-30, 82.6 before flow_one's float test)
#   splitting NumPy               600 + 1.5 n    460-580 (n = 10), 1370-2420 (n = 1000), 10600-18500 (n = 10^4)
#
# and per third body on a Keplerian orbit (Kepler's equation at every call; earth_precession's
# two): 0.12 n compiled (0.39 n measured for both), 4.5 Python floats (26.3 for both), 50 + 0.2 n
# NumPy (737 for both at n = 1000) and 5 per splitting stage in Python floats (60.7 for both);
# the other kinds cost the same within the spread. The choice needs them within a factor of a
# few: the compiled DOP853 and the splitting differ by 300 per call for one member, 10 to 15 for
# large ensembles.
@dataclass(frozen=True)
class _CallCost:
    """Microseconds per call: ``fixed + per_member * members``."""

    fixed: float
    per_member: float

    def us(self, members: int) -> float:
        return self.fixed + self.per_member * members


#: Cost of one call on each path (see the table above).
CALL_COST = {
    "dop853 compiled": _CallCost(0.0, 0.15),
    "dop853 Python floats": _CallCost(18.0, 0.0),
    "dop853 NumPy": _CallCost(100.0, 0.15),
    "splitting Python floats": _CallCost(50.0, 0.0),
    "splitting NumPy": _CallCost(600.0, 1.5),
}
#: Added per torque of a kind, on each path (kinds not listed add nothing measurable).
KIND_COST = {
    "third_body": {
        "dop853 compiled": _CallCost(0.0, 0.12),
        "dop853 Python floats": _CallCost(4.5, 0.0),
        "dop853 NumPy": _CallCost(50.0, 0.2),
        "splitting Python floats": _CallCost(5.0, 0.0),
    }
}


def _rk_path(engine) -> str:
    """The DOP853 path a run takes: the engine's own rule (``backend="auto"``)."""
    if engine.compilable and compiled_kernels.available():
        return "dop853 compiled"
    return "dop853 Python floats" if engine.scalar else "dop853 NumPy"


def _split_path(engine) -> str:
    return "splitting Python floats" if engine.scalar else "splitting NumPy"


def call_seconds(engine, path: str) -> float:
    """Predicted seconds of one call on ``path`` (an evaluation or a stage, all members)."""
    n = engine.n
    us = CALL_COST[path].us(n)
    for spec in engine.specs:
        extra = KIND_COST.get(spec.kind, {}).get(path)
        if extra is not None:
            us += extra.us(n)
    return 1e-6 * us


_PILOT_FRACTION = 1.0 / 16.0
# Aim the full run at this fraction of the accuracy: errors may grow faster than linearly.
_PILOT_SAFETY = 0.1
_C_SPLIT = {2: 5e-2, 4: 1e-2, 6: 2e-3}  # error ~ C (h nu)^p (1 + nu T): a first guess only


@dataclass
class _Plan:
    """Settings for the whole run and its predicted cost, from a pilot over part of the span.

    ``seconds`` is the run's with its companion on ``path``, from the pilot's counted calls
    (:data:`CALL_COST`); ``complete`` is False for a splitting plan whose piloting stopped once
    its cost passed DOP853's (``seconds`` is then a lower bound and the settings are not final).
    """

    method: str
    settings: dict
    seconds: float
    pilot_error: float
    path: str = ""
    calls: float = 0.0
    complete: bool = True


def _pilot_times(scene):
    t0, t1 = float(scene.times[0]), float(scene.times[-1])
    span = t1 - t0
    tp = span * _PILOT_FRACTION if scene.times.size > 16 else span
    return np.linspace(t0, t0 + tp, 9), span, tp


def _pilot(scene, method, settings):
    """Run the model with a companion over the pilot span: (worst estimate, stats)."""
    sub = Scene(
        body=scene.body,
        omega0=scene.omega0,
        attitude0=scene.attitude0,
        torques=scene.torques,
        times=_pilot_times(scene)[0],
        accuracy=scene.accuracy,
        outputs=scene.outputs,
        ensemble=scene.ensemble,
    )
    # The pilots choose a step from the truncation: the splitting's rounding floor (its twins) cannot
    # be lowered by a shorter step, and over the pilot's span it would only drive the step down.
    run = _Numerical(sub, method, settings, rounding=False)
    for _ in run.blocks(sub.times, sub.times.size):
        pass
    e = run.error_estimate()
    return max(e["omega_relative"], e["attitude_rad"]), run.stats()


def _plan_dop853(scene) -> _Plan:
    engine = eng.Engine(scene.body, scene.torques, members=scene.members)
    _, span, tp = _pilot_times(scene)
    rtol0 = float(min(max(scene.accuracy / 100.0, 1e-13), 1e-4))
    err, stats = _pilot(scene, "dop853", {"rtol": rtol0})
    growth = span / tp if tp > 0 else 1.0
    err_full = err * growth
    rtol = rtol0 if err_full <= 0 else rtol0 * _PILOT_SAFETY * scene.accuracy / err_full
    rtol = float(min(max(rtol, 1e-13), 1e-3, 100 * rtol0))
    # Evaluations per member over the whole run (DOP853's steps grow like rtol^(-1/8)); the
    # companion at 10 rtol adds 10^(-1/8) = 0.75 of them.
    evals = stats.get("function_evaluations", 1) / max(scene.members, 1)
    calls = 1.75 * evals * growth * (rtol0 / rtol) ** (1.0 / 8.0)
    path = _rk_path(engine)
    return _Plan("dop853", {"rtol": rtol}, calls * call_seconds(engine, path), err, path, calls)


def _split_steps(scene, h) -> float:
    """Composition steps of the main run at step h (an even number in each output interval)."""
    gaps = np.diff(scene.times)
    return float(np.sum(2 * np.ceil(gaps[gaps > 0] / (2 * h) * (1 - 1e-12)))) if gaps.size else 0.0


def _plan_splitting(scene, budget: float | None = None) -> _Plan:
    """The splitting's step from pilots, and its predicted seconds.

    ``budget`` (DOP853's predicted seconds, when the chooser compares): once a pilot has failed
    (the step can only shrink from there, and the cost only grow) and the run at the next step
    would cost more than that, piloting stops: the plan is incomplete and DOP853 is cheaper.
    """
    engine = eng.Engine(scene.body, scene.torques, members=scene.members)
    order = 6 if scene.accuracy < 1e-6 else 4
    _, span, tp = _pilot_times(scene)
    nu = engine.torque_rate(scene.omega0, scene.attitude0, scene.times[0])
    path = _split_path(engine)
    if not scene.torques:
        # No torque: every composition is exact (its drifts are the exact free flow), so the
        # shortest one costs least (Strang: 2 drifts a step instead of 8 to 14; a century of
        # daily Earth outputs forced onto the splitting took minutes with order 6).
        order = 2
    stages = len(_composition_stages(order))
    per_call = call_seconds(engine, path)

    def cost(h):  # the main run (1), its companion at twice the step (0.5) and two rounding twins of it (0.5 each)
        calls = 2.5 * _split_steps(scene, h) * stages
        return calls * per_call, calls

    def pilot_cost(h):  # a pilot over tp with its companion (no rounding twins)
        return 1.5 * math.ceil(tp / h) * stages * per_call

    complete = True
    if nu <= 0 or span <= 0:
        h = max(span, 1.0)
        err = 0.0
    else:
        h = (scene.accuracy / (_C_SPLIT[order] * (1.0 + nu * span))) ** (1.0 / order) / nu
        h = float(min(h, span))
        growth = span / tp if tp > 0 else 1.0
        goal = _PILOT_SAFETY * scene.accuracy / growth  # the pilot's share of the accuracy
        h_ok, err = None, 0.0
        # The rate nu is a rough guess (a spinning symmetric body feels its torque far
        # less than nu says): pilot; grow the step while the estimate allows, shrink
        # it (at least halving, so that a step that resonates with the spin is left
        # behind) until it passes.
        for _ in range(12):
            if budget is not None and pilot_cost(h) > budget:
                # One pilot at this step would cost more than the whole run by the other integrator: a first guess
                # of 1e-4 s, doubled pilot by pilot, took 10 s where DOP853 took 0.6 (review finding). The pilots
                # shrinking the step cost more each time, so their sum stays below about twice the budget.
                complete = False
                break
            e, _ = _pilot(scene, "splitting", {"order": order, "step_s": h})
            if e <= goal:
                h_ok, err = h, e
                if e * 2.0**order < goal and h < span:
                    h = float(min(2.0 * h, span))
                    continue
                break
            if h_ok is not None:
                break
            factor = (goal / e) ** (1.0 / order)
            h *= min(0.5, factor)
            if h < 1e-7 * span:  # more than 10^7 steps: leave it to DOP853
                break
            if budget is not None and cost(h)[0] > budget:
                complete = False  # already dearer than DOP853, and only shorter steps remain
                break
        h = h_ok if h_ok is not None else h
    seconds, calls = cost(h)
    return _Plan("splitting", {"order": order, "step_s": h}, seconds, err, path, calls, complete)


def _composition_stages(order):
    from wobble.numerics.integrators import COMPOSITIONS

    return COMPOSITIONS[order]


_PLAN_CACHE: dict = {}
# Guards the cache's entries (not the pilots): two threads evicting at once popped the same key or read
# one just evicted (KeyError).
_PLAN_LOCK = threading.Lock()


def _plans(scene, only=None):
    """Pilot both integrators where they apply, or ``only`` one (memoised per scene object).

    With both, DOP853 is piloted first and its predicted seconds bound the splitting's piloting
    (:func:`_plan_splitting`); a splitting plan cut short that way is redone in full when the
    splitting itself is asked for (``only="splitting"``: a forced model).
    """
    key = id(scene)
    with _PLAN_LOCK:
        entry = _PLAN_CACHE.get(key)
        if entry is None or entry[0] is not scene:
            while len(_PLAN_CACHE) >= 8:
                _PLAN_CACHE.pop(next(iter(_PLAN_CACHE)))
            entry = _PLAN_CACHE[key] = (scene, {})
    cache = entry[1]
    if only in (None, "dop853") and "dop853" not in cache:
        cache["dop853"] = _plan_dop853(scene)
    if only in (None, "splitting"):
        current = cache.get("splitting")
        if current is None or (only == "splitting" and not current.complete):
            if eng.Engine(scene.body, scene.torques, members=scene.members).splittable:
                budget = cache["dop853"].seconds if only is None else None
                cache["splitting"] = _plan_splitting(scene, budget)
    return cache


def _seconds(plan: _Plan) -> str:
    """``0.044 s (compiled)``: a plan's predicted seconds and the path that makes its calls."""
    return f"{'at least ' if not plan.complete else ''}{plan.seconds:.2g} s ({plan.path.split(' ', 1)[1]})"


def _applies_splitting(scene, *, forced=False):
    engine = eng.Engine(scene.body, scene.torques, members=scene.members)
    if not engine.splittable:
        return "a torque depends on omega (other than linear damping): its kick has no exact solution"
    if forced:
        return None
    plans = _plans(scene)
    split, rk = plans["splitting"], plans["dop853"]
    if not (split.complete and split.seconds < rk.seconds):
        return f"pilot runs predict {_seconds(split)} against {_seconds(rk)} for dop853"
    return None


def _detail_splitting(scene):
    plans = _plans(scene)
    return f" (pilot runs predict {_seconds(plans['splitting'])} against {_seconds(plans['dop853'])} for dop853)"


def _detail_dop853(scene):
    return f" (pilot run predicts {_seconds(_plans(scene, 'dop853')['dop853'])})"


def _integrator_floor(scene):
    return _INTEGRATOR_FLOOR


def _build_splitting(scene, settings=None):
    if settings is None:
        settings = _plans(scene, "splitting")["splitting"].settings
    return _Numerical(scene, "splitting", settings)


def _build_dop853(scene, settings=None):
    if settings is None:
        settings = _plans(scene, "dop853")["dop853"].settings
    return _Numerical(scene, "dop853", settings)


CANDIDATES: tuple[Candidate, ...] = (
    Candidate(
        "averaged-precession",
        "averaged",
        _applies_averaged,
        _AveragedRun,
        _floor_averaged,
        "the scene asks only for the mean precession rate: the first-order averaged torque of the third bodies "
        "(Goldstein, Poole & Safko 2002 sec. 5.8; Woolard 1953; Kinoshita 1977), no integration",
    ),
    Candidate(
        "free-symmetric",
        "exact",
        _applies_free_symmetric,
        _build_free("free-symmetric"),
        _floor_free,
        "closed form for a torque-free symmetric body (Goldstein, Poole & Safko 2002, sec. 5.6)",
    ),
    Candidate(
        "free-elliptic",
        "exact",
        _applies_free,
        _build_free("free-elliptic"),
        _floor_free,
        "Jacobi elliptic functions for a torque-free body (Landau & Lifshitz section 37)",
    ),
    Candidate(
        "heavy-top",
        "exact",
        _applies_heavy_top,
        _build_heavy_top,
        _floor_heavy_top,
        "the exact heavy symmetric top (Goldstein, Poole & Safko 2002, sec. 5.7)",
    ),
    Candidate(
        "splitting",
        "numerical",
        _applies_splitting,
        _build_splitting,
        _integrator_floor,
        "Touma-Wisdom splitting: exact free flow between torque kicks",
        _detail_splitting,
    ),
    Candidate(
        "dop853",
        "numerical",
        lambda s: None,
        _build_dop853,
        _integrator_floor,
        "adaptive Dormand-Prince 8(5,3) on Euler's equations",
        _detail_dop853,
    ),
)
MODEL_NAMES = tuple(c.name for c in CANDIDATES)


@dataclass
class Choice:
    """The chosen candidate, why, and what was passed over; ``forced``: named by ``--model`` or the
    scene's ``model`` key (a forced integrator that misses the accuracy is an error, not a fallback)."""

    candidate: Candidate
    reason: str
    run: _ModelRun
    forced: bool = False


def check_model_name(force: str | None) -> None:
    """Refuse a forced model that is not ``auto`` or one of :data:`MODEL_NAMES` (None: not forced)."""
    if force is not None and force not in MODEL_NAMES and force != "auto":
        allowed = f"auto or one of {', '.join(MODEL_NAMES)}"
        if str(force).startswith("splitting-"):
            # The output names the splitting with its order (splitting-6): say where the order comes from.
            allowed += " (the splitting picks its order: 2 without torques, else 6 for an accuracy below 1e-6, 4 above)"
        raise InputError("model", force, allowed)


def choose_model(scene: Scene, force: str | None = None) -> Choice:
    """Pick the cheapest model that applies and can reach the scene's accuracy.

    ``force`` (``--model``) names the model; None takes the scene's own ``model`` key
    (``"auto"`` when absent), and ``"auto"`` chooses whatever the scene says.

    Raises
    ------
    wobble.errors.InputError
        ``force`` names no model, or one that does not apply (parameter
        ``model``); the accuracy is below what every applicable model can
        reach (the ``accuracy`` field, naming the scene file if any).
    """
    check_model_name(force)
    origin = f"--model {force}"
    if force is None:
        force = scene.mapping.get("model", "auto")
        origin = f'the scene\'s model = "{force}"'
    if force == "auto":
        force = None
    _check_summary_outputs(scene, force)
    passed = []
    best_floor = np.inf
    for cand in CANDIDATES:
        if force is not None and cand.name != force:
            continue
        if cand.kind == "averaged" and not (SUMMARY_OUTPUTS & set(scene.outputs)) and force is None:
            continue  # a scene that asks for the motion is never answered by an average
        if cand.kind == "numerical" and scene.accuracy < cand.floor(scene):
            # (checked before the predicate: the splitting's predicate runs pilots)
            best_floor = min(best_floor, cand.floor(scene))
            passed.append(f"{cand.name}: cannot promise {scene.accuracy:.3g} (best {cand.floor(scene):.3g})")
            continue
        why = _applies_splitting(scene, forced=True) if (force and cand.name == "splitting") else cand.applies(scene)
        if why is not None:
            if force:
                raise InputError("model", force, f"a model that applies to this scene ({cand.name}: {why})")
            passed.append(f"{cand.name}: {why}")
            continue
        floor = cand.floor(scene)
        best_floor = min(best_floor, floor)
        if scene.accuracy < floor:
            passed.append(f"{cand.name}: cannot promise {scene.accuracy:.3g} (best {floor:.3g})")
            continue
        try:
            run = cand.build(scene)
        except ModelUnavailable as exc:
            if force:
                raise InputError("model", force, f"a model available in this build ({exc})") from None
            passed.append(f"{cand.name}: unavailable ({exc})")
            continue
        reason = cand.summary
        if cand.detail is not None and not force:
            reason += cand.detail(scene)
        if passed:
            reason += "; passed over: " + "; ".join(passed)
        if force:
            reason = f"forced ({origin}): " + reason
        return Choice(cand, reason, run, forced=bool(force))
    raise scene.error(
        "accuracy",
        scene.accuracy,
        f"at least {best_floor:.3g} for this scene (the best any applicable model can promise in float64)",
    )


# --------------------------------------------------------------------------
# Outputs
# --------------------------------------------------------------------------
def _body_tensor(body: eng.BodyModel, n: int):
    axes = np.asarray(body.axes).reshape(-1, 3, 3)
    m = np.asarray(body.moments).reshape(-1, 3)
    return np.einsum("mki,mk,mkj->mij", axes, m, axes)  # (M, 3, 3) body frame


def derived_outputs(scene: Scene, engine: eng.Engine, t, w, q) -> dict:
    """The scene's outputs from omega (T, N, 3) and q (T, N, 4) in the body frame (SI)."""
    tensor = _body_tensor(scene.body, scene.members)
    L_body = np.einsum("mij,tmj->tmi", tensor, w)
    out = {}
    want = set(scene.outputs)
    if "omega" in want:
        out["omega"] = w
    if "attitude" in want:
        out["attitude"] = q
    if "angular_momentum" in want:
        out["angular_momentum"] = quat.rotate(q, L_body)
    if "angular_momentum_magnitude" in want:
        out["angular_momentum_magnitude"] = np.linalg.norm(L_body, axis=-1)
    kinetic = 0.5 * np.sum(w * L_body, axis=-1)
    if "kinetic_energy" in want:
        out["kinetic_energy"] = kinetic
    if want & {"potential_energy", "total_energy"}:
        pot = np.zeros_like(kinetic)
        tt = np.broadcast_to(np.asarray(t, dtype=float)[:, None], kinetic.shape)
        qi = engine.frame.quat_in(q)
        for b in engine.torques:
            pot = pot + b.potential(tt, qi, None)
        if "potential_energy" in want:
            out["potential_energy"] = pot
        if "total_energy" in want:
            out["total_energy"] = kinetic + pot
    if want & {"axis_direction", "tilt"}:
        axis = quat.rotate(q, np.array([0.0, 0.0, 1.0]))
        if "axis_direction" in want:
            out["axis_direction"] = axis
        if "tilt" in want:
            out["tilt"] = np.arctan2(np.hypot(axis[..., 0], axis[..., 1]), axis[..., 2])
    if "wobble_angle" in want:
        out["wobble_angle"] = np.arctan2(np.hypot(w[..., 0], w[..., 1]), w[..., 2])
    return out


def check_outputs(scene: Scene, engine: eng.Engine):
    """Refuse outputs the scene cannot define (energy with a non-conservative torque)."""
    if {"potential_energy", "total_energy"} & set(scene.outputs):
        bad = [t.kind for t, b in zip(engine.specs, engine.torques) if not b.conservative]
        if bad:
            raise scene.error(
                "outputs",
                list(scene.outputs),
                f"potential/total energy only with torques that have a potential (not {', '.join(bad)})",
            )


@dataclass
class RunRecord:
    """What a run did: the model, why, its error estimate and settings."""

    model: str
    reason: str
    error_estimate: dict
    settings: dict
    attempts: int
    stats: dict = field(default_factory=dict)


def execute(scene: Scene, sink, *, model: str | None = None, block_bytes: int = 64 * 2**20) -> RunRecord:
    """Run a scene: choose the model, compute the outputs block by block into ``sink``.

    Parameters
    ----------
    scene : Scene
    sink : object
        ``sink.begin()`` before each attempt, ``sink.write(t, outputs)``
        for each block (``outputs`` maps names to arrays (Tb, N, ...)),
        ``sink.discard()`` when an attempt is rejected (its estimate above
        the accuracy) and will be redone.
    model : str, optional
        Force a model by name (``--model``).
    block_bytes : int
        Memory budget of one block of outputs (and temporaries).

    Returns
    -------
    RunRecord
    """
    choice = choose_model(scene, model)
    if isinstance(choice.run, _AveragedRun):
        sink.begin()
        t, outputs = choice.run.summary()
        sink.write(t, outputs)
        return RunRecord(choice.run.name, choice.reason, choice.run.error_estimate(), dict(choice.run.settings), 1)
    engine = eng.Engine(scene.body, scene.torques, members=scene.members)
    check_outputs(scene, engine)
    per_time = max(1, scene.members) * 8 * 64
    block = int(max(1, min(scene.times.size, block_bytes // per_time)))
    try:
        run, est, attempts = _attempts(scene, sink, engine, choice, block)
    except _AccuracyNotReached as exc:
        # The integrator predicted cheaper could not reach the accuracy after all (its error
        # did not fall with its tolerance or step as the pilot said): the other one, unless forced.
        other = None if choice.forced else _other_integrator(scene, choice, exc.allowed)
        if other is None:
            raise scene.error("accuracy", scene.accuracy, exc.allowed) from None
        sink.discard()
        try:
            run, est, more = _attempts(scene, sink, engine, other, block)
        except _AccuracyNotReached as exc2:
            raise scene.error("accuracy", scene.accuracy, f"{exc.allowed}; {exc2.allowed}") from None
        attempts = exc.attempts + more
        choice = other
    stats = run.stats() if hasattr(run, "stats") else {}
    return RunRecord(run.name, choice.reason, est, dict(run.settings), attempts, stats)


class _AccuracyNotReached(Exception):
    """A numerical model's estimate stayed above the accuracy: ``allowed`` says what it reached."""

    def __init__(self, allowed: str, attempts: int):
        super().__init__(allowed)
        self.allowed = allowed
        self.attempts = attempts


def _attempts(scene, sink, engine, choice, block):
    """Run the chosen model, tightening and rerunning until its estimate meets the accuracy.

    Returns (run, estimate, attempts); raises :class:`_AccuracyNotReached`.
    """
    run = choice.run
    attempts = 0
    previous = np.inf
    while True:
        attempts += 1
        sink.begin()
        for tb, w, q in run.blocks(scene.times, block):
            sink.write(tb, derived_outputs(scene, engine, tb, w, q))
        est = run.error_estimate()
        worst = max(est["omega_relative"], est["attitude_rad"])
        if choice.candidate.kind == "exact" or worst <= scene.accuracy:
            return run, est, attempts
        rounding = est.get("rounding", 0.0)
        if rounding > scene.accuracy:
            # Amplified rounding: a shorter step only adds steps, and their rounding.
            raise _AccuracyNotReached(
                f"at least {rounding:.3g} for this scene with {run.name} (rounding floor: the motion amplifies "
                f"float64 rounding to that, and a shorter step only adds rounding; estimate {worst:.3g} after "
                f"{_count(attempts, 'run')})",
                attempts,
            )
        if attempts >= _MAX_ATTEMPTS or not worst < previous:
            raise _AccuracyNotReached(
                f"at least {worst:.3g} for this scene with {run.name} (estimate after {_count(attempts, 'run')})",
                attempts,
            )
        previous = worst
        sink.discard()
        run = _tighter(scene, run, worst, attempts)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _other_integrator(scene, choice, why: str) -> Choice | None:
    """The other numerical model, when the chosen one failed its accuracy (None: there is none)."""
    if choice.candidate.kind != "numerical":
        return None
    name = "dop853" if choice.candidate.name == "splitting" else "splitting"
    cand = next(c for c in CANDIDATES if c.name == name)
    if name == "splitting" and _applies_splitting(scene, forced=True) is not None:
        return None
    if scene.accuracy < cand.floor(scene):
        return None
    if name == "splitting":
        # Piloted under a budget: ten times DOP853's predicted run (at least 1 s). Unbounded, the pilots of a scene
        # whose accuracy DOP853 had shown out of reach ran past ten minutes (review finding).
        plan = _plan_splitting(scene, max(10.0 * _plans(scene, "dop853")["dop853"].seconds, 1.0))
        if not plan.complete:
            return None
        run = _build_splitting(scene, plan.settings)
    else:
        run = cand.build(scene)
    reason = (
        f"{cand.summary}, after {choice.run.name} did not reach the accuracy asked ({scene.accuracy:.3g}: {why}); "
        f"first choice: {choice.reason}"
    )
    return Choice(cand, reason, run)


def _tighter(scene, run, worst, attempts=1):
    """The same numerical model with settings tightened from the measured estimate."""
    ratio = scene.accuracy / worst
    if run.method == "dop853":
        floor = 100 * EPS  # the tightest tolerance DOP853 takes
        if run.settings["rtol"] <= floor:
            raise _AccuracyNotReached(
                f"at least {worst:.3g} for this scene with dop853 (tolerance floor reached)", attempts
            )
        # A step past the floor tries the floor itself: its estimate may still meet the accuracy.
        return _build_dop853(scene, {"rtol": max(run.settings["rtol"] * _PILOT_SAFETY * ratio, floor)})
    order = run.settings["order"]
    step = run.settings["step_s"] * (_PILOT_SAFETY * ratio) ** (1.0 / order)
    return _build_splitting(scene, {"order": order, "step_s": step})
