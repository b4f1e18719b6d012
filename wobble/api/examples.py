"""The files wobble ships, from Python: list them, find one, copy one to edit.

>>> import wobble
>>> [f.name for f in wobble.example_files("examples")]
['dumbbell.csv', 'my_planet.toml', 'planet.nc']
>>> wobble.example_path("tennis_racket").name
'tennis_racket.toml'
"""

from __future__ import annotations

import os
from pathlib import Path

from wobble.errors import InputError
from wobble.io.shipped import KINDS, ShippedFile, copy_shipped, find_shipped, shipped_files

__all__ = ["example_files", "example_path", "copy_example"]


def example_files(kind: str | None = None) -> list[ShippedFile]:
    """The shipped files (name, kind, description), optionally of one kind.

    Parameters
    ----------
    kind : str, optional
        ``bodies``, ``examples``, ``scenes`` or ``sweeps``.
    """
    if kind is not None and kind not in KINDS:
        raise InputError("kind", kind, f"one of {', '.join(KINDS)}")
    return shipped_files(kind)


def example_path(name: str) -> Path:
    """The installed path of the shipped file ``name`` (with or without its extension)."""
    found = find_shipped(name)
    if found is None:
        raise InputError("name", name, "a shipped file (wobble.example_files())")
    return Path(str(found.path()))


def copy_example(name: str, dest: str | os.PathLike | None = None, *, overwrite: bool = False) -> Path:
    """Copy the shipped file ``name`` to ``dest`` (file or folder; default the current folder)."""
    return copy_shipped(name, dest, overwrite=overwrite)
