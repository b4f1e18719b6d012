"""Geodetic excitation: the Liouville equation of polar motion, inverted and run forward, exactly for sampled data.

The pole p = x_p - i y_p (:mod:`.record`) and the excitation chi = chi_1 + i chi_2
are related by the linearised Liouville equation (Munk & MacDonald 1960;
Gross 1992, Geophys. J. Int. 109, 162; Brzezinski 1992, manuscripta geodaetica
17, 3):

    p + (i / sigma_c) dp/dt = chi,   sigma_c = (2 pi / T_c) (1 + i / (2 Q)),       (1)

whose free solution p = a exp(i sigma_c t) is the prograde, damped Chandler
wobble. With chi held constant over each sampling step (t_{k-1}, t_k] of length
Delta_k, (1) integrates exactly to

    p_k = lambda_k p_{k-1} + (1 - lambda_k) chi_k,   lambda_k = exp(i sigma_c Delta_k),   (2)

so the excitation of the step is

    chi_k = (p_k - lambda_k p_{k-1}) / (1 - lambda_k).                            (3)

(3) is the exact discrete inverse for any sampling, and (2) the exact forward
model: running (2) from p_0 with the chi of (3) gives the record back to
rounding. Wilson's (1985) deconvolution filter is (3) with 1 - lambda replaced
by -i sigma_c Delta e^{i sigma_c Delta / 2}, which differs by (sigma_c Delta)^2/24,
about 1e-5 for daily data. chi_k belongs to the step ending at t_k (its
midpoint is t_k - Delta_k / 2). Times in s, angles in rad, rates in rad/s.
"""

from __future__ import annotations

import math

import numpy as np

from wobble.errors import InputError
from wobble.models.polar_motion.record import DAY
from wobble.numerics.recurrence import linear_recurrence

__all__ = ["chandler_frequency", "excitation_from_pole", "pole_from_excitation", "band_amplitude", "band_reach"]


def chandler_frequency(period: float, q: float) -> complex:
    """sigma_c = (2 pi / T_c)(1 + i / (2 Q)), rad/s (Q = inf: undamped). ``period`` in s, Q > 0."""
    period, q = float(period), float(q)
    if not (math.isfinite(period) and period > 0):
        raise InputError("chandler_period", f"{period / DAY:g} d", "a positive, finite period")
    if not q > 0:
        raise InputError("q", q, "a quality factor Q > 0 (inf: undamped)")
    return (2.0 * math.pi / period) * complex(1.0, 0.0 if math.isinf(q) else 1.0 / (2.0 * q))


def _lambdas(t, sigma_c: complex) -> np.ndarray:
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.diff(t) > 0):
        raise InputError("t", f"{t.size} times", "at least two strictly increasing times")
    return np.exp(1j * sigma_c * np.diff(t))


def excitation_from_pole(t, p, sigma_c: complex) -> np.ndarray:
    """Equation (3): chi_k for k = 1 .. n-1 (the steps between the n samples), complex rad."""
    lam = _lambdas(t, sigma_c)
    p = np.asarray(p, dtype=complex)
    return (p[1:] - lam * p[:-1]) / -np.expm1(1j * sigma_c * np.diff(np.asarray(t, dtype=float)))


def pole_from_excitation(t, chi, sigma_c: complex, p0: complex) -> np.ndarray:
    """Equation (2) from p(t_0) = ``p0``: the pole at every t (n values) from the n - 1 step excitations."""
    t = np.asarray(t, dtype=float)
    lam = _lambdas(t, sigma_c)
    gain = -np.expm1(1j * sigma_c * np.diff(t))
    chi = np.asarray(chi, dtype=complex)
    if chi.shape != lam.shape:
        raise InputError("chi", f"{chi.size} values", f"one per step between the {t.size} times ({lam.size})")
    out = np.empty(t.size, dtype=complex)
    out[0] = p0
    if np.allclose(lam, lam[0], rtol=0, atol=1e-15) and np.allclose(gain, gain[0], rtol=0, atol=1e-15):
        # Uniform steps: one factor, and the recursion by blocks of matrix products (no Python loop,
        # and no import of scipy.signal, ~0.4 s).
        dt0 = float(t[1] - t[0])
        return linear_recurrence([p0], 1j * sigma_c * dt0, (gain[0] * chi)[:, None])[:, 0]
    p = complex(p0)
    for k in range(lam.size):
        p = lam[k] * p + gain[k] * chi[k]
        out[k + 1] = p
    return out


def band_reach(half_width: float) -> float:
    """How far (s) :func:`band_amplitude`'s kernel reaches for its amplitudes to count as known: the half-width
    of its main lobe, pi / half_width (1/(2B) for a band of +/- B cycles per time; 5 years for B = 0.1 cycle
    per year), which holds 90 % of the kernel's energy."""
    return math.pi / half_width


def band_amplitude(t, z, centre: float, half_width: float, lines=()) -> np.ndarray:
    """The envelope of ``z``'s content within ``centre`` +/- ``half_width`` (rad/s, signed: prograde > 0), for
    uniformly sampled ``z``; NaN within :func:`band_reach` of either end.

    An ideal band-pass: its sharp edges attenuate lines just outside the band (the annual wobble, 0.16
    cycle per year from the Chandler frequency, to 3 % in the middle of a 40-year record and up to 8 %
    within a few years of the unknown ends; a Gaussian band of the same half-width passes a fifth of
    it). Lines at the rates ``lines`` (rad/s, signed) are therefore fitted by least squares with constant
    amplitudes, with the mean, and removed first. The kernel is a sinc envelope whose main lobe spans
    +/- 1/(2B) (B the half-width in cycles per time): nearer an end than that, the amplitude is NaN; next
    to that edge a line in the band still reads up to 12 % high or low (the record's truncation: Gibbs).
    The convolution is linear, the series padded with as many zeros: a circular one wraps the record's
    start into its end (the pole's 2020 band amplitude then moves from 44 to 11 mas when the record is
    cut two years shorter, and the excitation's after 2015 reads 6.8 mas instead of 2.0).
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(z, dtype=complex)
    dt = float(np.median(np.diff(t)))
    if not np.allclose(np.diff(t), dt, rtol=1e-9, atol=1e-6):
        raise InputError("t", "uneven sampling", "uniformly sampled data for the band-pass")
    n = t.size
    s = t - t.mean()
    columns = np.column_stack([np.ones(n), *(np.exp(1j * rate * s) for rate in lines)])
    z = z - columns @ np.linalg.lstsq(columns, z, rcond=None)[0]  # the mean and the lines
    freq = 2 * math.pi * np.fft.fftfreq(2 * n, dt)
    spec = np.fft.fft(z, 2 * n)  # zero-padded to twice the length: no wrap-around
    spec[np.abs(freq - centre) > half_width] = 0.0
    out = np.abs(np.fft.ifft(spec)[:n])
    reach = band_reach(half_width)
    out[(t < t[0] + reach) | (t > t[-1] - reach)] = np.nan
    return out
