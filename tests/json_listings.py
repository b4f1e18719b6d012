"""Walking a command's JSON for its rename listings (shared by the JSON tests)."""

from __future__ import annotations


def listings(node):
    """Every object in ``node`` (at any depth) that lists renames under ``deprecated_keys``."""
    if isinstance(node, dict):
        if "deprecated_keys" in node:
            yield node
        for value in node.values():
            yield from listings(value)
    elif isinstance(node, list):
        for value in node:
            yield from listings(value)
