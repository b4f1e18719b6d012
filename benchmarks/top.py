"""The heavy-top cases and the SciPy baselines on the same equations.

Shared by scripts/bench_top.py, the work-precision harness and the user-level rows. The
top: I1 = 1 kg m2, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 rad/s,
theta0 = 60 deg, released with phidot0 = +0.3 rad/s (undulating), 0 (cusps),
-0.3 rad/s (loops); and a nearly sleeping top, theta0 = 1e-4 rad. References:
tests/references/heavy_top.json (mpmath, independent of wobble).

The SciPy baselines are written as a user writes them: the notes' Euler-angle equations
(Goldstein, Poole & Safko 2002, sec. 5.7) in Python floats, or for the nearly sleeping
top, where they cancel catastrophically, the non-singular omega + quaternion equations
(:func:`wobble.models.top_ode.top_rhs`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.cases import SCIPY, Case, floats, grid
from benchmarks.paths import load_json
from benchmarks.timing import Run
from wobble.models.engine import BodyModel, Engine, UniformGravity, attitude_angle
from wobble.models.top import heavy_top
from wobble.models.top_ode import top_rhs, vertical_in_body
from wobble.numerics import quaternion as Q

__all__ = [
    "I1",
    "I3",
    "MGL",
    "OMEGA3",
    "RTOL",
    "CASES",
    "quat_from_euler",
    "angle_between",
    "top_euler_angle_rhs",
    "run_dop853",
    "turning_error",
    "top_case",
    "mujoco_top",
]

I1, I3, MGL, OMEGA3 = 1.0, 0.5, 1.0, 10.0
RTOL = 1e-12
CASES = [
    ("cusps", "benchmark cusps", dict(theta0=np.pi / 3, phidot0=0.0)),
    ("undulating", "benchmark undulating", dict(theta0=np.pi / 3, phidot0=0.3)),
    ("loops", "benchmark loops", dict(theta0=np.pi / 3, phidot0=-0.3)),
    ("nearly sleeping (theta0 = 1e-4 rad)", "nearly sleeping 1e-4", dict(theta0=1e-4, phidot0=0.0)),
]


def quat_from_euler(phi, theta, psi):
    ch, sh = np.cos(theta / 2), np.sin(theta / 2)
    return np.stack(
        [
            ch * np.cos((phi + psi) / 2),
            sh * np.cos((phi - psi) / 2),
            sh * np.sin((phi - psi) / 2),
            ch * np.sin((phi + psi) / 2),
        ],
        axis=-1,
    )


def angle_between(q1, q2):
    d = Q.multiply(q1, Q.conjugate(q2))
    return 2 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def top_euler_angle_rhs(mdl):
    """The notes' equations (section 5.7) in Python floats, as a SciPy user writes them:
    phidot, psidot from the conserved momenta and
    I1 thetaddot = I1 phidot^2 sin cos - I3 omega3 phidot sin + M g l sin (state theta,
    thetadot, phi, psi)."""
    a, b, beta, w3 = mdl.a, mdl.b, mdl.beta, mdl.omega3
    sin, cos = math.sin, math.cos

    def f(t, y):
        th, thd = y[0], y[1]
        s, c = sin(th), cos(th)
        phd = (b - a * c) / (s * s)
        return [thd, phd * phd * s * c - a * phd * s + 0.5 * beta * s, phd, w3 - phd * c]

    return f


def turning_event(kind):
    if kind == "euler":

        def ev(t, y):
            return y[1]
    else:

        def ev(t, y):  # d(gamma3)/dt = d(cos theta)/dt = omega x gamma, third component
            w1, w2 = y[0], y[1]
            g = vertical_in_body(y[3:])
            return w1 * g[1] - w2 * g[0]

    return ev


def run_dop853(mdl, t, kind, rtol=RTOL, method="DOP853", extra_t=None, events=True):
    t_eval = t if extra_t is None else np.union1d(t, extra_t)
    ev = turning_event(kind) if events else None
    if kind == "euler":
        y0 = [mdl.theta0, mdl.thetadot0, mdl.phi0, mdl.psi0]
        scale = np.array([1.0, max(abs(mdl.a), 1.0), 1.0, 1.0])
        sol = solve_ivp(
            top_euler_angle_rhs(mdl),
            (0, t_eval[-1]),
            y0,
            method=method,
            t_eval=t_eval,
            rtol=rtol,
            atol=rtol * scale,
            events=ev,
        )
        th, ph, ps = sol.y[0], sol.y[2], sol.y[3]
        q = quat_from_euler(ph, th, ps)
        turning = sol.y_events[0][:, 0] if events else None
    else:
        w, q0 = mdl.evaluate(np.zeros(1), "direct")
        y0 = np.concatenate([w[0], q0[0]])
        scale = np.array([np.linalg.norm(w[0])] * 3 + [1.0] * 4)
        sol = solve_ivp(
            top_rhs(mdl.I1, mdl.I3, mdl.mgl),
            (0, t_eval[-1]),
            y0,
            method=method,
            t_eval=t_eval,
            rtol=rtol,
            atol=rtol * scale,
            events=ev,
        )
        q = sol.y[3:].T / np.linalg.norm(sol.y[3:].T, axis=1, keepdims=True)
        g = vertical_in_body(q)
        th = np.arctan2(np.hypot(g[:, 0], g[:, 1]), g[:, 2])
        turning = None
        if events:
            ge = vertical_in_body(sol.y_events[0][:, 3:])
            turning = np.arctan2(np.hypot(ge[:, 0], ge[:, 1]), ge[:, 2])
    return sol.t, th, q, turning


def turning_error(turning, ref):
    """Largest relative error of the integrator's turning angles against the mpmath ones."""
    lo, hi = float(ref["theta_min"]), float(ref["theta_max"])
    near = np.where(np.abs(turning - lo) < np.abs(turning - hi), lo, hi)
    return float(np.max(np.abs(turning - near) / near))


def _mujoco():
    try:
        import mujoco
    except ImportError:
        return None
    return mujoco


MUJOCO_XML = """<mujoco><option timestep="0.001" integrator="{integrator}" gravity="0 0 -10">
<flag contact="disable"/></option><worldbody><body name="top"><joint name="tip" type="ball"/>
<inertial pos="0 0 0.1" mass="1" diaginertia="0.99 0.99 0.5"/></body></worldbody></mujoco>"""


def mujoco_top(w0, q0, t, dt, integrator):
    """The top in MuJoCo: a ball joint at the tip, M = 1 kg, l = 0.1 m, g = 10 m/s2 (M g l = 1 J),
    I about the centre of mass (0.99, 0.99, 0.5) so that I1 about the tip = 1; no contacts.
    Steps of at most ``dt``, fitted to each output interval. Returns the attitude quaternions."""
    mj = _mujoco()
    m = mj.MjModel.from_xml_string(MUJOCO_XML.format(integrator=integrator))
    d = mj.MjData(m)
    d.qpos[:] = q0
    d.qvel[:] = w0  # a ball joint's velocity is the angular velocity in the body frame
    out = np.empty((t.size, 4))
    out[0] = q0
    for i in range(1, t.size):
        h = t[i] - t[i - 1]
        n = max(1, math.ceil(h / dt - 1e-9))
        m.opt.timestep = h / n
        mj.mj_step(m, d, nstep=n)
        out[i] = d.qpos
    return out


def top_case(key: str, label: str, refname: str, kw: dict, quick: bool, mujoco_dts=None) -> Case:
    """A heavy-top case of :data:`CASES`: wobble's exact top against SciPy (with turning-point
    events, for the turning angles), wobble's integrators and MuJoCo; ``quick``: fewer settings."""
    ref = next(c for c in load_json("tests", "references", "heavy_top.json")["cases"] if c["name"] == refname)
    W3 = OMEGA3
    mdl = heavy_top(I1, I3, MGL, omega3=W3, **kw)
    t0 = np.linspace(0.0, 1000 * mdl.nutation_period, 20_001)
    ref_t, ref_q = floats(ref["long"]["t"]), floats(ref["long"]["quaternion"])
    t, (iq,) = grid(t0, ref_t)
    q_exact = mdl.attitude(t)
    an = ref["analysis"]
    w_turn = max(abs(mdl.theta_min / float(an["theta_min"]) - 1), abs(mdl.theta_max / float(an["theta_max"]) - 1))
    desc = (
        f"I1 = 1, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 rad/s, theta0 = {kw['theta0']:.6g} rad, "
        f"phidot0 = {kw['phidot0']:g} rad/s ({mdl.nutation} nutation); 1000 nutation periods "
        f"({t0[-1]:.1f} s), 20,001 outputs."
    )
    case = Case(
        key,
        f"Heavy top: {label}",
        desc,
        "attitude angle error (rad), max over the reference times; turning points (relative) in their own column",
        f"mpmath (tests/references/heavy_top.json, case '{refname}'): turning angles and the attitude at "
        f"{ref_t.size:d} times up to 1000.25 periods; integrators also against wobble's exact attitude at every "
        "output",
        t0.size,
        complete=not quick,
    )
    case.context = {"model": mdl}

    def check_q(q, turning=None):
        if q.shape != (t.size, 4) or not np.all(np.isfinite(q)):
            return {"error": math.inf}
        e_ref = float(np.max(attitude_angle(q[iq], ref_q)))
        e_all = float(np.max(attitude_angle(q, q_exact)))
        out = {"error": e_ref, "error_vs_mpmath": e_ref, "error_vs_exact": e_all}
        if turning is not None:
            out["turning_error"] = turning
        return out

    def exact_angles():
        m = heavy_top(I1, I3, MGL, omega3=W3, **kw)
        return m.angles(t)

    def check_angles(a):
        th, ph, ps = a
        return check_q(quat_from_euler(ph, th, ps), w_turn)

    case.runs.append(Run("wobble exact", "construction + theta, phi, psi", exact_angles, check_angles))
    case.runs.append(
        Run("wobble exact (evaluation only)", "theta, phi, psi (model built)", lambda: mdl.angles(t), check_angles)
    )
    case.runs.append(
        Run(
            "wobble exact + omega",
            "construction + omega, quaternion",
            lambda: heavy_top(I1, I3, MGL, omega3=W3, **kw).evaluate(t),
            lambda o: check_q(o[1], w_turn),
        )
    )
    kind = "euler" if kw["theta0"] > 0.1 else "quaternion"
    rtols = {"DOP853": [1e-8, 1e-10, 1e-12], "RK45": [1e-6, 1e-8], "LSODA": [1e-8, 1e-10, 1e-12], "Radau": [1e-6]}
    if quick:
        rtols = {"DOP853": [1e-6, 1e-8], "RK45": [1e-5], "LSODA": [1e-6, 1e-8], "Radau": [1e-4]}
    for method in SCIPY:
        for rtol in rtols[method]:

            def go(m=method, r=rtol):
                return run_dop853(mdl, t, kind, rtol=r, method=m, events=True)

            def chk(o):
                tt, th, q, turning = o
                if tt.size != t.size:
                    return {"error": math.inf}
                qn = q / np.linalg.norm(q, axis=1, keepdims=True)
                te = turning_error(turning, an) if turning is not None and turning.size else math.inf
                return check_q(qn, te)

            case.runs.append(Run(f"scipy {method}", f"rtol {rtol:g} ({kind} equations, turning-point events)", go, chk))
    eng = Engine(BodyModel.from_moments([I1, I1, I3]), [UniformGravity(1.0, [0.0, 0.0, MGL], [0.0, 0.0, -1.0])])
    w_init, q_init = mdl.evaluate(np.zeros(1))
    w_init, q_init = w_init[0], q_init[0]
    wrtols = [1e-8, 1e-10] if not quick else [1e-6]
    for rtol in wrtols:
        case.runs.append(
            Run(
                "wobble DOP853",
                f"rtol {rtol:g}",
                lambda r=rtol: eng.integrate(w_init, q_init, t, method="dop853", rtol=r, estimate=False),
                lambda tr: check_q(tr.attitude[:, 0]),
                work=lambda tr: int(tr.stats["function_evaluations"]),
            )
        )
    steps = {2: [0.005], 4: [0.02], 6: [0.04]} if not quick else {2: [0.02], 4: [0.08], 6: [0.16]}
    for order, hs in steps.items():
        for h in hs:
            case.runs.append(
                Run(
                    f"wobble splitting-{order}",
                    f"h {h:g} s",
                    lambda h=h, o=order: eng.integrate(
                        w_init, q_init, t, method="splitting", step=h, order=o, estimate=False
                    ),
                    lambda tr: check_q(tr.attitude[:, 0]),
                    work=lambda tr: int(tr.stats["drifts"]),
                )
            )
    if mujoco_dts and _mujoco() is not None:
        for integrator, dts in mujoco_dts.items():
            for dt in dts:
                case.runs.append(
                    Run(
                        f"MuJoCo {integrator}",
                        f"dt {dt:g} s",
                        lambda dt=dt, i=integrator: mujoco_top(w_init, q_init, t, dt, i),
                        lambda q: check_q(q),
                    )
                )
    return case
