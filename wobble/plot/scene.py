"""A scene's outputs against time, drawn from the netCDF file ``wobble run`` wrote."""

from __future__ import annotations

import os

import matplotlib.pyplot as plt
import numpy as np

from wobble.errors import InputError

from wobble.plot._style import time_axis

__all__ = ["scene_figure"]

# Panels in the order they are drawn (at most four), with the variables each shows.
_PANELS = (
    ("omega", "angular velocity, body frame"),
    ("angular_momentum", "angular momentum, inertial frame"),
    ("energy", "energy, relative change from the start"),
    ("angles", "angles"),
)
_MAX_POINTS = 4000
_MAX_MEMBERS = 20


def scene_figure(source, *, path=None, overwrite: bool = False):
    """Every output of a scene run against time: omega, L, energy change, tilt/wobble angles.

    Parameters
    ----------
    source : path-like or xarray.Dataset
        The file ``wobble run`` wrote (read lazily, at most 4000 times and 20 members
        drawn), or a Dataset from :func:`wobble.run`.
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
        fig = _draw(_thin(ds))
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
    return out.load()


def _series(var) -> np.ndarray:
    """(time, members, components) whatever the variable's dims."""
    order = [d for d in ("time", "member") if d in var.dims] + [d for d in var.dims if d not in ("time", "member")]
    values = np.asarray(var.transpose(*order).values, dtype=float)
    if "member" not in var.dims:
        values = values[:, None, ...]
    return values.reshape(values.shape[0], values.shape[1], -1)


def _draw(ds):
    t = np.asarray(ds["time"].values, dtype=float)
    t = t - t[0]
    scale, unit = time_axis(t[-1] if t.size else 1.0)
    panels = [p for p in _PANELS if _has(ds, p[0])]
    fig, axes = plt.subplots(
        len(panels) or 1, 1, figsize=(7.5, 2.2 * max(len(panels), 1) + 0.6), sharex=True, squeeze=False
    )
    for ax, (kind, title) in zip(axes[:, 0], panels):
        _PANEL_DRAW[kind](ax, ds, t / scale)
        ax.set_title(title, fontsize=9)
    axes[-1, 0].set_xlabel(f"time ({unit})")
    fig.suptitle(f"{ds.attrs.get('title', 'scene')}: model {ds.attrs.get('model', '?')}", fontsize=10)
    fig.tight_layout()
    return fig


def _has(ds, kind: str) -> bool:
    wanted = {
        "omega": ("omega",),
        "angular_momentum": ("angular_momentum",),
        "energy": ("kinetic_energy", "total_energy"),
        "angles": ("tilt", "wobble_angle"),
    }[kind]
    return any(name in ds for name in wanted)


def _components(ax, ds, t, name: str, labels) -> None:
    values = _series(ds[name])
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
            )
    ax.set_ylabel(ds[name].attrs.get("units", ""))
    ax.legend(loc="upper right", fontsize=8)


def _omega(ax, ds, t) -> None:
    _components(ax, ds, t, "omega", [f"$\\omega_{a}$" for a in ("1", "2", "3")])


def _momentum(ax, ds, t) -> None:
    _components(ax, ds, t, "angular_momentum", ["$L_X$", "$L_Y$", "$L_Z$"])


def _energy(ax, ds, t) -> None:
    # Relative change: members of an ensemble differ in energy by orders of magnitude.
    for k, name in enumerate(("kinetic_energy", "total_energy")):
        if name in ds:
            values = _series(ds[name])[:, :, 0]
            scale = np.where(values[:1] != 0, np.abs(values[:1]), 1.0)
            ax.plot(
                t,
                (values - values[:1]) / scale,
                color=f"C{k}",
                lw=0.8,
                label=[name.replace("_", " ")] + [None] * (values.shape[1] - 1),
            )
    ax.set_ylabel("relative change")
    ax.legend(loc="upper right", fontsize=8)


def _angles(ax, ds, t) -> None:
    for k, name in enumerate(("tilt", "wobble_angle")):
        if name in ds:
            ax.plot(t, np.degrees(_series(ds[name])[:, :, 0]), color=f"C{k}", lw=1.0, label=name.replace("_", " "))
    ax.set_ylabel("deg")
    ax.legend(loc="upper right", fontsize=8)


_PANEL_DRAW = {"omega": _omega, "angular_momentum": _momentum, "energy": _energy, "angles": _angles}
