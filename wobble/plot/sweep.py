"""Figures for sweeps: the distribution of a swept output against the observed value."""

from __future__ import annotations

import math

import numpy as np


def histogram(ds, path=None, variable: str = "chandler_period", ax=None):
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
    units = ds[variable].attrs.get("units", "")
    ax.hist(values[ok], bins=80, color="0.55", density=True, label=f"model ({ok.sum():,} members)")
    obs = float(ds.attrs.get("observed_chandler_period_days", math.nan))
    if variable == "chandler_period" and math.isfinite(obs):
        ax.axvline(obs, color="C3", lw=2, label=f"observed {obs:.1f} {units}")
    ax.set_xlabel(f"{ds[variable].attrs.get('long_name', variable)} [{units}]")
    ax.set_ylabel("probability density")
    ax.set_title(ds.attrs.get("title", ""), fontsize=9)
    ax.legend(frameon=False)
    if path is not None:
        fig.savefig(path, dpi=150)
    return fig
