"""``wobble run``: run a scene (TOML) to a CF netCDF file, choosing the cheapest adequate model."""

from __future__ import annotations

import argparse
import json

EPILOG = """\
examples:
  wobble run data/scenes/tennis_racket.toml -o racket.nc
  wobble run tennis_racket -o racket.nc --json          an example scene by name
  wobble run earth_free_wobble -o earth.nc --overwrite
  wobble run satellite_gravity_gradient -o sat.nc --model dop853   force a model, to compare

The model is chosen from the scene (docs/engine.md): a closed form or elliptic
functions for a free body, the exact heavy top, else the splitting integrator
or DOP853; the choice, the reason and the error estimate are recorded in the
file's global attributes (model, model_reason, error_estimate). The file is
written as the run goes (memory stays bounded) under a temporary name, and
renamed only when the run succeeded; an existing file is replaced only with
--overwrite. Example scenes: wobble run --list.
"""


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "run",
        help="run a scene (TOML): cheapest adequate model, CF netCDF output",
        description="Run a scene file: body, initial state, torques, times, accuracy and outputs. "
        "The cheapest model that meets the accuracy is chosen and recorded in the output.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", nargs="?", help="scene file (TOML), or the name of an example scene")
    p.add_argument("-o", "--output", help="netCDF file to write")
    p.add_argument("--model", help="force a model: free-symmetric, free-elliptic, heavy-top, splitting, dop853")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--json", action="store_true", help="print the run summary as JSON")
    p.add_argument("--list", action="store_true", help="list the example scenes and exit")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.scene import _as_scene, example_scenes, run_to_netcdf
    from wobble.cli._table import print_rows
    from wobble.errors import InputError

    if args.list:
        names = example_scenes()
        print(json.dumps(names) if args.json else "\n".join(names))
        return 0
    if not args.scene:
        raise InputError("SCENE", None, "a scene file (TOML) or an example name (wobble run --list)")
    if not args.output:
        raise InputError("-o/--output", None, "the netCDF file to write (e.g. -o out.nc)")
    scene = _as_scene(args.scene)
    summary = run_to_netcdf(scene, args.output, model=args.model, overwrite=args.overwrite,
                            command=getattr(args, "command_line", None))
    if args.json:
        print(json.dumps(summary, indent=2, default=str))
    else:
        rows = [
            ("scene", summary["scene"]),
            ("model", summary["model"]),
            ("why", summary["model_reason"]),
            ("error estimate", f"{summary['error_estimate']:.3g} (asked {summary['accuracy_requested']:.3g})"),
            ("members x times", f"{summary['members']} x {summary['times']}"),
            ("written", summary["output"]),
        ]
        print_rows(rows)
    return 0
