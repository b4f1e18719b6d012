"""Torques with units: :class:`Torque` (Quantities in, engine specifications out).

Each constructor hands its Quantities to the scene-file reader's torque table
(:func:`wobble.io.scene_file.torque_from_mapping`), the one place a torque's parameters
are checked and converted to SI, and returns a :class:`Torque` that scenes
(:class:`wobble.Scene`) accept. See docs/engine.md for the equations.

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

from wobble.errors import InputError
from wobble.io.scene_file import torque_from_mapping
from wobble.models.torques import STANDARD_GRAVITY, CustomTorque

__all__ = ["Torque"]

_TORQUE = u.N * u.m


def _shown(value) -> str:
    """A constructor argument for a repr: numbers to six digits with their unit, a long array by its shape."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k!r}: {_shown(v)}" for k, v in value.items()) + "}"
    if isinstance(value, str) or callable(value):
        return repr(value) if isinstance(value, str) else getattr(value, "__name__", type(value).__name__)
    unit = f" {value.unit.to_string()}" if isinstance(value, u.Quantity) and value.unit != u.one else ""
    data = np.asarray(value.value if isinstance(value, u.Quantity) else value)
    if data.size > 6:
        return f"<array of shape {data.shape}>{unit}"
    return _nested(data) + unit


def _nested(data: np.ndarray) -> str:
    if data.ndim == 0:
        return f"{data.item():.6g}"
    return "[" + ", ".join(_nested(row) for row in data) + "]"


class Torque:
    """A torque acting on a scene's body (build with the class methods).

    Attributes
    ----------
    kind : str
        ``constant``, ``gravity``, ``gravity_gradient``, ``third_body``, ``magnetic``, ``damping`` or ``custom``.
    spec : object
        The SI specification in :mod:`wobble.models.engine`.
    """

    __slots__ = ("spec", "_given")

    def __init__(self, spec, given: dict | None = None):
        self.spec = spec
        self._given = given  # the arguments as the user gave them, for the repr

    @classmethod
    def _of(cls, mapping: dict) -> Torque:
        return cls(torque_from_mapping(mapping), {k: v for k, v in mapping.items() if k != "kind"})

    @property
    def kind(self) -> str:
        """The torque's kind."""
        return self.spec.kind

    def as_mapping(self) -> dict | None:
        """The torque as a scene file's ``[[torques]]`` table (``kind`` and the arguments as given), or None for a
        custom torque, whose function no file can hold. A run's ``scene`` attribute writes it."""
        return None if self._given is None else {"kind": self.kind, **self._given}

    def __repr__(self) -> str:
        """The constructor call with the values as given: ``Torque.damping(coefficient=0.001 kg m2 / s)``."""
        if self._given is None:  # a custom torque: its function is named, not shown
            spec = self.spec
            name = getattr(spec.function, "__name__", type(spec.function).__name__)
            return f"Torque.custom({name}, frame={spec.frame!r}, name={spec.name!r})"
        args = ", ".join(f"{k}={_shown(v)}" for k, v in self._given.items())
        return f"Torque.{self.kind}({args})"

    @classmethod
    def constant(cls, torque, frame: str = "body") -> Torque:
        """A constant torque (N m), fixed in the ``"body"`` or the ``"inertial"`` frame.

        ``torque`` has shape (3,) or (N, 3) (one per ensemble member).
        """
        return cls._of({"kind": "constant", "torque": torque, "frame": frame})

    @classmethod
    def gravity(cls, mass, center_of_mass, g=STANDARD_GRAVITY * u.m / u.s**2) -> Torque:
        """Uniform gravity about a fixed pivot: ``tau = r x m g`` (Goldstein, Poole & Safko 2002, sec. 5.7).

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
        # A scene file's gravity torque takes a magnitude "g" or a vector "gravity"; the Python keyword is g.
        key = "g" if np.ndim(g) == 0 else "gravity"
        try:
            return cls._of({"kind": "gravity", "mass": mass, "center_of_mass": center_of_mass, key: g})
        except InputError as exc:
            if exc.parameter != "gravity":
                raise
            raise InputError("g", exc.value, exc.allowed) from None

    @classmethod
    def gravity_gradient(
        cls, gm, distance, *, direction=None, orbit_normal=None, phase=0 * u.rad, mean_motion=None
    ) -> Torque:
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
        if (direction is None) == (orbit_normal is None):  # the mapping's check named its keys as the value
            given = "both" if direction is not None else "neither"
            raise InputError(
                "direction", given, "exactly one of direction (a fixed direction) and orbit_normal (a circular orbit)"
            )
        mapping = {"kind": "gravity_gradient", "gm": gm, "distance": distance, "phase": phase}
        for key, value in (("direction", direction), ("orbit_normal", orbit_normal), ("mean_motion", mean_motion)):
            if value is not None:
                mapping[key] = value
        return cls._of(mapping)

    @classmethod
    def third_body(
        cls,
        gm,
        *,
        semi_major_axis=None,
        eccentricity: float = 0.0,
        inclination=None,
        longitude_of_node=None,
        argument_of_periapsis=None,
        mean_anomaly=None,
        mean_motion=None,
        node_rate=None,
        periapsis_rate=None,
        ephemeris_times=None,
        ephemeris_positions=None,
        position=None,
        name: str = "third_body",
    ) -> Torque:
        """The tidal torque of a third body moving on a given orbit: ``tau = (3 GM / r^5) r_b x I r_b``.

        MacCullagh's formula (Goldstein, Poole & Safko 2002, sec. 5.8) with the perturber's
        position r from one of

        * its Keplerian orbit: ``semi_major_axis`` and optionally ``eccentricity``,
          ``inclination``, ``longitude_of_node``, ``argument_of_periapsis``, ``mean_anomaly``
          (angles at t = 0 in the inertial frame: x-y the reference plane, x the origin of
          longitudes), ``mean_motion`` (the rate of the mean anomaly; default sqrt(GM/a^3),
          right when the perturber is the heavy partner, as the Sun is: give it for the
          Moon), ``node_rate`` and ``periapsis_rate`` (secular rates); Kepler's equation is
          solved at each evaluation, compiled; or
        * an ephemeris table: ``ephemeris_times`` (increasing, covering the run) and
          ``ephemeris_positions`` (one inertial position per time), cubic splines; or
        * ``position``: your function ``f(t) -> (n, 3)``, t (n,) in s, positions in m
          (no compiled form: the NumPy DOP853 or the splitting).

        Parameters
        ----------
        gm : Quantity
            G M of the perturber (m3 / s2).
        name : str
            For messages (``"moon"``).

        Examples
        --------
        >>> import astropy.units as u
        >>> from wobble import Torque
        >>> moon = Torque.third_body(4.9028e12 * u.m**3 / u.s**2, semi_major_axis=384399 * u.km, eccentricity=0.0549,
        ...                          inclination=5.145 * u.deg, mean_motion=13.065 * u.deg / u.day,
        ...                          node_rate=-19.355 * u.deg / u.yr, name="moon")
        >>> moon.kind, round(moon.spec.orbit.semi_major_axis)
        ('third_body', 384399000)
        """
        mapping: dict = {"kind": "third_body", "gm": gm, "name": name}
        if semi_major_axis is not None:
            mapping["semi_major_axis"] = semi_major_axis
            mapping["eccentricity"] = eccentricity
        for key, value in (
            ("inclination", inclination),
            ("longitude_of_node", longitude_of_node),
            ("argument_of_periapsis", argument_of_periapsis),
            ("mean_anomaly", mean_anomaly),
            ("mean_motion", mean_motion),
            ("node_rate", node_rate),
            ("periapsis_rate", periapsis_rate),
        ):
            if value is not None:
                mapping[key] = value
        if ephemeris_times is not None or ephemeris_positions is not None:
            mapping["ephemeris"] = {
                k: v for k, v in (("times", ephemeris_times), ("positions", ephemeris_positions)) if v is not None
            }
        if position is not None:
            mapping["position"] = position
        return cls._of(mapping)

    @classmethod
    def magnetic(cls, dipole, field) -> Torque:
        """A magnetic dipole fixed in the body in a uniform field: ``tau = mu x B``.

        Parameters
        ----------
        dipole : Quantity, shape (3,) or (N, 3)
            The body's magnetic dipole moment (A m2), body frame.
        field : Quantity, shape (3,)
            The magnetic flux density (T), inertial frame.
        """
        return cls._of({"kind": "magnetic", "dipole": dipole, "field": field})

    @classmethod
    def damping(cls, coefficient) -> Torque:
        """Linear damping ``tau = -c omega``; c in N m s, one value or one per principal body axis."""
        return cls._of({"kind": "damping", "coefficient": coefficient})

    @classmethod
    def custom(
        cls, function, *, frame: str = "body", uses_omega: bool = True, uses_attitude: bool = True, name: str = "custom"
    ) -> Torque:
        """Your own torque: ``function(t, omega, q) -> tau``, vectorised, in SI.

        ``t`` (n,) in s, ``omega`` (n, 3) in rad/s (body frame), ``q`` (n, 4)
        body -> inertial; returns (n, 3) in N m in ``frame``. Set
        ``uses_omega=False`` when it does not depend on omega: the splitting
        integrator can then take it.
        """
        return cls(CustomTorque(function, frame, uses_omega, uses_attitude, name))
