"""Free modes against the core's flattening: the FCN lesson in one picture, with the Clairaut profile."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from astropy import units as u

from wobble.plot._style import legend_beside

__all__ = ["modes_figure"]

#: Inches beside each panel for its legend ("Chandler budget (coupling off)" at 7 points).
LEGEND_WIDTH = 1.5


def _band(ax, value, sigma, color, label):
    ax.axhspan(value - sigma, value + sigma, color=color, alpha=0.25, lw=0)
    ax.axhline(value, color=color, lw=1, label=label)


def modes_figure(results, path=None, *, overwrite: bool = False):
    """One row per planet: Clairaut's eps(r), the FCN in space and the CW against e_f.

    Parameters
    ----------
    results : list of wobble.NormalModes
        Bodies whose FCN is modelled get all three panels; others only the CW. A mode not
        shown (``modes=`` of :func:`wobble.normal_modes`, ``wobble modes --mode``) is not drawn.
    path : path-like, optional
        Save the figure (PNG, 150 dpi).

    Returns
    -------
    matplotlib.figure.Figure
    """
    # A column per mode some planet shows (wobble modes --mode FCN left a blank third of the figure), each
    # with room for its legend beside it: inside, the legends covered the +-1 sigma bands.
    columns = [m for m in ("FCN", "CW") if any(m in r.shown for r in results)]
    width = (11.0 / 3 + LEGEND_WIDTH) * (1 + len(columns))
    fig, axes = plt.subplots(len(results), 1 + len(columns), figsize=(width, 3.1 * len(results) + 0.4), squeeze=False)
    for row, r in zip(axes, results):
        _profile_panel(row[0], r)
        panels = dict(zip(columns, row[1:]))
        hyd = r.core_flattening_hydrostatic
        grid = None if hyd is None else np.linspace(0.85 * hyd, 1.15 * hyd, 61)
        periods = None if grid is None else r.periods_against_core_flattening(grid)
        for mode, ax in panels.items():
            if mode not in r.shown or (mode == "FCN" and grid is None):
                ax.set_axis_off()  # not asked for, or no liquid core to give the FCN
            elif mode == "FCN":
                _fcn_panel(ax, r, grid, periods["FCN_celestial"].to_value(u.day))
            elif grid is None:
                _cw_alone_panel(ax, r)
            else:
                _cw_panel(ax, r, grid, periods["CW"].to_value(u.day))
    fig.tight_layout()
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
        plt.close(fig)
    return fig


def _profile_panel(ax, r):
    # Wrapped: a body file's long title was cut at the figure's edge ("y planet ...").
    ax.set_title(textwrap.fill(f"{r.planet.title}: hydrostatic level surfaces", 48), fontsize=9)
    if r.figure is None:
        ax.text(
            0.5,
            0.5,
            "no density profile:\nno hydrostatic figure, no FCN",
            ha="center",
            va="center",
            transform=ax.transAxes,
        )
        ax.set_axis_off()  # an empty 0-1 frame read as a plot of nothing
        return
    radius = r.figure.radius.to_value(u.km)
    ax.plot(radius, 1.0 / r.figure.flattening, color="C0")
    ax.set_xlabel("radius [km]")
    ax.set_ylabel("1 / flattening (Clairaut)")
    anchors = r.figure.anchors
    if "observed_flattening" in anchors:
        ax.axhline(1.0 / anchors["observed_flattening"][0], color="0.4", ls=":", lw=1, label="observed surface")
        legend_beside(ax, fontsize=7)


def _fcn_panel(ax, r, grid, period):
    fcn = r.mode("FCN", "celestial")
    ax.plot(grid * 1e3, period, color="C3", label="FCN in space (model)")
    if fcn.observed is not None:
        _band(ax, fcn.observed.to_value(u.day), fcn.observed_uncertainty.to_value(u.day), "0.3", "observed")
    ax.axvline(r.core_flattening_hydrostatic * 1e3, color="C0", ls="--", lw=1, label="hydrostatic $e_f$")
    if r.core_flattening_required is not None:
        ax.axvline(r.core_flattening_required * 1e3, color="C2", ls="-.", lw=1, label="required $e_f$")
    ax.set_xlabel("core dynamical ellipticity $e_f$ [$10^{-3}$]")
    ax.set_ylabel("FCN period in space [d]")
    ax.set_title("free core nutation (retrograde)", fontsize=9)
    legend_beside(ax, fontsize=7)


def _cw_panel(ax, r, grid, period):
    cw = r.mode("CW")
    ax.plot(grid * 1e3, period, color="C1", label="CW (model, coupled)")
    # The model's own uncertainty beside the observed band: without it a 0.5-sigma miss looked like 2.6.
    sigma = cw.period_uncertainty.to_value(u.day) if cw.period_uncertainty is not None else float("nan")
    if np.isfinite(sigma):
        ax.fill_between(grid * 1e3, period - sigma, period + sigma, color="C1", alpha=0.15, lw=0, label="model ±1σ")
    if cw.observed is not None:
        _band(ax, cw.observed.to_value(u.day), cw.observed_uncertainty.to_value(u.day), "0.3", "observed")
    # The budget is this model with the core coupling off (the text's "coupling off ... = the Chandler budget"),
    # not the first-order formula, which the text quotes apart.
    ax.axhline(
        r.chandler_budget_period.to_value(u.day), color="C1", ls=":", lw=1, label="Chandler budget (coupling off)"
    )
    ax.axvline(r.core_flattening_hydrostatic * 1e3, color="C0", ls="--", lw=1, label="hydrostatic $e_f$")
    ax.set_xlabel("core dynamical ellipticity $e_f$ [$10^{-3}$]")
    ax.set_ylabel("Chandler period [d]")
    ax.set_title("Chandler wobble (prograde)", fontsize=9)
    legend_beside(ax, fontsize=7)


def _cw_alone_panel(ax, r):
    """The Chandler period with its uncertainty beside the observed one, for a body without a liquid-core model
    (nothing to vary it against): the text printed it and the figure drew nothing."""
    cw = r.mode("CW")
    _band(ax, cw.period.to_value(u.day), cw.period_uncertainty.to_value(u.day), "C1", "CW (model)")
    if cw.observed is not None:
        _band(ax, cw.observed.to_value(u.day), cw.observed_uncertainty.to_value(u.day), "0.3", "observed")
    ax.set_xticks([])
    ax.set_ylabel("Chandler period [d]")
    ax.set_title("Chandler wobble (prograde; no liquid core to vary)", fontsize=9)
    legend_beside(ax, fontsize=7)
