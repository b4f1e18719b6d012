"""Where a perturbing body is: a Keplerian orbit with secular rates, or an ephemeris table (SI).

:class:`KeplerOrbit` holds the elements of a bound orbit about the body's centre
(semi-major axis, eccentricity, inclination, longitude of the node and argument of
periapsis at the epoch t = 0, mean anomaly at the epoch, mean motion, and the secular
rates of the node and the periapsis: the Moon's regression in 18.6 years, its apsides'
advance in 8.85 years), in the inertial frame of the run (x-y the reference plane, x the
origin of longitudes). The position at any time comes from Kepler's equation
(:mod:`wobble.numerics.kepler`; Murray & Dermott 1999, *Solar System Dynamics*, sec. 2.4).

:class:`EphemerisTable` holds positions tabulated at increasing times (an ephemeris the
user computed elsewhere) and interpolates each component with a not-a-knot cubic spline
(de Boor 1978, *A Practical Guide to Splines*): the error is about
``(5/384) h^4 |r''''|``, i.e. ``(5/384) (n h)^4`` of the distance for an orbit of mean motion
n tabulated every h (6-hour steps for the Moon: 1e-7). It refuses times that are not
strictly increasing, and evaluation outside the table.

Everything in SI: m, s, rad.
"""

from __future__ import annotations

import bisect
import functools
import math
from dataclasses import dataclass, field

import numpy as np

from wobble.errors import InputError
from wobble.numerics import kepler

__all__ = ["KeplerOrbit", "EphemerisTable", "rms_radius", "TIDE_FLOOR", "tide_harmonic"]

#: A tide's harmonics smaller than this share of its largest are not counted in its fastest frequency:
#: below what a figure's line shows.
TIDE_FLOOR = 1e-3
# Samples of a table's tide in one window (about 12 MB a component); a longer table takes several.
_TABLE_WINDOW = 2**18


@functools.lru_cache(maxsize=64)
def tide_harmonic(e: float, floor: float = TIDE_FLOOR) -> int:
    """The highest harmonic k of the mean motion in ``1/r^3`` and ``exp(2 i nu)/r^3`` over a Keplerian orbit
    of eccentricity ``e`` whose amplitude reaches ``floor`` of the largest.

    Both are sampled at N equal steps of the mean anomaly (Kepler's equation, then the true anomaly;
    Murray & Dermott 1999, sec. 2.4), N a power of two some eight times the periapsis passage's
    spectral width ``12 sqrt(1 + e) / (1 - e)^(3/2)`` (in harmonics), and transformed (FFT): exact
    for these periodic series up to aliasing, which N keeps below ``floor``. 2 for a circle; for e near 1,
    at most 2^20 samples (e up to about 0.997; beyond, the width itself, which is larger than the
    harmonic measured at e = 0.998 by 1.4). Cached: a figure asks once per perturber.
    """
    if e == 0:
        return 2
    width = 12.0 * math.sqrt(1.0 + e) / (1.0 - e) ** 1.5
    count = 2 ** max(6, math.ceil(math.log2(8.0 * (width + 2.0))))
    if count > 2**20:
        return int(math.ceil(width)) + 2
    m = 2.0 * math.pi * np.arange(count) / count
    big_e = kepler.solve_kepler(m, e)
    nu = 2.0 * np.arctan2(math.sqrt(1.0 + e) * np.sin(0.5 * big_e), math.sqrt(1.0 - e) * np.cos(0.5 * big_e))
    inverse_cube = (1.0 - e * np.cos(big_e)) ** -3.0  # (a/r)^3
    radial = np.abs(np.fft.fft(inverse_cube))
    radial[0] = 0.0  # the mean: no frequency
    quadratic = np.abs(np.fft.fft(inverse_cube * np.exp(2j * nu)))
    harmonic = np.abs(np.fft.fftfreq(count, 1.0 / count))
    amplitude = np.maximum(radial, quadratic)
    return int(np.max(harmonic[amplitude >= floor * np.max(amplitude)]))


@dataclass(frozen=True)
class KeplerOrbit:
    """A bound Keplerian orbit with secular node and periapsis rates (SI, inertial frame).

    Attributes
    ----------
    semi_major_axis : float
        a, m.
    eccentricity : float
        e in [0, 1) (e >= 1 is parabolic or hyperbolic: refused).
    inclination : float
        i to the inertial x-y plane, rad, in [0, pi].
    longitude_of_node : float
        Omega at t = 0 from the inertial x axis, rad.
    argument_of_periapsis : float
        w at t = 0 from the ascending node, rad.
    mean_anomaly : float
        M at t = 0, rad.
    mean_motion : float
        dM/dt, rad/s (the anomalistic mean motion; >= 0).
    node_rate, periapsis_rate : float
        dOmega/dt and dw/dt, rad/s (the Moon: -1.07e-8 and +3.3e-9 in inertial space).
    """

    semi_major_axis: float
    eccentricity: float = 0.0
    inclination: float = 0.0
    longitude_of_node: float = 0.0
    argument_of_periapsis: float = 0.0
    mean_anomaly: float = 0.0
    mean_motion: float = 0.0
    node_rate: float = 0.0
    periapsis_rate: float = 0.0

    def __post_init__(self):
        a, e, i = self.semi_major_axis, self.eccentricity, self.inclination
        if not (math.isfinite(a) and a > 0):
            raise InputError("semi_major_axis", a, "a positive, finite length (m)")
        if not (math.isfinite(e) and 0.0 <= e < 1.0):
            raise InputError("eccentricity", e, "0 <= e < 1 (a bound orbit; e >= 1 is parabolic or hyperbolic)")
        if not (math.isfinite(i) and 0.0 <= i <= math.pi):
            raise InputError(
                "inclination", f"{math.degrees(i):.6g} deg" if math.isfinite(i) else i, "an angle in [0, 180] deg"
            )
        if not (math.isfinite(self.mean_motion) and self.mean_motion >= 0):
            raise InputError("mean_motion", self.mean_motion, "a non-negative, finite angular speed (rad/s)")
        for name in ("longitude_of_node", "argument_of_periapsis", "mean_anomaly", "node_rate", "periapsis_rate"):
            if not math.isfinite(getattr(self, name)):
                raise InputError(name, getattr(self, name), "a finite number")

    @property
    def elements(self) -> np.ndarray:
        """The element row of :data:`wobble.numerics.kepler.ELEMENTS`."""
        return np.array(
            [
                self.semi_major_axis,
                self.eccentricity,
                self.inclination,
                self.longitude_of_node,
                self.argument_of_periapsis,
                self.mean_anomaly,
                self.mean_motion,
                self.node_rate,
                self.periapsis_rate,
            ]
        )

    @property
    def periapsis(self) -> float:
        """a (1 - e), m: the closest approach."""
        return self.semi_major_axis * (1.0 - self.eccentricity)

    @property
    def moving(self) -> bool:
        """Whether the position changes with time."""
        return self.mean_motion != 0.0 or self.node_rate != 0.0 or self.periapsis_rate != 0.0

    @property
    def normal(self) -> np.ndarray:
        """Unit normal of the orbit plane at t = 0 (inertial frame)."""
        i, node = self.inclination, self.longitude_of_node
        return np.array([math.sin(i) * math.sin(node), -math.sin(i) * math.cos(node), math.cos(i)])

    def position(self, t):
        """Positions (n, 3) and distances (n,) at times t (s): :func:`wobble.numerics.kepler.position`."""
        return kepler.position(t, self.elements)

    def tide_rate(self, floor: float = TIDE_FLOOR) -> float:
        """The fastest angular frequency (rad/s) of the tide this body raises at a fixed attitude.

        The tide's torque is quadratic in the direction u and goes as ``1/r^3`` (MacCullagh):
        its time dependence is that of ``u u^T / r^3``, in the orbit's plane ``1/r^3`` and
        ``exp(2 i nu) / r^3`` (nu the true anomaly), periodic in the mean anomaly. Their harmonics
        ``k n`` are counted up to the highest whose amplitude reaches ``floor`` of the largest
        (:func:`tide_harmonic`: 2 for a circular orbit, 5 for the Moon's e = 0.055, 1064 for
        e = 0.95, whose periapsis passages are brief); the secular turns of the plane and the
        periapsis add ``2 (|dOmega/dt| + |dw/dt|)``.
        """
        secular = 2.0 * (abs(self.node_rate) + abs(self.periapsis_rate))
        if self.mean_motion == 0:
            return secular
        return secular + tide_harmonic(self.eccentricity, floor) * self.mean_motion


def _spline_coefficients(times, positions):
    """Not-a-knot cubic spline of each component: coefficients (4, K - 1, 3), highest power first."""
    from scipy.interpolate import CubicSpline

    return np.ascontiguousarray(CubicSpline(times, positions, axis=0, bc_type="not-a-knot").c)


@dataclass(frozen=True)
class EphemerisTable:
    """Positions of a perturber tabulated at increasing times, interpolated by cubic splines (SI).

    Attributes
    ----------
    times : numpy.ndarray (K,)
        Strictly increasing times (s, the run's clock), K >= 4.
    positions : numpy.ndarray (K, 3)
        Positions relative to the body's centre in the inertial frame (m).
    """

    times: np.ndarray
    positions: np.ndarray
    coefficients: np.ndarray = field(init=False, repr=False, compare=False)
    _knots: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float)
        p = np.asarray(self.positions, dtype=float)
        if t.ndim != 1 or t.size < 4 or not np.all(np.isfinite(t)):
            raise InputError(
                "ephemeris.times", f"{t.size} values" if t.ndim == 1 else t.shape, "at least 4 finite times (s)"
            )
        if np.any(np.diff(t) <= 0):
            k = int(np.flatnonzero(np.diff(t) <= 0)[0])
            raise InputError(
                "ephemeris.times",
                f"t[{k + 1}] = {t[k + 1]!r} s after t[{k}] = {t[k]!r} s",
                "strictly increasing times (a table monotone in time)",
            )
        if p.shape != (t.size, 3) or not np.all(np.isfinite(p)):
            raise InputError("ephemeris.positions", p.shape, f"({t.size}, 3) finite positions (m), one per time")
        if np.any(np.linalg.norm(p, axis=1) == 0):
            raise InputError("ephemeris.positions", "a zero vector", "positions away from the body's centre")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "coefficients", _spline_coefficients(t, p))
        object.__setattr__(self, "_knots", tuple(t.tolist()))  # bisect on floats: the scalar path

    @property
    def span(self) -> tuple[float, float]:
        """The first and last tabulated times (s)."""
        return float(self.times[0]), float(self.times[-1])

    @property
    def closest(self) -> float:
        """The smallest tabulated distance (m)."""
        return float(np.min(np.linalg.norm(self.positions, axis=1)))

    def check_covers(self, start: float, stop: float) -> None:
        """Refuse a run from ``start`` to ``stop`` (s) that the table does not cover."""
        t0, t1 = self.span
        if start < t0 or stop > t1:
            raise InputError(
                "ephemeris.times", f"[{t0!r}, {t1!r}] s", f"a table covering the run's span [{start!r}, {stop!r}] s"
            )

    def _check(self, t):
        t0, t1 = self.span
        if np.any(t < t0) or np.any(t > t1):
            bad = float(np.asarray(t)[(t < t0) | (t > t1)].flat[0])
            raise InputError("ephemeris.times", f"[{t0!r}, {t1!r}] s", f"a table covering t = {bad!r} s")

    def position(self, t):
        """Interpolated positions (n, 3) and distances (n,) at times t (s)."""
        t = np.asarray(t, dtype=float)
        self._check(t)
        k = np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, self.times.size - 2)
        dt = (t - self.times[k])[..., None]
        c = self.coefficients
        r = ((c[0, k] * dt + c[1, k]) * dt + c[2, k]) * dt + c[3, k]
        return r, np.sqrt(np.sum(r * r, axis=-1))

    def tide_rate(self, floor: float = TIDE_FLOOR) -> float:
        """The fastest angular frequency (rad/s) of the tide the tabulated body raises at a fixed attitude.

        :meth:`KeplerOrbit.tide_rate` measured on the table: ``u u^T / r^3`` sampled from the splines at
        half the table's smallest spacing, its mean taken out, Hann-windowed (the table need not hold
        whole periods), and its frequencies counted up to the highest whose amplitude reaches ``floor``
        of the largest; the result is that frequency bin's upper edge. Past 2^18 samples the table is
        taken in windows of 2^18 overlapping by half, the largest amplitude of each frequency kept (one
        window, sampled more coarsely, aliased: a 1.2-million-row table of an e = 0.3 orbit read 8.5 n
        against its 13 n). A measurement, not a bound: the window's leakage reads a few bins high, and
        a brief event within the first or last few per cent of a window reads low (one period of an
        e = 0.9 orbit starting at periapsis: 195 n against its 340 n). A table whose position does not
        change (to rounding) gives 0.
        """
        t0, t1 = self.span
        step = 0.5 * float(np.min(np.diff(self.times)))
        count = int(math.floor((t1 - t0) / step)) + 1
        size = min(count, _TABLE_WINDOW)
        starts = sorted({*range(0, count - size + 1, size // 2), count - size})
        window = np.hanning(size)
        rows, cols = np.triu_indices(3)
        largest, biggest = np.zeros(size // 2 + 1), 0.0
        for first in starts:
            r, d = self.position(np.minimum(t0 + np.arange(first, first + size) * step, t1))
            u = r / d[:, None]
            tide = u[:, rows] * u[:, cols] / d[:, None] ** 3
            biggest = max(biggest, float(np.max(np.abs(tide))))
            tide -= np.sum(window[:, None] * tide, axis=0) / np.sum(window)
            largest = np.maximum(largest, np.max(np.abs(np.fft.rfft(window[:, None] * tide, axis=0)), axis=1))
        if not np.max(largest) > 1e-12 * size * biggest:  # rounding: the perturber stands still
            return 0.0
        top = int(np.flatnonzero(largest >= floor * np.max(largest))[-1])
        return 2.0 * math.pi * (top + 1) / (size * step)  # the bin's upper edge: not below the line

    def position_one(self, t: float) -> tuple[float, float, float, float]:
        """:meth:`position` for one time in Python floats: (x, y, z, |r|)."""
        t0, t1 = self.span
        if not (t0 <= t <= t1):
            self._check(np.array([t]))
        k = min(max(bisect.bisect_right(self._knots, t) - 1, 0), len(self._knots) - 2)
        dt = t - self._knots[k]
        c = self.coefficients[:, k, :]
        x, y, z = (
            ((float(c[0, j]) * dt + float(c[1, j])) * dt + float(c[2, j])) * dt + float(c[3, j]) for j in range(3)
        )
        return x, y, z, math.sqrt(x * x + y * y + z * z)


def rms_radius(moments, mass: float) -> float:
    """sqrt((I1 + I2 + I3) / (2 M)), m: the RMS distance of the body's mass from its centre.

    Some of the mass lies at least this far out, so a perturber closer than this is inside
    the body (sum of m r^2 = (I1 + I2 + I3)/2 for any mass distribution).
    """
    return math.sqrt(float(np.sum(np.asarray(moments, dtype=float)[..., :3].reshape(-1, 3)[0])) / (2.0 * mass))
