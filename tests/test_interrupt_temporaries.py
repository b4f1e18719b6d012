"""Ctrl-C just after a temporary output is created, before its name reaches the clean-up, leaves nothing.

A clean-checkout CI run once left ``.sat.nc.PID.XXXXXXXX.tmp`` behind after Ctrl-C during
``wobble run ... -o sat.nc`` (test_interrupt.py): the interrupt landed between the creation of the
temporary file and the line that recorded its name, so the clean-up did not know there was one.
These tests put a real SIGINT at that point every time: ``tempfile.mkstemp`` (``mkdtemp`` for Zarr)
is wrapped to create the file and then signal this process, and Python raises the interrupt at its
next check, inside the wrapper, before the name is returned (the worst case).
"""

from __future__ import annotations

import os
import signal
import tempfile

import numpy as np
import pytest
import xarray as xr

from wobble.io.atomic import atomic_target
from wobble.io.netcdf import StreamingWriter, write_netcdf


# Python's own Ctrl-C handler for each test (tests/conftest.py): these tests are about it.
pytestmark = pytest.mark.usefixtures("python_ctrl_c")


def _interrupting(make):
    """``make`` (mkstemp or mkdtemp), then SIGINT to this process once the file or folder exists."""

    def wrapped(*args, **kwargs):
        made = make(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGINT)
        return made

    return wrapped


@pytest.fixture
def interrupt_on_create(monkeypatch):
    """SIGINT to this process right after each temporary file or folder is created."""
    monkeypatch.setattr(tempfile, "mkstemp", _interrupting(tempfile.mkstemp))
    monkeypatch.setattr(tempfile, "mkdtemp", _interrupting(tempfile.mkdtemp))


def _block(n=4):
    return xr.Dataset({"x": (("time",), np.arange(n, dtype=float))}, coords={"time": np.arange(n, dtype=float)})


def _contents(folder):
    return sorted(p.name for p in folder.iterdir())


def test_atomic_target(tmp_path, interrupt_on_create):
    with pytest.raises(KeyboardInterrupt):
        with atomic_target(tmp_path / "out.txt", overwrite=False) as tmp:
            open(tmp, "w").write("data")
    assert _contents(tmp_path) == []


def test_atomic_target_keeps_the_previous_file(tmp_path, interrupt_on_create):
    (tmp_path / "out.txt").write_text("previous")
    with pytest.raises(KeyboardInterrupt):
        with atomic_target(tmp_path / "out.txt", overwrite=True) as tmp:
            open(tmp, "w").write("data")
    assert _contents(tmp_path) == ["out.txt"]
    assert (tmp_path / "out.txt").read_text() == "previous"


def test_write_netcdf(tmp_path, interrupt_on_create):
    with pytest.raises(KeyboardInterrupt):
        write_netcdf(_block(), tmp_path / "out.nc")
    assert _contents(tmp_path) == []


def test_streaming_writer_as_run_to_netcdf_uses_it(tmp_path, interrupt_on_create):
    # The same sequence as wobble.api.scene.run_to_netcdf: begin/append/close, discard on any exception.
    writer = StreamingWriter(tmp_path / "out.nc")
    with pytest.raises(KeyboardInterrupt):
        try:
            writer.begin()
            writer.append(_block())
            writer.close()
        except BaseException:
            writer.discard()
            raise
    assert _contents(tmp_path) == []


def test_streaming_writer_restarted_for_a_second_attempt(tmp_path, monkeypatch):
    # A rejected attempt is discarded and the file begun again (models/scene.execute): interrupt the second creation.
    writer = StreamingWriter(tmp_path / "out.nc")
    writer.begin()
    writer.append(_block())
    monkeypatch.setattr(tempfile, "mkstemp", _interrupting(tempfile.mkstemp))
    with pytest.raises(KeyboardInterrupt):
        try:
            writer.discard()
            writer.begin()
        except BaseException:
            writer.discard()
            raise
    assert _contents(tmp_path) == []


def test_zarr_store(tmp_path, interrupt_on_create):
    pytest.importorskip("zarr")
    from wobble.io.zarr_store import write_zarr_blocks

    template = _block().chunk()
    with pytest.raises(KeyboardInterrupt):
        write_zarr_blocks(template, tmp_path / "out.zarr", [("x", (slice(0, 4),), np.ones(4))])
    assert _contents(tmp_path) == []
