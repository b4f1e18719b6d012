"""Forecasts of the pole with 68 % and 95 % intervals (:func:`forecast_polar_motion`).

>>> import wobble
>>> from astropy import units as u
>>> f = wobble.forecast_polar_motion(issued="2019-01-01", horizon=30 * u.day, method="ls_ar", latency=1 * u.day)
>>> f.to_dict()["horizon_days"], len(f.to_dict()["forecast"]), f.method
(30, 30, 'ls_ar')

Two methods (:mod:`wobble.models.polar_motion`): ``ls_ar``, least squares of
trend, Chandler, annual and semi-annual terms plus an autoregressive model of
the residuals (the operational baseline), and ``kalman``, a damped Chandler
oscillator driven by coloured (third-order autoregressive) excitation with
seasonal terms and a mean-pole drift, filtered with maximum-likelihood noise
(the physical model). Both take
the Chandler period wobble measures in the record before the issue date; the
Kalman model takes Q from wobble's Chandler budget (the anelastic Love number)
unless given.

**Latency.** A forecast issued on a date uses the record only up to that date
minus the record's publication delay: the IERS 20 C04 series appears about 30
days after the fact, the IERS Rapid Service's finals2000A values about a day.
Those are the defaults (``latency``); lead times count from the issue date.

**Intervals.** The 68 % and 95 % intervals are calibrated on the method's own
past forecasts (:mod:`wobble.models.polar_motion.forecast_calibration`): the
same method issued every week over the six years (Kalman) or two years
(LS+AR) before, each from its own data, and for each lead time the
split-conformal quantile of the absolute errors whose outcomes were known at
the issue date minus the latency. With ``calibrated=False`` they are the
model's Gaussian +/- sigma and +/- 1.96 sigma.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from astropy import units as u

from wobble.api.polar_motion.estimate import published_chandler_period
from wobble.api.polar_motion.record import MJD_J2000, RAD_PER_MAS, check_daily, series_with_attrs
from wobble.api._progress import stage_messages
from wobble.api.units import real_float, to_si
from wobble.errors import InputError
from wobble.io.dates import MJD_UNITS, iso_date, mjd_time, to_mjd
from wobble.io.json_keys import deprecate
from wobble.io.text import with_uncertainty
from wobble.models.polar_motion import forecast as _fc
from wobble.models.polar_motion import forecast_calibration as _cal
from wobble.models.polar_motion.least_squares import fit_least_squares
from wobble.models.polar_motion.record import DAY

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = [
    "LATENCY",
    "PolarMotionForecast",
    "forecast_polar_motion",
    "default_latency",
    "default_q",
    "chandler_period_before",
    "calibration_span_si",
    "calibration_text",
    "FORECAST_RENAMES",
]

#: ``wobble forecast --json`` keys kept under their old names for one release (README, "Commands"): the Kalman
#: model's ``details.q`` repeated the top-level ``quality_factor`` (and ``q`` is Omega^2 a^3/(GM) in modes).
FORECAST_RENAMES = {"details.q": "quality_factor"}

#: Publication delay of each kind of record, days: C04 about a month (the shipped file ends 34 days
#: before its package date), the Rapid Service's finals2000A about a day.
LATENCY = {"c04": 30.0, "finals2000A": 1.0}
_PERIOD_SPAN = 30.0 * JULIAN_YEAR


def default_latency(attrs) -> float:
    """The publication delay of the record's kind, s (C04: 30 d; finals2000A: 1 d; other Datasets: 1 d),
    from the global attributes of its Dataset (``source_format``)."""
    return LATENCY.get(attrs.get("source_format", ""), 1.0) * DAY


@functools.lru_cache(maxsize=1)
def default_q() -> float:
    """Q of the Chandler wobble from wobble's own model: the anelastic step of ``chandler_budget('earth')``.

    The nominal model alone (no Monte Carlo of the uncertainties, which costs 0.2-0.5 s and does not
    change Q), once per process.
    """
    from wobble.api.chandler import load_planet
    from wobble.models.chandler import chandler_budget

    return float(chandler_budget(load_planet("earth").parameters, "full", uncertainty=False).quality_factor)


#: What a quality factor may be: the free wobble's amplitude falls by exp(-pi / Q) a cycle, so under
#: Q = 1 (a factor 23 a cycle) there is no wobble left to speak of.
Q_ALLOWED = "a quality factor Q >= 1 (e.g. 100; the free wobble decays by exp(-pi/Q) a cycle), or inf (undamped)"


def check_q(q) -> float:
    """Q >= 1 (inf allowed: undamped)."""
    try:
        value = real_float(q)  # not "80" or True
    except (TypeError, ValueError):
        raise InputError("q", q, Q_ALLOWED) from None
    if not value >= 1.0:
        raise InputError("q", q, Q_ALLOWED)
    return value


def chandler_period_before(t, z, cutoff: float) -> float:
    """The Chandler period (s) wobble measures (least squares) in the 30 years of record before ``cutoff``."""
    use = (t <= cutoff + 1e-6) & (t >= cutoff - _PERIOD_SPAN)
    reference = published_chandler_period()["period"].to_value(u.s)
    return fit_least_squares(t[use], z[use], reference_period=reference, uncertainty=False).chandler.period


def check_horizon_days(horizon) -> int:
    """``horizon`` (a Quantity of time) as whole days, 1 to 1096 (:func:`.forecast.check_horizon` of the models).

    The lead times are whole days (the record is daily). A horizon in another unit is told its length in days
    beside the rule: 3 yr is 1095.75 d (a Julian year is 365.25 d), and "a whole number of days ... (three years)"
    alone read as refusing its own "three years". A calibration span needs no such rule: it is the stretch of
    record whose weekly past forecasts calibrate the intervals, any length from 26 weeks to 30 yr.
    """
    seconds = to_si(horizon, "horizon", u.s, shape=())
    try:
        return _fc.check_horizon(seconds)
    except InputError as exc:
        days = seconds / DAY
        if horizon.unit == u.day or not math.isfinite(days):
            raise
        julian = " (a Julian year is 365.25 d)" if horizon.unit == u.yr else ""
        note = f"; the horizon given is {days:g} d{julian}"
        low, high = max(1, math.floor(days)), min(round(_fc.MAX_HORIZON / DAY), math.ceil(days))
        if low < high:  # in range, between two whole days: name them
            note += f", so give {low} d or {high} d"
        raise InputError(exc.parameter, horizon, exc.allowed + note) from None


#: What a calibration span may be (the shortest holds MIN_COUNT forecasts a week apart).
CALIBRATION_SPAN_ALLOWED = (
    f"a span from {_cal.MIN_COUNT * _cal.STEP / (7 * DAY):.0f} weeks ({_cal.MIN_COUNT * _cal.STEP / DAY:g} d, "
    f"{_cal.MIN_COUNT} past forecasts a week apart) to 30 yr"
)


def calibration_span_si(span) -> float | None:
    """The calibration span in s: from 26 weeks to 30 years (a Quantity of time; None stays None: each method's own,
    6 yr for Kalman and 2 yr for LS+AR)."""
    if span is None:
        return None
    value = float(to_si(span, "calibration_span", u.s, shape=()))
    if not (math.isfinite(value) and _cal.MIN_COUNT * _cal.STEP - 1e-6 <= value <= 30 * JULIAN_YEAR):
        raise InputError("calibration_span", span, CALIBRATION_SPAN_ALLOWED)
    return value


def calibration_text(cal) -> str:
    """How the intervals were calibrated, in one sentence for people (JSON, netCDF attributes)."""
    if cal is None:
        return "68 % = mean +/- 1 sigma, 95 % = mean +/- 1.96 sigma of the model (Gaussian errors, not calibrated)"
    return (
        f"calibrated on the method's own past forecasts: {int(cal.count[0])} per lead time, issued every "
        f"{cal.step / DAY:g} d from {iso_date(MJD_J2000 + cal.first_issue / DAY)} to "
        f"{iso_date(MJD_J2000 + cal.last_issue / DAY)}, "
        "each from its own data, with outcomes known at the issue date minus the latency "
        f"(the latest {iso_date(MJD_J2000 + cal.last_outcome / DAY)}); per lead time and for x_p and y_p apart, the "
        "half-width is this forecast's sigma times the split-conformal quantile of the past errors over their own "
        "stated sigma (the ceil((n+1) p)-th smallest of the n ratios, p = 68.27 % and 95 %; Vovk, Gammerman & Shafer "
        "2005; Lei et al. 2018)"
    )


def whole_days(seconds: float) -> bool:
    """Whether ``seconds`` is a whole number of days (the record is daily: a forecast issued between two
    samples, or a latency of a day and a half, would score its past forecasts at times the record lacks)."""
    days = float(seconds) / DAY
    return math.isfinite(days) and abs(days - round(days)) <= 1e-9 * max(1.0, abs(days))


def latency_si(latency, attrs) -> float:
    """The record's publication delay in s: ``latency`` (a time Quantity, a whole number of days from 0 d to
    365 d) or the default of the record whose Dataset's global attributes are ``attrs``."""
    if latency is None:
        return default_latency(attrs)
    value = float(to_si(latency, "latency", u.s, shape=()))
    if not (math.isfinite(value) and 0 <= value <= 365 * DAY + 1e-6 and whole_days(value)):
        raise InputError("latency", latency, "a whole number of days from 0 d to 365 d (the record is daily)")
    return float(round(value / DAY)) * DAY


class PolarMotionForecast:
    """One forecast of the pole (build with :func:`forecast_polar_motion`).

    Attributes
    ----------
    method : str
        ``ls_ar`` or ``kalman``.
    issued : astropy.time.Time
        Issue date (UTC).
    last_data : astropy.time.Time
        Date of the last sample used.
    latency : Quantity
        The publication delay assumed, days.
    lead : Quantity
        Lead times, days (1 .. horizon).
    x, y : Quantity
        The forecast pole coordinates, mas.
    sigma_x, sigma_y : Quantity
        The model's own one-sigma errors, mas.
    calibration : Calibration or None
        The intervals' calibration on past forecasts (None: the model's Gaussian
        intervals, +/- 1 and 1.96 sigma); :meth:`bounds` gives the intervals either way.
    chandler_period : Quantity
        The Chandler period the forecast used, days.
    chandler_period_span : tuple of str or None
        First and last day of the record whose least squares gave it (the 30 years up to the
        issue date minus the latency, or less of a shorter record); None: the period was given.
    raw : wobble.models.polar_motion.forecast.Forecast
        The SI result of the model layer.
    """

    def __init__(self, raw: _fc.Forecast, latency: float, source: str, q: float | None, period_span=None):
        self.raw = raw
        self.chandler_period_span = period_span
        self.method = raw.method
        self.issued = mjd_time(MJD_J2000 + raw.issued / DAY)
        self.last_data = mjd_time(MJD_J2000 + raw.last_data / DAY)
        self.latency = (latency / DAY) << u.day
        self.lead = (raw.lead / DAY) << u.day
        x, y = raw.xy()
        self.x = (x / RAD_PER_MAS) << u.mas
        self.y = (y / RAD_PER_MAS) << u.mas
        self.sigma_x = (raw.sigma_x / RAD_PER_MAS) << u.mas
        self.sigma_y = (raw.sigma_y / RAD_PER_MAS) << u.mas
        self.chandler_period = raw.details["chandler_period_days"] << u.day
        self.calibration = raw.calibration
        self.q = q
        self.source = source
        #: True when no issue date was given: the record's end plus the latency, which lies in the past.
        self.issued_by_default = False

    def half_width(self, level: int) -> dict:
        """``{"x": ..., "y": ...}`` half-widths of the ``level`` % interval (68 or 95), mas."""
        hx, hy = self.raw.half_widths(level)
        return {"x": (hx / RAD_PER_MAS) << u.mas, "y": (hy / RAD_PER_MAS) << u.mas}

    @property
    def time_mjd(self) -> np.ndarray:
        """MJD (UTC) of each forecast value."""
        return MJD_J2000 + (self.raw.issued + self.raw.lead) / DAY

    def bounds(self, level: int) -> dict:
        """``{"x": (low, high), "y": (low, high)}`` of the ``level`` % interval (68 or 95), mas."""
        xl, xh, yl, yh = (v / RAD_PER_MAS for v in self.raw.bounds(level))
        return {"x": (xl << u.mas, xh << u.mas), "y": (yl << u.mas, yh << u.mas)}

    def to_dict(self) -> dict:
        """The JSON of ``wobble forecast --json``: issue, horizon, method, latency and one record per lead day."""
        b68, b95 = self.bounds(68), self.bounds(95)
        rows = []
        for k in range(len(self.lead)):
            rows.append(
                {
                    "lead_days": int(round(self.lead[k].value)),
                    "date": iso_date(float(self.time_mjd[k])),
                    "x_mas": float(self.x[k].value),
                    "y_mas": float(self.y[k].value),
                    "x_68_mas": [float(b68["x"][0][k].value), float(b68["x"][1][k].value)],
                    "y_68_mas": [float(b68["y"][0][k].value), float(b68["y"][1][k].value)],
                    "x_95_mas": [float(b95["x"][0][k].value), float(b95["x"][1][k].value)],
                    "y_95_mas": [float(b95["y"][0][k].value), float(b95["y"][1][k].value)],
                }
            )
        details = {k: v for k, v in self.raw.details.items() if k != "noise"}
        noise = self.raw.details.get("noise")
        if noise is not None:
            details["noise"] = {
                "excitation_mas": math.sqrt(noise.excitation) / RAD_PER_MAS,
                "correlation_time_days": noise.correlation_time / DAY,
                "excitation_order": noise.order,
                "excitation_partial_autocorrelations": [
                    math.exp(-DAY / noise.correlation_time),
                    *noise.partial_autocorrelations,
                ],
                "seasonal_mas": math.sqrt(noise.seasonal) / RAD_PER_MAS,
                "mean_pole_mas": math.sqrt(noise.mean_pole) / RAD_PER_MAS,
                "mean_pole_rate_mas_per_day": math.sqrt(noise.mean_pole_rate) / RAD_PER_MAS,
                "observation_mas": math.sqrt(noise.observation) / RAD_PER_MAS,
            }
        details.pop("q", None)  # the Kalman model's Q: the top-level quality_factor (FORECAST_RENAMES)
        out = {
            "issued": iso_date(self.issued),
            "horizon_days": len(self.lead),
            "method": self.method,
            "latency_days": float(self.latency.value),
            "last_data": iso_date(self.last_data),
            "chandler_period_days": float(self.chandler_period.value),
            "chandler_period_span": None if self.chandler_period_span is None else list(self.chandler_period_span),
            "quality_factor": self.q,
            "source_file": self.source,
            "intervals": calibration_text(self.calibration),
            "calibration": self._calibration_dict(),
            "details": details,
            "forecast": rows,
        }
        return deprecate(out, FORECAST_RENAMES)

    def _calibration_dict(self):
        cal = self.calibration
        if cal is None:
            return None
        return {
            "method": (
                "split-conformal quantiles of the method's own past errors over their stated sigma, per lead time"
            ),
            "span_days": cal.span / DAY,
            "step_days": cal.step / DAY,
            "past_forecasts_per_lead": int(cal.count[0]),
            "first_issue": iso_date(MJD_J2000 + cal.first_issue / DAY),
            "last_issue": iso_date(MJD_J2000 + cal.last_issue / DAY),
            "last_outcome": iso_date(MJD_J2000 + cal.last_outcome / DAY),
        }

    def to_dataset(self):
        """The forecast as a CF Dataset: lead time, forecast time and issue time, intervals as bounds variables."""
        from wobble.api.dataset import xarray
        from wobble.io import cf

        xr = xarray()
        b68, b95 = self.bounds(68), self.bounds(95)

        def pair(b, axis):
            return np.stack([b[axis][0].value, b[axis][1].value], axis=1)

        data = {
            "x_p": cf.variable("forecast", "x_p", self.x.value, ancillary_variables="x_p_bounds_68 x_p_bounds_95"),
            "y_p": cf.variable("forecast", "y_p", self.y.value, ancillary_variables="y_p_bounds_68 y_p_bounds_95"),
            "x_p_bounds_68": cf.variable("forecast", "x_p_bounds_68", pair(b68, "x")),
            "y_p_bounds_68": cf.variable("forecast", "y_p_bounds_68", pair(b68, "y")),
            "x_p_bounds_95": cf.variable("forecast", "x_p_bounds_95", pair(b95, "x")),
            "y_p_bounds_95": cf.variable("forecast", "y_p_bounds_95", pair(b95, "y")),
            "latency": cf.variable("forecast", "latency", float(self.latency.value)),
        }
        coords = {
            "lead_time": cf.variable("forecast", "lead_time", self.lead.value),
            "time": (
                ("lead",),
                self.time_mjd,
                {
                    "units": MJD_UNITS,
                    "calendar": "standard",
                    "standard_name": "time",
                    "long_name": "time the forecast is for (UTC)",
                    "axis": "T",
                },
            ),
            "forecast_reference_time": (
                (),
                float(MJD_J2000 + self.raw.issued / DAY),
                {
                    "units": MJD_UNITS,
                    "calendar": "standard",
                    "standard_name": "forecast_reference_time",
                    "long_name": "issue time of the forecast (UTC)",
                },
            ),
        }
        ds = xr.Dataset(data, coords=coords)
        cal = self._calibration_dict()
        ds.attrs = {
            "title": f"Polar-motion forecast ({self.method}) issued {iso_date(self.issued)}",
            "summary": "; ".join(line.strip() for line in self.summary().splitlines()[:2]),
            "references": _REFERENCES[self.method]
            + ("; interval calibration: " + _CALIBRATION_REFERENCES if cal else ""),
            "source_file": self.source,
            # The JSON's "method": a pipeline combining forecasts reads it here, not from the title.
            "forecast_method": self.method,
            "interval_calibration": "past_errors" if cal else "none",
            "intervals": calibration_text(self.calibration),
            "comment": (
                f"Data used up to {iso_date(self.last_data)} (latency {self.latency.value:g} d before the issue date). "
                "The pole is x_p toward Greenwich, y_p toward 90 deg W."
            ),
        }
        if cal:
            ds.attrs.update(
                calibration_span_days=cal["span_days"],
                calibration_step_days=cal["step_days"],
                calibration_past_forecasts_per_lead=cal["past_forecasts_per_lead"],
                calibration_first_issue=cal["first_issue"],
                calibration_last_issue=cal["last_issue"],
                calibration_last_outcome=cal["last_outcome"],
            )
        return ds

    def summary(self) -> str:
        """A few lines for a person: the forecast at a few lead times with its 68 % interval."""
        if self.chandler_period_span is None:
            source = "given"
        else:
            first, last = self.chandler_period_span
            years = (to_mjd(last, "last") - to_mjd(first, "first")) / (JULIAN_YEAR / DAY)
            source = f"least squares of the {years:.0f} years of record {first} to {last}"
        # The default issue date lies in the past: said, or a forecast "90 days ahead" that starts a month ago
        # reads as one from today.
        default = "; by default issued at the data's end plus the latency, not today" if self.issued_by_default else ""
        lines = [
            f"Polar-motion forecast ({self.method}) issued {iso_date(self.issued)}, data to {iso_date(self.last_data)} "
            f"(latency {self.latency.value:g} d{default})",
            f"  Chandler period {self.chandler_period.value:.1f} d ({source})",
            f"  {'lead [d]':>8}  {'date':>10}  {'x_p [mas]':>17}  {'y_p [mas]':>17}",
        ]
        n = len(self.lead)
        h = self.half_width(68)

        def pm(value, sigma) -> str:
            # The value to the decimal place of its +/-'s two significant digits, aligned on the +/-.
            number, _, plus = with_uncertainty(float(value), float(sigma)).partition(" +/- ")
            return f"{number:>8} +/- {plus:<4}"

        for k in sorted({0, 4, 9, 29, 89, 179, 364, n - 1}):
            if k < n:
                lines.append(
                    f"  {int(self.lead[k].value):8d}  {iso_date(float(self.time_mjd[k]))}  "
                    f"{pm(self.x[k].value, h['x'][k].value)}  {pm(self.y[k].value, h['y'][k].value)}".rstrip()
                )
        if self.calibration is None:
            lines.append("  (+/- one sigma of the model: the 68 % interval if its errors are Gaussian; not calibrated)")
        else:
            c = self._calibration_dict()
            lines.append(
                f"  (+/-: the 68 % interval, calibrated on {c['past_forecasts_per_lead']} past forecasts per lead "
                "time issued "
                f"{c['first_issue']} to {c['last_issue']})"
            )
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"PolarMotionForecast({self.method!r}, issued={iso_date(self.issued)}, horizon={len(self.lead)} d)"


_CALIBRATION_REFERENCES = (
    "split-conformal prediction (Vovk, Gammerman & Shafer 2005; Lei, G'Sell, Rinaldo et al. "
    "2018, J. Am. Stat. Assoc. 113, 1094)"
)

_REFERENCES = {
    "ls_ar": "Least squares + autoregression (Kosek et al. 1998; Kalarus, Schuh, Kosek et al. 2010, J. Geod. 84, 587)",
    "kalman": (
        "Damped Chandler oscillator (Liouville equation; Munk & MacDonald 1960; Gross 1992) driven by coloured "
        "excitation, "
        "Kalman filter with maximum-likelihood noise (Durbin & Koopman 2012)"
    ),
}


def forecast_polar_motion(
    data=None,
    *,
    file=None,
    issued=None,
    horizon: u.Quantity = 365 * u.day,
    method: str = "kalman",
    latency: u.Quantity | None = None,
    q: float | None = None,
    chandler_period: u.Quantity | None = None,
    calibrated: bool = True,
    calibration_span: u.Quantity | None = None,
    progress=None,
) -> PolarMotionForecast:
    """Forecast the pole from the record available at an issue date.

    Parameters
    ----------
    data : Dataset, path or None
        The record (as in :func:`wobble.chandler_wobble`; default: the shipped IERS 20 C04 series).
    file : path, optional
        A C04 or finals2000A file instead of ``data``.
    issued : date, optional
        Issue date, a day (0 h UTC; default: the last day of the record plus the latency, the day its
        last value became available).
    horizon : Quantity
        How far ahead, from 1 d to 3 years (default 365 d), in daily steps.
    method : str
        ``kalman`` (default) or ``ls_ar``.
    latency : Quantity, optional
        Publication delay of the record, a whole number of days from 0 d to 365 d (default: 30 d for
        C04, 1 d for finals2000A).
    q : float, optional
        Q of the Chandler wobble for the Kalman model, at least 1 or inf (default: wobble's Chandler
        budget, about 82; ``ls_ar`` has no Q).
    chandler_period : Quantity, optional
        The Chandler period (default: wobble's least-squares estimate from the 30 years before the
        issue date minus the latency; :attr:`PolarMotionForecast.chandler_period_span` says which days).
    calibrated : bool
        Calibrate the intervals on the method's past forecasts (default) or give the model's Gaussian ones.
    calibration_span : Quantity
        Span of past issue dates whose errors calibrate each lead time, a forecast a week (default: 6 yr for
        ``kalman``, 2 yr for ``ls_ar``; chosen on the 2006-2015 hindcast, ``docs/forecast.md``).
    progress : bool or callable, optional
        ``progress(message)`` is called at each stage: the Chandler period, the noise fit, the past
        forecasts of the calibration (True prints a line on stderr for each; the CLI shows them on a terminal).

    Returns
    -------
    PolarMotionForecast
    """
    method = _fc.check_method(method)
    horizon_days = check_horizon_days(horizon)
    q_value = default_q() if q is None else check_q(q)
    mjd, t, z, attrs = series_with_attrs(data, file)  # plain arrays from a file: no xarray for the JSON
    lat = latency_si(latency, attrs)
    issued_s = _issue_time(issued, mjd, t, lat, method, horizon_days, calibrated and calibration_span is None)
    span = calibration_span_si(calibration_span)
    what = _cal.METHOD_NAMES[method]
    # The issue date's own checks come first (information_set), so a too-early issue date is named as such.
    _fc.information_set(t, z, issued_s, lat, _cal.FITTING_SPAN[method], what)
    if calibrated:
        _cal.check_calibration_span(t, issued_s, lat, horizon_days, method, span)
    _check_gaps(mjd, issued_s, lat, horizon_days, method, calibrated, span)
    say = stage_messages(progress)
    period, period_span = _chandler_period(chandler_period, t, z, issued_s - lat, say)
    raw = _cal.forecast(
        t,
        z,
        issued_s,
        horizon_days,
        method=method,
        chandler_period=period,
        q=q_value,
        latency=lat,
        calibrated=calibrated,
        span=span,
        progress=say,
    )
    out = PolarMotionForecast(
        raw, lat, attrs.get("source_file", ""), q_value if method == "kalman" else None, period_span=period_span
    )
    out.issued_by_default = issued is None
    return out


def _check_gaps(mjd, issued_s: float, lat: float, horizon_days: int, method: str, calibrated: bool, span) -> None:
    """Days missing from what the forecast reads: its fitting span, and calibrated, its past forecasts' spans."""
    cutoff = MJD_J2000 + (issued_s - lat) / DAY
    need = _cal.FITTING_SPAN[method] / DAY
    check_daily(mjd, cutoff - need, cutoff, f"the {_cal.METHOD_NAMES[method]} fitting span")
    if calibrated:
        oldest = _cal.past_issue_times(issued_s, lat, horizon_days, _cal.span_for(method, span))[0]
        check_daily(
            mjd,
            MJD_J2000 + (oldest - lat) / DAY - need,
            cutoff,
            "the record the past forecasts that calibrate the intervals read (each with its fitting span)",
            "or the models' own Gaussian intervals, which read the fitting span only (--no-calibration; "
            "calibrated=False in Python)",
        )


def _issue_time(issued, mjd, t, lat: float, method: str, horizon_days: int, default_calibration: bool) -> float:
    """The issue time (s from J2000): the day the record's last value became available, or ``issued`` checked
    against the first day the method can be issued (its fitting span and the latency after the record's start;
    with the default calibration also the past forecasts that calibrate it) and the last (the record's end plus
    the latency)."""
    if issued is None:
        return t[-1] + lat
    issued_mjd = to_mjd(issued, "issued")
    if not whole_days(issued_mjd * DAY):
        raise InputError(
            "issued",
            f"{issued} ({mjd_time(issued_mjd).iso[:16]} UTC)",
            f"a day (0 h UTC), e.g. {iso_date(math.floor(issued_mjd))}: the record is daily",
        )
    what = _cal.METHOD_NAMES[method]
    first = math.ceil(mjd[0] + (_cal.FITTING_SPAN[method] + lat) / DAY - 1e-9)
    why = f"after the method's {_cal.FITTING_SPAN[method] / DAY:.0f}-day fitting span, plus the latency"
    if default_calibration:
        # The default calibration is not the user's choice: the date is, so give the first one that works.
        reach = _cal.calibration_reach(lat, horizon_days, _cal.SPANS[method])
        first = max(first, math.ceil(mjd[0] + (_cal.FITTING_SPAN[method] + lat + reach) / DAY - 0.5 - 1e-9))
        why += (
            f"; with calibrated intervals {horizon_days} d ahead, also the {reach / DAY:.0f} d of past "
            "forecasts that calibrate them, or choose uncalibrated intervals"
        )
    if not (first <= issued_mjd <= mjd[-1] + lat / DAY + 1e-9):
        raise InputError(
            "issued",
            issued,
            f"a date from {iso_date(first)} to {iso_date(mjd[-1] + lat / DAY)} for {what} (the record from "
            f"{iso_date(mjd[0])}, {why})",
        )
    return (issued_mjd - MJD_J2000) * DAY


def _chandler_period(chandler_period, t, z, last_data: float, say) -> tuple[float, tuple[str, str] | None]:
    """The Chandler period (s) and the first and last days it was measured from: the least-squares estimate
    from the 30 years of the record before ``last_data``, or the period given (no span)."""
    if chandler_period is not None:
        return float(to_si(chandler_period, "chandler_period", u.s, positive=True, shape=())), None
    say("Chandler period by least squares")
    period = chandler_period_before(t, z, last_data)
    used = t[(t <= last_data + 1e-6) & (t >= last_data - _PERIOD_SPAN)]
    return period, (iso_date(MJD_J2000 + used[0] / DAY), iso_date(MJD_J2000 + used[-1] / DAY))
