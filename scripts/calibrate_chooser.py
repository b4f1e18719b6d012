"""Measure the per-call costs behind the scene chooser's cost model (wobble.models.scene).

Usage::

    python scripts/calibrate_chooser.py              # per-call costs, then the satellite scene both ways
    python scripts/calibrate_chooser.py --repeats 7

The chooser predicts each integrator's time as the calls its pilot run counted (DOP853:
evaluations of Euler's equations, one per member; the splitting: composition stages, each a
drift and a kick of all members) times a cost per call of the path that will make them:

* DOP853 compiled (wobble.numerics.rigid_dop853: every built-in torque, Numba installed);
* DOP853 in Python floats (one member, every torque with a scalar form) or NumPy (an ensemble),
  what a torque without a compiled form (an ephemeris table, a position function) runs on,
  and every torque when Numba is not installed;
* the splitting: the exact free flow and the kick in Python floats (one member) or NumPy (an
  ensemble); it has no compiled form.

Part 1 times each path on the shipped torqued scenes (their bodies, torques and initial states;
1 and 1000 members, the members' omega0 perturbed by 1e-3) over a sixteenth of their span, as the
chooser's pilots do, and prints the cost per call (min over repeats: the machine's noise only adds).
Part 2 runs the ``satellite_gravity_gradient`` scene with each integrator at the settings the
chooser picks for it and prints the predicted and the measured times. The constants in
wobble/models/scene.py and the table in docs/engine.md come from this script's output. Timings
depend on the machine and its load; nothing here is used by the tests.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from wobble.api.scene import _as_scene
from wobble.models import engine as E
from wobble.models import scene as S

SCENES = ("satellite_gravity_gradient", "gyroscope", "earth_precession")


def _best(func, repeats):
    best, out = np.inf, None
    for _ in range(repeats):
        t = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t)
    return best, out


def _members(scene, n):
    rng = np.random.default_rng(1)
    w0 = np.repeat(scene.omega0[:1], n, axis=0)
    if n > 1:
        w0 = w0 * (1.0 + 1e-3 * rng.normal(size=w0.shape))
    return w0, np.repeat(scene.attitude0[:1], n, axis=0)


def per_call(repeats):
    print("| scene | members | path | calls | time (s) | µs per call | µs per member and call |")
    print("|---|---|---|---|---|---|---|")
    for name in SCENES:
        scene = _as_scene(name)
        span = float(scene.times[-1] - scene.times[0]) / 16
        t = scene.times[0] + np.linspace(0.0, span, 9)
        for n in (1, 1000):
            w0, q0 = _members(scene, n)
            engine = E.Engine(scene.body, scene.torques, members=n)
            step = span / 100

            def rk(backend):
                prop = engine.propagator(w0, q0, t[0], method="dop853", rtol=1e-10, backend=backend)
                prop.advance(t)
                return prop.stats()["function_evaluations"] / n  # evaluations per member

            def split():
                prop = engine.propagator(w0, q0, t[0], method="splitting", step=step, order=6)
                prop.advance(t)
                return prop.stats()["drifts"]

            rk("compiled")  # warm-up: Numba's kernels load once
            runs = [("dop853 compiled", lambda: rk("compiled"), repeats)]
            runs.append(("dop853 Python floats" if engine.scalar else "dop853 NumPy", lambda: rk("python"), 2))
            runs.append((S._split_path(engine), split, 2))
            for label, func, r in runs:
                dt, calls = _best(func, r)
                print(
                    f"| {name} | {n} | {label} | {calls:.0f} | {dt:.4g} | {1e6 * dt / calls:.3g} "
                    f"| {1e6 * dt / calls / n:.3g} |"
                )


def satellite(repeats):
    scene = _as_scene("satellite_gravity_gradient")
    plans = S._plans(scene, "dop853")
    plans.update(S._plans(scene, "splitting"))
    print()
    print(
        "| model | setting | steps | calls (main run) | calls predicted (with companion) | predicted (s) "
        "| measured (s) | error estimate |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for method in ("dop853", "splitting"):
        plan = plans[method]
        build = S._build_dop853 if method == "dop853" else S._build_splitting

        def run():
            r = build(scene, plan.settings)
            for _ in r.blocks(scene.times, scene.times.size):
                pass
            return r

        dt, r = _best(run, repeats if method == "dop853" else 1)
        st, est = r.stats(), r.error_estimate()
        if method == "dop853":
            setting, calls = f"rtol {plan.settings['rtol']:.3g}", f"{st['function_evaluations']} evaluations"
        else:
            setting, calls = f"h {plan.settings['step_s']:.3g} s", f"{st['drifts']} stages"
        err = max(est["omega_relative"], est["attitude_rad"])
        print(
            f"| {r.name} | {setting} | {st['steps']} | {calls} | {plan.calls:.0f} | {plan.seconds:.3g} | {dt:.3g} "
            f"| {err:.2g} |"
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{os.cpu_count()} CPUs, 1-minute load {load:.2f}\n")
    per_call(args.repeats)
    satellite(args.repeats)


if __name__ == "__main__":
    main()
