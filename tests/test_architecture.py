"""The layer rule, enforced: import-linter contracts from pyproject.toml."""

from __future__ import annotations

from pathlib import Path

from importlinter.cli import lint_imports

ROOT = Path(__file__).resolve().parents[1]


def test_import_contracts_hold(monkeypatch):
    """numerics <- models <- io <- api <- cli, and no units/xarray/I-O below the API."""
    monkeypatch.chdir(ROOT)
    status = lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True, no_logo=True)
    assert status == 0, "import-linter contracts are broken; run `lint-imports` for details"


# Heavy packages a script that only computes a Chandler period never needs; loaded on first use.
HEAVY = ("numba", "xarray", "pandas", "astropy.utils.iers", "astropy.units", "scipy", "dask", "matplotlib", "netCDF4")


def _loaded_after(code: str) -> list[str]:
    import subprocess
    import sys

    probe = f"import sys; {code}; print(' '.join(m for m in {HEAVY!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT)
    return out.stdout.split()


def test_import_wobble_is_lazy():
    """`import wobble` (and the CLI's parser) load none of the heavy packages (issue 15: start-up)."""
    assert _loaded_after("import wobble, wobble.cli; wobble.cli.build_parser()") == []


def test_table_commands_skip_xarray():
    """`wobble chandler earth --json` needs astropy.units and NumPy, not xarray, pandas or dask."""
    loaded = _loaded_after("import contextlib, io, wobble.cli as c; f = io.StringIO(); "
                           "contextlib.redirect_stdout(f).__enter__(); c.main(['chandler', 'earth', '--json'])")
    assert not set(loaded) & {"xarray", "pandas", "dask", "matplotlib", "numba", "astropy.utils.iers"}


def test_public_names_resolve():
    """Every name in wobble.__all__ resolves (the lazy table has no typo)."""
    import wobble

    missing = [name for name in wobble.__all__ if getattr(wobble, name, None) is None]
    assert missing == []
