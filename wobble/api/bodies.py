"""Rigid bodies with units: inertia tensors, principal axes, L and T (Goldstein, Poole & Safko 2002, sec. 5.1).

:class:`RigidBody` is the public face of :mod:`wobble.models.bodies`: every
dimensional argument is an :class:`astropy.units.Quantity`, converted to SI once on
the way in; every dimensional result is a Quantity (kg m2, kg m2 / s, J, m).

A body is an inertia tensor **about a reference point** (the centre of mass unless
you built or shifted it about another point), with its axes those of the **input
frame**, the frame you described the body in. Later models read:

* :attr:`RigidBody.principal_moments` -- I1 <= I2 <= I3 about the reference point;
* :meth:`RigidBody.principal` -- moments, axes and exact differences in a chosen order;
* :attr:`RigidBody.center_of_mass_offset` -- the vector R from the reference point to
  the centre of mass (for a top shifted to its tip, ``l = |R|``, Goldstein et al. 2002, sec. 5.7).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
from astropy import units as u

from wobble.api.units import dimensionless, to_si
from wobble.errors import FileFormatError, InputError
from wobble.io import cf
from wobble.models import bodies as _m
from wobble.models import density_grid as _grid
from wobble.models import solids as _solids

__all__ = ["RigidBody", "PrincipalAxes", "Classification", "DEFAULT_RTOL"]

DEFAULT_RTOL = _m.DEFAULT_RTOL
Classification = _m.Classification

_MOI = u.kg * u.m**2
_DENSITY = u.kg / u.m**3
_LENGTH_UNITS = "length units (e.g. 'm', 'km', 'cm')"
#: Default slab size when streaming a density grid (bytes of float64 per slab).
DEFAULT_CHUNK_BYTES = 32 * 2**20
_CF_MOI = "kg m2"
_PARAMETER_KEYS = {
    "mass",
    "center_of_mass",
    "reference_point",
    "principal_moments",
    "principal_axes",
    "principal_moment_differences",
    "tensor",
}


@dataclass(frozen=True, eq=False)
class PrincipalAxes:
    """Principal moments and axes of a :class:`RigidBody`, in a stated order.

    Attributes
    ----------
    moments : astropy.units.Quantity, shape (3,)
        I1, I2, I3 in kg m2.
    axes : numpy.ndarray, shape (3, 3)
        Row k is the unit vector of axis k + 1 in input-frame components; a proper
        rotation matrix (``axes @ v`` gives principal-frame components of ``v``).
    differences : astropy.units.Quantity, shape (3, 3)
        ``D[i, j] = I_(i+1) - I_(j+1)`` in kg m2, free of cancellation where the
        body was built from exact differences (H, J2, two nearly equal semi-axes).
    order : str
        ``ascending``, ``descending``, ``input`` or ``symmetry``.
    """

    moments: u.Quantity
    axes: np.ndarray
    differences: u.Quantity
    order: str
    _frame: _m.PrincipalFrame

    def ratio(self, i: int, j: int, k: int | None = None) -> float:
        """(I_i - I_j)/I_k with 1-based indices (k defaults to j), a plain float."""
        return self._frame.ratio(i, j, k)

    def __repr__(self) -> str:
        """The moments and axes to seven digits, one axis a line (the default repr printed the internal frame
        and the 3 x 3 differences twice, over ten lines)."""
        I = self.moments.to_value(u.kg * u.m**2)
        lines = [
            f"  I{k + 1} = {I[k]:.7g} kg m2, axis ({', '.join(f'{c:.7g}' for c in self.axes[k] + 0.0)})"
            for k in range(3)
        ]
        return f"<PrincipalAxes ({self.order}):\n" + "\n".join(lines) + ">"


def _angular_velocity(omega) -> np.ndarray:
    """omega in rad/s. An angle unit is required (no dimensionless_angles(), which reads Hz and 1/s as rad/s)."""
    return to_si(omega, "omega", u.rad / u.s)


def _length_vector(value, name: str) -> np.ndarray:
    return to_si(value, name, u.m, shape=(3,))


def _point(value, body: _m.Body, name: str = "point") -> np.ndarray:
    if isinstance(value, str):
        key = value.strip().lower()
        if key == "com":
            return np.array(body.center_of_mass)
        if key == "origin":
            return np.zeros(3)
        raise InputError(name, value, "'com', 'origin' or a length Quantity of shape (3,) (e.g. [0, 0, 1] * u.cm)")
    return _length_vector(value, name)


def _placement(mass, center_of_mass, about) -> dict:
    """``mass``, ``center_of_mass`` and ``about`` of the tensor constructors, in SI (None where not given)."""
    return {
        "mass": None if mass is None else _mass(mass),
        "center_of_mass": None if center_of_mass is None else _length_vector(center_of_mass, "center_of_mass"),
        "about": _about(about),
    }


def _about(value, name: str = "about"):
    """``about`` for constructors: None or 'com' (the centre of mass), 'origin', or a point."""
    if value is None:
        return None
    if isinstance(value, str):
        key = value.strip().lower()
        if key == "com":
            return None
        if key == "origin":
            return np.zeros(3)
        raise InputError(name, value, "'com', 'origin' or a length Quantity of shape (3,)")
    return _length_vector(value, name)


def _mass(value, name: str = "mass") -> float:
    return to_si(value, name, u.kg, positive=True, shape=())


def _length(value, name: str, *, allow_zero: bool = False) -> float:
    if allow_zero:
        return to_si(value, name, u.m, nonnegative=True, shape=())
    return to_si(value, name, u.m, positive=True, shape=())


def _rotation(rotation, name: str = "rotation"):
    """A scipy Rotation as its matrix; anything else is passed on (the model checks it)."""
    from scipy.spatial.transform import Rotation

    if isinstance(rotation, Rotation):
        if not rotation.single:
            raise InputError(name, rotation, "a single rotation (not a stack)")
        return rotation.as_matrix()
    if isinstance(rotation, u.Quantity):
        return _dimensionless_array(rotation, name)
    return rotation


def _identifier(text: str) -> str:
    ident = re.sub(r"[^a-z0-9_]+", "_", text.strip().lower()).strip("_")
    return ident or "rigid_body"


class RigidBody:
    """A rigid body: inertia tensor, mass and centre of mass, with units.

    Build one with a constructor (:meth:`from_principal_moments`,
    :meth:`from_tensor`, :meth:`from_point_masses`, :meth:`from_density`, the
    solids :meth:`solid_sphere` ... :meth:`spinning_top`, :meth:`oblate_planet`,
    :meth:`composite`, :meth:`from_parameter_file`, :meth:`from_dataset`), not
    with ``RigidBody(...)`` directly.

    Bodies are immutable: :meth:`shifted_to`, :meth:`translated`,
    :meth:`rotated` and ``+`` return new bodies.

    Examples
    --------
    >>> import wobble
    >>> from astropy import units as u
    >>> box = wobble.RigidBody.box(2 * u.kg, [3, 2, 1] * u.m)  # edges along x, y, z
    >>> print(box.principal_moments.to_value(u.kg * u.m**2).round(3), box.classify().kind)
    [0.833 1.667 2.167] asymmetric
    >>> spin = [0, 0, 2] * u.rad / u.s
    >>> L, T = box.angular_momentum(spin), box.kinetic_energy(spin)
    >>> print(L.to_value(u.kg * u.m**2 / u.s).round(3), f"{T.to_value(u.J):.3f} J")
    [0.    0.    4.333] 4.333 J
    """

    __slots__ = ("_body", "name")

    def __init__(self, body: _m.Body, name: str = ""):
        if not isinstance(body, _m.Body):
            raise InputError("body", body, "a wobble.models.bodies.Body (use a RigidBody constructor)")
        self._body = body
        self.name = str(name)

    # ------------------------------------------------------------------
    # Constructors
    # ------------------------------------------------------------------

    @classmethod
    def from_principal_moments(
        cls,
        moments,
        *,
        axes=None,
        mass=None,
        center_of_mass=None,
        about=None,
        rtol: float = DEFAULT_RTOL,
        name: str = "",
    ) -> RigidBody:
        """A body from its three principal moments.

        Parameters
        ----------
        moments : Quantity, shape (3,)
            Positive moments of inertia (e.g. ``[1, 2, 2.5] * u.g * u.cm**2``),
            about the input x, y, z axes unless ``axes`` is given. Their
            differences are formed in your unit before conversion, so nearly
            equal moments keep their small differences exactly.
        axes : array_like, shape (3, 3), or scipy Rotation, optional
            Row k is the direction (input frame) of the axis of ``moments[k]``
            (a proper rotation matrix; a scipy ``Rotation`` gives its matrix).
        mass : Quantity, optional
            Needed to shift the reference point or combine bodies.
        center_of_mass : Quantity, shape (3,), optional
            Default: the origin.
        about : 'com', 'origin' or Quantity (3,), optional
            The point the moments are about (default: the centre of mass).
        rtol : float
            Tolerance for the triangle inequality I1 + I2 >= I3 (and cyclic).
        """
        values = to_si(moments, "moments", _MOI, positive=True, shape=(3,))
        raw = np.asarray(moments.value, dtype=float)
        # Differences in the user's own unit (exact for nearly equal floats, Sterbenz), then scaled once.
        diffs = (raw[:, None] - raw[None, :]) * moments.unit.to(_MOI)
        body = _m.from_principal_moments(
            values,
            differences=diffs,
            axes=None if axes is None else _rotation(axes, "axes"),
            **_placement(mass, center_of_mass, about),
            rtol=rtol,
        )
        return cls(body, name)

    @classmethod
    def from_tensor(
        cls, tensor, *, mass=None, center_of_mass=None, about=None, rtol: float = DEFAULT_RTOL, name: str = ""
    ) -> RigidBody:
        """A body from a full 3x3 inertia tensor (Quantity, e.g. kg m2), checked.

        The tensor must be finite, symmetric to ``rtol`` relative to its largest
        entry, positive definite, and obey I1 + I2 >= I3 (and cyclic) to ``rtol``.
        ``mass``, ``center_of_mass`` and ``about`` are as in :meth:`from_principal_moments`.
        """
        t = to_si(tensor, "tensor", _MOI, shape=(3, 3))
        body = _m.from_tensor(
            t,
            **_placement(mass, center_of_mass, about),
            rtol=rtol,
        )
        return cls(body, name)

    @classmethod
    def from_point_masses(cls, masses, positions, *, about=None, name: str = "") -> RigidBody:
        """Point masses m_i at r_i: I_jk = sum_i m_i (r_i^2 delta_jk - x_ij x_ik) (Goldstein et al. 2002, sec. 5.1).

        Parameters
        ----------
        masses : Quantity, shape (N,)
            Positive masses.
        positions : Quantity, shape (N, 3)
            Positions (input frame).
        about : 'com', 'origin' or Quantity (3,), optional
            Reference point of the tensor (default: the centre of mass).
        """
        m = to_si(masses, "masses", u.kg, positive=True)
        r = to_si(positions, "positions", u.m)
        m = np.atleast_1d(m)
        return cls(_m.from_point_masses(m, r, about=_about(about)), name)

    @classmethod
    def from_density(
        cls,
        density,
        *,
        about=None,
        rule: str = "trapezoid",
        chunk_bytes: int = DEFAULT_CHUNK_BYTES,
        name: str = "",
    ) -> RigidBody:
        """A body from a density on a regular grid: I_jk = integral rho (r^2 delta_jk - x_j x_k) dV.

        Parameters
        ----------
        density : xarray.DataArray
            Dimensions exactly ``x``, ``y``, ``z`` (any order), each with a 1-D,
            uniformly spaced coordinate whose ``units`` attribute is a length; the
            array's ``units`` attribute is a mass density (``"kg m-3"``,
            ``"g cm-3"``). Values must be finite and >= 0 (zero outside the body).
            A lazily loaded array (``xarray.open_dataset``) is read slab by slab.
        about : 'com', 'origin' or Quantity (3,), optional
            Reference point (default: the centre of mass).
        rule : {"trapezoid", "simpson", "voxel"}
            Quadrature: trapezoidal (O(h^2)), Simpson (O(h^4), odd point counts),
            or voxel (each sample the mean over its cell; exact for piecewise-constant
            density, O(h^2) for smooth). For a density that jumps at the body's
            surface no rule guarantees more than O(h).
        chunk_bytes : int
            Slab size for streaming (default 32 MiB): memory use is about this
            much beyond the array itself, whatever the grid size.
        """
        dims, axes, scale = _grid_description(density)
        if not (isinstance(chunk_bytes, int) and chunk_bytes > 0):
            raise InputError("chunk_bytes", chunk_bytes, "a positive number of bytes")
        slabs = _slabs(density, dims, chunk_bytes)
        body = _grid.from_grid(slabs, axes, rule=rule, density_scale=scale, about=_about(about))
        return cls(body, name)

    @classmethod
    def solid_sphere(cls, mass, radius, *, name: str = "solid sphere") -> RigidBody:
        """Uniform solid sphere, centred at the origin: I = 2/5 M R^2."""
        return cls(_solids.solid_sphere(_mass(mass), _length(radius, "radius")), name)

    @classmethod
    def hollow_sphere(cls, mass, radius, inner_radius=None, *, name: str = "hollow sphere") -> RigidBody:
        """Uniform spherical shell (a thin shell, I = 2/3 M R^2, when ``inner_radius`` is None).

        Thick shell: I = 2/5 M (R^5 - r^5)/(R^3 - r^3).
        """
        inner = None if inner_radius is None else _length(inner_radius, "inner_radius", allow_zero=True)
        return cls(_solids.hollow_sphere(_mass(mass), _length(radius, "radius"), inner), name)

    @classmethod
    def ellipsoid(cls, mass, semi_axes, *, name: str = "ellipsoid") -> RigidBody:
        """Uniform ellipsoid, semi-axes (a, b, c) along x, y, z: I_x = M (b^2 + c^2)/5, ..."""
        return cls(_solids.ellipsoid(_mass(mass), to_si(semi_axes, "semi_axes", u.m, positive=True, shape=(3,))), name)

    @classmethod
    def box(cls, mass, edges, *, name: str = "box") -> RigidBody:
        """Uniform box with edge lengths (a, b, c) along x, y, z: I_x = M (b^2 + c^2)/12, ..."""
        return cls(_solids.box(_mass(mass), to_si(edges, "edges", u.m, positive=True, shape=(3,))), name)

    @classmethod
    def cylinder(cls, mass, radius, height, inner_radius=None, *, name: str = "cylinder") -> RigidBody:
        """Uniform cylinder (tube if ``inner_radius``), axis z: I3 = M (R^2 + r^2)/2,
        I1 = M (3 (R^2 + r^2) + h^2)/12."""
        inner = 0.0 if inner_radius is None else _length(inner_radius, "inner_radius", allow_zero=True)
        return cls(_solids.cylinder(_mass(mass), _length(radius, "radius"), _length(height, "height"), inner), name)

    @classmethod
    def cone(cls, mass, radius, height, *, name: str = "cone") -> RigidBody:
        """Uniform cone, axis z, apex at z = -3h/4: I3 = 3/10 M R^2, I1 = 3/80 M (4 R^2 + h^2)."""
        return cls(_solids.cone(_mass(mass), _length(radius, "radius"), _length(height, "height")), name)

    @classmethod
    def thin_disc(cls, mass, radius, *, name: str = "thin disc") -> RigidBody:
        """Uniform thin disc in the x-y plane: I1 = I2 = M R^2/4, I3 = M R^2/2."""
        return cls(_solids.thin_disc(_mass(mass), _length(radius, "radius")), name)

    @classmethod
    def thin_rod(cls, mass, length, *, name: str = "thin rod") -> RigidBody:
        """Uniform thin rod along z: I1 = I2 = M L^2/12, I3 = 0."""
        return cls(_solids.thin_rod(_mass(mass), _length(length, "length")), name)

    @classmethod
    def spinning_top(
        cls,
        disc_mass,
        disc_radius,
        axle_mass,
        axle_length,
        disc_height,
        axle_radius=None,
        *,
        name: str = "spinning top",
    ) -> RigidBody:
        """A top: thin disc on an axle along z, tip at the origin, about its centre of mass.

        The axle (thin rod, or solid cylinder of ``axle_radius``) runs from the tip at
        z = 0 to z = ``axle_length``; the disc is centred on it at z = ``disc_height``.
        For the heavy-top engine use ``top.shifted_to("origin")`` (about the tip).
        """
        axle_mass_si = to_si(axle_mass, "axle_mass", u.kg, nonnegative=True, shape=())
        ra = 0.0 if axle_radius is None else _length(axle_radius, "axle_radius", allow_zero=True)
        body = _solids.spinning_top(
            _mass(disc_mass, "disc_mass"),
            _length(disc_radius, "disc_radius"),
            axle_mass_si,
            _length(axle_length, "axle_length"),
            _length(disc_height, "disc_height", allow_zero=True),
            ra,
        )
        return cls(body, name)

    @classmethod
    def oblate_planet(
        cls,
        mass,
        radius,
        polar_moment_factor,
        *,
        dynamical_flattening=None,
        j2=None,
        j22=0.0,
        name: str = "planet",
    ) -> RigidBody:
        """A planet from C/(M R^2) and H = (C - A)/C or J2 = (C - A)/(M R^2); optional J22.

        The polar axis is z; with ``j22`` (unnormalised, (B - A)/(4 M R^2)) the
        smallest moment A lies along x. C - A is formed from H or J2 directly,
        so :meth:`moment_ratio` ``(3, 1)`` = (C - A)/A keeps full precision.
        """
        c = dimensionless(polar_moment_factor, "polar_moment_factor", low=0.0, high=1.0)
        # Their ranges depend on each other (J2 <= c/2, J22 against H): the model checks them.
        hh = None if dynamical_flattening is None else dimensionless(dynamical_flattening, "dynamical_flattening")
        jj = None if j2 is None else dimensionless(j2, "j2")
        q = dimensionless(j22, "j22", low=0.0, open_interval=False)
        body = _solids.oblate_planet(_mass(mass), _length(radius, "radius"), c, dynamical_flattening=hh, j2=jj, j22=q)
        return cls(body, name)

    @classmethod
    def composite(cls, parts, *, about=None, name: str = "") -> RigidBody:
        """The sum of bodies, each already placed (:meth:`translated`) and turned (:meth:`rotated`).

        About ``about`` ('com' -- the joint centre of mass, the default -- 'origin' or
        a point). Every part needs a mass.
        """
        parts = list(parts)
        for i, p in enumerate(parts):
            if not isinstance(p, RigidBody):
                raise InputError(f"parts[{i}]", p, "a RigidBody")
        body = _m.composite([p._body for p in parts], about=_about(about))
        return cls(body, name or " + ".join(p.name or "body" for p in parts))

    def __add__(self, other):
        if not isinstance(other, RigidBody):
            return NotImplemented
        return RigidBody.composite([self, other])

    def __radd__(self, other):
        if isinstance(other, (int, float)) and other == 0:  # sum(bodies)
            return self
        return NotImplemented

    # ------------------------------------------------------------------
    # Mass, centre of mass, tensor
    # ------------------------------------------------------------------

    @property
    def model(self) -> _m.Body:
        """The SI model (:class:`wobble.models.bodies.Body`) for other models to use."""
        return self._body

    @property
    def mass(self) -> u.Quantity | None:
        """Total mass (kg), or None for a body given by its moments alone."""
        return None if self._body.mass is None else self._body.mass << u.kg

    @property
    def center_of_mass(self) -> u.Quantity:
        """Centre of mass (m, input frame), shape (3,)."""
        return np.array(self._body.center_of_mass) << u.m

    @property
    def reference_point(self) -> u.Quantity:
        """The point (m, input frame) the tensor and principal moments are about."""
        return np.array(self._body.reference_point) << u.m

    @property
    def center_of_mass_offset(self) -> u.Quantity:
        """R = centre of mass - reference point (m); for a top about its tip, ``l = |R|``
        (Goldstein et al. 2002, sec. 5.7)."""
        return np.array(self._body.center_of_mass - self._body.reference_point) << u.m

    @property
    def tensor(self) -> u.Quantity:
        """Inertia tensor (kg m2) about the reference point, input-frame axes, shape (3, 3)."""
        return np.array(self._body.tensor) << _MOI

    @property
    def central_tensor(self) -> u.Quantity:
        """Inertia tensor (kg m2) about the centre of mass, input-frame axes."""
        return self._body.central_tensor() << _MOI

    # ------------------------------------------------------------------
    # Principal axes and classification
    # ------------------------------------------------------------------

    def principal(self, order: str = "ascending", rtol: float = DEFAULT_RTOL) -> PrincipalAxes:
        """Principal moments, axes and differences about the reference point.

        Parameters
        ----------
        order : {"ascending", "descending", "input", "symmetry"}
            ``ascending`` I1 <= I2 <= I3 (default); ``descending``; ``input`` (the
            axis nearest x first, then y, then z); ``symmetry`` (ascending, but a
            prolate body's unique axis is listed third, as a top's figure axis).
        rtol : float
            Moments equal to this relative tolerance are treated as degenerate:
            the unique axis is kept and the degenerate pair gets a canonical basis
            (stable under rounding), see :mod:`wobble.numerics.symmetric_eigen`.
        """
        f = self._body.principal(order, rtol)
        return PrincipalAxes(f.moments << _MOI, np.array(f.axes), f.differences << _MOI, f.order, f)

    @property
    def principal_moments(self) -> u.Quantity:
        """I1 <= I2 <= I3 (kg m2) about the reference point."""
        return self.principal().moments

    @property
    def principal_axes(self) -> np.ndarray:
        """Unit vectors of the principal axes (rows, input frame), ascending moments; det +1."""
        return self.principal().axes

    @property
    def principal_differences(self) -> u.Quantity:
        """(I2 - I1, I3 - I2, I3 - I1) in kg m2, exact where the body was built from them."""
        d = self.principal().differences
        return u.Quantity([d[1, 0], d[2, 1], d[2, 0]])

    def to_principal_rotation(self, order: str = "ascending"):
        """The rotation from input-frame to principal-frame components (scipy Rotation).

        ``rot.apply(v)`` gives the principal-frame components of the input-frame
        vector ``v``; ``rot.as_matrix()`` equals :meth:`principal` ``(order).axes``.
        """
        from scipy.spatial.transform import Rotation

        return Rotation.from_matrix(self.principal(order).axes)

    def classify(self, rtol: float = DEFAULT_RTOL) -> Classification:
        """Shape class with its numbers (kind, rtol, splittings, asymmetry)."""
        return self._body.classify(rtol)

    @property
    def classification(self) -> str:
        """``spherical``, ``oblate``, ``prolate`` or ``asymmetric`` at the default tolerance."""
        return self.classify().kind

    @property
    def asymmetry(self) -> float:
        """Relative difference of the closest pair of principal moments (0 for a symmetric body)."""
        return self.classify().asymmetry

    def moment_ratio(self, i: int, j: int, k: int | None = None) -> float:
        """(I_i - I_j)/I_k of the ascending principal moments (1-based; k defaults to j).

        ``moment_ratio(3, 1)`` is (C - A)/A of the Chandler model and the free symmetric top.
        """
        return self.principal().ratio(i, j, k)

    @property
    def dynamical_flattening(self) -> float:
        """H = (I3 - (I1 + I2)/2)/I3, from the exact differences."""
        f = self._body.principal()
        d = f.differences
        return float(0.5 * (d[2, 0] + d[2, 1]) / f.moments[2]) if f.moments[2] else 0.0

    # ------------------------------------------------------------------
    # Moving the body
    # ------------------------------------------------------------------

    def shifted_to(self, point) -> RigidBody:
        """The same body with its tensor about ``point``: 'com', 'origin' or a length (3,) (parallel axes)."""
        return RigidBody(self._body.shifted_to(_point(point, self._body)), self.name)

    def translated(self, offset) -> RigidBody:
        """The body moved by ``offset`` (length Quantity, shape (3,))."""
        return RigidBody(self._body.translated(_length_vector(offset, "offset")), self.name)

    def rotated(self, rotation, about=None) -> RigidBody:
        """The body turned by ``rotation`` (3x3 proper rotation matrix or scipy Rotation).

        An active rotation about ``about`` ('origin' -- the default --, 'com' or a
        point): r -> R (r - p) + p, I -> R I R^T.
        """
        p = None if about is None else _point(about, self._body, "about")
        return RigidBody(self._body.rotated(_rotation(rotation), p), self.name)

    # ------------------------------------------------------------------
    # Dynamics (Goldstein, Poole & Safko 2002, sec. 5.1)
    # ------------------------------------------------------------------

    def angular_momentum(self, omega, frame: str = "input") -> u.Quantity:
        """L = I omega (kg m2 / s) about the reference point.

        ``omega`` is an angular velocity Quantity of shape (..., 3) given in the
        ``frame`` ('input' or 'principal', the ascending principal axes), and L is
        returned in the same frame (in the principal frame L_j = I_j omega_j).
        """
        w = _angular_velocity(omega)
        return self._body.angular_momentum(w, frame) << (_MOI / u.s)

    def kinetic_energy(self, omega, frame: str = "input") -> u.Quantity:
        """T = 1/2 omega . I . omega (J) for rotation about the reference point."""
        w = _angular_velocity(omega)
        return self._body.kinetic_energy(w, frame) << u.J

    def moment_about(self, axis, frame: str = "input") -> u.Quantity:
        """n . I . n (kg m2), the moment about the direction ``axis`` (normalised; shape (..., 3))."""
        if isinstance(axis, u.Quantity):
            axis = _dimensionless_array(axis, "axis")
        return self._body.moment_about(axis, frame) << _MOI

    # ------------------------------------------------------------------
    # Output
    # ------------------------------------------------------------------

    def __repr__(self) -> str:
        mass = "unknown mass" if self._body.mass is None else f"mass {self._body.mass:.6g} kg"
        moments = ", ".join(f"{x:.6g}" for x in self._body.principal().moments)
        label = f" {self.name!r}" if self.name else ""
        return f"<RigidBody{label}: {mass}, principal moments [{moments}] kg m2, {self.classification}>"

    def to_dataset(self, rtol: float = DEFAULT_RTOL):
        """An xarray Dataset with CF attributes: tensor, principal moments, axes, mass, centre of mass.

        Write it with :func:`wobble.write_netcdf`; :meth:`from_dataset` reads it back.
        """
        from wobble.api.dataset import xarray

        xr = xarray()
        f = self._body.principal("ascending", rtol)
        cls = self._body.classify(rtol)
        comp = ["x", "y", "z"]

        def var(name, data):
            return cf.variable("bodies", name, data)

        d = f.differences
        data = {
            "tensor": var("tensor", np.array(self._body.tensor)),
            "principal_moments": var("principal_moments", np.array(f.moments)),
            "principal_axes": var("principal_axes", np.array(f.axes)),
            "principal_moment_differences": var("principal_moment_differences", np.array([d[1, 0], d[2, 1], d[2, 0]])),
            "center_of_mass": var("center_of_mass", np.array(self._body.center_of_mass)),
            "reference_point": var("reference_point", np.array(self._body.reference_point)),
        }
        if self._body.mass is not None:
            data["mass"] = var("mass", self._body.mass)
        coords = {
            "row": ("row", comp, {"long_name": "tensor row (input-frame axis)"}),
            "column": ("column", comp, {"long_name": "tensor column (input-frame axis)"}),
            "component": ("component", comp, {"long_name": "input-frame axis"}),
            "principal": (
                "principal",
                np.array([1, 2, 3]),
                {"units": "1", "long_name": "principal axis number (ascending moment)"},
            ),
            "pair": ("pair", ["I2-I1", "I3-I2", "I3-I1"], {"long_name": "pair of principal moments"}),
        }
        attrs = {
            "title": f"Rigid body{': ' + self.name if self.name else ''}",
            "wobble_kind": "rigid_body",
            "name": self.name,
            "classification": cls.kind,
            "classification_rtol": cls.rtol,
            "asymmetry": cls.asymmetry,
            "references": "Inertia tensor I_jk = integral rho (r^2 delta_jk - x_j x_k) dV, L = I omega, "
            "T = omega.I.omega/2 (Goldstein, Poole & Safko 2002, Classical Mechanics, sections 5.1-5.4)",
        }
        return xr.Dataset(data, coords=coords, attrs=attrs)

    @classmethod
    def from_dataset(cls, ds) -> RigidBody:
        """Rebuild a body from :meth:`to_dataset` (or a file read with :func:`wobble.load`)."""
        try:
            # np.array, not np.asarray: copies, so that a later change to the Dataset leaves the body as it was.
            tensor = np.array(ds["tensor"].transpose("row", "column").values, dtype=float)
            com = np.array(ds["center_of_mass"].values, dtype=float)
            ref = np.array(ds["reference_point"].values, dtype=float)
            moments = np.array(ds["principal_moments"].values, dtype=float)
            axes = np.array(ds["principal_axes"].transpose("principal", "component").values, dtype=float)
            pairs = np.array(ds["principal_moment_differences"].values, dtype=float)
            mass = float(ds["mass"].values) if "mass" in ds else None
            for key in ("tensor", "principal_moments", "principal_moment_differences"):
                if ds[key].attrs.get("units") != _CF_MOI:
                    raise InputError(f"dataset[{key!r}].units", ds[key].attrs.get("units"), f"{_CF_MOI!r}")
        except KeyError as exc:
            raise InputError("dataset", f"no variable {exc}", "a Dataset made by RigidBody.to_dataset") from None
        d12, d23, d13 = pairs
        diffs = np.array([[0.0, -d12, -d13], [d12, 0.0, -d23], [d13, d23, 0.0]])
        exact = _m.Eigenbasis(moments, axes, diffs)
        body = _m.Body(tensor, ref, com, mass, exact)
        return cls(body, str(ds.attrs.get("name", "")))

    def to_parameter_file(
        self, path, *, overwrite: bool = False, title: str = "", description: str = "", source: str = ""
    ):
        """Write the body in the ``wobble/1`` schema (``kind = "rigid_body"``), atomically.

        Values are SI; ``source`` (default: this wobble version) is recorded for
        every parameter with status ``derived``. :meth:`from_parameter_file` reads it.
        """
        from wobble import __version__
        from wobble.io.parameter_file import Parameter, ParameterFile, write_parameter_file

        src = source or f"wobble {__version__}, RigidBody.to_parameter_file"
        f = self._body.principal()
        d = f.differences

        def param(value, unit, note):
            q = np.asarray(value, dtype=float) << u.Unit(unit)
            return Parameter(q, np.zeros(q.shape) << q.unit, src, "derived", note)

        params = {}
        if self._body.mass is not None:
            params["mass"] = param(self._body.mass, "kg", "total mass")
        params["center_of_mass"] = param(self._body.center_of_mass, "m", "centre of mass, input frame")
        params["reference_point"] = param(self._body.reference_point, "m", "point the moments are about, input frame")
        params["principal_moments"] = param(f.moments, "kg m2", "I1 <= I2 <= I3 about the reference point")
        params["principal_axes"] = param(f.axes, "", "row k: unit vector of principal axis k+1, input frame")
        params["principal_moment_differences"] = param(
            [d[1, 0], d[2, 1], d[2, 0]], "kg m2", "I2 - I1, I3 - I2, I3 - I1 (exact where built from them)"
        )
        params["tensor"] = param(self._body.tensor, "kg m2", "I_jk about the reference point, input frame")
        pf = ParameterFile(
            kind="rigid_body",
            name=_identifier(self.name),
            title=title or self.name or "rigid body",
            description=description or "Rigid body written by wobble: inertia tensor, principal axes, mass.",
            parameters=params,
        )
        return write_parameter_file(pf, path, overwrite=overwrite)

    @classmethod
    def from_parameter_file(cls, path, *, rtol: float = DEFAULT_RTOL) -> RigidBody:
        """Read a ``wobble/1`` file with ``kind = "rigid_body"``.

        It gives ``principal_moments`` (optionally with ``principal_axes``, rows,
        and ``principal_moment_differences``) or a full ``tensor``; optionally
        ``mass``, ``center_of_mass`` and ``reference_point`` (default: the centre
        of mass). When both ``principal_moments`` and ``tensor`` are given they
        must agree to ``rtol``.
        """
        from wobble.io.parameter_file import read_parameter_file

        pf = read_parameter_file(path, kind="rigid_body", known=_PARAMETER_KEYS)
        p = pf.parameters

        def get(key):
            return p[key].value if key in p else None

        try:
            common = dict(
                mass=get("mass"), center_of_mass=get("center_of_mass"), about=get("reference_point"), rtol=rtol
            )
            if "principal_moments" in p:
                axes = (
                    None if "principal_axes" not in p else _dimensionless_array(get("principal_axes"), "principal_axes")
                )
                body = cls.from_principal_moments(get("principal_moments"), axes=axes, name=pf.title, **common)
                tensor = None
                if "tensor" in p:
                    tensor = to_si(get("tensor"), "tensor", _MOI, shape=(3, 3))
                    _check_agree(body, tensor, rtol)
                if "principal_moment_differences" in p or tensor is not None:
                    body = _replace_exact(body, get("principal_moment_differences"), tensor)
            elif "tensor" in p:
                body = cls.from_tensor(get("tensor"), name=pf.title, **common)
            else:
                raise FileFormatError(path, "parameters", "give principal_moments or tensor")
        except InputError as exc:
            raise FileFormatError(
                path, f"parameters.{exc.parameter}", f"got {exc.value}; allowed: {exc.allowed}"
            ) from None
        return body


def _dimensionless_array(value, name: str) -> np.ndarray:
    """A dimensionless Quantity (or array) as a float64 array."""
    if isinstance(value, u.Quantity):
        try:
            return np.asarray(value.to_value(u.dimensionless_unscaled), dtype=float)
        except u.UnitConversionError:
            raise InputError(name, value, "dimensionless numbers") from None
    return np.asarray(value, dtype=float)


def _replace_exact(body: RigidBody, pairs, tensor) -> RigidBody:
    """Use a file's exact differences and tensor (after checking they agree with its moments)."""
    b = body._body
    f = b.principal()
    given = f.differences
    if pairs is not None:
        d12, d23, d13 = to_si(pairs, "principal_moment_differences", _MOI, nonnegative=True, shape=(3,))
        scale = float(f.moments[2])
        given = np.array([[0.0, -d12, -d13], [d12, 0.0, -d23], [d13, d23, 0.0]])
        if np.max(np.abs(given - f.differences)) > 1e-12 * scale or abs(d13 - d12 - d23) > 1e-12 * scale:
            raise InputError(
                "principal_moment_differences", pairs, "I2 - I1, I3 - I2, I3 - I1 consistent with principal_moments"
            )
    exact = _m.Eigenbasis(b.eigenbasis.values, b.eigenbasis.vectors, given)
    t = b.tensor if tensor is None else 0.5 * (tensor + tensor.T)
    return RigidBody(_m.Body(t, b.reference_point, b.center_of_mass, b.mass, exact), body.name)


def _check_agree(body: RigidBody, tensor: np.ndarray, rtol: float) -> None:
    mine = body._body.tensor
    scale = float(np.max(np.abs(mine)))
    if np.max(np.abs(mine - tensor)) > max(rtol, 1e-12) * scale:
        raise InputError("tensor", "a tensor", "the tensor of principal_moments and principal_axes (or give only one)")


# ---------------------------------------------------------------------------
# Density grids (xarray) -> SI slabs
# ---------------------------------------------------------------------------


def _parse_units(text, name: str, target: u.UnitBase, what: str) -> u.UnitBase:
    if text is None or (isinstance(text, str) and not text.strip()):
        raise InputError(name, "no 'units' attribute", f"{what} in attrs['units']")
    try:
        unit = u.Unit(str(text), parse_strict="raise")
    except ValueError:
        raise InputError(name, f"units {text!r}", f"{what} that astropy can parse") from None
    if not unit.is_equivalent(target, equivalencies=None):
        raise InputError(name, f"units {text!r}", what)
    return unit


def _grid_description(density):
    import xarray as xr

    if not isinstance(density, xr.DataArray):
        raise InputError("density", type(density).__name__, "an xarray.DataArray with dimensions x, y, z")
    dims = tuple(str(d) for d in density.dims)
    if sorted(dims) != ["x", "y", "z"]:
        raise InputError(
            "density", f"dimensions {dims}", "exactly the dimensions x, y and z (a regular Cartesian grid)"
        )
    unit = _parse_units(density.attrs.get("units"), "density", _DENSITY, "mass/volume units (e.g. 'kg m-3', 'g cm-3')")
    axes = []
    for d in dims:
        name = f"density.{d}"
        if d not in density.coords:
            raise InputError(name, "no coordinate", f"a 1-D coordinate with {_LENGTH_UNITS}")
        coord = density.coords[d]
        lunit = _parse_units(coord.attrs.get("units"), name, u.m, _LENGTH_UNITS)
        x = np.asarray(coord.values)
        axes.append(_uniform_axis(d, x, lunit, name))
    return dims, tuple(axes), float(unit.to(_DENSITY))


def _uniform_axis(dim: str, x: np.ndarray, unit: u.UnitBase, name: str) -> _grid.GridAxis:
    n = x.size
    if x.ndim != 1 or n < 2:
        raise InputError(name, f"{n} point(s)", "a 1-D coordinate with at least 2 points")
    xf = x.astype(float)
    if not np.all(np.isfinite(xf)):
        raise InputError(name, "NaN or inf", "finite coordinates")
    step = (xf[-1] - xf[0]) / (n - 1)
    ideal = xf[0] + step * np.arange(n)
    eps = np.finfo(x.dtype).eps if x.dtype.kind == "f" else np.finfo(float).eps
    tol = 1e-6 * abs(step) + 4 * eps * float(np.max(np.abs(xf)))
    spacings = np.diff(xf)
    if step == 0 or np.max(np.abs(xf - ideal)) > tol:
        raise InputError(
            name,
            f"spacings from {spacings.min():.6g} to {spacings.max():.6g} {unit}",
            "uniformly spaced, strictly monotonic coordinates (to 1e-6 of the spacing); resample the grid first",
        )
    factor = float(unit.to(u.m))
    return _grid.GridAxis(dim, n, xf[0] * factor, xf[-1] * factor)


def _slabs(density, dims: tuple[str, ...], chunk_bytes: int):
    n0, n1, n2 = (density.sizes[d] for d in dims)
    per_plane = max(1, n1 * n2 * 8)
    step = max(1, chunk_bytes // per_plane)
    for start in range(0, n0, step):
        block = density.isel({dims[0]: slice(start, start + step)}).values
        yield start, block
