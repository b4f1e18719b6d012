"""Progress for long runs: a one-line bar on stderr (the command line turns it on when stderr is a terminal), and
the stage messages of the analyses."""

from __future__ import annotations

import sys
import time

from wobble.errors import InputError

__all__ = ["ProgressBar", "stage_messages"]


class ProgressBar:
    """``bar(done)`` redraws ``[####   ]  40.0% 4/10 <label>, 2.1 s``; ``bar.close()`` ends the line.

    Disabled, it does nothing, so callers need not test for it.
    """

    def __init__(self, total: int, label: str, enabled: bool):
        self.total, self.label, self.enabled, self.t0, self.last = total, label, enabled, time.perf_counter(), -1

    def __call__(self, done: int):
        if not self.enabled:
            return
        pct = int(1000 * done / self.total)
        if pct == self.last and done != self.total:
            return
        self.last = pct
        bar = "#" * int(30 * done / self.total)
        elapsed = time.perf_counter() - self.t0
        sys.stderr.write(f"\r[{bar:<30}] {done / self.total:6.1%} {done}/{self.total} {self.label}, {elapsed:.1f} s")
        sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\n")
            sys.stderr.flush()


def stage_messages(progress):
    """``progress`` as a function of one message: None or False, nothing; True, a line on stderr per stage
    (as ``hindcast_polar_motion(progress=True)`` shows its bar); a callable, itself."""
    if progress is None or progress is False:
        return lambda message: None
    if progress is True:
        return lambda message: print(message, file=sys.stderr, flush=True)
    if callable(progress):
        return progress
    raise InputError("progress", progress, "True, False or None, or a function taking one message (e.g. print)")
