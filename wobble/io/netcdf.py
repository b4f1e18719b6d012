"""CF-1.10 netCDF files: atomic writes and wobble-aware reading.

Layout rules every wobble file follows (see docs/netcdf.md):

* global attributes ``Conventions``, ``title``, ``history``, ``source`` (wobble
  and its version), ``references`` (the literature, never an internal document); no
  ``institution``: wobble is not one, and the user's own is theirs to add;
* every variable has ``units`` (UDUNITS syntax: ``day``, ``rad s-1``, ``1``) and
  ``long_name``, and ``standard_name`` where the CF table has one;
* time coordinates are float64 with CF units ``"<unit> since <epoch>"``
  (``seconds since 2000-01-01 12:00:00`` for simulations, whose epoch is
  nominal unless the scene gives one); :func:`open_wobble` keeps them as
  numbers so round trips are exact (``xarray.decode_cf`` gives datetimes); past
  292,000 years from the epoch, elapsed time in ``s`` with ``time_origin``
  (:func:`wobble.io.cf.time_coordinate`: no reader decodes calendar times that far);
* string-valued indexes such as ``body`` or ``step`` cannot be CF coordinate
  variables (those must be numeric and monotonic), so they are stored as label
  variables ``body_name(body)`` (CF section 6.1) and turned back into indexes
  by :func:`open_wobble`.

Writing is atomic: the file is written under a temporary name in the target
folder and renamed into place, so a failed or interrupted run never leaves a
half-written file and never destroys an existing one. An existing file is
replaced only when ``overwrite=True``.
"""

from __future__ import annotations

import datetime as _dt
import os
from pathlib import Path

import numpy as np
import xarray as xr

from wobble.errors import FileFormatError, InputError
from wobble.io.atomic import atomic_target, check_target, interrupts_held, new_temporary, publish, write_error

__all__ = [
    "CONVENTIONS",
    "SIMULATION_TIME_UNITS",
    "write_netcdf",
    "write_netcdf_blocks",
    "open_wobble",
    "to_cf",
    "from_cf",
    "StreamingWriter",
    "simulation_time_units",
]

CONVENTIONS = "CF-1.10"
# CF time units for elapsed simulation time (the epoch is nominal: J2000.0).
SIMULATION_TIME_UNITS = "seconds since 2000-01-01 12:00:00"
_LABELS_ATTR = "wobble_label_indexes"
# Variables larger than this many elements are compressed and chunked.
_COMPRESS_MIN_SIZE = 4096


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("wobble")
    except PackageNotFoundError:  # running from a source tree without install
        return "unknown"


def to_cf(ds: xr.Dataset, *, command: str | None = None) -> xr.Dataset:
    """Return a copy of ``ds`` laid out for a CF netCDF file.

    String indexes become label variables ``<dim>_name``; the global
    attributes ``Conventions``, ``source`` and ``history`` are set (history
    gains a timestamped line naming ``command``).
    """
    out = ds.copy()
    # CF 7.1: a boundary variable takes everything from its coordinate; xarray would name the coordinates
    # of its dimension in a 'coordinates' attribute on it.
    for name in {str(v.attrs["bounds"]) for v in out.variables.values() if "bounds" in v.attrs} & set(out.variables):
        out.variables[name].encoding = {**out.variables[name].encoding, "coordinates": None}
    label_dims = [name for name in out.indexes if name in out.dims and is_label_index(out[name].values)]
    if label_dims:
        out = out.rename_vars({d: f"{d}_name" for d in label_dims})
        out.attrs[_LABELS_ATTR] = " ".join(label_dims)
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    line = f"{stamp} wobble {_version()}" + (f": {command}" if command else "")
    previous = out.attrs.get("history")
    out.attrs["history"] = f"{previous}\n{line}" if previous else line
    out.attrs["Conventions"] = CONVENTIONS
    out.attrs["source"] = f"wobble {_version()}"
    return out


def from_cf(ds: xr.Dataset) -> xr.Dataset:
    """Undo :func:`to_cf`'s label layout: ``body_name(body)`` becomes index ``body``."""
    dims = ds.attrs.get(_LABELS_ATTR, "").split()
    if not dims:
        return ds
    out = ds.rename_vars({f"{d}_name": d for d in dims})
    for d in dims:
        out = out.set_xindex(d)
    out.attrs = {k: v for k, v in out.attrs.items() if k != _LABELS_ATTR}
    return out


def simulation_time_units(epoch: str | None = None) -> str:
    """CF units of elapsed simulation time: seconds since ``epoch`` (UTC), or the nominal J2000.0."""
    return f"seconds since {epoch}" if epoch else SIMULATION_TIME_UNITS


_CHUNK_BYTES = 4 * 2**20


def _time_chunks(dims, shape, itemsize, time_chunk) -> tuple:
    """Chunks of at most ~4 MB: up to ``time_chunk`` times, splitting the largest other axis if needed."""
    sizes = {d: max(1, int(n)) for d, n in zip(dims, shape)}
    sizes["time"] = int(time_chunk)
    others = [d for d in dims if d != "time"]
    row = itemsize * int(np.prod([sizes[d] for d in others])) if others else itemsize
    sizes["time"] = int(max(1, min(time_chunk, _CHUNK_BYTES // row)))
    while others and itemsize * int(np.prod([sizes[d] for d in dims])) > _CHUNK_BYTES:
        big = max(others, key=lambda d: sizes[d])
        if sizes[big] == 1:
            break
        sizes[big] = (sizes[big] + 1) // 2
    return tuple(sizes[d] for d in dims)


def _encoding(ds: xr.Dataset, *, streaming: bool = False, time_chunk: int = 4096) -> dict:
    """Compression and time chunking for large variables; no fill value on coordinates and bounds.

    A streamed file compresses and chunks every numeric variable along time
    (its final size is not known when it is created).
    """
    encoding: dict = {}
    # CF 7.1: boundary variables take everything from their coordinate and have no fill value.
    bounds = {str(v.attrs["bounds"]) for v in ds.variables.values() if "bounds" in v.attrs}
    for name, var in ds.variables.items():
        enc: dict = {}
        if var.dtype.kind == "f" and (name in ds.coords or name in bounds):
            enc["_FillValue"] = None
        if streaming and "time" in var.dims and var.dtype.kind in "fiu":
            enc.update(zlib=True, complevel=4, shuffle=True)
            enc["chunksizes"] = _time_chunks(var.dims, var.shape, var.dtype.itemsize, time_chunk)
        elif var.size >= _COMPRESS_MIN_SIZE and var.dtype.kind in "fiu":
            enc.update(zlib=True, complevel=4, shuffle=True)
            if "time" in var.dims:
                chunks = [min(n, 65536) if d == "time" else n for d, n in zip(var.dims, var.shape)]
                enc["chunksizes"] = tuple(int(c) for c in chunks)
        if enc:
            encoding[name] = enc
    return encoding


def write_netcdf(
    ds: xr.Dataset,
    path: str | os.PathLike,
    *,
    overwrite: bool = False,
    command: str | None = None,
) -> Path:
    """Write ``ds`` as a CF-1.10 netCDF-4 file, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        Data with ``units`` and ``long_name`` on every variable.
    path : path-like
        Output file. Its folder must exist.
    overwrite : bool
        Replace an existing file. Without it an existing file is an error and
        is left untouched.
    command : str, optional
        Recorded in the ``history`` attribute.

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    wobble.errors.OutputExistsError
        ``path`` exists and ``overwrite`` is false.
    wobble.errors.InputError
        The folder does not exist or ``path`` is a folder, or ``ds`` is not a Dataset.
    """
    if not isinstance(ds, xr.Dataset):  # a dict or a DataArray raised AttributeError from inside to_cf
        hint = " (ds = array.to_dataset())" if isinstance(ds, xr.DataArray) else ""
        raise InputError("ds", type(ds).__name__, f"an xarray Dataset{hint}")
    path = Path(path)
    with atomic_target(path, overwrite) as tmp:
        cf = to_cf(ds, command=command)
        with interrupts_held():  # Ctrl-C inside xarray's locked writer can deadlock it
            cf.to_netcdf(tmp, format="NETCDF4", engine="netcdf4", encoding=_encoding(cf))
    return path


def write_netcdf_blocks(
    template: xr.Dataset,
    path: str | os.PathLike,
    blocks,
    *,
    overwrite: bool = False,
    command: str | None = None,
) -> Path:
    """Write a dataset whose data arrive in blocks, atomically and in bounded memory.

    ``template`` gives the layout: its data variables that are filled by
    ``blocks`` must be lazy (dask) arrays of the final shape, so writing the
    structure costs no memory; coordinates and small variables are written
    as they are. ``blocks`` yields ``(name, index, values)`` with ``index`` a
    tuple of slices into variable ``name``; each block is written into the
    temporary file as soon as it arrives (any dask scheduler can produce
    them: the writes happen here, in one process). The file is renamed into
    place only after the last block.

    Parameters
    ----------
    template : xarray.Dataset
        Layout with CF attributes; dask-backed variables are filled by blocks.
    path : path-like
        Output file (its folder must exist).
    blocks : iterable of (str, tuple of slice, numpy.ndarray)
        The data.
    overwrite, command
        As for :func:`write_netcdf`.
    """
    import netCDF4

    path = Path(path)
    with atomic_target(path, overwrite) as tmp:
        cf = to_cf(template, command=command)
        # compute=False writes the structure and the in-memory variables only.
        with interrupts_held():  # Ctrl-C inside xarray's locked writer can deadlock it
            cf.to_netcdf(tmp, format="NETCDF4", engine="netcdf4", encoding=_encoding(cf), compute=False)
        with netCDF4.Dataset(tmp, "a") as nc:
            nc.set_auto_maskandscale(False)
            for name, index, values in blocks:
                nc.variables[name][index] = values
    return path


def open_wobble(path: str | os.PathLike) -> xr.Dataset:
    """Read a netCDF file written by wobble, restoring its indexes.

    Parameters
    ----------
    path : path-like
        A file written by :func:`write_netcdf`.

    Returns
    -------
    xarray.Dataset
        Loaded into memory (the file is closed on return).

    Raises
    ------
    wobble.errors.FileFormatError
        Missing, unreadable, or not written by wobble.
    """
    path = Path(path)
    if path.is_dir():
        raise FileFormatError(
            path,
            None,
            "a folder, not a netCDF file (a Zarr store of wobble sweep opens with wobble.load, "
            "wobble.io.zarr_store.open_wobble_zarr or xarray.open_zarr)",
        )
    if not path.is_file():
        raise FileFormatError(path, None, "no such file")
    try:
        with xr.open_dataset(path, engine="netcdf4", decode_times=False, decode_timedelta=False) as ds:
            ds = ds.load()
    except (OSError, ValueError) as exc:
        raise FileFormatError(path, None, f"not a readable netCDF file ({exc})") from None
    source = str(ds.attrs.get("source", ""))
    if not source.startswith("wobble"):
        raise FileFormatError(path, "global attribute 'source'", f"got {source!r}; allowed: a file written by wobble")
    if ds.attrs.get(INFERENCE_DATA_ATTR):
        raise FileFormatError(
            path,
            None,
            "an inference-data file of wobble invert (ArviZ groups, nothing in the root group): open it with "
            "arviz.from_netcdf(path) or xarray.open_dataset(path, group='posterior')",
        )
    return from_cf(ds)


#: Root-group attribute that marks a file of ArviZ groups (wobble invert's posterior file).
INFERENCE_DATA_ATTR = "inference_data_groups"


def mark_inference_data(path, title: str, groups, *, command: str | None = None, references: str | None = None) -> None:
    """Give a file of ArviZ InferenceData groups the global attributes of every wobble file
    (``Conventions``, ``title``, ``source``, ``history``, and ``references`` when given) in its root group,
    which ArviZ leaves empty, and name its groups there (:data:`INFERENCE_DATA_ATTR`)."""
    import netCDF4

    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    with netCDF4.Dataset(path, "a") as nc:
        nc.setncatts(
            {
                "Conventions": CONVENTIONS,
                "title": title,
                **({"references": references} if references else {}),
                "source": f"wobble {_version()}",
                "history": f"{stamp} wobble {_version()}" + (f": {command}" if command else ""),
                INFERENCE_DATA_ATTR: " ".join(groups),
                "comment": "ArviZ InferenceData groups: open with arviz.from_netcdf(path), or one group with "
                "xarray.open_dataset(path, group='posterior')",
            }
        )


def is_label_index(values: np.ndarray) -> bool:
    """True for string-valued index arrays (stored as labels in CF files)."""
    return np.asarray(values).dtype.kind in "OUS"


class StreamingWriter:
    """Write a Dataset to CF netCDF block by block along ``time``, atomically.

    The first block is written by xarray (the same layout as
    :func:`write_netcdf`, with ``time`` unlimited, compressed and chunked
    along time); later blocks are appended to the same temporary file in the
    target folder; :meth:`close` sets the final global attributes and renames
    the file into place. Until then the target is untouched: an error or an
    interruption removes the temporary file (:meth:`discard`), and an
    existing file is replaced only with ``overwrite=True``.

    Parameters
    ----------
    path : path-like
        Output file (its folder must exist).
    overwrite : bool
        Replace an existing file.
    command : str, optional
        Recorded in ``history``.
    """

    def __init__(self, path, *, overwrite: bool = False, command: str | None = None):
        self.path = check_target(path, overwrite)
        self.command = command
        self.tmp = None
        self.rows = 0
        self._nc = None

    def begin(self) -> None:
        """Start (or restart) the temporary file."""
        self.discard()
        with interrupts_held():  # until the name is recorded for discard() (see new_temporary)
            self.tmp = new_temporary(self.path)
        self.rows = 0

    def append(self, block: xr.Dataset) -> None:
        """Append a block (a Dataset with a ``time`` dimension; the first one fixes the layout)."""
        try:
            self._append(block)
        except RuntimeError as exc:  # netCDF4's report of a refused write (a full disk)
            translated = write_error(exc, self.path)
            if translated is None:
                raise
            raise translated from exc

    def _append(self, block: xr.Dataset) -> None:
        if self.tmp is None:
            self.begin()
        if self.rows == 0:
            cf = to_cf(block, command=self.command)
            with interrupts_held():  # Ctrl-C inside xarray's locked writer can deadlock it
                cf.to_netcdf(
                    self.tmp,
                    mode="w",
                    format="NETCDF4",
                    engine="netcdf4",
                    encoding=_encoding(cf, streaming=True),
                    unlimited_dims=["time"],
                )
            import netCDF4

            self._nc = netCDF4.Dataset(self.tmp, mode="a")
            self.rows = block.sizes["time"]
            return
        n = block.sizes["time"]
        sl = slice(self.rows, self.rows + n)
        for name, var in block.variables.items():
            if "time" not in var.dims:
                continue
            nc_var = self._nc.variables[name]
            index = tuple(sl if d == "time" else slice(None) for d in var.dims)
            nc_var[index] = np.asarray(var.values)
        self.rows += n

    def close(self, attrs: dict | None = None) -> Path:
        """Set the final global attributes, close and move the file into place."""
        if self.tmp is None or self._nc is None:
            raise InputError("output", str(self.path), "at least one block of data before closing")
        try:
            for key, value in (attrs or {}).items():
                self._nc.setncattr(key, value)
            self._nc.close()
            self._nc = None
            publish(self.tmp, self.path)
        except BaseException as exc:
            self.discard()
            translated = write_error(exc, self.path)
            if translated is None:
                raise
            raise translated from exc
        self.tmp = None
        return self.path

    def discard(self) -> None:
        """Remove the temporary file (the target is never touched)."""
        with interrupts_held():  # a second Ctrl-C must not cut the clean-up short
            if self._nc is not None:
                try:
                    self._nc.close()
                except Exception:  # closing a broken file must not mask the real error
                    pass
                self._nc = None
            if self.tmp is not None:
                Path(self.tmp).unlink(missing_ok=True)
                self.tmp = None
            self.rows = 0
