"""How every subcommand speaks: JSON for scripts, "wrote PATH" lines, numbers for people.

* ``--json`` prints one JSON document on stdout (:func:`print_json`; the format is
  :func:`wobble.io.text.dumps`);
* every file written is announced by one line ``wrote PATH`` (on stdout, or on stderr
  under ``--json`` so that stdout stays one JSON document);
* numbers in text go through :mod:`wobble.io.text` (re-exported here).
"""

from __future__ import annotations

import sys

from wobble.io.text import clean, decimals_for, dumps, duration, number, with_uncertainty

__all__ = [
    "clean",
    "dumps",
    "print_json",
    "wrote",
    "finish",
    "check_outputs",
    "number",
    "with_uncertainty",
    "decimals_for",
    "duration",
    "span_text",
]


def print_json(obj) -> None:
    """Print ``obj`` as one JSON document on stdout."""
    print(dumps(obj))


def wrote(path, *, json_mode: bool = False) -> None:
    """Announce a written file: ``wrote PATH`` (stderr under --json, stdout otherwise)."""
    print(f"wrote {path}", file=sys.stderr if json_mode else sys.stdout)


def finish(args, document, show, written) -> int:
    """The end of a command: ``document`` as JSON under ``--json``, else ``show()`` (which prints the
    text for people); then a ``wrote PATH`` line per file in ``written``. Returns the exit status, 0.

    A JSON object, or each object of a JSON list (one per body: chandler, modes, precession, whose files
    hold every body), gets ``output`` and ``plot`` for every file option the command has: null when not
    asked for, so its keys do not depend on the options (README, "Commands")."""
    for obj in document if isinstance(document, list) else [document]:
        if not isinstance(obj, dict):
            continue
        for name in ("output", "plot"):
            if hasattr(args, name) and name not in obj:
                path = getattr(args, name)
                obj[name] = None if not path else str(path)
    if args.json:
        print_json(document)
    else:
        show()
    for path in written:
        wrote(path, json_mode=args.json)
    return 0


#: File names a netCDF output may have (``-o``): a name that says another format is refused.
NETCDF_SUFFIXES = (".nc", ".nc4")


def check_outputs(args, names=("output", "plot"), *, zarr: bool = False) -> None:
    """Refuse, before any work, an output that exists (without --overwrite), is in a missing
    folder, or whose name says no format we write (``-o`` is netCDF, ``.nc``; a Zarr store, ``.zarr``,
    where ``zarr`` is true; ``--plot`` a figure): a long run must not end in an error a glance at
    its arguments could have given."""
    from pathlib import Path

    from wobble.errors import InputError, OutputExistsError

    overwrite = getattr(args, "overwrite", False)
    for name in names:
        path = getattr(args, name, None)
        if not path:
            continue
        if name == "plot":
            from wobble.plot.save import check_plot_path

            check_plot_path(path, overwrite)
            continue
        is_zarr = str(path).rstrip("/").endswith(".zarr")
        if not (Path(path).suffix.lower() in NETCDF_SUFFIXES or (zarr and is_zarr)):
            allowed = "a file name ending in .nc (netCDF)" + (" or a Zarr store ending in .zarr" if zarr else "")
            raise InputError("-o/--output" if name == "output" else f"--{name}", str(path), allowed)
        if is_zarr:
            # A Zarr store is a folder; an existing one is replaced as a whole with --overwrite.
            store = Path(path)
            if not (store.parent if str(store.parent) else Path(".")).is_dir():
                raise InputError("output", str(store), "a path in an existing folder")
            if store.exists() and not overwrite:
                raise OutputExistsError(store)
        else:
            from wobble.io.atomic import check_target

            check_target(path, overwrite)


def t_end_option(text: str, model, examples: str) -> float:
    """``--t-end`` in seconds (:func:`wobble.api.units.parse_duration`), checked against the model's own
    time limit (``model.check_times``: the reach of its exact phase reductions) and refused, if past it,
    under the option's name as typed."""
    import numpy as np

    from wobble.api.units import parse_duration
    from wobble.errors import InputError

    t_end = parse_duration(text, "--t-end", examples)
    try:
        model.check_times(np.array([t_end]))
    except InputError as exc:
        raise InputError("--t-end", text, exc.allowed) from None
    return t_end


def span_text(seconds: float, typed: str | None) -> str:
    """The end of an output span as the user gave it (``200 s``, ``100 yr (3.1557e+09 s)``), or,
    chosen by wobble, in the unit a person would use (:func:`wobble.io.text.duration`)."""
    from wobble.io.text import duration, is_number, number

    if typed is None:
        return duration(seconds)
    text = " ".join(str(typed).split())
    return f"{text} s" if is_number(text) else f"{text} ({number(seconds, 5)} s)"
