"""Torques with units: :class:`Torque` (Quantities in, engine specifications out).

Each constructor converts its Quantities to SI once and returns a
:class:`Torque` that scenes (:class:`wobble.Scene`) accept. See
docs/engine.md for the equations.

Example
-------
>>> import astropy.units as u
>>> from wobble import Torque
>>> top = Torque.gravity(mass=1 * u.kg, center_of_mass=[0, 0, 4] * u.cm)
>>> top.kind
'gravity'
>>> Torque.constant([0, 0, 2] * u.mN * u.m).spec.torque
array([0.   , 0.   , 0.002])
"""

from __future__ import annotations

import numpy as np
from astropy import units as u

from wobble.api._units import to_si
from wobble.errors import InputError
from wobble.models import engine as _eng

__all__ = ["Torque"]

_TORQUE = u.N * u.m


class Torque:
    """A torque acting on a scene's body (build with the class methods).

    Attributes
    ----------
    kind : str
        ``constant``, ``gravity``, ``gravity_gradient``, ``damping`` or ``custom``.
    spec : object
        The SI specification in :mod:`wobble.models.engine`.
    """

    __slots__ = ("spec",)

    def __init__(self, spec):
        self.spec = spec

    @property
    def kind(self) -> str:
        """The torque's kind."""
        return self.spec.kind

    def __repr__(self) -> str:
        return f"Torque.{self.kind}(...)"

    @classmethod
    def constant(cls, torque, frame: str = "body") -> Torque:
        """A constant torque (N m), fixed in the ``"body"`` or the ``"inertial"`` frame.

        ``torque`` has shape (3,) or (N, 3) (one per ensemble member).
        """
        tau = to_si(torque, "torque", _TORQUE)
        if np.shape(tau)[-1:] != (3,):
            raise InputError("torque", torque, "a 3-vector torque Quantity (e.g. [0, 0, 1] * u.N * u.m)")
        if frame not in ("body", "inertial"):
            raise InputError("frame", frame, "'body' or 'inertial'")
        return cls(_eng.ConstantTorque(np.asarray(tau), frame))

    @classmethod
    def gravity(cls, mass, center_of_mass, g=_eng.STANDARD_GRAVITY * u.m / u.s**2) -> Torque:
        """Uniform gravity about a fixed pivot: ``tau = r x m g`` (notes section 5.7).

        Parameters
        ----------
        mass : Quantity
            Mass of the body.
        center_of_mass : Quantity, shape (3,) or (N, 3)
            Centre of mass from the pivot, body frame (the body's moments must
            be about the pivot).
        g : Quantity
            A magnitude (gravity along the inertial -z axis) or an inertial
            acceleration vector (3,).
        """
        m = to_si(mass, "mass", u.kg, positive=True)
        r = to_si(center_of_mass, "center_of_mass", u.m)
        if np.shape(r)[-1:] != (3,):
            raise InputError("center_of_mass", center_of_mass, "a 3-vector length Quantity (body frame)")
        gv = to_si(g, "g", u.m / u.s**2)
        gv = np.array([0.0, 0.0, -float(gv)]) if np.ndim(gv) == 0 else np.asarray(gv, dtype=float)
        if gv.shape != (3,):
            raise InputError("g", g, "a magnitude or an inertial 3-vector (m / s2)")
        return cls(_eng.UniformGravity(m, np.asarray(r), gv))

    @classmethod
    def gravity_gradient(cls, gm, distance, *, direction=None, orbit_normal=None, phase=0 * u.rad, mean_motion=None) -> Torque:
        """The tidal torque of a distant point mass: ``tau = 3 GM / d^3 rho x I rho``.

        Parameters
        ----------
        gm : Quantity
            Gravitational parameter (m3 / s2) of the attracting mass.
        distance : Quantity
            Distance to it.
        direction : array_like (3,), optional
            Fixed inertial direction towards it; or
        orbit_normal : array_like (3,), optional
            The axis of a circular orbit on which the direction turns.
        phase : Quantity
            Angle of the direction at t = 0 in the orbit plane.
        mean_motion : Quantity, optional
            Angular rate of the direction; default sqrt(GM / d^3).
        """
        spec = _eng.GravityGradient(
            to_si(gm, "gm", u.m**3 / u.s**2, positive=True, shape=()),
            to_si(distance, "distance", u.m, positive=True, shape=()),
            None if direction is None else np.asarray(direction, dtype=float),
            None if orbit_normal is None else np.asarray(orbit_normal, dtype=float),
            to_si(phase, "phase", u.rad, shape=()),
            None if mean_motion is None else to_si(mean_motion, "mean_motion", u.rad / u.s, shape=()),
        )
        spec.unit_vectors()  # checks direction / orbit_normal now
        return cls(spec)

    @classmethod
    def damping(cls, coefficient) -> Torque:
        """Linear damping ``tau = -c omega``; c in N m s, one value or one per principal body axis."""
        c = to_si(coefficient, "coefficient", u.N * u.m * u.s, nonnegative=True)
        return cls(_eng.LinearDamping(np.asarray(c)))

    @classmethod
    def custom(cls, function, *, frame: str = "body", uses_omega: bool = True, uses_attitude: bool = True, name: str = "custom") -> Torque:
        """Your own torque: ``function(t, omega, q) -> tau``, vectorised, in SI.

        ``t`` (n,) in s, ``omega`` (n, 3) in rad/s (body frame), ``q`` (n, 4)
        body -> inertial; returns (n, 3) in N m in ``frame``. Set
        ``uses_omega=False`` when it does not depend on omega: the splitting
        integrator can then take it.
        """
        return cls(_eng.CustomTorque(function, frame, uses_omega, uses_attitude, name))
