"""Work-precision diagrams: error on x, seconds on y (log-log), one line per method.

Takes the plain rows of :mod:`wobble.bench` (dicts with ``method``, ``error``,
``t_min``), so the numerics never see matplotlib.
"""

from __future__ import annotations

import math
import textwrap

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

__all__ = ["work_precision_figure", "ERROR_FLOOR"]

# Errors of exactly zero (rounding) cannot sit on a log axis: drawn at this floor, and
# the caption says so.
ERROR_FLOOR = 1e-17


def work_precision_figure(title: str, rows: list[dict], *, xlabel: str = "error", per_member: bool = False) -> Figure:
    """One line per method through its (error, minimum time) points, settings in order of cost.

    Parameters
    ----------
    title : str
        Figure title (the case).
    rows : list of dict
        Each with ``method``, ``error`` and ``t_min`` (s), or ``per_member_s`` when
        ``per_member``; rows with a non-finite error are left out.
    xlabel : str
        What the error is.
    per_member : bool
        Plot seconds per member (ensembles).
    """
    fig = Figure(figsize=(7.0, 4.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    methods = list(dict.fromkeys(r["method"] for r in rows))
    markers = "osD^v<>ph*XP"
    for k, m in enumerate(methods):
        pts = [
            (max(r["error"], ERROR_FLOOR), r["per_member_s"] if per_member else r["t_min"])
            for r in rows
            if r["method"] == m and math.isfinite(r["error"])
        ]
        if not pts:
            continue
        pts.sort(key=lambda p: p[1])
        ax.plot(
            [p[0] for p in pts],
            [p[1] for p in pts],
            marker=markers[k % len(markers)],
            color=f"C{k % 10}",
            ls="-" if k < 10 else "--",
            label=m,
            lw=1.6 if m.startswith("wobble") else 1.0,
            ms=5,
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    # The case's description is reST for the docs (``omega``): plain text here, wrapped to the figure's width
    # (it was cut at both ends); the floor is named only when an error was drawn on it.
    floored = any(r["error"] < ERROR_FLOOR for r in rows if math.isfinite(r["error"]))
    label = xlabel.replace("``", "") + (f" (zero drawn at {ERROR_FLOOR:g})" if floored else "")
    ax.set_xlabel(textwrap.fill(label, 95), fontsize=8)
    ax.set_ylabel("seconds per member (min)" if per_member else "seconds (min of runs)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig
