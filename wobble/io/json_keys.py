"""Renamed JSON keys kept under their old names for one release, listed under ``deprecated_keys``.

Every ``--json`` output follows one rule when a key is renamed (README, "Commands"): the new
key holds the value, the old one holds the same value for one release, and the object that
holds them lists ``old path -> new path`` under ``deprecated_keys``. A path is relative to
that object: ``a.b`` (a key of a nested object), ``x[].y`` (a key of every element of a list)
and ``m.*.y`` (a key of every value of a map). This module is the one implementation; the
commands give it their renames.
"""

from __future__ import annotations

__all__ = ["deprecate", "values_at", "error_estimate_renames"]


def deprecate(doc: dict, renames: dict[str, str]) -> dict:
    """Add the old name of every renamed key in ``doc`` (same value) and list them under ``deprecated_keys``.

    Parameters
    ----------
    doc : dict
        A JSON-ready object, changed in place and returned.
    renames : dict
        ``old path -> new path``, relative to ``doc``. An old and a new path with the same parent
        (``x[].old`` and ``x[].new``) alias the key in every element; with different parents,
        each must name one value (no ``[]`` or ``*``). A new key absent from a parent (a key that
        appears only for some inputs) adds no alias there.

    Returns
    -------
    dict
        ``doc``, whose ``deprecated_keys`` (created if missing) now also lists ``renames``.
    """
    for old, new in renames.items():
        old_parent, old_key = _split(old)
        new_parent, new_key = _split(new)
        if old_parent == new_parent:
            for node in _parents(doc, old_parent):
                if new_key in node:
                    node[old_key] = node[new_key]
            continue
        sources, targets = _parents(doc, new_parent), _parents(doc, old_parent)
        if _is_pattern(old_parent) or _is_pattern(new_parent):
            raise ValueError(f"renames across parents must name single values: {old!r} -> {new!r}")
        if sources and targets and new_key in sources[0]:
            targets[0][old_key] = sources[0][new_key]
    doc.setdefault("deprecated_keys", {}).update(renames)
    return doc


def error_estimate_renames(keys) -> dict[str, str]:
    """``error_estimate.K -> error_estimate_K`` for each key K: the flat form of ``wobble run``'s JSON and of the
    netCDF attributes, which ``free`` and ``top`` now share (they held an object under the name that is a
    number in ``run``)."""
    return {f"error_estimate.{k}": f"error_estimate_{k}" for k in keys}


def values_at(doc: dict, path: str) -> list:
    """Every value the path reaches in ``doc`` (one per element or map value a ``[]`` or ``*`` goes through)."""
    parent, key = _split(path)
    return [node[key] for node in _parents(doc, parent) if key in node]


def _split(path: str) -> tuple[tuple[str, ...], str]:
    *parent, key = path.split(".")
    return tuple(parent), key


def _is_pattern(parent: tuple[str, ...]) -> bool:
    return any(part == "*" or part.endswith("[]") for part in parent)


def _parents(doc: dict, parent: tuple[str, ...]) -> list[dict]:
    """Every object the path ``parent`` reaches from ``doc`` (keys, ``name[]`` lists, ``*`` map values)."""
    nodes = [doc]
    for part in parent:
        reached = []
        for node in nodes:
            if part == "*":
                reached.extend(v for v in node.values() if isinstance(v, dict))
            elif part.endswith("[]"):
                items = node.get(part[:-2])
                if isinstance(items, list):
                    reached.extend(x for x in items if isinstance(x, dict))
            elif isinstance(node.get(part), dict):
                reached.append(node[part])
        nodes = reached
    return nodes
