"""What every polar-motion forecast is: issue time, the data it may use, lead times, means and intervals.

A forecast *issued* at time t_i may use the samples up to t_i - latency (the
record's publication delay): its information set. Lead times are counted from
the issue time, so a 10-day forecast with a latency of one day extrapolates 11
days past the last sample. Means are of the complex pole
p = x_p - i y_p; each of x_p and y_p has its own one-sigma error, and the
68 % and 95 % intervals are mean +/- z sigma with z = 1 and 1.96 (Gaussian
forecast errors). Times in s, angles in rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from wobble.errors import InputError
from wobble.models.polar_motion.record import DAY, pole_xy

__all__ = [
    "METHODS",
    "MAX_HORIZON",
    "Z68",
    "Z95",
    "Forecast",
    "PastForecasts",
    "information_set",
    "check_horizon",
    "check_method",
    "daily",
]

#: Forecast methods: least squares + autoregression, and the damped-oscillator state-space model (Kalman).
METHODS = ("ls_ar", "kalman")
#: Longest horizon either method forecasts: three years (beyond, both are harmonic extrapolations).
MAX_HORIZON = 1096.0 * DAY
#: Two-sided Gaussian quantiles of the 68.27 % and 95 % intervals.
Z68 = 1.0
Z95 = 1.959963984540054


@dataclass(frozen=True, eq=False)
class Forecast:
    """One forecast of the pole.

    Attributes
    ----------
    method : str
        ``ls_ar`` or ``kalman``.
    issued : float
        Issue time, s (the caller's origin).
    last_data : float
        Time of the last sample used (``issued - latency`` or earlier).
    lead : ndarray
        Lead times from ``issued``, s (one per day).
    mean : ndarray, complex
        Forecast of p = x_p - i y_p at ``issued + lead``, rad.
    sigma_x, sigma_y : ndarray
        One-sigma forecast errors of x_p and y_p, rad.
    baseline : ndarray, complex
        The method's deterministic part alone (LS+AR: the least-squares
        extrapolation; Kalman: the harmonic and drift states without the
        wobble), for skill scores.
    details : dict
        What the method fitted (orders, noise parameters, spans).
    calibration : Calibration, optional
        Interval half-widths from the method's past errors
        (:class:`~.forecast_calibration.Calibration`); None: the model's sigma.
    """

    method: str
    issued: float
    last_data: float
    lead: np.ndarray
    mean: np.ndarray
    sigma_x: np.ndarray
    sigma_y: np.ndarray
    baseline: np.ndarray
    details: dict = field(default_factory=dict)
    calibration: object | None = None

    def xy(self) -> tuple[np.ndarray, np.ndarray]:
        """(x_p, y_p) of the mean, rad."""
        return pole_xy(self.mean)

    def half_widths(self, level: int) -> tuple[np.ndarray, np.ndarray]:
        """(x_p, y_p) half-widths of the ``level`` % interval (68 or 95), rad: the calibration's when there is
        one (:mod:`.forecast_calibration`), else z sigma of the model (Gaussian errors)."""
        if self.calibration is not None:
            return self.calibration.half_widths(level)
        z = {68: Z68, 95: Z95}[level]
        return z * self.sigma_x, z * self.sigma_y

    def bounds(self, level: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(x low, x high, y low, y high) of the ``level`` % interval (68 or 95), rad."""
        hx, hy = self.half_widths(level)
        x, y = self.xy()
        return x - hx, x + hx, y - hy, y + hy


@dataclass(frozen=True, eq=False)
class PastForecasts:
    """Forecasts of one method issued in the past (means only), for :func:`.forecast_calibration.calibrate`.

    Attributes
    ----------
    issued : ndarray (k,)
        Issue times, s, increasing.
    mean : ndarray (k, H), complex
        Forecasts of p = x_p - i y_p at lead 1 .. H days after each issue, rad.
    sigma : ndarray (k, H, 2)
        The models' one-sigma errors of x_p and y_p, rad.
    """

    issued: np.ndarray
    mean: np.ndarray
    sigma: np.ndarray

    def take(self, times) -> PastForecasts:
        """The forecasts issued at ``times`` (each must be present)."""
        times = np.asarray(times, dtype=float)
        idx = np.searchsorted(self.issued, times - 1e-6)
        if np.any(idx >= self.issued.size) or np.any(
            np.abs(self.issued[np.minimum(idx, self.issued.size - 1)] - times) > 1e-6
        ):
            raise ValueError("past forecasts missing for some issue times")
        return PastForecasts(self.issued[idx], self.mean[idx], self.sigma[idx])


def information_set(t, z, issued: float, latency: float, span: float, what: str) -> tuple[np.ndarray, np.ndarray]:
    """The samples a forecast issued at ``issued`` may use: ``t <= issued - latency``, the last ``span`` of them.

    Raises InputError when the issue time is before the record plus the
    method's fitting span (``what`` names the method), or after the last sample
    plus the latency (data that do not exist yet).
    """
    t = np.asarray(t, dtype=float)
    z = np.asarray(z, dtype=complex)
    cutoff = issued - latency
    if cutoff > t[-1] + 0.5 * DAY:
        raise InputError(
            "issued",
            f"{(issued - t[-1]) / DAY:.0f} d after the last sample",
            f"an issue date at most the latency ({latency / DAY:g} d) after the record's last day",
        )
    if cutoff - t[0] < span - 0.5 * DAY:
        raise InputError(
            "issued",
            f"{(cutoff - t[0]) / DAY:.0f} d of data before it",
            f"an issue date at least {span / DAY:.0f} d (the {what} fitting span) plus the latency after the "
            "record's start",
        )
    keep = (t <= cutoff + 1e-6) & (t >= cutoff - span - 1e-6)
    return t[keep], z[keep]


def check_horizon(horizon: float) -> int:
    """The horizon as a number of days, 1 to :data:`MAX_HORIZON`."""
    h = float(horizon)
    days = h / DAY
    # Whole days: the record is daily and the leads are 1, 2, ... days (36 h was taken as 1 d).
    whole = math.isfinite(days) and abs(days - round(days)) <= 1e-9 * max(1.0, abs(days))
    if not (whole and DAY <= h + 1e-9 <= MAX_HORIZON + 1e-9):
        raise InputError(
            "horizon", f"{days:g} d", f"a whole number of days from 1 d to {MAX_HORIZON / DAY:.0f} d (three years)"
        )
    return int(round(days))


def check_method(method: str) -> str:
    """A known forecast method."""
    if method not in METHODS:
        raise InputError("method", method, " or ".join(repr(m) for m in METHODS))
    return method


def daily(t, what: str) -> None:
    """Refuse a fitting span that is not sampled once a day without gaps (the models step by days)."""
    steps = np.diff(np.asarray(t, dtype=float))
    if steps.size and not np.allclose(steps, DAY, rtol=0, atol=1e-3):
        raise InputError(
            "data",
            f"{int(np.sum(~np.isclose(steps, DAY, rtol=0, atol=1e-3)))} gaps in the {what} fitting span",
            "daily samples without gaps",
        )
