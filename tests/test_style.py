"""Style, enforced: ``ruff check`` and ``ruff format --check`` pass on the whole checkout.

The rules are in pyproject.toml (``[tool.ruff]``); DEVELOPERS.md says how to run them.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytest.importorskip("ruff", reason="ruff is not installed (it is in the test extra: pip install -e '.[test]')")


def _ruff(*args: str) -> subprocess.CompletedProcess:
    # --no-cache: a test run writes nothing into the checkout.
    return subprocess.run(
        [sys.executable, "-m", "ruff", *args, "--no-cache", "."], cwd=ROOT, capture_output=True, text=True
    )


def test_ruff_check_passes():
    """No lint finding (pyflakes, pycodestyle, bugbear, pyupgrade, no unused ``# noqa``)."""
    out = _ruff("check", "--output-format", "concise")
    assert out.returncode == 0, (
        f"ruff check found problems (fix them, or run `ruff check --fix`):\n{out.stdout}{out.stderr}"
    )


def test_ruff_format_is_clean():
    """Every file is as ``ruff format`` writes it."""
    out = _ruff("format", "--check")
    assert out.returncode == 0, f"files ruff format would change (run `ruff format`):\n{out.stdout}{out.stderr}"
