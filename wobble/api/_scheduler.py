"""The dask schedulers the parallel commands (sweep, invert, forecast --hindcast) accept, checked in one place.

A scheduler is ``None`` (the command's own local default), one of dask's local
schedulers by name, the address of a running ``dask.distributed`` scheduler
(``tcp://host:port``), or a ``distributed.Client`` already connected.
"""

from __future__ import annotations

import contextlib

from wobble.errors import InputError

__all__ = ["LOCAL", "check_scheduler", "connected"]

#: dask's local schedulers, by the names dask gives them.
LOCAL = ("threads", "processes", "synchronous")
_ALLOWED = "threads, processes, synchronous or a scheduler address such as tcp://127.0.0.1:8786"
#: Seconds to wait for a scheduler address to answer (distributed's own default is 30 s).
CONNECT_TIMEOUT = 10


def check_scheduler(scheduler) -> None:
    """Refuse a scheduler name that is neither a local scheduler nor an address, before any work starts."""
    if isinstance(scheduler, str) and scheduler not in LOCAL and "://" not in scheduler:
        raise InputError("scheduler", scheduler, _ALLOWED)


@contextlib.contextmanager
def connected(scheduler):
    """A ``distributed.Client`` for an address (closed afterwards) or the client given.

    An address where no scheduler answers is an input error naming it, not a
    bare ``OSError`` from the depths of distributed.
    """
    from distributed import Client

    if not isinstance(scheduler, str):
        yield scheduler
        return
    try:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError):
        raise InputError(
            "scheduler",
            scheduler,
            f"the address of a running dask scheduler (none answered there within {CONNECT_TIMEOUT} s)",
        ) from None
    try:
        yield client
    finally:
        client.close()
