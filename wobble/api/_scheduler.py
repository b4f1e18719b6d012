"""The dask schedulers the parallel commands (sweep, invert, forecast --hindcast) accept, checked in one place.

A scheduler is ``None`` (the command's own local default), one of dask's local
schedulers by name, the address of a running ``dask.distributed`` scheduler
(``tcp://host:port``), or a ``distributed.Client`` already connected.
"""

from __future__ import annotations

import contextlib

from wobble.errors import InputError

__all__ = ["LOCAL", "check_scheduler", "connected", "process_pool"]

#: dask's local schedulers, by the names dask gives them.
LOCAL = ("threads", "processes", "synchronous")
_ALLOWED = "threads, processes, synchronous or a scheduler address such as tcp://127.0.0.1:8786"
#: Seconds to wait for a scheduler address to answer (distributed's own default is 30 s).
CONNECT_TIMEOUT = 10


def check_scheduler(scheduler) -> None:
    """Refuse a scheduler name that is neither a local scheduler nor an address, before any work starts.

    A tcp:// or tls:// address needs a port from 1 to 65535 (distributed's own parser said "not a dask
    scheduler: ValueError" of ``tcp://localhost`` and OverflowError of port 99999, as if something had
    answered there).
    """
    if not isinstance(scheduler, str) or scheduler in LOCAL:
        return
    scheme, found, location = scheduler.partition("://")
    if not found:
        raise InputError("scheduler", scheduler, _ALLOWED)
    if scheme in ("tcp", "tls") and _port(location) is None:
        raise InputError("scheduler", scheduler, f"a {scheme}://host:port address with a port from 1 to 65535")


def _port(location: str) -> int | None:
    """The port of ``host:port`` or ``[v6 host]:port``; None when there is none or it is out of range."""
    head, colon, port = location.rpartition(":")
    if not colon or (head.startswith("[") and not head.endswith("]")) or not (port.isascii() and port.isdigit()):
        return None
    number = int(port)
    return number if 1 <= number <= 65535 else None


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
    answer = _identity(scheduler)
    if not answer:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError):  # it answered a moment ago: gone since
            answer = f"none answered there within {CONNECT_TIMEOUT} s"
    if answer:
        raise InputError("scheduler", scheduler, f"the address of a running dask scheduler ({answer})")
    try:
        yield client
    finally:
        client.close()


def _identity(address: str) -> str:
    """'' when a dask scheduler answers at ``address`` within :data:`CONNECT_TIMEOUT`, else what happened.

    Asked before ``Client(address)``, which does not return when something other than a scheduler
    holds the port (an HTTP server: its handshake waits without end, past its own timeout) and dies
    in distributed's depths when that something answers (a stranger's reply read as a message
    length: "Unable to allocate 3.07 EiB"). The scheduler's ``identity`` call, bounded by
    ``asyncio.wait_for``, ends in time in every case.
    """
    import asyncio
    import concurrent.futures
    import ssl

    from distributed.comm.core import CommClosedError
    from distributed.core import rpc
    from distributed.security import Security

    try:
        # The TLS settings of dask's configuration, as Client(address) takes them (a tls:// scheduler).
        connection_args = Security().get_connection_args("client")
    except Exception as exc:  # a certificate path that does not exist, a key that does not load
        return f"dask's TLS settings (distributed.comm.tls.*) could not be used: {_told(exc)}"
    if address.startswith("tls://") and connection_args.get("ssl_context") is None:
        return "a tls:// address needs dask's TLS settings (distributed.comm.tls.*), and none are set"

    async def ask():
        # A plain TCP connection first, so that an address where nothing listens ("none answered") is told
        # from one where something accepts the connection and then says nothing (an HTTP server waiting for
        # its request): distributed's handshake waits for a reply without a time limit of its own.
        await _reach(address)
        remote = rpc(address, timeout=CONNECT_TIMEOUT, connection_args=connection_args)
        try:
            return await asyncio.wait_for(remote.identity(), CONNECT_TIMEOUT)
        except TimeoutError:
            raise _Silent from None
        finally:
            await remote.close_rpc()

    try:
        # On a thread of its own, with its own event loop: asyncio.run refuses to start inside a running loop
        # (a Jupyter notebook's).
        with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
            reply = pool.submit(asyncio.run, ask()).result()
    except ssl.SSLError as exc:  # an OSError, but something answered
        return f"the TLS handshake there failed: {_told(exc)}"
    except CommClosedError as exc:  # likewise: a TLS server spoken to without TLS, among others
        return f"what answered there closed the connection: {_told(exc)}"
    except _Silent:
        return (
            f"something accepted the connection there but did not answer as a dask scheduler within {CONNECT_TIMEOUT} s"
        )
    except (OSError, TimeoutError):
        return f"none answered there within {CONNECT_TIMEOUT} s"
    except Exception as exc:  # anything else: what answers there does not speak dask's protocol
        return f"what answered there is not a dask scheduler: {_told(exc)}"
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        kind = reply.get("type") if isinstance(reply, dict) else type(reply).__name__
        return f"what answered there is not a dask scheduler but {kind!r}"
    return ""


class _Silent(Exception):
    """The address accepted a connection, then sent nothing a scheduler sends in time."""


async def _reach(address: str) -> None:
    """Open and close a TCP connection to a tcp:// or tls:// address; OSError or TimeoutError when none is
    accepted within :data:`CONNECT_TIMEOUT`. Other transports are left to distributed."""
    import asyncio

    from distributed.comm.addressing import parse_address, parse_host_port

    scheme, location = parse_address(address)
    if scheme not in ("tcp", "tls"):
        return
    host, port = parse_host_port(location)
    _, writer = await asyncio.wait_for(asyncio.open_connection(host, port), CONNECT_TIMEOUT)
    writer.close()
    with contextlib.suppress(OSError):
        await writer.wait_closed()


def _told(exc: BaseException) -> str:
    """An exception for a one-line message: its type and its printable text, at most 160 characters (what a
    stranger's server sent must not reach the terminal as control codes)."""
    said = "".join(ch if ch.isprintable() else " " for ch in str(exc))
    said = " ".join(said.split())[:160]
    return type(exc).__name__ + (f": {said}" if said else "")


def _worker_signals() -> None:
    """In a pool's worker: Ctrl-C is the parent's to handle (it stops the pool), and SIGTERM and SIGHUP
    end the worker quietly, as the system's default (a forked worker inherited the command line's
    handlers, which raise an exception there and print its traceback)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)


@contextlib.contextmanager
def process_pool(workers: int, context):
    """A ``concurrent.futures.ProcessPoolExecutor`` whose workers stop at once when the block is left by
    an exception (Ctrl-C, SIGTERM, an error).

    Leaving the executor's own ``with`` block waits for every task already submitted: after Ctrl-C a
    weekly five-year hindcast went on for 73 s before the process exited (measured 2026-11-30). Here
    queued tasks are cancelled and the workers terminated; their results are not wanted.
    """
    import concurrent.futures

    pool = concurrent.futures.ProcessPoolExecutor(workers, mp_context=context, initializer=_worker_signals)
    try:
        yield pool
    except BaseException:
        # The executor has no public way to stop running workers before Python 3.14 (terminate_workers).
        processes = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()
        for process in processes:
            process.join(timeout=10)
        raise
    pool.shutdown(wait=True)
