"""The exact free body's cases: generic, near the separatrix, Earth over a century.

wobble's exact solution (and with the attitude) against SciPy's RK45, DOP853, LSODA and
Radau and wobble's compiled DOP853 on Euler's equations, all against the committed mpmath
references (tests/references/free_rotation.json) and the exact solution at every output.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.cases import SCIPY, Case, floats, grid, phase_error, rel_error
from benchmarks.paths import load_json
from benchmarks.timing import Run
from wobble.models.engine import BodyModel, Engine, attitude_angle
from wobble.models.free import free_rotation

__all__ = ["FREE", "free_case", "free_euler_rhs", "solve", "sol_omega"]


def free_euler_rhs(moments):
    """Euler's equations for a free body as a SciPy user writes them (Python floats)."""
    i1, i2, i3 = (float(x) for x in moments)
    a, b, c = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3

    def f(t, w):
        w1, w2, w3 = w
        return [a * w2 * w3, b * w3 * w1, c * w1 * w2]

    return f


def solve(f, t, y0, method, rtol, atol):
    """solve_ivp from t[0] to t[-1] with outputs at t."""
    return solve_ivp(f, (t[0], t[-1]), y0, method=method, t_eval=t, rtol=rtol, atol=atol)


def sol_omega(sol, n):
    """omega (n, 3) of a SciPy solution, NaN where the run failed."""
    return sol.y[:3].T if sol.success and sol.y.shape[1] == n else np.full((n, 3), np.nan)


FREE = {
    "free_generic": dict(
        ref="generic 1000 s",
        t_end=1000.0,
        n=10_001,
        title="Generic asymmetric free body",
        description="I = (1, 2, 3) kg m2, omega0 = (1, 0.1, 1) rad/s, 1000 s, 10^4 output intervals.",
    ),
    "free_separatrix": dict(
        ref="separatrix 2e-12",
        t_end=200.0,
        n=10_001,
        title="Free body near the separatrix",
        description="I = (1, 2, 3) kg m2, omega0 = (1e-6, 1, 1e-6) rad/s (1 - m = 2e-12), "
        "200 s, 10^4 output intervals; flip times of the exact solution.",
    ),
    "free_earth": dict(
        ref="Earth 100 years",
        t_end=None,
        n=36_526,
        title="Earth-like free wobble, 100 years daily",
        description="Earth's principal moments (8.01012e37, 8.01032e37, 8.03652e37 kg m2, the "
        "catalogue values of tests/references/free_rotation.json) spinning at 7.292115e-5 rad/s, "
        "rotation axis 1e-6 rad from the figure axis; 36,526 daily outputs.",
    ),
}


def free_case(key: str, quick: bool) -> Case:
    """The case ``key`` of :data:`FREE`; ``quick``: fewer tolerances."""
    spec = FREE[key]
    ref = next(c for c in load_json("tests", "references", "free_rotation.json")["closed"] if c["name"] == spec["ref"])
    I = floats(ref["moments"])
    w0 = floats(ref["omega0"])
    ref_t, ref_w = floats(ref["t"]), floats(ref["omega"])
    att_t, att_q = floats(ref["attitude_t"]), floats(ref["attitude"])
    if key == "free_earth":
        t0 = np.arange(spec["n"]) * 86400.0
    else:
        t0 = np.linspace(0.0, spec["t_end"], spec["n"])
    t, (iw, iq) = grid(t0, ref_t, att_t)
    exact = free_rotation(I, w0)
    w_exact = exact.omega(t)
    earth = key == "free_earth"
    measure = phase_error if earth else rel_error
    what = (
        "wobble phase error (rad): max wrapped difference of atan2(omega2, omega1)"
        if earth
        else "max relative error of omega, ``|omega - omega_ref| / |omega_ref|``"
    )
    case = Case(
        key,
        spec["title"],
        spec["description"],
        what,
        f"mpmath (tests/references/free_rotation.json, case '{spec['ref']}') at {ref_t.size:d} times; "
        "integrators also against wobble's exact solution at every output",
        t0.size,
        complete=not quick,
    )
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
        flips_ref = floats(ref["flip_times"])

        def check_exact(w, _c=check_exact):
            flips = exact.flip_times(0.0, float(t[-1]))
            err = float(np.max(np.abs(flips - flips_ref))) if flips.shape == flips_ref.shape else math.inf
            return {**_c(w), "flip_time_error_s": err}

    case.runs.append(Run("wobble exact", "omega", lambda: free_rotation(I, w0).omega(t), check_exact))
    if earth:
        # The evaluation alone (the model built once, as a script reusing it would): what the
        # Earth target's "36,526 daily outputs in under 1 ms" measures; construction is separate.
        case.runs.append(
            Run("wobble exact (evaluation only)", "omega (model built)", lambda: exact.omega(t), check_exact)
        )
    case.runs.append(
        Run(
            "wobble exact + attitude",
            "omega, quaternion",
            lambda: (lambda m: (m.omega(t), m.attitude(t)))(free_rotation(I, w0)),
            check_exact_att,
        )
    )
    # The integrators.
    scale = float(np.hypot(w0[0], w0[1])) if earth else float(np.linalg.norm(w0))
    rtols = {
        "DOP853": [1e-6, 1e-8, 1e-10, 1e-12],
        "RK45": [1e-5, 1e-7, 1e-9],
        "LSODA": [1e-6, 1e-8, 1e-10, 1e-12],
        "Radau": [1e-4, 1e-6, 1e-8],
        "wobble DOP853": [1e-6, 1e-8, 1e-10, 1e-12],
    }
    if quick:
        rtols = {k: v[:2] for k, v in rtols.items()}
    f = free_euler_rhs(I)
    for method in SCIPY:
        for rtol in rtols[method]:
            # atol relative to the wobble for Earth (a user controls the small components)
            atol = rtol * (scale if earth else 1e-3 * scale)
            case.runs.append(
                Run(
                    f"scipy {method}",
                    f"rtol {rtol:g}",
                    lambda m=method, r=rtol, a=atol: solve(f, t, w0, m, r, a),
                    lambda s: check_integrator(sol_omega(s, t.size)),
                    work=lambda s: int(s.nfev),
                )
            )
    eng = Engine(BodyModel.from_moments(I), [])
    q1 = np.array([1.0, 0.0, 0.0, 0.0])
    for rtol in rtols["wobble DOP853"]:
        case.runs.append(
            Run(
                "wobble DOP853",
                f"rtol {rtol:g}",
                lambda r=rtol: eng.integrate(w0, q1, t, method="dop853", rtol=r, attitude=False, estimate=False),
                lambda tr: check_integrator(tr.omega[:, 0]),
                work=lambda tr: int(tr.stats["function_evaluations"]),
            )
        )
    case.notes.append(
        "The splitting integrators are not swept here: without a torque their drift is the exact "
        "free flow, so they return the exact solution at any step."
    )
    return case
