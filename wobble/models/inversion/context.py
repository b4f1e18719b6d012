"""What some forward models need besides the planet's parameters (SI floats).

The free core nutation needs the liquid core's *hydrostatic* dynamical ellipticity
e_f, which comes from the planet's density profile (Clairaut's equation,
:mod:`wobble.models.hydrostatic`); the precession rate needs the perturbers' orbits
(:mod:`wobble.models.precession`). Neither is a planet parameter, so a setup carries
them in a :class:`ForwardContext`, built by the setup reader
(:mod:`wobble.io.inversion_file`) from the shipped profile and perturber files.

Two hydrostatic cores:

* :class:`FixedCoreFigure`: a profile that does not change with the sampled
  parameters (PREM for Earth): e_f is one number, computed once by
  :func:`wobble.models.hydrostatic.hydrostatic_figure`.
* :class:`LinearMantleCoreFigure`: a uniform liquid core under a linear mantle fitted
  to the body's mass and polar moment (``mars_layered``,
  :func:`wobble.models.hydrostatic.core_under_linear_mantle`), rebuilt for every
  member from its sampled core radius and density (and polar moment). Clairaut's
  equation is solved ahead of sampling on a Chebyshev grid in the three
  dimensionless numbers e_f depends on, x = r_c/R, y = rho_c/rho_mean and
  c = C/(M R^2) (e_f/q depends on nothing else; q = Omega^2 R^3/(G M)), and
  interpolated (tensor Chebyshev series). The grid covers the box the priors can
  reach (a normal prior to 1e-12 in each tail); the interpolation error is measured
  against the direct vectorised solve
  (:func:`wobble.models.hydrostatic.core_flattening_under_linear_mantle`) at random
  admissible points of the box when the table is built (:attr:`~LinearMantleCoreFigure.max_error`;
  the build refuses a table worse than :data:`TABLE_TOLERANCE`), and members outside the
  box or outside the profiles :func:`~wobble.models.hydrostatic.check_profile` accepts
  get NaN. The Chebyshev series extends smoothly over the parts of the box where the
  profile is not admissible (Radau's equation stays regular there), so the validity
  boundary does not spoil the fit.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.polynomial import chebyshev as cheb

from wobble.errors import InputError
from wobble.models import hydrostatic as _hydro
from wobble.models.precession import PerturberOrbit, torque_strength

__all__ = ["ForwardContext", "FixedCoreFigure", "LinearMantleCoreFigure", "TABLE_TOLERANCE", "DEGREES"]

#: Largest relative interpolation error of e_f accepted when a table is built.
TABLE_TOLERANCE = 1e-9
#: Chebyshev degrees in (x, y, c), tried in order until the table meets TABLE_TOLERANCE.
DEGREES = ((14, 14, 6), (20, 20, 9), (28, 28, 12))
_CHECK_POINTS = 400


@dataclass(frozen=True)
class FixedCoreFigure:
    """The hydrostatic e_f of a fixed density profile (e.g. PREM): one number.

    Attributes
    ----------
    profile : str
        The profile's name.
    core_ellipticity : float
        e_f from Clairaut's equation for the profile at the planet's spin.
    """

    profile: str
    core_ellipticity: float

    def hydrostatic(self, batch) -> np.ndarray:
        """e_f of every member of ``batch`` (the same number)."""
        return np.full(batch.shape, self.core_ellipticity)

    def describe(self) -> str:
        return (
            f"hydrostatic e_f = {self.core_ellipticity:.7g} of the profile {self.profile} (Clairaut's equation, "
            "first order)"
        )


def _nodes(n: int) -> np.ndarray:
    """Chebyshev points of the first kind on [-1, 1] (no end points: the box edges are never sampled)."""
    k = np.arange(n)
    return np.cos(math.pi * (k + 0.5) / n)


def _to_box(u, lo, hi):
    return lo + 0.5 * (np.asarray(u) + 1.0) * (hi - lo)


def _from_box(v, lo, hi):
    return 2.0 * (np.asarray(v) - lo) / (hi - lo) - 1.0


def _fit(box, degrees):
    """Chebyshev coefficients (nx+1, ny+1, nc+1) of e_f/q on ``box`` by interpolation at the nodes."""
    us = [_nodes(d + 1) for d in degrees]
    grid = np.meshgrid(*[_to_box(u, lo, hi) for u, (lo, hi) in zip(us, box)], indexing="ij")
    values = _hydro.core_flattening_unchecked(grid[0].ravel(), grid[1].ravel(), grid[2].ravel(), 1e-12)
    values = values.reshape(grid[0].shape)
    if not np.all(np.isfinite(values)):
        return None
    inv = [np.linalg.inv(cheb.chebvander(u, d)) for u, d in zip(us, degrees)]
    return np.einsum("ai,bj,ck,ijk->abc", inv[0], inv[1], inv[2], values)


def _chebyshev_t(u, degree):
    """T_0..T_degree at u in [-1, 1], shape (n, degree + 1): cos(k arccos u), one vectorised call."""
    return np.cos(np.arccos(np.clip(u, -1.0, 1.0))[:, None] * np.arange(degree + 1))


def _evaluate(coefficients, box, x, y, c):
    degrees = [n - 1 for n in coefficients.shape]
    tx, ty, tc = (_chebyshev_t(_from_box(v, lo, hi), d) for v, (lo, hi), d in zip((x, y, c), box, degrees))
    inner = (tc @ coefficients.reshape(-1, degrees[2] + 1).T).reshape(-1, degrees[0] + 1, degrees[1] + 1)
    return np.einsum("ni,nij,nj->n", tx, inner, ty)


@lru_cache(maxsize=16)
def _table(box: tuple, seed: int):
    """(coefficients, max relative error, check points) for ``box``: the first degrees of
    :data:`DEGREES` whose error at random admissible points is within :data:`TABLE_TOLERANCE`."""
    rng = np.random.default_rng(seed)
    pts = [rng.uniform(lo, hi, 4 * _CHECK_POINTS) for lo, hi in box]
    lo_y, hi_y = _hydro.linear_mantle_core_density_range(pts[0], pts[2])
    keep = (pts[1] >= lo_y) & (pts[1] < hi_y)
    pts = [p[keep][:_CHECK_POINTS] for p in pts]
    if pts[0].size == 0:
        raise InputError(
            "priors",
            "core radius, density and polar moment",
            "priors that reach profiles in hydrostatic equilibrium (a mantle of positive density, no denser than "
            "the core)",
        )
    reference = _hydro.core_flattening_unchecked(*pts, 1e-13)
    error = math.inf
    for degrees in DEGREES:
        coefficients = _fit(box, degrees)
        if coefficients is None:
            raise InputError(
                "priors",
                _box_text(box),
                "priors for which the core's hydrostatic figure exists everywhere (in part of this range the mantle "
                "would need a negative mass: Clairaut's equation has no regular solution there)",
            )
        error = float(np.max(np.abs(_evaluate(coefficients, box, *pts) / reference - 1.0)))
        if error <= TABLE_TOLERANCE:
            coefficients.setflags(write=False)
            return coefficients, error, pts[0].size
    raise InputError(
        "priors",
        _box_text(box),
        f"priors over which the hydrostatic core can be tabulated to {TABLE_TOLERANCE:g} (narrower priors; last "
        f"error {error:.2g})",
    )


def _box_text(box) -> str:
    return (
        f"core radius/R in [{box[0][0]:.4g}, {box[0][1]:.4g}], core density/mean density in [{box[1][0]:.4g}, "
        f"{box[1][1]:.4g}], "
        f"C/(MR^2) in [{box[2][0]:.4g}, {box[2][1]:.4g}]"
    )


@dataclass(frozen=True)
class LinearMantleCoreFigure:
    """Hydrostatic e_f of a uniform core under a linear mantle, tabulated over the priors' box.

    Build with :meth:`build`. Attributes are SI or dimensionless.

    Attributes
    ----------
    profile : str
        The profile's name (``mars_layered``).
    radius : float
        R, the profile's outer radius, m.
    box : tuple of (low, high)
        The ranges of x = r_c/R, y = rho_c/rho_mean, c = C/(M R^2) covered.
    coefficients : numpy.ndarray
        Chebyshev coefficients of e_f/q over the box.
    max_error : float
        Largest relative error of the table against the direct solve at
        ``check_points`` random admissible points of the box.
    check_points : int
    """

    profile: str
    radius: float
    box: tuple
    coefficients: np.ndarray = field(repr=False)
    max_error: float = math.nan
    check_points: int = 0

    @classmethod
    def build(cls, profile: str, radius: float, box, seed: int = 20240901) -> LinearMantleCoreFigure:
        """Tabulate e_f/q over ``box`` ((x_lo, x_hi), (y_lo, y_hi), (c_lo, c_hi)), checked to
        :data:`TABLE_TOLERANCE`."""
        box = tuple((float(lo), float(hi)) for lo, hi in box)
        for (lo, hi), name in zip(box, ("core radius/R", "core density/mean density", "C/(M R^2)")):
            if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
                raise InputError(name, f"[{lo:.6g}, {hi:.6g}]", "a finite, positive range")
        if box[0][1] >= 1.0:
            raise InputError(
                "fluid_core_radius", f"up to {box[0][1]:.4g} of the radius", "a prior for a core inside the planet"
            )
        coefficients, error, points = _table(box, seed)
        return cls(profile, float(radius), box, coefficients, error, points)

    def dimensionless(self, batch):
        """(x, y, c, q) of every member: the numbers e_f depends on, from the batch's values."""
        gm = batch["gm"]
        mass = gm / batch["gravitational_constant"]
        r = self.radius
        x = batch["fluid_core_radius"] / r
        y = batch["fluid_core_density"] / (mass / (4.0 / 3.0 * math.pi * r**3))
        c = _c_factor(batch) * (batch["equatorial_radius"] / r) ** 2
        q = batch["rotation_rate"] ** 2 * r**3 / gm
        return x, y, c, q

    def hydrostatic(self, batch) -> np.ndarray:
        """e_f of every member; NaN outside the box or where the profile is not admissible."""
        x, y, c, q = (np.broadcast_to(v, batch.shape).ravel() for v in self.dimensionless(batch))
        inside = np.ones(x.shape, dtype=bool)
        for v, (lo, hi) in zip((x, y, c), self.box):
            inside &= (v >= lo) & (v <= hi)
        # Admissible (check_profile): the mantle positive at both ends and no denser than the core below it.
        a0, a1 = _hydro.linear_mantle_coefficients(x, y, c)
        bottom = a0 + a1 * x
        ok = inside & (bottom > 0) & (a0 + a1 > 0) & (bottom <= y * (1.0 + 1e-9))
        out = np.full(x.shape, np.nan)
        if np.any(ok):
            out[ok] = q[ok] * _evaluate(self.coefficients, self.box, x[ok], y[ok], c[ok])
        return out.reshape(batch.shape)

    def describe(self) -> str:
        return (
            f"hydrostatic e_f of a uniform core under a linear mantle ({self.profile}), rebuilt for every draw: "
            f"Clairaut's equation tabulated on a Chebyshev grid of degrees "
            f"{'x'.join(str(n - 1) for n in self.coefficients.shape)} (largest relative error {self.max_error:.1g} "
            f"at {self.check_points} random points)"
        )


def _c_factor(batch):
    planet = batch.planet
    if planet.polar_moment_factor is not None or "polar_moment_factor" in batch.values:
        return batch["polar_moment_factor"]
    return batch["j2"] / batch["dynamical_flattening"]


def box_corners(ranges: Mapping[str, tuple[float, float]], function) -> tuple[float, float]:
    """(min, max) of ``function(**values)`` over the corners of ``ranges`` (a function
    monotone in each argument takes its extremes there)."""
    names = list(ranges)
    outs = [function(**dict(zip(names, corner))) for corner in itertools.product(*(ranges[n] for n in names))]
    return min(outs), max(outs)


@dataclass(frozen=True)
class ForwardContext:
    """Fixed inputs of forward models that are not planet parameters (SI).

    Attributes
    ----------
    core_figure : FixedCoreFigure or LinearMantleCoreFigure or None
        The hydrostatic core (the FCN needs it).
    perturbers : tuple of PerturberOrbit
        The bodies whose tidal torque precesses the planet (the Sun first).
    geodesic_rate : float
        Geodesic precession added to the tidal rate, rad/s: the Sun's, when the
        observed rate includes it (Earth's IAU psi_A), else 0 (Mars' tracking fits).
    """

    core_figure: FixedCoreFigure | LinearMantleCoreFigure | None = None
    perturbers: tuple[PerturberOrbit, ...] = ()
    geodesic_rate: float = 0.0

    @property
    def torque_strength(self) -> float:
        """Sum over the tidal perturbers of G M <(a/r)^3> P2(cos i) f / a^3, s^-2
        (:func:`wobble.models.precession.torque_strength`)."""
        return float(sum(torque_strength(o) for o in self.perturbers if not o.ring))

    @property
    def rings(self) -> tuple[PerturberOrbit, ...]:
        """The ring satellites among the perturbers (:func:`wobble.models.precession.ring_factor`)."""
        return tuple(o for o in self.perturbers if o.ring)
