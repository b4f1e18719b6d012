"""Saving figures the way wobble writes every file: checked first, atomic, mode from the umask."""

from __future__ import annotations

import os
from pathlib import Path

from wobble.errors import InputError
from wobble.io.atomic import atomic_target, check_target

__all__ = ["FORMATS", "check_plot_path", "save_figure"]

FORMATS = ("png", "pdf", "svg")


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


def save_figure(fig, path: str | os.PathLike, *, overwrite: bool = False, dpi: int = 150) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) under a temporary name, then rename.

    The figure is closed afterwards (a command draws once; pyplot would keep it alive).
    """
    import matplotlib.pyplot as plt

    path = check_plot_path(path, overwrite)
    try:
        with atomic_target(path, overwrite) as tmp:
            fig.savefig(tmp, dpi=dpi, format=path.suffix.lower().lstrip("."))
    finally:
        plt.close(fig)
    return path
