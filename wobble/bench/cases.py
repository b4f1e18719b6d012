"""The fixed, named cases of issue 8 and the methods run on each.

Each builder returns a :class:`Case`: its runs (every method at every setting, see
:class:`wobble.bench.timing.Run`), the reference it is measured against, and what
"error" means for it. The references never depend on the method measured:

* exact solutions are measured against the committed mpmath references
  (tests/references/free_rotation.json, heavy_top.json);
* integrators against the exact solution at every output (itself checked against
  mpmath in the test suite) and against mpmath at the reference times; where there
  is no exact solution, against mpmath (tests/references/engine_torqued.json) or a
  cached Radau run at rtol 1e-13 (scripts/bench_engine_reference.json).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from wobble.bench import top as topcases
from wobble.bench import torqued
from wobble.bench._paths import load_json
from wobble.bench.timing import Run
from wobble.models.engine import BodyModel, Engine, UniformGravity, attitude_angle
from wobble.models.free import free_rotation
from wobble.models.top import heavy_top

SCIPY = ("RK45", "DOP853", "LSODA", "Radau")


@dataclass
class Case:
    key: str
    title: str
    description: str
    error_measure: str
    reference: str
    outputs: int
    runs: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    context: dict = field(default_factory=dict)


def _floats(rows):
    return np.array([[float(v) for v in r] for r in rows]) if isinstance(rows[0], list) else np.array([float(v) for v in rows])


def rel_error(got, want) -> float:
    """max over rows of ``|got - want| / |want|`` (vectors along the last axis)."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    if got.shape != want.shape or not np.all(np.isfinite(got)):
        return math.inf
    return float(np.max(np.linalg.norm(got - want, axis=-1) / np.linalg.norm(want, axis=-1)))


def phase_error(got, want) -> float:
    """max wrapped difference (rad) of the wobble phase ``atan2(omega_2, omega_1)``."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    if got.shape != want.shape or not np.all(np.isfinite(got)):
        return math.inf
    d = np.arctan2(got[:, 1], got[:, 0]) - np.arctan2(want[:, 1], want[:, 0])
    return float(np.max(np.abs(np.angle(np.exp(1j * d)))))


def _grid(t, *extra):
    """The case's output times with the reference times merged in, and their indices."""
    full = np.union1d(t, np.concatenate([np.asarray(e, float) for e in extra]) if extra else [])
    return full, [np.searchsorted(full, e) for e in extra]


def euler_rhs(moments):
    """Euler's equations for a free body as a SciPy user writes them (Python floats)."""
    i1, i2, i3 = (float(x) for x in moments)
    a, b, c = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3

    def f(t, w):
        w1, w2, w3 = w
        return [a * w2 * w3, b * w3 * w1, c * w1 * w2]

    return f


def _solve(f, t, y0, method, rtol, atol):
    sol = solve_ivp(f, (t[0], t[-1]), y0, method=method, t_eval=t, rtol=rtol, atol=atol)
    return sol


def _sol_omega(sol, n):
    return sol.y[:3].T if sol.success and sol.y.shape[1] == n else np.full((n, 3), np.nan)


# ---------------------------------------------------------------------------
# Free body: generic, separatrix, Earth
# ---------------------------------------------------------------------------
FREE = {
    "free_generic": dict(ref="generic 1000 s", t_end=1000.0, n=10_001,
                         title="Generic asymmetric free body",
                         description="I = (1, 2, 3) kg m2, omega0 = (1, 0.1, 1) rad/s, 1000 s, 10^4 output intervals."),
    "free_separatrix": dict(ref="separatrix 2e-12", t_end=200.0, n=10_001,
                            title="Free body near the separatrix",
                            description="I = (1, 2, 3) kg m2, omega0 = (1e-6, 1, 1e-6) rad/s (1 - m = 2e-12), "
                            "200 s, 10^4 output intervals; flip times of the exact solution."),
    "free_earth": dict(ref="Earth 100 years", t_end=None, n=36_526,
                       title="Earth-like free wobble, 100 years daily",
                       description="Earth's principal moments (8.01012e37, 8.01032e37, 8.03652e37 kg m2, the "
                       "catalogue values of tests/references/free_rotation.json) spinning at 7.292115e-5 rad/s, "
                       "rotation axis 1e-6 rad from the figure axis; 36,526 daily outputs."),
}


def free_case(key: str, quick: bool) -> Case:
    spec = FREE[key]
    ref = next(c for c in load_json("tests", "references", "free_rotation.json")["closed"] if c["name"] == spec["ref"])
    I = _floats(ref["moments"])  # noqa: E741
    w0 = _floats(ref["omega0"])
    ref_t, ref_w = _floats(ref["t"]), _floats(ref["omega"])
    att_t, att_q = _floats(ref["attitude_t"]), _floats(ref["attitude"])
    if key == "free_earth":
        t0 = np.arange(spec["n"]) * 86400.0
    else:
        t0 = np.linspace(0.0, spec["t_end"], spec["n"])
    t, (iw, iq) = _grid(t0, ref_t, att_t)
    exact = free_rotation(I, w0)
    w_exact = exact.omega(t)
    earth = key == "free_earth"
    measure = phase_error if earth else rel_error
    what = ("wobble phase error (rad): max wrapped difference of atan2(omega2, omega1)" if earth else
            "max relative error of omega, ``|omega - omega_ref| / |omega_ref|``")
    case = Case(key, spec["title"], spec["description"], what,
                "mpmath (tests/references/free_rotation.json, case '%s') at %d times; integrators also against "
                "wobble's exact solution at every output" % (spec["ref"], ref_t.size), t0.size)
    case.context = {"t": t, "exact": exact, "w_exact": w_exact, "iw": iw, "ref_w": ref_w}

    def check_integrator(w):
        e_ref = measure(w[iw], ref_w)
        e_all = measure(w, w_exact)
        return {"error": max(e_ref, e_all), "error_vs_mpmath": e_ref, "error_vs_exact": e_all}

    def check_exact(w):
        return {"error": measure(w[iw], ref_w), "error_vs_mpmath": measure(w[iw], ref_w)}

    def check_exact_att(out):
        w, q = out
        ew = measure(w[iw], ref_w)
        eq = float(np.max(attitude_angle(q[iq], att_q)))
        return {"error": max(ew, eq), "error_vs_mpmath": ew, "attitude_error_rad": eq}

    if key == "free_separatrix":
        flips_ref = _floats(ref["flip_times"])

        def check_exact(w, _c=check_exact):  # noqa: F811
            flips = exact.flip_times(0.0, float(t[-1]))
            err = float(np.max(np.abs(flips - flips_ref))) if flips.shape == flips_ref.shape else math.inf
            return {**_c(w), "flip_time_error_s": err}

    case.runs.append(Run("wobble exact", "omega", lambda: free_rotation(I, w0).omega(t), check_exact))
    if earth:
        # The evaluation alone (the model built once, as a script reusing it would): what the
        # Earth target's "36,526 daily outputs in under 1 ms" measures; construction is separate.
        case.runs.append(Run("wobble exact (evaluation only)", "omega (model built)", lambda: exact.omega(t), check_exact))
    case.runs.append(Run("wobble exact + attitude", "omega, quaternion",
                         lambda: (lambda m: (m.omega(t), m.attitude(t)))(free_rotation(I, w0)), check_exact_att))
    # The integrators.
    scale = float(np.hypot(w0[0], w0[1])) if earth else float(np.linalg.norm(w0))
    rtols = {
        "DOP853": [1e-6, 1e-8, 1e-10, 1e-12], "RK45": [1e-5, 1e-7, 1e-9], "LSODA": [1e-6, 1e-8, 1e-10, 1e-12],
        "Radau": [1e-4, 1e-6, 1e-8], "wobble DOP853": [1e-6, 1e-8, 1e-10, 1e-12],
    }
    if quick:
        rtols = {k: v[:2] for k, v in rtols.items()}
    f = euler_rhs(I)
    for method in SCIPY:
        for rtol in rtols[method]:
            # atol relative to the wobble for Earth (a user controls the small components)
            atol = rtol * (scale if earth else 1e-3 * scale)
            case.runs.append(Run(f"scipy {method}", f"rtol {rtol:g}",
                                 lambda m=method, r=rtol, a=atol: _solve(f, t, w0, m, r, a),
                                 lambda s: check_integrator(_sol_omega(s, t.size)), work=lambda s: int(s.nfev)))
    eng = Engine(BodyModel.from_moments(I), [])
    q1 = np.array([1.0, 0.0, 0.0, 0.0])
    for rtol in rtols["wobble DOP853"]:
        case.runs.append(Run("wobble DOP853", f"rtol {rtol:g}",
                             lambda r=rtol: eng.integrate(w0, q1, t, method="dop853", rtol=r, attitude=False, estimate=False),
                             lambda tr: check_integrator(tr.omega[:, 0]),
                             work=lambda tr: int(tr.stats["function_evaluations"])))
    case.notes.append("The splitting integrators are not swept here: without a torque their drift is the exact "
                      "free flow, so they return the exact solution at any step.")
    return case


# ---------------------------------------------------------------------------
# Heavy top
# ---------------------------------------------------------------------------
def _mujoco():
    try:
        import mujoco  # noqa: F401
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
    ref = next(c for c in load_json("tests", "references", "heavy_top.json")["cases"] if c["name"] == refname)
    I1, I3, MGL, W3 = topcases.I1, topcases.I3, topcases.MGL, topcases.OMEGA3  # noqa: N806
    mdl = heavy_top(I1, I3, MGL, omega3=W3, **kw)
    t0 = np.linspace(0.0, 1000 * mdl.nutation_period, 20_001)
    ref_t, ref_q = _floats(ref["long"]["t"]), _floats(ref["long"]["quaternion"])
    t, (iq,) = _grid(t0, ref_t)
    q_exact = mdl.attitude(t)
    an = ref["analysis"]
    w_turn = max(abs(mdl.theta_min / float(an["theta_min"]) - 1), abs(mdl.theta_max / float(an["theta_max"]) - 1))
    desc = (f"I1 = 1, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 rad/s, theta0 = {kw['theta0']:.6g} rad, "
            f"phidot0 = {kw['phidot0']:g} rad/s ({mdl.nutation} nutation); 1000 nutation periods "
            f"({t0[-1]:.1f} s), 20,001 outputs.")
    case = Case(key, f"Heavy top: {label}", desc,
                "attitude angle error (rad), max over the reference times; turning points (relative) in their own column",
                "mpmath (tests/references/heavy_top.json, case '%s'): turning angles and the attitude at %d times up "
                "to 1000.25 periods; integrators also against wobble's exact attitude at every output" % (refname, ref_t.size),
                t0.size)
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
        return check_q(topcases.quat_from_euler(ph, th, ps), w_turn)

    case.runs.append(Run("wobble exact", "construction + theta, phi, psi", exact_angles, check_angles))
    case.runs.append(Run("wobble exact (evaluation only)", "theta, phi, psi (model built)", lambda: mdl.angles(t),
                         check_angles))
    case.runs.append(Run("wobble exact + omega", "construction + omega, quaternion",
                         lambda: heavy_top(I1, I3, MGL, omega3=W3, **kw).evaluate(t), lambda o: check_q(o[1], w_turn)))
    kind = "euler" if kw["theta0"] > 0.1 else "quaternion"
    rtols = {"DOP853": [1e-8, 1e-10, 1e-12], "RK45": [1e-6, 1e-8], "LSODA": [1e-8, 1e-10, 1e-12], "Radau": [1e-6]}
    if quick:
        rtols = {"DOP853": [1e-6, 1e-8], "RK45": [1e-5], "LSODA": [1e-6, 1e-8], "Radau": [1e-4]}
    for method in SCIPY:
        for rtol in rtols[method]:
            def go(m=method, r=rtol):
                return topcases.run_dop853(mdl, t, kind, rtol=r, method=m, events=True)

            def chk(o):
                tt, th, q, turning = o
                if tt.size != t.size:
                    return {"error": math.inf}
                qn = q / np.linalg.norm(q, axis=1, keepdims=True)
                te = topcases.turning_error(turning, an) if turning is not None and turning.size else math.inf
                return check_q(qn, te)

            case.runs.append(Run(f"scipy {method}", f"rtol {rtol:g} ({kind} equations, turning-point events)", go, chk))
    eng = Engine(BodyModel.from_moments([I1, I1, I3]), [UniformGravity(1.0, [0.0, 0.0, MGL], [0.0, 0.0, -1.0])])
    w_init, q_init = mdl.evaluate(np.zeros(1))
    w_init, q_init = w_init[0], q_init[0]
    wrtols = [1e-8, 1e-10] if not quick else [1e-6]
    for rtol in wrtols:
        case.runs.append(Run("wobble DOP853", f"rtol {rtol:g}",
                             lambda r=rtol: eng.integrate(w_init, q_init, t, method="dop853", rtol=r, estimate=False),
                             lambda tr: check_q(tr.attitude[:, 0]), work=lambda tr: int(tr.stats["function_evaluations"])))
    steps = {2: [0.005], 4: [0.02], 6: [0.04]} if not quick else {2: [0.02], 4: [0.08], 6: [0.16]}
    for order, hs in steps.items():
        for h in hs:
            case.runs.append(Run(f"wobble splitting-{order}", f"h {h:g} s",
                                 lambda h=h, o=order: eng.integrate(w_init, q_init, t, method="splitting", step=h, order=o,
                                                                    estimate=False),
                                 lambda tr: check_q(tr.attitude[:, 0]), work=lambda tr: int(tr.stats["drifts"])))
    if mujoco_dts and _mujoco() is not None:
        for integrator, dts in mujoco_dts.items():
            for dt in dts:
                case.runs.append(Run(f"MuJoCo {integrator}", f"dt {dt:g} s",
                                     lambda dt=dt, i=integrator: mujoco_top(w_init, q_init, t, dt, i), lambda q: check_q(q)))
    return case


# ---------------------------------------------------------------------------
# Torqued (no exact solution)
# ---------------------------------------------------------------------------
def torqued_case(which: str, quick: bool) -> Case:
    if which == "satellite":
        c = torqued.Satellite()
        seconds = torqued.load_reference(c, False)
        ref = f"SciPy Radau at rtol 1e-13, atol 1e-16 (scripts/bench_engine_reference.json; it took {seconds:.0f} s)"
        desc = ("Spin-stabilised microsatellite, I = (0.90, 0.92, 1.20) kg m2, 1 rad/s, gravity-gradient torque "
                "of Earth on a 500 km circular orbit; 300 s, 21 outputs.")
        steps = {2: [0.1, 0.05], 4: [0.4, 0.2, 0.1], 6: [0.8, 0.4, 0.2]}
    else:
        c = torqued.Top()
        ref = "mpmath Taylor integration at 30 digits (tests/references/engine_torqued.json, case 'asymmetric top')"
        desc = ("Asymmetric top under gravity: I = (1, 1.5, 2) kg m2 about the pivot, centre of mass off every "
                "axis, 8 rad/s; 5 s, 7 outputs.")
        steps = {2: [0.002, 0.001], 4: [0.01, 0.005, 0.0025], 6: [0.02, 0.01, 0.005]}
    scipy_rtols = {"DOP853": [1e-7, 1e-9, 1e-11, 1e-13], "RK45": [1e-6, 1e-8, 1e-10], "LSODA": [1e-7, 1e-9, 1e-11],
                   "Radau": [1e-6, 1e-8]}
    wobble_rtols = [1e-7, 1e-9, 1e-11, 1e-13]
    if quick:
        scipy_rtols = {k: v[:2] for k, v in scipy_rtols.items()}
        wobble_rtols = wobble_rtols[:2]
        steps = {k: v[:1] for k, v in steps.items()}
    case = Case(f"torqued_{which.replace(' ', '_')}", f"Torqued: {c.name}", desc,
                "max over the outputs of ``|omega - omega_ref| / |omega_ref|`` and of the attitude angle (rad)",
                ref, c.t.size)

    def chk(o):
        return {"error": torqued.error(c, o[0], o[1])}

    for method in SCIPY:
        for rtol in scipy_rtols[method]:
            case.runs.append(Run(f"scipy {method}", f"rtol {rtol:g}", torqued.run_scipy(c, method, rtol), chk,
                                 work=lambda o: int(o[2])))
    for rtol in wobble_rtols:
        case.runs.append(Run("wobble DOP853", f"rtol {rtol:g}", torqued.run_wobble(c, "dop853", rtol), chk,
                             work=lambda o: int(o[2])))
    # The same method in NumPy: what a custom torque (a Python callable) runs on.
    for rtol in wobble_rtols:
        case.runs.append(Run("wobble DOP853 (NumPy)", f"rtol {rtol:g}",
                             torqued.run_wobble(c, "dop853", rtol, backend="python"), chk, work=lambda o: int(o[2])))
    for order, hs in steps.items():
        for h in hs:
            case.runs.append(Run(f"wobble splitting-{order}", f"h {h:g} s", torqued.run_wobble(c, "splitting", h, order),
                                 chk, work=lambda o: int(o[2])))
    return case
