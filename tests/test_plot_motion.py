"""What ``wobble free --plot`` and ``wobble top --plot`` draw, read back from the figures' artists and
checked against the models' own periods and angles (a visual audit found long spans drawn from too
few samples, offsets such as 1e-19 hiding the numbers, arcsec where degrees read, legends on the data).

The criteria, stated once here and in the modules' constants:

* free, time panels: at least 1000 samples per period of omega, at most the first 10 periods
  (omega repeats exactly), the title saying how many the span holds;
* free, polhode: one period, a closed curve;
* top, the axis's path: at least 200 samples per nutation period, at most 40,001 samples
  (the first 200 nutation periods past them, the title saying so);
* no offset or multiplier text on any axis; angles in deg from 1 deg, else arcsec, mas, µas.
"""

from __future__ import annotations

import math
import re

import matplotlib.pyplot as plt  # the Agg backend: tests/conftest.py sets MPLBACKEND
import mpmath
import numpy as np
import pytest
from astropy import units as u

from wobble.api.free import FreeRotation
from wobble.errors import InputError
from wobble.api.top import HeavyTop
from wobble.plot.free import motion_figure
from wobble.plot.top import axis_locus_figure, cubic_figure, effective_potential_figure

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s
MAS = math.radians(1 / 3.6e6)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _earth():
    # The help's example (wobble free --help): Earth's moments and spin, 100 yr.
    return FreeRotation([8.01012e37, 8.01032e37, 8.03652e37] * KGM2, [7.292115e-11, 0, 7.292115e-5] * RAD_S)


def _near_sleeping():
    # The help's nearly sleeping top (wobble top --help).
    return HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=1e-6 * u.rad, omega3=10 * RAD_S)


def _time_axes(fig):
    return fig.axes[0], fig.axes[1]


def _seconds_per_unit(ax) -> float:
    unit = ax.get_xlabel().split("[")[1].rstrip("]")
    return {"s": 1.0, "min": 60.0, "h": 3600.0, "d": 86400.0, "yr": 365.25 * 86400.0}[unit]


def _offsets(fig) -> list[str]:
    """Every offset or multiplier text on the figure's 2-D axes (drawn first: formatters set them then)."""
    fig.canvas.draw()
    return [
        axis.get_offset_text().get_text()
        for ax in fig.axes
        if ax.name == "rectilinear"
        for axis in (ax.xaxis, ax.yaxis)
        if axis.get_offset_text().get_text()
    ]


# -- free: the time panels ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "body, t_end",
    [
        (FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S), 20000 * u.s),  # 2,886 periods
        (_earth(), 100 * u.yr),  # 120 periods
        (FreeRotation([1, 2, 3] * KGM2, [1e-6, 1, 1e-6] * RAD_S), 20000 * u.s),  # 194 periods, 389 flips
    ],
    ids=["lab", "earth", "flips"],
)
def test_a_long_span_draws_its_first_periods_each_finely(body, t_end):
    period = body.period.to_value(u.s)
    count = t_end.to_value(u.s) / period
    fig = motion_figure(body, t_end)
    top, bottom = _time_axes(fig)
    scale = _seconds_per_unit(bottom)
    for ax in (top, bottom):
        assert ax.lines  # the loop below must have something to check
        for line in ax.lines:
            t = np.asarray(line.get_xdata()) * scale
            assert t[0] == 0 and 1 <= t[-1] / period <= 10 * (1 + 1e-12)  # one to ten periods
            assert np.max(np.diff(t)) <= period / 1000 * (1 + 1e-9)  # 1000 samples a period at least
    assert f"first 10 of {count:,.0f} periods shown" in top.get_title()


def test_a_long_span_no_longer_aliases_omega():
    # Aliasing drew 2,000 samples over 2,886 periods: omega1's swing per period was missed. Drawn now
    # over its first periods, each period's largest omega1 is the amplitude of the motion.
    body = FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    period = body.period.to_value(u.s)
    fine = body.omega(np.linspace(0, period, 100001) * u.s).to_value(RAD_S)
    fig = motion_figure(body, 20000 * u.s)
    top, _ = _time_axes(fig)
    line = next(line for line in top.lines if line.get_label() == "$\\omega_1$")
    t = np.asarray(line.get_xdata()) * _seconds_per_unit(fig.axes[1])
    w1 = np.asarray(line.get_ydata())
    for k in range(int(t[-1] / period)):
        inside = (t >= k * period) & (t < (k + 1) * period)
        assert np.max(w1[inside]) == pytest.approx(np.max(fine[:, 0]), rel=1e-4)


def test_earth_reads_without_offsets_as_fractions_of_the_spin():
    body = _earth()
    fig = motion_figure(body, 100 * u.yr)
    assert _offsets(fig) == []  # it showed 1e-11 over omega and 1e-19 over omega3 - omega3(0)
    top, bottom = _time_axes(fig)
    assert top.get_ylabel() == "$10^{-6}$ $|\\omega(0)|$"
    assert bottom.get_ylabel() == "$|\\omega(0)|$"  # omega3's change is constant to rounding: drawn flat
    spin = np.linalg.norm(body.omega0.to_value(RAD_S))
    scale = _seconds_per_unit(bottom)
    for line in top.lines:  # the numbers drawn are omega1, omega2 in units of 1e-6 |omega(0)|
        t = np.asarray(line.get_xdata()) * scale
        k = int(line.get_label()[-2]) - 1
        truth = body.omega(t * u.s).to_value(RAD_S)[:, k] / (1e-6 * spin)
        assert np.max(np.abs(line.get_ydata() - truth)) < 1e-9
        assert 0.5 < np.max(np.abs(line.get_ydata())) < 1000


def test_a_lab_body_keeps_rad_per_s():
    fig = motion_figure(FreeRotation([1, 2, 3] * KGM2, [0.1, 0, 1] * RAD_S), 20 * u.s)
    assert [ax.get_ylabel() for ax in _time_axes(fig)] == ["rad s$^{-1}$", "rad s$^{-1}$"]
    assert _offsets(fig) == []


# -- free: the polhode -----------------------------------------------------------------------------------


def _polhode(fig):
    ax = fig.axes[2]
    line = ax.lines[0]
    if ax.name == "3d":
        return ax, np.column_stack(line.get_data_3d())
    return ax, np.column_stack(line.get_data())


@pytest.mark.parametrize(
    "body, t_end",
    [
        (FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S), 20000 * u.s),  # on the sphere
        (_earth(), 100 * u.yr),  # seen down e3
        (FreeRotation([1, 2, 3] * KGM2, [1e-6, 1, 1e-6] * RAD_S), 20000 * u.s),  # flipping
    ],
    ids=["lab", "earth", "flips"],
)
def test_the_polhode_of_a_long_span_is_one_closed_curve(body, t_end):
    # It was drawn from 2,000 samples over thousands of periods: a filled patch of chords.
    fig = motion_figure(body, t_end)
    ax, points = _polhode(fig)
    extent = np.max(np.abs(points))
    assert np.max(np.abs(points[0] - points[-1])) <= 1e-9 * extent  # closed
    # Once round, not thousands of times: its length is one circuit's, from the model over one period.
    period = body.period.to_value(u.s)
    moments = body.moments.to_value(KGM2)
    L = moments * body.omega(np.linspace(0, period, 200001) * u.s).to_value(RAD_S)
    L /= np.linalg.norm(L, axis=1, keepdims=True)
    circuit = np.sum(np.linalg.norm(np.diff(L, axis=0), axis=1))
    drawn = np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1))
    if ax.name != "3d":  # seen down an axis: the drawn units (mas) back to the unit sphere's
        drawn *= {"deg": math.radians(1), "arcsec": 1e3 * MAS, "mas": MAS}[ax.get_ylabel().split("(")[1][:-1]]
    assert drawn == pytest.approx(circuit, rel=1e-3)
    assert "one period, a closed curve" in ax.get_title()


def test_a_polhode_of_three_degrees_reads_in_degrees():
    # A symmetric body's polhode is a circle at arctan(I1 w_perp / (I3 w3)) = arctan(0.05) = 2.86 deg
    # from e3; it was drawn as +-10,000 arcsec (degrees only from 3 deg).
    fig = motion_figure(FreeRotation([1, 1, 2] * KGM2, [0.1, 0, 1] * RAD_S), 20 * u.s)
    ax, points = _polhode(fig)
    assert "(deg from $e_3$)" in ax.get_xlabel() and ax.get_ylabel().endswith("(deg)")
    radius = np.hypot(points[:, 0], points[:, 1])  # each point at its angle from e3
    assert np.allclose(radius, np.degrees(np.arctan(0.05)), rtol=1e-9)


@pytest.mark.parametrize(
    "degrees, unit",
    [
        (2.0, "deg"),
        (1.01, "deg"),
        (0.99, "arcsec"),
        (1.01 / 3600, "arcsec"),
        (0.99 / 3600, "mas"),
        (0.5e-3 / 3600, "µas"),
    ],
)
def test_the_polhode_unit_is_the_largest_its_radius_reaches(degrees, unit):
    # A symmetric body [1, 1, 2] spun at w3 = 1 with w1 = 2 tan(angle): L is `degrees` from e3.
    w1 = 2 * math.tan(math.radians(degrees))
    fig = motion_figure(FreeRotation([1, 1, 2] * KGM2, [w1, 0, 1] * RAD_S), 20 * u.s)
    ax, _ = _polhode(fig)
    assert ax.get_ylabel() == f"L along $e_2$ ({unit})"
    fig.canvas.draw()
    assert ax.xaxis.get_offset_text().get_text() == ax.yaxis.get_offset_text().get_text() == ""


def test_the_polhode_of_a_long_separatrix_is_resolved():
    # The flip of a separatrix lasts seconds; over 1e5 s it was drawn from two samples (a chord).
    body = FreeRotation([2, 5, 6] * KGM2, [1, 0.3, -1] * RAD_S)
    fig = motion_figure(body, 1e5 * u.s)
    _, points = _polhode(fig)
    steps = np.degrees(np.arccos(np.clip(np.sum(points[1:] * points[:-1], axis=1), -1, 1)))
    assert np.max(steps) < 1.0  # every step under a degree on the sphere
    assert abs(points[-1, 1]) == pytest.approx(1.0, abs=1e-9)  # and it ends on the intermediate axis


# -- free: the legends -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "moments, omega, t_end",
    [
        ([1, 2, 3], [0.1, 0, 1], None),  # three periods: the last peaks were under the legend
        ([1, 2, 3], [1e-6, 1, 1e-6], 200),  # flips
        ([2, 5, 6], [1, 0.3, -1], 20),  # the separatrix
        ([8.01012e37, 8.01032e37, 8.03652e37], [7.292115e-11, 0, 7.292115e-5], 100 * 365.25 * 86400),
    ],
    ids=["wobble", "flips", "separatrix", "earth"],
)
def test_no_legend_covers_a_curve(moments, omega, t_end):
    body = FreeRotation(moments * KGM2, omega * RAD_S)
    fig = motion_figure(body, (t_end or 3 * body.period.to_value(u.s)) * u.s)
    fig.canvas.draw()
    for ax in _time_axes(fig):
        box = ax.get_legend().get_window_extent()
        assert ax.lines
        for line in ax.lines:
            xy = ax.transData.transform(np.column_stack(line.get_data()))
            inside = (xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1)
            assert not inside.any(), f"{line.get_label()} under the legend of {ax.get_ylabel()}"


# -- top: the axis's path --------------------------------------------------------------------------------


def _trace(ax):
    return np.column_stack(ax.lines[2].get_data())  # after the two turning circles


def test_a_long_span_of_loops_is_drawn_with_every_loop_resolved():
    # 4,000 samples over 1,484 nutation periods (2.7 a period): no loop could be seen.
    top = HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=30 * u.deg, phidot0=-0.3 * RAD_S, omega3=10 * RAD_S)
    period = top.nutation_period.to_value(u.s)
    fig = axis_locus_figure(top, 2000 * u.s)
    ax = fig.axes[0]
    xy = _trace(ax)
    assert xy.shape[0] <= 40001  # bounded
    assert f"first 200 of {2000 / period:,.0f} nutation periods drawn" in ax.get_title()
    assert (xy.shape[0] - 1) / 200 >= 200  # 200 samples a nutation period
    # The path drawn ends where the axis is after 200 nutation periods (the model, at that time) ...
    end = top.to_dataset(t=[200 * period] * u.s).symmetry_axis.values[0, :2]
    assert np.max(np.abs(xy[-1] - end)) < 1e-9
    # ... and no step of it jumps across the band between the turning circles.
    band = np.sin(top.model.theta_max) - np.sin(top.model.theta_min)
    assert np.max(np.linalg.norm(np.diff(xy, axis=0), axis=1)) < 0.05 * band


def test_a_short_span_is_drawn_whole_at_the_same_density():
    top = HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, phidot0=-0.3 * RAD_S, omega3=10 * RAD_S)
    t_end = 20 * u.s
    fig = axis_locus_figure(top, t_end)
    ax = fig.axes[0]
    xy = _trace(ax)
    periods = (t_end / top.nutation_period).to_value(u.one)
    assert (xy.shape[0] - 1) / periods >= 200 and "\n" not in ax.get_title()  # all of it, no note
    end = top.to_dataset(t=[20] * u.s).symmetry_axis.values[0, :2]
    assert np.max(np.abs(xy[-1] - end)) < 1e-9


def test_regular_precession_is_drawn_once_round():
    base = dict(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=40 * u.deg, omega3=10 * RAD_S)
    slow, _ = HeavyTop(**base).regular_precession_rates()
    top = HeavyTop(**base, phidot0=slow)
    assert top.nutation == "regular"
    fig = axis_locus_figure(top, 1e4 * u.s)
    xy = _trace(fig.axes[0])
    assert np.max(np.abs(xy[0] - xy[-1])) < 1e-9  # closed: one turn (the span holds 329)
    assert np.allclose(np.hypot(xy[:, 0], xy[:, 1]), np.sin(np.radians(40)), rtol=1e-9)
    assert "one turn drawn" in fig.axes[0].get_title()


def test_a_nearly_sleeping_top_reads_in_mas():
    top = _near_sleeping()
    fig = axis_locus_figure(top, 10 * top.nutation_period)
    ax = fig.axes[0]
    assert _offsets(fig) == []  # a 1e-6 multiplier sat on the title
    assert "mas from the vertical" in ax.get_xlabel() and ax.get_ylabel() == "y (horizontal, mas)"
    # theta from 1e-6 rad = 206.3 mas to theta_max, with four digits (it read 5.73e-05 to 6.251e-05 deg).
    low, high = top.model.theta_min / MAS, top.model.theta_max / MAS
    assert f"theta from {low:.4g} to {high:.4g} mas" in ax.get_title() and f"{low:.4g}" == "206.3"
    radius = np.hypot(*_trace(ax).T)  # each point at its angle from the vertical, in mas
    assert np.max(radius) == pytest.approx(high, rel=1e-3) and np.min(radius) == pytest.approx(low, rel=1e-3)


def test_a_nearly_sleeping_top_s_cubic_and_potential_read_without_offsets():
    top = _near_sleeping()
    fig = cubic_figure(top)
    assert _offsets(fig) == []  # the enlarged u axis read '1e-13+10e-1'
    whole, near = fig.axes
    assert near.get_xlabel() == "u - u2 [$10^{-15}$]"
    m = top.model
    assert whole.get_title().startswith(f"u1 = 1 - {m.x1:.4g}, u2 = 1 - {m.x2:.4g}")  # not 1.000000 twice
    roots = near.lines[1].get_xdata()  # u1 - u2 and 0, in units of 1e-15
    assert roots[0] * 1e-15 == pytest.approx(-(m.x1 - m.x2), rel=1e-12) and roots[1] == 0
    potential = effective_potential_figure(top)
    low, high = m.theta_min / MAS, m.theta_max / MAS
    assert potential.axes[0].get_title() == f"Effective potential; turning angles {low:.2f} and {high:.2f} mas"


def test_an_ordinary_top_s_figures_keep_their_units():
    top = HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
    locus = axis_locus_figure(top, 10 * top.nutation_period)
    assert locus.axes[0].get_xlabel() == "x (horizontal)" and " deg, 0 to " in locus.axes[0].get_title()
    cubic = cubic_figure(top)
    assert cubic.axes[1].get_xlabel() == "u = cos(theta)"
    for fig in (locus, cubic, effective_potential_figure(top)):
        assert _offsets(fig) == []


def test_a_top_hanging_nearly_straight_down_is_titled_from_below():
    """theta from 179.999 to 179.9991 deg was titled '180 to 180 deg'; it is measured from below now."""
    top = HeavyTop(
        I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=(180 - 1e-3) * u.deg, omega3=10 * u.rad / u.s
    )
    title = axis_locus_figure(top, 5 * u.s).axes[0].get_title()
    below = (np.pi - top.model.theta_max, np.pi - top.model.theta_min)
    arcsec = math.radians(1 / 3600)
    assert f"180 deg minus {below[0] / arcsec:.4g} to {below[1] / arcsec:.4g} arcsec" in title


def test_the_top_s_axis_path_is_drawn_from_the_model_without_xarray_and_refuses_too_many_samples():
    """The path was taken from a Dataset (xarray imported: 0.9 s of a 3-s `wobble top --plot`); with the
    long-span sampling, a huge ``samples`` went to np.linspace unchecked (a MemoryError, not a message)."""
    import subprocess
    import sys

    from wobble.errors import InputError

    top = HeavyTop(
        I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=30 * u.deg, omega3=10 * u.rad / u.s
    )
    with pytest.raises(InputError, match=r"^samples: got 1000000000000; allowed: at most \d+ samples here"):
        axis_locus_figure(top, 5 * u.s, samples=10**12)
    body = FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)
    with pytest.raises(InputError, match=r"^samples: got 1000000000000; allowed: at most \d+ samples here"):
        motion_figure(body, 5 * u.s, samples=10**12)
    from wobble.plot.free import polhode_figure

    for bad in (10**12, 1, 2.5):
        with pytest.raises(InputError, match="^samples: got"):
            polhode_figure([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s, samples=bad)
    code = (
        "import sys; from astropy import units as u; import wobble; from wobble.plot.top import axis_locus_figure; "
        "t = wobble.HeavyTop(I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=30 * u.deg, "
        "omega3=10 * u.rad / u.s); axis_locus_figure(t, 5 * u.s); print('xarray' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


def test_flips_are_counted_without_listing_them():
    """`wobble free ... --t-end 1e13` listed every flip (1.9e11 of them, 1.4 TB) to count them for its JSON and
    its figure's title; flip_count counts them, and agrees with the list wherever the list fits, its ends
    placed on flips, between them and before the first."""
    body = FreeRotation([1, 2, 3] * u.kg * u.m**2, [1e-6, 1, 1e-6] * u.rad / u.s)
    listed = body.flip_times(2000 * u.s).to_value(u.s)
    gap = body.model.time_between_flips
    spans = [(0.0, 2000.0), (0.0, listed[0] / 2), (listed[3], listed[9]), (listed[3] + gap / 3, listed[9] - gap / 3)]
    spans += [(listed[5], listed[5]), (-listed[4], listed[2])]
    for t0, t1 in spans:
        expected = body.flip_times(t1 * u.s, t0 * u.s).size
        assert body.flip_count(t1 * u.s, t0 * u.s) == expected, (t0, t1)
    assert body.flip_count(1e13 * u.s) == pytest.approx(1e13 / gap, abs=2)
    assert FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s).flip_count(1e13 * u.s) == 0


def test_a_top_hanging_straight_down_is_a_point_not_rings_of_rounding():
    """At theta = pi, sin(theta) is 1.2e-16: taken as a tilt, it drew rings of 2.5e-5 micro-arcseconds under
    a '1e-5' offset text."""
    top = HeavyTop(
        I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=180 * u.deg, omega3=10 * u.rad / u.s
    )
    fig = axis_locus_figure(top, 5 * u.s)
    fig.canvas.draw()
    ax = fig.axes[0]
    assert "180 deg (straight down)" in ax.get_title()
    assert ax.xaxis.get_offset_text().get_text() == "" == ax.yaxis.get_offset_text().get_text()
    assert "µas" not in ax.get_xlabel()


def test_the_flip_figure_of_a_long_span_draws_its_first_periods_densely():
    """flip_figure drew 4,001 samples over any span (5e-5 of a sample per flip over 1e7 s) and listed every
    flip to mark them; it now draws the first periods as motion_figure does, and counts the span's flips."""
    from wobble.plot.free import MAX_PERIODS_SHOWN, SAMPLES_PER_PERIOD, flip_figure

    moments, omega0 = [1, 2, 3] * u.kg * u.m**2, [1e-6, 1, 1e-6] * u.rad / u.s
    body = FreeRotation(moments, omega0)
    period = body.period.to_value(u.s)
    fig = flip_figure(moments, omega0, 1e7 * u.s)
    ax = fig.axes[0]
    t = ax.get_lines()[0].get_xdata()
    assert (
        t[-1] == pytest.approx(MAX_PERIODS_SHOWN * period) and np.max(np.diff(t)) <= period / SAMPLES_PER_PERIOD * 1.01
    )
    assert f"{body.flip_count(1e7 * u.s):,} flips in the span" in ax.get_title()
    fig.canvas.draw()
    assert ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1  # beside the axes
    plt.close(fig)


def test_first_periods_cuts_a_long_span_to_its_first_periods_and_says_how_many():
    from wobble.plot._sampling import first_periods, period_count

    times, count = first_periods(10.0, 1.0, 3, 4)  # ten periods, three shown, four samples each
    np.testing.assert_array_equal(times, np.linspace(0.0, 3.0, 13))
    assert count == 10.0
    times, count = first_periods(2.5, 1.0, 3, 4, least=2)  # the whole span: nothing to say
    np.testing.assert_array_equal(times, np.linspace(0.0, 2.5, 11))
    assert count is None
    assert first_periods(0.1, 1.0, 3, 4, least=50)[0].size == 50  # at least ``least`` samples
    # A span of exactly ``most`` periods in floats (3 * 0.1 / 0.1 = 3.0000000000000004) is not cut: the title
    # read "first 3 of 3 periods".
    period = 0.1
    assert 3 * period / period > 3 and first_periods(3 * period, period, 3, 4)[1] is None
    assert [period_count(c) for c in (12345.6, 99.94, 3.0)] == ["12,346", "99.9", "3"]


_TOP = dict(I1=5e-4, I3=1e-4, mgl=0.1, theta0=math.radians(30), omega3=200.0)  # SI; started at rest in theta


def _slow_regular_rate() -> float:
    """The slow steady precession rate at theta0, at 50 digits from the inputs: f(u0) = f'(u0) = 0 with
    thetadot = 0 gives I1 cos theta phidot^2 - I3 omega3 phidot + M g l = 0 (Goldstein, Poole & Safko 2002,
    sec. 5.7), phidot = [I3 omega3 - sqrt(I3^2 omega3^2 - 4 I1 M g l cos theta)] / (2 I1 cos theta)."""
    with mpmath.workdps(50):
        i1, i3, mgl, w3 = (mpmath.mpf(_TOP[k]) for k in ("I1", "I3", "mgl", "omega3"))
        c = mpmath.cos(mpmath.mpf(_TOP["theta0"]))
        return float((i3 * w3 - mpmath.sqrt((i3 * w3) ** 2 - 4 * i1 * mgl * c)) / (2 * i1 * c))


def _regular_precession(relative_offset: float = 0.0):
    t = _TOP
    return HeavyTop(
        I1=t["I1"] * KGM2,
        I3=t["I3"] * KGM2,
        mgl=t["mgl"] * u.J,
        theta0=t["theta0"] * u.rad,
        omega3=t["omega3"] * RAD_S,
        phidot0=_slow_regular_rate() * (1 + relative_offset) * RAD_S,
    )


def _goldstein_cubic(phidot0: float):
    """f(u) = (1 - u^2)(alpha - beta u) - (b - a u)^2 of the top _TOP started with phidot0 (Goldstein, Poole &
    Safko 2002, sec. 5.7; notes p. 71), at 50 digits from the float inputs: a = I3 omega3 / I1, b = a cos theta0 +
    phidot0 sin^2 theta0, alpha = phidot0^2 sin^2 theta0 + beta cos theta0, beta = 2 M g l / I1. Returns f (of an
    mpf) and its roots u1 < u2 < u3 by mpmath.polyroots, as mpf (at 50 digits, the turning points 1e-10 apart
    keep 30 digits of their difference)."""
    mp = mpmath.mpf
    with mpmath.workdps(50):
        a, beta = mp(_TOP["I3"]) * mp(_TOP["omega3"]) / mp(_TOP["I1"]), 2 * mp(_TOP["mgl"]) / mp(_TOP["I1"])
        c, s = mpmath.cos(mp(_TOP["theta0"])), mpmath.sin(mp(_TOP["theta0"]))
        b = a * c + mp(phidot0) * s**2
        alpha = (mp(phidot0) * s) ** 2 + beta * c
        roots, error = mpmath.polyroots(
            [alpha - b * b, 2 * a * b - beta, -(alpha + a * a), beta], maxsteps=200, extraprec=200, error=True, asc=True
        )
        assert error < mp(10) ** -40 and all(abs(mpmath.im(r)) < mp(10) ** -40 for r in roots)
        roots = sorted(mpmath.re(r) for r in roots)

    def f(x):
        with mpmath.workdps(50):
            return (1 - x**2) * (alpha - beta * x) - (b - a * x) ** 2

    return f, roots


def test_a_regular_precession_s_cubic_draws_its_double_root_not_rounding():
    """At u1 = u2 the zoom spanned 1e-12 of u, where f expanded in floats is rounding alone: it drew
    2e-14 s^-2 of noise under 'the motion: f >= 0'. It now draws the double root's parabola."""
    top = _regular_precession()
    m = top.model
    near = cubic_figure(top).axes[1]
    assert near.get_title() == "u1 = u2: a double root, regular precession"
    assert [t.get_text() for t in near.get_legend().get_texts()] == ["the motion: u = u2 (theta constant)"]
    u, f = (np.asarray(v) for v in near.lines[0].get_data())
    # At this scale (a twentieth of the way to u3) the expanded cubic is exact to 1e-13 of it: the two agree.
    np.testing.assert_allclose(f, m.f(u), rtol=0, atol=1e-9 * np.ptp(f))
    assert np.max(f) <= 1e-12 * np.ptp(f)  # touching zero from below at u2, nowhere above


@pytest.mark.parametrize("offset", [1e-9, 1e-6])
def test_a_nearly_regular_precession_s_hump_is_drawn_however_narrow(offset):
    """Turning points 9.4e-11 apart in u (phidot 1e-9 off the regular rate) bound a hump of 2e-18 s^-2,
    far below the expanded cubic's 2e-14 of rounding: drawn from the roots, it is above zero exactly between
    them and below outside, and it is Goldstein's f(u) formed at 50 digits from the top's inputs, whose roots
    (mpmath.polyroots) set the window: measured, 8e-7 of the hump at 1e-9 (the float roots' rounding of the
    width, 1.6e-7 of it), 4e-10 at 1e-6."""
    top = _regular_precession(offset)
    f_exact, (u1, u2, u3) = _goldstein_cubic(top.model.phidot0)
    assert top.model.phidot0 == _slow_regular_rate() * (1 + offset)
    assert top.model.regular_precession_rates()[0] == pytest.approx(_slow_regular_rate(), rel=1e-15)
    fig = cubic_figure(top)
    whole, near = fig.axes
    assert near.get_title() == "between the turning points"
    assert [t.get_text() for t in near.get_legend().get_texts()] == ["the motion: f >= 0"]
    # The roots marked on the whole cubic: the exact ones, to the last bit of a float.
    np.testing.assert_allclose(whole.lines[1].get_xdata(), [float(r) for r in (u1, u2, u3)], rtol=2.3e-16, atol=0)
    xscale = int(re.search(r"10\^\{(-?\d+)\}", near.get_xlabel()).group(1))
    fscale = 10.0 ** int(re.search(r"10\^\{(-?\d+)\}", near.get_ylabel()).group(1))
    drawn_d, f = (np.asarray(v) for v in near.lines[0].get_data())
    width = float(u2 - u1)  # the exact turning points, not the model's
    assert 0 < width < 1e-3
    np.testing.assert_allclose(near.lines[1].get_xdata(), [-width / 10.0**xscale, 0.0], rtol=1e-6, atol=0)
    d = drawn_d * 10.0**xscale
    inside = (d > -width * (1 - 1e-6)) & (d < -width * 1e-6)
    outside = (d < -width * (1 + 1e-6)) | (d > width * 1e-6)
    assert inside.any() and outside.any() and np.all(f[inside] > 0) and np.all(f[outside] < 0)
    # The hump itself: f at u = u2 + d, u2 the exact upper turning point.
    truth = np.array([float(f_exact(u2 + mpmath.mpf(float(x)) * mpmath.mpf(10) ** xscale)) for x in drawn_d])
    np.testing.assert_allclose(f * fscale, truth, rtol=0, atol=5e-6 * np.max(truth))


def test_a_nearly_sleeping_top_s_potential_well_is_drawn_between_its_turning_angles():
    """Turning angles of 206 and 225 mas could not be seen on 0-180 deg: a second panel draws the well."""
    top = _near_sleeping()
    m = top.model
    fig = effective_potential_figure(top)
    assert len(fig.axes) == 2 and _offsets(fig) == []
    well = fig.axes[1]
    assert well.get_xlabel() == "theta [mas]" and well.get_ylabel() == "V' - E' [$10^{-15}$ J]"
    theta_mas, drawn = (np.asarray(v) for v in well.lines[0].get_data())
    # mpmath at 50 digits from the inputs (I1 = 1, I3 = 0.5 kg m2, M g l = 1 J, theta0 = 1e-6 rad, omega3 =
    # 10 rad/s, started at rest in theta and phi): a = I3 omega3 / I1, b = a cos theta0, E' = M g l cos theta0,
    # so V' - E' = M g l (cos theta - cos theta0) + (I1/2) a^2 (cos theta0 - cos theta)^2 / sin^2 theta (notes p. 71).
    assert m.b == pytest.approx(m.a * math.cos(1e-6), rel=1e-15)  # the top starts at rest in theta and phi
    with mpmath.workdps(50):
        a, c0 = mpmath.mpf(5), mpmath.cos(mpmath.mpf("1e-6"))

        def exact(theta):
            c = mpmath.cos(mpmath.mpf(float(theta)))
            return float((c - c0) + mpmath.mpf(0.5) * a**2 * (c0 - c) ** 2 / (1 - c**2))

        truth = np.array([exact(t * MAS) for t in theta_mas])
    depth = np.max(np.abs(truth))
    np.testing.assert_allclose(drawn * 1e-15, truth, rtol=0, atol=1e-6 * depth)
    # Below zero exactly between the turning angles.
    inside = (theta_mas * MAS > m.theta_min * (1 + 1e-6)) & (theta_mas * MAS < m.theta_max * (1 - 1e-6))
    outside = (theta_mas * MAS < m.theta_min * (1 - 1e-6)) | (theta_mas * MAS > m.theta_max * (1 + 1e-6))
    assert inside.any() and outside.any() and np.all(drawn[inside] < 0) and np.all(drawn[outside] > 0)


def test_an_ordinary_top_s_potential_is_one_panel():
    top = HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
    assert len(effective_potential_figure(top).axes) == 1


def test_a_symmetric_body_s_constant_spin_says_why_its_panel_is_flat():
    """omega_3 of a body symmetric about axis 3 is exactly constant (Euler: (I1 - I2) w1 w2 = 0): the panel
    of its change was a flat zero line without a word."""
    body = FreeRotation([2, 2, 3] * KGM2, [0.1, 0, 1] * RAD_S)
    fig = motion_figure(body, 30 * u.s)
    texts = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert "$\\omega_3 - \\omega_3(0)$ = 0: constant (a symmetric body)\n$\\omega_3(0)$ = 1.00000 rad s$^{-1}$" in texts


def test_earth_s_spin_is_drawn_flat_with_its_measured_spread_not_as_a_staircase_of_rounding():
    """The Earth's omega_3 = A_3 dn(u | m) moves by 1 - sqrt(1 - m) = m/2 = 3.8e-15 of itself (m = 7.6e-15; Landau
    & Lifshitz sec. 37): 20 float steps of 1.9e-16, drawn as a staircase of 21 levels. Within the scene figure's
    rounding (1e-12 of |omega|) it is drawn flat, the spread measured and the start named."""
    body = _earth()
    fig = motion_figure(body, 100 * u.yr)
    _, bottom = _time_axes(fig)
    (line,) = bottom.lines
    assert np.all(np.asarray(line.get_ydata()) == 0)  # one level, no staircase (21 before)
    period = body.period.to_value(u.s)
    w3 = body.omega(np.linspace(0, period, 10001) * u.s).to_value(RAD_S)[:, 2]
    assert np.ptp(w3) / w3[0] == pytest.approx(body.parameter / 2, rel=0.05)  # the closed form's swing
    (text,) = [t.get_text() for t in bottom.get_legend().get_texts()]
    assert text.startswith("$\\omega_3 - \\omega_3(0)$ drawn as 0:\nconstant to 4e-15 of itself")
    start = re.fullmatch(r"(?s).*\n\$\\omega_3\(0\)\$ = ([\d.]+) \$10\^\{-6\}\$ rad s\$\^\{-1\}\$", text)
    assert start and float(start.group(1)) * 1e-6 == pytest.approx(w3[0], abs=0.5e-4 * 1e-6)  # six digits


def test_a_spin_changing_by_under_5_percent_is_drawn_as_its_change_with_its_start_named():
    """The scene figure's rule: [1, 2, 3] kg m2 spun at (0.1, 0, 1) rad/s has omega_3 swing by 0.17 % of itself,
    drawn before on an axis from 0.998 to 1 with no start named; now its change from the start."""
    body = FreeRotation([1, 2, 3] * KGM2, [0.1, 0, 1] * RAD_S)
    fig = motion_figure(body, 20 * u.s)
    _, bottom = _time_axes(fig)
    (line,) = bottom.lines
    t = np.asarray(line.get_xdata()) * _seconds_per_unit(bottom)
    w3 = body.omega(t * u.s).to_value(RAD_S)[:, 2]
    assert 1e-3 < np.ptp(w3) < 0.05  # under the 5 % of the rule, over the 1e-3 the figure had used
    np.testing.assert_allclose(line.get_ydata(), w3 - w3[0], rtol=0, atol=1e-15)
    assert bottom.get_ylabel() == "rad s$^{-1}$"
    (text,) = [t.get_text() for t in bottom.get_legend().get_texts()]
    assert text == "$\\omega_3 - \\omega_3(0)$\n$\\omega_3(0)$ = 1.00000 rad s$^{-1}$"


def test_a_real_wobble_of_the_largest_component_is_drawn_as_it_is():
    # omega_2 of [1, 2, 3] kg m2 spun at (1, 0.1, 1) rad/s swings from -1 to 1 rad/s: neither a change nor flat.
    body = FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    fig = motion_figure(body, 60 * u.s)
    _, bottom = _time_axes(fig)
    (line,) = bottom.lines
    t = np.asarray(line.get_xdata()) * _seconds_per_unit(bottom)
    np.testing.assert_array_equal(line.get_ydata(), body.omega(t * u.s).to_value(RAD_S)[:, 1])
    assert [t.get_text() for t in bottom.get_legend().get_texts()] == ["$\\omega_2$"]


def test_a_top_through_the_vertical_draws_its_well_without_a_zero_division():
    """theta_min = 0 (started at the vertical with a small thetadot): V' - E' is 0/0 at theta = 0, and the
    panel's grid started there (a RuntimeWarning, an error in the tests)."""
    top = HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=0 * u.rad, omega3=10 * RAD_S, thetadot0=1e-3 * RAD_S)
    assert top.model.theta_min == 0.0
    fig = effective_potential_figure(top)
    theta, drawn = (np.asarray(v) for v in fig.axes[1].lines[0].get_data())
    assert len(fig.axes) == 2 and np.all(np.isfinite(drawn))
    assert fig.axes[1].get_xlabel() == "theta [arcsec]"  # theta_max = 4.4e-4 rad = 90 arcsec
    scale = 10.0 ** int(re.search(r"10\^\{(-?\d+)\}", fig.axes[1].get_ylabel()).group(1))
    # mpmath at 50 digits from the inputs: a = I3 omega3 / I1 = 5 = b (started at the vertical),
    # E' = M g l + I1 thetadot0^2 / 2, V' - E' = cos theta - E' + (a^2/2)(1 - cos theta)^2 / sin^2 theta.
    with mpmath.workdps(50):
        e_prime = 1 + mpmath.mpf("1e-3") ** 2 / 2

        def exact(t):
            c = mpmath.cos(mpmath.mpf(float(t)) * mpmath.pi / (180 * 3600))
            return float(c - e_prime + mpmath.mpf(25) / 2 * (1 - c) ** 2 / (1 - c**2))

        truth = np.array([exact(t) for t in theta])
    np.testing.assert_allclose(drawn * scale, truth, rtol=0, atol=1e-9 * np.max(np.abs(truth)))


def test_the_time_axis_speaks_the_unit_the_span_was_given_in(tmp_path, capsys, monkeypatch):
    """--t-end 200 is in seconds, and so is the figure (its axis read 0 to 3.5 min beside flip times and a
    span printed in s); '3.5 minutes' draws minutes; without a unit given, the unit a person would use."""
    from cli_run import run_cli

    body = FreeRotation([1, 2, 3] * KGM2, [1e-6, 1, 1e-6] * RAD_S)
    for unit, label in [(None, "time [min]"), (u.s, "time [s]"), ("d", "time [d]")]:
        fig = motion_figure(body, 200 * u.s, time_unit=unit)
        top, bottom = _time_axes(fig)
        assert bottom.get_xlabel() == label
        # The flips the model gives are drawn where they fall on that axis (the first near 26.87 s).
        first = body.flip_times(200 * u.s)[0].to_value(u.s) / _seconds_per_unit(bottom)
        marks = [seg[0, 0] for coll in bottom.collections for seg in coll.get_segments()]
        assert min(abs(x - first) for x in marks) < 1e-9 * first
        plt.close(fig)
    with pytest.raises(InputError, match="time_unit"):
        motion_figure(body, 200 * u.s, time_unit=u.m)
    import wobble.plot.save

    labels, save = [], wobble.plot.save.save_figure
    monkeypatch.setattr(
        wobble.plot.save,
        "save_figure",
        lambda fig, *a, **k: (labels.append(fig.axes[1].get_xlabel()), save(fig, *a, **k))[1],
    )
    argv = ["free", "--inertia", "1", "2", "3", "--omega", "1e-6", "1", "1e-6", "--plot"]
    for t_end in ("200", "3.5 minutes"):
        code, _, err = run_cli([*argv, str(tmp_path / "f.png"), "--overwrite", "--t-end", t_end], capsys)
        assert code == 0, err
    assert labels == ["time [s]", "time [min]"]
