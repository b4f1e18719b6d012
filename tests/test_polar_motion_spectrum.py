"""The Fourier kernel against closed forms, and the sign convention of the two-sided spectrum."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, REFERENCE_PERIOD, TRUTH, YEAR

from wobble.models import polar_motion as pm
from wobble.numerics.spectral import dtft, dtft_at


def test_dtft_grid_matches_the_geometric_sum():
    # sum_{n<N} exp(i a n) exp(-i w n) = (1 - e^{i(a-w)N}) / (1 - e^{i(a-w)}): closed form.
    n, a = 500, 0.3
    t = np.arange(n, dtype=float)
    z = np.exp(1j * a * t)
    omega0, step, count = -1.0, 0.013, 200  # 200 > RESEED: the recurrence is re-seeded on the way
    got = dtft(t, z, omega0, step, count)
    w = omega0 + step * np.arange(count)
    d = a - w
    expected = (1 - np.exp(1j * d * n)) / (1 - np.exp(1j * d))
    np.testing.assert_allclose(got, expected, rtol=1e-11, atol=1e-10)
    np.testing.assert_allclose(dtft_at(t, z, w[[3, 150]]), expected[[3, 150]], rtol=1e-12)


def test_dtft_transforms_columns_together():
    rng = np.random.default_rng(1)
    t = np.sort(rng.uniform(-50, 50, 300))  # uneven
    z = rng.standard_normal((300, 3)) + 1j * rng.standard_normal((300, 3))
    got = dtft(t, z, -0.5, 0.01, 90)
    for j in range(3):
        np.testing.assert_allclose(got[:, j], dtft_at(t, z[:, j], -0.5 + 0.01 * np.arange(90)), rtol=1e-10, atol=1e-10)


def test_prograde_circle_is_at_positive_frequency():
    # A counter-clockwise circle seen from above the north pole: with x toward
    # Greenwich and y toward 90 W, that is x = cos, y = -sin (y is a clockwise axis).
    t = np.arange(0, 20 * YEAR, DAY)
    w = 2 * math.pi / TRUTH["period"]
    x, y = np.cos(w * t), -np.sin(w * t)
    p = pm.complex_pole(x, y)
    np.testing.assert_allclose(p, np.exp(1j * w * t), atol=1e-12)
    np.testing.assert_allclose(pm.pole_xy(p), (x, y), atol=1e-15)
    spec = pm.two_sided_spectrum(t, p * MAS, reference_period=REFERENCE_PERIOD, drift_degree=0)
    assert spec.rate[np.argmax(spec.amplitude)] > 0
    assert spec.amplitude.max() == pytest.approx(MAS, rel=0.01)  # a circle of radius 1 mas
