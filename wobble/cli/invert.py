"""``wobble invert``: Bayesian inversion of a planet's parameters from its observed wobble."""

from __future__ import annotations

import argparse
import sys

from wobble.cli._types import whole_number
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble invert mars                       Mars' core radius from the Chandler period, k2, the FCN and the precession
  wobble invert earth --json               Earth's anelastic exponent, Chandler Q and core-flattening excess (scripts)
  wobble invert mars_chandler_only --steps 1000   the Chandler period alone: how little one period says
  wobble invert mars --steps 500 -o mars_posterior.nc --plot mars_corner.png --overwrite
  wobble invert mars --prior-only --steps 500     the priors pushed through the model (what the data add)
  wobble invert mars --seed 7 --steps 200 --burn 100 --quiet     another seed, a shorter burn-in, no progress bar
  wobble example bodies/mars.toml mars_edited.toml    a planet file to edit, then:
  wobble invert mars --body-file mars_edited.toml --steps 300 --burn 100 --quiet   the Mars set-up on your planet
  wobble example inversions/mars my_setup.toml    copy a shipped set-up to edit, then:
  wobble invert my_setup.toml --ensembles 2 --steps 300 --burn 100 --scheduler tcp://127.0.0.1:8786
                                                  on a running dask.distributed cluster

The examples with --steps are cut short so that they finish in seconds (--burn
shortens the burn-in too: 500 or 1000 steps in the shipped setups), and their
summaries warn, rightly, that R-hat is above 1.01 (and that there are too few
autocorrelation times): R-hat is about 1 + tau/N for N steps and an autocorrelation
time tau of some 10 steps (Mars), so a few hundred steps do not converge, and their
intervals are rough. For numbers to use, leave out --steps: each shipped setup's own
length is chosen for convergence (2000 steps for earth and mars; 8000 for
mars_chandler_only, whose long curved posterior only just reaches R-hat 1.01).

Setups are wobble-inversion/1 TOML files (priors, observables, sampler settings);
the shipped ones (data/inversions/: earth, mars, mars_chandler_only) are found by
name from any folder. Observables: chandler_period, tidal_k2, fcn_period (the free
core nutation in space), precession_rate, and derived quantities (the wobble's Q,
the core's e_f). Sampling uses emcee; the summary gives each parameter's median,
central 68 % and 95 % intervals, R-hat and effective sample size (ArviZ), and
warns when R-hat > 1.01 or the ESS is small. -o writes ArviZ InferenceData as
netCDF (reopen with arviz.from_netcdf). The same seed gives the same numbers.
A progress bar is shown on a terminal unless --quiet.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "invert",
        help="Bayesian inversion: interior parameters from the observed wobble (emcee, ArviZ)",
        description="Sample the posterior of a planet's parameters (core radius, anelasticity, Love "
        "numbers, core flattening, polar moment) given observed wobble periods, tides, the free core "
        "nutation and the precession, with priors from the catalogue or the setup.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "setup", metavar="SETUP", help="a setup file (.toml) or a shipped setup: earth, mars, mars_chandler_only"
    )
    p.add_argument(
        "--json", action="store_true", help="print the result as JSON (parameters, observables, sampler, warnings)"
    )
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write the ArviZ InferenceData as netCDF")
    p.add_argument("--overwrite", action="store_true", help="replace existing output files")
    p.add_argument(
        "--plot", metavar="FILE.png", help="corner plot of the posterior with the priors and published values"
    )
    p.add_argument(
        "--body-file",
        metavar="FILE",
        help="a planet file of your own in place of the setup's body (as in wobble chandler --body-file)",
    )
    p.add_argument("--seed", type=whole_number, help="random seed (default: the setup's); same seed, same numbers")
    p.add_argument("--walkers", type=whole_number, help="walkers per ensemble (even, >= twice the parameters)")
    p.add_argument("--steps", type=whole_number, help="steps kept per walker after the burn-in")
    p.add_argument("--burn", type=whole_number, help="burn-in steps discarded per walker")
    p.add_argument("--ensembles", type=whole_number, help="independent ensembles, pooled (parallel with --scheduler)")
    p.add_argument("--prior-only", action="store_true", help="sample the priors only (no data): what the data add")
    p.add_argument(
        "--scheduler", help="run ensembles on dask: threads, processes, synchronous or a dask.distributed address"
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.inversion import SIZE, invert
    from wobble.cli._output import print_json, wrote

    for name in ("seed", "burn"):
        value = getattr(args, name)
        if value is not None and value < 0:
            raise InputError(f"--{name}", value, "a non-negative integer")
    from wobble.io.cf import INT64_ALLOWED, INT64_MAX

    if args.seed is not None and args.seed > INT64_MAX:
        raise InputError("--seed", args.seed, f"a non-negative integer {INT64_ALLOWED}")
    for name in ("walkers", "steps", "ensembles"):
        value = getattr(args, name)
        if value is not None and value < 1:
            raise InputError(f"--{name}", value, "a positive integer")
    # Refuse unwritable outputs before any sampling.
    from wobble.io.atomic import check_target

    if args.output:
        check_target(args.output, args.overwrite)
    if args.plot:
        from wobble.plot.save import check_plot_path

        check_plot_path(args.plot, args.overwrite)  # names --plot (check_target alone named -o/--output)
    from wobble.cli._record import as_typed

    # The memory refusal names the product of four settings: named here as the options that set them.
    size = ("--walkers x (--burn + --steps) x --ensembles", None)
    with as_typed({"body": ("--body-file", args.body_file), SIZE: size}):
        result = invert(
            args.setup,
            body=args.body_file,
            seed=args.seed,
            walkers=args.walkers,
            steps=args.steps,
            burn=args.burn,
            ensembles=args.ensembles,
            prior_only=args.prior_only,
            scheduler=args.scheduler,
            progress=not args.quiet and sys.stderr.isatty(),
        )
    if args.output:
        result.write(args.output, overwrite=args.overwrite, command=args.command_line)
    if args.plot:
        result.plot(args.plot, overwrite=args.overwrite)
    if args.json:
        out = result.to_dict()
        out["output"] = args.output
        out["plot"] = args.plot
        print_json(out)
    else:
        print(result.summary())
    for path in (args.output, args.plot):
        if path:
            wrote(path, json_mode=args.json)
    return 0
