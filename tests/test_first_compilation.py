"""Numba's just-in-time work is seen through its event API, and its first compilation is announced
on a terminal, once, and nowhere else.

On the first run after installing, Numba compiles wobble's kernels (15 to 35 s); the command line
then prints one status line on a terminal, and the benchmarks leave that work out of every timing.
numerics prints nothing itself: :mod:`wobble.numerics.compiled` counts Numba's events and calls
what the caller registered for the block.
"""

from __future__ import annotations

import io

import pytest

nb = pytest.importorskip("numba")

from wobble.numerics import compiled  # noqa: E402


def _new_kernel(k):
    """A function Numba has not seen: calling it compiles (no disk cache)."""
    return nb.njit(lambda x: x + k)


def test_activity_counts_compilations_and_nothing_else():
    compiled.listen()
    compiled.listen()  # idempotent: one pair of listeners, so one count per event
    kernel = _new_kernel(1)
    before = compiled.activity()
    kernel(1)
    after = compiled.activity()
    assert after[0] and after[2] == before[2] + 1 and after[1] > before[1]
    kernel(2)  # already compiled for int64: no new event
    assert compiled.activity() == after


def test_the_notice_is_called_once_and_only_inside_its_block():
    said = []
    with compiled.compilation_notice(lambda: said.append("outer")):
        with compiled.compilation_notice(lambda: said.append("inner")):  # takes over
            _new_kernel(2)(1)
            _new_kernel(3)(1)
        _new_kernel(4)(1)  # the outer block again
    _new_kernel(5)(1)  # outside every block
    assert said == ["inner", "outer"]


def test_the_command_line_announces_only_on_a_terminal(monkeypatch):
    from wobble import cli

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    compiled.listen()
    pipe, terminal = io.StringIO(), Terminal()
    for k, stream in enumerate((pipe, terminal)):
        monkeypatch.setattr(cli.sys, "stderr", stream)
        with cli._compilation_notice("run"):
            _new_kernel(10 + k)(1)
            _new_kernel(20 + k)(1)
    assert pipe.getvalue() == ""
    text = terminal.getvalue()
    assert text.startswith("wobble run: compiling the numerical kernels (first run after installing only")
    assert text.count("\n") == 1
