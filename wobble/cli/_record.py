"""What the commands on the IERS polar-motion record (``polar-motion``, ``excitation``, ``forecast``)
share: the record's options, the outputs they write, the way they report, and the way they read
their options as typed: :func:`parse_time` (a bare number is in the option's own unit, which its
help states), :func:`parse_q` and :func:`as_typed` (an API error named as the option).

Each command adds its own options around :func:`add_record` (or :func:`add_file`) and
:func:`add_outputs`, builds one result object (``to_dict()``, ``summary()``, ``to_dataset()``)
and hands it to :func:`report` with its figure function.
"""

from __future__ import annotations

import contextlib
import importlib
import re
from collections import namedtuple

from wobble.errors import InputError

__all__ = [
    "add_file",
    "check_file",
    "add_record",
    "add_outputs",
    "report",
    "Typed",
    "parse_time",
    "parse_q",
    "as_typed",
]


def add_file(p) -> None:
    """``--file``: the IERS series to read."""
    p.add_argument(
        "--file", metavar="PATH", help="an IERS C04 or finals2000A file (default: the C04 series of astropy-iers-data)"
    )


def check_file(args) -> None:
    """Refuse a ``--file`` that names no file (a folder, an empty path, none there) before any work,
    naming ``--file`` as ``--body-file`` is named (the reader said "no such file" of a folder)."""
    if args.file is not None:
        from wobble.io.eop import existing_eop_path

        existing_eop_path(args.file, "--file")


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
    from wobble.cli._stages import Stages

    written = []
    # Building the Dataset and drawing take seconds (xarray, dask, matplotlib on first use).
    with Stages() as stages:
        if args.output:
            from wobble.io.netcdf import write_netcdf

            stages(f"writing {args.output}")
            written.append(
                write_netcdf(result.to_dataset(), args.output, overwrite=args.overwrite, command=args.command_line)
            )
        if args.plot:
            # "module:function", imported only here: matplotlib costs ~0.5 s that a table does not need.
            module, name = figure.split(":")
            stages(f"drawing {args.plot}")
            written.append(getattr(importlib.import_module(module), name)(result, args.plot, overwrite=args.overwrite))
    document = result.to_dict() if args.json else None
    return finish(args, document, show or (lambda: print(result.summary())), written)


# An option's time as read: the Quantity, and the value as an error message shows it.
Typed = namedtuple("Typed", ["quantity", "shown"])


# A number as people type it, then whatever follows (the unit).
_NUMBER_THEN_UNIT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S.*?)\s*$")
_UNIT_NAMES = {"d": "days", "yr": "years"}


def parse_time(text, option: str, bare: str = "d", *, default: str | None = None) -> Typed | None:
    """``option``'s time, e.g. 433d, 90 or 8 yr, as a :class:`Typed` (None when neither given nor defaulted).

    A bare number is in ``bare`` ("d" or "yr", which the option's help states) and is shown as read
    ("3 d"); a number with a unit keeps the unit typed ("5 yr", "-5 d"). ``default`` is the text
    used when the option was not given; a message then says "(the default)".
    """
    if text is None:
        if default is None:
            return None
        read = parse_time(default, option, bare)
        return Typed(read.quantity, f"{read.shown} (the default)")
    from astropy import units as u

    raw = str(text).strip()
    # Examples in the option's own default unit: "90" would be 90 years for --window.
    examples = "433d, 90 or 8 yr" if bare == "d" else "8, 8 yr or 3000d"
    allowed = f"a time such as {examples} (a bare number is {_UNIT_NAMES.get(bare, bare)})"
    try:
        value = float(raw)
    except ValueError:
        pass
    else:
        return Typed(value * u.Unit(bare), f"{raw} {bare}")
    from wobble.io.quantity_values import quantity_from_text

    try:
        q = quantity_from_text(raw)
    except (ValueError, TypeError):
        raise InputError(option, text, allowed) from None
    if not q.isscalar or q.unit.physical_type != "time":
        raise InputError(option, text, allowed)
    match = _NUMBER_THEN_UNIT.fullmatch(raw)
    return Typed(q, f"{match[1]} {match[2]}" if match else str(q))


def parse_q(text):
    """--q as a float (inf allowed); None when not given."""
    if text is None:
        return None
    from wobble.api.polar_motion.forecast import Q_ALLOWED

    try:
        value = float(text)
    except ValueError:
        raise InputError("--q", text, Q_ALLOWED) from None
    if not value >= 1.0:
        raise InputError("--q", text, Q_ALLOWED)
    return value


@contextlib.contextmanager
def as_typed(options: dict):
    """InputErrors the API raises about its parameters, named as the options the user typed.

    ``options`` maps an API parameter (``chandler_period``) to ``(option, shown)``: the option's
    name as typed (``--period``) and its value as the user typed it (None: the API's own value,
    e.g. a date or "121 d of data before it"). The API keeps its Python names. Only what the
    command line's generic renaming (an API name equal to an option's dest, in wobble.cli.main)
    cannot do belongs here: other names (``chandler_period``, ``start/end``) and values shown with
    the unit a bare number was read in (``3 d``).
    """
    try:
        yield
    except InputError as exc:
        if exc.parameter not in options:
            raise
        option, shown = options[exc.parameter]
        raise InputError(option, exc.value if shown is None else shown, exc.allowed) from None
