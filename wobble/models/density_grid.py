"""Bodies from a density sampled on a regular grid, streamed slab by slab (SI float64).

I_jk = integral rho(r) (r^2 delta_jk - x_j x_k) dV (course notes section 5.1, p. 67)
by a tensor-product quadrature rule (:mod:`wobble.numerics.grid_quadrature`); the
moments are accumulated about the grid centre and moved to the centre of mass
without cancellation.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from wobble.errors import InputError
from wobble.models.bodies import Body, tensor_from_second_moments
from wobble.numerics.grid_quadrature import RULES, accumulate_moments, moment_rows

__all__ = ["GridAxis", "from_grid"]


@dataclass(frozen=True)
class GridAxis:
    """One axis of a regular grid in SI: ``n`` nodes from ``start`` to ``stop`` (m)."""

    name: str
    n: int
    start: float
    stop: float

    @property
    def step(self) -> float:
        """(stop - start) / (n - 1) in m: signed, negative for a decreasing coordinate."""
        return (self.stop - self.start) / (self.n - 1)

    @property
    def spacing(self) -> float:
        """|step| in m."""
        return abs(self.step)

    @property
    def center(self) -> float:
        """Mid-point of the axis in m."""
        return 0.5 * (self.start + self.stop)


def _checked_slabs(slabs, dims: tuple[str, ...], scale: float, name: str) -> Iterator[tuple[int, np.ndarray]]:
    for start, block in slabs:
        block = np.asarray(block, dtype=float)
        ok = np.isfinite(block) & (block >= 0)
        if not np.all(ok):
            local = np.unravel_index(int(np.argmin(ok)), block.shape)
            index = (int(local[0]) + start, int(local[1]), int(local[2]))
            where = ", ".join(f"{d}={i}" for d, i in zip(dims, index))
            raise InputError(name, f"{float(block[local])!r} at index [{where}]", "finite, non-negative densities")
        yield start, block * scale if scale != 1.0 else block


def from_grid(
    slabs: Iterable[tuple[int, np.ndarray]],
    axes: tuple[GridAxis, GridAxis, GridAxis],
    *,
    rule: str = "trapezoid",
    density_scale: float = 1.0,
    about=None,
    name: str = "density",
) -> Body:
    """A body from a density sampled on a regular grid, streamed slab by slab.

    I_jk = integral rho (r^2 delta_jk - x_j x_k) dV (notes 5.1, p. 67) by the
    tensor-product rule ``rule`` (see :mod:`wobble.numerics.grid_quadrature` for
    the rules and their orders).

    Parameters
    ----------
    slabs : iterable of (int, ndarray)
        ``(start, block)``: the densities ``rho[start:start + k, :, :]`` in the
        array's own axis order (see ``axes``), in units that ``density_scale``
        turns into kg/m^3. Every slab is checked (finite, >= 0).
    axes : tuple of three GridAxis
        The array axes in array order; their names must be x, y and z in some order.
    rule : {"trapezoid", "simpson", "voxel"}
    density_scale : float
        Factor from the slabs' unit to kg/m^3.
    about : array_like, shape (3,), optional
        Reference point (m); default: the centre of mass.
    """
    if rule not in RULES:
        raise InputError("rule", rule, ", ".join(RULES))
    names = tuple(a.name for a in axes)
    if sorted(names) != ["x", "y", "z"]:
        raise InputError(name, f"dimensions {names}", "exactly the dimensions x, y and z")
    for a in axes:
        need = 3 if rule == "simpson" else 2
        if a.n < need or (rule == "simpson" and a.n % 2 == 0):
            allowed = "an odd number (>= 3) of points for Simpson's rule" if rule == "simpson" else "at least 2 points"
            raise InputError(f"{name}.{a.name}", f"{a.n} points", allowed)
        if not a.spacing > 0:
            raise InputError(f"{name}.{a.name}", f"spacing {a.spacing}", "a positive grid spacing")
    rows = tuple(moment_rows(a.n, a.step, rule) for a in axes)
    # Moments past double precision (1e300 kg/m3 over a kilometre, 5515 kg/m3 over 1e150 m) are
    # refused below by name, without NumPy's overflow warnings first; the moments of order three
    # and more, which the sums carry along but the tensor does not need, may overflow harmlessly.
    with np.errstate(over="ignore", invalid="ignore"):
        raw = accumulate_moments(_checked_slabs(slabs, names, float(density_scale), name), rows)
    xyz = [names.index(c) for c in "xyz"]  # array axis holding x, y, z

    def moment(*powers_xyz: int) -> float:
        idx = [0, 0, 0]
        for c, p in enumerate(powers_xyz):
            idx[xyz[c]] = p
        return float(raw[tuple(idx)])

    mass = moment(0, 0, 0)
    first = np.array([moment(*np.eye(3, dtype=int)[c]) for c in range(3)])
    second = np.empty((3, 3))
    for j in range(3):
        for k in range(3):
            second[j, k] = moment(*(np.eye(3, dtype=int)[j] + np.eye(3, dtype=int)[k]))
    if not (np.isfinite(mass) and np.all(np.isfinite(first)) and np.all(np.isfinite(second))):
        raise InputError(
            name,
            f"total mass {mass:g} kg",
            "a density whose mass and second moments fit double precision (below 1.8e308 in SI): "
            "the values or the grid's extent are too large",
        )
    if not mass > 0:
        raise InputError(name, f"total mass {mass:g} kg", "a density with positive total mass")
    center = np.array([axes[xyz[c]].center for c in range(3)])
    offset = first / mass  # centre of mass from the grid centre
    central = tensor_from_second_moments(second - mass * np.outer(offset, offset))
    com = center + offset
    body = Body(central, com, com, mass)
    return body if about is None else body.shifted_to(about)
