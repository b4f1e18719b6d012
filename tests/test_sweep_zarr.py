"""Sweeps streamed to Zarr: the same data, attributes and indexes as the netCDF file; atomic."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import wobble
from wobble.errors import FileFormatError, OutputExistsError
from wobble.io.zarr_store import open_wobble_zarr, write_zarr_blocks

pytest.importorskip("zarr")

SWEEPS = Path(__file__).resolve().parents[1] / "data" / "sweeps"


def _same(a: xr.Dataset, b: xr.Dataset) -> None:
    # history carries the time of writing; everything else must be identical
    xr.testing.assert_identical(
        a.drop_attrs(deep=False).assign_attrs({k: v for k, v in a.attrs.items() if k != "history"}),
        b.drop_attrs(deep=False).assign_attrs({k: v for k, v in b.attrs.items() if k != "history"}),
    )


@pytest.mark.parametrize("name, chunks", [("mars_chandler", (7000, 30000)), ("top_phase_diagram", (5000, 20000))])
def test_zarr_store_equals_the_netcdf_file_whatever_the_chunking(tmp_path, name, chunks):
    spec = SWEEPS / f"{name}.toml"
    nc = wobble.run_sweep(spec, tmp_path / "a.nc", chunk_size=chunks[0])
    zs = wobble.run_sweep(spec, tmp_path / "a.zarr", chunk_size=chunks[1])
    _same(nc, zs)
    _same(zs, open_wobble_zarr(tmp_path / "a.zarr"))  # save-reopen round trip
    _same(zs, wobble.load(tmp_path / "a.zarr"))  # wobble.load reads a store too (it refused it by name)


def test_zarr_output_is_atomic(tmp_path):
    out = tmp_path / "m.zarr"
    first = wobble.run_sweep(SWEEPS / "mars_chandler.toml", out)
    with pytest.raises(OutputExistsError):
        wobble.run_sweep(SWEEPS / "mars_chandler.toml", out)
    template = first[["chandler_period"]].chunk()

    def failing():
        yield "chandler_period", (slice(0, 10),), np.zeros(10)
        raise RuntimeError("interrupted")

    with pytest.raises(RuntimeError, match="interrupted"):
        write_zarr_blocks(template, out, failing(), overwrite=True)
    _same(open_wobble_zarr(out), first)  # the old store is untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.zarr"]  # no temporary left
    again = wobble.run_sweep(SWEEPS / "mars_chandler.toml", out, overwrite=True)
    _same(again, first)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.zarr"]


def test_not_a_wobble_store(tmp_path):
    xr.Dataset({"x": ("n", np.arange(3.0))}).to_zarr(tmp_path / "other.zarr", zarr_format=2, consolidated=True)
    with pytest.raises(FileFormatError, match="source"):
        open_wobble_zarr(tmp_path / "other.zarr")
    with pytest.raises(FileFormatError, match="no such"):
        open_wobble_zarr(tmp_path / "missing.zarr")


def test_reading_a_store_without_zarr_names_the_store(tmp_path, monkeypatch):
    """Without zarr, reading a store (wobble.load reads them now) said "output: got *.zarr", the writer's
    message; it names the store and how to install zarr."""
    xr.Dataset({"x": ("n", np.arange(3.0))}).to_zarr(tmp_path / "s.zarr", zarr_format=2, consolidated=True)
    monkeypatch.setitem(sys.modules, "zarr", None)  # import zarr raises ModuleNotFoundError
    with pytest.raises(FileFormatError, match=r"s\.zarr.*a Zarr store, which needs zarr: pip install"):
        wobble.load(tmp_path / "s.zarr")
