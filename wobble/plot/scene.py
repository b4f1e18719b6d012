"""A scene's outputs against time, drawn from the netCDF file ``wobble run`` wrote."""

from __future__ import annotations

import math
import os

import matplotlib.pyplot as plt
import numpy as np

from wobble.errors import InputError

from wobble.plot._sampling import (
    first_periods,
    free_period,
    largest_gap,
    note,
    panel_rates,
    period_count,
    resolved,
    series,
)
from wobble.plot._style import (
    ANGLE_UNITS,
    ROUNDING_CHANGE,
    SMALL_CHANGE,
    angle_unit,
    constancy,
    finite_range,
    largest,
    power_axis,
    start_text,
    time_axis,
    unit_label,
)

__all__ = ["scene_figure"]

# Panels in the order they are drawn, with the variables each shows.
_PANELS = (
    ("omega", "angular velocity, body frame"),
    ("angular_momentum", "angular momentum, inertial frame"),
    ("energy", "energy, relative change from the start"),
    ("axis", "figure axis (body axis 3): precession about the inertial z axis"),
    ("tilt", "tilt: body axis 3 from the inertial z axis"),
    ("wobble_angle", "wobble angle: omega from body axis 3"),
)
_WANTED = {
    "omega": ("omega",),
    "angular_momentum": ("angular_momentum",),
    "energy": ("kinetic_energy", "total_energy"),
    "axis": ("axis_direction",),
    "tilt": ("tilt", "axis_direction"),
    "wobble_angle": ("wobble_angle",),
}
# matplotlib's path simplification merges segments finer than a pixel and keeps their extremes, so
# tens of thousands of points draw as fast as thousands and look like all of them; beyond this the
# figure draws every n-th sample (and checks the sampling at that spacing).
_MAX_POINTS = 50_000
#: A free body's omega over more periods than this is drawn for its first ones (each repeats the first).
MAX_PERIODS_SHOWN = 10
_MAX_MEMBERS = 20
# The components of the vector panels.
_VECTORS = {
    "omega": [f"$\\omega_{a}$" for a in ("1", "2", "3")],
    "angular_momentum": ["$L_X$", "$L_Y$", "$L_Z$"],
}
# An ensemble's members by colour, its energies by line style, or by marker when the samples are
# too sparse for lines.
_LINESTYLES = ("-", "--", ":")
_MARKERS = (".", "x", "+")
# Angle units, largest first (rad each).
_ANGLE_UNITS = ANGLE_UNITS[:3]  # deg, arcsec, mas: a scene's angles do not need micro-arcseconds
# The axis's azimuth (precession angle) means little within this of the inertial z axis: there the
# figure draws the axis's offset from z instead.
_NEAR_POLE = math.radians(1.0)
# An energy whose relative change stays within this is conserved to rounding: 64 ulp (a sum of a few terms,
# each rounded, over many samples) and far below any integrator's error that wobble reports.
_ENERGY_ROUNDING = 64 * np.finfo(float).eps


def scene_figure(source, *, path=None, overwrite: bool = False):
    """Every output of a scene run against time: omega, L, energy change, figure axis, tilt, wobble angle.

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

    Angles are drawn in deg, arcsec or mas, whichever their range (or, for a constant, their size)
    reads in, as plain numbers; an ensemble's vectors one component a panel, its members by colour,
    and every legend beside its panel. A free body's omega over more than :data:`MAX_PERIODS_SHOWN`
    periods is drawn for its first ones, when every panel follows omega (thousands of periods in a
    panel are a solid band), and the title says how many the span holds.

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
        shown, count = _first_periods(ds)
        cut = (
            ""
            if count is None
            else (f"first {MAX_PERIODS_SHOWN} of {period_count(count)} periods of omega shown (each repeats the first)")
        )
        fig = _draw(*_thin(shown), cut=cut)
    finally:
        if own:
            ds.close()
    if path is None:
        return fig
    from wobble.plot.save import save_figure

    return save_figure(fig, path, overwrite=overwrite)


def _first_periods(ds):
    """(the Dataset to draw, the span's number of periods or None): a free body's omega repeats every period,
    so a span of more than :data:`MAX_PERIODS_SHOWN` periods, whose panels all follow omega (no figure
    axis or tilt, which precess), is drawn for its first periods, as ``wobble free --plot`` draws it (120
    periods of the Earth's free wobble drew solid bands)."""
    if any(name in ds for name in (*_WANTED["axis"], *_WANTED["tilt"])):
        return ds, None
    period = free_period(ds)
    t = np.asarray(ds["time"].values, dtype=float)
    if period is None or t.size < 2:
        return ds, None
    # The free figure's rule (first_periods): where it cuts, and how many periods the span holds.
    times, count = first_periods(t[-1] - t[0], period, MAX_PERIODS_SHOWN, 1)
    if count is None:
        return ds, None
    return ds.isel(time=np.flatnonzero(t <= t[0] + times[-1])), count


def _thin(ds):
    step = max(1, int(np.ceil(ds.sizes["time"] / _MAX_POINTS)))
    out = ds.isel(time=slice(None, None, step))
    if "member" in out.dims:
        out = out.isel(member=slice(0, _MAX_MEMBERS))
    return out.load(), step


def _draw(ds, every: int = 1, cut: str = ""):
    t = np.asarray(ds["time"].values, dtype=float)
    if t.size == 0:  # t[0] below was an IndexError
        raise InputError("source", "a Dataset with no times", "a run's Dataset or file with at least one time")
    t = t - t[0]
    scale, unit = time_axis(t[-1] if t.size else 1.0)
    panels = _layout(ds)
    rates = panel_rates(ds)
    gap = largest_gap(t)
    fig, axes = plt.subplots(
        len(panels) or 1, 1, figsize=(9.0, 2.2 * max(len(panels), 1) + 0.6), sharex=True, squeeze=False
    )
    for ax, (kind, title, part) in zip(axes[:, 0], panels):
        lines = resolved(rates[kind], gap)
        title = _PANEL_DRAW[kind](ax, ds, t / scale, lines, unit, part) or title
        ax.set_title(title, fontsize=9)
        if not lines:
            _note(ax, note(rates[kind], gap, every))
    axes[-1, 0].set_xlabel(f"time [{unit}]")
    title = f"{ds.attrs.get('title', 'scene')}: model {ds.attrs.get('model', '?')}"
    fig.suptitle(f"{title}\n{cut}" if cut else title, fontsize=10)
    fig.tight_layout()
    return fig


def _layout(ds) -> list:
    """(kind, title, component or None) of each panel; an ensemble's vectors one component a panel."""
    panels = []
    for kind, title in _PANELS:
        if not _has(ds, kind):
            continue
        if kind in _VECTORS and "member" in ds[kind].dims and ds.sizes["member"] > 1:
            # Members by colour in one panel a component: 4 members x 3 components in one panel
            # were 12 curves in 3 colours.
            labels = _VECTORS[kind]
            panels += [(kind, f"{title}: {labels[k]}", k) for k in range(len(labels))]
        else:
            panels.append((kind, title, None))
    return panels


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
    return any(name in ds for name in _WANTED[kind])


def _look(lines: bool, k: int) -> dict:
    """Line style k, or marker k when the samples are too sparse for lines."""
    if lines:
        return {"ls": _LINESTYLES[k % len(_LINESTYLES)]}
    return {"ls": "none", "marker": _MARKERS[k % len(_MARKERS)], "ms": 3}


def _legend(ax, handles=None) -> None:
    # Outside the axes, on the right: a legend inside covered the curves of the tops' panels.
    kw = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0, "fontsize": 8}
    if handles is None:
        ax.legend(**kw)
    else:
        ax.legend(handles=handles, **kw)


def _member_handles(ds, n: int, kinds, lines: bool) -> list:
    """Legend entries of an ensemble: each member's colour, then each kind's line style (or marker)."""
    from matplotlib.lines import Line2D

    labels = ds["member"].values if "member" in ds.coords else range(n)
    handles = [Line2D([], [], color=f"C{j % 10}", label=f"member {labels[j]}") for j in range(n)]
    return handles + [Line2D([], [], color="0.3", label=name, **_look(lines, k)) for k, name in kinds]


def _components(ax, ds, t, name: str, labels, lines: bool) -> str | None:
    """One body's vector, a colour per component (a component 20 times the others and constant named).

    A vector whose drawn components change by less than :data:`~wobble.plot._style.SMALL_CHANGE` of their
    size is drawn as its change from the start, its start in the title (the Sun's and Moon's slow work on the
    Earth's angular momentum drew three flat lines); one constant to
    :data:`~wobble.plot._style.ROUNDING_CHANGE` (a free body's L) as it is, not its rounding. Values are in a
    named power of ten of the unit; sizes and ranges are
    taken over the finite samples. Returns the panel's title addition, if any.
    """
    values = series(ds[name])[:, 0, :]
    unit = unit_label(ds[name].attrs.get("units", ""))
    size = np.array([largest(values[:, k]) for k in range(values.shape[1])])
    spread = np.array([finite_range(values[:, k]) for k in range(values.shape[1])])
    # A spin 1e3 times the wobble would flatten the wobble: name it instead of drawing it.
    named = [
        k
        for k in range(values.shape[1])
        if size.size > 1 and size[k] > 20 * np.max(np.delete(size, k)) and spread[k] < 1e-3 * size[k]
    ]
    kept = [k for k in range(values.shape[1]) if k not in named]
    # Rounding is relative to the whole vector; whether a change shows, to the components drawn.
    moved = float(np.max(spread[kept], initial=0.0))
    drawn, suffix = values, None
    changing = float(np.max(spread)) > ROUNDING_CHANGE * float(np.linalg.norm(size))
    if changing and moved < SMALL_CHANGE * float(np.linalg.norm(size[kept])) and np.all(np.isfinite(values[0])):
        # Every component's change, a large constant one's too: the change is the scale now.
        drawn, named, kept = values - values[0], [], list(range(values.shape[1]))
        suffix = f"change from the start, {start_text(values[0], unit)}"
    scale = power_axis(ax, largest(drawn[:, kept]) if kept else 0.0, unit)
    for k in range(values.shape[1]):
        if k in named:
            ax.plot(
                [],
                [],
                " ",
                label=f"{labels[k]} = {np.mean(values[:, k]):.6g} {unit} ({constancy(spread[k], size[k])})",
            )
        else:
            ax.plot(t, drawn[:, k] / scale, color=f"C{k}", lw=1.0, label=labels[k], **_look(lines, 0))
    _legend(ax)
    return suffix


def _component(ax, ds, t, name: str, k: int, lines: bool) -> None:
    """Component k of an ensemble's vector, a colour per member."""
    values = series(ds[name])[:, :, k]
    scale = power_axis(ax, largest(values), unit_label(ds[name].attrs.get("units", "")))
    for j in range(values.shape[1]):
        label = f"member {_member_label(ds, j)}"
        ax.plot(t, values[:, j] / scale, color=f"C{j % 10}", lw=1.0, label=label, **_look(lines, 0))
    _legend(ax)


def _vector(kind: str):
    """The drawer of a vector panel: one body's components together, or an ensemble's one at a time."""

    def draw(ax, ds, t, lines, unit, part=None) -> str | None:
        if part is not None:
            _component(ax, ds, t, kind, part, lines)
            return None
        suffix = _components(ax, ds, t, kind, _VECTORS[kind], lines)
        return None if suffix is None else f"{dict(_PANELS)[kind]}: {suffix}"

    return draw


def _energy(ax, ds, t, lines, unit, part=None) -> None:
    # Relative change: members of an ensemble differ in energy by orders of magnitude.
    kinds, changes = [], []
    for k, name in enumerate(("kinetic_energy", "total_energy")):
        if name in ds:
            values = series(ds[name])[:, :, 0]
            scale = np.where(values[:1] != 0, np.abs(values[:1]), 1.0)
            changes.append((values - values[:1]) / scale)
            kinds.append((k, name.replace("_", " ")))
    members = changes[0].shape[1] if changes else 1
    biggest = max((largest(c) for c in changes), default=0.0)
    if biggest <= _ENERGY_ROUNDING:
        # Conserved to rounding (a free body, a top): its last bits drawn as a curve looked like data.
        kinds = [(k, f"{label}: constant to rounding (|change| <= {biggest:.1g})") for k, label in kinds]
        changes = [np.zeros_like(c) for c in changes]
        biggest = 0.0
    # "relative change [10^-9]", not matplotlib's "1e-8" above the axis
    scale = power_axis(ax, biggest, name="relative change")
    for (k, label), change in zip(kinds, changes):
        for j in range(members):
            look = {"color": f"C{k}", **_look(lines, 0)} if members == 1 else {"color": f"C{j % 10}", **_look(lines, k)}
            ax.plot(t, change[:, j] / scale, lw=0.8, label=label if j == 0 else None, **look)
    _legend(ax, None if members == 1 else _member_handles(ds, members, kinds, lines))


def _angle_unit(radians) -> tuple[float, str]:
    """(rad per unit, name): deg, arcsec or mas, the largest in which the angles' range is at least 1.

    A constant (a range within rounding of its size) goes by its size instead; a unit that would need
    more than six digits before the point gives way to the next larger one.
    """
    values = np.asarray(radians, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return _ANGLE_UNITS[0][1], _ANGLE_UNITS[0][0]
    top = float(np.max(np.abs(values)))
    spread = float(np.ptp(values))
    name = angle_unit(spread if spread > 1e-9 * top else top)[1]  # the figures' one rule, on the range
    names = [n for n, _ in _ANGLE_UNITS]
    i = names.index(name) if name in names else len(names) - 1  # micro-arcseconds: mas, a scene's smallest
    while i > 0 and top / _ANGLE_UNITS[i][1] >= 1e6:
        i -= 1
    name, rad = _ANGLE_UNITS[i]
    return rad, name


def _angle_curves(ax, ds, t, curves, lines: bool, labels) -> tuple[float, str]:
    """Draw angle series (time, members), all in one unit; returns (rad per unit, its name).

    ``labels``: one per curve. One member: a colour per curve, each labelled. Several: a colour per
    member and a line style per curve; one curve labels its members, several label their first member's
    line with the curve's name.
    """
    rad, name = _angle_unit(np.concatenate([c.ravel() for c in curves]))
    members = curves[0].shape[1]
    for i, (values, label) in enumerate(zip(curves, labels)):
        for j in range(members):
            if members == 1:
                color, look, text = f"C{i}", _look(lines, 0), label
            else:
                color, look = f"C{j % 10}", _look(lines, i)
                text = f"member {_member_label(ds, j)}" if len(curves) == 1 else (label if j == 0 else None)
            ax.plot(t, values[:, j] / rad, color=color, lw=1.0, label=text, **look)
    ax.set_ylabel(name)
    # Plain numbers in the unit chosen: no offset ("+8.438e4") or multiplier ("1e-5") to decode.
    ax.ticklabel_format(axis="y", style="plain", useOffset=False)
    shown = np.concatenate([c.ravel() for c in curves]) / rad
    shown = shown[np.isfinite(shown)]
    if shown.size and np.ptp(shown) <= 1e-9 * np.max(np.abs(shown)):
        # Constant to rounding (a steady precession's tilt): a plain axis would spell out the rounding.
        middle = float(np.mean(shown))
        ax.set_ylim(middle - max(0.05 * abs(middle), 1.0), middle + max(0.05 * abs(middle), 1.0))
    return rad, name


def _member_label(ds, j: int):
    return ds["member"].values[j] if "member" in ds.coords else j


def _tilt(ax, ds, t, lines, unit, part=None) -> None:
    if "tilt" in ds:
        _angle_curves(ax, ds, t, [series(ds["tilt"])[:, :, 0]], lines, ["tilt"])
    else:
        e3 = series(ds["axis_direction"])
        # atan2, as the engine forms it: arccos of e3_z reads 0 for any tilt under 1e-8 rad (cos rounds to 1).
        tilt = np.arctan2(np.hypot(e3[..., 0], e3[..., 1]), e3[..., 2])
        _angle_curves(ax, ds, t, [tilt], lines, ["tilt (from the axis direction)"])
    _legend(ax)


def _wobble(ax, ds, t, lines, unit, part=None) -> None:
    _angle_curves(ax, ds, t, [series(ds["wobble_angle"])[:, :, 0]], lines, ["wobble angle"])
    _legend(ax)


def _axis(ax, ds, t, lines, unit, part=None) -> str | None:
    """The figure axis's precession angle about inertial z from its start, or near z its offset from z."""
    e3 = series(ds["axis_direction"])
    across = np.hypot(e3[..., 0], e3[..., 1])
    if np.min(across) < math.sin(_NEAR_POLE):
        curves = [np.arcsin(np.clip(e3[..., i], -1.0, 1.0)) for i in (0, 1)]
        _angle_curves(ax, ds, t, curves, lines, ["toward inertial x", "toward inertial y"])
        _legend(ax)
        return "figure axis (body axis 3): offset from the inertial z axis"
    azimuth = np.unwrap(np.arctan2(e3[..., 1], e3[..., 0]), axis=0)
    precession = azimuth - azimuth[:1]
    rad, name = _angle_curves(ax, ds, t, [precession], lines, ["precession angle from the start"])
    if precession.shape[1] == 1 and t.size > 1 and lines:  # an unresolved panel's fit would be the alias's
        label = _precession_rate_label(ds, t, precession[:, 0] / rad, f"{name}/{unit}")
        ax.plot([], [], " ", label=label)
    _legend(ax)
    return None


def _precession_rate_label(ds, t, angle, rate_unit: str) -> str:
    """The mean precession rate for the legend: wobble.measure_precession's (secular rate and the
    perturbers' nutation terms fitted together) where the scene has the perturbers it needs, else a
    straight line's slope, said to be one. A straight line over 20 years of Earth's precession took
    up part of the 18.6-year nutation: -50.90"/yr against the measured -50.40"/yr."""
    from astropy import units as u

    from wobble.api.precession_measure import measure_precession

    try:
        rate = measure_precession(ds, axis="axis_direction").rate.to_value(u.Unit(rate_unit))
    except (InputError, ValueError, KeyError):  # no perturber with a node, or a span too short to fit one
        slope = np.polyfit(t, angle, 1)[0]
        return f"straight-line rate {slope:.5g} {unit_label(rate_unit)}"
    return f"mean rate {rate:.5g} {unit_label(rate_unit)} (nutation fitted)"


_PANEL_DRAW = {
    "omega": _vector("omega"),
    "angular_momentum": _vector("angular_momentum"),
    "energy": _energy,
    "axis": _axis,
    "tilt": _tilt,
    "wobble_angle": _wobble,
}
