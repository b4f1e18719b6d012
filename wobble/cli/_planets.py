"""What the planet commands (``chandler``, ``modes``, ``precession``) share: the bodies they
take, the outputs they write, and the way they report.

Each command adds its own options between :func:`add_bodies` and :func:`add_outputs`, turns
the bodies from :func:`bodies_from_args` into result objects (``to_dict()``, ``summary()``),
and hands them to :func:`report` with its Dataset builder and figure function.
"""

from __future__ import annotations

import importlib
from pathlib import Path

from wobble.errors import InputError

__all__ = ["add_bodies", "add_outputs", "bodies_from_args", "report"]


def add_bodies(p) -> None:
    """The positional BODY names and the repeatable ``--body-file``."""
    p.add_argument("bodies", nargs="*", metavar="BODY", help="catalogued planets (default: all of them)")
    p.add_argument(
        "--body-file",
        action="append",
        default=[],
        metavar="FILE",
        help="a planet file in the wobble/1 schema (repeatable; 'wobble example my_planet.toml' writes one to edit)",
    )


def add_outputs(p, plot_help: str) -> None:
    """``--json``, ``-o FILE.nc``, ``--overwrite`` and ``--plot FILE.png``."""
    p.add_argument("--json", action="store_true", help="print a JSON list, one object per body")
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write a CF-1.10 netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--plot", metavar="FILE.png", help=plot_help)


def bodies_from_args(args) -> list:
    """Catalogue names and resolved planet files, in the order given; every catalogued planet
    when none is given. Unknown names and unwritable outputs are refused before any work."""
    from wobble.api.chandler import known_planets
    from wobble.cli._output import check_outputs
    from wobble.io.shipped import resolve

    known = known_planets()
    seen = set()
    for name in args.bodies:
        if name.lower() not in known:
            raise InputError("BODY", name, f"one of {', '.join(known)} (files go with --body-file)")
        if name.lower() in seen:  # twice in a file's body index made wobble.load build a duplicate index
            raise InputError("BODY", f"{name} (given twice)", "each body once")
        seen.add(name.lower())
    check_outputs(args)
    # Paths, not strings: a file of one's own named "earth" is that file, not the catalogued Earth.
    files = [Path(resolve(f, ("examples", "bodies"), "--body-file", (".toml",))) for f in args.body_file]
    return list(args.bodies) + files or list(known)


def report(args, results, dataset, figure, text=None, document=None) -> int:
    """Write ``dataset(results)`` (``-o``) and the figure (``--plot``; ``figure`` names its function
    as ``"module:function"``, called ``function(results, path)``), print the
    JSON list (``document(result)`` per result, default ``result.to_dict()``) or the summaries
    (``text(result)``, default ``result.summary()``), then a ``wrote PATH`` line per file.
    Returns the exit status, 0."""
    from wobble.cli._output import finish

    written = []
    if args.output:
        from wobble.io.netcdf import write_netcdf

        written.append(write_netcdf(dataset(results), args.output, overwrite=args.overwrite, command=args.command_line))
    if args.plot:
        # "module:function", imported only here: matplotlib costs ~0.5 s that a table does not need.
        module, name = figure.split(":")
        getattr(importlib.import_module(module), name)(results, args.plot, overwrite=args.overwrite)
        written.append(args.plot)
    summary = text or (lambda r: r.summary())
    as_dict = document or (lambda r: r.to_dict())
    listing = [as_dict(r) for r in results] if args.json else None
    return finish(args, listing, lambda: print("\n\n".join(summary(r) for r in results)), written)
