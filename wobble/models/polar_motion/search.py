"""The frequency search both estimators share: an oversampled grid and a bounded Brent refinement.

:func:`refine_peaks` is :func:`refine_peak` for many series at once (the Monte
Carlo's realisations): the same bounded Brent steps for each
(:func:`wobble.numerics.bounded_brent.minimize_bounded`), the function evaluated
once per step for all of them.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from wobble.numerics.bounded_brent import minimize_bounded

__all__ = ["OVERSAMPLE", "at_band_edge", "band_grid", "refine_peak", "refine_peaks"]

#: Grid points per Rayleigh resolution 2 pi / T.
OVERSAMPLE = 8


def band_grid(lo_rate, hi_rate, span):
    """Rates from lo to hi (inclusive) with about 8 points per Rayleigh resolution 2 pi / T."""
    count = int(math.ceil((hi_rate - lo_rate) * OVERSAMPLE * span / (2 * math.pi))) + 1
    d = (hi_rate - lo_rate) / (count - 1)
    return lo_rate + d * np.arange(count), d


def at_band_edge(rate: float, lo_rate: float, hi_rate: float, step: float) -> bool:
    """Whether a best rate lies within half a grid step of the search band's edge (or is NaN): then no peak
    inside the band was resolved, only the band's own limit."""
    return not (lo_rate + 0.5 * step < rate < hi_rate - 0.5 * step)


def refine_peak(fun, rates, values, step, lo, hi) -> float:
    """Maximise ``fun`` near the largest grid value (bounded Brent)."""
    k = int(np.argmax(values))
    a = max(lo, rates[k] - step)
    b = min(hi, rates[k] + step)
    res = optimize.minimize_scalar(lambda r: -fun(r), bounds=(a, b), method="bounded", options={"xatol": step * 1e-4})
    return float(res.x) if -res.fun >= values[k] else float(rates[k])


def refine_peaks(fun, rates, values, step, lo, hi) -> np.ndarray:
    """:func:`refine_peak` for every column of ``values`` (shape (rates, m)) at once.

    ``fun(r, index)`` returns the values of the columns ``index`` (an integer
    array) at the rates ``r`` (one each). Column k gets what
    ``refine_peak(lambda r: fun([r], [k])[0], rates, values[:, k], ...)`` would.
    """
    k = np.argmax(values, axis=0)
    columns = np.arange(values.shape[1])
    peak, best = rates[k], values[k, columns]
    x, f = minimize_bounded(
        lambda r, index: -fun(r, index), np.maximum(lo, peak - step), np.minimum(hi, peak + step), step * 1e-4
    )
    return np.where(-f >= best, x, peak)
