"""The modes figure (wobble modes --plot): where its legends sit."""

from __future__ import annotations

import matplotlib.pyplot as plt
import pytest
from matplotlib.transforms import Bbox

import wobble
from wobble.plot.modes import modes_figure


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _my_planet():
    from wobble.io.shipped import find_shipped

    return wobble.normal_modes(wobble.load_planet(str(find_shipped("my_planet.toml").path())))


def _covered(ax, legend_box, renderer) -> list[str]:
    """The drawn things of ``ax`` (lines, bands, spans) whose extent, within the axes, meets ``legend_box``."""
    hits = []
    for artist in [*ax.lines, *ax.collections, *ax.patches]:
        inside = Bbox.intersection(artist.get_window_extent(renderer), ax.bbox)
        if inside is not None and inside.overlaps(legend_box):
            hits.append(artist.get_label())
    return hits


@pytest.mark.parametrize(
    "results",
    [
        lambda: [wobble.normal_modes("earth"), wobble.normal_modes("mars")],  # the docs' figure
        lambda: [wobble.normal_modes("earth", modes=("CW",))],
        lambda: [_my_planet()],  # no profile: the CW alone, its model band beside the observed one
    ],
    ids=["earth-mars", "earth-cw", "no-profile"],
)
def test_no_legend_covers_a_band_or_a_line(results):
    """The Chandler panels' legends ("best", then inside) sat on the model's and the observed +-1 sigma bands,
    which span the panel's width; the FCN panel's on its full-height e_f lines. Each legend is now beside its
    panel; the check is on what is drawn, so a legend inside clear of every band and line would pass too."""
    fig = modes_figure(results())
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legends = [ax for ax in fig.axes if ax.get_legend() is not None]
    assert legends  # the loop below must have something to check
    for ax in legends:
        box = ax.get_legend().get_window_extent(renderer)
        assert _covered(ax, box, renderer) == [], f"legend of {ax.get_title()!r} covers these"
        # And it stays on the figure: beside the last column it was cut at the edge.
        assert fig.bbox.contains(box.x1 - 1, box.y0 + 1)
