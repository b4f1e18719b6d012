"""The Fourier kernel against closed forms, and the sign convention of the two-sided spectrum."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, REFERENCE_PERIOD, TRUTH, YEAR

from wobble.models import polar_motion as pm
from wobble.numerics.spectral import dtft, dtft_at, phases


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


@pytest.mark.parametrize("n", [1, 300, 23648])
def test_block_rotated_exponentials_against_the_geometric_sum(n):
    """dtft_at with grid=(t0, dt): the closed form of test_dtft_grid_matches_the_geometric_sum, on a
    daily grid as long as the C04 record, to the rounding the exact exponentials carry (the angles
    omega t reach ~100 rad, rounded to ~1e-14 either way)."""
    t0, dt = -1.0215504e9, DAY
    t = t0 + dt * np.arange(n)
    a = 2 * math.pi / (433.0 * DAY)
    z = np.exp(1j * a * (t - t0))
    w = a + np.array([-3e-9, -1e-10, 0.0, 2e-11, 4e-9])
    d = a - w
    with np.errstate(invalid="ignore", divide="ignore"):  # expm1: d dt is as small as 2e-6 rad
        closed = np.where(d == 0, n, np.expm1(1j * d * dt * n) / np.expm1(1j * d * dt))
    expected = closed * np.exp(-1j * w * t0)
    got = dtft_at(t, z, w, grid=(t0, dt))
    assert np.max(np.abs(got - expected)) <= 1e-13 * n
    # and each exponential within a few ulps of the exact one, beside the angle's own rounding
    exact = np.exp(-1j * np.multiply.outer(w, t))
    angle = np.max(np.abs(np.multiply.outer(w, t)))
    assert np.max(np.abs(phases(n, w, (t0, dt)) - exact)) <= 1e-15 + 4.5e-16 * angle


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


@pytest.mark.parametrize("kind", ["boxcar", "hann"])
@pytest.mark.parametrize("years", [7.3, 20.0, 41.7])
def test_the_noise_ring_is_the_mean_power_outside_the_main_lobe(kind, years):
    """spectrum._local_level against its definition: the mean of |sum_k w_k r_k exp(-i f t_k)|^2 / sum w^2
    over the ring's grid f = rate + j d (d = 2 pi / (4 span), |j| <= ceil((lobe + 0.1 cycle/yr) / d)),
    leaving out the main lobe |j| <= lobe / d (4 steps boxcar, 8 Hann), edges included, counted in
    grid steps (a float test |f - rate| > lobe kept an edge point for some spans, not others).
    The points are summed here by definition, one frequency at a time."""
    from wobble.models.polar_motion.spectrum import _local_level

    rng = np.random.default_rng(int(years * 10))
    t = np.arange(0.0, years * YEAR, DAY)
    s = t - 0.5 * (t[0] + t[-1])
    span = t[-1] - t[0]
    w = np.hanning(t.size) if kind == "hann" else np.ones(t.size)
    rate = 2 * math.pi / (433.0 * DAY)
    r = rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size) + 3 * np.exp(1j * rate * s)
    got = _local_level(s, w * r, w, rate, span, kind)

    steps = 8 if kind == "hann" else 4
    d = 2 * math.pi / (4 * span)
    half = math.ceil((steps * d + 0.1 * 2 * math.pi / (365.24219 * DAY)) / d)
    ring = [j for j in range(-half, half + 1) if abs(j) > steps]
    power = [abs(np.sum(w * r * np.exp(-1j * (rate + j * d) * s))) ** 2 / np.sum(w**2) for j in ring]
    assert got == pytest.approx(np.mean(power), rel=1e-9)
    # The lobe's edge point counts: with it (or without the next one) the mean is another number.
    edge = abs(np.sum(w * r * np.exp(-1j * (rate + steps * d) * s))) ** 2 / np.sum(w**2)
    assert abs(np.mean(power + [edge]) / np.mean(power) - 1) > 1e-6
