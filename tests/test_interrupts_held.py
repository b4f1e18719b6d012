"""``interrupts_held``: Ctrl-C during an xarray write is delivered after it, never inside it.

xarray's netCDF writer takes a non-reentrant lock and takes it again in its clean-up, so a
``KeyboardInterrupt`` raised inside it deadlocked ``wobble sweep`` (the interrupt tests in
test_interrupt.py exercise the real command; these check the mechanism in-process).
"""

from __future__ import annotations

import os
import signal

import pytest

from wobble.io.atomic import interrupts_held


# Python's own Ctrl-C handler for each test (tests/conftest.py): these tests are about it.
pytestmark = pytest.mark.usefixtures("python_ctrl_c")


def test_an_interrupt_inside_is_raised_after_the_block_ends():
    finished = []
    with pytest.raises(KeyboardInterrupt):
        with interrupts_held():
            os.kill(os.getpid(), signal.SIGINT)
            finished.append(True)  # the block is not cut short
    assert finished == [True]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_no_interrupt_no_exception_and_the_handler_is_restored():
    with interrupts_held():
        pass
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_custom_handler_is_called_once_after_the_block():
    calls = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: calls.append(signum))
    try:
        with interrupts_held():
            os.kill(os.getpid(), signal.SIGINT)
            os.kill(os.getpid(), signal.SIGINT)
            assert calls == []
        assert calls == [signal.SIGINT]
    finally:
        signal.signal(signal.SIGINT, previous)
