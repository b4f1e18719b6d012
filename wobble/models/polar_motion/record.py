"""The polar-motion record as the estimators see it: the complex pole, its constants and checks.

Units: time in seconds (any origin; the caller's), angles in radians,
angular frequencies in rad/s.

**Sign convention.** The pole is the complex number

    p = x_p - i y_p,                                                        (1)

with x_p toward the Greenwich meridian and y_p toward 90 deg W (IERS). With
this sign a term ``a exp(+i sigma t)``, sigma > 0, turns counter-clockwise seen
from above the north pole: *prograde*, in the sense of the Earth's rotation
(Munk & MacDonald 1960, sec. 6; Gross 2007, Treatise on Geophysics 3, eq. 11).
"""

from __future__ import annotations

import math

import numpy as np

from wobble.errors import InputError
from wobble.numerics.calendar import DAY, JULIAN_YEAR, TROPICAL_YEAR

__all__ = [
    "DAY",
    "JULIAN_YEAR",
    "TROPICAL_YEAR",
    "ANNUAL_RATE",
    "beat_period",
    "check_reference_period",
    "CHANDLER_BAND",
    "MIN_SPAN",
    "MAX_DRIFT_DEGREE",
    "complex_pole",
    "pole_xy",
    "as_series",
    "check_band",
    "check_degree",
    "check_q",
    "span_caveats",
    "bin_means",
    "same_times",
]

ANNUAL_RATE = 2.0 * math.pi / TROPICAL_YEAR
#: Default search band for the Chandler period, s (390 to 500 days).
CHANDLER_BAND = (390.0 * DAY, 500.0 * DAY)
#: Shortest span analysed: two years (fewer than two Chandler cycles is not a period).
MIN_SPAN = 2.0 * JULIAN_YEAR


def complex_pole(x, y) -> np.ndarray:
    """The pole as p = x_p - i y_p (equation 1): prograde terms rotate as exp(+i sigma t)."""
    return np.asarray(x, dtype=float) - 1j * np.asarray(y, dtype=float)


def pole_xy(p) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`complex_pole`: (x_p, y_p) = (Re p, -Im p)."""
    p = np.asarray(p)
    return p.real.copy(), -p.imag


def as_series(t, z, name: str = "series") -> tuple[np.ndarray, np.ndarray]:
    """(t, z) as float and complex arrays, checked: 1-D, finite, increasing, at least :data:`MIN_SPAN` long."""
    t = np.asarray(t, dtype=float)
    z = np.asarray(z, dtype=complex)
    if t.ndim != 1 or t.shape != z.shape:
        raise InputError(name, f"times {t.shape}, values {z.shape}", "1-D times and values of the same length")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(z))):
        raise InputError(name, "NaN or inf", "finite times and pole coordinates (drop missing samples first)")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        raise InputError(name, "times not increasing", "strictly increasing sample times")
    if t.size < 2 or t[-1] - t[0] < MIN_SPAN:
        span = 0.0 if t.size < 2 else (t[-1] - t[0]) / DAY
        raise InputError(
            name,
            f"a span of {span:g} d",
            f"a span of at least {MIN_SPAN / DAY:g} d (two Julian years) to measure a period",
        )
    return t, z


def check_band(band) -> tuple[float, float]:
    """A search band (two periods, s) above the annual period."""
    lo, hi = (float(b) for b in band)
    if not (math.isfinite(lo) and math.isfinite(hi) and TROPICAL_YEAR * 1.02 < lo < hi):
        raise InputError(
            "band", f"{lo / DAY:g} to {hi / DAY:g} d", "two periods, increasing, above 1.02 tropical years (372.5 d)"
        )
    return lo, hi


#: The highest degree of the mean-pole polynomial.
MAX_DRIFT_DEGREE = 6


def check_degree(drift_degree) -> int:
    """The degree of the mean-pole polynomial, an integer from 0 to :data:`MAX_DRIFT_DEGREE`."""
    if (
        isinstance(drift_degree, bool)
        or not isinstance(drift_degree, (int, np.integer))
        or not 0 <= drift_degree <= MAX_DRIFT_DEGREE
    ):
        raise InputError("drift_degree", drift_degree, f"an integer from 0 (a fixed mean pole) to {MAX_DRIFT_DEGREE}")
    return int(drift_degree)


def check_q(q) -> float:
    """A quality factor above 1 (the Monte-Carlo excitation term's Q)."""
    try:
        value = float(q)
    except (TypeError, ValueError):
        raise InputError("excitation_q", q, "a quality factor above 1, or None") from None
    if not (math.isfinite(value) and value > 1.0):
        raise InputError("excitation_q", q, "a finite quality factor above 1, or None")
    return value


def check_reference_period(reference_period) -> float:
    """A published Chandler period, s: finite and longer than 1.02 tropical years."""
    try:
        value = float(reference_period)
    except (TypeError, ValueError):
        raise InputError(
            "reference_period", reference_period, "a Chandler period in seconds, longer than a year"
        ) from None
    if not (math.isfinite(value) and value > 1.02 * TROPICAL_YEAR):
        raise InputError(
            "reference_period", f"{value / DAY:g} d", "a finite Chandler period longer than 1.02 tropical years"
        )
    return value


def beat_period(reference_period: float) -> float:
    """Beat of the Chandler and annual terms, 1/(1/T_a - 1/T_c), s: about 6.4 years for 433 d.

    ``reference_period`` is a *published* Chandler period (the Earth catalogue's
    ``observed_chandler_period``, passed in by :mod:`wobble.api`): it only places
    the beat that decides what a "short" span is, and is never a prior.
    """
    return 1.0 / (1.0 / TROPICAL_YEAR - 1.0 / check_reference_period(reference_period))


def span_caveats(span: float, beat: float) -> list[str]:
    """What a span shorter than one Chandler-annual beat period (``beat``, s) means for the estimate."""
    notes = []
    if span < beat:
        notes.append(
            f"span {span / JULIAN_YEAR:.1f} yr is shorter than the {beat / JULIAN_YEAR:.1f}-yr beat of "
            "the Chandler and annual terms: the two are barely separable, and the uncertainty is widened "
            "by the drift-model and excitation terms"
        )
    return notes


def bin_means(t: np.ndarray, y: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """Means of ``y`` in bins of ``width`` (s) from t[0]; times are the bin centres; empty bins dropped."""
    idx = np.floor((t - t[0]) / width).astype(int)
    n = int(idx[-1]) + 1
    counts = np.bincount(idx, minlength=n)
    sums = np.bincount(idx, weights=y.real, minlength=n) + 1j * np.bincount(idx, weights=y.imag, minlength=n)
    keep = counts > 0
    centres = t[0] + width * (np.arange(n) + 0.5)
    return centres[keep], sums[keep] / counts[keep]


def same_times(t: np.ndarray, masks: dict) -> list[list]:
    """Groups (two or more) of the keys of ``masks`` whose samples ``t[mask]`` are the same times about
    their centre: the same drift and annual columns, the same Fourier grids, so one computation for
    all (the windows or sub-spans of a gap-free daily record; one group per length in days).

    Spans shorter than :data:`MIN_SPAN`, which an estimator refuses, are in no group.
    """
    groups: dict[tuple, list] = {}
    for key, m in masks.items():
        tm = t[m]
        if tm.size < 2 or tm[-1] - tm[0] < MIN_SPAN:
            continue
        centred = tm - 0.5 * (tm[0] + tm[-1])
        groups.setdefault((centred.tobytes(), 0.5 * (tm[-1] - tm[0])), []).append(key)
    return [g for g in groups.values() if len(g) > 1]
