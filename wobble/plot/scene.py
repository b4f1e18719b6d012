"""A scene's outputs against time, drawn from the netCDF file ``wobble run`` wrote."""

from __future__ import annotations

import os

import matplotlib.pyplot as plt
import numpy as np

from wobble.errors import InputError

from wobble.plot._sampling import largest_gap, note, panel_rates, resolved, series
from wobble.plot._style import time_axis

__all__ = ["scene_figure"]

# Panels in the order they are drawn (at most four), with the variables each shows.
_PANELS = (
    ("omega", "angular velocity, body frame"),
    ("angular_momentum", "angular momentum, inertial frame"),
    ("energy", "energy, relative change from the start"),
    ("angles", "angles"),
)
# matplotlib's path simplification merges segments finer than a pixel and keeps their extremes, so
# tens of thousands of points draw as fast as thousands and look like all of them; beyond this the
# figure draws every n-th sample (and checks the sampling at that spacing).
_MAX_POINTS = 50_000
_MAX_MEMBERS = 20


def scene_figure(source, *, path=None, overwrite: bool = False):
    """Every output of a scene run against time: omega, L, energy change, tilt/wobble angles.

    A panel whose samples are too far apart for the fastest motion its quantities can carry is drawn
    with markers alone and says so ("samples 118 s apart: motion with periods down to ~3.14 s not
    resolved"), never as lines through an alias. The criterion: lines only where ``Omega dt <= pi/2``
    (four samples per period or more; at two, Nyquist's limit, the samples are those of a slower
    motion, and below four a line cuts the peaks by up to 29 %), ``dt`` the largest gap drawn and
    ``Omega`` bounded from physics at the samples, not from their differences (an alias is as smooth
    as a resolved motion): for a free body's omega the rate at which it turns in the body on its
    polhode, from Euler's equations with the body the file records (the Euler frequency
    (C - A)/A omega_3 of a symmetric body); ``|omega x e3|`` over the axis's excursion for the figure
    axis; twice the body's rotation rate ``|omega|`` for what a torque from a field fixed in space
    drives (the field turns at ``|omega|`` as the body sees it, and tides and gravity gradients are
    quadratic in it). Details and limits: :mod:`wobble.plot._sampling`.

    Parameters
    ----------
    source : path-like or xarray.Dataset
        The file ``wobble run`` wrote (read lazily, at most 50,000 times and 20 members drawn), or a
        Dataset from :func:`wobble.run`.
    path : path-like, optional
        Save the figure there (atomically); the function then returns the path.
    overwrite : bool
        Replace an existing ``path``.
    """
    import xarray as xr

    own = isinstance(source, (str, os.PathLike))
    if not own and not (isinstance(source, xr.Dataset) and "time" in source.dims):
        raise InputError("source", source, "the path of a file wobble run wrote, or a Dataset from wobble.run")
    ds = xr.open_dataset(source, engine="netcdf4", decode_times=False) if own else source
    try:
        fig = _draw(*_thin(ds))
    finally:
        if own:
            ds.close()
    if path is None:
        return fig
    from wobble.plot.save import save_figure

    return save_figure(fig, path, overwrite=overwrite)


def _thin(ds):
    step = max(1, int(np.ceil(ds.sizes["time"] / _MAX_POINTS)))
    out = ds.isel(time=slice(None, None, step))
    if "member" in out.dims:
        out = out.isel(member=slice(0, _MAX_MEMBERS))
    return out.load(), step


def _draw(ds, every: int = 1):
    t = np.asarray(ds["time"].values, dtype=float)
    t = t - t[0]
    scale, unit = time_axis(t[-1] if t.size else 1.0)
    panels = [p for p in _PANELS if _has(ds, p[0])]
    rates = panel_rates(ds)
    known = [rates[k] for k in ("tilt", "wobble_angle") if k in ds and rates[k] is not None]
    rates["angles"] = max(known) if known else None
    gap = largest_gap(t)
    fig, axes = plt.subplots(
        len(panels) or 1, 1, figsize=(7.5, 2.2 * max(len(panels), 1) + 0.6), sharex=True, squeeze=False
    )
    for ax, (kind, title) in zip(axes[:, 0], panels):
        lines = resolved(rates[kind], gap)
        _PANEL_DRAW[kind](ax, ds, t / scale, lines)
        ax.set_title(title, fontsize=9)
        if not lines:
            _note(ax, note(rates[kind], gap, every))
    axes[-1, 0].set_xlabel(f"time ({unit})")
    fig.suptitle(f"{ds.attrs.get('title', 'scene')}: model {ds.attrs.get('model', '?')}", fontsize=10)
    fig.tight_layout()
    return fig


def _note(ax, text: str) -> None:
    # Above the data: the y range grows by a fifth to make room, so the note covers no marker.
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.2 * (hi - lo))
    ax.text(
        0.01,
        0.97,
        text,
        transform=ax.transAxes,
        fontsize=8,
        color="C3",
        va="top",
        bbox={"facecolor": "white", "edgecolor": "C3", "alpha": 0.9, "boxstyle": "round,pad=0.3"},
    )


def _has(ds, kind: str) -> bool:
    wanted = {
        "omega": ("omega",),
        "angular_momentum": ("angular_momentum",),
        "energy": ("kinetic_energy", "total_energy"),
        "angles": ("tilt", "wobble_angle"),
    }[kind]
    return any(name in ds for name in wanted)


def _look(lines: bool) -> dict:
    """Lines, or markers alone when the samples are too sparse for lines."""
    return {"ls": "-"} if lines else {"ls": "none", "marker": ".", "ms": 3}


def _components(ax, ds, t, name: str, labels, lines: bool) -> None:
    values = series(ds[name])
    size = np.max(np.abs(values), axis=(0, 1))
    for k in range(values.shape[2]):
        others = np.max(np.delete(size, k)) if size.size > 1 else 0.0
        if size[k] > 20 * others and np.ptp(values[:, :, k]) < 1e-3 * size[k]:
            # A spin 1e3 times the wobble would flatten the wobble: name it instead of drawing it.
            ax.plot([], [], " ", label=f"{labels[k]} = {np.mean(values[:, :, k]):.6g} (constant to 1e-3)")
            continue
        for j in range(values.shape[1]):
            ax.plot(
                t,
                values[:, j, k],
                color=f"C{k}",
                lw=0.9 if values.shape[1] > 1 else 1.3,
                alpha=0.6 if values.shape[1] > 1 else 1.0,
                label=labels[k] if j == 0 else None,
                **_look(lines),
            )
    ax.set_ylabel(ds[name].attrs.get("units", ""))
    ax.legend(loc="upper right", fontsize=8)


def _omega(ax, ds, t, lines) -> None:
    _components(ax, ds, t, "omega", [f"$\\omega_{a}$" for a in ("1", "2", "3")], lines)


def _momentum(ax, ds, t, lines) -> None:
    _components(ax, ds, t, "angular_momentum", ["$L_X$", "$L_Y$", "$L_Z$"], lines)


def _energy(ax, ds, t, lines) -> None:
    # Relative change: members of an ensemble differ in energy by orders of magnitude.
    for k, name in enumerate(("kinetic_energy", "total_energy")):
        if name in ds:
            values = series(ds[name])[:, :, 0]
            scale = np.where(values[:1] != 0, np.abs(values[:1]), 1.0)
            ax.plot(
                t,
                (values - values[:1]) / scale,
                color=f"C{k}",
                lw=0.8,
                label=[name.replace("_", " ")] + [None] * (values.shape[1] - 1),
                **_look(lines),
            )
    ax.set_ylabel("relative change")
    ax.legend(loc="upper right", fontsize=8)


def _angles(ax, ds, t, lines) -> None:
    for k, name in enumerate(("tilt", "wobble_angle")):
        if name in ds:
            ax.plot(
                t,
                np.degrees(series(ds[name])[:, :, 0]),
                color=f"C{k}",
                lw=1.0,
                label=name.replace("_", " "),
                **_look(lines),
            )
    ax.set_ylabel("deg")
    ax.legend(loc="upper right", fontsize=8)


_PANEL_DRAW = {"omega": _omega, "angular_momentum": _momentum, "energy": _energy, "angles": _angles}
