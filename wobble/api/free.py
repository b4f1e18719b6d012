"""Torque-free rotation with units: :class:`FreeRotation` (Quantities in, xarray out).

The physics is :mod:`wobble.models.free`; this module converts units once on
the way in and once on the way out and lays the result out as a CF Dataset.

Example
-------
>>> import astropy.units as u
>>> from wobble import FreeRotation
>>> body = FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)
>>> body.regime
'major-axis'
>>> ds = body.to_dataset(t_end=100 * u.s, samples=1001)
>>> sorted(ds.data_vars)[:3]
['angular_momentum', 'angular_momentum_magnitude', 'angular_momentum_magnitude_drift']
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from astropy import units as u

from wobble.numerics.scaled_norm import norm
from wobble.api.sampling import sample_times
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.io import cf
from wobble.io.json_keys import deprecate, error_estimate_renames
from wobble.models import free as _free

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["FreeRotation", "MOMENT_UNIT", "BYTES_PER_SAMPLE"]

MOMENT_UNIT = u.kg * u.m**2
_RATE = u.rad / u.s
_LMOM = u.kg * u.m**2 / u.s
# Float64 values held per sample while a Dataset is built (time, omega, attitude,
# energy and |L| with drifts, and the temporaries of the evaluation), in bytes.
BYTES_PER_SAMPLE = 8 * 64


class FreeRotation:
    """Exact torque-free motion of a rigid body.

    Parameters
    ----------
    moments : astropy.units.Quantity or wobble.RigidBody
        The three principal moments of inertia in any order (e.g.
        ``[1, 2, 3] * u.kg * u.m**2``), or a rigid body, whose principal moments are
        taken in ascending order (``body.principal_moments``). Outputs keep this axis order.
    omega0 : astropy.units.Quantity
        Angular velocity at t = 0, 3 components in rad/s or any angular-speed unit, in the
        principal frame of the moments given; for a rigid body, in the body's own (input)
        frame, as :func:`wobble.run` reads it, turned here into principal components
        (``body.principal_axes @ omega0``; :attr:`principal_axes` keeps that matrix). Zero is
        allowed (no motion).

    Raises
    ------
    wobble.errors.InputError
        Wrong units or shape, non-finite values, non-positive moments, or
        moments violating the triangle inequality.

    Notes
    -----
    Exact closed forms (docs/free-rotation.md): the symmetric precession of
    Goldstein, Poole & Safko 2002 (sec. 5.6), the Jacobi elliptic solution of Landau & Lifshitz
    section 37 in both regimes, the separatrix, and the exact attitude.

    Examples
    --------
    A body spun almost exactly about its intermediate axis flips over and over
    (the tennis-racket, or Dzhanibekov, effect):

    >>> import wobble
    >>> from astropy import units as u
    >>> spin = wobble.FreeRotation([1, 2, 3] * u.kg * u.m**2, [1e-6, 1, 1e-6] * u.rad / u.s)
    >>> print(spin.regime, f"flip every {spin.time_between_flips:.2f}")
    major-axis flip every 51.46 s
    >>> ds = spin.to_dataset(t_end=100 * u.s, samples=11)  # xarray Dataset, CF attributes
    >>> ds["omega"].dims
    ('time', 'axis')
    """

    def __init__(self, moments, omega0):
        axes = np.eye(3)
        if not isinstance(moments, u.Quantity) and hasattr(moments, "principal_moments"):
            # A body's omega0 is in its own frame, as wobble.run reads it: taken as principal components it
            # spun a box with edges (1, 2, 3) given omega along x about its z axis (ascending order puts the
            # smallest moment first), and a body with products of inertia about no axis it was given.
            axes = np.asarray(getattr(moments, "principal_axes", axes), dtype=float)
            moments = moments.principal_moments
        I = to_si(moments, "moments", MOMENT_UNIT, positive=True, shape=(3,))
        w = axes @ to_si(omega0, "omega0", _RATE, shape=(3,))
        self._axes = axes
        self._model = _free.free_rotation(I, w)

    @property
    def principal_axes(self) -> np.ndarray:
        """Rows: the principal axes of the outputs in the frame ``omega0`` was given in (the identity unless a
        rigid body was given); ``principal_axes.T @ v`` takes an output vector back to that frame."""
        return self._axes.copy()

    # -- summary quantities -------------------------------------------------
    @property
    def model(self) -> _free.FreeRotationModel:
        """The SI model underneath (floats and arrays, no units)."""
        return self._model

    @property
    def moments(self) -> u.Quantity:
        """Principal moments (kg m2), in the order given."""
        return np.asarray(self._model.moments) << MOMENT_UNIT

    @property
    def omega0(self) -> u.Quantity:
        """Initial angular velocity in the body frame (rad/s)."""
        return np.asarray(self._model.omega0) << _RATE

    @property
    def regime(self) -> str:
        """'steady', 'symmetric', 'major-axis' (L^2 > 2EI2), 'minor-axis' (L^2 < 2EI2) or 'separatrix'."""
        return self._model.regime

    @property
    def parameter(self) -> float:
        """Parameter m = k^2 of the Jacobi functions (0 for steady or symmetric motion)."""
        return self._model.m

    @property
    def complementary_parameter(self) -> float:
        """1 - m, computed exactly from the invariants (not as 1 - m in floats)."""
        return self._model.m1

    @property
    def modulus(self) -> float:
        """Modulus k = sqrt(m)."""
        return float(np.sqrt(self._model.m))

    @property
    def period(self) -> u.Quantity:
        """Period of omega(t) (inf on the separatrix and for steady spin)."""
        return self._model.period << u.s

    @property
    def time_between_flips(self) -> u.Quantity | None:
        """Time between tennis-racket flips, 2K/lambda (half the period), or None when the body does
        not flip (see :attr:`flips`: for a small wobble the sign changes of the intermediate component
        are half periods of the wobble, not flips)."""
        t = self._model.time_between_flips
        return None if t is None or not self.flips else t << u.s

    @property
    def intermediate_axis_swing(self) -> u.Quantity | None:
        """How far the intermediate principal axis swings about the plane normal to L (degrees).

        The axis moves between arccos(c) and 180 deg - arccos(c) from L, a swing of
        180 deg - 2 arccos(c) (see :func:`wobble.models.free.intermediate_axis_alignment`):
        180 deg is a full tennis-racket flip, a few micro-degrees Earth's wobble.
        None for a symmetric body or no rotation.
        """
        c = _free.intermediate_axis_alignment(self._model.moments, self._model.omega0)
        if c is None:
            return None
        if self._model.regime == "steady":  # a steady spin (even about the intermediate axis) never moves
            return 0.0 << u.deg
        return (180.0 - 2.0 * np.degrees(np.arccos(c))) << u.deg

    @property
    def flips(self) -> bool:
        """Whether the body turns over (tennis-racket flips): the intermediate axis swings by
        more than 90 deg, so each sign change of its omega component is a flip of the body,
        not a half-period of a small wobble."""
        swing = self.intermediate_axis_swing
        return swing is not None and swing.to_value(u.deg) > 90.0

    def flip_times(self, t_end, t_start=0 * u.s) -> u.Quantity:
        """Times of the flips between ``t_start`` and ``t_end``: the sign changes of the intermediate-axis
        component of omega; empty when the body does not flip (:attr:`flips`)."""
        t1 = to_si(t_end, "t_end", u.s, shape=())
        t0 = to_si(t_start, "t_start", u.s, shape=())
        if not self.flips:
            return np.empty(0) << u.s
        return self._model.flip_times(t0, t1) << u.s

    def flip_count(self, t_end, t_start=0 * u.s) -> int:
        """How many flips :meth:`flip_times` lists between ``t_start`` and ``t_end``, counted without listing
        them (over a long span they would not fit in memory); 0 when the body does not flip."""
        t1 = to_si(t_end, "t_end", u.s, shape=())
        t0 = to_si(t_start, "t_start", u.s, shape=())
        return self._model.flip_count(t0, t1) if self.flips else 0

    @property
    def energy(self) -> u.Quantity:
        """Kinetic energy T (J)."""
        return self._model.energy << u.J

    @property
    def angular_momentum(self) -> u.Quantity:
        """The magnitude of the angular momentum, ``|L|`` (kg m2 / s)."""
        return self._model.angular_momentum << _LMOM

    @property
    def angular_momentum_inertial(self) -> u.Quantity:
        """L in the inertial frame (kg m2 / s); the body frame at t = 0."""
        return self._model.angular_momentum_inertial << _LMOM

    @property
    def max_time(self) -> u.Quantity:
        """The largest time from t = 0, either way, at which the motion is given (s): 2^50 - 1 turns of
        the fastest of its reduced phases (the phases are reduced exactly up to there); inf at rest."""
        return self._model.max_time << u.s

    @property
    def error_estimate(self) -> dict:
        """Error bounds of the solution: relative error of omega, attitude angle (rad)."""
        return dict(self._model.error_estimate)

    def to_dict(self) -> dict:
        """A JSON-ready summary in SI (keys end in their unit), as ``wobble free --json`` prints."""
        mdl = self._model
        swing = self.intermediate_axis_swing
        flips = self.flips
        err = dict(mdl.error_estimate)
        out = {
            "regime": mdl.regime,
            "moments_kg_m2": list(mdl.moments),
            "omega0_rad_per_s": list(mdl.omega0),
            "parameter_m": mdl.m,
            "complementary_parameter_1_minus_m": mdl.m1,
            "modulus_k": self.modulus,
            "period_s": mdl.period if np.isfinite(mdl.period) else None,
            "flips": flips,
            "intermediate_axis_swing_deg": None if swing is None else float(swing.to_value(u.deg)),
            "time_between_flips_s": mdl.time_between_flips if flips else None,
            "energy_J": mdl.energy,
            "angular_momentum_kg_m2_per_s": mdl.angular_momentum,
            "precession_rate_rad_per_s": mdl.precession_rate,
            **{f"error_estimate_{k}": v for k, v in err.items()},
            "error_estimate": {},
        }
        return deprecate(out, error_estimate_renames(err))

    def summary(self) -> str:
        """The motion in words: regime, period, whether the body flips."""
        from wobble.io.text import duration, number

        d = self.to_dict()
        text = f"{d['regime']} rotation, omega repeats every {duration(d['period_s'])}"
        if d["flips"]:
            return text + f"; the body flips every {duration(d['time_between_flips_s'])}"
        swing = d["intermediate_axis_swing_deg"]
        return text + ("" if swing is None else f"; no flips (the intermediate axis swings by {number(swing, 4)} deg)")

    def __repr__(self) -> str:
        return f"FreeRotation(moments={self.moments}, omega0={self.omega0}, regime={self.regime!r})"

    # -- evaluation ---------------------------------------------------------
    def omega(self, t) -> u.Quantity:
        """Body-frame angular velocity at times ``t`` (a time Quantity), shape t.shape + (3,)."""
        ts = to_si(t, "t", u.s)
        return self._model.omega(np.asarray(ts, dtype=float)) << _RATE

    def attitude(self, t) -> np.ndarray:
        """Unit quaternions (w, x, y, z) body -> inertial at times ``t``; identity at t = 0."""
        ts = to_si(t, "t", u.s)
        return self._model.attitude(np.asarray(ts, dtype=float))

    def evaluate(self, t=None, *, t_end=None, samples: int | None = None) -> xr.Dataset:
        """Deprecated alias of :meth:`to_dataset` (one name per action across wobble)."""
        import warnings

        warnings.warn(
            "FreeRotation.evaluate is deprecated; use FreeRotation.to_dataset", DeprecationWarning, stacklevel=2
        )
        return self.to_dataset(t, t_end=t_end, samples=samples)

    def to_dataset(self, t=None, *, t_end=None, samples: int | None = None) -> xr.Dataset:
        """The motion as a CF Dataset at times ``t`` or at ``samples`` times in [0, t_end].

        Parameters
        ----------
        t : astropy.units.Quantity, optional
            Times (1-D).
        t_end : astropy.units.Quantity, optional
            End time, with ``samples`` evenly spaced outputs from 0 (inclusive).
        samples : int, optional
            Number of outputs (>= 1).

        Returns
        -------
        xarray.Dataset
            ``time`` (s, CF units ``seconds since 2000-01-01 12:00:00``),
            ``omega(time, axis)``, ``angular_momentum(inertial_axis)`` (X, Y, Z: the body axes at t = 0),
            ``attitude(time, component)``, ``kinetic_energy``,
            ``kinetic_energy_drift``, ``angular_momentum_magnitude`` and
            ``angular_momentum_magnitude_drift`` (time).

        Raises
        ------
        wobble.errors.InputError
            Neither or both of ``t`` and ``t_end``; bad ``samples``; a request
            that would not fit in memory (the message gives the size needed); times
            beyond :attr:`max_time`.
        """
        ts = self._times(t, t_end, samples)
        mdl = self._model
        try:
            omega, q = mdl.state(ts)
        except InputError as exc:
            if exc.parameter != "t" or t is not None:
                raise
            raise InputError("t_end", t_end, exc.allowed) from None
        I = np.asarray(mdl.moments)
        energy = 0.5 * np.sum((I * omega) * omega, axis=-1)  # (I w) w: I w^2 of I = 1e300, w = 1e-300 is 1e-300
        lw = I * omega
        lmag = norm(lw)  # scaled: no square to underflow (|L| of 1e-300)
        return self._dataset(ts, omega, q, energy, lmag)

    def _times(self, t, t_end, samples):
        return sample_times(t, t_end, samples, BYTES_PER_SAMPLE)

    def _dataset(self, ts, omega, q, energy, lmag) -> xr.Dataset:
        from wobble.api.dataset import build

        mdl = self._model
        e0, l0 = mdl.energy, mdl.angular_momentum

        def var(name, data):
            return cf.variable("free", name, data)

        ds = build(
            {
                "omega": var("omega", omega),
                "angular_momentum": var("angular_momentum", mdl.angular_momentum_inertial),
                "attitude": var("attitude", q),
                "kinetic_energy": var("kinetic_energy", energy),
                "kinetic_energy_drift": var("kinetic_energy_drift", energy - e0),
                "angular_momentum_magnitude": var("angular_momentum_magnitude", lmag),
                "angular_momentum_magnitude_drift": var("angular_momentum_magnitude_drift", lmag - l0),
            },
            coords={
                "time": cf.time_coordinate(ts),
                "axis": cf.label_coordinate("axis"),
                "inertial_axis": cf.label_coordinate("inertial_axis"),
                "component": cf.label_coordinate("component"),
                "moment_of_inertia": var("moment_of_inertia", np.asarray(mdl.moments)),
            },
            attrs={
                "title": "Torque-free rigid-body rotation (exact solution)",
                "references": "Landau & Lifshitz, Mechanics, section 37; Goldstein, Poole & Safko 2002, Classical "
                "Mechanics, "
                "section 5.6",
                "regime": mdl.regime,
                "elliptic_parameter_m": mdl.m,
                "elliptic_complementary_parameter": mdl.m1,
                "kinetic_energy_J": e0,
                "angular_momentum_kg_m2_per_s": l0,
            },
        )
        if np.isfinite(mdl.period):
            ds.attrs["period_s"] = mdl.period
        # Not for a wobble, whose sign changes are not flips, nor on the separatrix (one flip: None), as period_s.
        if self.flips and mdl.time_between_flips is not None:
            ds.attrs["time_between_flips_s"] = mdl.time_between_flips
        return ds
