"""Zarr stores with the CF layout of wobble's netCDF files, streamed block by block.

For sweeps too large or too parallel for one netCDF file: a Zarr store (format 2, a
folder of chunk files) holds the same variables, attributes and label indexes as
:func:`wobble.io.netcdf.write_netcdf_blocks` writes, and is filled chunk by chunk so
memory stays bounded. zarr is an optional dependency (``pip install "wobble[zarr]"``).

Atomic like every wobble output: the store is built in a temporary folder next to the
target and renamed into place after the last block; an existing store is replaced only
with ``overwrite=True`` (the old one is moved aside first and removed after the rename).
"""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

import xarray as xr

from wobble.errors import FileFormatError, InputError, OutputExistsError
from wobble.io.atomic import interrupts_held, new_temporary_folder
from wobble.io.netcdf import from_cf, to_cf

__all__ = ["is_zarr_path", "is_zarr_store", "open_wobble_zarr", "write_zarr_blocks"]

#: Zarr format 2: every reader (zarr-python 2 and 3, xarray, Julia, R) opens it, and it has a
#: stable representation of the fixed-width label strings CF label variables use.
ZARR_FORMAT = 2


def is_zarr_path(path) -> bool:
    """Whether an output path asks for a Zarr store (its name ends in ``.zarr``)."""
    return str(path).rstrip("/\\").endswith(".zarr")


def is_zarr_store(path) -> bool:
    """Whether ``path`` is a Zarr store on disk, whatever its name: a folder with Zarr's format-2 or
    format-3 metadata (``.zgroup``, ``zarr.json``)."""
    folder = Path(path)
    return folder.is_dir() and ((folder / ".zgroup").is_file() or (folder / "zarr.json").is_file())


def _zarr(path=None):
    """zarr, or a clear error: for writing (no ``path``), name the output; for reading, the store."""
    try:
        import zarr
    except ModuleNotFoundError:
        if path is not None:
            raise FileFormatError(path, None, 'a Zarr store, which needs zarr: pip install "wobble[zarr]"') from None
        raise InputError(
            "output", "*.zarr", 'a .nc file, or install zarr for Zarr output: pip install "wobble[zarr]"'
        ) from None
    return zarr


def write_zarr_blocks(
    template: xr.Dataset, path, blocks, *, overwrite: bool = False, command: str | None = None
) -> Path:
    """Write a dataset whose data arrive in blocks into a Zarr store, atomically, in bounded memory.

    Same contract as :func:`wobble.io.netcdf.write_netcdf_blocks`: ``template``'s lazy
    (dask) variables give the layout and are filled by ``blocks``, an iterable of
    ``(name, index, values)`` with ``index`` a tuple of slices.
    """
    zarr = _zarr()
    path = Path(path)
    if path.exists() and not overwrite:
        raise OutputExistsError(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError("output", str(path), "a path in an existing folder")
    tmp = None
    try:
        with interrupts_held():  # until the name is recorded for the clean-up (see new_temporary)
            tmp = new_temporary_folder(path)
        cf = to_cf(template, command=command)
        # compute=False writes the metadata and the in-memory variables only.
        cf.to_zarr(tmp, mode="w", compute=False, zarr_format=ZARR_FORMAT, consolidated=False)
        group = zarr.open_group(str(tmp), mode="r+", zarr_format=ZARR_FORMAT)
        for name, index, values in blocks:
            group[name][index] = values
        zarr.consolidate_metadata(str(tmp), zarr_format=ZARR_FORMAT)
        # Ctrl-C between moving an old store aside and renaming the new one into place would leave the
        # user's store under a temporary name that a later run removes: the renames go together.
        with interrupts_held():
            _replace(tmp, path)
    except BaseException as exc:
        if tmp is not None:
            with interrupts_held():  # a second Ctrl-C must not cut the clean-up short
                _remove(tmp)
        if isinstance(exc, OSError) and exc.errno and not exc.filename:  # zarr's writes do not name the store
            raise OSError(exc.errno, exc.strerror or os.strerror(exc.errno), str(path)) from exc
        raise
    return path


def _remove(tmp: Path, settle: float = 2.0) -> None:
    """Remove the temporary store, again if needed: after Ctrl-C, zarr's own I/O thread may still
    finish a chunk it was writing (and recreate its folder) just after the first removal."""
    deadline = time.monotonic() + settle
    while True:
        shutil.rmtree(tmp, ignore_errors=True)
        time.sleep(0.05)
        if not tmp.exists() or time.monotonic() > deadline:
            return


def _replace(tmp: Path, path: Path) -> None:
    """Rename the finished store onto ``path``; an old store is moved aside, then removed."""
    old = None
    if path.exists():
        old = new_temporary_folder(path, ".old")
        os.rmdir(old)
        os.replace(path, old)
    os.replace(tmp, path)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True) if old.is_dir() else old.unlink()


def open_wobble_zarr(path) -> xr.Dataset:
    """Read a Zarr store written by wobble into memory, restoring its label indexes."""
    path = Path(path)
    if not path.is_dir():
        raise FileFormatError(path, None, "no such Zarr store")
    _zarr(path)
    try:
        with xr.open_zarr(path, decode_times=False, decode_timedelta=False) as ds:
            ds = ds.load()
    except (OSError, ValueError, KeyError) as exc:
        raise FileFormatError(path, None, f"not a readable Zarr store ({exc})") from None
    source = str(ds.attrs.get("source", ""))
    if not source.startswith("wobble"):
        raise FileFormatError(path, "global attribute 'source'", f"got {source!r}; allowed: a store written by wobble")
    return from_cf(ds)
