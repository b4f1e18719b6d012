"""The schedulers the parallel commands accept (wobble.api._scheduler): names checked, addresses that do not answer."""

from __future__ import annotations

import socket
import threading
import time

import pytest

from cli_run import run_cli
from wobble.api import _scheduler
from wobble.errors import InputError


@pytest.fixture
def quick_timeout(monkeypatch):
    monkeypatch.setattr(_scheduler, "CONNECT_TIMEOUT", 1)


@pytest.mark.parametrize("name", ["threads", "processes", "synchronous", "tcp://127.0.0.1:8786", None])
def test_known_schedulers_pass_the_check(name):
    _scheduler.check_scheduler(name)


def test_an_unknown_name_is_refused_with_what_is_allowed():
    with pytest.raises(InputError, match="scheduler: got thread; allowed: threads, processes, synchronous or"):
        _scheduler.check_scheduler("thread")


@pytest.mark.parametrize(
    "address", ["tcp://localhost", "tcp://127.0.0.1:99999", "tcp://127.0.0.1:0", "tls://[::1]", "tcp://h:+1"]
)
def test_an_address_without_a_usable_port_is_refused_before_any_connection(address):
    """distributed's parser had been reached: "what answered there is not a dask scheduler: ValueError" for
    tcp://localhost and OverflowError for port 99999, as if something had answered."""
    with pytest.raises(InputError, match="host:port address with a port from 1 to 65535"):
        _scheduler.check_scheduler(address)


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:8786", "tls://[::1]:8786", "tcp://:8786"])
def test_an_address_with_a_port_passes_the_check(address):
    _scheduler.check_scheduler(address)


def test_an_address_where_nothing_listens_says_none_answered(quick_timeout):
    """Told apart from a server that accepts the connection and says nothing (an HTTP server)."""
    assert _scheduler._identity("tcp://127.0.0.1:1") == "none answered there within 1 s"


def test_an_address_where_nothing_answers_is_named(quick_timeout):
    with pytest.raises(InputError, match=r"scheduler: got tcp://127\.0\.0\.1:1; allowed: the address of a running"):
        with _scheduler.connected("tcp://127.0.0.1:1"):
            pass


@pytest.fixture
def stranger():
    """A TCP server on a free local port that is not a dask scheduler: ``reply`` b'' (it reads and says
    nothing, as an HTTP server waits for its request) or bytes it sends to whoever connects."""
    servers = []

    def start(reply: bytes) -> str:
        listener = socket.socket()
        listener.bind(("127.0.0.1", 0))
        listener.listen()
        listener.settimeout(0.2)
        stop = threading.Event()

        def serve():
            held = []
            while not stop.is_set():
                try:
                    conn, _ = listener.accept()
                except OSError:
                    continue
                held.append(conn)
                if reply:
                    conn.sendall(reply)
            for conn in held:
                conn.close()
            listener.close()

        thread = threading.Thread(target=serve, daemon=True)
        thread.start()
        servers.append((stop, thread))
        return f"tcp://127.0.0.1:{listener.getsockname()[1]}"

    yield start
    for stop, thread in servers:
        stop.set()
        thread.join(5)


@pytest.mark.parametrize(
    ("reply", "why"),
    [
        (b"", "something accepted the connection there but did not answer as a dask scheduler within 1 s"),
        (b"HTTP/1.0 400 Bad Request\r\n\r\n" * 8, "what answered there is not a dask scheduler"),
    ],
)
def test_an_address_held_by_something_else_is_refused_in_time(quick_timeout, stranger, reply, why):
    """Client(address) never returned when an HTTP server held the port (past its own timeout), and died
    with numpy's "Unable to allocate 3.07 EiB" when a stranger's bytes were read as a message length."""
    address = stranger(reply)
    start = time.monotonic()
    with pytest.raises(InputError, match=f"scheduler: got {address}; allowed: the address of a running dask "):
        with _scheduler.connected(address):
            pass
    assert time.monotonic() - start < 30  # a bound on a hang, not a timing: the refusal takes about 1 s
    with pytest.raises(InputError) as info:
        with _scheduler.connected(address):
            pass
    assert why in str(info.value)


@pytest.mark.parametrize(
    "args",
    [
        ["forecast", "--hindcast", "2019-01-01:2019-02-01", "--horizon", "10", "--scheduler", "tcp://127.0.0.1:1"],
        ["sweep", "mars_chandler", "--scheduler", "tcp://127.0.0.1:1"],
    ],
)
def test_the_command_line_names_the_option_of_an_address_that_does_not_answer(quick_timeout, capsys, args):
    code, out, err = run_cli(args, capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "--scheduler: got tcp://127.0.0.1:1; allowed: the address of a running" in err


def test_a_client_given_is_used_as_it_is():
    sentinel = object()
    with _scheduler.connected(sentinel) as client:
        assert client is sentinel


def test_a_hindcast_on_a_distributed_client_equals_the_local_one():
    distributed = pytest.importorskip("distributed")
    import numpy as np
    from astropy import units as u

    import wobble

    kwargs = dict(
        start="2019-01-01",
        end="2019-01-15",
        horizon=10 * u.day,
        latency=1 * u.day,
        methods=("ls_ar",),
        calibrated=False,
    )
    local = wobble.hindcast_polar_motion(scheduler="synchronous", **kwargs)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=":0"
    ) as cluster:
        with distributed.Client(cluster) as client:
            on_client = wobble.hindcast_polar_motion(scheduler=client, **kwargs)
        by_address = wobble.hindcast_polar_motion(scheduler=cluster.scheduler_address, **kwargs)
    expected = list(local.to_dict()["methods"]["ls_ar"]["rms_2d_mas"].values())
    for remote in (on_client, by_address):
        np.testing.assert_array_equal(list(remote.to_dict()["methods"]["ls_ar"]["rms_2d_mas"].values()), expected)


def test_an_address_is_checked_from_inside_a_running_event_loop(quick_timeout, stranger):
    """A notebook runs its cells inside an event loop, where asyncio.run refuses to start: the check ran
    there and called every scheduler 'not a dask scheduler: RuntimeError'. It runs on a thread of its own."""
    import asyncio

    import distributed

    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, protocol="tcp", host="127.0.0.1", dashboard_address=":0"
    ) as cluster:

        async def in_a_notebook():
            return _scheduler._identity(cluster.scheduler_address), _scheduler._identity(stranger(b""))

        real, silent = asyncio.run(in_a_notebook())
    assert real == "" and silent.startswith("something accepted the connection there")


def test_a_tls_scheduler_is_reached_with_the_configured_certificates(tmp_path):
    """A tls:// scheduler takes its certificates from dask's configuration, as Client(address) does: the check
    asked it without them and refused it ('not a dask scheduler: TypeError')."""
    import shutil
    import subprocess

    import dask
    import distributed
    from distributed.security import Security

    if shutil.which("openssl") is None:
        pytest.skip("needs openssl to make a certificate")
    cert, key = tmp_path / "cert.pem", tmp_path / "key.pem"
    subprocess.run(
        ["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=127.0.0.1"]
        + ["-keyout", str(key), "-out", str(cert)],
        check=True,
        capture_output=True,
    )
    tls = {"distributed.comm.tls.ca-file": str(cert)}
    for role in ("scheduler", "worker", "client"):
        tls |= {f"distributed.comm.tls.{role}.cert": str(cert), f"distributed.comm.tls.{role}.key": str(key)}
    with dask.config.set(tls):
        with distributed.LocalCluster(
            n_workers=1,
            threads_per_worker=1,
            processes=False,
            protocol="tls",
            host="127.0.0.1",
            dashboard_address=":0",
            security=Security(),
        ) as cluster:
            assert cluster.scheduler_address.startswith("tls://")
            assert _scheduler._identity(cluster.scheduler_address) == ""
            with _scheduler.connected(cluster.scheduler_address) as client:
                assert client.submit(sum, [40, 2]).result() == 42


def test_tls_settings_that_cannot_be_used_are_named(tmp_path):
    """A certificate path that does not exist in dask's TLS settings raised FileNotFoundError bare (the command
    line printed 'No such file or directory', naming nothing); a tls:// address without TLS settings was
    called 'not a dask scheduler: TypeError'."""
    import dask
    import distributed  # noqa: F401  (its configuration loaded first: dask.config.set would restore it away)

    missing = str(tmp_path / "no-such-cert.pem")
    tls = {f"distributed.comm.tls.{key}": missing for key in ("ca-file", "client.cert", "client.key")}
    with dask.config.set(tls):
        with pytest.raises(InputError, match=r"scheduler: got tcp://127\.0\.0\.1:1; allowed: .*TLS settings"):
            with _scheduler.connected("tcp://127.0.0.1:1"):
                pass
    with pytest.raises(InputError, match="a tls:// address needs dask's TLS settings"):
        with _scheduler.connected("tls://127.0.0.1:1"):
            pass


def test_what_a_stranger_said_reaches_the_message_printable_and_short():
    told = _scheduler._told(RuntimeError("\x1b]0;title\x07\x1b[31mRED\n" + "x" * 500))
    assert told.startswith("RuntimeError: ") and told.isprintable() and len(told) <= len("RuntimeError: ") + 160


def test_a_typed_value_with_control_characters_reaches_stderr_printable(capsys):
    """The value a user typed was echoed as typed: an ESC in --scheduler reached the terminal (a review found it,
    beside the stranger's reply that _told already cleaned). Every refusal shows it escaped, on one line."""
    code, out, err = run_cli(["sweep", "mars_chandler", "--scheduler", "tcp://\x1b[31mx\x07:1"], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "\x1b" not in err and "\x07" not in err and r"tcp://\x1b[31mx\x07:1" in err
