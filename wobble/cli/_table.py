"""The two-column summaries the subcommands print when ``--json`` is not given."""

from __future__ import annotations

__all__ = ["fmt", "print_rows"]


def fmt(v) -> str:
    """A value for a person: ``-`` for None, yes/no, floats to 15 digits, short lists."""
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.15g}"
    if isinstance(v, list):
        return ", ".join(fmt(x) for x in v[:6]) + (" ..." if len(v) > 6 else "")
    return str(v)


def print_rows(rows) -> None:
    """Print ``(label, value)`` pairs with the labels aligned."""
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"{k:<{width}}  {v if isinstance(v, str) else fmt(v)}")
