"""Benchmark: wobble's exact free-body solution against scipy, per sample and per run.

Usage: python scripts/bench_free_eval.py [--quick]   (writes docs/performance-free.md)

Times, in one process and interleaved (one warm-up, then min and median of
repeats, DifferentialEquations.jl work-precision style):

* per-sample cost of wobble's omega(t) (and omega + attitude) against
  scipy.special.ellipj on the same number of arguments;
* the generic case (I = 1, 2, 3 kg m2; omega0 = (1, 0.1, 1) rad/s;
  1000 s; 10^4 outputs) against scipy.integrate.solve_ivp DOP853 at rtol 1e-12;
* the same within 2e-12 of the separatrix (omega0 = (1e-6, 1, 1e-6), 200 s) with flip times;
* Earth-like free wobble over 100 years with 36,526 daily outputs.

Errors are measured against the mpmath references in
tests/references/free_rotation.json (independent of wobble).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np
import scipy
import scipy.special as sp
from scipy.integrate import solve_ivp

import wobble
from wobble.models.free import free_rotation

ROOT = Path(__file__).resolve().parents[1]
REF = json.loads((ROOT / "tests" / "references" / "free_rotation.json").read_text())
CLOSED = {c["name"]: c for c in REF["closed"]}


def timeit(fn, repeats):
    fn()  # warm-up
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), statistics.median(ts)


def interleaved(fns: dict, repeats: int):
    for fn in fns.values():
        fn()  # warm-up
    times = {k: [] for k in fns}
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - t0)
    return {k: (min(v), statistics.median(v)) for k, v in times.items()}


def ref_error(model, case):
    t = np.array([float(x) for x in case["t"]])
    want = np.array([[float(v) for v in row] for row in case["omega"]])
    got = model.omega(t)
    return float(np.max(np.linalg.norm(got - want, axis=1) / np.linalg.norm(want, axis=1)))


def euler_rhs(I):
    def f(t, w):
        return np.cross(I * w, w) / I

    return f


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    args = ap.parse_args(argv)
    reps = 5 if args.quick else 30
    rows = []

    # 1. Per-sample cost against scipy.special.ellipj (same N, same process).
    I = np.array([1.0, 2.0, 3.0])
    w0 = np.array([1.0, 0.1, 1.0])
    model = free_rotation(I, w0)
    n = 10_000
    t = np.linspace(0.0, 1000.0, n + 1)
    u_arg = 1.3 * t + 0.2
    res = interleaved(
        {
            "ellipj": lambda: sp.ellipj(u_arg, model.m),
            "omega": lambda: model.omega(t),
            "omega+attitude": lambda: (model.omega(t), model.attitude(t)),
        },
        reps,
    )
    per = {k: v[0] / t.size * 1e9 for k, v in res.items()}
    med = {k: v[1] / t.size * 1e9 for k, v in res.items()}

    # 2. Generic case against DOP853 at rtol 1e-12.
    gen = CLOSED["generic 1000 s"]
    exact_err = ref_error(model, gen)

    def dop():
        return solve_ivp(euler_rhs(I), (0, 1000.0), w0, method="DOP853", t_eval=t, rtol=1e-12, atol=1e-14)

    res2 = interleaved({"exact": lambda: model.omega(t), "dop853": dop}, max(3, reps // 10))
    sol = dop()
    exact_t = model.omega(t)
    dop_err = float(np.max(np.linalg.norm(sol.y.T - exact_t, axis=1) / np.linalg.norm(exact_t, axis=1)))
    rows.append(("generic, 1000 s, 10^4 outputs: wobble exact omega", res2["exact"], exact_err))
    rows.append(("generic: solve_ivp DOP853 rtol 1e-12 (error vs exact)", res2["dop853"], dop_err))

    # 3. Near the separatrix: omega and flip times.
    sepc = CLOSED["separatrix 2e-12"]
    sep = free_rotation(I, np.array([1e-6, 1.0, 1e-6]))
    ts = np.linspace(0.0, 200.0, n + 1)
    sep_err = ref_error(sep, sepc)
    ts = np.linspace(0.0, 200.0, n + 1)
    flips = sep.flip_times(0.0, 200.0)
    flip_err = float(np.max(np.abs(flips - np.array([float(x) for x in sepc["flip_times"]]))))
    r3 = interleaved({"sep": lambda: sep.omega(ts)}, reps)
    rows.append(("separatrix 1-m = 2e-12, 200 s, 10^4 outputs: wobble exact omega", r3["sep"], sep_err))

    # 4. Earth, 100 years daily.
    ec = CLOSED["Earth 100 years"]
    earth = free_rotation([float(x) for x in ec["moments"]], [float(x) for x in ec["omega0"]])
    td = np.arange(36526) * 86400.0
    tw = np.array([float(x) for x in ec["t"]])
    want = np.array([[float(v) for v in row] for row in ec["omega"]])
    got = earth.omega(tw)
    phase_err = float(np.max(np.hypot(*(got[:, :2] - want[:, :2]).T) / np.hypot(*want[:, :2].T)))
    r4 = interleaved(
        {"earth": lambda: earth.omega(td), "earth_att": lambda: (earth.omega(td), earth.attitude(td))}, reps
    )
    xs = td * 2.4e-7
    sin_t = timeit(lambda: np.sin(xs), reps)[0]
    rows.append(("Earth 100 yr, 36,526 daily outputs: omega (wobble phase error, rad)", r4["earth"], phase_err))
    rows.append(("Earth 100 yr, 36,526 daily outputs: omega + attitude", r4["earth_att"], phase_err))

    lines = [
        "# Performance of the exact free-body solution",
        "",
        "Generated by `python scripts/bench_free_eval.py` (do not edit by hand) on "
        f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC.",
        f"Machine: {platform.machine()}, {platform.processor() or 'unknown CPU'}, Python {platform.python_version()}, "
        f"NumPy {np.__version__}, SciPy {scipy.__version__}, wobble {wobble.__version__}; "
        f"{os.cpu_count()} CPUs with a load average (1, 5, 15 min) of {', '.join(f'{x:.2f}' for x in os.getloadavg())} "
        "at the end of the run. "
        f"Timings: one warm-up, then min and median of repeats, methods interleaved in one process.",
        "",
        "## Cost per sample against scipy.special.ellipj",
        "",
        f"{t.size} samples, parameter m = {model.m:.6f} (generic case).",
        "",
        "| evaluation | min (ns/sample) | median (ns/sample) | ratio to ellipj (min) |",
        "|---|---|---|---|",
    ]
    for k in ("ellipj", "omega", "omega+attitude"):
        lines.append(f"| {k} | {per[k]:.1f} | {med[k]:.1f} | {per[k] / per['ellipj']:.2f} |")
    lines += [
        "",
        "`omega` is the whole exact solution (double-double phase, reduction, sn/cn/dn, scaling);",
        "`omega+attitude` adds the quaternion (Carlson R_F, R_C, R_J per sample).",
        "",
        "## Cases of the work-precision benchmark",
        "",
        "| case / method | min (s) | median (s) | max relative error |",
        "|---|---|---|---|",
    ]
    for name, (tmin, tmed), err in rows:
        lines.append(f"| {name} | {tmin:.3g} | {tmed:.3g} | {err:.1e} |")
    speedup = res2["dop853"][0] / res2["exact"][0]
    lines += [
        "",
        f"Generic case: wobble's exact solution is {speedup:.0f} times faster than DOP853 at rtol 1e-12 "
        f"(target: at least 100) and {dop_err / max(exact_err, 1e-300):.0e} times more accurate "
        f"(wobble {exact_err:.1e} against mpmath, target 1e-13).",
        f"Near the separatrix (1 - m = {sep.m1:.3g}): omega error {sep_err:.1e} against mpmath (target 1e-10); "
        f"flip times within {flip_err:.1e} s of mpmath's (target 1e-9 s).",
        f"Earth, 100 years daily: wobble phase error {phase_err:.1e} rad (target 1e-12) in "
        f"{r4['earth'][0] * 1e3:.2f} ms for omega (target under 1 ms).",
        (
            f"Target missed on this machine: {r4['earth'][0] * 1e3:.2f} ms, {r4['earth'][0] / 1e-3:.1f} times the "
            "1 ms goal "
            f"(one np.sin over the same 36,526 values takes {sin_t * 1e3:.2f} ms here)."
            if r4["earth"][0] > 1e-3
            else f"Earth target met: {r4['earth'][0] * 1e3:.2f} ms (one np.sin over the same 36,526 values takes "
            f"{sin_t * 1e3:.2f} ms here)."
        ),
        "A uniform daily grid takes the block-rotation path (docs/free-rotation.md, 'Long spans'): exact phasors at",
        "~sqrt(N) block starts, one complex product per sample, sn/cn/dn from their nome series (m ~ 1e-14 here).",
        "",
        "Errors of wobble are against the mpmath references of tests/references/free_rotation.json;",
        "the DOP853 error is against wobble's exact solution at all 10^4 outputs.",
    ]
    out = ROOT / "docs" / "performance-free.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
