"""The first compilation of Numba kernels is announced on a terminal, once, and nowhere else.

On the first run after installing, Numba compiles wobble's kernels (about 20 s); the command line
then prints one status line on a terminal. numerics prints nothing itself: it forwards Numba's
first "numba:compile" event to what the interface registered.
"""

from __future__ import annotations

import io

import pytest

nb = pytest.importorskip("numba")

from wobble.numerics import compiled  # noqa: E402


def test_the_first_compilation_calls_each_callback_once():
    compiled.listen()
    compiled.listen()  # idempotent: one listener
    said = []
    compiled.on_first_compilation(lambda: said.append("a"))
    compiled.on_first_compilation(lambda: said.append("b"))
    nb.njit(lambda x: x + 1)(1)  # a new function: compiled
    nb.njit(lambda x: x + 2)(1)
    assert said == ["a", "b"]


def test_the_command_line_announces_only_on_a_terminal(monkeypatch):
    from wobble import cli

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    pipe, terminal = io.StringIO(), Terminal()
    for stream in (pipe, terminal):
        monkeypatch.setattr(cli.sys, "stderr", stream)
        cli._announce_first_compilation("run")
        compiled.listen()
        nb.njit(lambda x: x * 2)(1)
        nb.njit(lambda x: x * 3)(1)
    assert pipe.getvalue() == ""
    text = terminal.getvalue()
    assert text.startswith("wobble run: compiling the numerical kernels (first run after installing only")
    assert text.count("\n") == 1
