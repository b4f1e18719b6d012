"""Timing and memory the way DifferentialEquations.jl's work-precision diagrams time.

Every (method, setting) of a case is a :class:`Run`. :func:`measure` runs each once
(the warm-up; its output is the one whose error is measured), then times the runs
again in rounds, every run once per round, so that all methods see the same machine
load (interleaved). A run whose warm-up took longer than ``slow_s`` is not repeated:
its warm-up time is its only timing (its method's cheaper settings ran before it, so
caches and imports are warm), which keeps the long SciPy runs affordable.

Numba's just-in-time work (importing Numba, loading a kernel from its disk cache, compiling
it: ~20 s for the DOP853 kernels on a new install) is never timed. :mod:`wobble.numerics.compiled` watches it
through Numba's event API; a warm-up during which any happened is not a timing, so the run
is run once more (timed, as a timed run is) before its time decides how often it is
repeated, and a timed run during which any happened is discarded and run again.
"""

from __future__ import annotations

import ctypes
import gc
import os
import statistics
import time
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wobble.numerics import compiled

#: The environment for timing a command as a fresh process the way a user runs it: a user's Python
#: caches the bytecode of what it imports (__pycache__); a session that sets PYTHONDONTWRITEBYTECODE
#: would compile wobble's modules from source on every run and time that instead.
USER_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


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


#: The clock of every timing (a module attribute, so that a test can replace it).
clock = time.perf_counter


def _jit_kind(before: tuple, after: tuple) -> str | None:
    """What Numba did between two :func:`wobble.numerics.compiled.activity` readings: None, "loaded" or
    "compiled"."""
    if after == before:
        return None
    return "compiled" if after[2] != before[2] else "loaded"


def _timed(r: Run, attempts: int = 3) -> float:
    """One timed run of ``r.fn()`` during which Numba did no just-in-time work (a run during
    which it did is discarded and run again)."""
    for _ in range(attempts):
        gc.collect()
        before = compiled.activity()
        t0 = clock()
        r.fn()
        dt = clock() - t0
        if compiled.activity() == before:
            return dt
    raise RuntimeError(
        f"{r.method} [{r.setting}]: Numba loaded or compiled a kernel in each of {attempts} runs after its warm-up; "
        "its time would be the compilation's"
    )


def measure(runs: list[Run], repeats: int, slow_s: float = 2.0, progress=None) -> list[dict]:
    """Warm up and check every run, then time them interleaved; return one row per run.

    No timing includes Numba's just-in-time work (see the module docstring): a warm-up that
    loaded or compiled kernels is followed by one more run, timed, whose time stands for the
    run's (its only timing when over ``slow_s``); ``progress`` is told when Numba starts
    compiling during a warm-up (the first run after installing)."""
    if compiled.available():  # Numba's import (~0.4 s) before the warm-ups, and its listeners hearing every compilation
        compiled.listen()
    times: list[list[float]] = []
    for r in runs:
        gc.collect()

        def compiling(r=r):
            progress(
                f"  compiling the Numba kernels of {r.method} (first run after installing only: "
                "they are then cached on disk) ..."
            )

        with compiled.compilation_notice(compiling if progress else lambda: None):
            before = compiled.activity()
            t0 = clock()
            out = r.fn()
            dt = clock() - t0
            jit = _jit_kind(before, compiled.activity())
        r.result = {"method": r.method, "setting": r.setting, **r.check(out)}
        if r.work is not None:
            r.result["work"] = r.work(out)
        del out
        note = ""
        if jit is not None:
            # The warm-up's time includes the import, loading or compilation: run it once more.
            warm_up, dt = dt, _timed(r)
            note = f"; the warm-up took {warm_up:.3g} s, Numba having {jit} its kernels"
        r.result["warm_up_jit"] = jit
        times.append([dt])
        if progress:
            progress(f"  {r.method} [{r.setting}]: error {r.result['error']:.2e}, {dt:.3g} s (warm-up{note})")
    # What the case and the warm-ups made (references, lazily imported modules such as xarray and
    # pandas) is left out of the collections before each timed run (gc.freeze), as harness.run_benchmark
    # does with what was there before: a full collection walks ~10^6 objects, which evicts the CPU
    # caches and slowed the millisecond runs after it by 0.4-0.7 ms (HeavyTop(...).motion(t): 2.8 ms
    # against 2.2 ms for the same call without it), a cost no user's call pays. run_benchmark
    # unfreezes at its end; a direct caller of measure() may call gc.unfreeze() after it.
    gc.collect()
    gc.freeze()
    # Fast runs (< 50 ms) get three times the repeats: their minimum is what noise hides.
    want = [0 if t[0] > slow_s else (3 * repeats if t[0] < 0.05 else repeats) for t in times]
    for k in range(max(want, default=0)):
        for r, t, n in zip(runs, times, want):
            if k < n:
                if k == 0:
                    t.clear()
                t.append(_timed(r))
    rows = []
    for r, t, n in zip(runs, times, want):
        rows.append(
            {**r.result, "t_min": min(t), "t_median": statistics.median(t), "timed_runs": len(t), "timed_once": n == 0}
        )
    return rows


def peak_memory(fn: Callable[[], Any]) -> int | None:
    """Peak resident memory (bytes) that ``fn()`` adds to the process, measured in a forked child.

    The child returns the allocator's free memory to the system (``malloc_trim``), fixes
    glibc's mmap threshold at 128 kB (so large arrays come from fresh pages, not from memory
    freed by earlier runs), resets the kernel's high-water mark (``/proc/self/clear_refs``),
    runs ``fn`` and reports ``VmHWM - VmRSS`` before the run. Everything the run makes
    resident counts (NumPy, Python objects, C libraries such as MuJoCo) and the run is not
    slowed down (tracemalloc slowed pure-Python loops up to 27-fold). Where that is not
    available (no fork, no /proc: not Linux), the tracemalloc peak of Python and NumPy
    allocations (:func:`traced_peak`).
    """
    if not measures_resident_memory():
        return traced_peak(fn)
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: measure, report, leave without running any cleanup
        code = 1
        try:
            os.close(read_end)
            libc = ctypes.CDLL(None)
            libc.mallopt(_M_MMAP_THRESHOLD, 128 * 1024)
            libc.malloc_trim(0)
            gc.collect()
            _CLEAR_REFS.write_text("5")  # VmHWM := VmRSS
            before = _status_bytes("VmRSS")
            fn()
            os.write(write_end, str(max(_status_bytes("VmHWM") - before, 0)).encode())
            code = 0
        finally:
            os._exit(code)
    os.close(write_end)
    data = b""
    while chunk := os.read(read_end, 64):
        data += chunk
    os.close(read_end)
    _, status = os.waitpid(pid, 0)
    return int(data) if data and status == 0 else None


_CLEAR_REFS = Path("/proc/self/clear_refs")


def measures_resident_memory() -> bool:
    """Whether :func:`peak_memory` measures resident memory (Linux) rather than tracemalloc's peak."""
    return hasattr(os, "fork") and _CLEAR_REFS.exists()


_M_MMAP_THRESHOLD = -3  # glibc's mallopt parameter


def _status_bytes(key: str) -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(key + ":"):
            return int(line.split()[1]) * 1024
    raise KeyError(key)


def traced_peak(fn: Callable[[], Any]) -> int:
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
