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


def test_import_wobble_does_not_load_numba():
    """Numba (~0.4 s to import) is loaded by the compiled kernels only, when they first run."""
    import subprocess
    import sys

    code = "import sys, wobble, wobble.cli; print('numba' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "False"
