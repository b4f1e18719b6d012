"""Hindcasts: forecasts issued every week (or any step) over a span of the past, scored against the record.

Each forecast uses only what was available at its issue date (the record up
to the issue date minus the latency; the Chandler period and the Kalman noise
re-estimated every 13 issues from those data alone), and so does the
calibration of its intervals on the method's past forecasts, exactly as
:func:`wobble.forecast_polar_motion` calibrates a forecast. The issues are cut into
blocks of 13 that run in parallel: on a local process pool by default, or on
the dask scheduler given (``"threads"``, ``"processes"``, ``"synchronous"``, a
``tcp://`` address or a ``distributed.Client``), as the sweeps do.
"""

from __future__ import annotations

import concurrent.futures
import math
import multiprocessing
import os

import numpy as np
from astropy import units as u

from wobble.api.polar_motion.estimate import published_chandler_period
from wobble.api.polar_motion.forecast import (
    calibration_span_si,
    calibration_text,
    check_q,
    default_q,
    check_horizon_days,
    latency_si,
    whole_days,
)
from wobble.api.polar_motion.record import MJD_J2000, RAD_PER_MAS, check_daily, observed_mas, series_with_attrs
from wobble.api.units import to_si
from wobble.api._progress import ProgressBar
from wobble.api._scheduler import LOCAL, check_scheduler, connected, process_pool
from wobble.errors import InputError
from wobble.io.dates import MJD_UNITS, iso_date, to_mjd
from wobble.io.json_keys import deprecate
from wobble.models.polar_motion import forecast as _fc
from wobble.models.polar_motion import forecast_calibration as _cal
from wobble.models.polar_motion import hindcast as _hc
from wobble.models.polar_motion.record import DAY

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = ["PolarMotionHindcast", "hindcast_polar_motion", "ANCHORS"]

# The scores' JSON keys with their unit, as every other key (README, "Commands"); the old names are kept for one
# release under deprecated_keys. Skills are ratios and keep theirs.
_METRIC_KEYS = {
    **{m: f"{m}_mas" for m in ("rms_2d", "mae_2d", "rms_x", "rms_y", "mae_x", "mae_y")},
    "coverage_68": "coverage_68_fraction",
    "coverage_95": "coverage_95_fraction",
}


#: The scores of every method and lead, in the order of the hindcast's file (the JSON lists them in its own).
_SCORE_NAMES = (
    "mae_x",
    "mae_y",
    "rms_x",
    "rms_y",
    "mae_2d",
    "rms_2d",
    "coverage_68",
    "coverage_95",
    "skill_persistence",
    "skill_ls",
)


#: Published results to set beside ours: (label, metric, {lead days: mas}).
ANCHORS = (
    (
        "Dill et al. 2023, LS+AR with angular-momentum forecasts, 2016-2020",
        "rms_2d",
        {5: 1.13, 10: 2.32, 40: 10.05, 90: 19.13},
    ),
    ("Dill et al. 2023, x_p", "rms_x", {5: 0.93, 10: 1.92, 40: 8.65, 90: 15.76}),
    ("Dill et al. 2023, y_p", "rms_y", {5: 0.65, 10: 1.30, 40: 5.14, 90: 10.85}),
    (
        "Lei, Zhao & Guo 2023, weighted LS + vector AR, x_p",
        "mae_x",
        {10: 2.87, 30: 7.03, 150: 13.97, 270: 18.47, 365: 20.52},
    ),
    (
        "Lei, Zhao & Guo 2023, weighted LS + vector AR, y_p",
        "mae_y",
        {10: 1.81, 30: 4.41, 150: 15.41, 270: 21.17, 365: 21.82},
    ),
)


def _run_blocks(t, z, blocks, scheduler, workers, bar: ProgressBar):
    """Every block's forecasts, in order, computed in parallel; ``bar`` counts the issue dates done."""
    if scheduler is None:
        workers = min(workers or (os.cpu_count() or 1), len(blocks))
        if workers <= 1:
            out, done = [], 0
            for b in blocks:
                out.append(_hc.run_block(t, z, b))
                done += len(b.issues)
                bar(done)
            return out
        context = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn")
        with process_pool(workers, context) as pool:
            futures = {pool.submit(_hc.run_block, t, z, b): len(b.issues) for b in blocks}
            done = 0
            for f in concurrent.futures.as_completed(futures):
                done += futures[f]
                bar(done)
            return [f.result() for f in futures]
    if isinstance(scheduler, str) and scheduler in LOCAL:
        import dask

        tasks = [dask.delayed(_hc.run_block, pure=True)(t, z, b) for b in blocks]
        out = list(dask.compute(*tasks, scheduler=scheduler))
        bar(bar.total)
        return out
    from distributed import as_completed

    with connected(scheduler) as client:
        tt, zz = client.scatter(t, broadcast=True), client.scatter(z, broadcast=True)
        futures = [client.submit(_hc.run_block, tt, zz, b, pure=True) for b in blocks]
        size = {f.key: len(b.issues) for f, b in zip(futures, blocks)}
        done = 0
        for f in as_completed(futures):
            done += size[f.key]
            bar(done)
        return client.gather(futures)


class PolarMotionHindcast:
    """Forecasts issued over a past span and their scores (build with :func:`hindcast_polar_motion`).

    Attributes
    ----------
    methods : tuple of str
    issued_mjd : ndarray
        Issue dates, MJD (UTC).
    lead : Quantity
        Lead times, days.
    latency : Quantity
    scores : dict
        Per method, a :class:`wobble.models.polar_motion.hindcast.Scores` (rad; see :meth:`to_dataset` for mas).
    """

    def __init__(
        self,
        methods,
        forecasts,
        truth,
        persistence,
        ls_only,
        latency,
        q,
        source,
        calibrated=True,
        calibration_span=None,
    ):
        self.methods = tuple(methods)
        self.calibrated = bool(calibrated)
        # Each method's own span unless one was given for all (forecast_calibration.SPANS).
        self.calibration_spans = {m: (_cal.span_for(m, calibration_span) / DAY) << u.day for m in self.methods}
        self.forecasts = forecasts  # [issue][method] -> Forecast
        first = forecasts[0][0]
        self.issued_mjd = np.array([MJD_J2000 + row[0].issued / DAY for row in forecasts])
        self.lead = (first.lead / DAY) << u.day
        self.latency = (latency / DAY) << u.day
        self.q = q
        self.source = source
        self.truth = truth
        self.scores = {}
        for k, m in enumerate(self.methods):
            mean = np.array([row[k].mean for row in forecasts])
            half = {
                level: tuple(np.array(v) for v in zip(*(row[k].half_widths(level) for row in forecasts)))
                for level in (68, 95)
            }
            self.scores[m] = _hc.score(truth, mean, half[68], half[95], persistence, ls_only)

    def at(self, metric: str, method: str, leads=(5, 10, 40, 90, 365)) -> dict:
        """``{lead days: value}`` of a score (mas for errors, fractions otherwise) at the given lead times."""
        values = getattr(self.scores[method], metric)
        scale = 1.0 if metric.startswith(("coverage", "skill")) else 1.0 / RAD_PER_MAS
        return {int(d): float(values[d - 1] * scale) for d in leads if d <= len(self.lead)}

    def to_dict(self) -> dict:
        """Scores at 5, 10, 40, 90 and 365 days (and every lead's 2-D RMS), with the published anchors."""
        leads = (1, 5, 10, 30, 40, 90, 150, 270, 365)
        out = {
            "issued_first": iso_date(float(self.issued_mjd[0])),
            "issued_last": iso_date(float(self.issued_mjd[-1])),
            "issues": len(self.issued_mjd),
            "horizon_days": len(self.lead),
            "latency_days": float(self.latency.value),
            "quality_factor": self.q if "kalman" in self.methods else None,  # LS+AR has no Q
            "source_file": self.source,
            "intervals": self._intervals_text(),
            "calibration_span_days": (
                {m: float(v.value) for m, v in self.calibration_spans.items()} if self.calibrated else None
            ),
            "methods": {},
            # metric is the score's old name (an alias below, gone next release); metric_key the key that holds
            # the score under methods, to join an anchor with it.
            "anchors": [
                {
                    "label": a,
                    "metric": m,
                    "metric_key": _METRIC_KEYS.get(m, m),
                    "values_mas": {str(k): v for k, v in vals.items()},
                }
                for a, m, vals in ANCHORS
            ],
        }
        for m in self.methods:
            out["methods"][m] = {
                _METRIC_KEYS.get(metric, metric): {str(k): v for k, v in self.at(metric, m, leads).items()}
                for metric in (
                    "rms_2d",
                    "mae_2d",
                    "rms_x",
                    "rms_y",
                    "mae_x",
                    "mae_y",
                    "coverage_68",
                    "coverage_95",
                    "skill_persistence",
                    "skill_ls",
                )
            }
        return deprecate(out, {f"methods.*.{old}": f"methods.*.{new}" for old, new in _METRIC_KEYS.items()})

    def _spans_text(self) -> str:
        """``6 yr`` when every method has that span, else ``6 yr (kalman) or 2 yr (ls_ar)``."""
        years = {m: f"{v.to_value(u.yr):g} yr" for m, v in self.calibration_spans.items()}
        if len(set(years.values())) == 1:
            return next(iter(years.values()))
        return " or ".join(f"{y} ({m})" for m, y in years.items())

    def _intervals_text(self) -> str:
        if not self.calibrated:
            return calibration_text(None)
        return (
            "each forecast's intervals calibrated on the same method's past forecasts issued weekly over the "
            f"{self._spans_text()} "
            "before it with outcomes known at its issue date minus the latency (split-conformal quantiles of their "
            "errors "
            "over their stated sigma, per lead time and component; Vovk, Gammerman & Shafer 2005; Lei et al. 2018)"
        )

    def to_dataset(self):
        """The hindcasts, the outcomes and the scores as a CF Dataset (dimensions method, issue, lead)."""
        from wobble.api.dataset import xarray

        xr = xarray()
        ds = xr.Dataset({**self._forecast_variables(), **self._score_variables()}, coords=self._coordinates())
        ds.attrs = self._attributes()
        return ds

    def _forecast_variables(self) -> dict:
        """Every forecast (method, issue, lead) with its sigma and interval half-widths, and the outcomes, in mas."""
        from wobble.io import cf

        mas = 1.0 / RAD_PER_MAS

        def per_forecast(value):  # (issue, method, lead) as stored -> (method, issue, lead), in mas
            return np.array([[value(f) for f in row] for row in self.forecasts]).transpose(1, 0, 2) * mas

        data = {
            "x_p_forecast": per_forecast(lambda f: f.xy()[0]),
            "y_p_forecast": per_forecast(lambda f: f.xy()[1]),
            "x_p_sigma": per_forecast(lambda f: f.sigma_x),
            "y_p_sigma": per_forecast(lambda f: f.sigma_y),
        }
        for level in (68, 95):
            data[f"x_p_half_width_{level}"] = per_forecast(lambda f: f.half_widths(level)[0])
            data[f"y_p_half_width_{level}"] = per_forecast(lambda f: f.half_widths(level)[1])
        data["x_p_observed"] = observed_mas(self.truth.real)
        data["y_p_observed"] = observed_mas(-self.truth.imag)
        data["latency"] = float(self.latency.value)
        return {name: cf.variable("forecast", name, value) for name, value in data.items()}

    def _score_variables(self) -> dict:
        """The scores per method and lead (mas; coverages and skills as fractions), and the two references'."""
        from wobble.io import cf

        mas = 1.0 / RAD_PER_MAS
        first = self.scores[self.methods[0]]
        data = {
            "rms_2d_persistence": cf.variable("forecast", "rms_2d_persistence", first.rms_2d_persistence * mas),
            "rms_2d_ls": cf.variable("forecast", "rms_2d_ls", first.rms_2d_ls * mas),
        }
        for name in _SCORE_NAMES:
            scale = 1.0 if name.startswith(("coverage", "skill")) else mas
            data[name] = cf.variable(
                "forecast", name, np.array([getattr(self.scores[m], name) for m in self.methods]) * scale
            )
        return data

    def _coordinates(self) -> dict:
        """method, issue_time, lead_time and the valid time of every forecast."""
        from wobble.io import cf

        return {
            "method": (
                "method",
                list(self.methods),
                {"long_name": "forecast method (ls_ar: least squares + autoregression; kalman: state-space model)"},
            ),
            "issue_time": (("issue",), self.issued_mjd, cf.attrs("forecast", "issue_time", calendar="standard")),
            "lead_time": cf.variable("forecast", "lead_time", self.lead.value),
            # The valid time of every forecast, as the forecast file's "time": a pipeline had to add the
            # issue and lead times itself, and cf_xarray found no time axis (ds.cf["T"]).
            "time": (
                ("issue", "lead"),
                self.issued_mjd[:, None] + np.asarray(self.lead.to_value(u.day), dtype=float)[None, :],
                {
                    "units": MJD_UNITS,
                    "calendar": "standard",
                    "standard_name": "time",
                    "long_name": "time the forecast is for: issue time plus lead time (UTC)",
                },
            ),
        }

    def _attributes(self) -> dict:
        """The file's global attributes: what was hindcast, how the intervals were made, the calibration spans."""
        attrs = {
            "title": f"Polar-motion hindcast {iso_date(float(self.issued_mjd[0]))} to "
            f"{iso_date(float(self.issued_mjd[-1]))}",
            "summary": f"{len(self.issued_mjd)} issues x {len(self.lead)} lead days, methods "
            f"{', '.join(self.methods)}, latency {self.latency.value:g} d",
            "references": "; ".join(a for a, _, _ in ANCHORS[:1] + ANCHORS[3:4])
            + "; IERS EOP 20 C04 series (Paris Observatory)",
            "source_file": self.source,
            "interval_calibration": "past_errors" if self.calibrated else "none",
            "intervals": self._intervals_text(),
            "comment": (
                "Each forecast uses the record up to its issue time minus the latency; the Chandler period and the "
                "state-space "
                "noise are re-estimated every 13 issues from those data. Coverage counts outcomes inside the intervals "
                "(x_p_half_width_68 ...), pooling x_p and y_p."
            ),
        }
        if self.calibrated:
            for m, v in self.calibration_spans.items():
                attrs[f"calibration_span_days_{m}"] = float(v.value)
        return attrs

    def __repr__(self) -> str:
        first, last = iso_date(float(self.issued_mjd[0])), iso_date(float(self.issued_mjd[-1]))
        return (
            f"PolarMotionHindcast({', '.join(self.methods)}, {self.issued_mjd.size} issues {first} to {last}, "
            f"latency={self.latency.value:g} d)"
        )

    def summary(self) -> str:
        """The 2-D RMS, x_p mean absolute error and coverage at a few lead times, beside the published anchors."""
        leads = tuple(d for d in (5, 10, 40, 90, 365) if d <= len(self.lead)) or (len(self.lead),)
        lines = [
            f"Hindcast {iso_date(float(self.issued_mjd[0]))} to {iso_date(float(self.issued_mjd[-1]))}: "
            f"{len(self.issued_mjd)} issue{'' if len(self.issued_mjd) == 1 else 's'}, "
            f"latency {self.latency.value:g} d; intervals "
            + ("calibrated on past forecasts" if self.calibrated else "of the models (not calibrated)"),
            f"  {'':<34}" + "".join(f"{d:>8} d" for d in leads),
        ]
        for m in self.methods:
            # Coverage in per cent, as the documentation's tables give it (the JSON keeps fractions).
            for metric, label, scale, fmt in (
                ("rms_2d", "2-D RMS [mas]", 1.0, ".2f"),
                ("mae_x", "x_p MAE [mas]", 1.0, ".2f"),
                ("coverage_68", "68 % interval coverage [%]", 100.0, ".1f"),
                ("coverage_95", "95 % interval coverage [%]", 100.0, ".1f"),
                ("skill_persistence", "skill vs persistence", 1.0, ".2f"),
            ):
                vals = self.at(metric, m, leads)
                lines.append(
                    f"  {m + ' ' + label:<34}" + "".join(f"{scale * vals.get(d, math.nan):>10{fmt}}" for d in leads)
                )
        lines.append(
            f"  {'LS extrapolation 2-D RMS [mas]':<34}"
            + "".join(f"{self.scores[self.methods[0]].rms_2d_ls[d - 1] / RAD_PER_MAS:>10.2f}" for d in leads)
        )
        lines.append(
            f"  {'persistence 2-D RMS [mas]':<34}"
            + "".join(f"{self.scores[self.methods[0]].rms_2d_persistence[d - 1] / RAD_PER_MAS:>10.2f}" for d in leads)
        )
        # The anchor is 2016-2020 and used angular-momentum forecasts: say so, whatever span was scored.
        _, _, vals = ANCHORS[0]
        lines.append(
            f"  {'Dill et al. 2023 2-D RMS [mas]':<34}"
            + "".join(f"{vals[d]:>10.2f}" if d in vals else f"{'-':>10}" for d in leads)
            + "   (2016-2020, with angular-momentum forecasts)"
        )
        return "\n".join(lines)


def hindcast_polar_motion(
    data=None,
    *,
    file=None,
    start="2016-01-01",
    end="2021-01-01",
    every: u.Quantity = 7 * u.day,
    horizon: u.Quantity = 365 * u.day,
    methods=("ls_ar", "kalman"),
    latency: u.Quantity | None = None,
    q: float | None = None,
    scheduler=None,
    workers: int | None = None,
    calibrated: bool = True,
    calibration_span: u.Quantity | None = None,
    progress: bool = False,
) -> PolarMotionHindcast:
    """Forecasts issued every ``every`` from ``start`` up to (not including) ``end``, scored against the record.

    Parameters
    ----------
    data, file, latency, q
        As in :func:`wobble.forecast_polar_motion`.
    start, end : date
        The span of issue dates (UTC); every forecast's outcome must be in the record.
    every : Quantity
        Spacing of the issue dates, a whole number of days (default 7 d).
    horizon : Quantity
        Lead times 1 .. horizon days (default 365 d).
    methods : sequence of str
        ``ls_ar`` and/or ``kalman``; the LS+AR's least-squares extrapolation is the skill reference.
    scheduler : str or distributed.Client, optional
        A dask scheduler; default: a local process pool of ``workers`` (default: the CPU count).
    calibrated, calibration_span
        As in :func:`wobble.forecast_polar_motion`: each forecast's intervals calibrated on the
        method's past forecasts (issued before it, outcomes known at its issue date minus the latency).
    progress : bool
        A progress bar on stderr, counting issue dates as their blocks finish (the command line shows it
        on a terminal).
    """
    methods = tuple(_fc.check_method(m) for m in methods)
    if not methods:
        raise InputError("methods", methods, "one or more of 'ls_ar', 'kalman'")
    check_scheduler(scheduler)
    horizon_days = check_horizon_days(horizon)
    step = float(to_si(every, "every", u.s, finite=False, shape=()))
    if not (math.isfinite(step) and step >= DAY - 1e-6 and whole_days(step)):
        raise InputError("every", every, "a whole number of days, at least 1 d (the record is daily)")
    q_value = default_q() if q is None else check_q(q)
    span = calibration_span_si(calibration_span)
    mjd, t, z, attrs = series_with_attrs(data, file)
    lat = latency_si(latency, attrs)
    a, b = to_mjd(start, "start"), to_mjd(end, "end")
    for name, value, day in (("start", start, a), ("end", end, b)):
        if not whole_days(day * DAY):
            raise InputError(
                name,
                value,
                f"a day (0 h UTC), e.g. {iso_date(math.floor(day))}: forecasts are issued on the days of the record",
            )
    if b <= a:
        raise InputError("end", end, f"a date after start ({iso_date(a)})")
    issues = _issue_times(mjd, t, a, b, step, start, end, methods, lat, horizon_days, calibrated, span)
    reference = published_chandler_period()["period"].to_value(u.s)
    blocks = _hc.blocks(
        issues,
        horizon_days,
        ("ls_ar",) + tuple(m for m in methods if m != "ls_ar"),
        lat,
        q_value,
        reference,
        calibrated=methods if calibrated else (),
        calibration_span=span,
    )
    bar = ProgressBar(sum(len(b.issues) for b in blocks), "issue dates", progress)
    try:
        rows = [row for block in _run_blocks(t, z, blocks, scheduler, workers, bar) for row in block]
    finally:
        bar.close()
    order = ["ls_ar"] + [m for m in methods if m != "ls_ar"]
    lead = DAY * np.arange(1, horizon_days + 1)
    truth = np.array([_hc.truth_at(t, z, row[0].issued + lead) for row in rows])
    persistence = np.array([_hc.truth_at(t, z, np.array([row[0].last_data]))[0] for row in rows])
    ls_only = np.array([row[0].baseline for row in rows])
    keep = [order.index(m) for m in methods]
    forecasts = [[row[k] for k in keep] for row in rows]
    return PolarMotionHindcast(
        methods, forecasts, truth, persistence, ls_only, lat, q_value, attrs.get("source_file", ""), calibrated, span
    )


def _issue_times(mjd, t, a, b, step, start, end, methods, lat, horizon_days, calibrated, span) -> np.ndarray:
    """The issue dates (s from J2000), checked against the record: each method's fitting span (and, calibrated,
    its past forecasts) before the first, the last forecast's horizon within the record."""
    issues = (a - MJD_J2000) * DAY + step * np.arange(math.ceil((b - a) * DAY / step - 1e-9))
    need = max(_cal.FITTING_SPAN[m] for m in set(methods) | {"ls_ar"})
    if issues[0] - lat - t[0] < need - 0.5 * DAY:
        raise InputError(
            "start",
            start,
            f"an issue date at least {need / JULIAN_YEAR:.0f} yr (the fitting span) plus the latency after the "
            f"record's start ({iso_date(mjd[0])})",
        )
    if calibrated:
        # Each method's past forecasts reach back its own calibration span, then need its own fitting span.
        first_ok, m = max(
            (t[0] + _cal.FITTING_SPAN[m] + lat + _cal.calibration_reach(lat, horizon_days, _cal.span_for(m, span)), m)
            for m in methods
        )
        if issues[0] < first_ok - 0.5 * DAY:
            raise InputError(
                "start",
                start,
                f"an issue date on or after {iso_date(MJD_J2000 + first_ok / DAY)}: the calibration's past forecasts "
                f"({_cal.span_for(m, span) / JULIAN_YEAR:g} yr of them, then the horizon) need their "
                f"{_cal.FITTING_SPAN[m] / JULIAN_YEAR:.0f}-yr {m} fitting span in the record",
            )
    last_needed = issues[-1] + horizon_days * DAY
    if last_needed > t[-1] + 1e-6:
        raise InputError(
            "end",
            end,
            f"an end whose forecasts end within the record: the last issue plus {horizon_days} d must be on or "
            f"before {iso_date(mjd[-1])}",
        )
    # Every day read: the first issue's fitting span (calibrated, its past forecasts' too) to the last outcome.
    first = min(
        issues[0]
        - lat
        - _cal.FITTING_SPAN[m]
        - (_cal.calibration_reach(lat, horizon_days, _cal.span_for(m, span)) if calibrated else 0.0)
        for m in methods
    )
    check_daily(
        mjd,
        MJD_J2000 + first / DAY,
        MJD_J2000 + last_needed / DAY,
        "the record the hindcast reads (fitting spans"
        + (", the calibration's past forecasts" if calibrated else "")
        + " and outcomes)",
        "or uncalibrated intervals, which read less (--no-calibration; calibrated=False in Python)"
        if calibrated
        else "",
    )
    return issues
