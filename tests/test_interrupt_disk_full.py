"""A full disk while writing: one line, exit status 2, the previous file intact, no temporary left.

Two ways, for every writer (netCDF written whole, streamed by ``wobble run`` and in blocks by ``wobble sweep``,
Zarr, PNG, the InferenceData file of ``wobble invert``, the copies of ``wobble example``, the TOML files of
``RigidBody.to_parameter_file``), each writer at least one way:

* simulated in-process: the write path of each writer is made to fail the way it fails on a full
  disk (xarray's netCDF write leaves part of the file and raises netCDF4's bare
  ``RuntimeError("NetCDF: HDF error")`` while the file system reports no free space; zarr's chunk
  writes, Pillow's PNG encoder and shutil's copy raise ``OSError(ENOSPC)``);
* for real, in a child process under a file-size limit (``RLIMIT_FSIZE`` with SIGXFSZ ignored): the
  operating system refuses every write past the limit with EFBIG, as a full disk refuses with
  ENOSPC (no loop device or size-limited file system is needed).
"""

from __future__ import annotations

import contextlib
import errno
import io
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from wobble.cli import main

PREVIOUS = b"previous result\n"


def _run(argv, folder: Path):
    out, err = io.StringIO(), io.StringIO()
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
    finally:
        os.chdir(cwd)
    return code, err.getvalue()


def _full_statvfs(real):
    def statvfs(path):
        s = real(path)
        return os.statvfs_result(
            (s.f_bsize, s.f_frsize, s.f_blocks, 0, 0, s.f_files, s.f_ffree, s.f_favail, s.f_flag, s.f_namemax)
        )

    return statvfs


@pytest.fixture
def full_netcdf(monkeypatch):
    """xarray's netCDF writes fail as netCDF4 does on a full disk: part of the file, then a bare
    RuntimeError("NetCDF: HDF error"), with the file system reporting no free space. (A Python
    subclass of netCDF4.Dataset cannot stand in: the library cannot free its instances.)"""
    import xarray as xr

    def to_netcdf(self, path=None, *args, **kwargs):
        with open(path, "wb") as fh:
            fh.write(b"\x89HDF\r\n\x1a\n partial")
        raise RuntimeError("NetCDF: HDF error")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    monkeypatch.setattr(os, "statvfs", _full_statvfs(os.statvfs))


def _no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.fixture
def full_zarr(monkeypatch):
    from zarr.storage import _local

    monkeypatch.setattr(_local, "_put", _no_space)


@pytest.fixture
def full_png(monkeypatch):
    from PIL import ImageFile

    def half_then_full(im, fp, *args, **kwargs):
        fp.write(b"\x89PNG\r\n\x1a\n partial")
        _no_space()

    monkeypatch.setattr(ImageFile, "_save", half_then_full)


@pytest.fixture
def full_copy(monkeypatch):
    monkeypatch.setattr(os, "sendfile", _no_space)


CASES = {
    "netcdf": ("full_netcdf", ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "-o", "prev.nc"]),
    "netcdf streamed (wobble run)": ("full_netcdf", ["run", "tennis_racket", "-o", "prev.nc"]),
    "netcdf in blocks (wobble sweep)": ("full_netcdf", ["sweep", "mars_chandler", "--members", "300", "-o", "prev.nc"]),
    "zarr (wobble sweep)": ("full_zarr", ["sweep", "mars_chandler", "--members", "300", "-o", "prev.zarr"]),
    "png": ("full_png", ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "--plot", "prev.png"]),
    "example copy": ("full_copy", ["example", "dumbbell.csv", "prev.csv"]),
}


@pytest.mark.parametrize("name", list(CASES))
def test_a_full_disk_is_one_line_and_keeps_the_previous_file(request, tmp_path, name):
    fixture, argv = CASES[name]
    target = tmp_path / argv[-1]
    target.write_bytes(PREVIOUS)
    request.getfixturevalue(fixture)
    code, err = _run([*argv, "--overwrite"], tmp_path)
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "No space left on device" in err and argv[-1] in err
    assert target.read_bytes() == PREVIOUS
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]


# One child process under a 1 kB file-size limit runs every writer (one interpreter: the
# imports are paid once) and reports each exit status and stderr.
_CHILD = textwrap.dedent("""
    import contextlib, io, json, os, resource, signal, sys
    from pathlib import Path
    from wobble.cli import main
    from wobble.api.bodies import RigidBody
    from astropy import units as u
    import wobble.api.inversion, wobble.api.sweep, wobble.api.scene, wobble.plot.free, zarr  # before the limit
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (1024, 1024))
    results = {}
    for argv in json.loads(sys.argv[1]):
        err = io.StringIO()
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = main(argv + ["--overwrite"])
        results[argv[-1]] = [code, err.getvalue()]
    try:
        RigidBody.cylinder(mass=1 * u.kg, radius=1 * u.m, height=2 * u.m).to_parameter_file("prev.toml", overwrite=True)
        results["prev.toml"] = [0, ""]
    except OSError as exc:
        results["prev.toml"] = [2, f"{exc.strerror} ({exc.filename})"]
    print(json.dumps(results))
""")

REAL = [
    ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "-o", "free.nc"],
    ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "--plot", "free.png"],
    ["sweep", "mars_chandler", "--members", "300", "-o", "sweep.zarr"],
    ["invert", "earth", "--steps", "20", "--burn", "5", "--quiet", "-o", "invert.nc"],
    ["example", "planet.nc", "planet.nc"],
]


@pytest.mark.slow
def test_a_real_file_size_limit_on_every_writer(tmp_path):
    names = [argv[-1] for argv in REAL] + ["prev.toml"]
    for name in names:
        (tmp_path / name).write_bytes(PREVIOUS)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONWARNINGS="ignore")
    child = subprocess.run(
        [sys.executable, "-c", _CHILD, json.dumps(REAL)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert child.returncode == 0, child.stderr[-2000:]
    results = json.loads(child.stdout.strip().splitlines()[-1])
    for name in names:
        code, err = results[name]
        assert code == 2, (name, err)
        assert "File too large" in err and "Traceback" not in err, (name, err)
        assert (tmp_path / name).read_bytes() == PREVIOUS, name
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(names)
