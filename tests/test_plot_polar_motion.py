"""What the polar-motion, excitation and hindcast figures draw, read back from the figures: the marks where the
measurements are, notes where there is nothing to draw, one colour per method (a visual audit's findings)."""

from __future__ import annotations

import matplotlib.colors as mcolors
import numpy as np
import pytest
from astropy import units as u

import wobble
from wobble.errors import InputError
from wobble.plot.polar_motion import COLLAPSE_YEAR, overview, two_sided_spectrum, windowed_wobble


@pytest.fixture(scope="module")
def short():
    """Five years, windows just long enough to run (two years of samples each; too short to hold a Chandler
    term: their values are left out)."""
    return wobble.polar_motion_analysis(
        start="2015", end="2020", window=732.5 * u.day, step=1 * u.yr, excitation_q=None, quality_factor=False
    )


def test_two_year_windows_are_refused_not_left_empty():
    """A window of exactly 2 yr holds 730 daily samples' span, short of the 2 yr each window's fit needs:
    every window came out NaN, silently. Refused now, naming the shortest that runs."""
    with pytest.raises(InputError, match=r"^window: got 2.0 yr; allowed: a length from 2.005 yr \(732.5 d"):
        wobble.polar_motion_analysis(start="2015", end="2020", window=2 * u.yr, excitation_q=None, quality_factor=False)
    # A span no window fits is told the least that takes one (it was offered "from 2.005 yr to 2.00 yr").
    with pytest.raises(InputError, match=r"start/end: got 2015-01-01 to 2017-01-02 \(732 d\); allowed: .* 732.5 d"):
        wobble.polar_motion_analysis(start="2015-01-01", end="2017-01-02", excitation_q=None, quality_factor=False)


def test_the_chandler_mark_is_at_the_measured_period(short):
    """The mark was the highest bin within 0.03 cpy of the published frequency: on five years, the annual peak's
    flank (+0.850 cpy, where the spectral estimate said 390 d = +0.937 cpy)."""
    ax = two_sided_spectrum(short.spectrum, chandler_period=short.spectral.period)
    days = short.spectral.period.to_value(u.day)
    label = next(t.get_text() for t in ax.texts if t.get_text().startswith("Chandler"))
    assert f"{days:.1f} d = {365.25 / days:+.3f} cpy" in label
    marked = next(t.xy[0] for t in ax.texts if t.get_text().startswith("Chandler"))
    cpy = short.spectrum["frequency"].values  # cycles per Julian year
    assert abs(marked - 365.25 / days) <= np.min(np.abs(cpy - 365.25 / days)) + 1e-12
    # The log axis starts near the spectrum, not at the drift-removed zero bin (~1e-12 mas).
    amp = short.spectrum["amplitude_spectrum"].values[(np.abs(cpy) <= 3) & (cpy != 0)]
    assert ax.get_ylim()[0] == pytest.approx(0.5 * np.percentile(amp, 1))


def test_windows_without_a_fit_say_so_and_the_axis_keeps_to_the_windows(short):
    empty = short.windows.copy(deep=True)
    for name in ("chandler_amplitude", "chandler_period", "annual_prograde_amplitude"):
        empty[name][:] = np.nan
    ax_a, ax_p = windowed_wobble(empty)
    assert any("no window has a Chandler term" in t.get_text() for t in ax_a.texts + ax_p.texts)
    years = 2000 + (short.windows["window_time"].values - 51544.5) / 365.25
    half = 732.5 / 365.25 / 2
    assert ax_a.get_xlim() == pytest.approx((years.min() - half, years.max() + half))


def test_the_2015_line_is_drawn_only_where_the_windows_reach_it(short):
    def collapse_lines(ax):
        return [line for line in ax.get_lines() if line.get_label().startswith("2015")]

    later = wobble.polar_motion_analysis(
        start="2010", end="2020", window=4 * u.yr, excitation_q=None, quality_factor=False
    )
    (line,) = collapse_lines(windowed_wobble(later.windows)[0])
    assert line.get_xdata()[0] == COLLAPSE_YEAR
    early = wobble.polar_motion_analysis(
        start="1980", end="1990", window=4 * u.yr, excitation_q=None, quality_factor=False
    )
    ax_a, _ = windowed_wobble(early.windows)
    assert collapse_lines(ax_a) == [] and ax_a.get_xlim()[1] < 1990  # not drawn, and the axis not stretched to it
    title = overview(short).axes[0].get_title()
    assert "2020-01-01" in title  # the pole-path panel says its span


def test_a_short_excitation_figure_says_why_its_band_panel_is_empty():
    from wobble.plot.excitation import excitation_figure

    ex = wobble.geodetic_excitation(start="2017-01-01", end="2020-01-01")
    assert ex.band_chi is None
    fig = excitation_figure(ex)
    assert any("no Chandler-band amplitudes" in t.get_text() for t in fig.axes[1].texts)
    assert "no peak in its excitation" not in fig.axes[0].get_title()  # the title states what is drawn


def test_a_hindcast_figure_gives_each_method_one_colour_in_every_panel():
    from wobble.plot.forecast import hindcast_figure

    h = wobble.hindcast_polar_motion(
        start="2018-03-01", end="2018-03-15", horizon=10 * u.day, latency=1 * u.day, workers=1
    )
    fig = hindcast_figure(h)
    for m in h.methods:
        colours = {
            mcolors.to_hex(line.get_color())
            for ax in fig.axes
            for line in ax.get_lines()
            if line.get_label().split(" ")[0] == m
        }
        assert len(colours) == 1, (m, colours)
    # Legends of the error panels are outside the axes (inside they hid the anchors).
    for ax in fig.axes[:2]:
        box = ax.get_legend().get_bbox_to_anchor().transformed(ax.transAxes.inverted())
        assert box.y1 < 0


@pytest.mark.parametrize("issued", ["1979-02-26", "2026-10-29"])  # the first issue date allowed, and the last
def test_a_one_day_forecast_is_drawn_and_its_legend_hides_no_data(issued):
    """Found by hand beside the fuzzer (seed 419 session): '--horizon 1d' drew nothing right of the issue line (a
    band and a line of one point are empty) while the legend, inside the x_p panel, listed them over the record.
    A forecast of a few days is drawn as points with error bars, and the legend is below the panels."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.container import ErrorbarContainer

    from wobble.plot.forecast import forecast_figure

    f = wobble.forecast_polar_motion(issued=issued, horizon=1 * u.day)
    fig = forecast_figure(f)
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    b68, b95 = f.bounds(68), f.bounds(95)
    year = 2000 + (float(f.time_mjd[0]) - 51544.5) / 365.25
    for ax, key, value in ((fig.axes[0], "x", f.x), (fig.axes[1], "y", f.y)):
        assert ax.get_legend() is None  # not inside a panel
        (point,) = [line for line in ax.get_lines() if line.get_label() == "forecast (kalman)"]
        assert point.get_marker() == "o" and point.get_ydata() == pytest.approx(value.value)
        lo, hi = ax.get_xlim()
        assert lo < year < hi and hi - year > 0.01 * (hi - lo)  # inside the frame, its marker not cut
        bars = {c.get_label(): c for c in ax.containers if isinstance(c, ErrorbarContainer)}
        for label, b in (("68 %", b68), ("95 % (calibrated on past forecasts)", b95)):
            (segments,) = [lc.get_segments() for lc in bars[label].lines[2]]
            (ys,) = [s[:, 1] for s in segments]
            assert ys == pytest.approx([b[key][0][0].value, b[key][1][0].value])
    # The figure's legend lists what the panels draw, and lies outside both of them.
    legend = fig.legends[0]
    drawn = {a.get_label() for ax in fig.axes for a in ax.get_lines() + list(ax.containers)}
    assert {t.get_text() for t in legend.get_texts()} <= drawn
    box = legend.get_window_extent(renderer)
    for ax in fig.axes:
        assert not box.overlaps(ax.get_window_extent(renderer))


def test_a_forecast_of_weeks_keeps_its_bands():
    from matplotlib.collections import FillBetweenPolyCollection

    from wobble.plot.forecast import forecast_figure

    f = wobble.forecast_polar_motion(issued="2020-01-01", horizon=30 * u.day, calibrated=False)
    ax = forecast_figure(f).axes[0]
    assert sum(isinstance(c, FillBetweenPolyCollection) for c in ax.collections) == 2
    assert not ax.containers


def test_a_span_without_a_chandler_term_is_not_titled_with_one():
    """Found by hand beside the fuzzer (seed 419 session): two years, 2024-09-26 to 2026-09-29, were titled
    "365 +/- 76 d, 11907054 mas (least squares)" over a pole path 180 mas across, with a band of that period on
    the period panel and a legend of two empty window series. The title says the term is not resolved and why;
    no band is drawn for it; a legend lists only what is drawn."""
    a = wobble.polar_motion_analysis(start="2024-09-26", end="2026-09-29", excitation_q=None, quality_factor=False)
    assert not a.least_squares.resolved
    fig = overview(a)
    title = fig.get_suptitle()
    assert "not resolved by the least squares" in title and "variance inflation" in title
    assert "mas" not in title.split("\n")[0]
    ax_path, ax_spec, ax_amp, ax_per = fig.axes[:4]
    assert not [p for p in ax_per.patches + ax_per.collections if p.get_label().startswith("whole span")]
    assert ax_amp.get_legend() is None  # both window series are empty (NaN): nothing to list
    labels = [t.get_text() for t in ax_per.get_legend().get_texts()]
    assert labels == [f"model {a.budget.period.value:.1f} d"]
    mark = next(t.get_text() for t in ax_spec.texts if t.get_text().startswith("Chandler"))
    assert "no peak resolved" in mark
