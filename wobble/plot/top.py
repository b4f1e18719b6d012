"""Figures of the heavy symmetric top (Goldstein, Poole & Safko 2002, sec. 5.7): the axis on the sphere for the
three nutation classes, the effective potential V'(theta) with the E' line, f(u) with its roots."""

from __future__ import annotations


import math

import matplotlib.pyplot as plt
import numpy as np
from astropy import units as u

from wobble.api.sampling import check_samples, check_step, sample_times
from wobble.api.top import BYTES_PER_SAMPLE, HeavyTop
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.plot._sampling import first_periods, period_count
from wobble.plot._style import angle_unit, largest, power_axis, power_label, power_of_ten, unit_label

__all__ = [
    "nutation_classes_figure",
    "axis_trace_axes",
    "locus_times",
    "tilt_text",
    "axis_locus_figure",
    "effective_potential_figure",
    "cubic_figure",
]


def _check_top(top) -> None:
    if not isinstance(top, HeavyTop):
        raise InputError("top", top, "a wobble.HeavyTop")


#: Samples per period of the axis's path: a nutation period, or a turn of the precession when the tilt
#: is constant (regular precession). A loop takes about a third of a nutation period and a cusp's
#: rounding less: 200 samples draw both smoothly at the figure's size.
SAMPLES_PER_PERIOD = 200
#: Samples of the axis's path at least (a span of a few periods is drawn finer than the rule needs).
MIN_LOCUS_SAMPLES = 3000
#: Samples of the axis's path at most (about 0.1 s to draw): past them, only the first
#: MAX_LOCUS_SAMPLES / SAMPLES_PER_PERIOD = 200 nutation periods are drawn, and the title says so.
#: By then the loops have gone round the vertical many times and later ones only fill the band.
MAX_LOCUS_SAMPLES = 40_000


def locus_times(top: HeavyTop, t_end: float, samples: int | None = None) -> tuple[np.ndarray, str]:
    """(times in s, a note for the title) at which the axis's path from 0 to ``t_end`` (s) is drawn.

    With ``samples`` given, that many evenly spaced times. Otherwise :data:`SAMPLES_PER_PERIOD`
    per period of the path (the nutation period; a turn of the precession for regular precession,
    drawn once since every turn retraces the circle), at least :data:`MIN_LOCUS_SAMPLES`; past
    :data:`MAX_LOCUS_SAMPLES`, the first periods only, which the note names (fixed samples over a
    long span once drew 2.6 points per nutation period, and no loop could be seen).
    """
    if samples is not None:  # checked against the memory a motion of that many samples needs
        return sample_times(None, t_end * u.s, samples, BYTES_PER_SAMPLE), ""
    m = top.model
    if m.nutation == "sleeping":  # the axis stays upright: a point
        return np.linspace(0.0, t_end, MIN_LOCUS_SAMPLES), ""
    if m.nutation == "regular":
        rate = abs(m.mean_precession_rate)
        period, most, name = (2 * np.pi / rate if rate > 0 else np.inf), 1, "turns of the precession"
    else:
        period, most, name = m.nutation_period, MAX_LOCUS_SAMPLES // SAMPLES_PER_PERIOD, "nutation periods"
    if not (np.isfinite(period) and period > 0):
        return np.linspace(0.0, t_end, MIN_LOCUS_SAMPLES), ""
    times, count = first_periods(t_end, period, most, SAMPLES_PER_PERIOD, MIN_LOCUS_SAMPLES)
    if count is None:
        return times, ""
    note = "one turn drawn (each retraces it)" if most == 1 else f"first {most} of {period_count(count)} {name} drawn"
    return times, note


#: A horizontal distance sin(theta) below this is rounding: sin(pi) is 1.2e-16, not 0 (a top hanging straight
#: down drew rings of 2.5e-5 micro-arcseconds under an offset text).
_ROUNDING_EXTENT = 1e-15


def _tilt_extent(m) -> float:
    """The largest horizontal distance sin(theta) of the axis from the vertical over its motion (0 when
    that is rounding). Rounding only below: pi - theta of a hanging top is known to 1.2e-16, but theta next to
    the upward vertical keeps its own digits (a top tilted 1e-16 rad was drawn as a dot in a unit frame)."""
    if m.theta_min <= np.pi / 2 <= m.theta_max:
        return 1.0
    if m.theta_max < np.pi / 2:
        return float(np.sin(m.theta_max))
    extent = float(np.sin(m.theta_min))
    return extent if extent > _ROUNDING_EXTENT else 0.0


def tilt_text(theta_min: float, theta_max: float, digits: str = ".4g") -> str:
    """'A to B unit' for two tilts in rad: in deg, or in the arcsec, mas or µas that the larger reaches
    when it is under a degree (a nearly sleeping top's 1e-6 rad reads '206.3 to 225.1 mas'); a top
    hanging within a degree of straight down is measured from below ('180 deg minus 1.03 to 3.2 arcsec',
    where both read '180 deg' before)."""
    if min(theta_min, theta_max) > np.pi - np.radians(1.0):
        if np.pi - min(theta_min, theta_max) <= _ROUNDING_EXTENT:
            return "180 deg (straight down)"
        return "180 deg minus " + tilt_text(np.pi - theta_max, np.pi - theta_min, digits)
    size, name = angle_unit(max(theta_min, theta_max)) if max(theta_min, theta_max) > 0 else (np.radians(1.0), "deg")
    if 0 < max(theta_min, theta_max) < 1e-3 * size:  # under a thousandth of a µas (1e-16 rad): in rad
        size, name, digits = 1.0, "rad", ".4g"
    return f"{theta_min / size:{digits}} to {theta_max / size:{digits}} {name}"


def axis_trace_axes(
    ax, top: HeavyTop, *, periods: float = 6.0, samples: int | None = None, title: str | None = None, t_end=None
):
    """Draw the trace of the symmetry axis on the unit sphere, seen from above, on ``ax``.

    The trace (x, y) = sin(theta) (sin phi, -cos phi) runs between the turning circles
    theta_min and theta_max (dashed), as in the textbook pictures of undulation, cusps
    and loops (Goldstein, Poole & Safko 2002, sec. 5.7). From 0 to ``t_end`` (default
    ``periods`` nutation periods), sampled as :func:`locus_times` says (``samples`` fixes
    the number). A trace within a degree of the vertical is drawn at its angles from the
    vertical, in the unit they reach (arcsec, mas, µas), so no offset or multiplier hides
    the numbers.
    """
    _check_top(top)
    m = top.model
    if t_end is not None:
        t1 = to_si(t_end, "t_end", u.s, positive=True, shape=())
    else:
        t1 = periods * m.nutation_period if np.isfinite(m.nutation_period) else 10.0
    if samples is not None:
        samples = check_samples(samples, BYTES_PER_SAMPLE)
    check_step(t1, samples or MIN_LOCUS_SAMPLES, t_end if t_end is not None else t1 * u.s, " of the figure")
    try:  # the whole span is checked, drawn or not
        m.check_times(np.array([0.0, t1]))
    except InputError as exc:
        raise InputError("t_end", t_end if t_end is not None else t1 * u.s, exc.allowed) from None
    t, note = locus_times(top, t1, samples)
    # The model's arrays, not a Dataset: building one imported xarray (0.9 s of a 3-s `wobble top --plot`).
    axis = m.motion(t).axis
    extent = _tilt_extent(m)
    size, name = (1.0, "")
    radii = np.sin([m.theta_min, m.theta_max])
    if 0 < extent < np.sin(np.radians(1.0)):
        # Within a degree of the vertical: each point at its angle from it (sin theta -> theta, or
        # pi - theta hanging), in the unit that angle reaches.
        extent = float(np.arcsin(extent))
        size, name = angle_unit(extent)
        if power_of_ten(extent / size):
            # Under a thousandth of a µas (a top tilted 1e-16 rad, or 1e-300): radians in a power of ten.
            exponent = power_of_ten(extent)
            size, name = 10.0**exponent, power_label(exponent, "rad")
        across = np.hypot(axis[:, 0], axis[:, 1])
        axis = axis[:, :2] * np.divide(np.arcsin(across), across, out=np.ones_like(across), where=across > 0)[:, None]
        radii = np.arcsin(radii)
    ring = np.linspace(0, 2 * np.pi, 400)
    for radius in radii:
        ax.plot(radius * np.cos(ring) / size, radius * np.sin(ring) / size, color="0.6", lw=0.8, ls="--")
    ax.plot(axis[:, 0] / size, axis[:, 1] / size, color="C0", lw=1.2)
    ax.plot(axis[:1, 0] / size, axis[:1, 1] / size, "o", color="C3", ms=4, label="start")
    r = extent / size * 1.08 or 1.0  # a sleeping top (theta = 0): a unit frame, not an empty one
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x (horizontal, {name} from the vertical)" if name else "x (horizontal)")
    ax.set_ylabel(f"y (horizontal, {name})" if name else "y (horizontal)")
    title = title or m.nutation
    ax.set_title(f"{title}\n{note}" if note else title)
    return ax


def axis_locus_figure(top: HeavyTop, t_end, *, samples: int | None = None, path=None, overwrite: bool = False):
    """The path of the figure (symmetry) axis seen from above, from 0 to ``t_end``:
    what ``wobble top --plot`` draws (undulation, cusps or loops between the turning circles).

    Sampled as :func:`locus_times` says (``samples`` fixes the number): a span of more than
    200 nutation periods is drawn for its first 200, and the title says so.
    Returns the figure, or the written path when ``path`` is given (saved atomically).
    """
    from wobble.io.text import duration

    _check_top(top)
    t_end = to_si(t_end, "t_end", u.s, positive=True, shape=()) * u.s
    fig, ax = plt.subplots(figsize=(5.6, 5.6))
    m = top.model
    title = f"{m.nutation}: theta from {tilt_text(m.theta_min, m.theta_max)}, 0 to {duration(t_end.to_value(u.s), 4)}"
    axis_trace_axes(ax, top, samples=samples, t_end=t_end, title=title)
    ax.title.set_fontsize(9)
    ax.legend(loc="upper right", fontsize=8)  # the red dot: where the axis starts
    fig.tight_layout()
    if path is None:
        return fig
    from wobble.plot.save import save_figure

    return save_figure(fig, path, overwrite=overwrite)


def nutation_classes_figure(I1, I3, mgl, theta0, omega3, phidots, *, periods: float = 6.0):
    """Three panels: the axis trace for initial precession rates ``phidots`` (rad/s Quantities),
    typically > 0 (undulating), 0 (released: cusps) and < 0 (loops)."""
    fig, axes = plt.subplots(1, len(phidots), figsize=(4.2 * len(phidots), 4.4))
    for ax, pd in zip(np.atleast_1d(axes), phidots):
        top = HeavyTop(I1=I1, I3=I3, mgl=mgl, theta0=theta0, omega3=omega3, phidot0=pd)
        pdv = pd.to_value(u.rad / u.s)
        axis_trace_axes(ax, top, periods=periods, title=f"{top.nutation}: phidot0 = {pdv:g} {unit_label('rad/s')}")
    fig.suptitle(
        "The symmetry axis on the unit sphere seen from above, between the turning circles "
        "theta_min and theta_max (dashed); red dot: start",
        fontsize=10,
    )
    fig.tight_layout()
    return fig


def effective_potential_figure(top: HeavyTop):
    """V'(theta) = M g l cos theta + (I1/2)((b - a cos theta)/sin theta)^2 with the E' line;
    the motion is confined where V' <= E' (between the turning angles; Goldstein, Poole & Safko 2002,
    sec. 5.7).

    Turning angles less than a degree apart (a nearly sleeping top's 206 and 225 mas) are not to be
    seen on the whole range: a second panel draws V' - E' between them, in the angle unit their size
    reads in and a power of ten of J, from the cubic's roots: V' - E' = -I1 f(u) / (2 sin^2 theta) with
    f = beta (x1 - x)(x2 - x)(x3 - x), x = 1 - cos theta (V' - E' directly is a difference of two
    numbers near E', and f's own terms cancel near the vertical)."""
    m = top.model
    narrow = 0.0 < m.theta_max - m.theta_min < math.radians(1.0)
    fig, axes = plt.subplots(1, 2 if narrow else 1, figsize=(10.0 if narrow else 6.4, 4.0), squeeze=False)
    ax = axes[0, 0]
    th = np.linspace(1e-3, np.pi - 1e-3, 2000)
    v = m.effective_potential(th)
    ax.plot(np.degrees(th), v, color="C0", label="V'(theta)")
    ax.axhline(m.energy_prime, color="C3", lw=1, label="E'")
    for t_ in (m.theta_min, m.theta_max):
        ax.axvline(np.degrees(t_), color="0.5", lw=0.8, ls=":")
    top_ = max(m.energy_prime, m.mgl) + 3 * (abs(m.energy_prime) + m.mgl)
    ax.set_ylim(min(np.min(v), m.energy_prime) - 0.2 * abs(top_), top_)
    ax.set_xlabel("theta [deg]")
    ax.set_ylabel("energy [J]")
    turning = tilt_text(m.theta_min, m.theta_max, ".2f").replace(" to ", " and ")
    ax.set_title(f"Effective potential; turning angles {turning}")
    ax.legend()
    if narrow:
        _potential_well(axes[0, 1], m)
    fig.tight_layout()
    return fig


def _potential_well(ax, m) -> None:
    """V' - E' between and about the turning angles (see :func:`effective_potential_figure`)."""
    width = m.theta_max - m.theta_min
    # Not from theta = 0 (a top through the vertical, theta_min = 0): V' - E' is 0/0 there, its limit finite.
    low = max(m.theta_min - 0.3 * width, 0.5 * m.theta_min, 1e-3 * width)
    th = np.linspace(low, min(m.theta_max + 0.3 * width, np.pi), 1000)
    well = m.well(th)  # from the cubic's roots: V' - E' directly is a difference of two numbers near E'
    rad, name = angle_unit(m.theta_max)
    divisor = power_axis(ax, largest(well), "J", name="V' - E'")
    ax.plot(th / rad, well / divisor, color="C0")
    ax.fill_between(th / rad, well / divisor, 0, where=well <= 0, color="C2", alpha=0.3, label="the motion: V' <= E'")
    ax.plot([m.theta_min / rad, m.theta_max / rad], [0, 0], "o", color="C3")
    ax.axhline(0, color="0.3", lw=0.8)
    ax.ticklabel_format(axis="x", style="plain", useOffset=False)
    ax.set_xlabel(f"theta [{name}]")
    ax.set_title("between the turning angles")
    ax.legend(loc="upper center", fontsize=8)


def _u_text(u_value: float, x: float, digits: int) -> str:
    """u = cos(theta) for a title: as 1 - x when it is too close to 1 for ``digits`` decimals to tell
    (a nearly sleeping top's u1 and u2 both read 1.000000)."""
    if 0 < x < 10.0 ** (2 - digits):
        return f"1 - {x:.4g}"
    return f"{u_value:.{digits}f}"


def cubic_figure(top: HeavyTop):
    """f(u) = udot^2 with its roots u1 <= u2 <= 1 < u3; the motion has u1 <= u <= u2 where f >= 0
    (Goldstein, Poole & Safko 2002, sec. 5.7). Left: the whole cubic (f(+-1) = -(b -+ a)^2 <= 0, so
    u3 > 1); right: the physical interval enlarged, f from its roots (:meth:`HeavyTopModel.f_about_u2`). An interval
    narrower than 1e-3 (a nearly sleeping top, a nearly regular precession) is drawn against u - u2 and
    f in powers of ten named in the labels, so no offset such as '1e-13+10e-1' hides the numbers; a
    double root (u1 = u2, a regular precession) is drawn over a twentieth of the way to u3, the parabola
    touching zero."""
    m = top.model
    u3 = m.u3 if np.isfinite(m.u3) else 2.0
    fig, (ax, az) = plt.subplots(1, 2, figsize=(10.0, 4.0))
    uu = np.linspace(-1.2, u3 + 0.3 * (u3 + 1.2), 3000)
    f = m.f(uu)
    ax.plot(uu, f, color="C0", label="f(u)")
    roots = [r for r in (m.u1, m.u2, m.u3) if np.isfinite(r)]
    ax.plot(roots, np.zeros(len(roots)), "o", color="C3", label="roots u1, u2, u3")
    lim = np.max(np.abs(f)) * 1.05
    ax.set_ylim(-lim, lim)
    width = m.x1 - m.x2  # u2 - u1, with the digits u1 and u2 lose next to the vertical
    pad = 0.3 * width if width > 0 else 0.05 * (u3 - m.u2)
    d = np.linspace(-width - pad, min(pad, m.x2), 1000)  # u - u2, up to u = 1
    fz = m.f_about_u2(d)
    narrow = width + 2 * pad < 1e-3
    if narrow:
        ex, ey = power_of_ten(np.max(np.abs(d))), power_of_ten(np.max(np.abs(fz)))
        xz, ends, fz = d / 10.0**ex, [-width / 10.0**ex, 0.0], fz / 10.0**ey
    else:
        xz, ends = m.u2 + d, [m.u1, m.u2]
    az.plot(xz, fz, color="C0")
    if width > 0:
        inside = (d >= -width) & (d <= 0)
        az.fill_between(xz, 0, fz, where=inside, color="C2", alpha=0.3, label="the motion: f >= 0")
        az.plot(ends, [0, 0], "o", color="C3")
    else:  # no interval to shade: the motion is the double root, u = u2
        az.plot(ends[1:], [0], "o", color="C3", label="the motion: u = u2 (theta constant)")
    for a_ in (ax, az) if not narrow else (ax,):
        a_.axhline(0, color="0.3", lw=0.8)
        for x in (-1, 1):
            a_.axvline(x, color="0.6", lw=0.8, ls="--")
        a_.set_xlabel("u = cos(theta)")
    if narrow:
        az.axhline(0, color="0.3", lw=0.8)
        az.axvline(m.x2 / 10.0**ex, color="0.6", lw=0.8, ls="--")  # u = 1, when the interval reaches it
        az.set_xlabel("u - u2" + (f" [{power_label(ex)}]" if ex else ""))
        az.set_ylabel(f"f(u) [{power_label(ey, 's$^{-2}$')}]")
        az.ticklabel_format(style="plain", useOffset=False)
    az.set_xlim(xz[0], xz[-1])
    ax.set_ylabel("f(u) [s$^{-2}$]")
    if not narrow:
        az.set_ylabel("f(u) [s$^{-2}$]")
    ax.set_title(f"u1 = {_u_text(m.u1, m.x1, 6)}, u2 = {_u_text(m.u2, m.x2, 6)}, u3 = {u3:.4f}")
    az.set_title("between the turning points" if width > 0 else "u1 = u2: a double root, regular precession")
    ax.legend(loc="lower right", fontsize=8)
    az.legend(loc="lower center", fontsize=8)
    fig.tight_layout()
    return fig
