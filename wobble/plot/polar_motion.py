"""Figures of observed polar motion: the pole's path, the two-sided spectrum, the windowed wobble.

Every function draws on a Matplotlib ``Axes`` you pass (or a new figure) and
returns it; nothing here opens a window (``matplotlib.figure.Figure``, no
pyplot). :func:`save_overview` writes the four panels of
``wobble polar-motion --plot``.

The pole path is drawn as seen from above the north pole: x_p to the right
(toward Greenwich), y_p downward (toward 90 deg W). In that view the complex
pole p = x_p - i y_p is the ordinary complex plane and a prograde motion,
like the Chandler wobble, turns counter-clockwise.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from wobble.io.dates import iso_date
from wobble.numerics.calendar import DAY, JULIAN_YEAR, TROPICAL_YEAR
from wobble.plot._style import decimal_year, pm
from wobble.plot.save import WIDE_DPI, save_figure

__all__ = [
    "pole_path",
    "two_sided_spectrum",
    "windowed_wobble",
    "overview",
    "save_figure",
    "save_overview",
    "mark_collapse",
    "log_floor",
    "COLLAPSE_YEAR",
]

#: Days in a Julian year: the spectra's frequencies are per day, their axes per Julian year.
_JULIAN_DAYS = JULIAN_YEAR / DAY


def _published_chandler_cpy() -> float:
    """The published Chandler frequency (Earth catalogue), cycles per Julian year: where to look for the peak
    to label."""
    from astropy import units as u

    from wobble.api.polar_motion import published_chandler_period

    return _JULIAN_DAYS / published_chandler_period()["period"].to_value(u.day)


#: The year after which the Chandler amplitude collapsed (polar-motion.md, section 6; forecast.md), and the split
#: of the excitation's before/after comparison: a line on the panels against time, where their span reaches it.
COLLAPSE_YEAR = 2015.0


def mark_collapse(ax, years, label: str = "2015 (the post-2015 amplitude collapse)") -> None:
    """A dotted line at :data:`COLLAPSE_YEAR`, labelled, if the span ``years`` holds it (it stretched the axis of
    a 1980-2010 figure to 2016, unexplained)."""
    years = np.asarray(years, dtype=float)
    finite = years[np.isfinite(years)]
    if finite.size and finite.min() <= COLLAPSE_YEAR <= finite.max():
        ax.axvline(COLLAPSE_YEAR, color="0.5", ls=":", lw=1, label=label)


def log_floor(ax, freq, amp) -> None:
    """Bottom of a log amplitude axis: half the 1st percentile of the amplitudes away from zero frequency.

    With the drift removed the zero-frequency bin is ~1e-12 mas, which put the axis's bottom ten decades
    below the spectrum and squeezed the peaks into its top fifth.
    """
    freq, amp = np.asarray(freq, dtype=float), np.asarray(amp, dtype=float)
    away = amp[(freq != 0) & np.isfinite(amp) & (amp > 0)]
    if away.size:
        ax.set_ylim(bottom=0.5 * float(np.percentile(away, 1)))


def _axes(ax, **kw):
    if ax is not None:
        return ax
    return Figure(figsize=kw.get("figsize", (6, 5)), layout="constrained").add_subplot()


def pole_path(data, *, start=None, end=None, ax=None, model=None):
    """x_p against y_p over a span, seen from above the north pole.

    Parameters
    ----------
    data : xarray.Dataset
        With ``x_p``, ``y_p`` (any angle unit) and ``time`` (MJD), e.g. from
        :func:`wobble.load_polar_motion` or ``PolarMotionAnalysis.data``.
    start, end : date, optional
        The span drawn (UTC dates as in :func:`wobble.load_polar_motion`).
    ax : matplotlib Axes, optional
    model : xarray.Dataset, optional
        A dataset with ``x_p_mean_pole``/``y_p_mean_pole`` (from
        ``PolarMotionAnalysis.to_dataset()``) to draw the mean pole.
    """
    from astropy import units as u

    from wobble.api.polar_motion.record import mjd_values
    from wobble.io.dates import select_dates

    ax = _axes(ax)
    mjd = mjd_values(data["time"])
    keep = select_dates(mjd, start, end)
    x = (np.asarray(data["x_p"].values) * u.Unit(data["x_p"].attrs["units"])).to_value(u.mas)[keep]
    y = (np.asarray(data["y_p"].values) * u.Unit(data["y_p"].attrs["units"])).to_value(u.mas)[keep]
    years = decimal_year(mjd[keep])
    points = ax.scatter(x, y, c=years, s=2, cmap="viridis", linewidths=0)
    ax.plot(x, y, lw=0.3, color="0.6", zorder=0)
    if model is not None and "x_p_mean_pole" in model:
        mm = mjd_values(model["time"])
        mk = (mm >= mjd[keep][0]) & (mm <= mjd[keep][-1])
        ax.plot(
            model["x_p_mean_pole"].values[mk] * 1e3,
            model["y_p_mean_pole"].values[mk] * 1e3,
            color="C3",
            lw=1.5,
            label="mean pole (fitted drift)",
        )
        ax.legend(loc="lower right", fontsize="small")
    # Direction of motion at the middle of the span.
    k = len(x) // 2
    if len(x) > 20:
        ax.annotate("", xy=(x[k + 5], y[k + 5]), xytext=(x[k], y[k]), arrowprops={"arrowstyle": "->", "color": "k"})
    ax.set_aspect("equal", adjustable="datalim")
    ax.invert_yaxis()
    ax.set_xlabel("x_p [mas] (toward Greenwich)")
    ax.set_ylabel("y_p [mas] (toward 90° W), downward")
    span = f"{iso_date(float(mjd[keep][0]))} to {iso_date(float(mjd[keep][-1]))}" if keep.any() else "no data"
    ax.set_title(f"pole path {span}, seen from above the north pole\n(counter-clockwise = prograde)", fontsize="medium")
    cbar = ax.figure.colorbar(points, ax=ax, shrink=0.8)
    cbar.set_label("year")
    return ax


def two_sided_spectrum(spectrum, *, ax=None, log=True, max_cpy=3.0, chandler_period=None, resolved=True):
    """Amplitude against frequency in cycles per year, retrograde (negative) and prograde (positive).

    Parameters
    ----------
    spectrum : xarray.Dataset
        ``PolarMotionAnalysis.spectrum`` (``amplitude_spectrum`` on ``frequency`` in cycles per Julian year).
    chandler_period : Quantity, optional
        The measured period (``PolarMotionAnalysis.spectral.period``): the Chandler mark goes to its
        frequency and its label gives it. Without it the mark is the highest bin within 0.03 cycle per year
        of the published frequency, which on a short span can be the annual peak's flank.
    resolved : bool
        Whether that estimate resolves a Chandler peak (``PolarMotionAnalysis.spectral.resolved``): if not (its
        period at the search band's edge), the mark's label says so.
    """
    ax = _axes(ax, figsize=(7, 4))
    freq = spectrum["frequency"]  # cycles per Julian year; files before 2026-11-30 wrote day-1
    cpy = np.asarray(freq.values) * (_JULIAN_DAYS if freq.attrs.get("units") == "day-1" else 1.0)
    amp = np.asarray(spectrum["amplitude_spectrum"].values)
    keep = np.abs(cpy) <= max_cpy
    ax.plot(cpy[keep], amp[keep], lw=0.8, color="C0", zorder=2)
    if log:
        ax.set_yscale("log")
    # Label each peak at its height, staggered so the Chandler and prograde
    # annual labels (0.16 cycle/yr apart) do not overlap.
    marks = [
        ("Chandler", _published_chandler_cpy(), (-60, 8)),
        ("annual", JULIAN_YEAR / TROPICAL_YEAR, (12, -4)),
        ("retrograde annual", -JULIAN_YEAR / TROPICAL_YEAR, (-40, 10)),
    ]
    for label, f, offset in marks:
        if label == "Chandler" and chandler_period is not None:
            _mark_measured(ax, cpy, amp, keep, chandler_period, offset, resolved)
            continue
        near = keep & (np.abs(cpy - f) < 0.03)
        if not near.any():
            continue
        k = np.flatnonzero(near)[np.argmax(amp[near])]
        _mark(ax, cpy[k], amp[k], f"{label}\n{cpy[k]:+.3f} cpy, {amp[k]:.0f} mas", offset)
    ax.set_xlabel("frequency [cycles per year]  (negative: retrograde, positive: prograde)")
    ax.set_ylabel("amplitude [mas]")
    if log:
        ax.set_ylim(top=amp[keep].max() * 4)
        log_floor(ax, cpy[keep], amp[keep])
    else:  # room above the highest peak for its label (it ran into the title)
        ax.set_ylim(0, amp[keep].max() * 1.25)
    ax.set_title("two-sided spectrum of x_p - i y_p (drift removed)", fontsize="medium")
    ax.set_xlim(-max_cpy, max_cpy)
    return ax


def _mark_measured(ax, cpy, amp, keep, period, offset, resolved=True) -> None:
    """The Chandler mark at the measured period's frequency (the bin nearest it), labelled with the period (and,
    where the estimate resolves no peak, with that)."""
    from astropy import units as u

    days = period.to_value(u.day)
    f = _JULIAN_DAYS / days
    if not (np.isfinite(f) and keep.any()):
        return
    k = np.flatnonzero(keep)[np.argmin(np.abs(cpy[keep] - f))]
    arrow = abs(f - JULIAN_YEAR / TROPICAL_YEAR) < 0.12
    if arrow:  # beside the annual peak (a short span's estimate): the label clears it, an arrow points back
        offset = (offset[0] - 70, offset[1] + 10)
    note = "" if resolved else "\nat the band's edge: no peak resolved"
    _mark(ax, cpy[k], amp[k], f"Chandler (spectral estimate)\n{days:.1f} d = {f:+.3f} cpy{note}", offset, arrow)


def _mark(ax, x, y, text, offset, arrow: bool = False) -> None:
    """A peak's ring and its label, ``offset`` points away (with an arrow to the ring when moved aside)."""
    ax.plot(x, y, "o", ms=4, mfc="none", color="C3", zorder=3)
    props = {"arrowprops": {"arrowstyle": "-", "color": "C3", "lw": 0.6}} if arrow else {}
    ax.annotate(text, (x, y), xytext=offset, textcoords="offset points", fontsize="x-small", **props)


def windowed_wobble(windows, *, axes=None, period=None, model_period=None):
    """Chandler amplitude and period in sliding windows, against the windows' centres.

    Parameters
    ----------
    windows : xarray.Dataset
        ``PolarMotionAnalysis.windows``.
    axes : (Axes, Axes), optional
        For the amplitude and the period.
    period : (float, float), optional
        The full-record period and its uncertainty, days (a band on the period panel); None when the span
        resolves no Chandler term (no band: a band at the search's edge would read as a measurement).
    model_period : float, optional
        The modelled period, days (a line on the period panel).
    """
    if axes is None:
        fig = Figure(figsize=(7, 5), layout="constrained")
        axes = fig.subplots(2, 1, sharex=True)
    ax_a, ax_p = axes
    years = decimal_year(windows["window_time"].values)
    width = float(windows.attrs.get("window_years", np.nan))
    ax_a.errorbar(
        years,
        windows["chandler_amplitude"],
        yerr=windows["chandler_amplitude_uncertainty"],
        fmt="o-",
        ms=3,
        lw=1,
        label="Chandler",
    )
    ax_a.errorbar(
        years,
        windows["annual_prograde_amplitude"],
        yerr=windows["annual_prograde_amplitude_uncertainty"],
        fmt="s-",
        ms=2,
        lw=0.8,
        color="C2",
        alpha=0.7,
        label="annual (prograde)",
    )
    mark_collapse(ax_a, years)
    drawn = np.isfinite(np.asarray(windows["chandler_amplitude"].values, dtype=float)).any()
    if not drawn:
        # No window with a Chandler term (gaps, or windows too short to resolve one): say so, not two empty panels;
        # below the middle of the period panel, where its model line (alone, so centred) would run through it.
        for ax, y in ((ax_a, 0.5), (ax_p, 0.25)):
            ax.text(
                0.5,
                y,
                "no window has a Chandler term to show (the caveats say why)",
                ha="center",
                va="center",
                transform=ax.transAxes,
                fontsize="small",
            )
    ax_a.set_ylabel("amplitude [mas]")
    ax_a.set_ylim(bottom=0)
    if np.isfinite(years).any() and np.isfinite(width):  # the windows' reach, whatever their fits gave
        ax_a.set_xlim(np.nanmin(years) - width / 2, np.nanmax(years) + width / 2)
    # A legend of what is drawn: series of windows without a value (all NaN) are not listed.
    empty = {
        label
        for label, name in (("Chandler", "chandler_amplitude"), ("annual (prograde)", "annual_prograde_amplitude"))
        if not np.isfinite(np.asarray(windows[name].values, dtype=float)).any()
    }
    listed = [(h, lab) for h, lab in zip(*ax_a.get_legend_handles_labels()) if lab not in empty]
    if listed:
        ax_a.legend(*zip(*listed), fontsize="small")
    ax_a.set_title(f"sliding windows of {width:g} years (plotted at their centres)", fontsize="medium")
    ax_p.errorbar(years, windows["chandler_period"], yerr=windows["chandler_period_uncertainty"], fmt="o-", ms=3, lw=1)
    if period is not None:
        p, s = period
        ax_p.axhspan(p - s, p + s, color="C0", alpha=0.15, label=f"whole span {pm(p, s)} d")
    if model_period is not None:
        ax_p.axhline(model_period, color="C3", ls="--", lw=1, label=f"model {model_period:.1f} d")
    if period is not None or model_period is not None:
        ax_p.legend(fontsize="small")
    ax_p.set_ylabel("Chandler period [d]")
    ax_p.set_xlabel("year")
    return ax_a, ax_p


def overview(analysis, *, path_span=None) -> Figure:
    """The four panels of ``wobble polar-motion --plot`` for a :class:`~wobble.PolarMotionAnalysis`.

    ``path_span`` = (start, end) chooses the span of the pole path (default:
    the last 6.4 years, one Chandler-annual beat, or the whole span if shorter).
    """
    from astropy import units as u

    fig = Figure(figsize=(12, 9), layout="constrained")
    grid = fig.add_gridspec(2, 2)
    ax_path = fig.add_subplot(grid[0, 0])
    ax_spec = fig.add_subplot(grid[0, 1])
    sub = grid[1, :].subgridspec(2, 1)
    ax_amp = fig.add_subplot(sub[0])
    ax_per = fig.add_subplot(sub[1], sharex=ax_amp)
    e = analysis.estimate
    if path_span is None:
        end_mjd = float(e.end.mjd)
        start_mjd = max(float(e.start.mjd), end_mjd - 6.4 * _JULIAN_DAYS)
        from astropy.time import Time

        path_span = (Time(start_mjd, format="mjd"), Time(end_mjd, format="mjd"))
    pole_path(analysis.data, start=path_span[0], end=path_span[1], ax=ax_path)
    two_sided_spectrum(
        analysis.spectrum,
        ax=ax_spec,
        chandler_period=analysis.spectral.period,
        resolved=analysis.spectral.resolved,
    )
    windowed_wobble(
        analysis.windows,
        axes=(ax_amp, ax_per),
        period=(e.period.to_value(u.day), e.period_uncertainty.to_value(u.day)) if e.resolved else None,
        model_period=analysis.budget.period.to_value(u.day),
    )
    if e.resolved:
        fig.suptitle(
            f"Chandler wobble {iso_date(e.start)} to {iso_date(e.end)}: "
            f"{pm(e.period.to_value(u.day), e.period_uncertainty.to_value(u.day))} d, "
            f"{e.amplitude.to_value(u.mas):.0f} mas (least squares)"
        )
    else:  # the title had given 365 +/- 76 d and 11907054 mas over a pole path 180 mas across
        fig.suptitle(
            f"Chandler wobble {iso_date(e.start)} to {iso_date(e.end)}: not resolved by the least squares\n"
            f"{e.unresolved_because}"
        )
    return fig


def save_overview(analysis, path, *, overwrite: bool = False, dpi: int = WIDE_DPI) -> Path:
    """Write :func:`overview` to ``path`` (format from the suffix), atomically; refuse to replace without
    ``overwrite``."""
    return save_figure(overview(analysis), path, overwrite=overwrite, dpi=dpi)
