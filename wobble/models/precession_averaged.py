"""The averaged (analytic) precession of a scene: what the engine's third bodies do on average (SI).

A spinning, nearly axisymmetric body under the tidal torques of perturbers on Keplerian
orbits (:class:`wobble.models.torques.ThirdBody`) precesses, on average over the
perturbers' orbits, about the inertial z axis at the first-order rate of
:mod:`wobble.models.precession` (Goldstein, Poole & Safko 2002, sec. 5.8; Woolard 1953;
Kinoshita 1977),

    dpsi/dt = -(3/2) sum_k G M_k / (a_k^3 (1 - e_k^2)^(3/2)) P2(cos i_k) (H / omega) cos eps,

with H = (C - (A + B)/2)/C about the figure axis, omega the spin and eps the angle of the
figure axis from the inertial z axis (the obliquity); and an inclined perturber whose node
regresses at nu (relative to the moving equinox: nu_inertial - dpsi/dt) adds the nodal
nutation of :mod:`wobble.models.nutation`. This is the model the scene chooser takes when a
scene asks only for ``mean_precession_rate`` (:mod:`wobble.models.scene`), and the
analytic side of :func:`wobble.api.precession_measure.measure_precession`.

When it applies (:func:`averaging_applies`): every torque is a third body on a Keplerian
orbit; the body spins about its largest-moment axis, fast against the orbits; each
perturber's orbit lies in the x-y plane or its node regresses fast against the
precession. Its error is that of first-order averaging (:func:`averaging_error`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wobble.models.nutation import NodalNutation, nodal_nutation
from wobble.models.orbit import KeplerOrbit
from wobble.models.precession import PerturberOrbit, precession_rate
from wobble.models.rigid_frame import BodyModel, InternalFrame
from wobble.models.torques import ThirdBody
from wobble.numerics import quaternion as quat

__all__ = ["AveragedPrecession", "averaging_applies", "averaged_precession", "perturber_orbit", "averaging_error"]

#: Largest ratio of an orbit's mean motion to the spin, and of the precession rate to an
#: orbit's mean motion or node rate, for which first-order averaging is taken to apply.
SLOW = 0.1


@dataclass(frozen=True)
class AveragedPrecession:
    """First-order averaged precession and nutation of each member (SI: rad, rad/s).

    Attributes
    ----------
    rate : numpy.ndarray (N,)
        dpsi/dt, the node longitude of the equator on the x-y plane (negative: retrograde).
    obliquity : numpy.ndarray (N,)
        Angle of the figure axis from the inertial z axis at t0.
    node_longitude : numpy.ndarray (N,)
        psi at t0: the longitude of the ascending node of the equator on the x-y plane.
    dynamical_flattening, spin_rate : numpy.ndarray (N,)
        H about the figure axis and the spin omega.
    perturbers : tuple of PerturberOrbit
        The third bodies as the averaged model sees them (node rates relative to the moving
        equinox of the first member).
    nutation : tuple of (str, NodalNutation)
        The nodal nutation of each inclined perturber with a regressing node (first member).
    error : float
        Relative size of what first-order averaging leaves out (:func:`averaging_error`).
    """

    rate: np.ndarray
    obliquity: np.ndarray
    node_longitude: np.ndarray
    dynamical_flattening: np.ndarray
    spin_rate: np.ndarray
    perturbers: tuple
    nutation: tuple
    error: float


def _orbits(torques):
    return [t for t in torques if isinstance(t, ThirdBody) and t.orbit is not None]


def perturber_orbit(spec: ThirdBody, node_rate: float | None = None) -> PerturberOrbit:
    """A third body's Keplerian orbit as :class:`wobble.models.precession.PerturberOrbit`."""
    o: KeplerOrbit = spec.orbit
    return PerturberOrbit(
        spec.name,
        spec.gm,
        o.semi_major_axis,
        o.eccentricity,
        o.inclination,
        1.0,
        o.node_rate if node_rate is None else node_rate,
    )


def _figure(body: BodyModel, omega0, attitude0):
    """Per member: (H, omega, wobble angle, inertial figure axis (N, 3) along the spin)."""
    n = int(np.shape(omega0)[0])
    frame = InternalFrame.of(body, n)
    m = np.broadcast_to(frame.moments, (n, 3))
    axis_body = np.broadcast_to(frame.P, (n, 3, 3))[:, 2, :]  # internal axis 3 in body components
    w = np.asarray(omega0, dtype=float).reshape(n, 3)
    along = np.sum(w * axis_body, axis=-1)
    spin = np.abs(along)
    wobble = np.arctan2(np.linalg.norm(w - along[:, None] * axis_body, axis=-1), spin)
    axis = quat.rotate(np.asarray(attitude0, dtype=float).reshape(n, 4), axis_body * np.sign(along)[:, None])
    h = (m[:, 2] - 0.5 * (m[:, 0] + m[:, 1])) / m[:, 2]
    return h, spin, wobble, axis, m


def averaging_applies(body: BodyModel, omega0, attitude0, torques) -> str | None:
    """None when the averaged model applies to the scene, else why not (one phrase)."""
    orbits = _orbits(torques)
    if not torques:
        return "no torque acts"
    if len(orbits) != len(torques):
        others = sorted(
            {
                t.kind if not isinstance(t, ThirdBody) else "a third body given by a table or a callable"
                for t in torques
                if not any(t is o for o in orbits)
            }
        )
        return "the averaged model takes third bodies on Keplerian orbits only (not " + ", ".join(others) + ")"
    h, spin, wobble, axis, m = _figure(body, omega0, attitude0)
    if np.any(m[:, 2] <= m[:, 1]):
        return "the body has no unique largest moment (no figure axis to precess)"
    if np.any(spin == 0):
        return "the body does not spin about its figure axis"
    if np.any(wobble > SLOW):
        return "the spin is far from the figure axis (the averaged model needs spin about it)"
    n_max = max(t.orbit.mean_motion for t in orbits)
    if n_max > SLOW * float(np.min(spin)):
        return "an orbit is not slow against the spin"
    rate = _rates(h, spin, axis, orbits)
    for t in orbits:
        o = t.orbit
        if o.inclination != 0 and o.node_rate == 0:
            return (
                f"the orbit of {t.name} is inclined and its node does not regress: the axis precesses about its "
                "orbit normal, not about the inertial z axis"
            )
        slowest = min(o.mean_motion, abs(o.node_rate) if o.node_rate else math.inf)
        if float(np.max(np.abs(rate))) > SLOW * slowest:
            return f"the precession is not slow against the orbit of {t.name}"
    return None


def _rates(h, spin, axis, orbits):
    eps = np.arccos(np.clip(axis[:, 2], -1.0, 1.0))
    pert = [perturber_orbit(t) for t in orbits]
    return np.array([precession_rate(float(hk), float(wk), float(ek), pert) for hk, wk, ek in zip(h, spin, eps)])


def averaging_error(rate: float, spin: float, wobble: float, torques) -> float:
    """A priori relative error of the averaged rate: the first order it leaves out.

    The sum over perturbers of each one's share of the rate times the ratio of the
    precession rate to the fastest motion averaged over (the orbit's mean motion, or its
    node rate when the orbit is inclined: the coupling of nutation and precession), plus
    the square of the wobble angle (a free wobble changes the mean torque at second order).
    For Earth it is 5e-4; the engine's 20-year simulation differs by 2e-5
    (docs/precession.md).
    """
    orbits = _orbits(torques)
    strengths = [t.gm / t.orbit.semi_major_axis**3 for t in orbits]
    total = sum(strengths) or 1.0
    err = 0.0
    for t, s in zip(orbits, strengths):
        o = t.orbit
        fast = o.mean_motion if o.inclination == 0 or o.node_rate == 0 else min(o.mean_motion, abs(o.node_rate))
        err += s / total * (abs(rate) / fast if fast > 0 else 0.0)
    return float(err + wobble**2)


def averaged_precession(body: BodyModel, omega0, attitude0, torques) -> AveragedPrecession:
    """The first-order averaged precession (and nodal nutation) of every member.

    Call :func:`averaging_applies` first: this function assumes the model applies.
    """
    orbits = _orbits(torques)
    h, spin, wobble, axis, _ = _figure(body, omega0, attitude0)
    rate = _rates(h, spin, axis, orbits)
    eps = np.arccos(np.clip(axis[:, 2], -1.0, 1.0))
    psi = np.arctan2(axis[:, 0], -axis[:, 1])
    nutation = []
    relative = []
    for t in orbits:
        o = t.orbit
        nu = o.node_rate - float(rate[0]) if o.node_rate else None  # from the moving equinox
        orbit = perturber_orbit(t, nu)
        relative.append(orbit)
        if nu and o.inclination:
            nut: NodalNutation = nodal_nutation(float(h[0]), float(spin[0]), float(eps[0]), orbit)
            nutation.append((t.name, nut))
    err = max(averaging_error(float(r), float(w), float(wb), torques) for r, w, wb in zip(rate, spin, wobble))
    return AveragedPrecession(rate, eps, psi, h, spin, tuple(relative), tuple(nutation), err)
