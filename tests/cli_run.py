"""Running ``wobble`` in the test's own process, as the command-line tests do."""

from __future__ import annotations

from wobble.cli import main


def run_cli(argv, capsys):
    """``wobble ARGV`` in this process: (exit status, stdout, stderr), argparse's own exits included."""
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err
