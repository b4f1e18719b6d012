"""``wobble forecast``: polar-motion forecasts with 68 % and 95 % intervals, and hindcasts scored against the record."""

from __future__ import annotations

import argparse

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

Methods: kalman (default), a damped Chandler oscillator driven by coloured excitation
with seasonal terms and a mean-pole drift, filtered with maximum-likelihood noise
(Liouville equation: Munk & MacDonald 1960; Gross 1992; Kalman filter: Durbin & Koopman
2012); ls_ar, least squares of trend, Chandler, annual and semi-annual terms plus an
autoregressive model of the residuals (Kosek et al. 1998; Kalarus et al. 2010). Both use
the Chandler period wobble measures before the issue date. A forecast uses the record up
to the issue date minus its publication delay (--latency; default 30 d for C04, 1 d for
finals2000A). The 68 % and 95 % intervals are calibrated on the method's own past
forecasts: the same method issued every week over the --calibration-span (default 2yr)
before, each from its own data; per lead time, the split-conformal quantile of the
errors (over their stated sigma) whose outcomes were known at the issue date minus the
latency (Vovk, Gammerman & Shafer 2005). --no-calibration gives the models' Gaussian
+/- sigma instead.
--hindcast START:END issues forecasts every --every over the span and scores them
(MAE and RMS per component and for the 2-D pole, interval coverage, skill against
persistence and the least-squares extrapolation) beside Dill et al. (2023); the
2016-2020 weekly hindcast of the documentation is --hindcast 2016-01-01:2021-01-01
--every 7d --latency 1d (about a minute of CPU on two cores).
"""


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
    p.add_argument("--issued", metavar="DATE", help="issue date (default: the record's last day plus the latency)")
    p.add_argument(
        "--horizon",
        metavar="T",
        default="365d",
        help="how far ahead, e.g. 365d or 90 (days; default 365d, at most 3 years)",
    )
    p.add_argument("--method", help="kalman (default) or ls_ar; with --hindcast: both (default), kalman or ls_ar")
    add_file(p)
    p.add_argument(
        "--latency",
        metavar="T",
        help="publication delay of the record, e.g. 1d (default: 30 d for C04, 1 d for finals2000A)",
    )
    p.add_argument(
        "--q",
        metavar="Q",
        help="quality factor of the Chandler wobble, Q > 0 (default: wobble's Chandler budget, about 82)",
    )
    p.add_argument(
        "--calibration-span",
        metavar="T",
        help="span of past issue dates whose errors calibrate the intervals (default: 2yr)",
    )
    p.add_argument(
        "--no-calibration", action="store_true", help="the models' Gaussian intervals, not calibrated on past forecasts"
    )
    p.add_argument("--hindcast", metavar="START:END", help="issue forecasts over this span of dates and score them")
    p.add_argument("--every", metavar="T", default="7d", help="spacing of the hindcast's issue dates (default: 7d)")
    p.add_argument(
        "--scheduler",
        help="hindcast on a dask scheduler: threads, processes, synchronous or an address (default: a local "
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
    from wobble.cli.excitation import parse_days, parse_q

    horizon = parse_days(args.horizon, "--horizon")
    latency = parse_days(args.latency, "--latency")
    q = parse_q(args.q)
    span = parse_days(args.calibration_span, "--calibration-span")
    hindcast = args.hindcast is not None
    methods = _methods(args.method, hindcast)
    check_outputs(args)
    if hindcast:
        from wobble.api.polar_motion.hindcast import hindcast_polar_motion

        if args.hindcast.count(":") != 1:
            raise InputError("--hindcast", args.hindcast, "START:END, e.g. 2016-01-01:2021-01-01")
        start, end = args.hindcast.split(":")
        result = hindcast_polar_motion(
            args.file,
            start=start,
            end=end,
            every=parse_days(args.every, "--every"),
            horizon=horizon,
            methods=methods,
            latency=latency,
            q=q,
            scheduler=args.scheduler,
            calibrated=not args.no_calibration,
            calibration_span=span,
        )
    else:
        from wobble.api.polar_motion.forecast import forecast_polar_motion

        if args.issued is not None and ":" in args.issued:
            raise InputError("--issued", args.issued, "one date (a span of issue dates goes with --hindcast)")
        result = forecast_polar_motion(
            args.file,
            issued=args.issued,
            horizon=horizon,
            method=methods[0],
            latency=latency,
            q=q,
            calibrated=not args.no_calibration,
            calibration_span=span,
        )
    figure = "save_hindcast_figure" if hindcast else "save_forecast_figure"
    return report(args, result, f"wobble.plot.forecast:{figure}")
