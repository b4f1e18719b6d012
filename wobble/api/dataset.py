"""Reading wobble's netCDF files back, with units: :func:`load` and the ``ds.wobble`` accessor.

Files keep CF units as UDUNITS strings (``rad s-1``, ``kg m2 s-1``, ``J``,
``1``); :func:`quantity` turns a variable into an :class:`astropy.units.Quantity`,
and ``ds.wobble.quantity(name)`` / ``ds.wobble.quantities()`` do the same from a
Dataset. Times stay numbers (seconds since the epoch in their units attribute):
``ds.wobble.quantity("time")`` is elapsed time as a Quantity, and
``ds.wobble.epoch`` the epoch.

Example
-------
>>> import astropy.units as u
>>> import wobble
>>> ds = wobble.run(wobble.Scene(body=[1, 1, 2] * u.kg * u.m**2, omega0=[0.1, 0, 1] * u.rad / u.s,
...                              t_end=10 * u.s, samples=11, outputs=["omega", "kinetic_energy"]))
>>> ds.wobble.quantity("kinetic_energy")[0]
<Quantity 1.005 J>
"""

from __future__ import annotations

import os
import re

import numpy as np
import xarray as xr
from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.cf import astropy_unit_text
from wobble.io.netcdf import open_wobble

__all__ = ["load", "quantity", "WobbleAccessor", "xarray", "build"]

_SINCE = re.compile(r"^\s*(\w+)\s+since\s+(.+?)\s*$")
# UDUNITS time words astropy does not know by these names.
_TIME_WORDS = {
    "second": "s",
    "seconds": "s",
    "sec": "s",
    "secs": "s",
    "minute": "min",
    "minutes": "min",
    "hour": "h",
    "hours": "h",
    "day": "d",
    "days": "d",
}


def _unit(text: str, name: str) -> u.UnitBase:
    match = _SINCE.match(text)
    if match:
        text = match.group(1)
    text = _TIME_WORDS.get(text.strip(), text)
    text = astropy_unit_text(text)  # the UDUNITS names wobble writes (Julian_year, milliarcsecond)
    try:
        return u.Unit(text if text.strip() != "1" else "", parse_strict="raise")
    except ValueError:
        raise InputError(name, text, "a variable whose units attribute astropy can parse (UDUNITS syntax)") from None


def quantity(var: xr.DataArray) -> u.Quantity:
    """The values of a variable as a Quantity in its ``units`` (time: elapsed, in its unit).

    Raises
    ------
    wobble.errors.InputError
        The variable has no ``units`` attribute, or one astropy cannot parse.
    """
    if not isinstance(var, (xr.DataArray, xr.Variable)):
        raise InputError("var", type(var).__name__, "a variable of a Dataset (ds['name'])")
    name = str(getattr(var, "name", None) or "variable")  # an xarray Variable has no name
    units = var.attrs.get("units")
    if units is None:
        raise InputError(name, var.attrs, "a variable with a units attribute")
    return var.values << _unit(str(units), name)


@xr.register_dataset_accessor("wobble")
class WobbleAccessor:
    """``ds.wobble``: units for wobble Datasets (registered on ``import wobble``)."""

    def __init__(self, ds: xr.Dataset):
        self._ds = ds

    def quantity(self, name: str) -> u.Quantity:
        """Variable ``name`` as a Quantity."""
        if name not in self._ds.variables:
            raise InputError("name", name, "one of " + ", ".join(sorted(map(str, self._ds.variables))))
        return quantity(self._ds[name])

    def quantities(self) -> dict:
        """Every data variable with units, as Quantities; flags (CF ``flag_values``: ``applied``,
        ``invalid_reason``, ``chandler_resolved``) are labels, not quantities, and are left out (a Quantity
        turned their integer codes into floats)."""
        return {
            str(k): quantity(v)
            for k, v in self._ds.data_vars.items()
            if "units" in v.attrs and "flag_values" not in v.attrs
        }

    @property
    def epoch(self) -> str | None:
        """The epoch of the time coordinate (``"2000-01-01 12:00:00"``), or None."""
        if "time" not in self._ds.variables:
            return None
        attrs = self._ds["time"].attrs
        match = _SINCE.match(str(attrs.get("units", "")))
        # A span past CF's decodable calendar range keeps its epoch apart (wobble.io.cf.time_coordinate).
        return match.group(2) if match else attrs.get("time_origin")

    @property
    def model(self) -> str | None:
        """The model that produced the data (``free-elliptic``, ``splitting-6``, ...)."""
        return self._ds.attrs.get("model")


def xarray():
    """The xarray module, with the ``ds.wobble`` accessor registered.

    API modules import xarray through this function, inside the functions that
    build Datasets: a command that prints a table never pays for xarray and
    pandas (~0.4 s), and every Dataset wobble returns has its accessor.
    """
    return xr


# Default indexes of the string-labelled dimensions (axis, component, ...) and their data
# adapters, by name and labels: xarray's indexes (and the adapters over them) are immutable and
# shared between Datasets, so one per label set will do; each Dataset gets its own variable.
_LABEL_INDEXES: dict = {}


def build(data_vars: dict, coords: dict, attrs: dict | None = None) -> xr.Dataset:
    """``xr.Dataset(data_vars, coords=coords, attrs=attrs)``, built without the general merge.

    For wobble's own Datasets, whose entries are ``(dims, numpy data, attrs)`` tuples from
    the CF registry (:func:`wobble.io.cf.variable`, ``time_coordinate``, ``label_coordinate``)
    and whose dimension coordinates are 1-D: every variable is made as the general
    constructor makes it, every dimension coordinate gets xarray's default index
    (``PandasIndex.from_variables``, as xarray's ``create_default_index_implicit``), in the
    same order, so the Dataset is the one ``xr.Dataset(...)`` returns (tested), without its
    merge and alignment (about 1 ms for a heavy top's 19 variables). Anything else
    (conflicting sizes, a coordinate that is not a tuple, an xarray without the direct
    constructor) goes through ``xr.Dataset``, which raises or builds as usual.
    """
    from xarray.core.indexes import PandasIndex

    construct = getattr(xr.Dataset, "_construct_direct", None)
    entries = {**data_vars, **coords}
    if (
        construct is None
        or len(entries) != len(data_vars) + len(coords)
        or not all(isinstance(v, tuple) and len(v) == 3 for v in entries.values())
    ):
        return _general(data_vars, coords, attrs)
    variables: dict = {}
    dims: dict = {}
    indexes: dict = {}
    for name, (vdims, data, vattrs) in entries.items():
        cached = (
            _LABEL_INDEXES.get((name, tuple(data)))
            if name in coords
            and vdims in (name, (name,))
            and isinstance(data, (list, tuple))
            and all(isinstance(x, str) for x in data)
            else None
        )
        if cached is not None:  # a label coordinate seen before: its index and the index's data adapter
            index, adapter = cached
            if dims.setdefault(name, len(data)) != len(data):
                return _general(data_vars, coords, attrs)
            variables[name] = xr.IndexVariable((name,), adapter, attrs=vattrs, fastpath=True)
            indexes[name] = index
            continue
        # A numeric NumPy array is what xarray's own checks (as_compatible_data) would hand on
        # unchanged: they are skipped for it.
        plain = type(data) is np.ndarray and data.ndim > 0 and data.dtype.kind in "biufc"
        var = xr.Variable(vdims, data, vattrs, fastpath=plain)
        for dim, size in zip(var.dims, var.shape):
            if dims.setdefault(dim, size) != size:
                return _general(data_vars, coords, attrs)
        if name in coords and var.dims == (name,):  # a dimension coordinate: the default index
            labels = isinstance(data, (list, tuple)) and all(isinstance(x, str) for x in data)
            if plain and data.ndim == 1 and data.dtype.kind in "iuf" and data.dtype != np.float16:
                # What from_variables makes of a plain numeric array (pd.Index of its values,
                # named, with the variable's dtype), without its generic checks and copies.
                import pandas as pd

                index = PandasIndex(pd.Index(data, name=name), name, coord_dtype=var.dtype, fastpath=True)
            else:
                index = PandasIndex.from_variables({name: var}, options={})
            var = index.create_variables({name: var})[name]
            if labels and vdims in (name, (name,)):
                _LABEL_INDEXES[(name, tuple(data))] = (index, var._data)
            indexes[name] = index
        elif name in coords and name in var.dims:
            return _general(data_vars, coords, attrs)  # a multi-dimensional coordinate named as its dimension
        variables[name] = var
    if any(dim in entries and dim not in indexes for dim in dims):
        return _general(data_vars, coords, attrs)  # a data variable named as a dimension
    return construct(variables, set(coords), dims, dict(attrs) if attrs else {}, indexes)


def _general(data_vars, coords, attrs):
    ds = xr.Dataset(data_vars, coords=coords)
    if attrs:
        ds.attrs.update(attrs)
    return ds


def load(path: str | os.PathLike) -> xr.Dataset:
    """Read a netCDF file (or a Zarr store of ``wobble sweep``) written by wobble (units via
    ``ds.wobble.quantity(name)``).

    Raises
    ------
    wobble.errors.FileFormatError
        Missing, unreadable, or not written by wobble (its ``source``
        attribute does not name wobble).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> import wobble
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = wobble.write_netcdf(wobble.chandler_dataset([wobble.chandler_budget("mars")]),
    ...                            Path(folder.name) / "mars.nc")
    >>> ds = wobble.load(path)
    >>> model, observed = ds.wobble.quantity("model_period")[0], ds.wobble.quantity("observed_period")[0]
    >>> print(f"{model:.1f} model, {observed:.1f} observed")
    205.6 d model, 206.9 d observed
    >>> folder.cleanup()
    """
    from wobble.io.zarr_store import is_zarr_store, open_wobble_zarr

    # A Zarr store of wobble sweep is read as open_wobble_zarr reads it (it was refused here, by name).
    ds = open_wobble_zarr(path) if is_zarr_store(path) else open_wobble(path)
    if "Conventions" not in ds.attrs:
        raise FileFormatError(path, "global attribute 'Conventions'", "missing; allowed: a CF file written by wobble")
    return ds
