"""The Chandler budget as a picture: from the rigid period to the observed one, step by step."""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
from astropy import units as u

from wobble.plot._style import pm

__all__ = ["budget_figure"]

_COLORS = {"rigid": "0.35", "lengthens": "C0", "shortens": "C3"}


def budget_figure(budgets, path=None, *, overwrite: bool = False):
    """A waterfall per planet: each step's change of the period, the model and the observation.

    Parameters
    ----------
    budgets : wobble.ChandlerBudget or list of them
        One panel each.
    path : path-like, optional
        Save the figure (PNG, PDF or SVG by suffix; 150 dpi), atomically.
    overwrite : bool
        Replace an existing ``path``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    budgets = _budgets(budgets)
    fig, axes = plt.subplots(len(budgets), 1, figsize=(8.8, 2.3 * len(budgets) + 0.6), squeeze=False)
    for ax, b in zip(axes[:, 0], budgets):
        steps = b.steps
        names = [s.name.replace("_", " ") for s in steps]
        previous = 0.0
        for i, s in enumerate(steps):
            value = s.period.to_value(u.day)
            if s.name == "rigid":
                # A mark, not a bar: the axis does not start at zero, so a bar's length would mean nothing.
                ax.plot([value], [i], "D", color=_COLORS["rigid"], ms=7)
                ax.annotate(
                    f"{value:.1f} d", (value, i), xytext=(8, 0), textcoords="offset points", va="center", fontsize=8
                )
            else:
                color = _COLORS["lengthens"] if value > previous else _COLORS["shortens"]
                ax.barh(i, value - previous, left=previous, color=color, height=0.6)
                # Changes in a column at the right edge, clear of the bars and lines.
                ax.text(
                    0.99,
                    i,
                    f"{value - previous:+.1f} d",
                    va="center",
                    ha="right",
                    fontsize=8,
                    transform=ax.get_yaxis_transform(),
                )
            previous = value
        model = b.period.to_value(u.day)
        sigma = b.period_uncertainty.to_value(u.day)
        ax.axvspan(model - sigma, model + sigma, color="C0", alpha=0.12, lw=0)
        # The digits the text prints (the uncertainty's two significant ones: Mars' 206.90 +/- 0.50).
        ax.axvline(model, color="C0", lw=1.2, label=f"model {pm(model, sigma)} d")
        if b.observed is not None:
            obs = b.observed.to_value(u.day)
            osig = b.observed_uncertainty.to_value(u.day)
            ax.axvspan(obs - osig, obs + osig, color="k", alpha=0.15, lw=0)
            ax.axvline(obs, color="k", lw=1.5, ls="--", label=f"observed {pm(obs, osig)} d")
        ax.set_yticks(range(len(names)), names)
        ax.invert_yaxis()
        first = steps[0].period.to_value(u.day)
        top = max(s.period.to_value(u.day) for s in steps if math.isfinite(s.period.value))
        ax.set_xlim(0.85 * first, 1.18 * top)
        ax.set_title(f"{b.planet.title}: Chandler period, step by step (days of 86400 s)", fontsize=10)
        # Beside the axes: no corner inside is empty for every planet (upper right hid a change on Earth's,
        # lower left the one bar of a planet with two steps).
        ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize=8, frameon=False)
        ax.set_xlabel("period [d]")
    fig.tight_layout()
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
    return fig


def _budgets(budgets) -> list:
    """One budget or a list of them, each a :class:`wobble.ChandlerBudget`."""
    from wobble.api.chandler import ChandlerBudget
    from wobble.errors import InputError

    items = (
        [budgets]
        if isinstance(budgets, ChandlerBudget)
        else list(budgets)
        if isinstance(budgets, (list, tuple))
        else None
    )
    if not items or not all(isinstance(b, ChandlerBudget) for b in items):
        raise InputError(
            "budgets", budgets, 'a ChandlerBudget or a list of them (e.g. [wobble.chandler_budget("earth")])'
        )
    return items
