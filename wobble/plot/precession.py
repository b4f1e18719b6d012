"""The precession budget as a picture: each term's share of the rate, and the model against the observation."""

from __future__ import annotations

import matplotlib.pyplot as plt

from wobble.api.precession import ARCSEC_PER_CENTURY
from wobble.plot._style import pm

__all__ = ["budget_figure"]


def _number(ax, row, text):
    """A bar's number in the column at the left edge, clear of the bars (which run left from zero)."""
    ax.text(0.01, row, text, va="center", ha="left", fontsize=8, transform=ax.get_yaxis_transform())


def _rows(b) -> list[tuple[str, float]]:
    """(name, rate in arcsec/cy) of each bar: the budget's terms, the planets' summed into one (as the text)."""
    rows = []
    for t in b.terms:
        if t.name not in b.planet_terms:
            rows.append((t.name, t.rate.to_value(ARCSEC_PER_CENTURY)))
        elif not any(name == "planets" for name, _ in rows):
            rows.append(("planets", b.planetary.to_value(ARCSEC_PER_CENTURY)))
    return rows


def budget_figure(budgets, path=None, *, overwrite: bool = False):
    """One panel per body: a horizontal waterfall of the terms, then the model and the observed rate.

    Parameters
    ----------
    budgets : list of wobble.PrecessionBudget
    path : path-like, optional
        Save the figure (PNG, 150 dpi).

    Returns
    -------
    matplotlib.figure.Figure
    """
    rows = [_rows(b) for b in budgets]
    fig, axes = plt.subplots(len(budgets), 1, figsize=(7.2, 0.42 * sum(len(r) + 3 for r in rows) + 0.8), squeeze=False)
    for ax, b, terms in zip(axes[:, 0], budgets, rows):
        running = 0.0
        left_out = [] if b.includes_geodesic else ["geodesic"]  # the model compared is the tidal rate
        for i, (name, value) in enumerate(terms):
            if name in left_out:  # drawn apart, hatched, and not added: the model bar below leaves it out
                ax.barh(i, value, left=0.0, color="none", edgecolor="0.5", hatch="///", height=0.6)
            else:
                ax.barh(i, value, left=running, color="C3" if value < 0 else "C0", height=0.6)
                running += value
            _number(ax, i, f"{value:+.3f}")
        model = b.rate.to_value(ARCSEC_PER_CENTURY)
        sigma = b.rate_uncertainty.to_value(ARCSEC_PER_CENTURY)
        n = len(terms)
        ax.barh(n, model, color="0.35", height=0.6)
        # The digits the text prints (the uncertainty's two significant ones): "+/- 0.001" where it said 0.00080.
        _number(ax, n, pm(model, sigma))
        labels = [name.replace("_", " ") + (" (not in the model)" if name in left_out else "") for name, _ in terms]
        labels.append("model (with geodesic)" if b.includes_geodesic else "model (tidal)")
        if b.observed is not None:
            obs = b.observed.to_value(ARCSEC_PER_CENTURY)
            osig = b.observed_uncertainty.to_value(ARCSEC_PER_CENTURY)
            ax.barh(n + 1, obs, color="k", height=0.6)
            _number(ax, n + 1, pm(obs, osig))
            labels.append("observed")
        ax.set_yticks(range(len(labels)), labels)
        ax.invert_yaxis()
        # Bars run left from zero; the numbers sit in a column at the left edge, clear of them.
        low = min(model, 0.0) * 1.6
        ax.set_xlim(low, -0.02 * low)
        ax.set_xlabel("rate of the equator's node [arcsec per Julian century]; negative = retrograde", fontsize=8)
        title = f"{b.planet.title}: forced precession, term by term"
        if b.residual is not None:  # a few thousandths of the bars: written, since it cannot be seen
            title += f"\nmodel - observed {b.residual.to_value(ARCSEC_PER_CENTURY):+.3f} ({b.residual_sigma:+.1f} σ)"
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
        plt.close(fig)
    return fig


def nutation_ellipse_figure(budget, path=None, *, overwrite: bool = False):
    """The pole's 18.6-year nutation ellipse: Delta psi sin(eps) against Delta eps, rigid model and IAU 2000A.

    Parameters
    ----------
    budget : wobble.PrecessionBudget
        A body with a perturber whose node regresses (Earth: the Moon).
    path : path-like, optional
        Save the figure (PNG, 150 dpi).
    """
    import numpy as np
    from astropy import units as u

    if not budget.nutation:
        raise ValueError(f"{budget.body} has no perturber with a node rate (no principal nutation)")
    n = budget.nutation[0]
    eps = budget.planet.parameters.obliquity.value
    omega = np.linspace(0.0, 2 * np.pi, 361)
    fig, ax = plt.subplots(figsize=(5.6, 4.4))
    curves = [("rigid body, first order (this model)", n.longitude, n.obliquity, "C0", "-")]
    if n.reference_longitude is not None:
        curves.append(("IAU 2000A (non-rigid Earth)", n.reference_longitude, n.reference_obliquity, "k", "--"))
    for label, lon, obl, color, style in curves:
        a, b = lon.to_value(u.arcsec), obl.to_value(u.arcsec)
        ax.plot(
            a * np.sin(omega) * np.sin(eps),
            b * np.cos(omega),
            color=color,
            ls=style,
            label=f'{label}: {a:+.4f}", {b:+.4f}"',
        )
    for deg in (0, 90, 180, 270):
        w = np.radians(deg)
        a, b = n.longitude.to_value(u.arcsec), n.obliquity.to_value(u.arcsec)
        ax.plot(a * np.sin(w) * np.sin(eps), b * np.cos(w), "o", color="C0", ms=3)
        ax.annotate(
            f"Ω = {deg}°",
            (a * np.sin(w) * np.sin(eps), b * np.cos(w)),
            fontsize=7,
            xytext=(4, 4),
            textcoords="offset points",
        )
    ax.set_aspect("equal")
    ax.set_xlabel("Δψ sin ε [arcsec] (along the ecliptic, IAU sign)")
    ax.set_ylabel("Δε [arcsec]")
    ax.set_title(
        f"{budget.planet.title}: principal nutation ({n.period.to_value(u.yr):.2f} yr, the "
        f"{n.perturber.capitalize()}'s node)",
        fontsize=9,
    )
    ax.legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.08), frameon=False)
    fig.tight_layout()
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
        plt.close(fig)
    return fig
