"""Whether a scene figure's samples resolve the motion they stand for (its check against aliasing).

Straight lines through samples ``dt`` apart draw a motion of angular frequency ``Omega`` faithfully only
while ``Omega dt`` is small. From ``Omega dt = pi`` on (Nyquist's two samples per period) the samples are
exactly those of a slower motion, the alias: a gyroscope's 600 rad/s body-frame wobble sampled every
0.01 s draws a smooth 28 rad/s wave. Below it, with fewer than four samples per period
(``Omega dt > pi/2``), the chords cut the peaks by up to ``1 - cos(pi/4)`` = 29 % of the amplitude and a
wave sampled near its zeros draws nearly flat. So a panel is drawn with lines only where

    Omega dt <= pi/2                        (:data:`LINES_LIMIT`: four samples per period or more),

``dt`` the largest gap between the samples drawn, and otherwise with markers alone and a note.

The samples cannot give ``Omega``: an alias is as smooth as a resolved motion, so differences between
samples see only the alias. ``Omega`` comes from the equations of motion, evaluated at the samples, and
from what the file records of the body (the ``scene`` attribute ``wobble run`` writes; its body is
rebuilt with :func:`wobble.io.scene_file.body_from_mapping`):

* omega of a free body: it runs on its polhode about the principal axis of largest moment (smallest,
  when ``L^2 < 2 T I_mid``); the rate at which its components across that axis turn is its angular
  speed about it, ``|a . (w_perp x w_perp_dot)| / |w_perp|^2`` with Euler's ``w_dot = I^-1 (I w x w)``
  (Landau & Lifshitz, Mechanics, secs. 36-37; :func:`wobble.models.euler_rates.polhode_turn_rate`): for a
  symmetric body the Euler frequency ``(C - A)/A omega_3`` at every sample, however sparse the samples.
* a series ``x`` whose derivative is known at the samples (the wobble angle of a free body, from
  Euler's equations; the figure axis ``e3``, whose speed is ``|omega x e3| = |(omega_1, omega_2)|``
  by kinematics, or at most ``|L x e3| / min(I_1, I_2)`` when the file has L but not omega): the
  rate ``max |xdot| / max |x - mean x|``, the least frequency a motion of that size and speed has
  (Bernstein's inequality, ``max |xdot| <= Omega max |x - mean|``, with equality for a sinusoid).
  The tilt is the figure axis's too.
* the angular momentum and the energy of a free body are constant (rate 0: what they draw is
  rounding).
* under torques: a torque from a field fixed in space (uniform gravity, a magnetic field: linear in
  the field's direction; a gravity gradient or a tide: quadratic) turns with the body as the body
  sees it, at up to ``2 |omega|``, ``|omega|`` the body's rotation rate (``|L| / I_min`` when the
  file has no omega): the rate of omega and the wobble angle, and of the angular momentum and the
  energy, except for a body symmetric about its axis 3 under torques that depend on its attitude only
  through that axis (a tide, through its inertia tensor ``A 1 + (C - A) e3 e3``; gravity or a magnetic
  field on an arm along the axis: :meth:`wobble.models.torques.TorqueSpec.through_figure_axis`): those
  then move at up to twice the figure axis's rate, the torques being at most quadratic in it. A centre
  of mass off the axis, a torque fixed in the body or damping take the general rate.

A torque's own time dependence adds to these rates: a perturber's tide is quadratic in its direction and
goes as ``1/r^3``, so at a fixed attitude it runs at up to twice its orbit's mean motion and, on an
eccentric orbit, at the harmonics of the distance and the true anomaly, counted up to the highest
above 1e-3 of the largest (:meth:`wobble.models.orbit.KeplerOrbit.tide_rate`; a table's, measured on
it): the Moon's ``2L + l`` and ``2L + 2l`` terms, 5 n = 1.3e-5 rad/s, in the Earth's angular
momentum, where the figure axis alone moves at 1.1e-8 rad/s. With the body turning, the rate is
``2 |omega|`` plus that, or twice the figure axis's rate plus it on the symmetric body above. A file
that does not record its body (a hand-made Dataset) is taken to be under torques from a field fixed in
space, the conservative reading of what it does not say. A bound that cannot be had (no omega, no L, a
torque given as a Python callable) makes no claim.
"""

from __future__ import annotations

import json
import math

import numpy as np

from wobble.numerics.scaled_norm import norm
from wobble.models import euler_rates
from wobble.numerics import quaternion as quat

__all__ = [
    "LINES_LIMIT",
    "series",
    "panel_rates",
    "largest_gap",
    "resolved",
    "note",
    "first_periods",
    "period_count",
    "free_period",
]

LINES_LIMIT = math.pi / 2
# Below this share of a series' size its range is rounding, not motion.
_ROUNDING = 1e-9


def series(var) -> np.ndarray:
    """(time, members, components) whatever the variable's dims."""
    order = [d for d in ("time", "member") if d in var.dims] + [d for d in var.dims if d not in ("time", "member")]
    values = np.asarray(var.transpose(*order).values, dtype=float)
    if "member" not in var.dims:
        values = values[:, None, ...]
    return values.reshape(values.shape[0], values.shape[1], -1)


def largest_gap(times) -> float:
    """The largest spacing of the samples drawn (s); 0 for fewer than two."""
    t = np.asarray(times, dtype=float)
    return float(np.max(np.diff(t))) if t.size > 1 else 0.0


def resolved(rate: float | None, gap: float) -> bool:
    """Whether lines through samples ``gap`` apart draw a motion of angular frequency ``rate`` (rad/s).

    None (no bound from the file) counts as resolved: the figure makes no claim it cannot back.
    """
    return rate is None or not rate * gap > LINES_LIMIT


def note(rate: float, gap: float, every: int = 1) -> str:
    """What a panel drawn with markers says: the spacing and the shortest period it may miss."""
    from wobble.io.text import number, span_unit

    def span(seconds):
        size, symbol = span_unit(seconds)
        return f"{number(seconds / size, 3)} {symbol}"

    period = span(2 * math.pi / rate) if rate > 0 and math.isfinite(rate) else "?"
    drawn = f" (one in {every} drawn)" if every > 1 else ""
    return f"samples {span(gap)} apart{drawn}: motion with periods down to ~{period} not resolved (markers only)"


def first_periods(t_end: float, period: float, most: float, per_period: int, least: int = 2):
    """(times in s, the number of periods in the span or None) of a periodic motion's figure.

    A motion that repeats every ``period`` shows all it does in its first periods; thousands of
    them in a panel only alias into bands. So the times run from 0 over the span or its first
    ``most`` periods, whichever is shorter.

    Parameters
    ----------
    t_end, period : float
        The span and the period (s), both positive.
    most : float
        The periods drawn at most. A span within rounding of ``most`` periods (``t_end = most *
        period`` in floats can give 3.0000000000000004 periods) is not cut.
    per_period, least : int
        Samples a period, and at least ``least`` in all.

    Returns
    -------
    times : ndarray
        The times drawn (s), from 0.
    count : float or None
        ``t_end / period`` when the span was cut, for the title to say so (:func:`period_count`);
        None otherwise.
    """
    count = t_end / period
    cut = count > most * (1 + 1e-12)
    n = max(least, math.ceil(per_period * min(count, most)) + 1)
    return np.linspace(0.0, most * period if cut else t_end, n), (count if cut else None)


def period_count(count: float) -> str:
    """A count of periods for a title: whole and grouped from 100 on (``12,345``), else 3 digits."""
    return f"{count:,.0f}" if count >= 100 else f"{count:.3g}"


def _excursion(x):
    """max |x - mean x| over time (member, component): the amplitude, even from samples that alias."""
    return np.max(np.abs(x - np.mean(x, axis=0)), axis=0)


def _rate(xdot, x) -> float:
    """max |xdot| over the excursion of ``x``, per member and component (arrays (time, member, comp))."""
    floor = _ROUNDING * np.max(np.abs(x), axis=0)
    speed = np.max(np.abs(xdot), axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        rates = np.where(speed > 0, speed / np.maximum(_excursion(x), floor), 0.0)
    return float(np.max(rates)) if rates.size else 0.0


class _Motion:
    """The rates the file's data and the body it records allow (rad/s)."""

    def __init__(self, ds):
        self.ds = ds
        self.members = ds.sizes.get("member", 1)
        self.moments, self.axes, self.principal = None, None, False
        self.torques = True
        # A hand-made Dataset records no torque: taken as one from a field fixed in space, through the axis.
        self.field_rate: float | None = 0.0
        self.through_axis = True
        # Here, not at the top: the free and top figures use this module's sampling rules, not scene files.
        from wobble.io.scene_file import body_from_mapping

        try:
            record = json.loads(ds.attrs["scene"])
            body = body_from_mapping(record["body"])
            self.torques = bool(record.get("torques"))
        except (KeyError, TypeError, ValueError):
            return
        if self.torques:
            self.field_rate, self.through_axis = _torque_facts(record)
        moments = np.asarray(body.moments, dtype=float).reshape(-1, 3)[: self.members]
        axes = np.asarray(body.axes, dtype=float).reshape(-1, 3, 3)[: self.members]
        self.moments, self.axes = moments, axes
        self.principal = bool(np.allclose(axes, np.eye(3), rtol=0, atol=1e-12))

    @property
    def axisymmetric(self) -> bool:
        """Symmetric about body axis 3: its torque from a field fixed in space depends on that axis only."""
        m = self.moments
        return self.principal and m is not None and bool(np.all(np.abs(m[:, 0] - m[:, 1]) <= 1e-12 * m[:, 2]))

    def omega(self):
        return series(self.ds["omega"]) if "omega" in self.ds else None

    def spin(self) -> float | None:
        """The body's largest rotation rate |omega|, or |L| / I_min when the file has no omega."""
        w = self.omega()
        if w is not None:
            return float(np.max(norm(w)))
        if "angular_momentum" in self.ds and self.moments is not None:
            L = series(self.ds["angular_momentum"])
            return float(np.max(norm(L) / np.min(self.moments, axis=-1)))
        return None

    def forced(self) -> float | None:
        """2 |omega| + the torque's own rate: a field as the body sees it, turned by the body and quadratic in
        its direction, plus the field's own time dependence; None where either is unknown."""
        w = self.spin()
        return None if w is None or self.field_rate is None else 2.0 * w + self.field_rate

    def polhode_rate(self, w) -> float:
        """The largest rate at which a free body's omega turns in the body (rad/s):
        :func:`wobble.models.euler_rates.polhode_turn_rate` at the samples."""
        rates = euler_rates.polhode_turn_rate(self.moments, self.axes, w)
        return float(np.max(rates[np.isfinite(rates)], initial=0.0))  # a NaN sample bounds nothing

    def figure_axis(self):
        """Body axis 3 in the inertial frame (time, member, 3), or None."""
        if "axis_direction" in self.ds:
            return series(self.ds["axis_direction"])
        if "attitude" in self.ds:
            return quat.rotate(series(self.ds["attitude"]), np.array([0.0, 0.0, 1.0]))
        return None

    def axis_speed(self, e3):
        """|d e3/dt| at the samples (time, member), or None."""
        w = self.omega()
        if w is not None:
            return np.hypot(w[..., 0], w[..., 1])
        if "angular_momentum" not in self.ds or self.moments is None:
            return None
        L = series(self.ds["angular_momentum"])
        if self.principal:
            # omega's part across e3 is (L_1/I_1, L_2/I_2) in the body frame.
            return norm(np.cross(L, e3)) / np.min(self.moments[:, :2], axis=-1)
        return norm(L) / np.min(self.moments, axis=-1)

    def axis_rate(self) -> float | None:
        """The figure axis's rate: its speed over its excursion (rad/s)."""
        e3 = self.figure_axis()
        if e3 is None:
            return self.spin()
        speed = self.axis_speed(e3)
        if speed is None:
            return None
        size = np.max(_excursion(e3), axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            rates = np.where(speed.max(axis=0) > 0, speed.max(axis=0) / np.maximum(size, _ROUNDING), 0.0)
        return float(np.max(rates))

    def omega_rate(self) -> float | None:
        w = self.omega()
        if w is None:
            return None
        if self.torques or self.moments is None:
            return self.forced()
        return self.polhode_rate(w)

    def wobble_rate(self) -> float | None:
        if self.torques or self.moments is None or self.omega() is None:
            return self.forced()
        angle_dot = euler_rates.wobble_angle_rate(self.moments, self.axes, self.omega())
        return _rate(angle_dot[..., None], series(self.ds["wobble_angle"]))

    def conserved_rate(self) -> float | None:
        """The angular momentum's and the energy's rate: 0 for a free body."""
        if not self.torques and self.moments is not None:
            return 0.0
        if self.axisymmetric and self.through_axis:
            # Its torque is quadratic in the figure axis (through A 1 + (C - A) e3 e3): twice the axis's rate.
            axis = self.axis_rate()
            return None if axis is None or self.field_rate is None else 2.0 * axis + self.field_rate
        return self.forced()


def _torque_facts(record: dict) -> tuple[float | None, bool]:
    """(the fastest own rate (rad/s) of a recorded scene's torques, None when one is unknown or unreadable;
    whether they all act on a symmetric body through its figure axis alone)
    (:meth:`wobble.models.torques.TorqueSpec.field_rate`, ``through_figure_axis``)."""
    from wobble.io.scene_file import scene_from_mapping

    try:
        specs = scene_from_mapping(record).torques
    except (KeyError, TypeError, ValueError):  # wobble's own errors are ValueErrors
        return None, False
    rates = [spec.field_rate() for spec in specs]
    rate = None if any(x is None for x in rates) else max(rates, default=0.0)
    return rate, all(spec.through_figure_axis() for spec in specs)


def free_period(ds) -> float | None:
    """The period (s) of omega of the one free body a file records (its ``scene`` attribute, no torques),
    from the exact solution at the first sample; None for an ensemble, a torqued body, a file without its
    body, or an aperiodic motion (a separatrix, a steady spin)."""
    from wobble.models.free import free_rotation

    m = _Motion(ds)
    if m.torques or m.moments is None or m.members != 1 or "omega" not in ds:
        return None
    w0 = series(ds["omega"])[0, 0]
    if not np.all(np.isfinite(w0)):
        return None
    period = free_rotation(m.moments[0], m.axes[0] @ w0).period
    return period if math.isfinite(period) and period > 0 else None


def panel_rates(ds) -> dict:
    """The fastest angular frequency (rad/s) each panel kind can carry, or None where the file gives no bound.

    Keys: ``omega``, ``angular_momentum``, ``energy``, ``tilt``, ``wobble_angle``, ``axis`` (see the
    module docstring).
    """
    m = _Motion(ds)
    return {
        "omega": m.omega_rate(),
        "angular_momentum": m.conserved_rate(),
        "energy": m.conserved_rate(),
        "tilt": m.axis_rate(),
        "wobble_angle": m.wobble_rate() if "wobble_angle" in ds else None,
        "axis": m.axis_rate(),
    }
