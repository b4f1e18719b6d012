"""The example command lines of every help text, as the tests and scripts run them.

Every example printed by ``wobble --help`` and ``wobble COMMAND --help`` must run as
printed, from any folder, on a fresh install (``tests/test_help_examples.py`` runs them
in empty temporary folders; ``scripts/check_help_examples.py`` runs every one, the long
benchmarks too).
"""

from __future__ import annotations

import argparse
import re
import shlex

__all__ = ["example_commands", "help_texts", "help_examples"]


def example_commands(text: str) -> list[list[str]]:
    """The ``wobble ...`` command lines of a help text's examples, as argument lists.

    A line ending in a backslash continues on the next; a description after a
    command is separated from it by three or more spaces (or put on its own line).
    """
    lines = text.splitlines()
    try:
        start = next(i for i, line in enumerate(lines) if line.strip().lower().startswith("example"))
    except StopIteration:
        return []
    commands, pending = [], None
    for line in lines[start + 1 :]:
        stripped = line.strip()
        if pending is not None:
            pending += " " + stripped
        elif stripped.startswith("wobble "):
            pending = stripped
        else:
            continue
        if pending.endswith("\\"):
            pending = pending[:-1].rstrip()
            continue
        command = re.split(r"\s{3,}", pending)[0]
        commands.append(shlex.split(command))
        pending = None
    if pending is not None:
        raise ValueError(f"unterminated example: {pending!r}")
    return commands


def help_texts(parser: argparse.ArgumentParser) -> dict[str, str]:
    """``{"wobble": top-level help, "chandler": its help, ...}`` for a built parser."""
    (action,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    texts = {"wobble": parser.format_help()}
    texts.update({name: sub.format_help() for name, sub in action.choices.items()})
    return texts


def help_examples() -> dict[str, list[list[str]]]:
    """Every help text's examples (argument lists without the leading ``wobble``), by help text."""
    from wobble.cli import build_parser

    return {name: [argv[1:] for argv in example_commands(text)] for name, text in help_texts(build_parser()).items()}
