"""``wobble run``: run a scene (TOML) to a CF netCDF file, choosing the cheapest adequate model."""

from __future__ import annotations

import argparse
from pathlib import Path

EPILOG = """\
examples:
  wobble run --list                                      the example scenes, with what they show
  wobble run tennis_racket -o racket.nc --plot racket.png
  wobble run tennis_racket -o racket.nc --json --overwrite   an example scene by name
  wobble run earth_free_wobble -o earth.nc --overwrite
  wobble run satellite_gravity_gradient -o sat.nc --json   the model chosen, and why (predicted seconds)
  wobble run top_cusps -o cusps.nc --model dop853       force a model, to compare with the exact top
  wobble example tossed_book my_book.toml                copy a scene to edit, then:
  wobble run my_book.toml -o book.nc

The model is chosen from the scene: a closed form or elliptic functions for a free
body, the exact heavy top, else the splitting integrator or DOP853; the choice, the
reason and the error estimate are recorded in the file's global attributes (model,
model_reason, error_estimate). The file is written as the run goes (memory stays
bounded) under a temporary name, and renamed only when the run succeeded; an
existing file is replaced only with --overwrite.
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
    p.add_argument("scene", nargs="?", metavar="SCENE", help="scene file (TOML), or the name of an example scene")
    p.add_argument("-o", "--output", metavar="FILE.nc", help="netCDF file to write")
    p.add_argument("--plot", metavar="FILE.png", help="draw the scene's outputs against time (from the file written)")
    p.add_argument(
        "--model",
        help="force a model: averaged-precession, free-symmetric, free-elliptic, heavy-top, splitting, dop853 "
        "(default auto: the cheapest that meets the scene's accuracy)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace existing output files")
    p.add_argument("--json", action="store_true", help="print the run summary as JSON")
    p.add_argument("--list", action="store_true", help="list the example scenes with one-line descriptions and exit")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.cli._output import check_outputs, finish
    from wobble.errors import InputError

    if args.list:
        return _list(args.json)
    if not args.scene:
        raise InputError.missing("SCENE", "a scene file (TOML) or an example name (wobble run --list)")
    from wobble.io.shipped import resolve

    path = resolve(args.scene, "scenes", "SCENE")  # an unknown scene is named before a missing -o
    from wobble.errors import FileFormatError
    from wobble.io.scene_file import read_scene  # (not wobble.api.scene's: that imports xarray, ~1 s)
    from wobble.models.scene import check_model_name

    # What is wrong with the scene or the model is said before a missing -o (it was "-o/--output: missing"
    # for a broken scene file and for --model rk4).
    scene = read_scene(path)
    check_model_name(args.model)
    if not args.output:
        raise InputError.missing("-o/--output", "the netCDF file to write (e.g. -o out.nc)")
    check_outputs(args)
    from wobble.api.scene import run_to_netcdf

    try:
        summary = run_to_netcdf(
            scene, args.output, model=args.model, overwrite=args.overwrite, command=getattr(args, "command_line", None)
        )
    except FileFormatError as exc:
        if exc.where != "accuracy" or not _is_shipped(path):
            raise
        # The installed file is not the user's to edit: say how to ask for another accuracy.
        name = Path(path).stem
        raise FileFormatError(
            exc.path,
            exc.where,
            f"{exc.problem}; for another accuracy copy the scene (wobble example {name} "
            f"my_{name}.toml) and edit its accuracy",
        ) from None
    written = [summary["output"]]
    if args.plot:
        from wobble.plot.scene import scene_figure

        written.append(scene_figure(summary["output"], path=args.plot, overwrite=args.overwrite))
        summary["plot"] = str(written[-1])
    return finish(args, summary, lambda: _print_summary(summary), written)


def _is_shipped(path) -> bool:
    from wobble.io.shipped import find_shipped

    found = find_shipped(Path(path).name, "scenes")
    return found is not None and Path(str(found.path())).resolve() == Path(path).resolve()


def _list(as_json: bool) -> int:
    from wobble.cli._output import print_json
    from wobble.io.shipped import shipped_files

    scenes = shipped_files("scenes")
    if as_json:
        print_json([{"name": f.stem, "title": f.description} for f in scenes])
        return 0
    width = max(len(f.stem) for f in scenes)
    for f in scenes:
        print(f"{f.stem:<{width}}  {f.description}")
    return 0


def _print_summary(summary: dict) -> None:
    from wobble.cli._output import number
    from wobble.cli._table import print_rows

    asked = f"asked {number(summary['accuracy_requested'], 3)}"
    if summary.get("error_estimate_rounding") is not None:  # the splitting's: a shorter step cannot lower it
        asked += f"; rounding floor {number(summary['error_estimate_rounding'], 3)}"
    print_rows(
        [
            ("scene", summary["scene"]),
            ("model", summary["model"]),
            ("why", summary["model_reason"]),
            ("error estimate", f"{number(summary['error_estimate'], 3)} ({asked})"),
            ("members x times", f"{summary['members']} x {summary['times']}"),
        ]
    )
