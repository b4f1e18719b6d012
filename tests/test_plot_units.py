"""Every figure spells a unit one way: powers as mathtext superscripts, ``rad s$^{-1}$`` (drawn rad s⁻¹), the
spelling most figures used (the free and top figures); the scene, sweep and corner figures wrote the files' CF
spelling (``rad s-1``, ``kg m2 s-1``) and the top's classes and the sweep's phase diagram a slash (``rad/s``).

Each figure kind is drawn from the inputs its own tests use and every text on it is read back."""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import pytest
from astropy import units as u
from matplotlib.text import Text

import wobble
from wobble.plot._style import unit_label

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s

_UNIT = r"(?:kg|rad|deg|arcsec|mas|µas|yr|min|m|s|d|h|J)"
#: The other spellings: a CF power after a unit (s-1, m2), a slash between units (rad/s, arcsec/yr), Unicode powers.
OTHER = re.compile(rf"(?:^|[\s(\[]){_UNIT}-?\d+(?=$|[\s)\],;])|{_UNIT}/{_UNIT}\b|[⁻¹²³]")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _texts(fig) -> list[str]:
    fig.canvas.draw()  # tick labels and legends are set when drawn
    return [t.get_text() for t in fig.findobj(Text) if t.get_text()]


def _sweep_ensemble():
    from wobble.api.sweep import run_sweep
    from wobble.plot.sweep import ensemble

    vary = {
        "moment_ratio_ba": {"distribution": "uniform", "low": 1.0, "high": 3.0},
        "moment_ratio_cb": {"distribution": "uniform", "low": 1.0, "high": 1.5},
        "spin_period": {"distribution": "uniform", "low": 24.0, "high": 240.0, "unit": "h"},
        "spin_cos_colatitude": {"distribution": "uniform", "low": -1.0, "high": 1.0},
        "spin_longitude": {"distribution": "uniform", "low": 0.0, "high": 360.0, "unit": "deg"},
    }
    base = {"moment_a": {"value": 1e17, "unit": "kg m2"}, "final_time": {"value": 10.0, "unit": "d"}}
    spec = {"schema": "wobble-sweep/1", "name": "t", "target": "free_rotation", "members": 200, "seed": 11}
    return ensemble(run_sweep({**spec, "base": base, "vary": vary}))


def _sweep_histogram():
    from wobble.api.sweep import run_sweep
    from wobble.plot.sweep import histogram

    spec = {"schema": "wobble-sweep/1", "name": "t", "target": "chandler", "body": "mars", "members": 200, "seed": 7}
    return histogram(
        run_sweep({**spec, "outputs": ["chandler_period"], "vary": {"love_number_k2": {"distribution": "normal"}}})
    )


def _top(**kw):
    return wobble.HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S, **kw)


def _polar_motion():
    from wobble.plot.polar_motion import overview

    short = dict(window=732.5 * u.day, step=1 * u.yr, excitation_q=None, quality_factor=False)
    return overview(wobble.polar_motion_analysis(start="2015", end="2020", **short))


FIGURES = {
    "free.motion": lambda: wobble.plot.free.motion_figure(
        wobble.FreeRotation([1, 2, 3] * KGM2, [0.1, 0, 1] * RAD_S), 20 * u.s
    ),
    "free.flip": lambda: wobble.plot.free.flip_figure([1, 2, 3] * KGM2, [1e-6, 1, 1e-6] * RAD_S, 200 * u.s),
    "free.polhode": lambda: wobble.plot.free.polhode_figure([1, 2, 3] * KGM2, [1, 0.1, 0.4] * RAD_S),
    "top.locus": lambda: wobble.plot.top.axis_locus_figure(_top(), 10 * u.s),
    "top.cubic": lambda: wobble.plot.top.cubic_figure(_top()),
    "top.potential": lambda: wobble.plot.top.effective_potential_figure(_top()),
    "top.classes": lambda: wobble.plot.top.nutation_classes_figure(
        1 * KGM2, 0.5 * KGM2, 1 * u.J, 60 * u.deg, 10 * RAD_S, [0.3 * RAD_S, 0 * RAD_S, -0.3 * RAD_S]
    ),
    "scene.tennis_racket": lambda: wobble.plot.scene.scene_figure(wobble.run("tennis_racket")),
    "scene.gyroscope": lambda: wobble.plot.scene.scene_figure(wobble.run("gyroscope")),  # its fitted rate, deg s-1
    "sweep.histogram": _sweep_histogram,
    "sweep.phase_diagram": lambda: wobble.plot.sweep.phase_diagram(wobble.api.sweep.run_sweep("top_phase_diagram")),
    "sweep.ensemble": _sweep_ensemble,
    "inversion.corner": lambda: wobble.plot.inversion.corner_figure(
        wobble.invert("earth", seed=5, steps=200, burn=100, walkers=16)
    ),
    "modes": lambda: wobble.plot.modes.modes_figure([wobble.normal_modes("earth")]),
    "chandler": lambda: wobble.plot.chandler.budget_figure([wobble.chandler_budget("earth")]),
    "precession.budget": lambda: wobble.plot.precession.budget_figure([wobble.precession_rate("earth")]),
    "precession.nutation": lambda: wobble.plot.precession.nutation_ellipse_figure(wobble.precession_rate("earth")),
    "polar_motion.overview": _polar_motion,
}


@pytest.mark.parametrize("kind", FIGURES)
def test_no_figure_spells_a_unit_the_other_way(kind):
    import wobble.api.sweep  # noqa: F401 - the phase diagram's builder, by its module's name

    texts = _texts(FIGURES[kind]())
    assert texts  # the check below must have something to read
    assert [t for t in texts if OTHER.search(t)] == []


def test_the_scene_s_units_from_its_file_are_spelled_as_the_free_figure_spells_them():
    """The file says 'rad s-1' and 'kg m2 s-1' (CF); the figure draws rad s⁻¹ and kg m² s⁻¹, as wobble free's."""
    fig = wobble.plot.scene.scene_figure(wobble.run("tennis_racket"))
    labels = {ax.get_title(): ax.get_ylabel() for ax in fig.axes}
    assert labels["angular velocity, body frame"] == "rad s$^{-1}$"
    assert labels["angular momentum, inertial frame"].endswith(" kg m$^{2}$ s$^{-1}$")
    free = wobble.plot.free.motion_figure(wobble.FreeRotation([1, 2, 3] * KGM2, [0.1, 0, 1] * RAD_S), 20 * u.s)
    assert free.axes[0].get_ylabel() == labels["angular velocity, body frame"]


@pytest.mark.parametrize(
    ("written", "drawn"),
    [
        ("rad s-1", "rad s$^{-1}$"),
        ("rad/s", "rad s$^{-1}$"),
        ("kg m2 s-1", "kg m$^{2}$ s$^{-1}$"),
        ("arcsec/yr", "arcsec yr$^{-1}$"),
        ("m s-2", "m s$^{-2}$"),
        ("J", "J"),
        ("d", "d"),
        ("", ""),
        ("1", "1"),  # CF's dimensionless unit: not a product of named units, left alone
        ("rad s$^{-1}$", "rad s$^{-1}$"),  # spelled already
        ("days since 2000-01-01", "days since 2000-01-01"),
    ],
)
def test_unit_label_spells_powers_as_superscripts(written, drawn):
    assert unit_label(written) == drawn
    assert not OTHER.search(f"[{drawn}]")
