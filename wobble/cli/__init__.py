"""The ``wobble`` command line.

Each subcommand lives in its own module (``wobble/cli/<name>.py``) exposing
``register(subparsers)``, which adds its parser and sets ``func`` to a
function ``run(args) -> int``. This module only dispatches and turns expected
failures into one line on stderr with exit status 2 (no traceback).
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import shlex
import sys

from wobble.errors import WobbleError

__all__ = ["main", "console", "build_parser", "SUBCOMMANDS"]

# Subcommand modules, in the order `wobble --help` lists them.
SUBCOMMANDS = (
    "chandler",
    "modes",
    "precession",
    "polar_motion",
    "excitation",
    "forecast",
    "inertia",
    "free",
    "top",
    "run",
    "sweep",
    "invert",
    "example",
    "bench",
)

EPILOG = """\
examples:
  wobble chandler earth mars            Chandler period budgets, as a table
  wobble chandler mars --json           the same for scripts
  wobble chandler --body-file my_planet.toml
                                        a body you describe ('wobble example my_planet.toml' copies this one to edit)
  wobble precession earth mars          forced precession of the spin axis, term by term
  wobble modes earth mars               every free mode: Chandler wobble, free core nutation
  wobble polar-motion --json            the Chandler wobble measured in the IERS record
  wobble excitation --json              the geodetic excitation of the pole (Liouville equation)
  wobble forecast --horizon 90d         the pole 90 days ahead, with 68 % and 95 % intervals
  wobble inertia --solid ellipsoid --mass 2 --axes 3 2 1
                                        inertia tensor, principal axes, classification
  wobble free --inertia 1 2 3 --omega 1 0.1 1 --t-end 100 --samples 1001 -o spin.nc
                                        exact torque-free motion, to a CF netCDF file
  wobble top --I1 1 --I3 0.5 --mgl 1 --theta0 "60 deg" --omega3 10 --json
                                        the heavy top: turning points, nutation class, period
  wobble sweep mars_chandler -o mars_sweep.nc
                                        Monte Carlo over Mars' uncertain parameters (dask)
  wobble invert mars --plot corner.png
                                        Bayesian inversion: the core radius of Mars from
                                        its Chandler period and k2 (emcee; ArviZ output)
  wobble run tennis_racket -o tennis.nc
                                        a scene (TOML file or example name): the cheapest
                                        adequate model, streamed to CF netCDF
  wobble example --list                 the shipped example files (planets, inputs, scenes, sweeps)
  wobble bench --quick                  work-precision benchmark: every solver, speed against error

A number without a unit is SI unless the option's help names another unit
(angles: degrees; the polar-motion commands' spans and periods: days or
years); days are days of 86400 s. Run 'wobble COMMAND --help' for each
command's options and an example.
"""


class _Parser(argparse.ArgumentParser):
    """argparse with usage errors reported as one line and exit status 2."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        # A value such as "-5d" or "-3 d" is a (negative) value, not an unknown option: argparse
        # knows only plain numbers (-5, -.5) and said "expected one argument" for --horizon -5d.
        # No wobble option starts with a digit, so a dash and a digit always begin a value; nor is
        # one called -inf or -nan, which Python's float reads (--q -inf reached argparse's "expected
        # one argument", not the option's own refusal naming --q).
        self._negative_number_matcher = re.compile(r"^-(?:\.?\d|(?:inf(?:inity)?|nan)(?![\w-]))", re.IGNORECASE)

    def error(self, message: str):  # overrides argparse.ArgumentParser.error
        # A value type's refusal (wobble.cli._types) as every other error reads: "--samples: got 2.5; ...".
        message = re.sub(r"^argument (\S+): got ", r"\1: got ", message)
        self.exit(2, f"{self.prog}: error: {_one_line(message)}\n")  # a value may hold a newline


class _VersionAction(argparse.Action):
    """``--version``: the installed version, read only when asked (importlib.metadata costs ~60 ms)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(
            option_strings,
            dest=dest,
            default=default,
            nargs=0,
            help=help or "show the program's version number and exit",
        )

    def __call__(self, parser, namespace, values, option_string=None):
        from wobble import __version__

        print(f"wobble {__version__}")  # on stdout, as argparse's own version action
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    """The full ``wobble`` argument parser with every subcommand registered."""
    parser = _Parser(
        prog="wobble",
        description="Planetary wobble and rigid-body rotation: Chandler periods with "
        "their physics budget, exact torque-free and heavy-top motion.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(title="commands", dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in SUBCOMMANDS:
        importlib.import_module(f"wobble.cli.{name}").register(sub)
    return parser


def _split_value(argv: list[str], extra: list[str]) -> str | None:
    """The message for a value typed as two words (``--horizon 5 m``), whose unit argparse calls unrecognized."""
    i = argv.index(extra[0]) if extra[0] in argv else -1
    if i < 1 or not re.fullmatch(r"[A-Za-z][A-Za-z0-9/*^.]*", extra[0]):
        return None
    if argv[i - 1].startswith("--") and "=" in argv[i - 1]:
        option, number = argv[i - 1].split("=", 1)
    elif i >= 2 and argv[i - 2].startswith("--"):
        option, number = argv[i - 2], argv[i - 1]
    else:
        return None
    from wobble.io.text import is_number

    if not is_number(number):
        return None
    value = f"{number} {extra[0]}"
    return f"{option}: got {value!r} as two arguments; allowed: one, {number}{extra[0]} or {value!r} in quotes"


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``wobble`` console script.

    Returns the exit status: 0 on success, 2 on bad input or a failed output,
    1 on an unexpected internal error (with its traceback, which is a bug).
    """
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    args, extra = parser.parse_known_args(argv)
    if extra:
        # Reported by the command's own parser ("wobble forecast: error: unrecognized arguments:
        # --quiet"), not the top-level one, which does not say which command was meant.
        sub = _subparser(parser, getattr(args, "command", None))
        (sub or parser).error(_split_value(argv, extra) or f"unrecognized arguments: {' '.join(extra)}")
    args.command_line = "wobble " + shlex.join(argv)  # for the files' history attribute
    if not getattr(args, "func", None):
        parser.print_help(sys.stderr)
        return 2
    from wobble._offline import configure_astropy_offline

    configure_astropy_offline(forbid_all_downloads=True)
    if "matplotlib" not in sys.modules:
        # The command line only writes figures to files: the Agg canvas, whatever MPLBACKEND says (a
        # GUI backend would want a display; MPLBACKEND=nonsense made --plot crash with a traceback). The
        # library itself (wobble.plot) leaves the backend to its caller.
        os.environ["MPLBACKEND"] = "Agg"
    try:
        with _compilation_notice(args.command):
            return int(args.func(args) or 0)
    except WobbleError as exc:
        text = getattr(exc, "command_line_message", None) or _one_line(_as_typed(exc, parser, args.command, argv))
        print(f"wobble {args.command}: error: {text}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # The reader of our output went away (`wobble ... | head`): stop quietly, the shell's way.
        _silence_stdout()
        return 141
    except OSError as exc:
        where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
        print(f"wobble {args.command}: error: {exc.strerror or exc}{where}", file=sys.stderr)
        return 2
    except Exception as exc:
        if not _is_units_error(exc):
            raise
        print(f"wobble {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        signum = getattr(exc, "signum", None)  # wobble.io.atomic.Terminated: SIGTERM or SIGHUP
        if signum is None:
            print(f"wobble {args.command}: interrupted; no output was written", file=sys.stderr)
            return 130
        import signal

        name = signal.Signals(signum).name
        print(f"wobble {args.command}: terminated ({name}); no output was written", file=sys.stderr)
        return 128 + signum


def console() -> int:
    """The ``wobble`` console script and ``python -m wobble``: :func:`main`, and, after an interrupt
    whose message is printed, an exit that does not wait for worker threads.

    Ctrl-C stops the main thread, but Python's exit joins every live non-daemon thread, and a
    hindcast or sweep on the threaded scheduler still has tasks running in its pool: the process
    printed "interrupted" at once and then took 6 s more to exit (a weekly five-year hindcast,
    measured 2026-11-30). By the time :func:`main` returns 130 every ``with`` block has unwound
    (temporary files removed, clients closed), so nothing those threads would finish is wanted.
    Only the command line does this: a caller of :func:`main` keeps its process.
    """
    from wobble.io.atomic import TERMINATING, terminate_as_interrupt

    # SIGTERM (timeout, kill, a batch system) and SIGHUP (a closed terminal) get Ctrl-C's clean-up: they
    # ended the process at once and left a half-written temporary file next to the output.
    terminate_as_interrupt()
    code = main()
    if code in (130, *(128 + s for s in TERMINATING)) and _worker_threads_alive():
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed or broken pipe: nothing left to say
                pass
        os._exit(code)
    return code


def _worker_threads_alive() -> bool:
    import threading

    main_thread = threading.main_thread()
    return any(t is not main_thread and t.is_alive() and not t.daemon for t in threading.enumerate())


def _compilation_notice(command: str):
    """On a terminal, one status line when Numba starts compiling wobble's kernels (the first run
    after installing: 15 to 35 s of silence otherwise); never in pipes, files or scripts' stderr."""
    import contextlib

    if not (hasattr(sys.stderr, "isatty") and sys.stderr.isatty()):
        return contextlib.nullcontext()
    from wobble.numerics.compiled import compilation_notice

    def say():
        print(
            f"wobble {command}: compiling the numerical kernels (first run after installing only, 15 to 35 s; "
            "they are then cached on disk) ...",
            file=sys.stderr,
            flush=True,
        )

    return compilation_notice(say)


def _as_typed(exc: WobbleError, parser: argparse.ArgumentParser, command: str, argv: list[str] | None = None):
    """An InputError about a Python parameter that is one of the command's options, named as typed.

    The API names its parameters (``calibration_span``); on the command line the user typed
    ``--calibration-span``. An option's argparse ``dest`` is that Python name, so the message
    names the option strings of the action with that dest (``-o/--output`` for ``output``), and a
    number the API converted is shown as typed in ``argv`` (``--theta0: got 200``, not ``200.0 deg``).
    """
    from wobble.errors import MISSING, InputError

    if not isinstance(exc, InputError):
        return exc
    actions = _subparser(parser, command)._actions

    def action_of(name):  # by dest (API name) or by option string (already renamed by the command)
        return next((a for a in actions if name in (a.dest, "/".join(a.option_strings), *a.option_strings)), None)

    found = [action_of(name) for name in exc.parameter.split(", ")]  # "I1, I3": both named
    if not all(found):
        return exc

    def name(a):
        return "/".join(a.option_strings) or a.metavar or a.dest.upper()  # SETUP, DEST

    typed = ", ".join(name(a) for a in found)
    value = exc.value
    if len(found) == 1 and value is not MISSING and not isinstance(value, str) and argv is not None:
        # A number the API converted (200.0 deg, -1.0) shown as the user typed it (200, -1).
        value = _typed_tokens(argv, found[0]) or value
    elif len(found) > 1 and value is not MISSING and not isinstance(value, str) and argv is not None:
        # Several options together (the rates whose energy overflows): each as typed, and those left at their
        # defaults said to be so, not a tuple of converted numbers under options nobody gave.
        tokens = [(a, _typed_tokens(argv, a)) for a in found]
        given = [(a, t) for a, t in tokens if t is not None]
        if given:
            typed = ", ".join(name(a) for a, _ in given)
            value = ", ".join(t for _, t in given)
            defaults = [f"{name(a)} {a.default}" for a, t in tokens if t is None and a.default is not None]
            if defaults:
                value += f" (and the default{'s' if len(defaults) > 1 else ''} {', '.join(defaults)})"
    return InputError(typed, value, exc.allowed)


def _typed_tokens(argv: list[str], action: argparse.Action) -> str | None:
    """The text typed after ``action``'s option (its last use), or None (not found, or a positional)."""
    count = action.nargs if isinstance(action.nargs, int) else 1 if action.nargs is None else None
    if not action.option_strings or count is None:
        return None
    found = None
    for i, token in enumerate(argv):
        option, eq, rest = token.partition("=")
        if option in action.option_strings:
            found = [rest] if eq and count == 1 else argv[i + 1 : i + 1 + count]
    return " ".join(found) if found else None


def _subparser(parser: argparse.ArgumentParser, command: str | None):
    """The parser of ``command`` (None for no command)."""
    choices = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    return choices.get(command) if command else None


def _silence_stdout() -> None:
    import os

    # Python flushes stdout at exit; point it at /dev/null so that flush cannot fail again.
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())


def _is_units_error(exc: BaseException) -> bool:
    # astropy.units is loaded only by commands that use it; its errors are bad input.
    units = sys.modules.get("astropy.units")
    return units is not None and isinstance(exc, units.UnitsError)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())
