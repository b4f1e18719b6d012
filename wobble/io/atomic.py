"""Atomic output: write under a temporary name in the target folder, then rename.

Every file wobble writes goes through :func:`atomic_target`, so a failed or
interrupted run never leaves a half-written file and never destroys an
existing one; an existing file is replaced only on request.

A write that fails for want of room (a full disk, a file-size limit) is an
:class:`OSError` naming the target, whichever library was writing: netCDF4 and
h5py report it as a bare ``RuntimeError`` ("NetCDF: HDF error"), which
:func:`write_error` turns back into the ``OSError`` it stands for, so the command
line reports it in one line (exit status 2) like any other file problem.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import shutil
import signal
import tempfile
import threading
import time
import traceback
from pathlib import Path

from wobble.errors import InputError, OutputExistsError

__all__ = [
    "atomic_target",
    "check_target",
    "new_temporary",
    "new_temporary_folder",
    "publish",
    "write_error",
    "remove_stale_temporaries",
    "interrupts_held",
]

# When this process began writing files (the module is imported before any write): temporaries
# older than this cannot belong to a write this process is doing.
_STARTED = time.time()

# Libraries whose failed writes surface as RuntimeError rather than OSError.
_FILE_LIBRARIES = ("netCDF4", "h5py", "h5netcdf")
# Their messages for a write the system refused (netCDF4: "NetCDF: HDF error"; HDF5: "file write failed ...
# errno = 28").
_WRITE_FAILURE = re.compile(r"HDF error|write failed|errno = \d+|can't write|no space|too large", re.IGNORECASE)
# Errors that mean the target's file system had no room for it.
_NO_ROOM = {errno.ENOSPC, errno.EFBIG, errno.EDQUOT}
# Below this many free bytes in the target's file system, a failed write is put down to a full disk.
_NEARLY_FULL = 1 << 20


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised where the command line turned them into exceptions
    (:func:`terminate_as_interrupt`), so that the clean-up of Ctrl-C runs for them too: a
    ``timeout`` or a closed terminal left a half-written temporary file behind."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


def _raise_terminated(signum, frame):
    raise Terminated(signum)


#: The signals :func:`terminate_as_interrupt` turns into :class:`Terminated`.
TERMINATING = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))


def terminate_as_interrupt() -> None:
    """Raise :class:`Terminated` on SIGTERM and SIGHUP (the command line's; a library leaves them alone)."""
    for signum in TERMINATING:
        signal.signal(signum, _raise_terminated)


@contextlib.contextmanager
def interrupts_held():
    """Hold Ctrl-C (SIGINT), and SIGTERM and SIGHUP where they raise, while the block runs, then
    raise the ``KeyboardInterrupt`` (or :class:`Terminated`) it was for.

    xarray's writers take a non-reentrant lock around the netCDF library and take it again in
    their clean-up: a ``KeyboardInterrupt`` raised between the two deadlocks the process (seen
    with Ctrl-C early in a large sweep's file), or is lost in a clean-up that swallows it and the
    run goes on. Holding the signal over such a call costs at most the call's own duration; the
    interrupt then arrives where wobble's clean-up (:func:`atomic_target`) removes the temporary.
    A signal whose handler is the system's (SIGTERM outside the command line) is not held.
    Outside the main thread (where signal handlers cannot be set) the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = {}
    for signum in (signal.SIGINT, *TERMINATING):
        handler = signal.getsignal(signum)
        if signum == signal.SIGINT or callable(handler):
            previous[signum] = signal.signal(signum, lambda number, frame: received.append(number))
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
    for signum in dict.fromkeys(received):  # each signal once, in the order they came
        handler = previous[signum]
        if handler is signal.default_int_handler:
            raise KeyboardInterrupt
        if callable(handler):
            handler(signum, None)


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


def _prefix(path: Path) -> str:
    # The writer's process id is part of the name, so a later run can tell a temporary
    # left by a killed run (process gone) from one a running process is still writing.
    return f".{path.name}.{os.getpid()}."


def new_temporary(path: Path) -> Path:
    """An empty temporary file ``.NAME.PID.XXXXXXXX.tmp`` next to ``path`` (same folder, so the
    rename is atomic); stale temporaries of the same target are removed first.

    Call it inside :func:`interrupts_held` together with the statement that records the name for
    the clean-up (``with interrupts_held(): self.tmp = new_temporary(path)``): a Ctrl-C between the
    two would otherwise leave a file nobody removes. The same holds for :func:`new_temporary_folder`.
    """
    folder = path.parent if str(path.parent) else Path(".")
    remove_stale_temporaries(path)
    with _named_for(path):
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=_prefix(path), suffix=".tmp")
    os.close(fd)
    return Path(tmp)


@contextlib.contextmanager
def _named_for(path: Path):
    """An OSError creating a temporary for ``path`` names ``path``, the file the user asked for
    (``/proc/x.nc``), not the temporary's name (``/proc/.x.nc.123.abc.tmp``) they never typed."""
    try:
        yield
    except OSError as exc:
        if exc.errno is None:
            raise
        raise OSError(exc.errno, exc.strerror or os.strerror(exc.errno), str(path)) from exc


def new_temporary_folder(path: Path, suffix: str = ".tmp") -> Path:
    """An empty temporary folder named like :func:`new_temporary`'s files (for Zarr stores)."""
    folder = path.parent if str(path.parent) else Path(".")
    if suffix == ".tmp":
        remove_stale_temporaries(path)
    with _named_for(path):
        return Path(tempfile.mkdtemp(dir=folder, prefix=_prefix(path), suffix=suffix))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True  # someone else's process: alive
    return True


def remove_stale_temporaries(path) -> list[Path]:
    """Remove what a killed run (SIGKILL, power loss) left while writing ``path``; return what went.

    Only temporaries that are clearly ours and stale are touched: named
    ``.NAME.PID.XXXXXXXX.tmp`` (or ``.old``, a Zarr store moved aside) for this very target, written
    by a process that no longer exists, and last modified before this process started. Anything
    else (another running wobble's temporary, a file of the user's) is left alone.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    pattern = re.compile(rf"\.{re.escape(path.name)}\.(\d+)\.[A-Za-z0-9_]{{8}}\.(tmp|old)")
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        found = pattern.fullmatch(entry.name)
        if not found:
            continue
        pid = int(found.group(1))
        try:
            stale = pid != os.getpid() and not _alive(pid) and entry.stat(follow_symlinks=False).st_mtime < _STARTED
        except OSError:
            continue
        if not stale:
            continue
        try:
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
            removed.append(Path(entry.path))
        except OSError:
            pass  # not ours to fight over: leave it
    return removed


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
    tmp = None
    try:
        # Ctrl-C between the creation of the file and the assignment of its name would leave a file the
        # clean-up below does not know of (seen in CI): hold it until ``tmp`` is set, inside the try.
        with interrupts_held():
            tmp = new_temporary(path)
        yield str(tmp)
        publish(tmp, path)
    except BaseException as exc:
        if tmp is not None:
            with interrupts_held():  # a second Ctrl-C must not cut the clean-up short
                tmp.unlink(missing_ok=True)
        translated = write_error(exc, path)
        if translated is not None:
            raise translated from exc
        if isinstance(exc, OSError) and exc.errno and (not exc.filename or exc.errno in _NO_ROOM):
            # Name the file that was not written (shutil names the source of a copy, zarr nothing).
            raise OSError(exc.errno, exc.strerror or os.strerror(exc.errno), str(path)) from exc
        raise


def write_error(exc: BaseException, path) -> OSError | None:
    """The :class:`OSError` that a file library's failed write of ``path`` stands for, or None.

    netCDF4 and h5py raise ``RuntimeError`` when the operating system refuses a write
    (HDF5 keeps the errno in its message, netCDF4 drops it). Only a RuntimeError of those
    libraries that reports a failed write is translated; anything else (a bug) is left alone.
    """
    if not isinstance(exc, RuntimeError):
        return None
    text = str(exc)
    frames = traceback.extract_tb(exc.__traceback__)
    from_library = text.startswith("NetCDF:") or any(lib in f.filename for f in frames for lib in _FILE_LIBRARIES)
    if not (from_library and _WRITE_FAILURE.search(text)):
        return None
    found = re.search(r"errno = (\d+)", text)
    code = int(found.group(1)) if found else _likely_errno(Path(path))
    detail = " ".join(str(exc).split())
    detail = detail if len(detail) <= 120 else detail[:117] + "..."
    return OSError(code, f"{os.strerror(code)}: the file could not be written ({detail})", str(path))


def _likely_errno(path: Path) -> int:
    """ENOSPC when the target's file system is (nearly) full, EFBIG under a file-size limit, else EIO."""
    folder = path.parent if str(path.parent) else Path(".")
    try:
        stat = os.statvfs(folder)
        if stat.f_bavail * stat.f_frsize < _NEARLY_FULL:
            return errno.ENOSPC
    except OSError:
        pass
    try:
        import resource

        if resource.getrlimit(resource.RLIMIT_FSIZE)[0] != resource.RLIM_INFINITY:
            return errno.EFBIG
    except (ImportError, OSError, ValueError):
        pass
    return errno.EIO
