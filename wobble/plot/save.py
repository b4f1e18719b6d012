"""Saving figures the way wobble writes every file: checked first, atomic, mode from the umask."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from wobble.errors import InputError
from wobble.io.atomic import atomic_target, check_target

__all__ = ["FORMATS", "WIDE_DPI", "check_plot_path", "save_figure"]

FORMATS = ("png", "pdf", "svg")
#: The resolution of the wide, many-panel figures (the polar-motion overview, the excitation, forecast and
#: hindcast figures, the corner plot): their text reads at 110 dots per inch, and 150 would give their PNGs
#: nearly twice the pixels.
WIDE_DPI = 110


def check_plot_path(path: str | os.PathLike, overwrite: bool = False, parameter: str = "--plot") -> Path:
    """Refuse a bad figure path before any work: wrong suffix, missing folder, existing file."""
    path = Path(path)
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in FORMATS:
        raise InputError(parameter, str(path), "a file name ending in .png, .pdf or .svg")
    try:
        return check_target(path, overwrite)
    except InputError as exc:
        raise InputError(parameter, exc.value, exc.allowed) from None


def save_figure(
    fig, path: str | os.PathLike, *, overwrite: bool = False, dpi: int = 150, parameter: str = "path"
) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) under a temporary name, then rename.

    The path is checked first (:func:`check_plot_path`), the figure is drawn into a temporary file
    beside it and renamed onto it (:func:`wobble.io.atomic.atomic_target`): the file gets the
    umask's mode like every other output, a failed draw leaves nothing behind, and an existing file
    is replaced only with ``overwrite``. A figure pyplot manages is closed afterwards, written or
    refused (a command draws once; pyplot would keep it alive); a bare
    ``matplotlib.figure.Figure`` needs no closing, and pyplot is not imported for it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to write.
    path : path-like
        The file, ending in .png, .pdf or .svg.
    overwrite : bool
        Replace an existing file.
    dpi : int
        Resolution of a PNG.
    parameter : str
        The name a refused path is reported under: the Python argument (the command line checks
        ``--plot`` itself, before any work).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    try:
        path = check_plot_path(path, overwrite, parameter)
        with atomic_target(path, overwrite) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix.lower().lstrip("."))
    finally:
        _close(fig)
    return path


def _close(fig) -> None:
    """Release ``fig`` from pyplot, if pyplot holds it (it holds only figures it made)."""
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None and getattr(getattr(fig, "canvas", None), "manager", None) is not None:
        pyplot.close(fig)
