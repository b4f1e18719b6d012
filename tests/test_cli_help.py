"""`wobble --help` and every subcommand's help are complete, each with an example that parses.

The subcommands are read from ``wobble.cli.SUBCOMMANDS``, so a new one is checked
without touching this file. The examples are parsed (never run) by the real parser.
"""

from __future__ import annotations

import argparse
import re

import pytest

from wobble.cli import SUBCOMMANDS, build_parser, main
from wobble.cli._examples import example_commands

COMMANDS = [name.replace("_", "-") for name in SUBCOMMANDS]  # module polar_motion -> polar-motion


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    (action,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(action.choices)


def _help(capsys, *argv: str) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, "--help"])
    out, err = capsys.readouterr()
    assert exit_info.value.code == 0, err
    assert not err
    return out


def test_the_command_list_is_read_from_the_cli():
    assert set(_subparsers(build_parser())) == set(COMMANDS)


def test_top_level_help_lists_every_command_with_examples(capsys):
    out = _help(capsys)
    assert out.startswith("usage: wobble")
    for name in COMMANDS:
        assert re.search(rf"^\s+{re.escape(name)}\b", out, flags=re.M), f"'wobble --help' does not list {name}"
    examples = example_commands(out)
    assert {argv[1] for argv in examples} == set(COMMANDS), "each command needs an example in 'wobble --help'"
    parser = build_parser()
    for argv in examples:
        parser.parse_args(argv[1:])  # a bad example exits with status 2


@pytest.mark.parametrize("name", COMMANDS)
def test_subcommand_help_is_complete(name, capsys):
    out = _help(capsys, name)
    assert out.startswith(f"usage: wobble {name}")
    sub = _subparsers(build_parser())[name]
    assert sub.description, f"wobble {name} has no description"
    for action in sub._actions:
        label = "/".join(action.option_strings) or action.dest
        assert action.help and action.help is not argparse.SUPPRESS and action.help.strip(), (
            f"wobble {name}: {label} has no help text"
        )
        for option in action.option_strings:
            assert option in out


@pytest.mark.parametrize("name", COMMANDS)
def test_subcommand_examples_parse(name, capsys):
    examples = example_commands(_help(capsys, name))
    assert any(argv[:2] == ["wobble", name] for argv in examples), f"'wobble {name} --help' has no example of itself"
    parser = build_parser()
    for argv in examples:  # a step such as 'wobble example FILE' may come first
        assert argv[0] == "wobble", argv
        args = parser.parse_args(argv[1:])
        assert callable(args.func)


def test_example_parser_reads_continuations_and_descriptions():
    text = """examples:
  wobble top --I1 1 \\
             --I3 0.5 --mgl 1
                                  a description on its own line
  wobble run x.toml -o "my file.nc"   a description
not an example: wobble free
"""
    assert example_commands(text) == [
        ["wobble", "top", "--I1", "1", "--I3", "0.5", "--mgl", "1"],
        ["wobble", "run", "x.toml", "-o", "my file.nc"],
    ]


def test_readme_lists_every_command_and_the_docs_build():
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    commands = readme[readme.index("## Commands") :]
    for name in COMMANDS:
        assert f"| `wobble {name}` |" in commands, f"README's Commands table lacks wobble {name}"
    assert "python -m sphinx -W docs docs/_build" in readme


def test_version_is_the_installed_distributions():
    # --version reads the version only when asked (importlib.metadata costs ~60 ms of every start-up).
    import subprocess
    import sys
    from importlib.metadata import version

    out = subprocess.run([sys.executable, "-m", "wobble", "--version"], capture_output=True, text=True, check=True)
    assert out.stdout == f"wobble {version('wobble')}\n" and out.stderr == ""
    import wobble

    assert wobble.__version__ == version("wobble") and "__version__" in dir(wobble)


def test_help_examples_walked_in_one_folder_do_not_collide():
    # Was: `wobble --help` wrote free.nc, racket.nc and mars.nc, so the same names in `free --help`,
    # `run --help` and `sweep --help` then stopped with "file exists" for a user trying every example.
    from wobble.cli._examples import help_examples

    written: dict[str, str] = {}
    for help_name, commands in help_examples().items():
        for argv in commands:
            targets = [argv[i + 1] for i, a in enumerate(argv[:-1]) if a in ("-o", "--output", "--plot")]
            if argv[0] == "example" and len(argv) > 1 and not argv[1].startswith("-"):
                rest = [a for a in argv[2:] if not a.startswith("-")]
                targets.append(rest[0] if rest else argv[1].split("/")[-1])
            for target in targets:
                earlier = written.get(target)
                assert earlier is None or "--overwrite" in argv, (target, earlier, help_name, argv)
                written[target] = help_name


def test_run_help_lists_every_model():
    from wobble.models.scene import MODEL_NAMES

    text = _subparsers(build_parser())["run"].format_help()
    assert all(name in " ".join(text.split()) for name in (*MODEL_NAMES, "auto"))
