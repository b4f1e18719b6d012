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

__all__ = ["atomic_target"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_target(path: str | os.PathLike, overwrite: bool):
    """Yield a temporary path in ``path``'s folder; rename it onto ``path`` on success.

    Whatever goes wrong (bad data, full disk, Ctrl-C), the temporary file is
    removed and an existing ``path`` is untouched.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError("output", str(path), "a file path, not a folder")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError("output", str(path), "a path in an existing folder")
    if path.exists() and not overwrite:
        raise OutputExistsError(path)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        yield tmp
        # mkstemp makes the file private (0600); give it the mode open() would.
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
