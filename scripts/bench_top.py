"""Benchmark: wobble's exact heavy top against scipy's DOP853 (and Radau) on four tops.

Usage: python scripts/bench_top.py [--quick] [--no-radau]     (writes docs/performance-top.md)

Cases: I1 = 1 kg m2, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 rad/s,
theta0 = 60 deg, released with phidot0 = 0 (cusps), +0.3 rad/s (undulating) and
-0.3 rad/s (loops); and a nearly sleeping top, theta0 = 1e-4 rad. Span: 1000
nutation periods, 20,001 equally spaced outputs.

Methods, timed in the same process, interleaved (one warm-up, then min and median
of repeats, as in DifferentialEquations.jl's work-precision diagrams):

* wobble exact: ``heavy_top(...)`` (the analysis, roots in 60-digit decimal) plus
  ``angles(t)`` (theta, phi, psi at all outputs); also the evaluation alone and the
  full state ``evaluate(t)`` (body omega and the attitude quaternion);
* scipy.integrate.solve_ivp DOP853 at rtol 1e-12 on the same equations: the notes'
  Euler-angle equations (theta, thetadot, phi, psi) for the 60 deg cases; for the
  nearly sleeping top, where the Euler-angle right-hand side cancels catastrophically,
  the non-singular quaternion + omega equations (wobble.models.top_ode.top_rhs).
  timed without events; the turning points for the error columns come from a separate
  run with solve_ivp events (thetadot = 0, or d(cos theta)/dt = 0);
* Radau at rtol 1e-10 on the cusps case (its cost grows steeply with tolerance).

Errors are measured against the mpmath references of tests/references/heavy_top.json
(independent of wobble): the turning angles (relative) and the attitude at times up
to 1000.25 periods (rad). The DOP853 trajectories are also compared with wobble's at
all 20,001 outputs.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import scipy

import wobble
from wobble.models.top import heavy_top

ROOT = Path(__file__).resolve().parents[1]
# The cases and the SciPy baselines live in benchmarks/ (a folder of the checkout), shared with
# the work-precision harness (wobble bench, scripts/work_precision.py).
sys.path.insert(0, str(ROOT))
from benchmarks.top import CASES, I1, I3, MGL, OMEGA3, angle_between, run_dop853, turning_error  # noqa: E402 - after sys.path.insert(0, ROOT)

REF = {c["name"]: c for c in json.loads((ROOT / "tests" / "references" / "heavy_top.json").read_text())["cases"]}


def interleaved(fast: dict, slow: dict, rounds: int, fast_per_round: int) -> dict:
    """One warm-up each, then ``rounds`` rounds; each round runs every slow method once and
    every fast method ``fast_per_round`` times, so all see the same machine load."""
    fns = {**fast, **slow}
    for fn in fns.values():
        fn()  # warm-up
    times = {k: [] for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            for _ in range(fast_per_round if k in fast else 1):
                t0 = time.perf_counter()
                fn()
                times[k].append(time.perf_counter() - t0)
    return {k: (min(v), statistics.median(v)) for k, v in times.items()}


def accuracy_rows():
    rows = []
    for name, c in REF.items():
        inp = {k: float(v) for k, v in c["inputs"].items()}
        mdl = heavy_top(
            inp["I1"],
            inp["I3"],
            inp["mgl"],
            inp["theta0"],
            inp["thetadot0"],
            inp["phidot0"],
            omega3=inp["omega3"],
            phi0=inp["phi0"],
            psi0=inp["psi0"],
        )
        an = c["analysis"]
        if mdl.nutation == "sleeping":
            turn = max(mdl.theta_min, mdl.theta_max)  # both 0 exactly
        else:
            turn = max(
                abs(mdl.theta_min - float(an["theta_min"])) / max(float(an["theta_min"]), 1e-300),
                abs(mdl.theta_max - float(an["theta_max"])) / float(an["theta_max"]),
            )
        per = abs(mdl.nutation_period / float(an["period"]) - 1) if "period" in an else float("nan")
        cells = []
        for key in ("ode", "long"):
            if key not in c:
                cells.append("-")
                continue
            t = np.array([float(x) for x in c[key]["t"]])
            qr = np.array([[float(v) for v in r] for r in c[key]["quaternion"]])
            errs = [float(np.max(angle_between(mdl.attitude(t, m_), qr))) for m_ in ("direct", "fourier")]
            cells.append(f"{errs[0]:.1e} / {errs[1]:.1e}")
        per_s = "-" if np.isnan(per) else f"{per:.1e}"
        rows.append(f"| {name} | {mdl.nutation} | {turn:.1e} | {per_s} | {cells[0]} | {cells[1]} |")
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--no-radau", action="store_true", help="skip the Radau run")
    args = ap.parse_args(argv)
    reps_fast = 3 if args.quick else 20
    reps_slow = 1 if args.quick else 3
    load_start = os.getloadavg()
    started = time.perf_counter()
    rows = []
    summary = []
    split = []
    for label, refname, kw in CASES:
        ref = REF[refname]
        mdl = heavy_top(I1, I3, MGL, omega3=OMEGA3, **kw)
        period = mdl.nutation_period
        t = np.linspace(0.0, 1000 * period, 20001)
        ref_t = np.array([float(x) for x in ref["long"]["t"]])
        ref_q = np.array([[float(v) for v in r] for r in ref["long"]["quaternion"]])
        kind = "euler" if kw["theta0"] > 0.1 else "quaternion"

        def exact_angles(kw=kw):
            m = heavy_top(I1, I3, MGL, omega3=OMEGA3, **kw)
            return m.angles(t)

        def exact_eval_only(mdl=mdl):
            return mdl.angles(t)

        def exact_state(mdl=mdl):
            return mdl.evaluate(t)

        def dop(mdl=mdl, kind=kind):  # timed without events (they are only for the error run)
            return run_dop853(mdl, t, kind, events=False)

        res = interleaved(
            {"angles": exact_angles, "eval": exact_eval_only, "state": exact_state},
            {"dop853": dop},
            reps_slow,
            reps_fast,
        )
        fast = slow = res
        # Errors. wobble: analysis against mpmath; attitude at the reference times.
        w_turn = max(
            abs(mdl.theta_min / float(ref["analysis"]["theta_min"]) - 1),
            abs(mdl.theta_max / float(ref["analysis"]["theta_max"]) - 1),
        )
        w_traj = float(np.max(angle_between(mdl.attitude(ref_t), ref_q)))
        tt, th, q, turning = run_dop853(mdl, t, kind, extra_t=ref_t)
        d_turn = turning_error(turning, ref["analysis"])
        idx = np.searchsorted(tt, ref_t)
        d_traj = float(np.max(angle_between(q[idx], ref_q)))
        on_grid = np.isin(tt, t)
        d_dev = float(np.max(angle_between(q[on_grid], mdl.attitude(t))))
        ratio = slow["dop853"][0] / fast["angles"][0]
        rows.append((label, "wobble exact: construction + theta, phi, psi", fast["angles"], w_turn, w_traj, "-"))
        rows.append((label, "wobble exact: theta, phi, psi (model built)", fast["eval"], w_turn, w_traj, "-"))
        rows.append((label, "wobble exact: omega and quaternion (model built)", fast["state"], w_turn, w_traj, "-"))
        rows.append(
            (label, f"solve_ivp DOP853 rtol 1e-12 ({kind} equations)", slow["dop853"], d_turn, d_traj, f"{d_dev:.1e}")
        )
        summary.append(
            (
                label,
                ratio,
                slow["dop853"][1] / fast["angles"][1],
                slow["dop853"][0] / fast["eval"][0],
                w_turn,
                d_turn,
                w_traj,
                d_traj,
                type(mdl.evaluator(t.size)).__name__.strip("_").lower(),
            )
        )
        split.append((fast["angles"][0], fast["eval"][0]))
        print(
            f"{label}: DOP853 {slow['dop853'][0]:.3g} s, wobble {fast['angles'][0] * 1e3:.3g} ms "
            f"(ratio {ratio:.0f}); turning points {w_turn:.1e} vs {d_turn:.1e}; attitude {w_traj:.1e} vs {d_traj:.1e}",
            flush=True,
        )
    radau_line = None
    if not args.no_radau:
        mdl = heavy_top(I1, I3, MGL, np.pi / 3, omega3=OMEGA3)
        ref = REF["benchmark cusps"]
        t = np.linspace(0.0, 1000 * mdl.nutation_period, 20001)
        ref_t = np.array([float(x) for x in ref["long"]["t"]])
        ref_q = np.array([[float(v) for v in r] for r in ref["long"]["quaternion"]])
        t0 = time.perf_counter()
        tt, th, q, turning = run_dop853(mdl, t, "euler", rtol=1e-10, method="Radau", extra_t=ref_t)
        radau_s = time.perf_counter() - t0
        idx = np.searchsorted(tt, ref_t)
        radau_line = (radau_s, turning_error(turning, ref["analysis"]), float(np.max(angle_between(q[idx], ref_q))))
        print(f"Radau rtol 1e-10 (cusps): {radau_s:.3g} s", flush=True)

    lines = [
        "# Performance of the exact heavy top",
        "",
        "Generated by `python scripts/bench_top.py` (do not edit by hand) on "
        f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC.",
        f"Machine: {platform.machine()}, {platform.processor() or 'unknown CPU'}, Python {platform.python_version()}, "
        f"NumPy {np.__version__}, SciPy {scipy.__version__}, wobble {wobble.__version__}; "
        f"{os.cpu_count()} CPUs with a load average (1, 5, 15 min) of {', '.join(f'{x:.2f}' for x in load_start)} at "
        f"the start and {', '.join(f'{x:.2f}' for x in os.getloadavg())} at the end of the run "
        f"({(time.perf_counter() - started) / 60:.1f} min). "
        "Timings: one warm-up, then min and median of repeats, methods interleaved in one process "
        "(the cores are shared with other jobs, so medians can be noisy). DOP853 integrates the "
        "equations written as a SciPy user writes them (Python floats, benchmarks/top.py), timed "
        "without events.",
        "",
        "Heavy top: I1 = 1 kg m2, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 rad/s; 1000 nutation "
        "periods, 20,001 outputs. Errors against mpmath (tests/references/heavy_top.json): turning "
        "angles (relative) and the attitude angle (rad) at 7 times up to 1000.25 periods. The last "
        "column compares the integrator with wobble's exact attitude at all 20,001 outputs.",
        "",
        "| case | method | min (s) | median (s) | turning points (rel.) | attitude vs mpmath (rad) | vs exact, all "
        "outputs (rad) |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, meth, (tmin, tmed), eturn, etraj, dev in rows:
        lines.append(f"| {label} | {meth} | {tmin:.3g} | {tmed:.3g} | {eturn:.1e} | {etraj:.1e} | {dev} |")
    if radau_line:
        lines.append(
            f"| cusps | solve_ivp Radau rtol 1e-10 (Euler-angle equations), one run | {radau_line[0]:.3g} | - | "
            f"{radau_line[1]:.1e} | {radau_line[2]:.1e} | - |"
        )
    lines += [
        "",
        "## Accuracy against mpmath, every reference case",
        "",
        "Both evaluation paths of wobble (direct: Jacobi + Carlson per output; fourier: the verified "
        "table) against tests/references/heavy_top.json: turning angles and period (relative), the "
        "attitude angle against mpmath's Taylor integration over ~3 periods (ode) and against the "
        "mpmath closed form at times up to 1000.25 periods (long), in rad.",
        "",
        "| case | class | turning points | period | attitude, ode (direct / fourier) | attitude, 1000 periods "
        "(direct / fourier) |",
        "|---|---|---|---|---|---|",
    ]
    lines += accuracy_rows()
    lines += [
        "",
        "## Speed ratios (DOP853 time / wobble time)",
        "",
        "| case | wobble path | incl. construction (minima) | incl. construction (medians) | evaluation only (minima) "
        "| wobble turning / attitude error | DOP853 turning / attitude error |",
        "|---|---|---|---|---|---|---|",
    ]
    met = True
    met_median = True
    for label, ratio, ratio_med, ratio_eval, wt, dt, wa, da, path in summary:
        lines.append(
            f"| {label} | {path} | {ratio:.0f}x | {ratio_med:.0f}x | {ratio_eval:.0f}x | {wt:.1e} / {wa:.1e} "
            f"| {dt:.1e} / {da:.1e} |"
        )
        met = met and ratio >= 1000 and wt <= dt and wa <= da
        met_median = met_median and ratio_med >= 1000
    lines += [
        "",
        "Target: at least 1000 times faster than DOP853 at rtol 1e-12, at equal or better error. "
        + (
            "Met on every case above on the minima (construction included)"
            if met
            else "Not met on every case on the minima (see the ratios, as measured)"
        )
        + (
            "; also on the medians."
            if met_median
            else "; on the medians, which the other jobs on this shared 2-core machine inflate (mostly "
            "for the millisecond-long wobble runs), some cases fall short: see the column."
        )
        + (
            " Why: of wobble's "
            f"{1e3 * min(a for a, _ in split):.1f}-{1e3 * max(a for a, _ in split):.1f} ms, the evaluation of the "
            f"20,001 outputs takes {1e3 * min(e for _, e in split):.1f}-{1e3 * max(e for _, e in split):.1f} ms "
            "(evaluation alone is well above 1000x); the rest is the construction: the analysis in 60-digit "
            "decimal arithmetic (roots, K, the complete Pi, the secular rates) and the Fourier table of the "
            "periodic parts with its check against the direct evaluation, both fixed costs per top in "
            "Python/NumPy."
            if not met
            else ""
        ),
        "",
        "wobble's path: 'fourier' = the verified Fourier series of the periodic parts (used from 1024 "
        "outputs on, where it reproduces the direct evaluation to rounding); 'elliptic' = Jacobi "
        "functions and Carlson's Pi per output. The turning points of wobble come from the roots of the "
        "cubic at construction; DOP853's from solve_ivp events over the whole span.",
    ]
    out = ROOT / "docs" / "performance-top.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
