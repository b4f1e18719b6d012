"""``wobble example``: list the shipped files and copy one to start from."""

from __future__ import annotations

import argparse

EPILOG = """\
examples:
  wobble example --list                          every shipped file, with what it is
  wobble example my_planet.toml planet.toml      a planet to edit (then: wobble chandler --body-file planet.toml)
  wobble example tennis_racket my_racket.toml    a scene, under a new name
  wobble example dumbbell.csv --overwrite        point masses (wobble inertia --points dumbbell.csv --length-unit cm)

Commands also find shipped files by name without a copy (as in 'wobble run tennis_racket'
or 'wobble inertia --points dumbbell.csv'); a file of your own with the same name in
the current folder takes precedence.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "example",
        help="list the shipped example files, or copy one to start from",
        description="The files wobble ships (planet catalogue, example inputs, scenes, sweeps): "
        "list them (without NAME, or with --list), or copy one into your folder to edit.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("name", nargs="?", metavar="NAME", help="a shipped file (with or without its extension)")
    p.add_argument("dest", nargs="?", metavar="DEST", help="where to copy it: a file or a folder (default: ./NAME)")
    p.add_argument("--list", action="store_true", help="list the shipped files with one-line descriptions")
    p.add_argument("--overwrite", action="store_true", help="replace an existing DEST")
    p.add_argument("--json", action="store_true", help="print the list (or the copied path) as JSON")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.cli._output import print_json, wrote
    from wobble.errors import InputError
    from wobble.io.shipped import KINDS, copy_shipped, shipped_files, shown_names

    if args.list or args.name is None:  # bare 'wobble example' lists: what a newcomer typing it wants
        files = shipped_files()
        if args.json:
            print_json(
                [
                    {"name": f.name, "kind": f.kind, "qualified_name": f.qualified, "description": f.description}
                    for f in files
                ]
            )
            return 0
        names = dict(zip(map(id, files), shown_names(files)))  # a name several folders ship has its folder
        width = max(map(len, names.values()))
        for kind, label in KINDS.items():
            group = [f for f in files if f.kind == kind]
            if group:
                print(f"{label}:")
                for f in group:
                    print(f"  {names[id(f)]:<{width}}  {f.description}")
        return 0
    try:
        path = copy_shipped(args.name, args.dest, overwrite=args.overwrite)
    except InputError as exc:
        if exc.parameter != "output":
            raise
        raise InputError("DEST", args.dest, exc.allowed) from None  # the argument as typed ("sub/dir/")
    if args.json:
        print_json({"name": args.name, "output": str(path)})
    wrote(path, json_mode=args.json)
    return 0
