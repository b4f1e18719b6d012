"""Hindcasts: forecasts issued at past dates from the data available then, scored against what followed.

Every forecast uses only the samples up to its issue time minus the latency
(:func:`~wobble.models.polar_motion.forecast.information_set`): the Chandler
period and the state-space noise are re-estimated every ``refit`` issues from
those samples too, never from later ones, and so are the intervals' calibrations
(:mod:`.forecast_calibration`). Scores per lead time (1 .. H days):

* mean absolute error and RMS of x_p and y_p, and of the 2-D pole
  (|p - p_hat|: RMS = sqrt(mean(dx^2 + dy^2)));
* coverage: the fraction of outcomes inside the 68 % and 95 % intervals
  (x_p and y_p pooled);
* skill against persistence (the last value used) and against the
  least-squares extrapolation alone: 1 - RMS / RMS_reference (2-D).

Times in s, angles in rad (scores in rad; the API converts).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wobble.models.polar_motion import forecast_calibration as fcal
from wobble.models.polar_motion.forecast import Forecast, check_method
from wobble.models.polar_motion.least_squares import fit_least_squares
from wobble.numerics.threads import one_blas_thread

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = ["PERIOD_SPAN", "Block", "blocks", "run_block", "Scores", "score", "truth_at"]

#: Span of data before each refit used to measure the Chandler period (least squares, no uncertainty).
PERIOD_SPAN = 30.0 * JULIAN_YEAR


@dataclass(frozen=True)
class Block:
    """Issue times that share one refit (period and noise estimated at the first, from data before it)."""

    issues: tuple[float, ...]
    horizon_days: int
    methods: tuple[str, ...]
    latency: float
    q: float
    reference_period: float
    chandler_period: float | None = None
    calibrated: tuple[str, ...] = ()
    calibration_span: float | None = None


def blocks(
    issues,
    horizon_days,
    methods,
    latency,
    q,
    reference_period,
    refit: int = 13,
    chandler_period=None,
    calibrated=None,
    calibration_span=None,
) -> list[Block]:
    """The issue times cut into blocks of ``refit`` consecutive issues (the unit of parallel work).

    ``calibrated`` names the methods whose intervals are calibrated (default: all);
    ``calibration_span`` None gives each method its own (:data:`.forecast_calibration.SPANS`).
    """
    issues = [float(x) for x in issues]
    methods = tuple(check_method(m) for m in methods)
    calibrated = methods if calibrated is None else tuple(check_method(m) for m in calibrated)
    return [
        Block(
            tuple(issues[i : i + refit]),
            int(horizon_days),
            methods,
            float(latency),
            float(q),
            float(reference_period),
            chandler_period,
            calibrated,
            None if calibration_span is None else float(calibration_span),
        )
        for i in range(0, len(issues), refit)
    ]


@one_blas_thread
def run_block(t, z, block: Block) -> list[list[Forecast]]:
    """The forecasts of every method at every issue of ``block`` (outer list: issues), calibrated as the block says.

    The Chandler period and the Kalman noise are estimated once, at the first
    issue, from the data before it; every forecast of the block, and every past
    forecast its calibration uses, shares them (:func:`.forecast_calibration.forecast`).
    The past forecasts of all the block's issues are computed once.
    """
    first = block.issues[0]
    cutoff = first - block.latency
    period = block.chandler_period
    if period is None:
        use = (t <= cutoff + 1e-6) & (t >= cutoff - PERIOD_SPAN)
        period = fit_least_squares(
            t[use], z[use], reference_period=block.reference_period, uncertainty=False
        ).chandler.period
    setup = None
    if "kalman" in block.methods:
        tk, zk = fcal.known_at(t, z, cutoff)
        setup, _ = fcal.kalman_setup(tk, zk, first, block.latency, period, block.q)
    past = {}
    for method in block.calibrated:
        span = fcal.span_for(method, block.calibration_span)
        times = np.unique(
            np.round(
                np.concatenate(
                    [fcal.past_issue_times(i, block.latency, block.horizon_days, span) for i in block.issues]
                ),
                3,
            )
        )
        past[method] = fcal.past_forecasts(
            t,
            z,
            times,
            block.horizon_days,
            method=method,
            chandler_period=period,
            latency=block.latency,
            setup=setup,
        )
    out = []
    for issued in block.issues:
        out.append(
            [
                fcal.forecast(
                    t,
                    z,
                    issued,
                    block.horizon_days,
                    method=method,
                    chandler_period=period,
                    q=block.q,
                    latency=block.latency,
                    calibrated=method in block.calibrated,
                    span=block.calibration_span,
                    setup=setup,
                    past=past.get(method),
                )
                for method in block.methods
            ]
        )
    return out


@dataclass(frozen=True, eq=False)
class Scores:
    """Scores of one method against lead time (arrays over leads; rad, fractions)."""

    mae_x: np.ndarray
    mae_y: np.ndarray
    rms_x: np.ndarray
    rms_y: np.ndarray
    mae_2d: np.ndarray
    rms_2d: np.ndarray
    coverage_68: np.ndarray
    coverage_95: np.ndarray
    rms_2d_persistence: np.ndarray
    rms_2d_ls: np.ndarray
    skill_persistence: np.ndarray
    skill_ls: np.ndarray


def score(
    truth: np.ndarray, mean: np.ndarray, half68: tuple, half95: tuple, persistence: np.ndarray, ls_only: np.ndarray
) -> Scores:
    """Scores of forecasts ``mean`` (issues x leads, complex) against ``truth`` (same shape).

    ``half68`` and ``half95`` are the (x_p, y_p) half-widths of the intervals
    (each issues x leads); ``persistence`` is the last value used by each
    issue (issues,), ``ls_only`` the least-squares extrapolation (issues x leads).
    """
    d = mean - truth
    dx, dy = d.real, -d.imag
    inside68 = (np.abs(dx) <= half68[0]).astype(float) + (np.abs(dy) <= half68[1])
    inside95 = (np.abs(dx) <= half95[0]).astype(float) + (np.abs(dy) <= half95[1])
    rms2 = np.sqrt(np.mean(np.abs(d) ** 2, axis=0))
    rms_p = np.sqrt(np.mean(np.abs(persistence[:, None] - truth) ** 2, axis=0))
    rms_ls = np.sqrt(np.mean(np.abs(ls_only - truth) ** 2, axis=0))
    return Scores(
        mae_x=np.mean(np.abs(dx), axis=0),
        mae_y=np.mean(np.abs(dy), axis=0),
        rms_x=np.sqrt(np.mean(dx**2, axis=0)),
        rms_y=np.sqrt(np.mean(dy**2, axis=0)),
        mae_2d=np.mean(np.abs(d), axis=0),
        rms_2d=rms2,
        coverage_68=np.mean(inside68, axis=0) / 2.0,
        coverage_95=np.mean(inside95, axis=0) / 2.0,
        rms_2d_persistence=rms_p,
        rms_2d_ls=rms_ls,
        skill_persistence=1.0 - rms2 / rms_p,
        skill_ls=1.0 - rms2 / rms_ls,
    )


def truth_at(t, z, times) -> np.ndarray:
    """The record at ``times`` (daily samples; a time between samples is interpolated), complex rad."""
    return np.interp(times, t, z.real) + 1j * np.interp(times, t, z.imag)
