"""Least-squares fits of equation (2) on sliding windows: how the wobble changes over the decades.

Times and lengths in s, angles in rad, rates in rad/s.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from wobble.errors import InputError
from wobble.models.polar_motion.least_squares import fit_least_squares, vp_rates, vp_tracked
from wobble.models.polar_motion.record import (
    CHANDLER_BAND,
    DAY,
    MIN_SPAN,
    as_series,
    check_band,
    check_degree,
    same_times,
)
from wobble.models.polar_motion.uncertainty import model_degrees
from wobble.numerics.threads import one_blas_thread

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = ["WindowedFits", "sliding_windows", "shortest_window", "window_allowed"]


@dataclass(frozen=True, eq=False)
class WindowedFits:
    """Least-squares fits of equation (2) on sliding windows (arrays over windows).

    Windows whose data cover less than 80 % of their length are NaN.
    """

    centre: np.ndarray
    start: np.ndarray
    end: np.ndarray
    n_samples: np.ndarray
    period: np.ndarray
    period_sigma: np.ndarray
    amplitude: np.ndarray
    amplitude_sigma: np.ndarray
    phase: np.ndarray
    annual_prograde_amplitude: np.ndarray
    annual_prograde_amplitude_sigma: np.ndarray
    annual_retrograde_amplitude: np.ndarray
    window: float
    step: float
    drift_degree: int
    #: Windows whose best period lay at or past the search band's edge, or whose Chandler term could not be told
    #: from the annual terms (variance inflation above 10): no Chandler term resolved there, and their values are
    #: left NaN (two-year windows gave 365-d "Chandler" terms of 6e9 mas beside the annual).
    unresolved: int = 0

    # Deprecated names (one release): the annual terms are annual_prograde_* and annual_retrograde_*.
    @property
    def annual_amplitude(self) -> np.ndarray:
        """Deprecated alias of :attr:`annual_prograde_amplitude`."""
        _deprecated("annual_amplitude", "annual_prograde_amplitude")
        return self.annual_prograde_amplitude

    @property
    def annual_amplitude_sigma(self) -> np.ndarray:
        """Deprecated alias of :attr:`annual_prograde_amplitude_sigma`."""
        _deprecated("annual_amplitude_sigma", "annual_prograde_amplitude_sigma")
        return self.annual_prograde_amplitude_sigma

    @property
    def retrograde_annual_amplitude(self) -> np.ndarray:
        """Deprecated alias of :attr:`annual_retrograde_amplitude`."""
        _deprecated("retrograde_annual_amplitude", "annual_retrograde_amplitude")
        return self.annual_retrograde_amplitude


def _deprecated(old: str, new: str) -> None:
    warnings.warn(
        f"WindowedFits.{old} is deprecated; use {new} (the old name goes in the next release)",
        DeprecationWarning,
        stacklevel=3,
    )


def _window_searches(t, z, masks, degree, band) -> dict[int, dict]:
    """The variable projection's Chandler rate of each window and the fits of its drift-model check,
    ``{window: {"rate": rate, "model_check": [tracked values at one degree less, one more]}}``.

    On a daily record most windows hold the same number of days, and then the same times about
    their centre (and the same drift and annual columns): their searches are one
    :func:`~wobble.models.polar_motion.least_squares.vp_rates` per degree (a QR, a grid product and
    the Brent refinements in lockstep), and the model check's coefficients one
    :func:`~wobble.models.polar_motion.least_squares.vp_tracked` per degree, instead of one of each
    per window and degree. Windows whose centred times match no other's (gaps; too short to be
    fitted) are left to fit_least_squares alone.
    """
    try:
        band = check_band(band)
    except InputError:
        return {}  # each window's fit refuses it, as it always has
    found: dict[int, dict] = {}
    for members in same_times(t, masks):
        tw = t[masks[members[0]]]
        zs = np.column_stack([z[masks[i]] for i in members])
        checks = [
            vp_tracked(tw, zs, vp_rates(tw, zs, drift_degree=d, band=band), drift_degree=d)
            for d in model_degrees(degree)
        ]
        for k, (i, rate) in enumerate(zip(members, vp_rates(tw, zs, drift_degree=degree, band=band))):
            found[i] = {"rate": float(rate), "model_check": [check[k] for check in checks]}
    return found


def shortest_window(t) -> float:
    """The shortest window whose fits can run, s: MIN_SPAN plus twice the median sample spacing.

    A window [a, a + W] of samples dt apart holds samples spanning more than W - 2 dt (up to a sample
    interval is lost at each end), and each window's fit needs MIN_SPAN of them, as the whole span's
    does: windows of exactly two years on daily data held 730 d each, and every one came out NaN,
    silently.
    """
    t = np.asarray(t, dtype=float)
    return MIN_SPAN + (2.0 * float(np.median(np.diff(t))) if t.size > 1 else 0.0)


def window_allowed(t) -> str:
    """What a refused window length is told: from :func:`shortest_window` to the span of ``t``."""
    year = JULIAN_YEAR
    shortest, span = shortest_window(t), float(t[-1] - t[0])
    if shortest > span:  # no length fits: say what span would take one (it offered an empty range)
        return (
            f"no window fits these {span / DAY:g} d: the samples in each must span {MIN_SPAN / year:g} yr, so "
            f"windows need at least {shortest / DAY:g} d of data (a later end date or an earlier start)"
        )
    return (
        f"a length from {shortest / year:.4g} yr ({shortest / DAY:g} d: the samples in each window must span "
        f"{MIN_SPAN / year:g} yr) to the span analysed ({span / year:.2f} yr)"
    )


@one_blas_thread
def sliding_windows(
    t,
    z,
    window: float,
    step: float | None = None,
    *,
    reference_period: float,
    drift_degree: int = 2,
    band: tuple[float, float] = CHANDLER_BAND,
    progress=None,
) -> WindowedFits:
    """Least-squares fits of equation (2) on windows of length ``window`` moved by ``step`` (s).

    Each window gets its own drift, annual terms and Chandler period,
    amplitude and phase, with the autocorrelation and drift-model
    uncertainty (a window is too short for the sub-span check). ``progress``
    (optional) is called as ``progress(done, total)``; ``reference_period``
    (a published Chandler period, s) as in
    :func:`~wobble.models.polar_motion.least_squares.fit_least_squares`.
    """
    t, z = as_series(t, z)
    span = t[-1] - t[0]
    window = float(window)
    if not (math.isfinite(window) and shortest_window(t) <= window <= span * (1 + 1e-9)):
        raise InputError("window", f"{window / JULIAN_YEAR:g} yr", window_allowed(t))
    step = JULIAN_YEAR if step is None else float(step)
    if not (math.isfinite(step) and step > 0):
        raise InputError("step", f"{step / DAY:g} d", "a positive, finite time")
    n = int(math.floor((span - window) / step + 1e-9)) + 1
    starts = t[0] + step * np.arange(n)
    # Centre the set of windows in the span.
    starts += 0.5 * (span - window - (starts[-1] - t[0]))
    out = {
        k: np.full(n, np.nan)
        for k in ("period", "period_sigma", "amplitude", "amplitude_sigma", "phase", "annual", "annual_sigma", "retro")
    }
    counts = np.zeros(n, dtype=int)
    masks = {}
    for i, a in enumerate(starts):
        m = (t >= a) & (t <= a + window)
        counts[i] = int(m.sum())
        if counts[i] >= 10 and t[m][-1] - t[m][0] >= 0.8 * window:
            masks[i] = m
    found = _window_searches(t, z, masks, check_degree(drift_degree), band)
    unresolved = 0
    for i in range(n):
        if progress is not None:
            progress(i, n)
        if i not in masks:
            continue
        m = masks[i]
        try:
            f = fit_least_squares(
                t[m],
                z[m],
                reference_period=reference_period,
                drift_degree=drift_degree,
                band=band,
                subspans=False,
                excitation_q=None,
                **found.get(i, {}),
            )
        except InputError:
            continue
        if not f.resolved:  # at the band's edge, or not separable from the annual terms
            unresolved += 1
            continue
        out["period"][i] = f.chandler.period
        out["period_sigma"][i] = f.chandler.period_sigma
        out["amplitude"][i] = f.chandler.amplitude
        out["amplitude_sigma"][i] = f.chandler.amplitude_sigma
        out["phase"][i] = f.chandler.phase
        out["annual"][i] = f.annual_prograde.amplitude
        out["annual_sigma"][i] = f.annual_prograde.amplitude_sigma
        out["retro"][i] = f.annual_retrograde.amplitude
    if progress is not None:
        progress(n, n)
    return WindowedFits(
        centre=starts + 0.5 * window,
        start=starts,
        end=starts + window,
        n_samples=counts,
        period=out["period"],
        period_sigma=out["period_sigma"],
        amplitude=out["amplitude"],
        amplitude_sigma=out["amplitude_sigma"],
        phase=out["phase"],
        annual_prograde_amplitude=out["annual"],
        annual_prograde_amplitude_sigma=out["annual_sigma"],
        annual_retrograde_amplitude=out["retro"],
        window=window,
        step=step,
        drift_degree=check_degree(drift_degree),
        unresolved=unresolved,
    )
