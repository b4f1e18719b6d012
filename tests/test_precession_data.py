"""The perturber catalogue re-derived from its sources.

The Moon's mean reciprocal distance and the factor by which the Sun's
perturbations of the lunar orbit change the mean tidal torque are derived
(data/precession/moon.toml) from the ELP-2000/82 series as abridged by Meeus
(1998, ch. 47), which ERFA implements as ``moon98``: a smoothly windowed time
average over fifty years (a weighted Birkhoff average, which converges faster
than any power of the span for quasi-periodic motion) must give them back.
"""

from __future__ import annotations

import math

import erfa
import numpy as np
import pytest

from wobble.io.perturbers import PERTURBER_UNITS, load_perturber, measured

KM = 1e3


@pytest.fixture(scope="module")
def lunar_averages():
    n = 60_000
    x = (np.arange(n) + 0.5) / n
    jd = 2451545.0 - 25 * 365.25 + 50 * 365.25 * x
    window = np.exp(-1.0 / (x * (1.0 - x)))
    window /= window.sum()
    p = erfa.moon98(jd, 0.0)["p"]
    # To the ecliptic of date; the ecliptic moves 47"/cy, so one matrix per 1000 samples is enough.
    rot = np.array([erfa.ecm06(j, 0.0) for j in jd[::1000]])
    pe = np.einsum("nij,nj->ni", rot[np.arange(n) // 1000], p)
    r = np.linalg.norm(p, axis=1) * erfa.DAU
    sin_beta = pe[:, 2] / np.linalg.norm(pe, axis=1)
    return window, r, sin_beta


def test_moon_semi_major_axis_is_the_mean_reciprocal_distance(lunar_averages):
    window, r, _ = lunar_averages
    moon = load_perturber("moon")
    a = measured(moon, "semi_major_axis", PERTURBER_UNITS["semi_major_axis"])
    assert 1.0 / np.sum(window / r) == pytest.approx(a.value, abs=0.1 * KM)


def test_moon_solar_perturbation_factor(lunar_averages):
    window, r, sin_beta = lunar_averages
    moon = load_perturber("moon")
    a = measured(moon, "semi_major_axis", PERTURBER_UNITS["semi_major_axis"]).value
    e = measured(moon, "eccentricity", PERTURBER_UNITS["eccentricity"]).value
    i = measured(moon, "inclination", PERTURBER_UNITS["inclination"]).value
    real = np.sum(window * (a / r) ** 3 * (1.0 - 3.0 * sin_beta**2))
    kepler = (1.0 - e**2) ** -1.5 * (1.0 - 1.5 * math.sin(i) ** 2)
    factor = measured(moon, "solar_perturbation_factor", PERTURBER_UNITS["solar_perturbation_factor"])
    assert real / kepler == pytest.approx(factor.value, abs=factor.sigma)


def test_moon_node_rate_is_18_6_years():
    node = measured(load_perturber("moon"), "node_rate", PERTURBER_UNITS["node_rate"]).value
    assert 2 * math.pi / abs(node) / (365.25 * 86400) == pytest.approx(18.61, abs=0.01)
