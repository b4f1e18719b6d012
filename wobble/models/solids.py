"""Solids and planets in closed form: their inertia tensors about the centre of mass (SI float64).

Uniform solids (sphere, shell, ellipsoid, box, cylinder, cone, disc, rod) with the
centre of mass at the origin and the symmetry axis along z, a spinning top built
from a disc and an axle, and a planet from C/(M R^2) and H or J2 (MacCullagh's
formula). Principal-moment differences are formed from the small quantities (two
nearly equal semi-axes, H, J2, J22), never by subtracting large moments, and are
carried exactly (:class:`wobble.models.bodies.Eigenbasis`). Squares of lengths are taken in units of a
power of two near the largest length (exact), and M times it twice, so a moment that is a normal double is
computed as one (a 1e-300 m box of 1e300 kg: 1e-300 kg m^2, not 0); a moment below the normal doubles is
refused (:func:`wobble.models.bodies.overflow_is_input_error`).
"""

from __future__ import annotations

import math

import numpy as np

from wobble.errors import InputError
from wobble.models.bodies import (
    Body,
    Eigenbasis,
    check_normal,
    composite,
    from_principal_moments,
    overflow_is_input_error,
    positive_number,
    scale_of,
    sorted_with_differences,
)

__all__ = [
    "solid_sphere",
    "hollow_sphere",
    "ellipsoid",
    "box",
    "cylinder",
    "cone",
    "thin_disc",
    "thin_rod",
    "spinning_top",
    "oblate_planet",
]


def _solid(mass: float, moments_xyz, differences=None, may_vanish=()) -> Body:
    v = np.asarray(moments_xyz, dtype=float)
    check_normal(v, may_vanish)
    order, values, diffs = sorted_with_differences(v, differences)
    return Body(np.diag(v), np.zeros(3), np.zeros(3), mass, Eigenbasis(values, np.eye(3)[order], diffs))


def _two_square_differences(k: float, q: np.ndarray) -> np.ndarray:
    """D[i, j] for I_i = k (s - q_i^2), s = sum q^2: I_i - I_j = k (q_j - q_i)(q_j + q_i), no cancellation."""
    return k * (q[None, :] - q[:, None]) * (q[None, :] + q[:, None])


@overflow_is_input_error
def solid_sphere(mass: float, radius: float) -> Body:
    """Uniform solid sphere: I = 2/5 M R^2 about every axis."""
    m, r = positive_number(mass, "mass"), positive_number(radius, "radius")
    i = 0.4 * m * r * r
    return _solid(m, [i, i, i], np.zeros((3, 3)))


@overflow_is_input_error
def hollow_sphere(mass: float, radius: float, inner_radius: float | None = None) -> Body:
    """Uniform spherical shell between ``inner_radius`` and ``radius`` (thin shell if None).

    I = 2/5 M (R^5 - r^5)/(R^3 - r^3), evaluated as
    2/5 M R^2 (1 + q + q^2 + q^3 + q^4)/(1 + q + q^2) with q = r/R (no cancellation
    for a thin shell, where q = 1 gives 2/3 M R^2; no underflow of R^4 for a tiny R).
    """
    m, big = positive_number(mass, "mass"), positive_number(radius, "radius")
    small = big if inner_radius is None else positive_number(inner_radius, "inner_radius", allow_zero=True)
    if small > big:
        raise InputError("inner_radius", inner_radius, f"at most the outer radius ({big:g} m)")
    q = small / big
    i = 0.4 * m * big * big * (1.0 + q * (1.0 + q * (1.0 + q * (1.0 + q)))) / (1.0 + q * (1.0 + q))
    return _solid(m, [i, i, i], np.zeros((3, 3)))


@overflow_is_input_error
def ellipsoid(mass: float, semi_axes) -> Body:
    """Uniform solid ellipsoid with semi-axes (a, b, c) along x, y, z: I_x = M (b^2 + c^2)/5, ..."""
    m = positive_number(mass, "mass")
    q = np.array([positive_number(x, "semi_axes") for x in _triple(semi_axes, "semi_axes")])
    scale = scale_of(q)
    q = q / scale
    k = (0.2 * m * scale) * scale
    s = q * q
    moments = k * np.array([s[1] + s[2], s[0] + s[2], s[0] + s[1]])
    return _solid(m, moments, _two_square_differences(k, q))


@overflow_is_input_error
def box(mass: float, edges) -> Body:
    """Uniform rectangular box with edge lengths (a, b, c) along x, y, z: I_x = M (b^2 + c^2)/12, ..."""
    m = positive_number(mass, "mass")
    q = np.array([positive_number(x, "edges") for x in _triple(edges, "edges")])
    scale = scale_of(q)
    q = q / scale
    k = (m / 12.0 * scale) * scale
    s = q * q
    moments = k * np.array([s[1] + s[2], s[0] + s[2], s[0] + s[1]])
    return _solid(m, moments, _two_square_differences(k, q))


def _triple(value, name: str):
    v = np.asarray(value, dtype=float)
    if v.shape != (3,):
        raise InputError(name, value, "three lengths (along x, y, z)")
    return v


@overflow_is_input_error
def cylinder(mass: float, radius: float, height: float, inner_radius: float = 0.0) -> Body:
    """Uniform cylinder (a tube if ``inner_radius`` > 0), axis along z.

    I_3 = M (R^2 + r^2)/2; I_1 = I_2 = M (3 (R^2 + r^2) + h^2)/12.
    """
    m, big, h = positive_number(mass, "mass"), positive_number(radius, "radius"), positive_number(height, "height")
    small = positive_number(inner_radius, "inner_radius", allow_zero=True)
    if small > big:
        raise InputError("inner_radius", inner_radius, f"at most the outer radius ({big:g} m)")
    scale = scale_of([big, small, h])
    big, small, h = big / scale, small / scale, h / scale
    ms = (m * scale) * scale
    r2 = big * big + small * small
    i1, i3 = ms * (3.0 * r2 + h * h) / 12.0, 0.5 * ms * r2
    return _solid(m, [i1, i1, i3])


@overflow_is_input_error
def cone(mass: float, radius: float, height: float) -> Body:
    """Uniform solid right circular cone, axis along z, about its centre of mass.

    The apex is at z = -3h/4 and the base (radius R) at z = +h/4 (a cone standing
    on its tip). I_3 = 3/10 M R^2; I_1 = I_2 = 3/80 M (4 R^2 + h^2).
    """
    m, r, h = positive_number(mass, "mass"), positive_number(radius, "radius"), positive_number(height, "height")
    scale = scale_of([r, h])
    r, h = r / scale, h / scale
    ms = (m * scale) * scale
    i1, i3 = 3.0 / 80.0 * ms * (4.0 * r * r + h * h), 0.3 * ms * r * r
    return _solid(m, [i1, i1, i3])


@overflow_is_input_error
def thin_disc(mass: float, radius: float) -> Body:
    """Uniform thin disc in the x-y plane: I_1 = I_2 = M R^2/4, I_3 = M R^2/2."""
    m, r = positive_number(mass, "mass"), positive_number(radius, "radius")
    i = 0.25 * m * r * r
    return _solid(m, [i, i, 2.0 * i])


@overflow_is_input_error
def thin_rod(mass: float, length: float) -> Body:
    """Uniform thin rod along z: I_1 = I_2 = M L^2/12, I_3 = 0 (an idealised line)."""
    m, ell = positive_number(mass, "mass"), positive_number(length, "length")
    i = m * ell * ell / 12.0
    return _solid(m, [i, i, 0.0], may_vanish=(2,))


@overflow_is_input_error
def spinning_top(
    disc_mass: float,
    disc_radius: float,
    axle_mass: float,
    axle_length: float,
    disc_height: float,
    axle_radius: float = 0.0,
) -> Body:
    """A top: a thin disc on an axle along z, with the tip of the axle at the origin.

    The axle (a thin rod, or a solid cylinder of ``axle_radius``) runs from the tip
    at z = 0 to z = ``axle_length``; the disc's centre is on the axle at
    z = ``disc_height``. The result is about its centre of mass; shift it to the
    tip (the origin) for the heavy-top engine (notes 5.7).
    """
    md = positive_number(disc_mass, "disc_mass")
    rd = positive_number(disc_radius, "disc_radius")
    ma = positive_number(axle_mass, "axle_mass", allow_zero=True)
    ell = positive_number(axle_length, "axle_length")
    h = positive_number(disc_height, "disc_height", allow_zero=True)
    if h > ell:
        raise InputError("disc_height", disc_height, f"a height on the axle, 0 to axle_length ({ell:g} m)")
    ra = positive_number(axle_radius, "axle_radius", allow_zero=True)
    parts = [thin_disc(md, rd).translated([0.0, 0.0, h])]
    if ma > 0:
        axle = thin_rod(ma, ell) if ra == 0 else cylinder(ma, ra, ell)
        parts.append(axle.translated([0.0, 0.0, 0.5 * ell]))
    top = composite(parts)
    check_normal(np.diag(top.tensor))
    return top


@overflow_is_input_error
def oblate_planet(
    mass: float,
    radius: float,
    polar_moment_factor: float,
    *,
    dynamical_flattening: float | None = None,
    j2: float | None = None,
    j22: float = 0.0,
) -> Body:
    """A planet from C/(M R^2) and either H = (C - A)/C or J2 = (C - A)/(M R^2).

    C = c M R^2 about the polar z axis; the mean equatorial moment is
    A = C (1 - H) or C - J2 M R^2 (MacCullagh's formula), and an optional
    equatorial ellipticity J22 = (B - A)/(4 M R^2) (unnormalised) splits it into
    A and B along x and y. The differences C - A, C - B, B - A are formed from H,
    J2 and J22 directly, so (C - A)/A keeps full precision however small H is.

    Parameters
    ----------
    mass : float
        kg.
    radius : float
        Reference (equatorial) radius R in m.
    polar_moment_factor : float
        C/(M R^2), in (0, 1).
    dynamical_flattening, j2 : float
        Exactly one: H in (0, 1/2] or J2 in (0, c/2] (A + B >= C, the moments' triangle inequality).
    j22 : float
        Unnormalised degree-2 order-2 coefficient magnitude, >= 0, below (1 - H) c / 2 so that A > 0.
    """
    m, r = positive_number(mass, "mass"), positive_number(radius, "radius")
    c = float(polar_moment_factor)
    if not (0.0 < c < 1.0):
        raise InputError("polar_moment_factor", polar_moment_factor, "C/(M R^2) in (0, 1) (0.3307 for Earth)")
    if (dynamical_flattening is None) == (j2 is None):
        raise InputError("dynamical_flattening/j2", (dynamical_flattening, j2), "exactly one of H or J2")
    mr2 = m * r * r
    big_c = c * mr2
    if dynamical_flattening is not None:
        hh = float(dynamical_flattening)
        if not (0.0 < hh <= 0.5):
            raise InputError(
                "dynamical_flattening",
                dynamical_flattening,
                "H = (C - A)/C in (0, 0.5]: positive for an oblate planet, at most 1/2 as A + B >= C",
            )
        c_minus_a = hh * big_c
    else:
        jj = float(j2)
        if not (0.0 < jj <= 0.5 * c):
            raise InputError("j2", j2, f"J2 in (0, C/(2 M R^2) = {0.5 * c:g}]: positive, and A + B >= C")
        c_minus_a = jj * mr2
    q = float(j22)
    if not (math.isfinite(q) and q >= 0):
        raise InputError("j22", j22, "a non-negative, finite J22")
    half_split = 2.0 * q * mr2  # (B - A)/2
    mean_a = big_c - c_minus_a
    if not half_split < mean_a:
        # The triangle inequality holds by H <= 1/2 (A + B = 2 mean A >= C); only A > 0 is left to J22.
        raise InputError(
            "j22", j22, f"J22 below (1 - H) c / 2 = {mean_a / (2.0 * mr2):g}: A = (1 - H) C - 2 J22 M R^2 must stay > 0"
        )
    moments = np.array([mean_a - half_split, mean_a + half_split, big_c])
    # D[i, j] = I_i - I_j from the small quantities, never by subtracting the large moments.
    cma, cmb, bma = c_minus_a + half_split, c_minus_a - half_split, 2.0 * half_split
    diffs = np.array([[0.0, -bma, -cma], [bma, 0.0, -cmb], [cma, cmb, 0.0]])
    return from_principal_moments(moments, differences=diffs, mass=m, name="polar_moment_factor")
