"""What ``wobble free --plot`` draws, read back from the figure's artists (a visual audit found
a polhode of 2.9 deg drawn as +-10,000 arcsec).

The criteria, stated once here and in the modules' constants:

* angles in deg from 1 deg, else arcsec, mas, µas.
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt  # the Agg backend: tests/conftest.py sets MPLBACKEND
import numpy as np
import pytest
from astropy import units as u

from wobble.api.free import FreeRotation
from wobble.plot.free import motion_figure

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s
MAS = math.radians(1 / 3.6e6)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


# -- free: the polhode -----------------------------------------------------------------------------------


def _polhode(fig):
    ax = fig.axes[2]
    line = ax.lines[0]
    if ax.name == "3d":
        return ax, np.column_stack(line.get_data_3d())
    return ax, np.column_stack(line.get_data())


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
