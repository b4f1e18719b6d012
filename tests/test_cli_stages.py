"""Stage lines while a command works: on a terminal only, each drawn over the last, cleared at the end;
the forecast names its stages through ``progress``."""

from __future__ import annotations

import io
import os
import pty
import select
import subprocess
import sys
from datetime import date

import pytest
from astropy import units as u

import wobble
from wobble.errors import InputError
from wobble.cli._stages import Stages


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_stages_draw_over_the_last_line_and_clear_it(monkeypatch):
    err = _Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    stages = Stages()
    stages("a long first message")
    stages("short")
    stages.done()
    text = err.getvalue()
    lines = text.split("\r")[1:]
    assert lines[0].endswith("] a long first message")
    # The shorter message covers every character of the longer one before it.
    assert lines[1].rstrip().endswith("] short") and len(lines[1]) == len(lines[0])
    assert lines[2] == " " * len(lines[1]) and lines[3] == ""  # cleared, the cursor back at the start
    stages.done()  # twice: nothing more
    assert err.getvalue() == text


def test_stages_are_silent_off_a_terminal(monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    stages = Stages()
    stages("working")
    stages.done()
    assert err.getvalue() == ""


def test_the_forecast_names_its_stages():
    said = []
    f = wobble.forecast_polar_motion(
        issued="2019-01-01", horizon=30 * u.day, method="kalman", latency=1 * u.day, progress=said.append
    )
    cal = f.to_dict()["calibration"]
    # Every weekly past issue date from the first to the last the calibration used.
    weeks = (date.fromisoformat(cal["last_issue"]) - date.fromisoformat(cal["first_issue"])).days / cal["step_days"]
    assert said == [
        "Chandler period by least squares",
        "Kalman noise by maximum likelihood",
        f"{round(weeks) + 1} past forecasts to calibrate the intervals",
    ]


def test_given_period_and_no_calibration_leave_those_stages_out():
    said = []
    wobble.forecast_polar_motion(
        issued="2019-01-01",
        horizon=30 * u.day,
        method="ls_ar",
        latency=1 * u.day,
        chandler_period=433 * u.day,
        calibrated=False,
        progress=said.append,
    )
    assert said == []


@pytest.mark.skipif(not hasattr(pty, "openpty"), reason="needs a pseudo-terminal")
def test_forecast_on_a_terminal_shows_then_clears_its_stages(tmp_path):
    master, slave = pty.openpty()
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONWARNINGS="ignore")
    proc = subprocess.Popen(
        [sys.executable, "-m", "wobble", "forecast", "--method", "ls_ar", "--horizon", "30d", "-o", "f.nc"],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=slave,
        stdin=subprocess.DEVNULL,
        env=env,
    )
    os.close(slave)
    out, _ = proc.communicate(timeout=300)
    seen = b""
    while select.select([master], [], [], 0.2)[0]:
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk
    os.close(master)
    assert proc.returncode == 0, seen
    text = seen.decode()
    assert "Chandler period by least squares" in text and "past forecasts to calibrate the intervals" in text
    assert "writing f.nc" in text
    assert text.endswith("\r") and text.rstrip("\r").split("\r")[-1].strip() == ""  # the last line cleared
    assert b"wrote f.nc" in out and b"\r" not in out  # the results themselves are untouched


def test_leaving_the_with_block_by_an_error_clears_the_line(monkeypatch):
    err = _Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    with pytest.raises(ValueError), Stages() as stages:
        stages("reading")
        raise ValueError("bad input")
    line = err.getvalue().split("\r")
    assert line[1].endswith("] reading") and line[2] == " " * len(line[1]) and line[3] == ""


def test_progress_true_prints_the_stages_and_anything_else_is_refused(capsys):
    """progress=True (as the hindcast takes it) raised "'bool' object is not callable" in the forecast and
    the polar-motion analysis; it prints one line per stage now, and a value that is neither a flag nor a
    function is refused by name."""
    wobble.forecast_polar_motion(issued="2019-01-01", horizon=30 * u.day, method="ls_ar", progress=True)
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == "Chandler period by least squares" and lines[-1].endswith(
        "past forecasts to calibrate the intervals"
    )
    with pytest.raises(InputError, match=r"^progress: got yes; allowed: True, False or None, or a function"):
        wobble.forecast_polar_motion(issued="2019-01-01", horizon=30 * u.day, method="ls_ar", progress="yes")
    with pytest.raises(InputError, match=r"^progress: got 3"):
        wobble.polar_motion_analysis(progress=3)
