"""Stage messages on stderr while a command works: one line, redrawn, only when stderr is a terminal."""

from __future__ import annotations

import sys
import time

__all__ = ["Stages"]


class Stages:
    """``stages(message)`` redraws ``[  1.2 s] message`` on stderr; ``stages.done()`` clears the line, as leaving
    ``with Stages() as stages:`` does, by an error too (whose one line then starts on a clean line).

    Off when stderr is not a terminal (a pipe, a file, a test), so scripts and logs see only results.
    """

    def __init__(self):
        self.on = sys.stderr.isatty()
        self.t0 = time.monotonic()
        self.width = 0  # of the line on screen: a shorter message is padded over it

    def __call__(self, message: str) -> None:
        if self.on:
            line = f"[{time.monotonic() - self.t0:5.1f} s] {message}".ljust(self.width)
            print("\r" + line, end="", file=sys.stderr, flush=True)
            self.width = len(line)  # what the screen holds now, the padding included

    def done(self) -> None:
        if self.on and self.width:
            print("\r" + " " * self.width + "\r", end="", file=sys.stderr, flush=True)
            self.width = 0

    def __enter__(self) -> Stages:
        return self

    def __exit__(self, *exc) -> None:
        self.done()
