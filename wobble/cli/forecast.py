"""``wobble forecast``: polar-motion forecasts with 68 % and 95 % intervals, and hindcasts scored against the record."""

from __future__ import annotations

import argparse
import re
import sys

from wobble.cli._record import add_file, add_outputs, report
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble forecast                                   a year ahead from the end of the shipped C04 record
  wobble forecast --issued 2019-01-01 --horizon 90d --method ls_ar --json
  wobble forecast --issued 2020-06-01 -o forecast.nc --plot forecast.png --overwrite
  wobble forecast --file finals2000A.all --horizon 30d
  wobble forecast --issued 2019-01-01 --horizon 90d --calibration-span 3yr
  wobble forecast --hindcast 2019-01-01:2019-07-01 --every 14d --horizon 90d --latency 1d -o hindcast.nc --overwrite

Methods: kalman (default), a damped Chandler oscillator driven by coloured (third-order
autoregressive) excitation with seasonal terms and a mean-pole drift, filtered with
maximum-likelihood noise (Liouville equation: Munk & MacDonald 1960; Gross 1992; Kalman
filter: Durbin & Koopman 2012); ls_ar, least squares of trend, Chandler, annual and
semi-annual terms plus an autoregressive model of the residuals (Kosek et al. 1998;
Kalarus et al. 2010). Both use the Chandler period wobble measures by least squares in
the 30 years of record before the issue date minus the latency (the output names that
span; 'wobble polar-motion' measures the whole record). A forecast uses the record up to
the issue date minus its publication delay (--latency; default 30 d for C04, 1 d for
finals2000A). The 68 % and 95 % intervals are calibrated on the method's own past
forecasts: the same method issued every week over the --calibration-span before (default
6yr for kalman, 2yr for ls_ar, chosen on a 2006-2015 hindcast), each from its own data;
per lead time, the split-conformal quantile of the errors (over their stated sigma)
whose outcomes were known at the issue date minus the latency (Vovk, Gammerman & Shafer
2005). --no-calibration gives the models' Gaussian +/- sigma instead. Each value is
shown to the decimal place of its +/- (two significant digits). --hindcast START:END
issues forecasts every --every over the span and scores them (MAE and RMS per component
and for the 2-D pole, interval coverage, skill against persistence and the least-squares
extrapolation) beside Dill et al. (2023); the 2016-2020 weekly hindcast of the
documentation is --hindcast 2016-01-01:2021-01-01 --every 7d --latency 1d (20 to 40 s on
two cores). A bare number (no unit) in --horizon, --latency, --calibration-span and
--every is days; dates are days (0 h UTC) of the daily record. """


def register(sub) -> None:
    p = sub.add_parser(
        "forecast",
        help="forecast the pole with 68 %% and 95 %% intervals (Kalman or LS+AR), or score a hindcast",
        description="Polar-motion forecasts from the IERS record available at an issue date, by a damped-oscillator "
        "state-space model (Kalman) or least squares + autoregression, with 68 % and 95 % intervals; or a hindcast: "
        "forecasts issued over a past span, scored against what followed.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--issued", metavar="DATE", help="issue date, a day (default: the record's last day plus the latency)"
    )
    p.add_argument(
        "--horizon",
        metavar="T",
        help="how far ahead, a whole number of days from 1 d to 1096 d (three years), e.g. 365d, 90 or 2wk "
        "(a bare number is days; a year is 365.25 d, so 1yr is refused: 365d or 366d; default 365d)",
    )
    p.add_argument("--method", help="kalman (default) or ls_ar; with --hindcast: both (default), kalman or ls_ar")
    add_file(p)
    p.add_argument(
        "--latency",
        metavar="T",
        help="publication delay of the record, whole days from 0 to 365, e.g. 1d or 1 (a bare number is days; "
        "default: 30 d for C04, 1 d for finals2000A)",
    )
    p.add_argument(
        "--q",
        metavar="Q",
        help="quality factor of the Chandler wobble in the kalman model, Q >= 1 or inf (default: wobble's "
        "Chandler budget, about 82)",
    )
    p.add_argument(
        "--calibration-span",
        metavar="T",
        help="span of past issue dates whose errors calibrate the intervals, from 26 weeks (182 d) to 30 yr, "
        "e.g. 3yr or 400 (a bare number is days; default: 6yr for kalman, 2yr for ls_ar)",
    )
    p.add_argument(
        "--no-calibration", action="store_true", help="the models' Gaussian intervals, not calibrated on past forecasts"
    )
    p.add_argument("--hindcast", metavar="START:END", help="issue forecasts over this span of dates and score them")
    p.add_argument(
        "--every",
        metavar="T",
        help="with --hindcast: spacing of its issue dates, whole days, e.g. 14d or 14 (a bare number is days; "
        "default: 7d)",
    )
    p.add_argument(
        "--scheduler",
        help="with --hindcast: a dask scheduler, threads, processes, synchronous or an address (default: a local "
        "process pool)",
    )
    add_outputs(
        p,
        json_help="print the forecast (or the hindcast's scores) as JSON",
        output_help="write the forecast or hindcast (CF-1.10 netCDF)",
        plot_help="write a figure (forecast with intervals; or error against lead time)",
    )
    p.set_defaults(func=run)


def _methods(text, hindcast: bool):
    if text is None:
        return ("ls_ar", "kalman") if hindcast else ("kalman",)
    if hindcast and text == "both":
        return ("ls_ar", "kalman")
    if text not in ("kalman", "ls_ar"):
        raise InputError("--method", text, "kalman or ls_ar" + (" (or both)" if hindcast else ""))
    return (text,)


def run(args) -> int:
    from wobble.cli._output import check_outputs
    from wobble.cli._record import as_typed, check_file, parse_q, parse_time

    hindcast = args.hindcast is not None
    for option, value in (("--every", args.every), ("--scheduler", args.scheduler)):
        if value is not None and not hindcast:
            raise InputError(option, value, "only with --hindcast START:END (a forecast is issued once)")
    if args.no_calibration and args.calibration_span is not None:
        raise InputError(
            "--calibration-span", args.calibration_span, "no span with --no-calibration (it calibrates nothing)"
        )
    if hindcast and args.issued is not None:
        raise InputError("--issued", args.issued, "no --issued with --hindcast (its START:END are the issue dates)")
    horizon = parse_time(args.horizon, "--horizon", "d", default="365d")
    latency = parse_time(args.latency, "--latency", "d")
    q = parse_q(args.q)
    span = parse_time(args.calibration_span, "--calibration-span", "d")  # None: each method's own
    every = parse_time(args.every, "--every", "d", default="7d")
    methods = _methods(args.method, hindcast)
    if q is not None and "kalman" not in methods:
        raise InputError("--q", args.q, "no --q with --method ls_ar (Q damps the kalman model's oscillator)")
    check_outputs(args)
    check_file(args)
    options = {
        "horizon": ("--horizon", horizon.shown),
        "latency": ("--latency", latency and latency.shown),
        "calibration_span": ("--calibration-span", span and span.shown),
        "every": ("--every", every.shown),
        "methods": ("--method", None),
        "start": ("--hindcast START", None),
        "end": ("--hindcast END", None),
    }
    # The API's defaults are the help's; None keeps "not given" (the latency: the record's own).
    calibration_span = span and span.quantity
    if hindcast:
        from wobble.api.polar_motion.hindcast import hindcast_polar_motion

        if args.hindcast.count(":") != 1:
            raise InputError("--hindcast", args.hindcast, "START:END, e.g. 2016-01-01:2021-01-01")
        start, end = args.hindcast.split(":")
        with as_typed(options):
            result = hindcast_polar_motion(
                args.file,
                start=start,
                end=end,
                every=every.quantity,
                horizon=horizon.quantity,
                methods=methods,
                latency=latency and latency.quantity,
                q=q,
                scheduler=args.scheduler,
                calibrated=not args.no_calibration,
                calibration_span=calibration_span,
                progress=sys.stderr.isatty(),
            )
    else:
        from wobble.api.polar_motion.forecast import forecast_polar_motion

        if args.issued is not None and re.match(r"\s*\d{4}[-.\d]*\s*:\s*\d{4}", args.issued):
            raise InputError("--issued", args.issued, "one date (a span of issue dates goes with --hindcast)")
        from wobble.cli._stages import Stages

        with Stages() as stages, as_typed(options):
            result = forecast_polar_motion(
                args.file,
                issued=args.issued,
                horizon=horizon.quantity,
                method=methods[0],
                latency=latency and latency.quantity,
                q=q,
                calibrated=not args.no_calibration,
                calibration_span=calibration_span,
                progress=stages,
            )
    figure = "save_hindcast_figure" if hindcast else "save_forecast_figure"
    return report(args, result, f"wobble.plot.forecast:{figure}")
