"""Density grids from netCDF files, opened lazily so large grids stream from disk.

A density file holds a variable on dimensions ``x``, ``y``, ``z`` (any order) with
a mass-density ``units`` attribute and 1-D coordinates with length units, the way a
planetary-interior or CT model comes. :func:`open_density` keeps the file open
while the caller reads it slab by slab (:meth:`wobble.RigidBody.from_density`).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import xarray as xr

from wobble.errors import FileFormatError, InputError

__all__ = ["open_density"]


@contextmanager
def open_density(path: str | os.PathLike, var: str | None = None) -> Iterator[xr.DataArray]:
    """Open the density variable of a netCDF file lazily (a context manager).

    Parameters
    ----------
    path : path-like
        The netCDF file.
    var : str, optional
        Variable name; by default the only variable on dimensions x, y, z.

    Yields
    ------
    xarray.DataArray
        Not loaded: slices are read from disk when asked for.

    Raises
    ------
    wobble.errors.FileFormatError
        Missing or unreadable file, or no (or several) candidate variables.
    wobble.errors.InputError
        ``var`` is not a data variable of the file (named ``var``).
    """
    path = Path(path)
    if not path.is_file():
        raise FileFormatError(path, None, "no such file")
    try:
        ds = xr.open_dataset(path, engine="netcdf4", decode_times=False, decode_timedelta=False)
    except (OSError, ValueError) as exc:
        raise FileFormatError(path, None, f"not a readable netCDF file ({exc})") from None
    try:
        yield ds[_choose(path, ds, var)]
    finally:
        ds.close()


def _choose(path: Path, ds: xr.Dataset, var: str | None) -> str:
    if var is not None:
        if var not in ds.data_vars:
            # A refusal of the parameter var, as every other one names its parameter, and the file by its name:
            # a shipped file's installed path means nothing to the person who typed its name.
            names = ", ".join(map(str, ds.data_vars)) or "none"
            raise InputError("var", var, f"a data variable of {path.name}: {names}")
        return var
    candidates = [str(n) for n, v in ds.data_vars.items() if sorted(map(str, v.dims)) == ["x", "y", "z"]]
    if not candidates:
        raise FileFormatError(path, None, "no variable on dimensions x, y, z (a density grid)")
    if len(candidates) > 1:
        raise FileFormatError(
            path, None, f"several density candidates ({', '.join(candidates)}); choose one with --var"
        )
    return candidates[0]
