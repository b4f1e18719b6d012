"""Timing and memory the way DifferentialEquations.jl's work-precision diagrams time.

Every (method, setting) of a case is a :class:`Run`. :func:`measure` runs each once
(the warm-up; its output is the one whose error is measured), then times the runs
again in rounds, every run once per round, so that all methods see the same machine
load (interleaved). A run whose warm-up took longer than ``slow_s`` is not repeated:
its warm-up time is its only timing (its method's cheaper settings ran before it, so
caches and imports are warm), which keeps the long SciPy runs affordable.
"""

from __future__ import annotations

import gc
import statistics
import time
import tracemalloc
from dataclasses import dataclass, field
from typing import Any, Callable


@dataclass
class Run:
    """One method at one setting on one case.

    ``fn()`` does the whole job a user would time (construction included) and returns
    its output; ``check(output)`` returns a dict of errors, with the headline error
    under ``"error"``.
    """

    method: str
    setting: str
    fn: Callable[[], Any]
    check: Callable[[Any], dict]
    work: Callable[[Any], Any] | None = None
    result: dict = field(default_factory=dict)


def measure(runs: list[Run], repeats: int, slow_s: float = 2.0, progress=None) -> list[dict]:
    """Warm up and check every run, then time them interleaved; return one row per run."""
    times: list[list[float]] = []
    for r in runs:
        gc.collect()
        t0 = time.perf_counter()
        out = r.fn()
        dt = time.perf_counter() - t0
        r.result = {"method": r.method, "setting": r.setting, **r.check(out)}
        if r.work is not None:
            r.result["work"] = r.work(out)
        del out
        times.append([dt])
        if progress:
            progress(f"  {r.method} [{r.setting}]: error {r.result['error']:.2e}, {dt:.3g} s (warm-up)")
    # Fast runs (< 50 ms) get three times the repeats: their minimum is what noise hides.
    want = [0 if t[0] > slow_s else (3 * repeats if t[0] < 0.05 else repeats) for t in times]
    for k in range(max(want, default=0)):
        for r, t, n in zip(runs, times, want):
            if k < n:
                if k == 0:
                    t.clear()
                gc.collect()
                t0 = time.perf_counter()
                r.fn()
                t.append(time.perf_counter() - t0)
    rows = []
    for r, t, n in zip(runs, times, want):
        rows.append({**r.result, "t_min": min(t), "t_median": statistics.median(t), "timed_runs": len(t),
                     "timed_once": n == 0})
    return rows


def peak_memory(fn: Callable[[], Any]) -> int:
    """Peak memory (bytes) Python and NumPy allocate during ``fn()``, by tracemalloc.

    NumPy reports its array buffers to tracemalloc, so the peak includes the outputs and
    the temporaries; memory allocated by C libraries outside Python's and NumPy's
    allocators (e.g. MuJoCo's model and data) is not counted.
    """
    gc.collect()
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        out = fn()
        _, peak = tracemalloc.get_traced_memory()
        del out
    finally:
        tracemalloc.stop()
    return int(peak)


def time_at(points: list[tuple[float, float]], target: float) -> float | None:
    """A method's time at the target error: log-log interpolation between its (error, time) points.

    Where the target lies outside the method's range: its cheapest point at or below the target
    error if there is one (it reaches the target, at that cost), else None (it never does).
    """
    import math

    pts = sorted((e, t) for e, t in points if e > 0 and math.isfinite(e))
    for (e1, t1), (e2, t2) in zip(pts, pts[1:]):
        if e1 <= target <= e2:
            w = (math.log(target) - math.log(e1)) / (math.log(e2) - math.log(e1))
            return math.exp(math.log(t1) + w * (math.log(t2) - math.log(t1)))
    below = [t for e, t in pts if e <= target]
    return min(below) if below else None
