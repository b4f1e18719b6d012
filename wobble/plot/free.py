"""Figures of torque-free rotation: the polhode on the energy ellipsoid, a tennis-racket flip."""

from __future__ import annotations


import matplotlib.pyplot as plt
import numpy as np
from astropy import units as u

from wobble.numerics.scaled_norm import norm
from wobble.api.sampling import check_samples, check_step
from wobble.api.free import BYTES_PER_SAMPLE, FreeRotation
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.plot._sampling import first_periods, period_count
from wobble.plot._style import (
    ROUNDING_CHANGE,
    SMALL_CHANGE,
    angle_unit,
    constancy,
    finite_range,
    largest,
    legend_beside,
    power_axis,
    power_of_ten,
    start_text,
    time_axis,
    unit_label,
)

__all__ = ["polhode_figure", "flip_figure", "motion_figure"]

#: The unit of angular velocity as every figure spells it.
_RAD_S = unit_label("rad s-1")


def polhode_figure(moments, omegas, *, samples: int = 2000):
    """Polhodes (paths of L in the body frame) on the energy ellipsoid.

    Parameters
    ----------
    moments : astropy.units.Quantity
        Three principal moments (same for all curves).
    omegas : list of astropy.units.Quantity
        Initial angular velocities; each is rescaled to the energy of the first
        so all polhodes lie on one ellipsoid ``sum L_j^2 / I_j = 2 T``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    I = to_si(moments, "moments", u.kg * u.m**2, positive=True, shape=(3,))
    if isinstance(omegas, u.Quantity) and omegas.ndim == 1:
        omegas = [omegas]  # one initial angular velocity
    omegas = [to_si(w, "omegas", u.rad / u.s, shape=(3,)) * (u.rad / u.s) for w in omegas]
    if not omegas:
        raise InputError("omegas", omegas, "one or more initial angular velocities (3-vectors in rad/s)")
    samples = check_samples(samples, BYTES_PER_SAMPLE)
    fig = plt.figure(figsize=(6.4, 6.0))
    ax = fig.add_subplot(projection="3d")
    w_first = omegas[0].to_value(u.rad / u.s)
    two_t = float(np.sum(I * w_first**2))
    uu, vv = np.meshgrid(np.linspace(0, 2 * np.pi, 60), np.linspace(0, np.pi, 30))
    radii = np.sqrt(two_t * I)
    ax.plot_surface(
        radii[0] * np.cos(uu) * np.sin(vv),
        radii[1] * np.sin(uu) * np.sin(vv),
        radii[2] * np.cos(vv),
        color="0.85",
        alpha=0.25,
        linewidth=0,
    )
    for w in omegas:
        w = w.to_value(u.rad / u.s)
        w = w * np.sqrt(two_t / np.sum(I * w**2))
        body = FreeRotation(moments, w * u.rad / u.s)
        period = body.period.to_value(u.s)
        span = period if np.isfinite(period) else 60.0 / max(body.model.precession_rate, 1e-300)
        t = np.linspace(0, span, samples)
        L = body.model.omega(t) * I
        color = "C3" if body.regime == "separatrix" else ("C0" if body.regime == "major-axis" else "C2")
        ax.plot(L[:, 0], L[:, 1], L[:, 2], color=color, lw=1.2)
    ax.set_xlabel(f"$L_1$ [{unit_label('kg m2 s-1')}]")
    ax.set_ylabel("$L_2$")
    ax.set_zlabel("$L_3$")
    ax.set_box_aspect(radii)
    ax.set_title("Polhodes on the energy ellipsoid (blue: about $I_3$, green: about $I_1$)")
    return fig


def flip_figure(moments, omega0, t_end):
    """Components of omega through tennis-racket (Dzhanibekov) flips, flip times marked.

    Raises
    ------
    wobble.errors.InputError
        A body that does not flip (its intermediate axis swings by less than 90 deg): draw it
        with :func:`motion_figure`.
    """
    to_si(t_end, "t_end", u.s, positive=True, shape=())  # checked before the body is built
    body = FreeRotation(moments, omega0)
    if not body.flips:
        swing = body.intermediate_axis_swing
        raise InputError(
            "omega0",
            omega0,
            f"a spin that flips the body (its intermediate axis swings by "
            f"{0.0 if swing is None else swing.to_value(u.deg):.3g} deg, not more than 90): see motion_figure",
        )
    t_end_s = to_si(t_end, "t_end", u.s, positive=True, shape=())
    check_step(t_end_s, 4001, t_end, " of the figure")
    # As motion_figure's time panels: ten periods at most, densely (4,001 samples over any span aliased a
    # long one, and every flip of it was listed to be marked).
    t, shown, note = _time_panel_times(body, t_end_s, 4001)
    w = body.omega(t * u.s).to_value(u.rad / u.s)
    fig, ax = plt.subplots(figsize=(7.0, 3.8))
    for k, label in enumerate(("$\\omega_1$", "$\\omega_2$", "$\\omega_3$")):
        ax.plot(t, w[:, k], label=label)
    marked = _mark_flips([ax], body.flip_times(shown * u.s).to_value(u.s), 1.0)
    ax.set_xlim(0, shown)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"body-frame angular velocity [{_RAD_S}]")
    title = (
        f"Tennis-racket flips: 1 - m = {body.complementary_parameter:.2g}, "
        f"flip every {body.time_between_flips.to_value(u.s):.6f} s{marked}"
    )
    if note:
        title += f"\n{note}; {body.flip_count(t_end_s * u.s):,} flips in the span"
    ax.set_title(title, fontsize=10 if note else None)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the axes: upper right hid the last flips
    fig.tight_layout()
    return fig


#: Samples per period of omega in the time panels. A flip next to the separatrix is the narrowest
#: feature: about 2.6 / lambda wide in a period of 4 K(m) / lambda, K <= 90 for the 1 - m >= 1e-75 the
#: model accepts, so at least 1/140 of a period, 7 samples; a smooth component is drawn to 5e-6 of itself.
SAMPLES_PER_PERIOD = 1000
#: Periods of omega the time panels show at most (about 70 pixels each at 150 dpi). omega(t) repeats
#: exactly, so the first periods show every later one; thousands of them in a panel only alias.
MAX_PERIODS_SHOWN = 10
#: Points on the polhode: one period of a periodic motion (a closed curve), or the span otherwise.
POLHODE_SAMPLES = 4001
#: Geometric steps per side of each instant the motion of a separatrix is refined about (the start,
#: the end and its flip): sech and tanh change on a scale 1/lambda that may be 1e-16 of the span.
SEPARATRIX_SAMPLES = 2000


def motion_figure(
    body: FreeRotation, t_end, *, samples: int = 2000, time_unit=None, path=None, overwrite: bool = False
):
    """omega(t) and the polhode of one body: what ``wobble free --plot`` draws.

    Left: the angular velocity's components against time, the largest one on its own
    axis (a planet's wobble is 1e-6 of its spin and would vanish beside it): its change from
    the start when it moves by less than 5 % of itself, its start named; flat when by no more
    than 1e-12 of |omega|, constant to rounding, its measured spread named (the rule of
    :func:`wobble.plot.scene.scene_figure`). When the spin dominates and its numbers would
    need a multiplier in rad/s, they are drawn as fractions of the initial spin in a power of
    ten, 10^k |omega(0)|, named in the axis label, so no offset or multiplier hides the numbers.
    Right: the polhode, the path of L/|L| in the body frame, on the unit sphere with the
    principal axes (Goldstein, Poole & Safko 2002, sec. 5.6; Landau & Lifshitz section 37).

    What is drawn of a long span: omega(t) repeats exactly every period, so the time panels
    show at most the first :data:`MAX_PERIODS_SHOWN` periods, at :data:`SAMPLES_PER_PERIOD`
    samples each, and the title says how many the span holds (thousands of periods in a
    panel alias into bands). The polhode of a periodic motion is one closed curve, drawn
    once over one period from :data:`POLHODE_SAMPLES` points. A separatrix (no period) is
    sampled more densely about its flip and the ends of the span.

    Parameters
    ----------
    body : FreeRotation
    t_end : astropy.units.Quantity
        End of the span (from 0).
    samples : int
        Points along the time panels at least.
    time_unit : astropy.units.Unit, optional
        The time axis's unit (``wobble free --t-end`` passes the one it was given in); by default the
        unit a person would use for the span (:func:`wobble.io.text.span_unit`).
    path : path-like, optional
        Save the figure there (atomically); the function then returns the path.
    overwrite : bool
        Replace an existing ``path``.

    Returns
    -------
    matplotlib.figure.Figure, or the written path when ``path`` is given
    """
    if not isinstance(body, FreeRotation):
        raise InputError("body", body, "a wobble.FreeRotation")
    t1 = to_si(t_end, "t_end", u.s, positive=True, shape=())
    samples = check_samples(samples, BYTES_PER_SAMPLE)  # 1e12 samples was a MemoryError, not a message
    check_step(t1, samples, t_end, " of the figure")  # times a subnormal step apart: nothing to draw
    axis_unit = None if time_unit is None else _time_unit(time_unit)
    t, shown, note = _time_panel_times(body, t1, samples)
    w = body.omega(t * u.s).to_value(u.rad / u.s)
    I = body.moments.to_value(u.kg * u.m**2)
    fig = plt.figure(figsize=(10.5, 4.6))
    top = fig.add_subplot(2, 2, 1)
    bottom = fig.add_subplot(2, 2, 3, sharex=top)
    scale = _time_panels(top, bottom, t, w, body, axis_unit)
    flips = body.flip_times(shown * u.s).to_value(u.s) if body.flips else np.empty(0)
    marked = _mark_flips([top, bottom], flips, scale) if flips.size else ""
    top.set_title(_motion_title(body, t1, note) + marked, fontsize=9)
    tp = _polhode_times(body, t1)
    L = I * body.omega(tp * u.s).to_value(u.rad / u.s)
    length = norm(L, axis=1, keepdims=True)
    L = np.divide(L, length, out=np.zeros_like(L), where=length > 0)  # a body at rest: L = 0, drawn at the centre
    near = int(np.argmax(np.min(np.abs(L), axis=0)))
    period = body.model.period
    closed = "\none period, a closed curve" if np.isfinite(period) and t1 >= period else ""
    if np.min(np.abs(L[:, near])) > np.cos(np.radians(5.0)):
        _polhode_from_above(fig.add_subplot(1, 2, 2), L, near, closed)
    else:
        _polhode_on_sphere(fig.add_subplot(1, 2, 2, projection="3d"), L, I, closed)
    fig.tight_layout()
    if path is None:
        return fig
    from wobble.plot.save import save_figure

    return save_figure(fig, path, overwrite=overwrite)


def _time_unit(unit) -> tuple[float, str]:
    """(seconds per unit, its name) of ``time_unit``, refused unless a unit of time."""
    try:
        unit = u.Unit(unit)
        seconds = float(unit.to(u.s))
    except (TypeError, ValueError, u.UnitsError):
        raise InputError("time_unit", unit, "a unit of time (astropy.units.s, 'min', 'd', 'yr')") from None
    return seconds, unit.to_string()


def _time_panel_times(body: FreeRotation, t1: float, samples: int) -> tuple[np.ndarray, float, str]:
    """(times in s, the end of what is shown, a note for the title) of the time panels: a periodic
    motion from 0 to at most :data:`MAX_PERIODS_SHOWN` periods with :data:`SAMPLES_PER_PERIOD` samples
    per period; a separatrix refined about its flip; a steady spin, ``samples`` points over the span."""
    period = body.model.period
    if np.isfinite(period) and period > 0:
        times, count = first_periods(t1, period, MAX_PERIODS_SHOWN, SAMPLES_PER_PERIOD, samples)
        note = (
            ""
            if count is None
            else f"first {MAX_PERIODS_SHOWN} of {period_count(count)} periods shown (each repeats the first)"
        )
        return times, float(times[-1]), note
    if body.regime == "separatrix":
        return _separatrix_times(body, t1, samples), t1, ""
    return np.linspace(0.0, t1, samples), t1, ""


def _separatrix_times(body: FreeRotation, t1: float, samples: int) -> np.ndarray:
    """``samples`` times evenly over [0, t1], and :data:`SEPARATRIX_SAMPLES` geometric steps on each
    side of 0, t1 and the flip, down to 1e-16 of the span: the flip's sech and tanh are resolved
    whatever their width beside the span."""
    steps = np.geomspace(1e-16 * t1, t1, SEPARATRIX_SAMPLES)
    anchors = [0.0, t1, *body.flip_times(t1 * u.s).to_value(u.s)]
    t = np.concatenate([np.linspace(0.0, t1, samples)] + [a + side * steps for a in anchors for side in (-1.0, 1.0)])
    return np.unique(t[(t >= 0.0) & (t <= t1)])


def _polhode_times(body: FreeRotation, t1: float) -> np.ndarray:
    """Times (s) of the polhode: one period (a closed curve; less when the span is shorter), else the span."""
    period = body.model.period
    if np.isfinite(period) and period > 0:
        return np.linspace(0.0, min(t1, period), POLHODE_SAMPLES)
    if body.regime == "separatrix":
        return _separatrix_times(body, t1, POLHODE_SAMPLES)
    return np.linspace(0.0, t1, 2)  # a steady spin: L stays put


def _motion_title(body: FreeRotation, t1: float, note: str) -> str:
    from wobble.io.text import duration

    if body.regime == "separatrix":
        head = "separatrix: omega never repeats (one flip, L tends to the intermediate axis)"
    elif not np.isfinite(body.model.period):
        head = f"{body.regime}: omega is constant"
    else:
        head = f"{body.regime}: omega repeats every {duration(body.period.to_value(u.s), 5)}"
    if not note:
        return head
    flips = body.flip_count(t1 * u.s)
    return f"{head}\n{note}" + (f"; {flips:,} flips in the span" if flips else "")


def _time_panels(top, bottom, t, w, body: FreeRotation, axis_unit: tuple[float, str] | None = None) -> float:
    """Draw omega's components on ``top`` (the two small ones) and ``bottom`` (the largest); returns
    the seconds per unit of the time axis.

    The largest component follows the scene figure's rule (:mod:`wobble.plot._style`): when it moves by
    less than :data:`~wobble.plot._style.SMALL_CHANGE` of itself its change from the start is drawn, the
    start named in the legend; when by no more than :data:`~wobble.plot._style.ROUNDING_CHANGE` of |omega|
    it is constant to rounding, drawn flat with its measured spread named (the Earth's omega_3, which
    varies by m/2 = 4e-15 of itself, drew a staircase of 20 float steps). When those numbers are too small
    to read in rad/s (a planet), the components and the change are drawn as fractions of |omega(0)|,
    each axis in a power of ten named in its label, never as an offset.
    """
    scale, unit = time_axis(t[-1], axis_unit)
    big = int(np.argmax(np.max(np.abs(w), axis=0)))
    others = [k for k in range(3) if k != big]
    dominant = w[:, big]
    spin = float(norm(body.omega0.to_value(u.rad / u.s)))
    spread, size = finite_range(dominant), largest(dominant)
    steady_spin = spread < SMALL_CHANGE * size
    # Rounding is judged against the whole vector, as the scene figure judges it.
    flat = steady_spin and spread <= ROUNDING_CHANGE * spin
    change = np.zeros_like(dominant) if flat else dominant - dominant[0]
    name = _dominant_name(big + 1, dominant[0], spread, size, flat, body.regime)
    if steady_spin and any(power_of_ten(largest(v)) for v in (w[:, others], change)):
        # A planet: a wobble 1e-6 of the spin, the spin's change smaller still: fractions of the spin.
        small, change = w[:, others] / spin, change / spin
        label, legend_title = "$|\\omega(0)|$", f"$|\\omega(0)|$ = {spin:.4g} {_RAD_S}"
    elif steady_spin:  # a lab body spun about an axis: its change in rad/s reads as it is
        small, label, legend_title = w[:, others], _RAD_S, None
    else:  # a real wobble of the largest component: drawn as it is
        small, change = w[:, others], dominant
        label, name, legend_title = _RAD_S, f"$\\omega_{big + 1}$", None
    for ax, values, names, colors in (
        (top, small, [f"$\\omega_{k + 1}$" for k in others], ["C0", "C1"]),
        (bottom, change[:, None], [name], ["C2"]),
    ):
        # The power of ten in the unit, plain tick labels: no offset hides the numbers.
        divisor = power_axis(ax, largest(values), label)
        for column, text, color in zip(values.T, names, colors):
            ax.plot(t / scale, column / divisor, color=color, label=text)
        # Beside the axes: any corner inside covers the curves' peaks.
        legend_beside(ax)
    if legend_title:
        top.get_legend().set_title(legend_title, prop={"size": 7})
    bottom.set_xlabel(f"time [{unit}]")
    return scale


def _dominant_name(n: int, start: float, spread: float, size: float, flat: bool, regime: str) -> str:
    """The legend entry of the largest component's change, omega_n - omega_n(0), with its start; drawn flat,
    how constant it is as measured (a body symmetric about the axis: exactly, by Euler's equations)."""
    change = f"$\\omega_{n} - \\omega_{n}(0)$"
    at_start = f"$\\omega_{n}(0)$ = {start_text(start, _RAD_S)}"
    if not flat:
        return f"{change}\n{at_start}"
    if spread == 0:
        why = " (a symmetric body)" if regime == "symmetric" else ""
        return f"{change} = 0: constant{why}\n{at_start}"
    return f"{change} drawn as 0:\n{constancy(spread, size)} of itself (rounding's scale)\n{at_start}"


#: Flips marked one line each up to this many in a span; more are closer than a figure resolves.
MAX_MARKED_FLIPS = 200


def _mark_flips(axes, times, scale: float) -> str:
    """Dotted lines at the flip ``times`` (s, drawn in units of ``scale``) on each of ``axes``, as one
    collection; none past :data:`MAX_MARKED_FLIPS` (a span of a million flips once drew a line
    each: millions of artists, 20 GB and no end). Returns the title's note on what was left out."""
    if times.size > MAX_MARKED_FLIPS:
        return f" ({times.size:,} flips, too close to mark)"
    for ax in axes:
        ax.vlines(times / scale, 0, 1, transform=ax.get_xaxis_transform(), colors="0.6", lw=0.8, ls=":")
    return ""


def _polhode_on_sphere(ax3, L, I, note: str = "") -> None:
    uu, vv = np.meshgrid(np.linspace(0, 2 * np.pi, 40), np.linspace(0, np.pi, 20))
    ax3.plot_wireframe(np.cos(uu) * np.sin(vv), np.sin(uu) * np.sin(vv), np.cos(vv), color="0.85", lw=0.4)
    ax3.plot(L[:, 0], L[:, 1], L[:, 2], color="C0", lw=1.4)
    ax3.plot(L[:1, 0], L[:1, 1], L[:1, 2], "o", color="C3", ms=4)
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1.25
        ax3.plot(*zip(-e, e), color="0.4", lw=0.8)
        ax3.text(*e, f"$e_{k + 1}$ (I={I[k]:.3g})", fontsize=8)
    ax3.set_box_aspect((1, 1, 1))
    ax3.set_axis_off()
    ax3.set_title(f"polhode: L/|L| in the body frame{note}", fontsize=9)


def _polhode_from_above(ax, L, axis: int, note: str = "") -> None:
    """A polhode that stays within a few degrees of a principal axis, seen down that axis: each point
    at its angle from the axis (an azimuthal equidistant view), in the unit :func:`angle_unit` picks."""
    a, b = [k for k in range(3) if k != axis]
    sign = np.sign(L[0, axis])
    x, y = L[:, a] * sign, L[:, b] * sign
    across = np.hypot(x, y)
    stretch = np.divide(np.arctan2(across, np.abs(L[:, axis])), across, out=np.ones_like(across), where=across > 0)
    x, y = x * stretch, y * stretch
    size, name = angle_unit(float(np.max(np.hypot(x, y))))
    ax.plot(x / size, y / size, color="C0", lw=1.4)
    ax.plot(x[:1] / size, y[:1] / size, "o", color="C3", ms=4)
    ax.plot([0], [0], "+", color="0.3", ms=10)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"L along $e_{a + 1}$ ({name} from $e_{axis + 1}$)")
    ax.set_ylabel(f"L along $e_{b + 1}$ ({name})")
    ax.set_title(f"polhode: L/|L| in the body frame, seen down $e_{axis + 1}${note}", fontsize=9)
