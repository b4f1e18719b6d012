"""The principal (18.6-year) nutation of a rigid body from the regression of a perturber's node.

A perturber on an orbit inclined by i to the reference plane, whose node
longitude Omega (counted from the equinox) turns at the rate nu, adds to the
averaged tidal potential of the spin axis a term periodic in Omega. With the
axis' node longitude psi and obliquity eps as canonical angle and momentum
(C omega cos eps), the averaged potential of one perturber is

    U = -(K/2) (s . m)^2,  K = C omega P,
    s . m = cos eps cos i - sin eps sin i cos Omega,                         (1)

with P = (3/2)(G M / a^3)(1 - e^2)^(-3/2) (H/omega) (times the orbit's
perturbation factor) the perturber's precession constant. To first order in
sin i, Hamilton's equations give the forced motion (Woolard 1953, Astron.
Pap. Amer. Ephem. XV, part I; Kinoshita 1977, Celest. Mech. 15, 277):

    Delta eps = +(P/|nu|) sin i cos i cos eps          cos Omega              (2)
    Delta psi = -(P/|nu|) sin i cos i cos 2eps / sin eps  sin Omega          (3)

in the IAU convention (Delta psi positive westward along the ecliptic, as
IAU 2000A: -17.2064" sin Omega, +9.2052" cos Omega). The ratio of the two
amplitudes, 2 cot(2 eps), depends on the obliquity only. For Earth the formula
with the rigid-Earth series REN-2000's own H (Souchay, Loysel, Kinoshita &
Folgueira 1999; -17.2806", +9.2279") is within 0.03 % of that series, which
adds the second-order and planetary-tilt terms; the non-rigid Earth's
IAU 2000A term is 0.4 % smaller.

Everything in SI (rad, s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from wobble.errors import InputError
from wobble.models.precession import PerturberOrbit, check_obliquity

__all__ = ["NodalNutation", "nodal_nutation", "perturber_precession_constant"]


@dataclass(frozen=True)
class NodalNutation:
    """Amplitudes of the nutation driven by one perturber's node regression.

    Attributes
    ----------
    longitude : float
        Coefficient of sin(Omega) in Delta psi (IAU convention), rad.
    obliquity : float
        Coefficient of cos(Omega) in Delta eps, rad.
    period : float
        The node's period 2 pi/|nu|, s.
    precession_constant : float
        P of the perturber (equation 1), rad/s.
    """

    longitude: float
    obliquity: float
    period: float
    precession_constant: float


def perturber_precession_constant(dynamical_flattening: float, spin_rate: float, orbit: PerturberOrbit) -> float:
    """P = (3/2) G M/a^3 (1 - e^2)^(-3/2) f (H/omega), rad/s (no inclination or obliquity factor)."""
    return (
        1.5
        * orbit.gm
        / orbit.semi_major_axis**3
        * orbit.eccentricity_factor
        * orbit.perturbation_factor
        * dynamical_flattening
        / spin_rate
    )


def nodal_nutation(
    dynamical_flattening: float, spin_rate: float, obliquity: float, orbit: PerturberOrbit
) -> NodalNutation:
    """Equations (2) and (3): the principal nutation from one perturber's node regression.

    Parameters
    ----------
    dynamical_flattening : float
        H = (C - A)/C.
    spin_rate : float
        omega, rad/s.
    obliquity : float
        eps, rad.
    orbit : PerturberOrbit
        With ``node_rate`` (rad/s, negative for a regressing node).
    """
    check_obliquity(obliquity)
    if orbit.node_rate is None or orbit.node_rate == 0:
        raise InputError(f"{orbit.name}.node_rate", orbit.node_rate, "a non-zero node rate (the nutation's frequency)")
    if math.sin(obliquity) == 0:
        raise InputError(
            "obliquity",
            obliquity,
            "an obliquity strictly between 0 and 180 deg (the node of the equator is undefined otherwise)",
        )
    p = perturber_precession_constant(dynamical_flattening, spin_rate, orbit)
    nu = abs(orbit.node_rate)
    tilt = math.sin(orbit.inclination) * math.cos(orbit.inclination)
    d_eps = p / nu * tilt * math.cos(obliquity)
    d_psi = -p / nu * tilt * math.cos(2.0 * obliquity) / math.sin(obliquity)
    return NodalNutation(d_psi, d_eps, 2.0 * math.pi / nu, p)
