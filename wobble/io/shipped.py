"""Files shipped with wobble: the body catalogue, example scenes, sweeps and inputs.

Everything under ``data/`` is installed as the package data ``wobble._data``,
so a command finds a shipped file by its name from any folder
(``wobble run tennis_racket``, ``wobble inertia --points dumbbell.csv``) and
``wobble example NAME`` copies one into the user's folder to start from.

A name given on the command line is looked up in this order: an existing file
at that path (the user's own always wins), then a shipped file of the kinds the
option accepts, by file name with or without its extension.
"""

from __future__ import annotations

import os
import shutil
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from wobble.errors import InputError

__all__ = [
    "KINDS",
    "ShippedFile",
    "shipped_files",
    "find_shipped",
    "resolve",
    "copy_shipped",
    "shown_names",
    "not_a_file",
]

# Folder of data/ -> what its files are, as `wobble example --list` heads them (in this order).
KINDS = {
    "bodies": "planets of the catalogue (wobble chandler NAME)",
    "profiles": "radial density profiles (wobble modes --profile NAME)",
    "inversions": "inversion set-ups (wobble invert NAME)",
    "precession": "perturbers (wobble precession --perturber NAME) and the published references",
    "examples": "example inputs",
    "scenes": "scenes (wobble run NAME)",
    "sweeps": "sweeps (wobble sweep NAME)",
}
_INDEX = "index.toml"  # descriptions of the examples/ files that cannot describe themselves


@dataclass(frozen=True)
class ShippedFile:
    """One shipped file: its name, kind (a :data:`KINDS` key) and one-line description."""

    name: str
    kind: str
    description: str

    @property
    def stem(self) -> str:
        return self.name.rsplit(".", 1)[0]

    @property
    def qualified(self) -> str:
        """``kind/name``: unique among every shipped file."""
        return f"{self.kind}/{self.name}"

    def path(self):
        """The file as an importlib Traversable (use :func:`importlib.resources.as_file`)."""
        return resources.files("wobble._data") / self.kind / self.name


def _first_line(text: str) -> str:
    return " ".join(str(text).split())


def _describe_toml(entry) -> str:
    try:
        data = tomllib.loads(entry.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError):
        return ""
    return _first_line(data.get("title") or data.get("description") or "")


def _index() -> dict[str, str]:
    entry = resources.files("wobble._data") / "examples" / _INDEX
    if not entry.is_file():
        return {}
    data = tomllib.loads(entry.read_text(encoding="utf-8"))
    return {name: _first_line(item.get("description", "")) for name, item in data.get("files", {}).items()}


def shipped_files(kinds=None) -> list[ShippedFile]:
    """Every shipped file of the given kinds (default: all), sorted by kind then name."""
    wanted = list(KINDS) if kinds is None else [kinds] if isinstance(kinds, str) else list(kinds)
    out = []
    index = _index()
    for kind in wanted:
        folder = resources.files("wobble._data") / kind
        if not folder.is_dir():
            continue
        for entry in sorted(folder.iterdir(), key=lambda e: e.name):
            name = entry.name
            if not entry.is_file() or name.startswith(("_", ".")) or name == _INDEX or name.endswith(".py"):
                continue
            description = index.get(name) or (_describe_toml(entry) if name.endswith(".toml") else "")
            out.append(ShippedFile(name, kind, description))
    return out


def find_shipped(name: str, kinds=None, suffixes=None) -> ShippedFile | None:
    """The shipped file called ``name`` (with or without its extension), or None.

    ``name`` may carry its folder (``inversions/mars``) where the same file name ships in
    several folders; an unqualified name that several folders hold is an error listing them.
    """
    key = os.fspath(name).strip()
    folder, _, base = key.rpartition("/")
    found = [f for f in _candidates(kinds, suffixes) if base in (f.name, f.stem) and folder in ("", f.kind)]
    if len(found) > 1:
        choices = ", ".join(f.qualified for f in found)
        raise InputError("NAME", key, f"one of {choices} (the same name ships in several folders)")
    return found[0] if found else None


def _candidates(kinds, suffixes) -> list[ShippedFile]:
    files = shipped_files(kinds)
    return files if suffixes is None else [f for f in files if f.name.endswith(tuple(suffixes))]


def shown_names(files: list[ShippedFile]) -> list[str]:
    """The names of ``files`` as a user types them: with the folder where several ship the
    same name (``bodies/earth.toml``, ``inversions/earth.toml``), else the bare name."""
    counts: dict[str, int] = {}
    for f in files:
        counts[f.name] = counts.get(f.name, 0) + 1
    return [f.qualified if counts[f.name] > 1 else f.name for f in files]


def _names(kinds, suffixes=None) -> str:
    return ", ".join(shown_names(_candidates(kinds, suffixes))) or "none"


def not_a_file(text: str | os.PathLike) -> str:
    """Why ``text``, which names no file to read, is refused, as a refusal's parenthesis says it.

    ``"an empty path was given"``, ``"it is a folder"``, ``"it is not a regular file"`` (a device such
    as /dev/null) or ``"there is no such file"``. An empty path is told so first: ``Path("")`` is the
    current folder, and "" was called a folder.
    """
    if not os.fspath(text):
        return "an empty path was given"
    path = Path(os.fspath(text))
    if path.is_dir():
        return "it is a folder"
    return "it is not a regular file" if path.exists() else "there is no such file"


def resolve(text: str | os.PathLike, kinds, parameter: str, suffixes=None) -> str:
    """A path to read for ``text``: the user's file if it exists, else the shipped one.

    Parameters
    ----------
    text : str or path-like
        What the user typed.
    kinds : str or sequence of str
        The :data:`KINDS` the option accepts.
    parameter : str
        The option, for the error message.
    suffixes : sequence of str, optional
        File name endings the option reads (``(".csv",)``); other shipped files are not offered.

    Returns
    -------
    str
        A file system path (shipped files live in the installed package).

    Raises
    ------
    wobble.errors.InputError
        Neither a file nor a shipped name; the message lists the shipped names.
    """
    text = os.fspath(text)
    if text and Path(text).is_file():
        return text  # as typed, so that a message about the file names it as the user did
    found = find_shipped(text, kinds, suffixes) if text.strip() else None
    if found is not None:
        return str(found.path())
    raise InputError(
        parameter, text, f"an existing file ({not_a_file(text)}), or a shipped one: {_names(kinds, suffixes)}"
    )


def copy_shipped(name: str, dest: str | os.PathLike | None = None, *, overwrite: bool = False) -> Path:
    """Copy the shipped file ``name`` to ``dest`` (a file or a folder; default ``./NAME``).

    The copy is written under a temporary name and renamed, never replacing an
    existing file unless ``overwrite``.
    """
    from wobble.io.atomic import atomic_target

    found = find_shipped(name)
    if found is None:
        raise InputError("NAME", name, f"a shipped file: {_names(None)} (wobble example --list)")
    target = Path(dest) if dest is not None else Path(found.name)
    if target.is_dir():
        target = target / found.name
    with resources.as_file(found.path()) as source, atomic_target(target, overwrite) as tmp:
        # A failure names its file: the source for a broken installation, the target for a full disk.
        shutil.copyfile(source, tmp)
    return target
