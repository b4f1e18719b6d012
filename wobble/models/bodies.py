"""Rigid bodies in SI: inertia tensors, principal axes, L, T (course notes section 5.1).

Closed-form solids and planets are in :mod:`wobble.models.solids`, bodies from a
density sampled on a grid in :mod:`wobble.models.density_grid`.

Everything here is float64 in SI units: masses in kg, lengths in m, moments of
inertia in kg m^2, angular velocities in rad/s, energies in J. No units, no
xarray, no files: :mod:`wobble.api.bodies` converts at the boundary.

A :class:`Body` is an inertia tensor about a **reference point**, with its axes
those of the **input frame** (the frame the user described the body in), plus the
body's mass and centre of mass when known. The reference point is the centre of
mass unless the body was built or shifted about another point (a top spins about
its tip). The inertia tensor is (notes section 5.1, p. 67)

    I_jk = sum_i m_i (r_i^2 delta_jk - x_ij x_ik)          (point masses)
    I_jk = integral rho(r) (r^2 delta_jk - x_j x_k) dV     (a continuous body)

with positions measured from the reference point; L = I omega, T = 1/2 omega . I . omega
and the moment about a unit axis n is n . I . n (p. 67-68).

Precision rules used throughout:

* the diagonal I_xx is summed as ``S_yy + S_zz`` (never ``trace(S) - S_xx``), so a
  needle's small moment keeps its relative precision;
* positions are taken relative to the centre of mass (or the grid centre) before
  squaring, so a body far from the origin loses nothing;
* principal-moment differences given directly (a planet's H or J2, two nearly
  equal semi-axes) are carried as an antisymmetric matrix ``D[i, j] = I_i - I_j``
  and never recomputed by subtraction; ratios such as (I3 - I1)/I1 use them.
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from wobble.numerics.floats import EPS, HUGE, TINY
from wobble.errors import InputError
from wobble.numerics.symmetric_eigen import canonical_frame, degenerate_pairs, symmetric_eigen3

__all__ = [
    "DEFAULT_RTOL",
    "ORDERS",
    "CLASSES",
    "Body",
    "PrincipalFrame",
    "Classification",
    "Eigenbasis",
    "steiner_term",
    "tensor_from_second_moments",
    "positive_number",
    "overflow_is_input_error",
    "sorted_with_differences",
    "from_principal_moments",
    "from_tensor",
    "from_point_masses",
    "composite",
]

#: Default relative tolerance: for symmetry of a given tensor, the triangle
#: inequalities, and for calling two principal moments equal (classification and
#: the canonical frame). Rounding noise of float64 tensors is ~1e-15; Earth's two
#: equatorial moments differ by 2.5e-5, so Earth is "asymmetric" at this tolerance.
DEFAULT_RTOL = 1e-9

#: Orders in which principal moments and axes can be listed.
ORDERS = ("ascending", "descending", "input", "symmetry")
#: Classification names.
CLASSES = ("spherical", "oblate", "prolate", "asymmetric")


# ---------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------


def _readonly(a) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


def _vector(value, name: str) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (3,):
        raise InputError(name, value, "a 3-vector (x, y, z)")
    if not np.all(np.isfinite(v)):
        raise InputError(name, value, "finite values (no NaN or inf)")
    return v


def positive_number(value, name: str, *, allow_zero: bool = False) -> float:
    """``value`` as a float, checked positive (or non-negative) and finite; else an InputError naming ``name``."""
    x = float(value)
    if not math.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        want = "a non-negative" if allow_zero else "a positive"
        raise InputError(name, value, f"{want}, finite number (SI)")
    return x


class BelowNormal(ArithmeticError):
    """A moment of inertia that should be positive came out below the normal doubles (2.2e-308 kg m^2)."""


#: The smallest normal double: a moment below it is subnormal (a few digits, or 0).


def check_normal(moments, may_vanish=()) -> None:
    """Raise :class:`BelowNormal` if a moment (kg m^2) is below the normal doubles; the indices in
    ``may_vanish`` are moments that are 0 by construction (a thin rod's axial moment)."""
    for k, v in enumerate(np.asarray(moments, dtype=float).reshape(-1)):
        if k not in may_vanish and v < TINY:
            raise BelowNormal


def scale_of(lengths) -> float:
    """A power of two near the largest of ``lengths`` (m): dividing by it is exact, and the squares of the
    scaled lengths neither underflow nor overflow (a 1e-300 m box of 1e300 kg has moments of 1e-300 kg m^2,
    though its edges squared are 0 in doubles)."""
    big = float(np.max(np.abs(np.asarray(lengths, dtype=float))))
    return math.ldexp(1.0, math.frexp(big)[1]) if big > 0 and math.isfinite(big) else 1.0


def overflow_is_input_error(fn):
    """Run a constructor with floating-point overflow, or moments below the normal doubles, as an
    InputError naming it.

    Finite inputs can overflow (a 1e200 m ellipsoid has moments near 1e400 kg m^2):
    that is bad input, not a bug, and must not surface as a NumPy warning or inf.
    Tiny ones can leave the normal range (an ellipsoid of 1e-300 kg and 1e-300 m has moments
    near 1e-900 kg m^2): printed as 0, or a subnormal with a few wrong digits among 7.
    """

    @functools.wraps(fn)
    def checked(*args, **kwargs):
        try:
            with np.errstate(over="raise", invalid="raise"):
                return fn(*args, **kwargs)
        except (FloatingPointError, OverflowError):
            raise InputError(
                fn.__name__,
                ", ".join(map(str, [*args, *kwargs.values()])),
                f"sizes whose moments of inertia fit double precision (below {HUGE:.4g} kg m2)",
            ) from None
        except BelowNormal:
            raise InputError(
                fn.__name__,
                ", ".join(map(str, [*args, *kwargs.values()])),
                f"sizes whose moments of inertia are normal doubles (at least {TINY:.4g} kg m2: "
                "below, a double keeps only a few digits, or none)",
            ) from None

    return checked


def steiner_term(mass: float, d: np.ndarray) -> np.ndarray:
    """Parallel-axis (Steiner) term ``M (|d|^2 delta_jk - d_j d_k)`` in kg m^2.

    Adding it to the tensor about the centre of mass gives the tensor about the
    point at ``-d`` from the centre of mass (``d`` = centre of mass minus point, m).
    The diagonal is formed as sums of squares, never as a difference.
    """
    d = np.asarray(d, dtype=float)
    # In units of a power of two near |d| (exact): M d^2 of 1e300 kg at 1e-300 m is 1e-300 kg m^2, though d^2 is 0.
    s = scale_of(d)
    d = d / s
    ms = (mass * s) * s
    dd = d * d
    out = 0.0 - ms * np.outer(d, d)  # 0.0 - x: no negative zeros off the diagonal
    out[0, 0] = ms * (dd[1] + dd[2])
    out[1, 1] = ms * (dd[0] + dd[2])
    out[2, 2] = ms * (dd[0] + dd[1])
    return out


def tensor_from_second_moments(s: np.ndarray) -> np.ndarray:
    """I = tr(S) 1 - S for S_jk = sum m x_j x_k, with the diagonal as sums (no cancellation)."""
    out = 0.0 - np.array(s, dtype=float)
    out[0, 0] = s[1, 1] + s[2, 2]
    out[1, 1] = s[0, 0] + s[2, 2]
    out[2, 2] = s[0, 0] + s[1, 1]
    return 0.5 * (out + out.T)


def _differences(values: np.ndarray) -> np.ndarray:
    return values[:, None] - values[None, :]


# ---------------------------------------------------------------------------
# Principal frame and classification
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class PrincipalFrame:
    """Principal moments and axes of a body, in a stated order.

    Attributes
    ----------
    moments : ndarray, shape (3,)
        Principal moments I1, I2, I3 in kg m^2.
    axes : ndarray, shape (3, 3)
        Row ``k`` is the unit vector of principal axis ``k + 1`` in input-frame
        components. The matrix is a proper rotation (right-handed, det +1) and
        maps input-frame components to principal-frame components: ``v_p = axes @ v``.
    differences : ndarray, shape (3, 3)
        ``D[i, j] = I_(i+1) - I_(j+1)`` in kg m^2, exact where the user gave them.
    order : str
        One of :data:`ORDERS`.
    """

    moments: np.ndarray
    axes: np.ndarray
    differences: np.ndarray
    order: str

    def ratio(self, i: int, j: int, k: int | None = None) -> float:
        """The dimensionless ratio (I_i - I_j)/I_k (1-based indices; ``k`` defaults to ``j``).

        Computed from the stored differences, so (I3 - I1)/I1 of a planet built from
        H keeps full relative precision. Division by a zero moment gives +-inf (or
        0 when the difference is zero too).
        """
        for name, idx in (("i", i), ("j", j), ("k", k if k is not None else j)):
            if idx not in (1, 2, 3):
                raise InputError(name, idx, "a principal-axis number 1, 2 or 3")
        k = j if k is None else k
        num = float(self.differences[i - 1, j - 1])
        den = float(self.moments[k - 1])
        if den == 0.0:
            return 0.0 if num == 0.0 else math.copysign(math.inf, num)
        return num / den


@dataclass(frozen=True)
class Classification:
    """Shape class of a body from its principal moments I1 <= I2 <= I3.

    Attributes
    ----------
    kind : str
        ``spherical`` (I1 = I2 = I3), ``oblate`` (I1 = I2 < I3, a disc or Earth),
        ``prolate`` (I1 < I2 = I3, a rod or cigar) or ``asymmetric``; "=" means
        equal to the relative tolerance ``rtol``.
    rtol : float
        The tolerance used.
    splitting_12, splitting_23 : float
        (I2 - I1)/I2 and (I3 - I2)/I3, from the exact differences where known.
    """

    kind: str
    rtol: float
    splitting_12: float
    splitting_23: float

    @property
    def asymmetry(self) -> float:
        """Relative difference of the closest pair of principal moments.

        A body is symmetric (oblate, prolate or spherical) exactly when this is
        <= ``rtol``; for a near-symmetric body it is the small number that the
        classification rounded to zero (e.g. 1e-12 for a top made in a lathe).
        """
        return min(self.splitting_12, self.splitting_23)


def _split(diff: float, larger: float) -> float:
    return 0.0 if larger == 0.0 else abs(diff) / abs(larger)


def classify_moments(moments: np.ndarray, differences: np.ndarray, rtol: float) -> Classification:
    """Classify ascending principal moments (see :class:`Classification`)."""
    s12 = _split(differences[1, 0], moments[1])
    s23 = _split(differences[2, 1], moments[2])
    deg12, deg23 = degenerate_pairs(differences, moments, rtol)
    if deg12 and deg23:
        kind = "spherical"
    elif deg12:
        kind = "oblate"
    elif deg23:
        kind = "prolate"
    else:
        kind = "asymmetric"
    return Classification(kind, float(rtol), float(s12), float(s23))


def _check_rtol(rtol) -> float:
    try:
        r = float(rtol)
    except (TypeError, ValueError):
        r = math.nan
    if not (0.0 <= r < 1.0):
        raise InputError("rtol", rtol, "a relative tolerance in [0, 1), e.g. 1e-9")
    return r


def _reorder(frame: PrincipalFrame, order: str, rtol: float) -> PrincipalFrame:
    """Re-list an ascending frame in another order, keeping it right-handed."""
    m, a, d = frame.moments, frame.axes, frame.differences
    if order == "ascending":
        return frame
    if order == "descending":
        perm = [2, 1, 0]
        axes = a[perm].copy()
        axes[1] = -axes[1]  # an odd permutation: flip the middle axis to stay right-handed
    elif order == "symmetry":
        kind = classify_moments(m, d, rtol).kind
        perm = [1, 2, 0] if kind == "prolate" else [0, 1, 2]  # cyclic: handedness kept
        axes = a[perm]
    elif order == "input":
        # The principal axis closest to input axis x first, then y, then z.
        perm = list(max(itertools.permutations(range(3)), key=lambda p: sum(abs(a[p[i], i]) for i in range(3))))
        axes = a[perm].copy()
        for i in (0, 1):
            if axes[i, i] < 0:
                axes[i] = -axes[i]
        axes[2] = np.cross(axes[0], axes[1])
    else:
        raise InputError("order", order, ", ".join(ORDERS))
    return PrincipalFrame(m[perm], axes, d[np.ix_(perm, perm)], order)


# ---------------------------------------------------------------------------
# The body
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Eigenbasis:
    """Exact principal data known at construction: ascending moments (kg m^2), their axes as
    rows (input frame) and the differences ``D[i, j] = I_i - I_j`` given without cancellation.

    A body built from its principal moments (a planet from H or J2, a solid in closed form)
    carries one, so its principal frame is not recomputed from the tensor by an eigensolver.
    """

    values: np.ndarray
    vectors: np.ndarray
    differences: np.ndarray


@dataclass(frozen=True, eq=False)
class Body:
    """A rigid body in SI: inertia tensor about a reference point, input-frame axes.

    Attributes
    ----------
    tensor : ndarray, shape (3, 3)
        Inertia tensor in kg m^2 about ``reference_point`` (symmetric).
    reference_point : ndarray, shape (3,)
        The point (m, input frame) the tensor is taken about.
    center_of_mass : ndarray, shape (3,)
        Centre of mass (m, input frame).
    mass : float or None
        Total mass in kg; None when the body was given by its moments alone.
    eigenbasis : Eigenbasis or None
        The principal data given exactly at construction, if any.
    """

    tensor: np.ndarray
    reference_point: np.ndarray
    center_of_mass: np.ndarray
    mass: float | None = None
    eigenbasis: Eigenbasis | None = field(default=None, repr=False)

    def __post_init__(self):
        for name in ("tensor", "reference_point", "center_of_mass"):
            value = np.asarray(getattr(self, name), dtype=float)
            if not np.all(np.isfinite(value)):
                # Finite inputs can still overflow (a 1e200 m ellipsoid has moments ~1e400).
                raise InputError(
                    name,
                    value.tolist(),
                    f"finite values: the inputs overflow double precision (beyond {HUGE:.4g} in SI)",
                )
        if self.mass is not None and not math.isfinite(self.mass):
            raise InputError("mass", self.mass, "a finite mass: the inputs overflow double precision")
        object.__setattr__(self, "tensor", _readonly(self.tensor))
        object.__setattr__(self, "reference_point", _readonly(self.reference_point))
        object.__setattr__(self, "center_of_mass", _readonly(self.center_of_mass))

    # -- principal axes -----------------------------------------------------

    def principal(self, order: str = "ascending", rtol: float = DEFAULT_RTOL) -> PrincipalFrame:
        """Principal moments (kg m^2) and axes (rows, input frame) about the reference point.

        Parameters
        ----------
        order : {"ascending", "descending", "input", "symmetry"}
            ``ascending`` (I1 <= I2 <= I3, the default); ``descending``; ``input``
            (the axis nearest input x first, then y, then z, each pointing along
            its input axis); ``symmetry`` (ascending, except that a prolate body
            lists its unique axis third, as a top's figure axis is x3).
        rtol : float
            Moments within this relative tolerance are treated as equal when
            fixing the frame (see :mod:`wobble.numerics.symmetric_eigen`).
        """
        rtol = _check_rtol(rtol)
        if order not in ORDERS:
            raise InputError("order", order, ", ".join(ORDERS))
        if self.eigenbasis is not None:
            values, vectors, diffs = self.eigenbasis.values, self.eigenbasis.vectors, self.eigenbasis.differences
            axes = canonical_frame(values, vectors, diffs, rtol)
        else:
            values, axes = symmetric_eigen3(self.tensor, rtol)
            # A mass distribution's tensor is positive semi-definite: a negative
            # eigenvalue can only be rounding (a line of point masses).
            tiny = 8.0 * EPS * float(np.max(np.abs(values)))
            values = np.where((values < 0) & (values >= -tiny), 0.0, values)
            diffs = _differences(values)
        frame = PrincipalFrame(_readonly(values), _readonly(axes), _readonly(diffs), "ascending")
        return _reorder(frame, order, rtol)

    def classify(self, rtol: float = DEFAULT_RTOL) -> Classification:
        """Spherical, oblate, prolate or asymmetric, to the relative tolerance ``rtol``."""
        frame = self.principal("ascending", rtol)
        return classify_moments(frame.moments, frame.differences, _check_rtol(rtol))

    # -- dynamics (notes 5.1) -------------------------------------------------

    def _frame_matrix(self, frame: str) -> np.ndarray | None:
        if frame == "input":
            return None
        if frame == "principal":
            return self.principal().axes
        raise InputError("frame", frame, "'input' or 'principal' (ascending principal axes)")

    def angular_momentum(self, omega, frame: str = "input") -> np.ndarray:
        """L = I omega (kg m^2/s) for angular velocity ``omega`` (rad/s, shape (..., 3)).

        ``frame`` says in which axes ``omega`` is given and ``L`` returned: the
        input frame or the (ascending) principal frame, where L_j = I_j omega_j.
        L is about the reference point (rotation about that fixed point).
        """
        w = _omega(omega)
        a = self._frame_matrix(frame)
        t = self.tensor if a is None else a @ self.tensor @ a.T
        return np.einsum("jk,...k->...j", t, w)

    def kinetic_energy(self, omega, frame: str = "input") -> np.ndarray:
        """T = 1/2 omega . I . omega in J for ``omega`` in rad/s (shape (..., 3))."""
        w = _omega(omega)
        a = self._frame_matrix(frame)
        t = self.tensor if a is None else a @ self.tensor @ a.T
        return 0.5 * np.einsum("...j,jk,...k->...", w, t, w)

    def moment_about(self, axis, frame: str = "input") -> np.ndarray:
        """n . I . n in kg m^2 for the direction ``axis`` (normalised here; shape (..., 3))."""
        n = np.asarray(axis, dtype=float)
        if n.shape[-1:] != (3,) or not np.all(np.isfinite(n)):
            raise InputError("axis", axis, "finite direction vectors of shape (..., 3)")
        norm = np.linalg.norm(n, axis=-1, keepdims=True)
        if np.any(norm == 0):
            raise InputError("axis", axis, "non-zero direction vectors")
        n = n / norm
        a = self._frame_matrix(frame)
        t = self.tensor if a is None else a @ self.tensor @ a.T
        return np.einsum("...j,jk,...k->...", n, t, n)

    # -- moving the body and the reference point -----------------------------

    def _require_mass(self, why: str) -> float:
        if self.mass is None:
            raise InputError("mass", None, f"a body with a known mass (needed to {why}); pass mass= when building it")
        return self.mass

    def central_tensor(self) -> np.ndarray:
        """Inertia tensor about the centre of mass (kg m^2), input-frame axes."""
        d = self.center_of_mass - self.reference_point
        if not np.any(d):
            return np.array(self.tensor)
        mass = self._require_mass("move the tensor to the centre of mass")
        return self.tensor - steiner_term(mass, d)

    def shifted_to(self, point) -> Body:
        """The same body with its tensor taken about ``point`` (m, input frame): parallel axes."""
        p = _vector(point, "point")
        if np.array_equal(p, self.reference_point):
            return self
        mass = self._require_mass("shift the reference point")
        try:
            with np.errstate(over="raise", invalid="raise"):
                tensor = self.central_tensor() + steiner_term(mass, self.center_of_mass - p)
        except FloatingPointError:
            raise InputError(
                "point",
                tuple(float(x) for x in p),
                "a point whose parallel-axis term M |d|^2 fits "
                "double precision (below about 1e308 kg m2), d its distance from the centre of mass",
            ) from None
        return Body(0.5 * (tensor + tensor.T), p, self.center_of_mass, mass)

    def translated(self, offset) -> Body:
        """The body moved by ``offset`` (m); the tensor about the moved reference point is unchanged."""
        d = _vector(offset, "offset")
        return Body(self.tensor, self.reference_point + d, self.center_of_mass + d, self.mass, self.eigenbasis)

    def rotated(self, rotation, about=None) -> Body:
        """The body turned by the proper rotation matrix ``rotation`` about ``about`` (m; origin).

        An active rotation: a point r of the body moves to R (r - p) + p, the
        tensor becomes R I R^T. Principal moments (and their exact differences)
        are unchanged.
        """
        r = _rotation_matrix(rotation)
        p = np.zeros(3) if about is None else _vector(about, "about")
        tensor = r @ self.tensor @ r.T
        exact = None
        if self.eigenbasis is not None:
            exact = Eigenbasis(self.eigenbasis.values, self.eigenbasis.vectors @ r.T, self.eigenbasis.differences)
        return Body(
            0.5 * (tensor + tensor.T),
            r @ (self.reference_point - p) + p,
            r @ (self.center_of_mass - p) + p,
            self.mass,
            exact,
        )


def _omega(omega) -> np.ndarray:
    w = np.asarray(omega, dtype=float)
    if w.shape[-1:] != (3,) or not np.all(np.isfinite(w)):
        raise InputError("omega", omega, "finite angular velocities of shape (..., 3) in rad/s")
    return w


def _rotation_matrix(rotation, name: str = "rotation") -> np.ndarray:
    r = np.asarray(rotation, dtype=float)
    allowed = "a proper rotation matrix (3x3, orthonormal to 1e-10, determinant +1)"
    if r.shape != (3, 3) or not np.all(np.isfinite(r)):
        raise InputError(name, rotation, allowed)
    if np.max(np.abs(r @ r.T - np.eye(3))) > 1e-10 or np.linalg.det(r) <= 0:
        raise InputError(name, rotation, allowed)
    # Remove the rounding-level non-orthogonality (nearest rotation, polar decomposition).
    u_, _, vt = np.linalg.svd(r)
    return u_ @ vt


# ---------------------------------------------------------------------------
# Checks on user-given tensors and moments
# ---------------------------------------------------------------------------


def _check_triangle(values: np.ndarray, diffs: np.ndarray, name: str, rtol: float, shown) -> None:
    """I1 + I2 >= I3 (and cyclic): every mass distribution satisfies it (sum of two squares)."""
    # With I1 <= I2 <= I3 only I1 + I2 >= I3 can fail; I1 - (I3 - I2) uses the exact difference.
    excess = values[0] - diffs[2, 1]
    if excess < -rtol * values[2]:
        raise InputError(
            name,
            shown,
            f"principal moments obeying the triangle inequality I1 + I2 >= I3 (and cyclic), "
            f"as every mass distribution does; here I1 + I2 - I3 = {excess:.6g} kg m2",
        )


def sorted_with_differences(values_xyz: np.ndarray, diffs_xyz: np.ndarray | None):
    order = np.argsort(values_xyz, kind="stable")
    values = values_xyz[order]
    if diffs_xyz is None:
        diffs = _differences(values)
    else:
        diffs = np.asarray(diffs_xyz, dtype=float)[np.ix_(order, order)]
    return order, values, diffs


def _placement(mass, center_of_mass, about) -> tuple[float | None, np.ndarray, np.ndarray]:
    m = None if mass is None else positive_number(mass, "mass")
    com = np.zeros(3) if center_of_mass is None else _vector(center_of_mass, "center_of_mass")
    ref = com if about is None else _vector(about, "about")
    return m, com, ref


def _check_central(tensor: np.ndarray, mass, com, ref, name: str, rtol: float, shown) -> None:
    """A tensor about a point other than the centre of mass must leave a physical central tensor."""
    d = com - ref
    if mass is None or not np.any(d):
        return
    central = tensor - steiner_term(mass, d)
    values, _ = symmetric_eigen3(central, rtol)
    scale = max(float(np.max(np.abs(tensor))), 1e-300)
    if values[0] < -rtol * scale:
        raise InputError(
            name,
            shown,
            "a tensor at least as large as the parallel-axis term M (d^2 1 - d d^T) of the "
            "centre of mass offset (the tensor about the centre of mass would not be positive)",
        )
    _check_triangle(values, _differences(values), name, rtol, shown)


@overflow_is_input_error
def from_principal_moments(
    moments,
    *,
    differences=None,
    mass=None,
    center_of_mass=None,
    about=None,
    axes=None,
    rtol: float = DEFAULT_RTOL,
    name: str = "moments",
) -> Body:
    """A body from its principal moments (kg m^2), along the input axes or given ``axes``.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Positive principal moments, one per principal axis. Without ``axes`` they
        are the moments about the input x, y, z axes (a diagonal tensor).
    axes : array_like, shape (3, 3), optional
        Row ``k`` is the unit vector (input-frame components) of the axis of
        ``moments[k]``; a proper rotation matrix. The tensor is then
        ``axes.T @ diag(moments) @ axes``.
    differences : array_like, shape (3, 3), optional
        ``D[i, j] = moments[i] - moments[j]`` when known without cancellation
        (kg m^2); otherwise formed by subtraction.
    mass : float, optional
        Mass in kg (needed to shift the reference point or combine bodies).
    center_of_mass : array_like, shape (3,), optional
        Centre of mass in m (default: the origin).
    about : array_like, shape (3,), optional
        The point the moments are taken about (default: the centre of mass).
    rtol : float
        Tolerance for the triangle inequalities.
    name : str
        Parameter name used in error messages.
    """
    rtol = _check_rtol(rtol)
    v = np.asarray(moments, dtype=float)
    if v.shape != (3,):
        raise InputError(name, moments, "three principal moments (I1, I2, I3)")
    if not np.all(np.isfinite(v)):
        raise InputError(name, moments, "finite moments (no NaN or inf)")
    if not np.all(v > 0):
        raise InputError(name, moments, "positive moments of inertia (every real body has I > 0)")
    if differences is not None:
        differences = np.asarray(differences, dtype=float)
        if differences.shape != (3, 3) or not np.all(np.isfinite(differences)):
            raise InputError("differences", differences, "a finite 3x3 matrix D[i, j] = I_i - I_j")
    order, values, diffs = sorted_with_differences(v, differences)
    _check_triangle(values, diffs, name, rtol, moments)
    m, com, ref = _placement(mass, center_of_mass, about)
    if axes is None:
        rows, tensor = np.eye(3), np.diag(v)
    else:
        rows = _rotation_matrix(axes, "axes")
        tensor = rows.T @ np.diag(v) @ rows
        tensor = 0.5 * (tensor + tensor.T)
    _check_central(tensor, m, com, ref, name, rtol, moments)
    return Body(tensor, ref, com, m, Eigenbasis(values, rows[order], diffs))


@overflow_is_input_error
def from_tensor(
    tensor, *, mass=None, center_of_mass=None, about=None, rtol: float = DEFAULT_RTOL, name: str = "tensor"
) -> Body:
    """A body from a full 3x3 inertia tensor (kg m^2), checked.

    The tensor must be finite, symmetric to ``rtol`` (relative to its largest
    entry; it is then symmetrised), positive definite, and its principal moments
    must obey the triangle inequalities I1 + I2 >= I3 (and cyclic) to ``rtol``.
    ``mass``, ``center_of_mass`` and ``about`` are as in :func:`from_principal_moments`.
    """
    rtol = _check_rtol(rtol)
    t = np.asarray(tensor, dtype=float)
    if t.shape != (3, 3):
        raise InputError(name, tensor, "a 3x3 inertia tensor")
    if not np.all(np.isfinite(t)):
        raise InputError(name, tensor, "finite entries (no NaN or inf)")
    scale = float(np.max(np.abs(t)))
    asym = float(np.max(np.abs(t - t.T)))
    if asym > rtol * scale:
        raise InputError(
            name, tensor, f"a symmetric tensor (I_jk = I_kj to a relative {rtol:g}); largest I_jk - I_kj = {asym:.6g}"
        )
    t = 0.5 * (t + t.T)
    values, _ = symmetric_eigen3(t, rtol)
    if not values[0] > 0:
        raise InputError(
            name, tensor, f"a positive-definite tensor (all principal moments > 0); smallest = {values[0]:.6g}"
        )
    _check_triangle(values, _differences(values), name, rtol, tensor)
    m, com, ref = _placement(mass, center_of_mass, about)
    _check_central(t, m, com, ref, name, rtol, tensor)
    return Body(t, ref, com, m)


@overflow_is_input_error
def from_point_masses(masses, positions, *, about=None) -> Body:
    """Point masses m_i (kg) at r_i (m): I_jk = sum_i m_i (r_i^2 delta_jk - x_ij x_ik).

    Vectorised over the masses. Positions are taken relative to the centre of mass
    before squaring (no cancellation for bodies far from the origin), then the
    tensor is moved to ``about`` (m; default: the centre of mass) exactly as the
    sum over (r_i - about) would give.
    """
    m = np.asarray(masses, dtype=float)
    r = np.asarray(positions, dtype=float)
    if m.ndim != 1 or m.size == 0:
        raise InputError("masses", masses, "a non-empty 1-D array of masses")
    if r.shape != (m.size, 3):
        raise InputError("positions", f"array of shape {r.shape}", f"shape ({m.size}, 3): one (x, y, z) per mass")
    if not np.all(np.isfinite(m)) or not np.all(m > 0):
        bad = m[~(np.isfinite(m) & (m > 0))][0]
        raise InputError("masses", bad, "positive, finite masses")
    if not np.all(np.isfinite(r)):
        raise InputError("positions", "NaN or inf", "finite positions")
    total = float(np.sum(m))
    # Products rounded one by one, then summed: a matrix product may fuse them (FMA), and then the two halves of a
    # symmetric body leave a residue of one product's rounding (1e-18 m for 10 g at +/-5 cm) instead of 0.
    com = (m[:, None] * r).sum(axis=0) / total
    ref = com if about is None else _vector(about, "about")
    d = r - ref
    md = m[:, None] * d
    # The same for the second moments: six sums of rounded products (memory N, not 9N), not a fused matrix product.
    s = np.empty((3, 3))
    for j in range(3):
        for k in range(j, 3):
            s[j, k] = s[k, j] = np.sum(md[:, j] * d[:, k])
    return Body(tensor_from_second_moments(s), ref, com, total)


# ---------------------------------------------------------------------------
# Composite bodies
# ---------------------------------------------------------------------------


def composite(parts: Iterable[Body], about=None) -> Body:
    """The sum of bodies (each already placed and rotated), about ``about`` (default: the joint centre of mass).

    Each part's tensor is moved to the common point with the parallel-axis theorem
    from its own centre of mass: I = sum_parts [I_cm + m (d^2 1 - d d^T)].
    """
    parts = list(parts)
    if not parts:
        raise InputError("parts", parts, "at least one body")
    for i, p in enumerate(parts):
        if not isinstance(p, Body):
            raise InputError(f"parts[{i}]", p, "a Body")
        p._require_mass("combine bodies")
    masses = np.array([p.mass for p in parts])
    total = float(masses.sum())
    coms = np.array([p.center_of_mass for p in parts])
    com = (masses @ coms) / total
    ref = com if about is None else _vector(about, "about")
    tensor = np.zeros((3, 3))
    for p in parts:
        tensor = tensor + p.central_tensor() + steiner_term(p.mass, p.center_of_mass - ref)
    return Body(0.5 * (tensor + tensor.T), ref, com, total)
