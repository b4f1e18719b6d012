"""The scene figure (wobble run --plot): what its panels draw, checked against the Dataset and the physics.

Sampling: a panel whose samples cannot resolve the fastest motion its quantities can carry is drawn
with markers and a note, never as lines through an alias; the rates come from closed forms here (the
Euler frequency (C - A)/A omega_3 of a symmetric body, a spin), never from the figure's own output.
"""

from __future__ import annotations

import math
import tomllib

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

import wobble
from wobble.io.scene_file import example_scene_path, read_scene
from wobble.plot.scene import scene_figure

ARCSEC = math.pi / 648_000


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _shipped(name: str, **time) -> dict:
    """A shipped scene's mapping, with its [time] table replaced when ``time`` is given."""
    with open(example_scene_path(name), "rb") as fh:
        scene = tomllib.load(fh)
    if time:
        scene["time"] = time
    return scene


def _panels(fig) -> dict:
    """Title -> axes of each panel."""
    return {ax.get_title(): ax for ax in fig.axes if ax.get_title()}


def _panel(fig, start: str):
    found = [ax for title, ax in _panels(fig).items() if title.startswith(start)]
    assert len(found) == 1, f"one panel titled {start!r}...: {list(_panels(fig))}"
    return found[0]


def _notes(ax) -> list[str]:
    return [t.get_text() for t in ax.texts if "not resolved" in t.get_text()]


def _curves(ax) -> list:
    """The lines that draw data (not the legend-only entries)."""
    return [line for line in ax.get_lines() if np.size(line.get_xdata()) > 0]


def _as_lines(ax) -> bool:
    curves = _curves(ax)
    assert curves
    return all(line.get_linestyle() not in ("None", "none", " ", "") for line in curves)


def _as_markers(ax) -> bool:
    curves = _curves(ax)
    assert curves
    return all(
        line.get_linestyle() in ("None", "none", " ", "") and line.get_marker() not in (None, "None", "", " ")
        for line in curves
    )


# --------------------------------------------------------------------------
# Sampling: no line through an alias
# --------------------------------------------------------------------------
def _symmetric_wobble(gap: float, samples: int) -> dict:
    """A free symmetric body, A = B = 1, C = 2 kg m2, omega_3 = 1 rad/s: omega_1, omega_2 turn in the body
    at the Euler frequency (C - A)/A omega_3 = 1 rad/s (Landau & Lifshitz, Mechanics, sec. 33)."""
    return {
        "schema": "wobble-scene/1",
        "accuracy": 1e-10,
        "outputs": ["omega"],
        "body": {"moments": {"value": [1.0, 1.0, 2.0], "unit": "kg m2"}},
        "initial": {"omega": {"value": [0.1, 0.0, 1.0], "unit": "rad/s"}},
        "time": {"stop": f"{gap * (samples - 1)} s", "samples": samples},
    }


def test_a_free_wobble_sampled_too_sparsely_is_drawn_with_markers_and_a_note():
    rate = (2.0 - 1.0) / 1.0 * 1.0  # (C - A)/A omega_3, rad/s
    # 6 s apart, 6 rad a sample: the samples are those of a wave turning -0.28 rad a sample, a
    # smooth 22 s alias of the 6.28 s motion.
    sparse = scene_figure(wobble.run(_symmetric_wobble(6.0, 11)))
    ax = _panel(sparse, "angular velocity")
    assert _as_markers(ax)
    (text,) = _notes(ax)
    assert text.startswith("samples 6 s apart") and f"~{2 * math.pi / rate:.3g} s" in text
    # Four samples a period is where lines begin: 1.4 rad a sample draws lines, 1.7 rad markers.
    assert rate * 1.4 < math.pi / 2 < rate * 1.7
    dense = _panel(scene_figure(wobble.run(_symmetric_wobble(1.4, 51))), "angular velocity")
    assert _as_lines(dense) and _notes(dense) == []
    coarse = _panel(scene_figure(wobble.run(_symmetric_wobble(1.7, 51))), "angular velocity")
    assert _as_markers(coarse) and len(_notes(coarse)) == 1


def test_a_fast_spinner_s_small_wobble_is_not_taken_for_rounding():
    """The rounding threshold compared |omega across the axis|^2 with the square of |omega|^2 (rad^4/s^4): at a
    spin of 1e4 rad/s a 0.05 rad/s wobble (5e-6 of the spin) counted as rounding, rate 0, and its alias was
    drawn as lines. The Euler frequency (C - A)/A omega_3 = 1e4 rad/s against samples 0.6 ms apart (6 rad a
    sample) must give markers and a note."""
    scene = _symmetric_wobble(6e-4, 11)
    scene["initial"]["omega"]["value"] = [0.05, 0.0, 1e4]
    ax = _panel(scene_figure(wobble.run(scene)), "angular velocity")
    assert _as_markers(ax) and len(_notes(ax)) == 1


def test_a_body_at_rest_draws_without_a_warning():
    """Its wobble angle's rate divided 0 by |omega|^2 = 0 outside the error state: a RuntimeWarning."""
    scene = _symmetric_wobble(1.0, 11)
    scene["initial"]["omega"]["value"] = [0.0, 0.0, 0.0]
    scene["outputs"] = ["omega", "wobble_angle"]
    scene_figure(wobble.run(scene))  # warnings are errors in the tests


def _spinning(times, spin: float) -> xr.Dataset:
    """A hand-made Dataset (no record of its body): omega_1, omega_2 turning at the spin, as a gyroscope's."""
    t = np.asarray(times, dtype=float)
    omega = np.stack([0.1 * np.cos(spin * t), 0.1 * np.sin(spin * t), np.full(t.size, spin)], axis=-1)
    return xr.Dataset(
        {"omega": (("time", "axis"), omega, {"units": "rad s-1"})}, coords={"time": ("time", t, {"units": "s"})}
    )


def test_a_dataset_without_its_body_is_checked_against_twice_its_spin():
    # Without the body the figure cannot rule torques out: a torque from a field fixed in space turns
    # at the spin as the body sees it (quadratic fields at twice it), so the rate is 2 |omega|.
    spin = 10.0
    rate = 2 * math.hypot(spin, 0.1)
    fine = _panel(scene_figure(_spinning(np.arange(0, 10, 0.05), spin)), "angular velocity")
    assert 0.05 * rate < math.pi / 2 and _as_lines(fine) and _notes(fine) == []
    coarse = _panel(scene_figure(_spinning(np.arange(0, 10, 0.2), spin)), "angular velocity")
    assert _as_markers(coarse)
    (text,) = _notes(coarse)
    assert text.startswith("samples 0.2 s apart") and f"~{2 * math.pi / rate:.3g} s" in text


def test_thinning_a_long_file_is_checked_at_the_spacing_drawn():
    # 100,001 samples 0.05 s apart resolve the spin; the figure draws one in three (at most 50,000
    # points), 0.15 s apart, which does not: it says so instead of drawing the alias.
    spin = 10.0
    fig = scene_figure(_spinning(np.arange(100_001) * 0.05, spin))
    ax = _panel(fig, "angular velocity")
    assert _as_markers(ax)
    (text,) = _notes(ax)
    assert text.startswith("samples 0.15 s apart (one in 3 drawn)")


def _gyroscope_precession() -> tuple[float, float, float]:
    """(phi_dot, theta, psi_dot) of the shipped gyroscope: its initial rates, checked against the steady
    precession of the heavy symmetric top, phi_dot = [I3 w3 - sqrt(I3^2 w3^2 - 4 I1 M g l cos theta)] /
    (2 I1 cos theta) (Goldstein, Poole & Safko 2002, eq. 5.73 with theta_dot = 0); the file's I1 is about the
    pivot already (m r^2/4 + m l^2, its description says)."""
    scene = _shipped("gyroscope")
    phi_dot, _, psi_dot = scene["initial"]["euler_rates"]["value"]
    theta = math.radians(scene["initial"]["euler_angles"]["value"][1])
    i1, _, i3 = scene["body"]["moments"]["value"]
    mass, lever, g = 0.1, scene["torques"][0]["center_of_mass"]["value"][2], 9.80665
    w3 = psi_dot + phi_dot * math.cos(theta)
    c = math.cos(theta)
    steady = (i3 * w3 - math.sqrt((i3 * w3) ** 2 - 4 * i1 * mass * g * lever * c)) / (2 * i1 * c)
    assert phi_dot == pytest.approx(steady, rel=1e-9)
    return phi_dot, theta, psi_dot


def test_the_gyroscope_sampled_as_it_was_says_its_omega_panel_is_not_resolved():
    # 101 samples over 1 s drew a smooth 4.5 Hz wave; omega_1, omega_2 turn at the spin, ~600 rad/s.
    scene = _shipped("gyroscope", stop="1 s", samples=101)
    phi_dot, theta, psi_dot = _gyroscope_precession()
    spin = math.hypot(psi_dot + phi_dot * math.cos(theta), phi_dot * math.sin(theta))  # |omega|
    fig = scene_figure(wobble.run(scene))
    omega = _panel(fig, "angular velocity")
    assert _as_markers(omega)
    (text,) = _notes(omega)
    assert text.startswith("samples 0.01 s apart") and f"~{2 * math.pi / (2 * spin):.3g} s" in text
    # The axis turns at 1.46 rad/s: its panels are resolved (the torque of a symmetric top depends on
    # its attitude through its axis only, so its energy too).
    for title in ("energy", "figure axis", "tilt"):
        ax = _panel(fig, title)
        assert _as_lines(ax) and _notes(ax) == [], title


def test_the_satellite_sampled_as_it_was_says_no_panel_is_resolved():
    # 49 samples over an orbit, 118 s apart: omega_1 turns in 19.7 s, the energy the gravity gradient
    # trades (B != A) at twice the spin, period pi s.
    fig = scene_figure(wobble.run(_shipped("satellite_gravity_gradient", stop="5677 s", samples=49)))
    for title in ("angular velocity", "angular momentum", "energy"):
        ax = _panel(fig, title)
        assert _as_markers(ax), title
        (text,) = _notes(ax)
        assert text.startswith("samples 118 s apart") and "~3.14 s" in text


# --------------------------------------------------------------------------
# The figure axis: precession and tilt, in the unit the panel names
# --------------------------------------------------------------------------
_UNITS = {"deg": math.pi / 180, "arcsec": ARCSEC, "mas": ARCSEC / 1000}


def _offset_text(fig, ax) -> str:
    fig.canvas.draw()
    return ax.yaxis.get_offset_text().get_text()


@pytest.fixture(scope="module")
def earth_precession():
    return wobble.run("earth_precession")


def test_the_axis_panels_draw_the_precession_and_nutation_of_earth_in_arcsec(earth_precession):
    ds = earth_precession
    fig = scene_figure(ds)
    e3 = ds["axis_direction"].values
    # The axis's azimuth about the ecliptic pole (inertial z) from its start, by hand, in arcsec.
    azimuth = np.unwrap(np.arctan2(e3[:, 1], e3[:, 0]))
    axis = _panel(fig, "figure axis")
    assert axis.get_ylabel() == "arcsec" and _notes(axis) == []
    (line,) = _curves(axis)
    np.testing.assert_allclose(line.get_ydata(), (azimuth - azimuth[0]) / ARCSEC, rtol=0, atol=1e-9)
    # 20 years at the model's analytic rate, -5040.038 arcsec per century (the scene's description),
    # within the nutation in longitude (17.2 arcsec amplitude).
    assert abs(line.get_ydata()[-1] - (-5040.038 * 20 / 100)) < 20
    # The tilt from the ecliptic pole: the obliquity, 84381.406 arcsec at the start, nutating.
    tilt = _panel(fig, "tilt")
    assert tilt.get_ylabel() == "arcsec" and _offset_text(fig, tilt) == ""
    (line,) = _curves(tilt)
    np.testing.assert_allclose(line.get_ydata(), np.arccos(e3[:, 2]) / ARCSEC, rtol=0, atol=1e-6)
    assert line.get_ydata()[0] == pytest.approx(84381.406, abs=1e-6)
    assert 15 < np.ptp(line.get_ydata()) < 25  # 2 x 9.2 arcsec of the 18.6-year term, and the short terms


def test_earth_s_angular_momentum_is_drawn_as_its_change_from_the_start(earth_precession):
    """The Sun's and Moon's torques turn L by 5e-3 rad in 20 years: on an axis spanning L that drew three
    flat lines under a '1e33'. The change is drawn, in a named power of ten, the start in the title."""
    ds = earth_precession
    fig = scene_figure(ds)
    L = ds["angular_momentum"].values
    panel = _panel(fig, "angular momentum, inertial frame: change from the start, (")
    assert panel.get_ylabel() == "$10^{30}$ kg m$^{2}$ s$^{-1}$" and _offset_text(fig, panel) == ""
    start = panel.get_title().split("(")[1].split(")")[0].split(", ")
    np.testing.assert_allclose([float(v) * 1e33 for v in start], L[0], rtol=0, atol=1e-5 * 1e33)
    curves = _curves(panel)
    assert len(curves) == 3
    for k, line in enumerate(curves):
        np.testing.assert_allclose(line.get_ydata(), (L[:, k] - L[0, k]) / 1e30, rtol=0, atol=1e-9)
    # L turns with the figure axis about the ecliptic pole: (0, L_h, L_z) by psi gives L_X = -L_h sin(psi).
    e3 = ds["axis_direction"].values
    psi = np.unwrap(np.arctan2(e3[:, 1], e3[:, 0]))
    psi -= psi[0]
    assert L[-1, 0] - L[0, 0] == pytest.approx(-np.hypot(L[0, 0], L[0, 1]) * np.sin(psi[-1]), rel=1e-3)


def test_a_free_body_s_constant_momentum_is_drawn_as_it_is_not_its_rounding():
    fig = scene_figure(wobble.run("tennis_racket"))
    panel = _panel(fig, "angular momentum")
    assert panel.get_title() == "angular momentum, inertial frame" and _offset_text(fig, panel) == ""
    energy = _panel(fig, "energy")
    assert _offset_text(fig, energy) == "" and energy.get_ylabel().startswith("relative change")
    # Conserved to rounding: said, and drawn flat (its last bits looked like data).
    (label,) = [t.get_text() for t in energy.get_legend().get_texts()]
    assert label.startswith("kinetic energy: constant to rounding (|change| <= ")
    flat = _curves(energy)
    assert len(flat) == 1 and np.all(flat[0].get_ydata() == 0)
    # A component named constant says how constant, as measured (it said "to 1e-3", the naming threshold).
    named = [t.get_text() for t in panel.get_legend().get_texts() if "constant" in t.get_text()]
    assert len(named) == 1 and "constant to 1e-3" not in named[0]


def _is_rate(text: str) -> bool:
    return text.startswith(("straight-line rate", "mean rate"))


def test_earth_s_precession_rate_in_the_legend_is_the_measured_one():
    """A straight line over the 20 years of earth_precession took up part of the 18.6-year nutation and showed
    -50.902"/yr; the legend now gives wobble.measure_precession's rate of the figure axis, to its five digits."""
    from astropy import units as u

    ds = wobble.run(_shipped("earth_precession"))
    want = wobble.measure_precession(ds, axis="axis_direction").rate.to_value(u.arcsec / u.yr)
    (label,) = [
        t.get_text() for t in _panel(scene_figure(ds), "figure axis").get_legend().get_texts() if _is_rate(t.get_text())
    ]
    assert label.startswith(f"mean rate {want:.5g} ") and label.endswith("(nutation fitted)")
    assert abs(want + 50.40) < 0.01  # and not the straight line's -50.90


def test_an_unresolved_axis_panel_gives_no_fitted_rate_and_an_empty_dataset_is_refused():
    """The precession's fitted rate was written even where the panel was marked unresolved (the alias's rate);
    a Dataset with no times raised IndexError."""
    from wobble.errors import InputError

    coarse = scene_figure(wobble.run(_shipped("gyroscope", stop="10 s", samples=5)))  # 2.5 s a sample, 3.6 rad
    axis = _panel(coarse, "figure axis")
    assert _as_markers(axis) and not any(_is_rate(t.get_text()) for t in axis.get_legend().get_texts())
    fine = scene_figure(wobble.run(_shipped("gyroscope", stop="1 s", samples=2001)))
    # No perturber to fit a nutation of: a straight line's slope, and it says so.
    assert any(
        t.get_text().startswith("straight-line rate") for t in _panel(fine, "figure axis").get_legend().get_texts()
    )
    with pytest.raises(InputError, match="^source: .*allowed: a run's Dataset or file with at least one time"):
        scene_figure(_spinning(np.array([]), 1.0))


def test_the_gyroscope_s_axis_panel_draws_its_steady_precession_in_degrees():
    ds = wobble.run(_shipped("gyroscope", stop="1 s", samples=201))
    fig = scene_figure(ds)
    axis = _panel(fig, "figure axis")
    assert axis.get_ylabel() == "deg"
    (line,) = _curves(axis)
    e3 = ds["axis_direction"].values
    azimuth = np.unwrap(np.arctan2(e3[:, 1], e3[:, 0]))
    np.testing.assert_allclose(line.get_ydata(), np.degrees(azimuth - azimuth[0]), rtol=0, atol=1e-9)
    # Started at the steady precession rate phi_dot = 1.4553 rad/s: the azimuth is phi_dot t.
    t = ds["time"].values
    np.testing.assert_allclose(line.get_ydata(), np.degrees(_gyroscope_precession()[0] * t), rtol=0, atol=1e-6)
    tilt = _panel(fig, "tilt")
    assert tilt.get_ylabel() == "deg" and _offset_text(fig, tilt) == ""
    lo, hi = tilt.get_ylim()
    assert lo < 80 < hi and hi - lo > 1  # a constant 80 deg, not its rounding spelled out


def test_a_wobble_angle_of_a_fifth_of_an_arcsec_is_drawn_in_mas_without_offset():
    ds = wobble.run(_shipped("earth_free_wobble", stop="400 d", step="1 d"))
    fig = scene_figure(ds)
    ax = _panel(fig, "wobble angle")
    assert ax.get_ylabel() == "mas" and _offset_text(fig, ax) == ""
    (line,) = _curves(ax)
    np.testing.assert_allclose(line.get_ydata(), ds["wobble_angle"].values / _UNITS["mas"], rtol=1e-12)
    assert line.get_ydata()[0] == pytest.approx(200.0, rel=1e-9)  # the scene's 0.2 arcsec


# --------------------------------------------------------------------------
# Ensembles and legends
# --------------------------------------------------------------------------
def test_an_ensemble_s_members_are_told_apart_by_colour_one_panel_a_component():
    ds = wobble.run("tumbling_asteroid")
    members = ds.sizes["member"]
    fig = scene_figure(ds)
    for k, name in enumerate(("omega_1", "omega_2", "omega_3")):
        ax = _panel(fig, f"angular velocity, body frame: $\\{name}$")
        curves = _curves(ax)
        assert len(curves) == members
        assert len({line.get_color() for line in curves}) == members
        assert ax.get_ylabel() == "$10^{-6}$ rad s$^{-1}$" and _offset_text(fig, ax) == ""  # micro-radians per second
        for j, line in enumerate(curves):
            np.testing.assert_allclose(line.get_ydata(), ds["omega"].values[:, j, k] / 1e-6, rtol=1e-15)
        labels = [text.get_text() for text in ax.get_legend().get_texts()]
        assert labels == [f"member {j}" for j in range(members)]
    energy = _panel(fig, "energy")
    assert len({line.get_color() for line in _curves(energy)}) == members


@pytest.mark.parametrize("name", ["top_cusps", "top_loops"])
def test_legends_sit_beside_the_panels_not_on_the_curves(name):
    fig = scene_figure(wobble.run(name))
    fig.canvas.draw()
    for ax in fig.axes:
        legend = ax.get_legend()
        assert legend is not None, ax.get_title()
        assert legend.get_window_extent().x0 >= ax.get_window_extent().x1, ax.get_title()


# --------------------------------------------------------------------------
# The shipped scenes sample what they show
# --------------------------------------------------------------------------
def _spacing(time: dict) -> float:
    """Sample spacing (s) of a shipped scene's [time] table."""
    import astropy.units as u

    span = u.Quantity(time["stop"]).to_value(u.s) - u.Quantity(time.get("start", "0 s")).to_value(u.s)
    if "step" in time:
        return u.Quantity(time["step"]).to_value(u.s)
    return span / (time["samples"] - 1)


def _euler_omega(initial: dict) -> np.ndarray:
    """Body-frame omega of z-x-z Euler angles and rates (Goldstein, Poole & Safko 2002, eq. 4.87)."""
    _, theta, psi = np.radians(initial["euler_angles"]["value"])
    phi_dot, theta_dot, psi_dot = initial["euler_rates"]["value"]
    return np.array(
        [
            phi_dot * math.sin(theta) * math.sin(psi) + theta_dot * math.cos(psi),
            phi_dot * math.sin(theta) * math.cos(psi) - theta_dot * math.sin(psi),
            phi_dot * math.cos(theta) + psi_dot,
        ]
    )


def _fastest(name: str) -> tuple[float, str]:
    """The fastest rate (rad/s) a shipped scene's figure draws, from its physics, and what it is."""
    scene = _shipped(name)
    initial = scene["initial"]
    if name == "earth_precession":
        # The axis's fastest visible term: the Moon's fortnightly nutation, twice its mean motion.
        import astropy.units as u

        moon = next(t for t in scene["torques"] if t["name"] == "moon")
        return 2 * u.Quantity(moon["mean_motion"]).to_value(u.rad / u.s), "the fortnightly nutation"
    if name in ("earth_free_wobble", "mars_free_wobble"):
        # Euler frequency of the rigid planet sqrt((C - A)(C - B)/(A B)) omega_3; the wobble angle
        # of a triaxial body varies at twice it.
        body = read_scene(example_scene_path(name))
        m = np.sort(np.asarray(body.body.moments).reshape(3))
        spin = float(np.linalg.norm(body.omega0))  # the catalogued rate
        return 2 * spin * math.sqrt((m[2] - m[0]) * (m[2] - m[1]) / (m[0] * m[1])), "twice the Euler frequency"
    omega = _euler_omega(initial) if "euler_angles" in initial else np.asarray(initial["omega"]["value"], float)
    if initial.get("omega", {}).get("unit") == "deg/h":
        omega = np.radians(omega) / 3600
    spin = float(np.max(np.linalg.norm(np.atleast_2d(omega), axis=-1)))
    if scene.get("torques"):
        # A field fixed in space turns at the spin as the body sees it; its torque up to quadratically.
        return 2 * spin, "twice the spin"
    # Free: omega turns in the body no faster than |omega| (|I_j - I_k| <= I_i in Euler's equations).
    return spin, "the spin"


@pytest.mark.parametrize("name", wobble.example_scenes())
def test_every_shipped_scene_samples_its_fastest_motion_four_times_a_period(name):
    rate, what = _fastest(name)
    gap = _spacing(_shipped(name)["time"])
    assert rate * gap <= math.pi / 2, f"{name}: {what} {rate:.4g} rad/s, samples {gap:.4g} s apart"


def test_no_shipped_scene_figure_needs_a_note_or_an_offset_text():
    """No panel is unresolved, and none has matplotlib's offset or multiplier ('1e33', '+8.438e4') above
    its axis: every unit and power of ten is in the axis label."""
    for name in wobble.example_scenes():
        fig = scene_figure(wobble.run(name))
        notes = {ax.get_title(): _notes(ax) for ax in fig.axes if _notes(ax)}
        assert notes == {}, name
        fig.canvas.draw()
        offsets = {
            ax.get_title(): (ax.xaxis.get_offset_text().get_text(), ax.yaxis.get_offset_text().get_text())
            for ax in fig.axes
        }
        assert {t: o for t, o in offsets.items() if o != ("", "")} == {}, name
        plt.close(fig)


def test_a_nan_sample_does_not_set_the_scale_of_a_vector_panel(earth_precession):
    """One NaN in L switched the change-from-start rule and the power of ten off: the ticks read
    -1000000000000000089690419062898688."""
    ds = earth_precession.copy(deep=True)
    ds["angular_momentum"].values[5, 0] = np.nan
    fig = scene_figure(ds)
    panel = _panel(fig, "angular momentum, inertial frame: change from the start")
    assert panel.get_ylabel() == "$10^{30}$ kg m$^{2}$ s$^{-1}$" and _offset_text(fig, panel) == ""
    fig.canvas.draw()
    assert all(len(t.get_text()) < 8 for t in panel.get_yticklabels())


@pytest.mark.parametrize(
    ("start", "text"),
    [
        ((0.0, 2.330471e33, 5.375291e33), "(0.00000, 2.33047, 5.37529) $10^{33}$ kg"),
        ((-9.9999996e32, 1e30, 0.0), "(-1.00000, 0.00100, 0.00000) $10^{33}$ kg"),  # not -1000.000 in 10^30
        ((0.0, 0.0, 0.0), "(0, 0, 0) kg"),
        ((-0.0, 1.5, -2.25), "(0.00000, 1.50000, -2.25000) kg"),
    ],
)
def test_a_start_is_written_to_six_digits_in_one_power_of_ten(start, text):
    from wobble.plot._style import start_text

    assert start_text(start, "kg") == text


def test_a_free_body_over_many_periods_is_drawn_for_its_first_ten():
    """earth_free_wobble holds 120 periods of omega over 100 years: drawn whole they were solid bands. As
    wobble free --plot does, the figure draws the first 10 (omega repeats exactly every period) and says so."""
    ds = wobble.run("earth_free_wobble")
    t, w2 = ds["time"].values, ds["omega"].values[:, 1]
    # The period from the samples themselves: the spacing of omega_2's upward zero crossings.
    k = np.flatnonzero((w2[:-1] < 0) & (w2[1:] >= 0))
    up = t[k] - w2[k] * (t[k + 1] - t[k]) / (w2[k + 1] - w2[k])
    period = float(np.mean(np.diff(up)))
    fig = scene_figure(ds)
    assert fig._suptitle.get_text().endswith(
        f"first 10 of {(t[-1] - t[0]) / period:,.0f} periods of omega shown (each repeats the first)"
    )
    w1_line = _curves(_panel(fig, "angular velocity"))[0]
    year = 365.25 * 86400
    drawn = w1_line.get_xdata()
    assert drawn[-1] == pytest.approx(10 * period / year, abs=float(np.median(np.diff(t))) / year)
    np.testing.assert_allclose(w1_line.get_ydata() * 1e-12, ds["omega"].values[: drawn.size, 0], rtol=1e-12)


def test_a_scene_with_a_figure_axis_is_drawn_over_its_whole_span():
    """The figure axis precesses (it does not repeat with omega): no cut."""
    ds = wobble.run("top_loops")
    fig = scene_figure(ds)
    assert "periods of omega shown" not in fig._suptitle.get_text()


def test_a_tilt_under_1e_8_rad_is_drawn_not_rounded_to_zero():
    """The tilt from the axis direction was arccos(e3_z), which reads 0 below about 1e-8 rad (cos rounds to
    1); the engine forms it as atan2(|e3_xy|, e3_z). A tilt of 1e-9 rad (0.206 mas), by construction."""
    t = np.linspace(0.0, 10.0, 201)
    tilt = 1e-9 * (1 + 0.5 * np.sin(t))
    e3 = np.stack([np.sin(tilt) * np.cos(t), np.sin(tilt) * np.sin(t), np.cos(tilt)], axis=-1)
    ds = xr.Dataset(
        {"axis_direction": (("time", "inertial_axis"), e3, {"units": "1"})},
        coords={"time": ("time", t, {"units": "s"})},
    )
    panel = _panel(scene_figure(ds), "tilt")
    assert panel.get_ylabel() == "mas"
    (line,) = _curves(panel)
    np.testing.assert_allclose(line.get_ydata() * _UNITS["mas"], tilt, rtol=1e-9)


def test_an_axis_near_the_pole_is_drawn_as_its_offset_toward_x_and_y():
    """A figure axis within a few degrees of inertial z has no useful azimuth: the panel draws its offsets
    toward inertial x and y, asin(e3_x) and asin(e3_y), in one unit (its own loop drew what the angle
    curves draw; now it calls them). One member: a colour per offset; two: a colour per member, a line
    style per offset, each offset named once."""
    scene = _symmetric_wobble(0.1, 101)
    scene["outputs"] = ["axis_direction"]
    ds = wobble.run(scene)
    axis = _panel(scene_figure(ds), "figure axis (body axis 3): offset")
    e3 = ds["axis_direction"].values
    rad = {"deg": math.radians(1.0), "arcsec": math.radians(1 / 3600)}[axis.get_ylabel()]
    x, y = _curves(axis)
    np.testing.assert_allclose(x.get_ydata(), np.arcsin(e3[:, 0]) / rad, rtol=0, atol=1e-12)
    np.testing.assert_allclose(y.get_ydata(), np.arcsin(e3[:, 1]) / rad, rtol=0, atol=1e-12)
    assert [x.get_label(), y.get_label()] == ["toward inertial x", "toward inertial y"]
    assert [x.get_color(), y.get_color()] == ["C0", "C1"] and x.get_linestyle() == y.get_linestyle()
    scene["initial"]["omega"] = {"value": [[0.1, 0.0, 1.0], [0.05, 0.0, 1.0]], "unit": "rad/s"}
    axis = _panel(scene_figure(wobble.run(scene)), "figure axis (body axis 3): offset")
    lines = _curves(axis)
    assert [line.get_color() for line in lines] == ["C0", "C1", "C0", "C1"]
    assert (
        len({line.get_linestyle() for line in lines[:2]})
        == 1
        != len({lines[0].get_linestyle(), lines[2].get_linestyle()})
    )
    assert [line.get_label() for line in lines if not line.get_label().startswith("_")] == [
        "toward inertial x",
        "toward inertial y",
    ]
