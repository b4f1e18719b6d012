"""What the commands on the IERS polar-motion record (``polar-motion``, ``excitation``, ``forecast``)
share: the record's options, the outputs they write, and the way they report.

Each command adds its own options around :func:`add_record` (or :func:`add_file`) and
:func:`add_outputs`, builds one result object (``to_dict()``, ``summary()``, ``to_dataset()``)
and hands it to :func:`report` with its figure function.
"""

from __future__ import annotations

import importlib

__all__ = ["add_file", "add_record", "add_outputs", "report"]


def add_file(p) -> None:
    """``--file``: the IERS series to read."""
    p.add_argument(
        "--file", metavar="PATH", help="an IERS C04 or finals2000A file (default: the C04 series of astropy-iers-data)"
    )


def add_record(p) -> None:
    """``--start``, ``--end`` and ``--file``: which days of which series."""
    p.add_argument("--start", metavar="DATE", help="first day to use (default: the file's first)")
    p.add_argument("--end", metavar="DATE", help="last day to use (default: the file's last)")
    add_file(p)


def add_outputs(p, *, output_help: str, plot_help: str, json_help: str = "print the results as JSON") -> None:
    """``--json``, ``-o FILE.nc``, ``--overwrite`` and ``--plot FILE.png``."""
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("-o", "--output", metavar="FILE.nc", help=output_help)
    p.add_argument("--overwrite", action="store_true", help="replace existing output files")
    p.add_argument("--plot", metavar="FILE.png", help=plot_help)


def report(args, result, figure: str, show=None) -> int:
    """Write ``result.to_dataset()`` (``-o``) and the figure (``--plot``; ``figure`` names its function as
    ``"module:function"``, called ``function(result, path, overwrite=...)`` and returning the path written),
    print ``result.to_dict()`` as JSON or the text (``show()``, default: print ``result.summary()``),
    then a ``wrote PATH`` line per file. Returns the exit status, 0."""
    from wobble.cli._output import finish

    written = []
    if args.output:
        from wobble.io.netcdf import write_netcdf

        written.append(
            write_netcdf(result.to_dataset(), args.output, overwrite=args.overwrite, command=args.command_line)
        )
    if args.plot:
        # "module:function", imported only here: matplotlib costs ~0.5 s that a table does not need.
        module, name = figure.split(":")
        written.append(getattr(importlib.import_module(module), name)(result, args.plot, overwrite=args.overwrite))
    document = result.to_dict() if args.json else None
    return finish(args, document, show or (lambda: print(result.summary())), written)
