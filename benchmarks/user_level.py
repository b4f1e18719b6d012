"""The public API as a user meets it, against the SciPy a user would write.

* ``user_top``: ``HeavyTop(I1=..., I3=..., mgl=..., theta0=..., phidot0=..., omega3=...).motion(t)``,
  Quantities in and a CF Dataset out (the construction, the series of the motion, every
  variable of the Dataset: angles, rates, omega, the attitude, the axis trace, E, p_phi,
  p_psi and their drifts), for the four tops of the top_* cases, 20,001 outputs over 1000
  nutation periods. Baseline: ``scipy.integrate.solve_ivp(method="DOP853")`` on the
  notes' Euler-angle equations in Python floats (the quaternion and omega equations for the
  nearly sleeping top, where the Euler-angle ones cancel), ``t_eval`` the same times,
  no events.
* ``user_free``: ``FreeRotation(moments, omega0).to_dataset(t)`` for the generic body of
  the free_generic case (I = 1, 2, 3 kg m2, omega0 = (1, 0.1, 1) rad/s, 1000 s, 10,001 outputs); the
  Dataset holds omega and the attitude, so the baseline integrates both: Euler's equations
  and q' = q (0, omega) / 2 in Python floats.

The baseline's tolerance is the solver targets': rtol = 1e-12 (the tightest setting they compare),
atol = 1e-12 times each component's scale (1 rad, max(|a|, 1) rad/s, 1 rad, 1 rad for the
Euler angles; |omega0| and 1 for omega and the quaternion). Its error at that setting is
measured, not assumed: the attitude angle (rad) between the run and the mpmath reference
at the reference times (tests/references/heavy_top.json: 7 times up to 1000.25 periods;
free_rotation.json: 2 times, with omega's relative error at 21 times), the same measure
as wobble's. wobble's error is ~1e-15 and DOP853's ~1e-8 at rtol 1e-12, so "equal or
better error" holds for wobble; no DOP853 tolerance reaches wobble's error.

A second wobble row times ``motion(t)`` on a top already built and evaluated once (a
script evaluating several time grids of one top): the series are then reused.
"""

from __future__ import annotations

import math

import numpy as np

from benchmarks.cases import Case, floats, grid, rel_error
from benchmarks.paths import load_json
from benchmarks.timing import Run
from benchmarks.top import CASES, I1, I3, MGL, OMEGA3, run_dop853
from wobble.models.engine import attitude_angle
from wobble.models.top import heavy_top

__all__ = ["RTOL", "user_top_case", "user_free_case"]

RTOL = 1e-12
API_TOP = "wobble API: HeavyTop(...).motion(t)"
API_TOP_BUILT = "wobble API: motion(t), top built"
API_FREE = "wobble API: FreeRotation(...).to_dataset(t)"
PLAIN = "scipy DOP853 (plain, no events)"


def user_top_case(quick: bool) -> Case:
    """The heavy top through the public API against plain DOP853; ``quick``: the cusps top only."""
    import astropy.units as u

    from wobble import HeavyTop

    tops = CASES[:1] if quick else CASES
    case = Case(
        "user_top",
        "User level: HeavyTop(...).motion(t) against plain SciPy DOP853",
        "The four heavy tops of the work-precision benchmark (I1 = 1, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 "
        "rad/s; theta0 = 60 deg with phidot0 = 0, 0.3, -0.3 rad/s, and theta0 = 1e-4 rad), 1000 nutation periods, "
        "20,001 outputs. wobble: "
        "HeavyTop(...) with Quantities, then .motion(t) with t a time Quantity: construction, the series of the "
        "motion and the whole CF Dataset. SciPy: solve_ivp(method='DOP853', t_eval=t) on the Euler-angle equations "
        "in Python floats (omega and quaternion equations for theta0 = 1e-4 rad), rtol 1e-12, no events.",
        "attitude angle error (rad), max over the mpmath reference times",
        "mpmath (tests/references/heavy_top.json): the attitude at 7 times up to 1000.25 periods",
        20_001,
        complete=not quick,
    )
    refs = {c["name"]: c for c in load_json("tests", "references", "heavy_top.json")["cases"]}
    stages = None
    cpu = []
    for label, refname, kw in tops:
        ref = refs[refname]
        mdl = heavy_top(I1, I3, MGL, omega3=OMEGA3, **kw)
        ref_t, ref_q = floats(ref["long"]["t"]), floats(ref["long"]["quaternion"])
        t, (iq,) = grid(np.linspace(0.0, 1000 * mdl.nutation_period, 20_001), ref_t)
        ts = t * u.s
        q_exact = mdl.attitude(t)
        args = dict(
            I1=I1 * u.kg * u.m**2,
            I3=I3 * u.kg * u.m**2,
            mgl=MGL * u.J,
            theta0=kw["theta0"] * u.rad,
            phidot0=kw["phidot0"] * u.rad / u.s,
            omega3=OMEGA3 * u.rad / u.s,
        )
        built = HeavyTop(**args)
        built.motion(ts)  # the series built once, as after a first evaluation
        if stages is None:
            stages = _stages(HeavyTop, args, ts, label)
        if not quick:  # one more DOP853 run per top (seconds): the full run only
            cpu.append(
                (label, *_cpu_times(HeavyTop, args, ts, mdl, t, "euler" if kw["theta0"] > 0.1 else "quaternion"))
            )

        def check(q, iq=iq, ref_q=ref_q, q_exact=q_exact, n=t.size):
            if q.shape != (n, 4) or not np.all(np.isfinite(q)):
                return {"error": math.inf}
            e_ref = float(np.max(attitude_angle(q[iq], ref_q)))
            e_all = float(np.max(attitude_angle(q, q_exact)))
            return {"error": e_ref, "error_vs_mpmath": e_ref, "error_vs_exact": e_all}

        kind = "euler" if kw["theta0"] > 0.1 else "quaternion"
        case.runs.append(
            Run(
                API_TOP,
                label,
                lambda a=args, ts=ts: HeavyTop(**a).motion(ts),
                lambda ds, c=check: c(ds["attitude"].values),
            )
        )
        case.runs.append(
            Run(API_TOP_BUILT, label, lambda b=built, ts=ts: b.motion(ts), lambda ds, c=check: c(ds["attitude"].values))
        )

        def plain(mdl=mdl, t=t, kind=kind):
            tt, th, q, _ = run_dop853(mdl, t, kind, rtol=RTOL, events=False)
            return q if tt.size == t.size else np.full((t.size, 4), np.nan)

        case.runs.append(
            Run(
                PLAIN,
                f"{label}: rtol 1e-12, {kind} equations",
                plain,
                lambda q, c=check: c(q / np.linalg.norm(q, axis=1, keepdims=True)),
            )
        )
    case.context["stages"] = stages
    case.notes.append(
        "Where the time of the first row goes (" + stages["top"] + ", minima of 20 runs each, outside the interleaved "
        f"timing): HeavyTop(...) {stages['construction'] * 1e3:.2f} ms (the unit conversions and the 60-digit "
        f"analysis); building the verified series of the motion {stages['series'] * 1e3:.2f} ms (once per top); "
        f"the motion at every output {stages['motion'] * 1e3:.2f} ms (one compiled call, in blocks); the times' "
        f"conversion and the CF Dataset {stages['dataset'] * 1e3:.2f} ms (astropy, xarray)."
    )
    if cpu:
        case.notes.append(
            "The same comparison in CPU time (time.thread_time, to which the other processes of a busy machine add "
            "nothing, though they still slow its caches), outside the interleaved timing: HeavyTop(...).motion(t), "
            "minimum of 20 runs, against one plain DOP853 run: "
            + "; ".join(f"{name} {call * 1e3:.2f} ms vs {dop:.2f} s, {dop / call:.0f}x" for name, call, dop in cpu)
            + "."
        )
    return case


def _cpu_times(HeavyTop, args, ts, mdl, t, kind):
    """CPU time of the user's call (minimum of 20) and of one plain DOP853 run, in s."""
    import time

    out = []
    for _ in range(20):
        c0 = time.thread_time()
        HeavyTop(**args).motion(ts)
        out.append(time.thread_time() - c0)
    c0 = time.thread_time()
    run_dop853(mdl, t, kind, rtol=RTOL, events=False)
    return min(out), time.thread_time() - c0


def _stages(HeavyTop, args, ts, label):
    """Minimum times of the stages of HeavyTop(...).motion(t): construction, series, motion, Dataset."""
    import time

    from wobble.models import top_series

    def best(fn, n=20):
        out = []
        for _ in range(n):
            t0 = time.perf_counter()
            fn()
            out.append(time.perf_counter() - t0)
        return min(out)

    from wobble.numerics import compiled

    top = HeavyTop(**args)
    t = ts.to_value("s")
    mdl = top.model
    direct = mdl.evaluator(1, "direct")  # the closed-form evaluator the series are built from
    fast = t.size >= compiled.LONG_ARRAY and compiled.available()  # as HeavyTopModel.evaluator sets it up
    motion = best(lambda: mdl.motion(t))
    return {
        "top": label,
        "construction": best(lambda: HeavyTop(**args)),
        "series": best(lambda: top_series.build(direct, mdl.error_estimate, fast)),
        "motion": motion,
        "dataset": best(lambda: top.motion(ts)) - motion,  # the times' conversion and the Dataset
    }


def _free_rhs(moments):
    """Euler's equations and the attitude quaternion's, in Python floats (as a SciPy user writes them)."""
    i1, i2, i3 = (float(x) for x in moments)
    a, b, c = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3

    def f(t, y):
        w1, w2, w3, qw, qx, qy, qz = y
        return [
            a * w2 * w3,
            b * w3 * w1,
            c * w1 * w2,
            -0.5 * (qx * w1 + qy * w2 + qz * w3),
            0.5 * (qw * w1 + qy * w3 - qz * w2),
            0.5 * (qw * w2 - qx * w3 + qz * w1),
            0.5 * (qw * w3 + qx * w2 - qy * w1),
        ]

    return f


def user_free_case(quick: bool) -> Case:
    """The generic free body through the public API against plain DOP853 (omega and attitude)."""
    import astropy.units as u
    from scipy.integrate import solve_ivp

    from wobble import FreeRotation

    closed = load_json("tests", "references", "free_rotation.json")["closed"]
    ref = next(c for c in closed if c["name"] == "generic 1000 s")
    moments, w0 = floats(ref["moments"]), floats(ref["omega0"])
    ref_t, ref_w = floats(ref["t"]), floats(ref["omega"])
    att_t, att_q = floats(ref["attitude_t"]), floats(ref["attitude"])
    t, (iw, iq) = grid(np.linspace(0.0, 1000.0, 10_001), ref_t, att_t)
    case = Case(
        "user_free",
        "User level: FreeRotation(...).to_dataset(t) against plain SciPy DOP853",
        "The generic free body of the work-precision benchmark: I = (1, 2, 3) kg m2, omega0 = (1, 0.1, 1) rad/s, "
        "1000 s, 10,001 outputs. "
        "wobble: FreeRotation(moments, omega0) with Quantities, then .to_dataset(t): construction, omega and the "
        "attitude, the CF Dataset. SciPy: solve_ivp(method='DOP853', t_eval=t) on Euler's equations and the "
        "quaternion's, in Python floats, rtol 1e-12, no events.",
        "max of omega's relative error and the attitude angle (rad) at the mpmath reference times",
        "mpmath (tests/references/free_rotation.json, case 'generic 1000 s'): omega at 21 times, the attitude at 2",
        10_001,
        complete=not quick,
    )
    ts = t * u.s
    m_q, w0_q = moments * u.kg * u.m**2, w0 * u.rad / u.s

    def check(w, q):
        if w.shape != (t.size, 3) or q.shape != (t.size, 4) or not np.all(np.isfinite(q)):
            return {"error": math.inf}
        ew = rel_error(w[iw], ref_w)
        eq = float(np.max(attitude_angle(q[iq] / np.linalg.norm(q[iq], axis=1, keepdims=True), att_q)))
        return {"error": max(ew, eq), "error_vs_mpmath": max(ew, eq), "attitude_error_rad": eq}

    case.runs.append(
        Run(
            API_FREE,
            "generic",
            lambda: FreeRotation(m_q, w0_q).to_dataset(ts),
            lambda ds: check(ds["omega"].values, ds["attitude"].values),
        )
    )
    f = _free_rhs(moments)
    y0 = np.concatenate([w0, [1.0, 0.0, 0.0, 0.0]])
    atol = RTOL * np.array([np.linalg.norm(w0)] * 3 + [1.0] * 4)

    def plain():
        sol = solve_ivp(f, (t[0], t[-1]), y0, method="DOP853", t_eval=t, rtol=RTOL, atol=atol)
        if not sol.success or sol.y.shape[1] != t.size:
            return np.full((t.size, 3), np.nan), np.full((t.size, 4), np.nan)
        return sol.y[:3].T, sol.y[3:].T

    case.runs.append(Run(PLAIN, "generic: rtol 1e-12, omega and quaternion", plain, lambda o: check(*o)))
    return case
