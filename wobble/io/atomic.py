"""Atomic output: write under a temporary name in the target folder, then rename.

Every file wobble writes goes through :func:`atomic_target`, so a failed or
interrupted run never leaves a half-written file and never destroys an
existing one; an existing file is replaced only on request.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from wobble.errors import InputError, OutputExistsError

__all__ = ["atomic_target", "check_target", "new_temporary", "publish"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_target(path: str | os.PathLike, overwrite: bool) -> Path:
    """``path`` as a Path after checking it can be written: a file in an existing folder,
    not present unless ``overwrite``. Raises before any work is done."""
    path = Path(path)
    if path.is_dir():
        raise InputError("output", str(path), "a file path, not a folder")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError("output", str(path), "a path in an existing folder")
    if path.exists() and not overwrite:
        raise OutputExistsError(path)
    return path


def new_temporary(path: Path) -> Path:
    """An empty temporary file next to ``path`` (same folder, so the rename is atomic)."""
    folder = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    return Path(tmp)


def publish(tmp: str | os.PathLike, path: Path) -> None:
    """Give ``tmp`` the mode open() would (mkstemp makes it 0600) and rename it onto ``path``."""
    os.chmod(tmp, 0o666 & ~_umask())
    os.replace(tmp, path)


@contextlib.contextmanager
def atomic_target(path: str | os.PathLike, overwrite: bool):
    """Yield a temporary path in ``path``'s folder; rename it onto ``path`` on success.

    Whatever goes wrong (bad data, full disk, Ctrl-C), the temporary file is
    removed and an existing ``path`` is untouched.
    """
    path = check_target(path, overwrite)
    tmp = new_temporary(path)
    try:
        yield str(tmp)
        publish(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
