"""Figures for sweeps: the distribution of a swept output against the observed value."""

from __future__ import annotations

import math

import numpy as np

from wobble.plot._style import unit_label

__all__ = ["histogram", "phase_diagram", "ensemble"]


def histogram(ds, path=None, variable: str = "chandler_period", ax=None, *, overwrite: bool = False):
    """Histogram of ``variable`` over the valid members, with the observed value marked.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep's results (``invalid_reason`` selects the valid members).
    path : path-like, optional
        Save the figure there (PNG, 150 dpi).
    variable : str
        The output to show.
    ax : matplotlib.axes.Axes, optional
        Draw into these axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    values = np.asarray(ds[variable].values, dtype=float).ravel()
    ok = (np.asarray(ds["invalid_reason"].values).ravel() == 0) & np.isfinite(values)
    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 4.0), constrained_layout=True)
    else:
        fig = ax.figure
    units = unit_label(ds[variable].attrs.get("units", ""))
    ax.hist(values[ok], bins=80, color="0.55", density=True, label=f"model ({ok.sum():,} members)")
    obs = float(ds.attrs.get("observed_chandler_period_days", math.nan))
    if variable == "chandler_period" and math.isfinite(obs):
        ax.axvline(obs, color="C3", lw=2, label=f"observed {obs:.1f} {units}")
    ax.set_xlabel(f"{ds[variable].attrs.get('long_name', variable)} [{units}]")
    ax.set_ylabel("probability density")
    ax.set_title(ds.attrs.get("title", ""), fontsize=9)
    ax.legend(frameon=False)
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
    return fig


# Okabe & Ito (2008, "Color Universal Design") colours, told apart under deuteranopia and protanopia: the
# seaborn-like set before made cusps and loops both olive, undulating and regular both blue (Machado, Oliveira &
# Fernandes 2009 simulation; tests/test_sweep_top.py).
_CLASS_COLOURS = {
    "invalid": "white",
    "undulating": "#0072B2",
    "cusps": "#D55E00",
    "loops": "#009E73",
    "regular": "#CC79A7",
    "sleeping": "#E69F00",
}


def phase_diagram(ds, path=None, fig=None, *, overwrite: bool = False):
    """The heavy top's phase diagram: nutation class over tilt and spin, one panel per phidot0.

    Parameters
    ----------
    ds : xarray.Dataset
        A ``heavy_top`` grid sweep with dimensions ``theta0`` and ``omega3``
        (and optionally ``phidot0``) and the CF flag variable ``nutation_class``.
    path : path-like, optional
        Save the figure there (PNG, 150 dpi).
    fig : matplotlib.figure.Figure, optional
        Draw into this figure.

    Returns
    -------
    matplotlib.figure.Figure
        Classes coloured (undulating, cusps, loops, regular precession,
        sleeping); the dashed line is the sleeping-top stability limit
        I3^2 omega3^2 = 4 M g l I1 (Goldstein, Poole & Safko 2002, sec. 5.7).
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    cls = ds["nutation_class"]
    if not {"theta0", "omega3"} <= set(cls.dims):
        raise ValueError(f"a phase diagram needs grid dimensions theta0 and omega3; got {cls.dims}")
    meanings = str(cls.attrs["flag_meanings"]).split()
    values = np.asarray(cls.attrs["flag_values"]).tolist()
    cmap = ListedColormap([_CLASS_COLOURS.get(m, "0.5") for m in meanings])
    norm = BoundaryNorm(np.arange(min(values) - 0.5, max(values) + 1.0), cmap.N)
    extra = [d for d in cls.dims if d not in ("theta0", "omega3")]
    panels = [cls] if not extra else [cls.isel({extra[0]: i}) for i in range(cls.sizes[extra[0]])]
    if fig is None:
        fig = plt.figure(figsize=(3.0 * len(panels) + 1.6, 3.6), constrained_layout=True)
    axes = fig.subplots(1, len(panels), sharey=True, squeeze=False)[0]
    w = np.asarray(ds["omega3"].values)
    th = _in(ds["theta0"], "deg")  # the grid is in the unit the sweep file gave it in
    stable = ds.get("sleeping_stable")
    for ax, panel in zip(axes, panels):
        ax.pcolormesh(w, th, panel.transpose("theta0", "omega3").values, cmap=cmap, norm=norm, shading="nearest")
        if stable is not None:
            s = stable.isel({extra[0]: 0}) if extra else stable
            limit = w[np.argmax(s.isel(theta0=0).values > 0)] if bool(s.isel(theta0=0).any()) else None
            if limit is not None:
                ax.axvline(limit, color="k", ls="--", lw=1)
        title = ""
        if extra:
            val = float(panel[extra[0]])
            units = unit_label(ds[extra[0]].attrs.get("units", ""))
            title = f"{extra[0]} = {val:g} {units}"
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(f"spin omega3 [{unit_label(ds['omega3'].attrs.get('units', 'rad s-1'))}]")
    axes[0].set_ylabel("initial tilt theta0 [deg]")
    handles = [Patch(color=_CLASS_COLOURS.get(m, "0.5"), label=m.replace("_", " ")) for m in meanings if m != "invalid"]
    handles.append(plt.Line2D([], [], color="k", ls="--", label="sleeping top stable to the right"))
    fig.legend(handles=handles, loc="outside right center", frameon=False, fontsize=8)
    fig.suptitle(ds.attrs.get("title", ""), fontsize=9)
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
    return fig


def _in(coord, unit: str) -> np.ndarray:
    """A coordinate's values in ``unit``, read from its ``units`` attribute."""
    from wobble.api.dataset import quantity

    return quantity(coord).to_value(unit)


#: The most members of each mode the ensemble's scatter draws (more only blacken it, and slow it).
_SCATTER = 4000


def ensemble(ds, path=None, fig=None, *, overwrite: bool = False):
    """A tumbling ensemble: precession periods and wobble-angle ranges, short- against long-axis modes.

    Parameters
    ----------
    ds : xarray.Dataset
        A ``free_rotation`` sweep (``regime``, ``precession_period``,
        ``wobble_angle_min``, ``wobble_angle_max``).
    path : path-like, optional
        Save the figure there (PNG, 150 dpi).
    fig : matplotlib.figure.Figure, optional
        Draw into this figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    if fig is None:
        fig = plt.figure(figsize=(9.6, 3.8), constrained_layout=True)
    ax1, ax2 = fig.subplots(1, 2)
    regime = np.asarray(ds["regime"].values).ravel()
    meanings = str(ds["regime"].attrs["flag_meanings"]).split()
    codes = np.asarray(ds["regime"].attrs["flag_values"]).tolist()
    period = np.asarray(ds["precession_period"].values).ravel() / 86400.0
    lo = np.degrees(np.asarray(ds["wobble_angle_min"].values).ravel())
    hi = np.degrees(np.asarray(ds["wobble_angle_max"].values).ravel())
    ok = np.isfinite(period) & (period > 0)
    shown = 0  # the most members of one mode in the scatter (it draws at most _SCATTER of each)
    if ok.any():
        bins = np.geomspace(np.percentile(period[ok], 0.1), np.percentile(period[ok], 99.9), 80)
        for name, colour in (("major-axis", "C0"), ("minor-axis", "C1")):
            sel = ok & (regime == codes[meanings.index(name)])
            label = f"{name.replace('_', ' ')} ({sel.sum():,})"
            ax1.hist(period[sel], bins=bins, histtype="step", color=colour, lw=1.5, label=label)
            ax2.scatter(lo[sel][:_SCATTER], hi[sel][:_SCATTER], s=2, alpha=0.4, color=colour, label=label)
            shown = max(shown, min(int(sel.sum()), _SCATTER))
        ax1.set_xscale("log")
    else:  # every member invalid or steady (a file's ranges may allow no body): say so, not a warning
        for ax in (ax1, ax2):
            ax.text(
                0.5,
                0.5,
                "no member with a finite precession period",
                ha="center",
                va="center",
                fontsize=9,
                transform=ax.transAxes,
            )
    ax1.set_xlabel("precession period about L [d]")
    ax1.set_ylabel("members")
    handles = ax1.get_legend_handles_labels()[0]  # none without valid members: the title alone says why
    ax1.legend(handles=handles, frameon=False, fontsize=8, title=_invalid_text(ds["invalid_reason"]), title_fontsize=8)
    ax2.plot([0, 90], [0, 90], color="0.6", lw=0.8)
    ax2.set_xlabel("wobble angle min [deg]")
    ax2.set_ylabel("wobble angle max [deg]")
    # It said "4000 members each" whatever the ensemble held (a 2,000-member run drew fewer).
    each = f"up to {_SCATTER:,} members of each mode" if shown == _SCATTER else "every member"
    ax2.set_title(f"angle between circulation axis and L ({each})", fontsize=8)
    if ax2.get_legend_handles_labels()[0]:  # which colour is which mode
        ax2.legend(frameon=False, fontsize=8, loc="lower right", markerscale=4)  # below max = min: empty
    fig.suptitle(ds.attrs.get("title", ""), fontsize=9)
    if path is not None:
        from wobble.plot.save import save_figure

        save_figure(fig, path, overwrite=overwrite)
    return fig


def _invalid_text(reason) -> str:
    """``22 invalid (triangle inequality violated), 235 (bad moments or spin)``: each reason's count, from the
    variable's flags (the legend said "triangle inequality" for every invalid member)."""
    values = np.asarray(reason.values).ravel()
    meanings = str(reason.attrs["flag_meanings"]).split()
    codes = np.asarray(reason.attrs["flag_values"]).tolist()
    parts = [
        f"{int(np.sum(values == code)):,} ({meaning.replace('_', ' ')})"
        for code, meaning in zip(codes, meanings)
        if code != 0 and np.any(values == code)
    ]
    return ("invalid: " + ", ".join(parts)) if parts else "0 invalid"
