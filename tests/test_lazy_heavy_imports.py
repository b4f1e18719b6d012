"""Heavy libraries are loaded where a command uses them, not on the way (a profile of 2026-11-30 found
each of these costing about a second of a few-second command). Checked in a fresh interpreter: which
modules a call leaves in ``sys.modules``, not how long it takes (no timing in tests)."""

from __future__ import annotations

import subprocess
import sys

import pytest


def _loaded_after(code: str, modules: tuple[str, ...]) -> dict[str, bool]:
    probe = f"import sys\n{code}\nprint(' '.join(str(m in sys.modules) for m in {modules!r}))"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    return dict(zip(modules, (w == "True" for w in done.stdout.split()[-len(modules) :])))


def test_a_local_sweep_does_not_load_dask_distributed():
    """Given a scheduler's name, dask imports dask.distributed to look for a client; wobble gives it the local
    get function instead (0.3-1.1 s of a 3-5 s sweep)."""
    pytest.importorskip("dask")
    code = (
        "import wobble\n"
        "spec = {'schema': 'wobble-sweep/1', 'name': 's', 'target': 'chandler', 'body': 'mars', 'members': 50,\n"
        "        'outputs': ['chandler_period'], 'vary': {'love_number_k2': {'distribution': 'normal'}}}\n"
        "for scheduler in ('threads', 'synchronous'):\n"
        "    assert wobble.run_sweep(spec, scheduler=scheduler).sizes['member'] == 50\n"
    )
    assert _loaded_after(code, ("dask", "distributed")) == {"dask": True, "distributed": False}


def test_a_free_body_on_a_long_grid_does_not_load_numba():
    """The compiled grid saves about a millisecond; importing Numba and loading the kernel cost about a second.
    It runs only where Numba is loaded already; the NumPy path gives the same numbers (test_free_model)."""
    code = (
        "import astropy.units as u, wobble\n"
        "fr = wobble.FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)\n"
        "assert fr.to_dataset(t_end=1000 * u.s, samples=20001).sizes['time'] == 20001\n"
    )
    assert _loaded_after(code, ("numba",)) == {"numba": False}
