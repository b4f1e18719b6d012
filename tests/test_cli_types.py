"""``wobble.cli._types``: a count or a number the command line cannot read is refused as every other
bad input is, in one line naming the option, what was typed and what is allowed (argparse's own
``type=int`` said "invalid int value" and no more)."""

from __future__ import annotations

import pytest


def _counted_options():
    """(command, option, type) of every option the command line parses as a whole number or a real number."""
    from wobble.cli import build_parser
    from wobble.cli._types import real_number, whole_number

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    found = []
    for command, p in sub.choices.items():
        for action in p._actions:
            if action.type in (whole_number, real_number) and action.option_strings:
                found.append((command, action.option_strings[-1], action.type.__name__))
    return found


def test_every_counted_option_is_found():
    found = {(c, o) for c, o, _ in _counted_options()}
    assert {("free", "--samples"), ("top", "--samples"), ("invert", "--walkers"), ("inertia", "--tolerance")} <= found
    # No option parses with argparse's bare int or float (whose refusal says "invalid int value" and no more).
    from wobble.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    assert not [(c, a.dest) for c, p in sub.choices.items() for a in p._actions if a.type in (int, float)]


@pytest.mark.parametrize(("command", "option", "kind"), _counted_options())
def test_a_count_that_is_not_one_is_refused_in_one_line_naming_the_option(command, option, kind, capsys):
    from cli_run import run_cli

    typed = "2.5" if kind == "whole_number" else "nan"
    code, out, err = run_cli([command, option, typed], capsys)
    allowed = (
        "a whole number of at most 30 digits (1001, 1e3)" if kind == "whole_number" else "a finite number (1e-10, 0.5)"
    )
    assert (code, out) == (2, "")
    assert err == f"wobble {command}: error: {option}: got {typed}; allowed: {allowed}\n"


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1001", 1001),
        ("1_000", 1000),
        ("1e3", 1000),
        ("-4", -4),
        ("10.0", 10),
        (" 5 ", 5),
        ("-0", 0),
        ("1e16", 10**16),  # read as the decimal typed, not through a float
        ("9007199254740993.0", 2**53 + 1),  # a float would make it 2**53
        ("1e29", 10**29),
    ],
)
def test_a_whole_number_may_be_typed_as_a_float_literal_with_no_fraction(text, value):
    from wobble.cli._types import whole_number

    assert whole_number(text) == value and type(whole_number(text)) is int


@pytest.mark.parametrize(
    "text",
    ["2.5", "1e300", "inf", "nan", "x", "", "1e-400", "1.0000000000000001", "0.99999999999999999", "0x10", "_1", "1__0"]
    + ["1e30", "1" * 31, "1e999999999"],
)
def test_what_is_not_a_whole_number_is_refused(text):
    import argparse

    from wobble.cli._types import whole_number

    with pytest.raises(argparse.ArgumentTypeError) as caught:
        whole_number(text)
    shown = repr(text) if not text.strip() else text if len(text) <= 200 else text[:97] + "..." + text[-100:]
    assert str(caught.value) == f"got {shown}; allowed: a whole number of at most 30 digits (1001, 1e3)"
