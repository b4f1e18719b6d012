"""Figures of forecasts: the pole ahead with its intervals, and a hindcast's error against lead time beside
published curves.

Matplotlib ``Figure`` objects (no pyplot); files are written atomically with
the umask's mode (:func:`wobble.plot.save.save_figure`).
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from wobble.io.dates import iso_date
from wobble.plot._style import decimal_year
from wobble.plot.save import WIDE_DPI, save_figure

__all__ = ["POINTS_UP_TO", "forecast_figure", "save_forecast_figure", "hindcast_figure", "save_hindcast_figure"]


#: A forecast of up to this many lead days is drawn as points with error bars: as bands and a line, one day (a
#: single point) drew nothing at all right of the issue line while the legend listed it, and a few days were a
#: sliver a few pixels wide at the edge of two years of record.
POINTS_UP_TO = 5


def forecast_figure(forecast, data=None) -> Figure:
    """x_p and y_p against time: the record's last two years, the forecast, its 68 % and 95 % intervals.

    Intervals are bands about the forecast's line; a forecast of up to :data:`POINTS_UP_TO` days is drawn as
    points with error bars (thick: 68 %, thin with caps: 95 %) instead. The legend is outside the panels, below
    them, where it hides no data.
    """
    from astropy import units as u

    from wobble.api.polar_motion.record import load_polar_motion, mjd_values

    fig = Figure(figsize=(9, 6.5), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    if data is None:
        data = load_polar_motion(forecast.source or None)
    mjd = mjd_values(data["time"])
    last = float(forecast.last_data.mjd)
    keep = (mjd > last - 730) & (mjd <= float(forecast.time_mjd[-1]))
    tf = decimal_year(forecast.time_mjd)
    b68, b95 = forecast.bounds(68), forecast.bounds(95)
    kind = "calibrated on past forecasts" if forecast.calibration is not None else "the model's, not calibrated"
    points = tf.size <= POINTS_UP_TO
    for ax, name, value, key in ((axes[0], "x_p", forecast.x, "x"), (axes[1], "y_p", forecast.y, "y")):
        obs = (np.asarray(data[name].values) * u.Unit(data[name].attrs["units"])).to_value(u.mas)
        used = keep & (mjd <= last)
        later = keep & (mjd > last)
        ax.plot(decimal_year(mjd[used]), obs[used], color="k", lw=1, label="record used")
        if later.any():
            ax.plot(decimal_year(mjd[later]), obs[later], color="0.5", lw=1, ls=":", label="record after (not used)")
        v = value.value
        (lo95, hi95), (lo68, hi68) = ((b[key][0].value, b[key][1].value) for b in (b95, b68))
        if points:
            ax.errorbar(
                tf, v, yerr=[v - lo95, hi95 - v], fmt="none", ecolor="C0", alpha=0.45, elinewidth=1.2, capsize=4,
                label=f"95 % ({kind})", zorder=3,
            )  # fmt: skip
            ax.errorbar(
                tf, v, yerr=[v - lo68, hi68 - v], fmt="none", ecolor="C0", elinewidth=3.5, label="68 %", zorder=3
            )
            # Hollow, so the 68 % bar shows through it where the interval is smaller than the marker.
            ax.plot(tf, v, "o", mfc="none", mec="k", mew=0.9, ms=6, label=f"forecast ({forecast.method})", zorder=4)
        else:
            ax.fill_between(tf, lo95, hi95, color="C0", alpha=0.15, lw=0, label=f"95 % ({kind})")
            ax.fill_between(tf, lo68, hi68, color="C0", alpha=0.3, lw=0, label="68 %")
            ax.plot(tf, v, color="C0", lw=1.5, label=f"forecast ({forecast.method})")
        ax.axvline(decimal_year(float(forecast.issued.mjd)), color="C3", lw=0.8, ls="--")
        ax.set_ylabel(f"{name} [mas]")
    if points:  # room right of the last point, so its marker and caps are not cut by the frame
        lo, hi = axes[0].get_xlim()
        axes[0].set_xlim(lo, max(hi, float(tf[-1]) + 0.03 * (float(tf[-1]) - lo)))
    # Below the panels: inside the top one, the legend (three columns) covered the x_p record.
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=3, fontsize="small", frameon=False)
    axes[1].set_xlabel("year")
    axes[0].set_title(
        f"forecast issued {iso_date(forecast.issued)} (dashed), data to {iso_date(forecast.last_data)} (latency "
        f"{forecast.latency.value:g} d)",
        fontsize="medium",
    )
    return fig


def save_forecast_figure(forecast, path, *, overwrite: bool = False, data=None):
    """Write :func:`forecast_figure` to ``path`` (png, pdf or svg)."""
    return save_figure(forecast_figure(forecast, data), path, overwrite=overwrite, dpi=WIDE_DPI)


#: One colour per method in every panel (a method's x_p and y_p, 68 % and 95 % differ by line style): from the
#: colour cycle the same orange was kalman in one panel, ls_ar's y_p in the next and ls_ar's 95 % in a third.
METHOD_COLOURS = {"kalman": "C0", "ls_ar": "C1"}


def hindcast_figure(hindcast) -> Figure:
    """2-D RMS and x_p mean absolute error against lead time for each method, persistence and LS alone, with
    the anchors; and the 68 % and 95 % interval coverage."""
    from wobble.api.polar_motion.hindcast import ANCHORS
    from wobble.api.polar_motion.record import RAD_PER_MAS

    fig = Figure(figsize=(11, 8), layout="constrained")
    (ax_rms, ax_mae), (ax_cov, ax_skill) = fig.subplots(2, 2)
    lead = hindcast.lead.value
    first = hindcast.scores[hindcast.methods[0]]
    for k, m in enumerate(hindcast.methods):
        s = hindcast.scores[m]
        c = METHOD_COLOURS.get(m, f"C{k + 2}")
        ax_rms.plot(lead, s.rms_2d / RAD_PER_MAS, lw=1.5, color=c, label=m)
        ax_mae.plot(lead, s.mae_x / RAD_PER_MAS, lw=1.5, color=c, label=f"{m} x_p")
        ax_mae.plot(lead, s.mae_y / RAD_PER_MAS, lw=1, ls="--", color=c, label=f"{m} y_p")
        ax_cov.plot(lead, 100 * s.coverage_68, lw=1.5, color=c, label=f"{m} 68 %")
        ax_cov.plot(lead, 100 * s.coverage_95, lw=1, ls="--", color=c, label=f"{m} 95 %")
        ax_skill.plot(lead, s.skill_persistence, lw=1.5, color=c, label=f"{m} vs persistence")
        ax_skill.plot(lead, s.skill_ls, lw=1, ls="--", color=c, label=f"{m} vs LS alone")
    ax_rms.plot(lead, first.rms_2d_persistence / RAD_PER_MAS, color="0.5", lw=1, label="persistence")
    ax_rms.plot(lead, first.rms_2d_ls / RAD_PER_MAS, color="0.5", lw=1, ls=":", label="LS extrapolation alone")
    markers = {"rms_2d": (ax_rms, "o"), "mae_x": (ax_mae, "s"), "mae_y": (ax_mae, "^")}
    for label, metric, values in ANCHORS:
        if metric not in markers:
            continue
        ax, mk = markers[metric]
        d = np.array(sorted(values))
        ax.plot(d, [values[k] for k in d], mk, color="k", mfc="none", ms=6, label=label)
    for ax in (ax_rms, ax_mae):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("lead time [d]")
    # Below the panels: inside, the legends covered the persistence curve or the short-range anchors (Dill et
    # al. at 5 and 10 days, Lei et al. at 10), wherever the curves of a given hindcast happened to run.
    for ax in (ax_rms, ax_mae):
        ax.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    ax_rms.set_ylabel("2-D RMS error [mas]")
    ax_mae.set_ylabel("mean absolute error [mas]")
    ax_cov.axhspan(63, 73, color="0.5", alpha=0.2, lw=0, label="goal for 68 %: 63-73 %")
    ax_cov.axhline(95, color="0.5", lw=0.8)
    ax_cov.set_ylim(0, 100)
    ax_cov.set_xlabel("lead time [d]")
    ax_cov.set_ylabel("outcomes inside the interval [%]")
    ax_cov.legend(fontsize="x-small")
    ax_skill.axhline(0, color="0.5", lw=0.8)
    ax_skill.set_xlabel("lead time [d]")
    ax_skill.set_ylabel("skill, 1 - RMS / RMS(reference)")
    ax_skill.legend(fontsize="x-small")
    intervals = (
        "intervals calibrated on past forecasts"
        if getattr(hindcast, "calibrated", False)
        else "the models' own intervals"
    )
    ax_cov.set_title(intervals, fontsize="medium")
    fig.suptitle(
        f"hindcast: {len(hindcast.issued_mjd)} forecasts issued "
        f"{decimal_year(hindcast.issued_mjd[0]):.1f}-{decimal_year(hindcast.issued_mjd[-1]):.1f}, "
        f"latency {hindcast.latency.value:g} d (anchors: published, with angular-momentum forecasts where marked)"
    )
    return fig


def save_hindcast_figure(hindcast, path, *, overwrite: bool = False):
    """Write :func:`hindcast_figure` to ``path`` (png, pdf or svg)."""
    return save_figure(hindcast_figure(hindcast), path, overwrite=overwrite, dpi=WIDE_DPI)
