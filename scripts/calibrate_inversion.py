"""Calibrate the Bayesian inversion and time it; write docs/performance-inversion.md.

Usage::

    python scripts/calibrate_inversion.py                 # full: 200 injections per setup
    python scripts/calibrate_inversion.py --draws 400 --scheduler processes
    python scripts/calibrate_inversion.py --quick         # a 10-draw smoke run (report not for docs)
    python scripts/calibrate_inversion.py --only calibration --draws 400   # replace that section only

Three parts:

1. **The shipped setups at their default settings** (``wobble invert mars``, ``earth``,
   ``mars_chandler_only``): posterior medians and intervals, the largest R-hat, the
   smallest ESS, wall-clock time and time per effective sample (with the load average
   of the machine around each run); and the same setups prior-only, to show what the
   data add (the ratio of the 68 % widths).
2. **What each observable adds**: the Mars and Earth setups with one observable left
   out (or the core's compliances known), shorter chains.
3. **Injection–recovery** (simulation-based calibration; Cook, Gelman & Rubin 2006;
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
# Shorter chains than the defaults for each injection: an ESS near 2000 is plenty for
# the 2.5 and 97.5 % quantiles, and the check is of the intervals, not of their digits.
CAL_SETTINGS = dict(walkers=64, steps=400, burn=400)
# The ablations: shorter chains than the defaults (their medians and intervals, not R-hat).
ABLATION_SETTINGS = dict(steps=1000, burn=500)


def _digits(value, sigma) -> int:
    """Significant digits that show ``value`` to two digits of its uncertainty (at least 5)."""
    if not (math.isfinite(value) and math.isfinite(sigma) and value != 0 and sigma > 0):
        return 5
    return max(5, int(math.floor(math.log10(abs(value)))) - int(math.floor(math.log10(sigma))) + 2)


def _fmt(x, digits=4):
    if x is None or not math.isfinite(x):
        return "-"
    return f"{x:.{digits}g}"


def default_runs(lines: list[str], quick: bool):
    import wobble

    lines += [
        "## The shipped setups at their default settings",
        "",
        "| setup | parameter | median | 68 % interval | 95 % interval | R-hat | ESS (min of bulk, tail) | prior 68 "
        "% width / posterior 68 % width |",
        "|---|---|---|---|---|---|---|---|",
    ]
    timing = []
    extra = dict(steps=300, burn=200) if quick else {}
    for name in SETUPS:
        load0 = _load()
        t0 = time.perf_counter()
        result = wobble.invert(name, **extra)
        wall = time.perf_counter() - t0
        load = (load0, _load())
        prior = wobble.invert(name, prior_only=True, **extra)
        prior_rows = {r.name: r for r in prior.rows()}
        for r in result.rows():
            p = prior_rows[r.name]
            ratio = (p.upper_68 - p.lower_68) / (r.upper_68 - r.lower_68)
            unit = f" {r.unit}" if r.unit else ""
            lines.append(
                f"| {name} | {r.name} | {_fmt(r.median, 5)}{unit} | [{_fmt(r.lower_68, 5)}, {_fmt(r.upper_68, 5)}] | "
                f"[{_fmt(r.lower_95, 5)}, {_fmt(r.upper_95, 5)}] | {r.r_hat:.4f} | {min(r.ess, r.ess_tail):.0f} | "
                f"{ratio:.2f} |"
            )
        for q in result.quantity_rows():
            if not q["measured"]:
                unit = f" {q['unit']}" if q["unit"] else ""
                lines.append(
                    f"| {name} | {q['name']} (derived) | {_fmt(q['median'], 4)}{unit} | [{_fmt(q['lower_68'], 4)}, "
                    f"{_fmt(q['upper_68'], 4)}] | "
                    f"[{_fmt(q['lower_95'], 4)}, {_fmt(q['upper_95'], 4)}] | - | - | "
                    f"{(q['prior_upper_68'] - q['prior_lower_68']) / (q['upper_68'] - q['lower_68']):.2f} |"
                )
        d = result.to_dict()["diagnostics"]
        timing.append((name, result, wall, d, load))
        print(f"{name}: {wall:.1f} s, min ESS {d['min_ess']:.0f}, warnings {result.warnings}", file=sys.stderr)
    lines += [
        "",
        "Posterior predictive of each measurement (replicated data, central 68 %):",
        "",
        "| setup | observable | measured | posterior predictive median [68 %] | P(y_rep > y) |",
        "|---|---|---|---|---|",
    ]
    for name, result, _, _, _ in timing:
        for q in result.quantity_rows():
            if q["measured"]:
                n = _digits(q["observed"], q["observed_uncertainty"])
                lines.append(
                    f"| {name} | {q['name']} | {_fmt(q['observed'], n)} +/- {_fmt(q['observed_uncertainty'], 2)} "
                    f"{q['unit']} | "
                    f"{_fmt(q['predictive_median'], n)} [{_fmt(q['predictive_lower_68'], n)}, "
                    f"{_fmt(q['predictive_upper_68'], n)}] | "
                    f"{q['predictive_p_value']:.2f} |"
                )
    lines += [
        "",
        "Time (wall clock, whole `wobble.invert` call; sampling alone in brackets) and time per effective sample "
        "(sampling time over the smallest bulk or tail ESS of any parameter), with the machine's one-minute load "
        "average before and after the run (2 cores: a load of 4 leaves this run about half a core's worth less):",
        "",
        "| setup | walkers x steps (+ burn-in) | moves | time [s] | load before, after | max R-hat | min ESS | ms "
        "per effective sample | warnings |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, result, wall, d, load in timing:
        s = result.settings
        rhat = max(r.r_hat for r in result.rows())
        thin = f", thin {s.thin}" if s.thin > 1 else ""
        lines.append(
            f"| {name} | {s.walkers} x {s.steps} (+ {s.burn}{thin}) | {', '.join(f'{m} {w:g}' for m, w in s.moves)} | "
            f"{wall:.1f} ({d['seconds']:.1f}) | {load[0]:.1f}, {load[1]:.1f} | "
            f"{rhat:.4f} | {d['min_ess']:.0f} | "
            f"{1e3 * d['seconds_per_effective_sample']:.2f} | "
            f"{'; '.join(w.split(':')[0] for w in result.warnings) or 'none'} |"
        )
    figure = next((r.setup.context.core_figure for _, r, _, _, _ in timing if r.setup.name == "mars"), None)
    if figure is not None:
        lines += [
            "",
            f"Mars' hydrostatic core: {figure.describe()}; box x = r_c/R in [{figure.box[0][0]:.4f}, "
            f"{figure.box[0][1]:.4f}], "
            f"y = rho_c/rho_mean in [{figure.box[1][0]:.4f}, {figure.box[1][1]:.4f}], c = C/(MR^2) in "
            f"[{figure.box[2][0]:.5f}, {figure.box[2][1]:.5f}] (R = {figure.radius / 1e3:.1f} km).",
        ]
    lines.append("")


def _load() -> float:
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan


def _shipped(name: str) -> dict:
    import tomllib
    from importlib import resources

    return tomllib.loads((resources.files("wobble._data") / "inversions" / f"{name}.toml").read_text())


def _without(name: str, observable: str, *, drop_parameters=(), catalogue_prior=()) -> dict:
    data = _shipped(name)
    data["name"] = f"{name} without {observable}"
    data["observables"].pop(observable, None)
    for key in drop_parameters:
        data["parameters"].pop(key, None)
        data.get("compare", {}).pop(key, None)
    for key in catalogue_prior:
        data["parameters"][key] = {"unit": ""}
    return data


def ablations(lines: list[str], quick: bool):
    """The shipped setups with one observable left out, or the compliances known."""
    import wobble

    settings = dict(steps=200, burn=200) if quick else ABLATION_SETTINGS
    mars_known = _shipped("mars")
    mars_known["name"] = "mars with beta and gamma known"
    for key in ("core_compliance_beta", "core_compliance_gamma"):
        mars_known["parameters"].pop(key)
    earth_known = _shipped("earth")
    earth_known["name"] = "earth with beta and gamma known"
    for key in ("core_compliance_beta", "core_compliance_gamma"):
        earth_known["parameters"].pop(key)
    variants = [
        ("mars", _shipped("mars"), "all four (the shipped setup)"),
        ("mars", _without("mars", "fcn_period"), "without the FCN"),
        (
            "mars",
            _without("mars", "precession_rate", catalogue_prior=("polar_moment_factor",)),
            "without the precession (C/(MR^2) at its catalogued 0.36419 +- 0.00011)",
        ),
        ("mars", _without("mars", "tidal_k2"), "without the tidal k2"),
        ("mars", mars_known, "all four, the compliances beta and gamma fixed at their catalogued values"),
        ("earth", _shipped("earth"), "Chandler period and FCN (the shipped setup)"),
        (
            "earth",
            _without(
                "earth",
                "fcn_period",
                drop_parameters=("core_flattening_excess", "core_compliance_beta", "core_compliance_gamma"),
            ),
            "Chandler period alone",
        ),
        ("earth", earth_known, "Chandler period and FCN, beta and gamma fixed at their catalogued values"),
    ]
    lines += [
        "## What each observable adds",
        "",
        "Medians and central 68 % intervals of the main parameters for the shipped setups with one observable "
        "left out, "
        f"or with the core's compliances fixed; {settings['steps']} steps after {settings['burn']} burn-in "
        "(shorter than the defaults: "
        "the intervals, not R-hat, are the point here).",
        "",
        "| body | observables | parameter | median | 68 % interval |",
        "|---|---|---|---|---|",
    ]
    shown = {
        "mars": ("fluid_core_radius", "polar_moment_factor", "core_compliance_beta", "love_number_k2"),
        "earth": ("anelastic_exponent", "core_flattening_excess", "core_compliance_beta"),
    }
    for body, data, label in variants:
        result = wobble.invert(data, **settings)
        for r in result.rows():
            if r.name in shown[body]:
                unit = f" {r.unit}" if r.unit else ""
                lines.append(
                    f"| {body} | {label} | {r.name} | {_fmt(r.median, 5)}{unit} | [{_fmt(r.lower_68, 5)}, "
                    f"{_fmt(r.upper_68, 5)}] |"
                )
        print(f"ablation {body}: {label} done", file=sys.stderr)
    lines.append("")


def calibration(lines: list[str], draws: int, scheduler, seed: int, setups=CALIBRATED):
    import wobble

    lines += [
        "## Injection–recovery (simulation-based calibration)",
        "",
        f"{draws} truths per setup drawn from its priors; measurements simulated from each truth with the "
        f"setup's uncertainties; each inverted with {CAL_SETTINGS['walkers']} walkers x {CAL_SETTINGS['steps']} steps "
        f"(+ {CAL_SETTINGS['burn']} burn-in); seed {seed}. A calibrated inversion covers the truth in 68 % and 95 % "
        "of the cases; the standard error of a coverage over n draws is sqrt(p(1 - p)/n). The rank of the truth "
        "among 99 thinned posterior draws is uniform on 0..99 when the posterior is right (Talts et al. 2018): "
        "the last column is the p-value of a chi-square test on 10 bins.",
        "",
        "| setup | parameter | 68 % coverage | 95 % coverage | rank histogram (10 bins) | chi-square p |",
        "|---|---|---|---|---|---|",
    ]
    n_params = []
    for name in setups:
        t0 = time.perf_counter()
        cal = wobble.injection_recovery(
            name, draws=draws, seed=seed, scheduler=scheduler, progress=sys.stderr.isatty(), **CAL_SETTINGS
        )
        wall = time.perf_counter() - t0
        hist = cal.rank_histogram()
        for pname, c in cal.coverage.items():
            counts = np.array(hist[pname])
            p = stats.chisquare(counts).pvalue
            lines.append(
                f"| {name} | {pname} | {100 * c['68']:.1f} +/- {100 * c['se_68']:.1f} % | {100 * c['95']:.1f} +/- "
                f"{100 * c['se_95']:.1f} % | "
                f"{' '.join(str(int(x)) for x in counts)} | {p:.2f} |"
            )
        ess = cal.to_dict()["min_ess_median"]
        lines.append(f"| {name} | (all) | {draws} draws in {wall:.0f} s | median smallest ESS {ess:.0f} | | |")
        n_params.append(len(cal.coverage))
        print(f"calibration {name}: {wall:.0f} s", file=sys.stderr)
    # What chance alone allows: X ~ Binomial(n, 0.68) hits for a calibrated inversion.
    k = sum(n_params)
    within = stats.binom.cdf(math.floor(draws * 0.73 + 1e-9), draws, 0.68) - stats.binom.cdf(
        math.ceil(draws * 0.63 - 1e-9) - 1, draws, 0.68
    )
    lines += [
        "",
        f"For a calibrated inversion the number of 68 % intervals holding the truth is Binomial({draws}, 0.68): "
        f"each coverage lies within 5 points of 68 % with probability {within:.2f}, so all {k} of them would "
        f"with probability about {within**k:.2f} if they were independent (they are correlated within a setup, "
        "which raises it). Coverages outside the 5-point band are to be read against this.",
    ]
    lines.append("")


def _replace_section(report: str, section: list[str]) -> str:
    """``report`` with its section headed like ``section[0]`` replaced by ``section`` (to the end).

    The calibration is the report's last section, so everything from its heading on is replaced.
    """
    head = report.split(section[0])[0] if section[0] in report else report
    return head + "\n".join(section) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--draws", type=int, default=200, help="injections per setup (default 200)")
    parser.add_argument("--setups", default=",".join(CALIBRATED), help="setups to calibrate (default mars,earth)")
    parser.add_argument("--seed", type=int, default=20260101)
    parser.add_argument("--scheduler", help="dask scheduler for the injections: processes, threads or an address")
    parser.add_argument(
        "--quick", action="store_true", help="10 draws and short default runs; prints the report instead of writing it"
    )
    parser.add_argument("--output", default=str(REPORT), help="report path (default docs/performance-inversion.md)")
    parser.add_argument(
        "--only",
        choices=("calibration",),
        help="run only this part and replace its section of the existing report, keeping the others "
        "(their timings stay those of the run that wrote them)",
    )
    typed = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(typed)
    if args.only and args.quick:
        # A 10-draw smoke run must not replace the section of the report the docs show.
        parser.error("--only replaces a section of the report; --quick runs are printed, not written")
    draws = 10 if args.quick else args.draws
    started = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg() if hasattr(os, "getloadavg") else (math.nan,) * 3
    lines = [
        "# Inversion: calibration and timing",
        "",
        # The command as typed (a scheduler or a seed changes how or what was run, so the report names it).
        f"Written by `{' '.join(['python scripts/calibrate_inversion.py', *typed])}` on {started}: "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, load average "
        f"{load[0]:.1f} at the start (a shared machine: timings are noisy; re-run on a quiet one). "
        "Do not edit by hand.",
        "",
    ]
    t0 = time.perf_counter()
    if args.only == "calibration":
        section: list[str] = []
        calibration(section, draws, args.scheduler, args.seed, tuple(args.setups.split(",")))
        command = " ".join(["python scripts/calibrate_inversion.py", *typed])
        section.append(
            f"Calibration rewritten on {started} by `{command}` in {time.perf_counter() - t0:.0f} s "
            f"(load average {load[0]:.1f} at its start)."
        )
        text = _replace_section(Path(args.output).read_text(), section)
        Path(args.output).write_text(text)
        print(f"wrote {args.output}", file=sys.stderr)
        return 0
    default_runs(lines, args.quick)
    ablations(lines, args.quick)
    calibration(lines, draws, args.scheduler, args.seed, tuple(args.setups.split(",")))
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
