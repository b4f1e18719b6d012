"""``wobble sweep``: parameter sweeps and Monte Carlo ensembles on dask."""

from __future__ import annotations

import argparse
import sys

from wobble.cli._types import whole_number
from wobble.errors import InputError

EPILOG = """\
examples:
  wobble sweep mars_chandler                       a shipped sweep, summary only
  wobble sweep mars_chandler -o mars.nc --plot mars.png
  wobble example mars_chandler my_sweep.toml       copy a sweep file to edit, then:
  wobble sweep my_sweep.toml -o out.nc --scheduler processes
  wobble sweep earth_chandler --members 10000 --json
  wobble sweep top_phase_diagram -o top.nc --plot top.png   the heavy top's phase diagram
  wobble sweep tumbling_asteroids -o ast.nc                 10^5 tumbling asteroids
  wobble sweep tumbling_asteroids -o ast.nc --overwrite --scheduler tcp://127.0.0.1:8786
                                                   on a running dask.distributed cluster

Members are computed chunk by chunk with the vectorised models and streamed to
the netCDF file as they finish (bounded memory). The same seed gives the same
draws whatever the chunking and the number of workers, and the same results to
the last digit or one unit in it (SIMD loops over chunks of other sizes may round
a last bit differently). A progress bar is shown
on a terminal unless --quiet. The Chandler sweeps draw every catalogued uncertainty,
as 'wobble chandler' does for its +/-, so the two sds agree within sampling error; the
centres differ a little: the sweep's mean and median are of the draws, 'wobble chandler'
prints the model at the catalogued values (they differ by the model's curvature over
the draws, e.g. 205.9 against 205.6 d for Mars). Spans print in days, hours, ... as
they come, with digits to the sd's two significant digits; --json keeps every digit,
in the file's units.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "sweep",
        help="parameter sweeps and Monte Carlo ensembles (dask, bounded memory)",
        description="Run a sweep file: vary a body's parameters (random draws or grids), "
        "evaluate every member with the vectorised models, keep the chosen outputs.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("sweep", metavar="SWEEP", help="a sweep file, or the name of one in data/sweeps")
    p.add_argument(
        "-o",
        "--output",
        metavar="FILE.nc",
        help="stream the results to a CF-1.10 netCDF file "
        "(or a Zarr store when the name ends in .zarr; needs the zarr package)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--members", type=whole_number, help="override the sweep's member count (random sweeps)")
    p.add_argument("--chunk-size", type=whole_number, help="members per dask chunk")
    p.add_argument("--scheduler", help="threads (default), processes, synchronous, or a dask.distributed address")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.add_argument(
        "--plot",
        metavar="FILE.png",
        help="histogram of the main output with the observed value "
        "(the phase diagram for heavy_top sweeps, periods and wobble angles for free_rotation)",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    from dataclasses import replace

    from wobble.api.sweep import load_sweep, run_sweep, summarize_sweep
    from wobble.cli._output import check_outputs, print_json, wrote
    from wobble.io.shipped import resolve

    check_outputs(args, zarr=True)
    spec = load_sweep(resolve(args.sweep, "sweeps", "SWEEP", (".toml",)))
    if args.members is not None:
        if spec.is_grid:
            raise InputError("--members", args.members, "only for random sweeps (a grid sets its own size)")
        from wobble.io.cf import INT64_ALLOWED, INT64_MAX

        if not 0 < args.members <= INT64_MAX:
            raise InputError("--members", args.members, f"a positive integer {INT64_ALLOWED}")
        spec = replace(spec, members=args.members)
    if args.chunk_size is not None and args.chunk_size <= 0:
        raise InputError("--chunk-size", args.chunk_size, "a positive integer")
    progress = not args.quiet and sys.stderr.isatty()
    ds = run_sweep(
        spec,
        args.output,
        overwrite=args.overwrite,
        chunk_size=args.chunk_size,
        scheduler=args.scheduler,
        progress=progress,
        command=args.command_line,
    )
    summary = summarize_sweep(ds)
    if args.plot:
        from wobble.plot import sweep as sweep_plot

        target = ds.attrs.get("sweep_target", "chandler")
        draw = {"heavy_top": sweep_plot.phase_diagram, "free_rotation": sweep_plot.ensemble}.get(
            target, sweep_plot.histogram
        )
        draw(ds, args.plot, overwrite=args.overwrite)
    written = [p for p in (args.output, args.plot) if p]
    if args.json:
        print_json({"sweep": spec.name, "output": args.output, "plot": args.plot, **summary.to_dict()})
        for path in written:
            wrote(path, json_mode=True)
        return 0
    print(summary.summary(spec.title))
    for path in written:
        wrote(path)
    return 0
