"""How every subcommand speaks: JSON for scripts, "wrote PATH" lines, numbers for people.

* ``--json`` prints one JSON document on stdout (:func:`print_json`; the format is
  :func:`wobble.io.text.dumps`);
* every file written is announced by one line ``wrote PATH`` (on stdout, or on stderr
  under ``--json`` so that stdout stays one JSON document);
* numbers in text go through :mod:`wobble.io.text` (re-exported here).
"""

from __future__ import annotations

import sys

from wobble.io.text import clean, decimals_for, dumps, duration, number, with_uncertainty

__all__ = ["clean", "dumps", "print_json", "wrote", "number", "with_uncertainty", "decimals_for", "duration"]


def print_json(obj) -> None:
    """Print ``obj`` as one JSON document on stdout."""
    print(dumps(obj))


def wrote(path, *, json_mode: bool = False) -> None:
    """Announce a written file: ``wrote PATH`` (stderr under --json, stdout otherwise)."""
    print(f"wrote {path}", file=sys.stderr if json_mode else sys.stdout)
