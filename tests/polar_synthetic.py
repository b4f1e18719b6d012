"""Synthetic polar-motion records with known Chandler, annual and drift terms (ground truth for the tests).

Units: seconds and radians, as the model layer. Every record is built from a
``numpy.random.Generator`` the caller seeds, so tests are reproducible.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.signal import lfilter

from wobble.io.catalog import load_planet

DAY = 86400.0
YEAR = 365.25 * DAY
MAS = math.pi / (180.0 * 3600.0 * 1000.0)
TROPICAL_YEAR = 365.24219 * DAY
#: The published Chandler period of the Earth catalogue (data/bodies/earth.toml), s: the
#: estimators take it to place the Chandler-annual beat period, as wobble.api passes it.
REFERENCE_PERIOD = load_planet("earth")[0].observed_chandler_period.value

TRUTH = {
    "period": 433.0 * DAY,
    "chandler_amplitude": 150.0 * MAS,
    "chandler_phase": 0.7,
    "annual_amplitude": 90.0 * MAS,
    "annual_phase": 0.3,
    "retrograde_amplitude": 5.0 * MAS,
    "retrograde_phase": -1.0,
}


def coloured_noise(rng, n, rms, rho=0.995):
    """Complex AR(1) noise of daily lag-one correlation ``rho`` (correlation time ~200 d) and given RMS."""
    e = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    ar = lfilter([1.0], [1.0, -rho], e)
    return ar / np.sqrt(np.mean(np.abs(ar) ** 2)) * rms


def damped_wobble(rng, n, period, q, rms, burn=20000):
    """A randomly excited damped free wobble (complex AR(1) with the mode's frequency and decay), daily."""
    sigma = 2 * math.pi / period
    lam = np.exp((1j * sigma - sigma / (2 * q)) * DAY)
    e = rng.standard_normal(n + burn) + 1j * rng.standard_normal(n + burn)
    m = lfilter([1.0], [1.0, -lam], e)[burn:]
    return m / np.sqrt(np.mean(np.abs(m) ** 2)) * rms


def record(rng, years, *, chandler="sinusoid", q=100.0, noise_rms=20 * MAS, gaps=True, start=0.0):
    """(t, p): daily samples over ``years`` with gaps and dropped days; p = x - i y in rad.

    ``chandler="sinusoid"`` is a constant circle (TRUTH); ``"damped"`` a randomly
    excited wobble of quality ``q`` whose mode period is TRUTH["period"].
    """
    n = int(round(years * 365.25))
    t = start + DAY * np.arange(n)
    s = t - t.mean()
    if chandler == "sinusoid":
        ch = TRUTH["chandler_amplitude"] * np.exp(1j * (2 * math.pi / TRUTH["period"] * s + TRUTH["chandler_phase"]))
    else:
        ch = damped_wobble(rng, n, TRUTH["period"], q, TRUTH["chandler_amplitude"])
    wa = 2 * math.pi / TROPICAL_YEAR
    annual = TRUTH["annual_amplitude"] * np.exp(1j * (wa * s + TRUTH["annual_phase"]))
    retro = TRUTH["retrograde_amplitude"] * np.exp(-1j * (wa * s - TRUTH["retrograde_phase"]))
    tau = s / s.max()
    drift = (40 + 300j + (20 - 60j) * tau + (5 + 8j) * tau**2) * MAS
    p = drift + ch + annual + retro + coloured_noise(rng, n, noise_rms)
    keep = np.ones(n, dtype=bool)
    if gaps:
        for _ in range(max(1, int(years))):  # about one gap of 1-30 days a year
            a = rng.integers(0, n - 31)
            keep[a : a + rng.integers(1, 31)] = False
        keep &= rng.random(n) > 0.1  # and 10 % of the days dropped at random: uneven sampling
        keep[[0, -1]] = True
    return t[keep], p[keep]


def state_space_record(rng, years, period, q, noise):
    """(t, p): a daily record of wobble's state-space model itself (free wobble driven by coloured
    excitation, seasonal circles, a drifting mean pole, white observation noise), from its own
    transition and noise (:func:`wobble.models.polar_motion.state_space.system`)."""
    from wobble.models.polar_motion.excitation import chandler_frequency
    from wobble.models.polar_motion.state_space import mean_pole_index, system

    F, Q, h, r = system(chandler_frequency(period, q), noise)
    lam, V = np.linalg.eigh(Q)
    root = V * np.sqrt(np.clip(lam, 0.0, None))  # root @ root^H = Q (rank-deficient)
    n = int(years * 365.25)
    m, mp = F.shape[0], mean_pole_index(noise.order)
    x = np.zeros(m, dtype=complex)
    x[mp - 4 : mp] = np.array([90, 5, 4, 1]) * MAS  # the seasonal circles
    x[mp], x[mp + 1] = (40 + 300j) * MAS, (0.005 + 0.01j) * MAS
    w = (root @ (rng.standard_normal((m, n)) + 1j * rng.standard_normal((m, n)))).T / math.sqrt(2)
    v = math.sqrt(r / 2) * (rng.standard_normal(n) + 1j * rng.standard_normal(n))
    out = np.empty(n, dtype=complex)
    for k in range(n):
        x = F @ x + w[k]
        out[k] = h @ x + v[k]
    return DAY * np.arange(n), out
