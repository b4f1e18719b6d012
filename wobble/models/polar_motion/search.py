"""The frequency search both estimators share: an oversampled grid and a bounded Brent refinement."""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

__all__ = ["OVERSAMPLE", "band_grid", "refine_peak"]

#: Grid points per Rayleigh resolution 2 pi / T.
OVERSAMPLE = 8


def band_grid(lo_rate, hi_rate, span):
    """Rates from lo to hi (inclusive) with about 8 points per Rayleigh resolution 2 pi / T."""
    count = int(math.ceil((hi_rate - lo_rate) * OVERSAMPLE * span / (2 * math.pi))) + 1
    d = (hi_rate - lo_rate) / (count - 1)
    return lo_rate + d * np.arange(count), d


def refine_peak(fun, rates, values, step, lo, hi) -> float:
    """Maximise ``fun`` near the largest grid value (bounded Brent)."""
    k = int(np.argmax(values))
    a = max(lo, rates[k] - step)
    b = min(hi, rates[k] + step)
    res = optimize.minimize_scalar(lambda r: -fun(r), bounds=(a, b), method="bounded", options={"xatol": step * 1e-4})
    return float(res.x) if -res.fun >= values[k] else float(rates[k])
