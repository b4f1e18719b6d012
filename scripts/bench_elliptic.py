"""Cost and agreement of the elliptic kernels' array paths; the callers' paths before and after.

Usage::

    python scripts/bench_elliptic.py                      # kernels: this tree
    python scripts/bench_elliptic.py --baseline DIR       # also the callers, this tree vs DIR
    python scripts/bench_elliptic.py --write              # also update docs/accuracy.md

``DIR`` is another source tree of wobble, e.g. the commit before a change::

    git archive 29f017c | tar -x -C /tmp/wobble-base

Part 1 (this tree only) times, interleaved (one warm-up, then the minimum and median of
the repeats), the vectorised calls against the float64 formulation they replace, rebuilt
from public pieces of :mod:`wobble.numerics.elliptic`:

* ``jacobi(u, m, m1)`` with one parameter per element (u uniform in [-200, 200]) against
  the former array path (reduction modulo 2K with a float64 K, ``reduce_half_period`` +
  ``jacobi_reduced``), and the largest difference of each from per-row calls (relative, in
  eps, and absolute): the accuracy bought by the double-double K;
* ``ellipk_dd`` (the double-double AGM) alone, per element;
* ``ellippi(n, m, m1)`` (Bulirsch's cel in double-double) against the former Carlson form
  ``ellippi_inc(n, pi/2, m, m1)``.

Part 2 (``--baseline``) runs the same model-level calls in a subprocess for each tree -- the
paths the benchmarks time (the free body's omega and attitude, the Earth's daily grid,
the free flow map of an ensemble, the heavy top, the top's phase diagram) -- and prints
both. Timings on a shared machine are noisy: compare ratios within one run.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "accuracy.md"
START, END = "<!-- bench-elliptic:start -->", "<!-- bench-elliptic:end -->"
EPS = 2.0**-52


def timeit(fn, repeats):
    fn()  # warm-up
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times)


def interleaved(fns, repeats):
    """min and median of each callable, timed in turn (round robin) after one warm-up each."""
    for f in fns.values():
        f()
    times = {k: [] for k in fns}
    for _ in range(repeats):
        for k, f in fns.items():
            t0 = time.perf_counter()
            f()
            times[k].append(time.perf_counter() - t0)
    return {k: (min(v), statistics.median(v)) for k, v in times.items()}


# ---------------------------------------------------------------------------
# Part 1: kernels
# ---------------------------------------------------------------------------
def kernels(repeats: int, sizes):
    sys.path.insert(0, str(ROOT))
    from wobble.numerics import elliptic as ell

    def old_jacobi(u, m, m1):
        """The former array path: u reduced modulo 2K with a float64 K (A&S 16.8 fold)."""
        lv = ell.landen_levels(m, m1)
        r, j = ell.reduce_half_period(u, lv.K)
        sn, cn, dn = ell.jacobi_reduced(r, lv)
        odd = np.floor(0.5 * j) != 0.5 * j
        return np.where(odd, -sn, sn), np.where(odd, -cn, cn), dn

    rng = np.random.default_rng(21)
    out = {"jacobi": [], "ellipk_dd": [], "ellippi": []}
    for n in sizes:
        m1 = np.concatenate([10.0 ** rng.uniform(-16, 0, n - n // 2), rng.uniform(0, 1, n // 2)])
        m = 1.0 - m1
        u = rng.uniform(-200, 200, n)
        t = interleaved({"new": lambda: ell.jacobi(u, m, m1), "old": lambda: old_jacobi(u, m, m1)}, repeats)
        out["jacobi"].append({"n": n, "new": t["new"], "old": t["old"]})
        out["ellipk_dd"].append({"n": n, "time": timeit(lambda: ell.ellipk_dd(m, m1), repeats)})
        nn = -rng.uniform(0, 3, n)
        t = interleaved(
            {"new": lambda: ell.ellippi(nn, m, m1), "old": lambda: ell.ellippi_inc(nn, 0.5 * np.pi, m, m1)}, repeats
        )
        out["ellippi"].append({"n": n, "new": t["new"], "old": t["old"]})
    # Agreement with per-row calls (a smaller set: per-row calls cost ~0.2 ms each).
    n = 2000
    m1 = np.concatenate([10.0 ** rng.uniform(-16, 0, n // 2), rng.uniform(0, 1, n // 2)])
    m = 1.0 - m1
    u = rng.uniform(-200, 200, n)
    rows = np.array([ell.jacobi(a, b, c) for a, b, c in zip(u, m, m1)], dtype=float)
    agree = {}
    for name, got in (("new", np.array(ell.jacobi(u, m, m1)).T), ("old", np.array(old_jacobi(u, m, m1)).T)):
        diff = np.abs(got - rows)
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.where(rows != 0, diff / np.abs(rows), diff) / EPS
        agree[name] = {"rel_eps": float(rel.max()), "abs": float(diff.max())}
    t_row = timeit(lambda: ell.jacobi(1.3, 0.4, 0.6), repeats)
    t_agm = timeit(lambda: ell.ellipk_dd(0.4, 0.6), repeats)
    t_pi = timeit(lambda: ell.ellippi(-0.3, 0.4, 0.6), repeats)
    return {
        "sizes": out,
        "agree": agree,
        "agree_rows": n,
        "scalar": {"jacobi": t_row, "ellipk_dd": t_agm, "ellippi": t_pi},
    }


# ---------------------------------------------------------------------------
# Part 2: the callers, in a subprocess per tree
# ---------------------------------------------------------------------------
CALLERS = r"""
import json, sys, time, statistics
import numpy as np
repeats = int(sys.argv[1])
from wobble.models.free import free_rotation, flow_sorted
from wobble.models.top import heavy_top
from wobble.models import top_phase

def best(fn):
    fn()
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter(); fn(); ts.append(time.perf_counter() - t0)
    return [min(ts), statistics.median(ts)]

res = {}
t = np.linspace(0.0, 1000.0, 10001)
res["free generic: build + omega + attitude, 1e4 outputs"] = best(
    lambda: (lambda f: (f.omega(t), f.attitude(t)))(free_rotation([1.0, 2.0, 3.0], [1.0, 0.1, 1.0])))
ts = np.linspace(0.0, 200.0, 10001)
res["free separatrix: build + omega + attitude, 1e4 outputs"] = best(
    lambda: (lambda f: (f.omega(ts), f.attitude(ts)))(free_rotation([1.0, 2.0, 3.0], [1e-6, 1.0, 1e-6])))
day = 86400.0
te = np.arange(36526) * day
earth = free_rotation([8.0101e37, 8.0103e37, 8.0365e37], [1e-9, 2e-9, 7.292115e-5])
res["Earth grid: omega, 36,526 daily outputs"] = best(lambda: earth.omega(te))
rng = np.random.default_rng(3)
N = 4096
I = np.sort(rng.uniform(1.0, 3.0, (N, 3)), axis=1)
w = rng.normal(size=(N, 3))
res["free flow map: 4096 members, one step"] = best(lambda: flow_sorted(I, w, 0.01))
tt = np.linspace(0.0, 100.0, 20001)
res["heavy top (undulating): build + angles, 20,001 outputs"] = best(
    lambda: heavy_top(1.0, 0.5, 1.0, np.pi / 3, 0.0, 0.3, omega3=10.0).angles(tt))
M = 20000
th = rng.uniform(0.2, 2.5, M); pd = rng.uniform(-1, 1, M); w3 = rng.uniform(5, 20, M)
res["top phase diagram: 20,000 members"] = best(
    lambda: top_phase.phase_analysis(np.ones(M), 0.5 * np.ones(M), np.ones(M), th, w3, pd, np.zeros(M)))
print(json.dumps(res))
"""


def callers(tree: Path, repeats: int):
    env = {**os.environ, "PYTHONPATH": str(tree)}
    proc = subprocess.run(
        [sys.executable, "-c", CALLERS, str(repeats)],
        capture_output=True,
        text=True,
        env=env,
        cwd=str(tree),
        check=True,
    )
    return json.loads(proc.stdout.strip().splitlines()[-1])


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------
def us(x):
    return f"{1e6 * x:.0f} us" if x < 1e-2 else f"{1e3 * x:.1f} ms"


def report(k, both, repeats) -> str:
    lines = [
        f"Measured by `python scripts/bench_elliptic.py` on {platform.machine()}, {os.cpu_count()} CPUs shared with "
        f"other jobs (noisy: compare within a row), Python {platform.python_version()}, NumPy {np.__version__}; "
        f"{repeats} repeats, min (median).",
        "",
        "| call | elements | now | former float64 path | now / former (min) |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, label in (("jacobi", "jacobi(u, m, m1), one m per element"), ("ellippi", "ellippi(n, m, m1)")):
        for r in k["sizes"][name]:
            n = r["n"]
            lines.append(
                f"| {label} | {n:,} | {us(r['new'][0])} ({us(r['new'][1])}); {1e9 * r['new'][0] / n:.0f} ns each | "
                f"{us(r['old'][0])} ({us(r['old'][1])}); {1e9 * r['old'][0] / n:.0f} ns each | "
                f"{r['new'][0] / r['old'][0]:.2f} |"
            )
    for r in k["sizes"]["ellipk_dd"]:
        lines.append(
            f"| ellipk_dd (double-double AGM) | {r['n']:,} | {us(r['time'][0])} ({us(r['time'][1])}); "
            f"{1e9 * r['time'][0] / r['n']:.0f} ns each | - | - |"
        )
    s = k["scalar"]
    lines.append(f"| jacobi, scalar m | 1 | {us(s['jacobi'][0])} | - | - |")
    lines.append(f"| ellipk_dd, scalar m | 1 | {us(s['ellipk_dd'][0])} | - | - |")
    lines.append(f"| ellippi, scalar | 1 | {us(s['ellippi'][0])} | - | - |")
    a = k["agree"]
    lines += [
        "",
        f"Vectorised `jacobi` against per-row calls ({k['agree_rows']:,} elements, half with m1 from 1e-16 to 1, "
        f"|u| <= 200): now {a['new']['rel_eps']:.2f} eps relative ({a['new']['abs']:.1e} absolute); the former "
        f"float64-K array path {a['old']['rel_eps']:.3g} eps relative ({a['old']['abs']:.1e} absolute).",
    ]
    if both:
        names = list(both["now"])
        lines += [
            "",
            "The callers (model-level calls of the benchmarked paths), this tree against the baseline tree:",
            "",
            "| call | now | baseline | now / baseline (min) |",
            "|---|---:|---:|---:|",
        ]
        for nme in names:
            a_, b_ = both["now"][nme], both["base"][nme]
            lines.append(f"| {nme} | {us(a_[0])} ({us(a_[1])}) | {us(b_[0])} ({us(b_[1])}) | {a_[0] / b_[0]:.2f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--baseline", type=Path, help="another wobble source tree for the callers' comparison")
    ap.add_argument("--write", action="store_true", help="update docs/accuracy.md between its markers")
    args = ap.parse_args(argv)
    k = kernels(args.repeats, (100, 10_000, 100_000))
    both = None
    if args.baseline is not None:
        both = {"now": callers(ROOT, args.repeats), "base": callers(args.baseline.resolve(), args.repeats)}
    text = report(k, both, args.repeats)
    print(text)
    if args.write:
        doc = DOC.read_text()
        head, rest = doc.split(START, 1)
        _, tail = rest.split(END, 1)
        DOC.write_text(f"{head}{START}\n{text}\n{END}{tail}")
        print(f"wrote {DOC.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
