"""Forecast intervals calibrated on the method's own past forecasts: quantiles of past standardised errors
per lead time.

A model's stated forecast variance is only as good as the model: on the IERS
record the 68 % intervals of least squares + autoregression held 48 % of the
outcomes at a year, those of the state-space model with a first-order
excitation 60 % at a day and 80 % at a month. Operational prediction centres
state their accuracy from their own past prediction errors instead (Kalarus et
al. 2010). This module does the same, per lead time, with nothing from the
future of the forecast it calibrates:

* the **past forecasts** are the same method's forecasts issued at
  t_i - k Delta (k = 1, 2, ...; Delta = :data:`STEP`, a week) before the
  issue time t_i, each from its own information set (the record up to
  t_i - k Delta - latency), with the Chandler period and noise parameters of
  the forecast being calibrated (a handful of numbers estimated on 10 to 30
  years of data up to t_i's cut-off); everything else - the least-squares
  fit, the autoregressions, the filtered state - is redone from each past
  issue's own data;
* for lead time l the errors used are those whose outcome, at
  t_i - k Delta + l, is at or before the cut-off c = t_i - latency (known when
  the forecast is issued): the most recent ``n`` of them, from ``span``
  of past issue dates (:data:`SPANS`: six years for the Kalman model, two
  for LS+AR);
* each error of x_p (likewise y_p) is divided by the sigma its own forecast
  stated, and the half-width of the p interval (p = 68.27 % or 95 %) at lead
  l is the ceil((n + 1) p)-th smallest of the n ratios times this forecast's
  sigma: the split-conformal quantile of a normalised score, which covers at
  least p of a new outcome when the scores are exchangeable (Vovk, Gammerman
  & Shafer 2005; Lei, G'Sell, Rinaldo et al. 2018, J. Am. Stat. Assoc. 113,
  1094, sec. 5.2). When all the sigmas are equal (the Kalman model, whose
  variance does not depend on the data) it is the quantile of the absolute
  errors themselves.

The week and the normalisation were chosen on a hindcast of forecasts issued
2006-2015, and so were the spans: of two to ten years, each method's is the one
with the sharpest intervals (the least mean interval score of Gneiting & Raftery
2007, J. Am. Stat. Assoc. 102, 359, eq. 43) among those whose 68 % intervals
held 63-73 % of the outcomes at every lead time from 1 to 365 days, with a
latency of 1 day and of 30 days (``scripts/calibration_span.py``). The Kalman
model's sigma does not depend on the data and its errors' ratio to it changes
slowly, so more past errors make a steadier quantile: six years. The LS+AR's
errors grew over those years faster than its sigma, and with spans of three
years or more its 68 % intervals fell below 63 % at some lead times: two.
The intervals are symmetric about the forecast and need no Gaussian
assumption. Only samples of the record at or before the cut-off are read (the
arrays are cut there first), so no outcome after it can enter. Times in s,
angles in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from wobble.errors import InputError
from wobble.models.polar_motion.forecast import Forecast, PastForecasts, check_method, information_set
from wobble.models.polar_motion.ls_ar import LS_SPAN, forecast_ls_ar, past_forecasts_ls_ar
from wobble.models.polar_motion.record import DAY
from wobble.models.polar_motion.state_space import (
    FIT_SPAN,
    KalmanSetup,
    NoiseParameters,
    fit_noise,
    forecast_kalman,
    past_forecasts_kalman,
)
from wobble.numerics.threads import one_blas_thread

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = [
    "SPANS",
    "span_for",
    "STEP",
    "P68",
    "P95",
    "MIN_COUNT",
    "FITTING_SPAN",
    "Calibration",
    "past_issue_times",
    "calibration_reach",
    "count_per_lead",
    "calibrate",
    "known_at",
    "kalman_setup",
    "past_forecasts",
    "check_calibration_span",
    "METHOD_NAMES",
    "forecast",
]

#: The span of data each method fits before its issue date.
FITTING_SPAN = {"ls_ar": LS_SPAN, "kalman": FIT_SPAN}
#: Each method's name in messages.
METHOD_NAMES = {"ls_ar": "LS+AR", "kalman": "Kalman"}

#: Span of past issue dates whose errors calibrate each lead time (the most recent with known outcomes),
#: per method (chosen on 2006-2015; see the module).
SPANS = {"ls_ar": 2.0 * JULIAN_YEAR, "kalman": 6.0 * JULIAN_YEAR}
#: Spacing of the past issue dates: a week.
STEP = 7.0 * DAY
#: Probabilities of the two intervals: one Gaussian sigma either side, and 95 %.
P68 = 0.6826894921370859
P95 = 0.95
#: Fewest past errors a lead time may be calibrated with (the 95 % quantile needs at least 19).
MIN_COUNT = 26
_EPS = 1e-6


@dataclass(frozen=True, eq=False)
class Calibration:
    """Half-widths of the 68 % and 95 % intervals per lead time from past errors (see the module).

    Attributes
    ----------
    half68, half95 : ndarray (H, 2)
        Half-widths for x_p (column 0) and y_p (column 1), rad.
    scale68, scale95 : ndarray (H, 2)
        The quantiles of the standardised past errors: the half-widths over the forecast's own sigma.
    count : ndarray (H,)
        Number of past errors behind each lead time's quantiles.
    span, step : float
        Span and spacing of the past issue dates, s.
    first_issue, last_issue : float
        Earliest and latest past issue times whose errors were used, s.
    last_outcome : float
        Latest outcome time used (at or before the cut-off), s.
    cutoff : float
        The information cut-off: issue time minus latency, s.
    """

    half68: np.ndarray
    half95: np.ndarray
    scale68: np.ndarray
    scale95: np.ndarray
    count: np.ndarray
    span: float
    step: float
    first_issue: float
    last_issue: float
    last_outcome: float
    cutoff: float

    def half_widths(self, level: int) -> tuple[np.ndarray, np.ndarray]:
        """(x_p, y_p) half-widths of the ``level`` % interval (68 or 95), rad."""
        h = {68: self.half68, 95: self.half95}[level]
        return h[:, 0], h[:, 1]


def span_for(method: str, span: float | None = None) -> float:
    """The calibration span of ``method``: ``span`` if given, else the method's own (:data:`SPANS`), s."""
    return SPANS[method] if span is None else float(span)


def past_issue_times(issued: float, latency: float, horizon_days: int, span: float, step: float = STEP) -> np.ndarray:
    """Every past issue time a forecast issued at ``issued`` is calibrated with, oldest first.

    Lead l (days) uses k from ceil((l + latency) / step) on, ``round(span / step)``
    of them; the oldest belongs to the longest lead.
    """
    k_last = round(calibration_reach(latency, horizon_days, span, step) / step)
    return issued - step * np.arange(k_last, 0, -1)


def calibration_reach(latency: float, horizon_days: int, span: float, step: float = STEP) -> float:
    """How long before the issue date its oldest past forecast is issued, s (the same for every issue date)."""
    return step * (_steps_to_longest_lead(latency, horizon_days, step) + count_per_lead(span, step) - 1)


def _steps_to_longest_lead(latency: float, horizon_days: int, step: float) -> int:
    """Steps back to the newest past issue whose outcome at the longest lead is known at the cut-off."""
    return math.ceil((horizon_days * DAY + latency) / step - 1e-9)


def count_per_lead(span: float, step: float = STEP) -> int:
    """Past issues per lead time: ``span / step``, at least :data:`MIN_COUNT`."""
    n = int(round(span / step))
    if n < MIN_COUNT:
        raise InputError(
            "calibration_span",
            f"{span / DAY:g} d",
            f"at least {MIN_COUNT * step / DAY:g} d ({MIN_COUNT} past forecasts a week apart)",
        )
    return n


def known_at(t, z, cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    """The record at or before ``cutoff``: all a calibration may read."""
    t = np.asarray(t, dtype=float)
    keep = t <= cutoff + _EPS
    return t[keep], np.asarray(z, dtype=complex)[keep]


def _order_statistic(a: np.ndarray, p: float, axis: int) -> np.ndarray:
    """The ceil((n + 1) p)-th smallest of n values along ``axis`` (split-conformal quantile)."""
    n = a.shape[axis]
    k = min(math.ceil((n + 1) * p), n) - 1
    return np.partition(a, k, axis=axis).take(k, axis=axis)


def calibrate(
    t,
    z,
    issued: float,
    latency: float,
    horizon_days: int,
    past: PastForecasts,
    sigma,
    *,
    span: float,
    step: float = STEP,
) -> Calibration:
    """Interval half-widths per lead time for a forecast issued at ``issued`` from ``past`` (see the module).

    ``t``, ``z`` is the record (daily; times s, pole rad); only its samples at or
    before ``issued - latency`` are read. ``past`` must hold the forecasts
    issued at :func:`past_issue_times` (more are ignored) with ``horizon_days``
    leads; ``sigma`` is the (sigma_x, sigma_y) the forecast itself states (H each).
    """
    cutoff = issued - latency
    tk, zk = known_at(t, z, cutoff)
    n = count_per_lead(span, step)
    times = past_issue_times(issued, latency, horizon_days, span, step)
    sel = past.take(times)
    lead = np.arange(1, horizon_days + 1)
    # Past issue k (index into ``times``, oldest first) at lead l: outcome at times[k] + l days.
    k_max = np.array(
        [times.size - math.ceil((d * DAY + latency) / step - 1e-9) for d in lead]
    )  # newest usable, per lead
    rows = k_max[:, None] - np.arange(n)[None, :]  # (H, n): the n most recent usable issues of each lead
    outcome_time = times[rows] + lead[:, None] * DAY
    pos = np.searchsorted(tk, outcome_time - _EPS)
    found = (pos < tk.size) & (np.abs(tk[np.minimum(pos, tk.size - 1)] - outcome_time) <= _EPS)
    if not found.all():
        missing = int(np.sum(~found))
        raise InputError(
            "data",
            f"{missing} outcomes of past forecasts missing from the record",
            "a daily record without gaps over the calibration span",
        )
    truth = zk[pos]
    err = sel.mean[rows, lead[:, None] - 1] - truth  # (H, n) complex
    stated = sel.sigma[rows, lead[:, None] - 1]  # (H, n, 2)
    ax = np.abs(err.real) / stated[..., 0]
    ay = np.abs(err.imag) / stated[..., 1]  # |y error| = |Im|, since y_p = -Im p
    scale68 = np.stack([_order_statistic(ax, P68, 1), _order_statistic(ay, P68, 1)], axis=1)
    scale95 = np.stack([_order_statistic(ax, P95, 1), _order_statistic(ay, P95, 1)], axis=1)
    now = np.stack([np.asarray(sigma[0], dtype=float), np.asarray(sigma[1], dtype=float)], axis=1)
    used = times[np.unique(rows)]
    return Calibration(
        half68=scale68 * now,
        half95=scale95 * now,
        scale68=scale68,
        scale95=scale95,
        count=np.full(horizon_days, n),
        span=float(span),
        step=float(step),
        first_issue=float(used[0]),
        last_issue=float(used[-1]),
        last_outcome=float(outcome_time.max()),
        cutoff=float(cutoff),
    )


def kalman_setup(
    t, z, issued: float, latency: float, chandler_period: float, q: float, noise: NoiseParameters | None = None
):
    """(setup, log-likelihood): the Kalman model at ``issued``, its noise fitted on the information set unless given."""
    ti, zi = information_set(t, z, issued, latency, FIT_SPAN, "Kalman")
    loglike = math.nan
    if noise is None:
        from wobble.models.polar_motion.excitation import chandler_frequency

        noise, loglike = fit_noise(ti, zi, chandler_frequency(chandler_period, q))
    return KalmanSetup.build(chandler_period, q, noise, zi.size), loglike


def past_forecasts(
    t,
    z,
    issues,
    horizon_days: int,
    *,
    method: str,
    chandler_period: float,
    latency: float,
    setup: KalmanSetup | None = None,
) -> PastForecasts:
    """The means of ``method``'s forecasts issued at ``issues`` (each from its own information set)."""
    if method == "kalman":
        return past_forecasts_kalman(t, z, issues, horizon_days, setup=setup, latency=latency)
    return past_forecasts_ls_ar(t, z, issues, horizon_days, chandler_period=chandler_period, latency=latency)


def check_calibration_span(
    t, issued: float, latency: float, horizon_days: int, method: str, span: float | None = None, step: float = STEP
) -> None:
    """Refuse a calibration whose oldest past forecast would need data from before the record's start
    (``span`` None: the method's own, :data:`SPANS`, which the message then calls the default: the user did
    not choose it)."""
    default = span is None
    span = span_for(method, span)
    oldest = past_issue_times(issued, latency, horizon_days, span, step)[0]
    need = FITTING_SPAN[method]
    have = oldest - latency - float(np.asarray(t)[0])
    if have < need - 0.5 * DAY:
        # The most forecasts per lead the record allows, n: the oldest is issued (k + n - 1) steps back
        # (calibration_reach) and needs its fitting span of record before it. The span offered is n whole
        # steps: a span holds round(span / step) forecasts, so the span less the shortfall could be refused.
        room = issued - latency - float(np.asarray(t)[0]) - need + 0.5 * DAY
        most = step * (math.floor(room / step + 1e-9) - _steps_to_longest_lead(latency, horizon_days, step) + 1)
        allowed = (
            # Rounded down, so that the span allowed never reads as the span refused (2.0 yr for 1.96).
            f"at most {math.floor(most / JULIAN_YEAR * 100) / 100:.2f} yr for this issue date and horizon "
            "(the oldest past forecast, issued "
            f"{(issued - oldest) / DAY:.0f} d before, needs its {need / JULIAN_YEAR:.0f}-yr {METHOD_NAMES[method]} "
            "fitting span in the record)"
            if most >= MIN_COUNT * step
            else "a later issue date: its past forecasts need "
            f"{(issued - oldest + latency + need) / JULIAN_YEAR:.1f} yr of record before it"
        )
        shown = f"{span / JULIAN_YEAR:g} yr" + (f" (the {METHOD_NAMES[method]} default)" if default else "")
        raise InputError("calibration_span", shown, allowed)


@one_blas_thread
def forecast(
    t,
    z,
    issued: float,
    horizon_days: int,
    *,
    method: str,
    chandler_period: float,
    q: float,
    latency: float = DAY,
    calibrated: bool = True,
    span: float | None = None,
    noise: NoiseParameters | None = None,
    setup: KalmanSetup | None = None,
    past: PastForecasts | None = None,
    progress=None,
) -> Forecast:
    """A forecast of ``method`` issued at ``issued`` with intervals calibrated on its past forecasts (see the module).

    The record is cut at the information cut-off ``issued - latency`` before
    anything else, so neither the forecast nor its calibration can read a
    later sample. ``noise``/``setup`` (Kalman) and ``past`` let a hindcast
    share work between issues; ``calibrated=False`` keeps the model's own
    Gaussian intervals; ``span`` None is the method's own (:data:`SPANS`); ``progress(message)``, when given,
    is told each stage.
    """
    say = progress or (lambda message: None)
    method = check_method(method)
    span = span_for(method, span)
    t, z = known_at(t, z, issued - latency)
    information_set(
        t, z, issued, latency, FITTING_SPAN[method], METHOD_NAMES[method]
    )  # the issue date's own checks first
    if calibrated:
        check_calibration_span(t, issued, latency, horizon_days, method, span)
    loglike = math.nan
    if method == "kalman":
        if setup is None:
            say("Kalman noise by maximum likelihood")
            setup, loglike = kalman_setup(t, z, issued, latency, chandler_period, q, noise)
        raw = forecast_kalman(
            t, z, issued, horizon_days, chandler_period=chandler_period, q=q, latency=latency, setup=setup
        )
        raw.details.update(noise_refitted=noise is None and math.isfinite(loglike), log_likelihood=loglike)
    else:
        raw = forecast_ls_ar(t, z, issued, horizon_days, chandler_period=chandler_period, latency=latency)
    if not calibrated:
        return raw
    times = past_issue_times(issued, latency, horizon_days, span)
    if past is None:
        say(f"{len(times)} past forecasts to calibrate the intervals")
        past = past_forecasts(
            t, z, times, horizon_days, method=method, chandler_period=chandler_period, latency=latency, setup=setup
        )
    return replace(
        raw, calibration=calibrate(t, z, issued, latency, horizon_days, past, (raw.sigma_x, raw.sigma_y), span=span)
    )
