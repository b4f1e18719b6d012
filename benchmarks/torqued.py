"""The torqued cases (no exact solution), shared with scripts/bench_engine.py.

* ``Satellite``: a spin-stabilised microsatellite (I = 0.90, 0.92, 1.20 kg m2) spinning at
  1 rad/s under the gravity-gradient torque of Earth on a 500 km circular orbit, 300 s,
  21 outputs. Reference: SciPy's Radau at rtol 1e-13, cached in
  benchmarks/engine_reference.json.
* ``AsymmetricTop``: the asymmetric top of tests/references/engine_torqued.json (mpmath Taylor
  integration at 30 digits).

SciPy is given the right-hand side in Python floats, the fastest a user gets without
compiling.
"""

from __future__ import annotations

import json
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.cases import SCIPY, Case
from benchmarks.paths import ROOT, load_json
from benchmarks.timing import Run
from benchmarks.timing import time_at as interpolate
from wobble.models.engine import BodyModel, Engine, GravityGradient, UniformGravity, attitude_angle
from wobble.numerics import quaternion as Q

REFERENCE = ROOT / "benchmarks" / "engine_reference.json"
GM_EARTH = 3.986004418e14  # data/bodies/earth.toml
ORBIT_RADIUS = 6878137.0


# --------------------------------------------------------------------------
# Cases
# --------------------------------------------------------------------------
class TorquedSystem:
    """A body, its torques, its initial state and output times, with SciPy's right-hand side."""

    def __init__(self, name, moments, torques, w0, q0, t):
        self.name = name
        self.moments = np.asarray(moments, dtype=float)
        self.torques = torques
        self.w0 = np.asarray(w0, dtype=float)
        self.q0 = np.asarray(q0, dtype=float)
        self.t = np.asarray(t, dtype=float)
        self.engine = Engine(BodyModel.from_moments(self.moments), torques)
        self.w_ref = self.q_ref = None

    def scipy_rhs(self):
        """Euler's equations as a SciPy user writes them (NumPy, one state vector)."""
        raise NotImplementedError


def _body_rhs(I, tau, w, q):
    """d(omega, q)/dt from a body-frame torque, in Python floats (the fast way to feed solve_ivp)."""
    i0, i1, i2 = I
    w0, w1, w2 = w
    qw, qx, qy, qz = q
    return np.array(
        [
            (tau[0] + (i1 - i2) * w1 * w2) / i0,
            (tau[1] + (i2 - i0) * w2 * w0) / i1,
            (tau[2] + (i0 - i1) * w0 * w1) / i2,
            -0.5 * (qx * w0 + qy * w1 + qz * w2),
            0.5 * (qw * w0 + qy * w2 - qz * w1),
            0.5 * (qw * w1 - qx * w2 + qz * w0),
            0.5 * (qw * w2 + qx * w1 - qy * w0),
        ]
    )


def _to_body(q, v):
    """R(q)^T v for a (not necessarily unit) quaternion, in floats."""
    n = math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
    w, x, y, z = (c / n for c in q)
    return (
        (1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y + w * z) * v[1] + 2 * (x * z - w * y) * v[2],
        2 * (x * y - w * z) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z + w * x) * v[2],
        2 * (x * z + w * y) * v[0] + 2 * (y * z - w * x) * v[1] + (1 - 2 * (x * x + y * y)) * v[2],
    )


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


class Satellite(TorquedSystem):
    def __init__(self, span=300.0, outputs=21):
        self.k = 3 * GM_EARTH / ORBIT_RADIUS**3
        self.n = math.sqrt(GM_EARTH / ORBIT_RADIUS**3)
        super().__init__(
            "satellite",
            [0.90, 0.92, 1.20],
            [GravityGradient(GM_EARTH, ORBIT_RADIUS, orbit_normal=[0.0, 0.0, 1.0])],
            [0.005, 0.0, 1.0],
            [1.0, 0.0, 0.0, 0.0],
            np.linspace(0.0, span, outputs),
        )

    def scipy_rhs(self):
        I, k, n = tuple(self.moments), self.k, self.n

        def f(t, y):
            w, q = y[:3].tolist(), y[3:].tolist()
            rb = _to_body(q, (math.cos(n * t), math.sin(n * t), 0.0))
            tq = _cross(rb, (I[0] * rb[0], I[1] * rb[1], I[2] * rb[2]))
            return _body_rhs(I, (k * tq[0], k * tq[1], k * tq[2]), w, q)

        return f


class AsymmetricTop(TorquedSystem):
    def __init__(self):
        c = next(
            c for c in load_json("tests", "references", "engine_torqued.json")["cases"] if c["name"] == "asymmetric top"
        )

        def fl(xs):
            return [float(x) for x in xs]

        self.r = np.array(fl(c["center_of_mass"]))
        self.mg = float(c["mass"]) * np.array(fl(c["gravity"]))
        super().__init__(
            "asymmetric top",
            fl(c["moments"]),
            [UniformGravity(float(c["mass"]), self.r, np.array(fl(c["gravity"])))],
            fl(c["omega0"]),
            fl(c["attitude0"]),
            [0.0] + fl(c["t"]),
        )
        self.w_ref = np.array([fl(r) for r in c["omega"]])
        self.q_ref = np.array([fl(r) for r in c["attitude"]])

    def scipy_rhs(self):
        I, r, mg = tuple(self.moments), tuple(self.r), tuple(self.mg)

        def f(t, y):
            w, q = y[:3].tolist(), y[3:].tolist()
            return _body_rhs(I, _cross(r, _to_body(q, mg)), w, q)

        return f


def load_reference(case: Satellite, rebuild: bool):
    if REFERENCE.is_file() and not rebuild:
        data = json.loads(REFERENCE.read_text())
        if data["t"] == case.t.tolist() and data["omega0"] == case.w0.tolist():
            case.w_ref, case.q_ref = np.array(data["omega"]), np.array(data["attitude"])
            return data["seconds"]
    t0 = time.perf_counter()
    y0 = np.concatenate([case.w0, case.q0])
    sol = solve_ivp(
        case.scipy_rhs(), (case.t[0], case.t[-1]), y0, method="Radau", rtol=1e-13, atol=1e-16, t_eval=case.t
    )
    seconds = time.perf_counter() - t0
    case.w_ref = sol.y[:3, 1:].T
    case.q_ref = Q.normalize(sol.y[3:, 1:].T)
    REFERENCE.write_text(
        json.dumps(
            {
                "what": "Radau rtol 1e-13 atol 1e-16 of the satellite case of scripts/bench_engine.py",
                "t": case.t.tolist(),
                "omega0": case.w0.tolist(),
                "seconds": seconds,
                "omega": case.w_ref.tolist(),
                "attitude": case.q_ref.tolist(),
            }
        )
        + "\n"
    )
    return seconds


# --------------------------------------------------------------------------
# Methods
# --------------------------------------------------------------------------
def error(case, w, q):
    """max over outputs (after t0) of |omega - ref| / |ref| and of the attitude angle."""
    rel = np.linalg.norm(w - case.w_ref, axis=-1) / np.linalg.norm(case.w_ref, axis=-1)
    return float(max(rel.max(), attitude_angle(q, case.q_ref).max()))


def run_scipy(case, method, rtol):
    f = case.scipy_rhs()
    y0 = np.concatenate([case.w0, case.q0])

    def go():
        sol = solve_ivp(f, (case.t[0], case.t[-1]), y0, method=method, rtol=rtol, atol=rtol * 1e-3, t_eval=case.t)
        return sol.y[:3, 1:].T, Q.normalize(sol.y[3:, 1:].T), sol.nfev

    return go


def run_wobble(case, method, setting, order=6, backend="auto"):
    def go():
        if method == "dop853":
            tr = case.engine.integrate(
                case.w0, case.q0, case.t, method="dop853", rtol=setting, estimate=False, backend=backend
            )
            work = tr.stats["function_evaluations"]
        else:
            tr = case.engine.integrate(
                case.w0, case.q0, case.t, method="splitting", step=setting, order=order, estimate=False
            )
            work = tr.stats["drifts"]
        return tr.omega[1:, 0], tr.attitude[1:, 0], work

    return go


def method_time_at(rows, method, target):
    """Log-log interpolation of a method's min time at the target error (None outside its range)."""
    return interpolate([(e, t) for m, _, e, t, _, _ in rows if m == method], target)


def torqued_case(which: str, quick: bool) -> Case:
    """The satellite or the asymmetric top. ``quick`` trims RK45, LSODA and Radau only: the
    one-trajectory target compares SciPy's DOP853 with every wobble integrator, so those run
    at the full run's settings in every mode and the target is judged the same way."""
    if which == "satellite":
        c = Satellite()
        seconds = load_reference(c, False)
        ref = f"SciPy Radau at rtol 1e-13, atol 1e-16 (benchmarks/engine_reference.json; it took {seconds:.0f} s)"
        desc = (
            "Spin-stabilised microsatellite, I = (0.90, 0.92, 1.20) kg m2, 1 rad/s, gravity-gradient torque "
            "of Earth on a 500 km circular orbit; 300 s, 21 outputs."
        )
        steps = {2: [0.1, 0.05], 4: [0.4, 0.2, 0.1], 6: [0.8, 0.4, 0.2]}
    else:
        c = AsymmetricTop()
        ref = "mpmath Taylor integration at 30 digits (tests/references/engine_torqued.json, case 'asymmetric top')"
        desc = (
            "Asymmetric top under gravity: I = (1, 1.5, 2) kg m2 about the pivot, centre of mass off every "
            "axis, 8 rad/s; 5 s, 7 outputs."
        )
        steps = {2: [0.002, 0.001], 4: [0.01, 0.005, 0.0025], 6: [0.02, 0.01, 0.005]}
    scipy_rtols = {
        "DOP853": [1e-7, 1e-9, 1e-11, 1e-13],
        "RK45": [1e-6, 1e-8, 1e-10],
        "LSODA": [1e-7, 1e-9, 1e-11],
        "Radau": [1e-6, 1e-8],
    }
    wobble_rtols = [1e-7, 1e-9, 1e-11, 1e-13]
    if quick:
        scipy_rtols = {k: (v if k == "DOP853" else v[:1]) for k, v in scipy_rtols.items()}
    case = Case(
        f"torqued_{which.replace(' ', '_')}",
        f"Torqued: {c.name}",
        desc,
        "max over the outputs of ``|omega - omega_ref| / |omega_ref|`` and of the attitude angle (rad)",
        ref,
        c.t.size,
    )

    def chk(o):
        return {"error": error(c, o[0], o[1])}

    for method in SCIPY:
        for rtol in scipy_rtols[method]:
            case.runs.append(
                Run(f"scipy {method}", f"rtol {rtol:g}", run_scipy(c, method, rtol), chk, work=lambda o: int(o[2]))
            )
    for rtol in wobble_rtols:
        case.runs.append(
            Run("wobble DOP853", f"rtol {rtol:g}", run_wobble(c, "dop853", rtol), chk, work=lambda o: int(o[2]))
        )
    # The same method in NumPy: what a custom torque (a Python callable) runs on.
    for rtol in wobble_rtols:
        case.runs.append(
            Run(
                "wobble DOP853 (NumPy)",
                f"rtol {rtol:g}",
                run_wobble(c, "dop853", rtol, backend="python"),
                chk,
                work=lambda o: int(o[2]),
            )
        )
    for order, hs in steps.items():
        for h in hs:
            case.runs.append(
                Run(
                    f"wobble splitting-{order}",
                    f"h {h:g} s",
                    run_wobble(c, "splitting", h, order),
                    chk,
                    work=lambda o: int(o[2]),
                )
            )
    return case
