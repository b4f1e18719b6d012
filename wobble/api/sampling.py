"""Sample times for the exact solutions' Datasets, refused up front when they would not fit in memory.

Shared by :class:`wobble.FreeRotation` and :class:`wobble.HeavyTop`, and by their figures
(:mod:`wobble.plot.free`, :mod:`wobble.plot.top`, which sample the same motions): either explicit
times ``t`` or ``t_end`` with ``samples`` (a linspace from 0), and a memory check that names the
largest request this machine can take.
"""

from __future__ import annotations


import astropy.units as u
import numpy as np

from wobble.numerics.floats import TINY
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.io.memory import available_memory, human_bytes

__all__ = ["available_memory", "human_bytes", "sample_times", "check_memory", "check_samples", "check_step"]


def check_memory(n: int, bytes_per_sample: int) -> None:
    """Refuse ``n`` samples when they need more than half the free memory, naming the limit."""
    need = n * bytes_per_sample
    have = available_memory() // 2
    if need > have:
        raise InputError(
            "samples",
            n,
            f"at most {have // bytes_per_sample} samples here: {n} samples need about {human_bytes(need)} "
            f"of memory and {human_bytes(have)} is usable (ask for fewer samples or a shorter span)",
        )


def sample_times(t, t_end, samples, bytes_per_sample: int) -> np.ndarray:
    """Times in s: ``t`` (a 1-D time Quantity) or ``samples`` points from 0 to ``t_end``."""
    if (t is None) == (t_end is None):
        raise InputError("t, t_end", (t, t_end), "either times t or t_end with samples, not both or neither")
    if t is not None:
        ts = np.atleast_1d(to_si(t, "t", u.s))
        if ts.ndim != 1:
            raise InputError("t", t, "a 1-D array of times")
        check_memory(ts.size, bytes_per_sample)
        return ts.astype(float)
    end = to_si(t_end, "t_end", u.s, nonnegative=True, shape=())
    check_samples(samples, bytes_per_sample, least=1)
    if end == 0 and samples > 1:
        # samples equal times would make a time coordinate that is not monotonic (invalid CF).
        raise InputError("t_end", t_end, "a positive end time (or a single sample, the state at t = 0)")
    check_step(end, int(samples), t_end)
    return np.linspace(0.0, end, int(samples))


def check_step(end: float, samples: int, shown, whose: str = "") -> None:
    """Refuse an end time ``end`` (s) whose ``samples`` evenly spaced times from 0 are a step below the normal
    doubles apart (``shown``: the end as the caller's error names it, under ``t_end``; ``whose``: whose samples,
    e.g. " of the figure", which samples its own way).

    Such times are not evenly spaced, and below 2^-1074 s not even distinct: t_end = 5e-324 s gave a file of
    1001 times with 2 values (a time coordinate CF does not allow), and figures of it nothing to draw.
    """
    least = (samples - 1) * TINY
    if samples > 1 and end < least:
        raise InputError(
            "t_end",
            shown,
            f"an end time of at least {least:.4g} s for the {samples} samples{whose}: the step t_end/(samples - 1) "
            f"must be a normal double (at least {TINY:.4g} s), or the sample times are neither evenly "
            "spaced nor distinct",
        )


def check_samples(samples, bytes_per_sample: int, *, least: int = 2) -> int:
    """``samples`` as an int: a whole number of at least ``least`` that fits in memory at
    ``bytes_per_sample`` each (a bool, 2.5 or 1e12 refused naming ``samples``)."""
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < least:
        raise InputError("samples", samples, f"a whole number of samples >= {least}")
    check_memory(int(samples), bytes_per_sample)
    return int(samples)
