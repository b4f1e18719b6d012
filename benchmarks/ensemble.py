"""Ensembles of 10^2 to 10^6 members: per-member cost of wobble's vectorised solvers.

Two ensembles, members with perturbed initial angular velocity:

* ``satellite``: 30 s of the gravity-gradient satellite (torqued; no exact solution),
  7 outputs. wobble's DOP853 (compiled, and in NumPy) and 6th-order splitting integrate
  all members in one call;
  SciPy's DOP853 loops over members (its per-member cost measured on 5 probe members).
  Errors on the probes against SciPy's LSODA at rtol 1e-13, atol 1e-16 (a method
  different from every one measured).
* ``free``: 30 s of the generic free body, 7 outputs. wobble's exact flow
  (:func:`wobble.models.free_flow.free_flow`, vectorised) against wobble's DOP853 and a loop
  of SciPy's DOP853; errors on the probes against wobble's exact solution per member
  (:func:`wobble.models.free.free_rotation`, checked against mpmath in the tests).

A size is skipped when the time predicted from the previous size exceeds ``cap_s``;
the report says so with the prediction.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks import torqued
from benchmarks.cases import rel_error
from benchmarks.free import free_euler_rhs
from benchmarks.timing import Run, measure, time_at
from wobble.models.engine import BodyModel, Engine, attitude_angle
from wobble.models.free import free_rotation
from wobble.models.free_flow import free_flow
from wobble.numerics import quaternion as Q

PROBES = 5


def _members(w0, n, seed=11, spread=0.002):
    return w0 + spread * np.random.default_rng(seed).normal(size=(n, 3))


def ensemble(which: str, sizes, repeats: int, cap_s: float, progress=None, scipy_rtols=(1e-7, 1e-9, 1e-11)) -> dict:
    """Per-member cost of wobble's solvers on ensembles of ``sizes`` members against a loop of
    SciPy's DOP853 at ``scipy_rtols`` (its cost measured on the probe members)."""
    span, outputs = 30.0, 7
    t = np.linspace(0.0, span, outputs)
    q1 = np.array([1.0, 0.0, 0.0, 0.0])
    if which == "satellite":
        c = torqued.Satellite(span=span, outputs=outputs)
        moments, torques, w0, f = c.moments, c.torques, c.w0, c.scipy_rhs()
        w_all = _members(w0, max(sizes))
        refs = []
        for i in range(PROBES):
            s = solve_ivp(
                f, (0.0, span), np.concatenate([w_all[i], q1]), method="LSODA", rtol=1e-13, atol=1e-16, t_eval=t
            )
            refs.append((s.y[:3].T, Q.normalize(s.y[3:].T)))
        wobble_settings = [
            ("wobble DOP853", "rtol 1e-9", dict(method="dop853", rtol=1e-9)),
            ("wobble DOP853 (NumPy)", "rtol 1e-9", dict(method="dop853", rtol=1e-9, backend="python")),
            ("wobble splitting-6", "h 0.75 s", dict(method="splitting", step=0.75, order=6)),
        ]
        title = "Ensemble: gravity-gradient satellites, 30 s, 7 outputs"
        reference = "SciPy LSODA at rtol 1e-13, atol 1e-16 on 5 probe members"
    else:
        moments, torques, w0 = np.array([1.0, 2.0, 3.0]), [], np.array([1.0, 0.1, 1.0])
        w_all = _members(w0, max(sizes), spread=0.01)
        f = free_euler_rhs(moments)  # the SciPy loop integrates omega only (Euler's equations)
        refs = []
        for i in range(PROBES):
            m = free_rotation(moments, w_all[i])
            refs.append((m.omega(t), m.attitude(t)))
        wobble_settings = [
            ("wobble exact flow", "free_flow", None),
            ("wobble DOP853", "rtol 1e-10", dict(method="dop853", rtol=1e-10)),
        ]
        title = "Ensemble: generic free bodies, 30 s, 7 outputs"
        reference = "wobble's exact solution per member (free_rotation, checked against mpmath) on 5 probe members"

    def member_error(w, q, i):
        wr, qr = refs[i]
        e = rel_error(w, wr)
        if q is not None:
            e = max(e, float(np.max(attitude_angle(q, qr))))
        return e

    # SciPy's DOP853, looping over the probe members.
    scipy_runs = []
    for rtol in scipy_rtols:

        def loop(rtol=rtol):
            out = []
            for i in range(PROBES):
                y0 = np.concatenate([w_all[i], q1]) if which == "satellite" else w_all[i]
                s = solve_ivp(f, (0.0, span), y0, method="DOP853", rtol=rtol, atol=rtol * 1e-3, t_eval=t)
                out.append((s.y[:3].T, Q.normalize(s.y[3:].T) if which == "satellite" else None))
            return out

        scipy_runs.append(
            Run(
                "scipy DOP853 (loop)",
                f"rtol {rtol:g}",
                loop,
                lambda out: {"error": max(member_error(w, q, i) for i, (w, q) in enumerate(out))},
            )
        )
    scipy_rows = measure(scipy_runs, repeats)
    for r in scipy_rows:
        r["per_member_s"] = r["t_min"] / PROBES
    scipy_points = [(r["error"], r["per_member_s"]) for r in scipy_rows]
    rows, skipped = [], []
    predicted = {}
    for n in sizes:
        runs = []
        for label, setting, kw in wobble_settings:
            key = (label, setting)
            if predicted.get(key, 0.0) > cap_s:
                skipped.append({"members": n, "method": label, "setting": setting, "predicted_s": predicted[key]})
                continue
            if kw is None:

                def go(n=n):
                    w = w_all[:n]
                    q = np.broadcast_to(q1, (n, 4))
                    return [free_flow(moments, w, q, h) for h in t]

                def chk(out):
                    return {
                        "error": max(
                            member_error(np.array([o[0][i] for o in out]), np.array([o[1][i] for o in out]), i)
                            for i in range(PROBES)
                        )
                    }
            else:
                eng = Engine(BodyModel.from_moments(moments), torques, members=n)

                def go(eng=eng, n=n, kw=kw):
                    return eng.integrate(w_all[:n], q1, t, estimate=False, **kw)

                def chk(tr):
                    return {"error": max(member_error(tr.omega[:, i], tr.attitude[:, i], i) for i in range(PROBES))}

            runs.append(Run(label, setting, go, chk))
        if not runs:
            continue
        if progress:
            progress(f"  {n} members")
        for r in measure(runs, repeats if n <= 10_000 else 1, slow_s=2.0, progress=progress):
            r["members"] = n
            r["per_member_s"] = r["t_min"] / n
            ref = time_at(scipy_points, max(r["error"], min(e for e, _ in scipy_points)))
            r["scipy_per_member_s"] = ref
            r["ratio_vs_scipy"] = None if ref is None else ref / r["per_member_s"]
            rows.append(r)
            predicted[(r["method"], r["setting"])] = r["t_min"] * 10  # the next size is 10 times larger
    return {
        "key": f"ensemble_{which}",
        "title": title,
        "reference": reference,
        "scipy": scipy_rows,
        "rows": rows,
        "skipped": skipped,
        "cap_s": cap_s,
        "error_measure": "max over the probe members and outputs of the relative omega error and the attitude "
        "angle (rad)",
    }


def best_ratio(result: dict, members: int) -> float | None:
    r = [x["ratio_vs_scipy"] for x in result["rows"] if x["members"] == members and x["ratio_vs_scipy"]]
    return max(r) if r else None


__all__ = ["ensemble", "best_ratio"]
