"""Calibrate the Bayesian inversion and time it; write docs/performance-inversion.md.

Usage::

    python scripts/calibrate_inversion.py                 # full: 200 injections per setup
    python scripts/calibrate_inversion.py --draws 400 --scheduler processes
    python scripts/calibrate_inversion.py --quick         # a 10-draw smoke run (report not for docs)

Two parts:

1. **The shipped setups at their default settings** (``wobble invert mars``, ``earth``,
   ``mars_chandler_only``): posterior medians and intervals, the largest R-hat, the
   smallest ESS, wall-clock time and time per effective sample; and the same setups
   prior-only, to show what the data add (the ratio of the 68 % widths).
2. **Injection–recovery** (simulation-based calibration; Cook, Gelman & Rubin 2006;
   Talts et al. 2018) for ``mars`` and ``earth``: truths drawn from the priors,
   measurements simulated with the setups' uncertainties, each inverted with the
   calibration settings below; the coverage of the central 68 % and 95 % intervals
   with its binomial standard error, and the SBC rank histogram with a chi-square
   test of uniformity.

Timings depend on the machine and its load; the report records both.
"""

from __future__ import annotations

import argparse
import datetime as dt
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
REPORT = ROOT / "docs" / "performance-inversion.md"
SETUPS = ("mars", "mars_chandler_only", "earth")
CALIBRATED = ("mars", "earth")
# Shorter chains than the defaults for each injection: an ESS near 1000 is plenty for
# the 2.5 and 97.5 % quantiles, and the check is of the intervals, not of their digits.
CAL_SETTINGS = dict(walkers=32, steps=1000, burn=500)


def _fmt(x, digits=4):
    if x is None or not math.isfinite(x):
        return "-"
    return f"{x:.{digits}g}"


def default_runs(lines: list[str], quick: bool):
    import wobble

    lines += ["## The shipped setups at their default settings", "",
              "| setup | parameter | median | 68 % interval | 95 % interval | R-hat | ESS (min of bulk, tail) | prior 68 % width / posterior 68 % width |",
              "|---|---|---|---|---|---|---|---|"]
    timing = []
    extra = dict(steps=300, burn=200) if quick else {}
    for name in SETUPS:
        t0 = time.perf_counter()
        result = wobble.invert(name, **extra)
        wall = time.perf_counter() - t0
        prior = wobble.invert(name, prior_only=True, **extra)
        prior_rows = {r.name: r for r in prior.rows()}
        for r in result.rows():
            p = prior_rows[r.name]
            ratio = (p.upper_68 - p.lower_68) / (r.upper_68 - r.lower_68)
            unit = f" {r.unit}" if r.unit else ""
            lines.append(
                f"| {name} | {r.name} | {_fmt(r.median, 5)}{unit} | [{_fmt(r.lower_68, 5)}, {_fmt(r.upper_68, 5)}] | "
                f"[{_fmt(r.lower_95, 5)}, {_fmt(r.upper_95, 5)}] | {r.r_hat:.4f} | {min(r.ess, r.ess_tail):.0f} | {ratio:.2f} |"
            )
        for q in result.quantity_rows():
            if not q["measured"]:
                unit = f" {q['unit']}" if q["unit"] else ""
                lines.append(
                    f"| {name} | {q['name']} (derived) | {_fmt(q['median'], 4)}{unit} | [{_fmt(q['lower_68'], 4)}, {_fmt(q['upper_68'], 4)}] | "
                    f"[{_fmt(q['lower_95'], 4)}, {_fmt(q['upper_95'], 4)}] | - | - | "
                    f"{(q['prior_upper_68'] - q['prior_lower_68']) / (q['upper_68'] - q['lower_68']):.2f} |"
                )
        d = result.to_dict()["diagnostics"]
        timing.append((name, result, wall, d))
        print(f"{name}: {wall:.1f} s, min ESS {d['min_ess']:.0f}, warnings {result.warnings}", file=sys.stderr)
    lines += ["", "Posterior predictive of each measurement (replicated data, central 68 %):", "",
              "| setup | observable | measured | posterior predictive median [68 %] | P(y_rep > y) |", "|---|---|---|---|---|"]
    for name, result, _, _ in timing:
        for q in result.quantity_rows():
            if q["measured"]:
                lines.append(
                    f"| {name} | {q['name']} | {_fmt(q['observed'], 5)} +/- {_fmt(q['observed_uncertainty'], 2)} {q['unit']} | "
                    f"{_fmt(q['predictive_median'], 5)} [{_fmt(q['predictive_lower_68'], 5)}, {_fmt(q['predictive_upper_68'], 5)}] | "
                    f"{q['predictive_p_value']:.2f} |"
                )
    lines += ["", "Time (wall clock, whole `wobble.invert` call; sampling alone in brackets) and time per effective sample "
              "(sampling time over the smallest bulk or tail ESS of any parameter):", "",
              "| setup | walkers x steps (+ burn-in) | time [s] | max R-hat | min ESS | ms per effective sample | warnings |",
              "|---|---|---|---|---|---|---|"]
    for name, result, wall, d in timing:
        s = result.settings
        rhat = max(r.r_hat for r in result.rows())
        lines.append(
            f"| {name} | {s.walkers} x {s.steps} (+ {s.burn}) | {wall:.1f} ({d['seconds']:.1f}) | {rhat:.4f} | {d['min_ess']:.0f} | "
            f"{1e3 * d['seconds_per_effective_sample']:.2f} | {'; '.join(w.split(':')[0] for w in result.warnings) or 'none'} |"
        )
    lines.append("")


def calibration(lines: list[str], draws: int, scheduler, seed: int):
    import wobble

    lines += ["## Injection–recovery (simulation-based calibration)", "",
              f"{draws} truths per setup drawn from its priors; measurements simulated from each truth with the "
              f"setup's uncertainties; each inverted with {CAL_SETTINGS['walkers']} walkers x {CAL_SETTINGS['steps']} steps "
              f"(+ {CAL_SETTINGS['burn']} burn-in); seed {seed}. A calibrated inversion covers the truth in 68 % and 95 % "
              "of the cases; the standard error of a coverage over n draws is sqrt(p(1 - p)/n). The rank of the truth "
              "among 99 thinned posterior draws is uniform on 0..99 when the posterior is right (Talts et al. 2018): "
              "the last column is the p-value of a chi-square test on 10 bins.", "",
              "| setup | parameter | 68 % coverage | 95 % coverage | rank histogram (10 bins) | chi-square p |",
              "|---|---|---|---|---|---|"]
    for name in CALIBRATED:
        t0 = time.perf_counter()
        cal = wobble.injection_recovery(name, draws=draws, seed=seed, scheduler=scheduler, progress=sys.stderr.isatty(), **CAL_SETTINGS)
        wall = time.perf_counter() - t0
        hist = cal.rank_histogram()
        for pname, c in cal.coverage.items():
            counts = np.array(hist[pname])
            p = stats.chisquare(counts).pvalue
            lines.append(
                f"| {name} | {pname} | {100 * c['68']:.1f} +/- {100 * c['se_68']:.1f} % | {100 * c['95']:.1f} +/- {100 * c['se_95']:.1f} % | "
                f"{' '.join(str(int(x)) for x in counts)} | {p:.2f} |"
            )
        ess = cal.to_dict()["min_ess_median"]
        lines.append(f"| {name} | (all) | {draws} draws in {wall:.0f} s | median smallest ESS {ess:.0f} | | |")
        print(f"calibration {name}: {wall:.0f} s", file=sys.stderr)
    lines.append("")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=200, help="injections per setup (default 200)")
    parser.add_argument("--seed", type=int, default=20260101)
    parser.add_argument("--scheduler", help="dask scheduler for the injections: processes, threads or an address")
    parser.add_argument("--quick", action="store_true", help="10 draws and short default runs; prints the report instead of writing it")
    parser.add_argument("--output", default=str(REPORT), help="report path (default docs/performance-inversion.md)")
    args = parser.parse_args(argv)
    draws = 10 if args.quick else args.draws
    started = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg() if hasattr(os, "getloadavg") else (math.nan,) * 3
    lines = [
        "# Inversion: calibration and timing",
        "",
        f"Written by `python scripts/calibrate_inversion.py{' --quick' if args.quick else ''}"
        f"{f' --draws {args.draws}' if args.draws != 200 and not args.quick else ''}` on {started}: "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, load average "
        f"{load[0]:.1f} at the start (a shared machine: timings are noisy; re-run on a quiet one). "
        "Do not edit by hand.",
        "",
    ]
    t0 = time.perf_counter()
    default_runs(lines, args.quick)
    calibration(lines, draws, args.scheduler, args.seed)
    lines.append(f"Total {time.perf_counter() - t0:.0f} s.")
    text = "\n".join(lines) + "\n"
    if args.quick:
        print(text)
    else:
        Path(args.output).write_text(text)
        print(f"wrote {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
