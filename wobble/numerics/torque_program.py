"""The torque program: the engine's built-in torques as arrays, for the compiled DOP853.

One :class:`TorqueProgram` (a ``NamedTuple`` of float64 arrays, which Numba passes as one
argument) describes every torque of a run in the engine's internal frame (principal axes
sorted by increasing moment). Each field is one torque *kind*; its rows are either one
shared row or one row per ensemble member, and the kinds that can appear several times
(gravity, gravity gradient, magnetic) stack them along a leading axis:

========================  ===============  ==========================================================
field                     shape            torque (body frame components)
========================  ===============  ==========================================================
``moments``               (M, 3)           the principal moments (not a torque: Euler's equations)
``body``                  (M, 3)           constant in the body frame, summed over terms
``inertial``              (M, 3)           constant in the inertial frame: ``R(q)^T tau``, summed
``grav_r``, ``grav_mg``   (G, M, 3) each   uniform gravity about a pivot: ``r x R(q)^T (m g)``
``gradient``              (J, 9)           gravity gradient ``k rho_b x (I rho_b)``, row
                                           ``(k, e1, e2, rate, phase)``, ``rho = cos(rate t + phase) e1
                                           + sin(rate t + phase) e2`` (``e2 = 0``: fixed ``e1``)
``magnetic_dipole``,      (B, M, 3) each   a body-fixed magnetic dipole in a uniform inertial field:
``magnetic_field``                         ``mu x R(q)^T B``
``third_body``            (P, 10)          a third body on a Keplerian orbit: ``(3 GM / r^3) u_b x (I u_b)``,
                                           row ``(GM, a, e, i, node, periapsis, M0, n, node rate,
                                           periapsis rate)`` (:mod:`wobble.numerics.kepler`)
``damping``               (D, 3), D <= M   linear damping ``-D omega`` (no rows: none)
========================  ===============  ==========================================================

Adding a torque kind touches this table (a field), the compiled right-hand side
(:func:`wobble.numerics.rigid_dop853._rhs`: one branch), the torque class
(:mod:`wobble.models.torques`), its scene-file entry (:mod:`wobble.io.scene_file`) and a
test: the recipe in DEVELOPERS.md.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["TorqueProgram", "FIELDS", "pack"]


class TorqueProgram(NamedTuple):
    """The arrays the compiled kernel reads (see the module docstring)."""

    moments: np.ndarray
    body: np.ndarray
    inertial: np.ndarray
    grav_r: np.ndarray
    grav_mg: np.ndarray
    gradient: np.ndarray
    magnetic_dipole: np.ndarray
    magnetic_field: np.ndarray
    third_body: np.ndarray
    damping: np.ndarray


FIELDS = TorqueProgram._fields


def _summed(rows) -> np.ndarray:
    return sum(rows[1:], rows[0]) if rows else np.zeros((1, 3))


def _stacked(pairs) -> tuple[np.ndarray, np.ndarray]:
    m = max([1] + [max(a.shape[0], b.shape[0]) for a, b in pairs])
    first = np.array([np.broadcast_to(a, (m, 3)) for a, _ in pairs]).reshape(-1, m, 3)
    second = np.array([np.broadcast_to(b, (m, 3)) for _, b in pairs]).reshape(-1, m, 3)
    return first, second


def pack(moments, terms) -> TorqueProgram:
    """A program from the moments (M, 3) and the torques' terms ``[(kind, arrays), ...]``.

    ``kind`` is ``body``, ``inertial`` (one (M, 3) array each, summed), ``gravity`` or
    ``magnetic`` (a pair of (M, 3) arrays), ``gradient`` (one row of 9), ``third_body`` (one
    row of 10) or ``damping`` (one (M, 3) array, summed).
    """
    by_kind: dict[str, list] = {}
    for kind, arrays in terms:
        by_kind.setdefault(kind, []).append(arrays)
    unknown = set(by_kind) - {"body", "inertial", "gravity", "magnetic", "gradient", "third_body", "damping"}
    if unknown:
        raise ValueError(f"unknown torque program kinds {sorted(unknown)}")
    grav_r, grav_mg = _stacked(by_kind.get("gravity", []))
    dipole, field = _stacked(by_kind.get("magnetic", []))
    damping = by_kind.get("damping", [])
    fields = dict(
        moments=moments,
        body=_summed(by_kind.get("body", [])),
        inertial=_summed(by_kind.get("inertial", [])),
        grav_r=grav_r,
        grav_mg=grav_mg,
        gradient=np.array(by_kind.get("gradient", []), dtype=float).reshape(-1, 9),
        magnetic_dipole=dipole,
        magnetic_field=field,
        third_body=np.array(by_kind.get("third_body", []), dtype=float).reshape(-1, 10),
        damping=_summed(damping) if damping else np.zeros((0, 3)),
    )
    return TorqueProgram(**{k: np.ascontiguousarray(v, dtype=float) for k, v in fields.items()})
