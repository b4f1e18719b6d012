"""What equation (7)'s circular, coplanar orbits leave out of the planets' torque on a bulge.

``wobble.models.precession`` takes each planet's pull on a body's bulge as G M <1/d^3> over two circular orbits in
one plane (equation (7)). This script takes the same double average over the real J2000 orbits, eccentric and
inclined (Standish & Williams, JPL 'Approximate Positions of the Planets', Table 1), by the midpoint rule in both
mean anomalies (uniform in time), and compares the strength that turns the axis about the body's orbit normal,

    k = (3/2) (<d d^T/d^5> across the plane - <d d^T/d^5> along the normal),

with equation (7)'s 0.75 <1/d^3> x G M. The orbits' orientations are held at J2000 (the rate at epoch). Printed:
each planet's ratio for Earth and Mars, the switch-offs that say why the largest ones move (Venus' inclination,
Mars' eccentricity), and each body's total against (7)'s and, for Earth, against Williams (1994). Quoted in
docs/precession.md, section 2.

Run from anywhere (a few seconds):

    python scripts/planets_real_orbits.py
"""

from __future__ import annotations

import math

import numpy as np
from astropy import units as u

import wobble
from wobble.io.perturbers import load_perturber, measured
from wobble.models.precession import mean_inverse_cube_distance

AU = 149_597_870_700.0  # m (IAU 2012)
WILLIAMS = 0.031367  # "/cy: the planets' first-order torque on Earth's bulge that IAU 2006 adopts
# Standish & Williams, Table 1 (J2000 mean elements, 1800-2050): a (au), e, I (deg), varpi (deg), Omega (deg).
ELEMENTS = {
    "mercury": (0.38709927, 0.20563593, 7.00497902, 77.45779628, 48.33076593),
    "venus": (0.72333566, 0.00677672, 3.39467605, 131.60246718, 76.67984255),
    "earth": (1.00000261, 0.01671123, -0.00001531, 102.93768193, 0.0),
    "mars": (1.52371034, 0.09339410, 1.84969142, -23.94362959, 49.55953891),
    "jupiter": (5.20288700, 0.04838624, 1.30439695, 14.72847983, 100.47390909),
    "saturn": (9.53667594, 0.05386179, 2.48599187, 92.59887831, 113.66242448),
    "uranus": (19.18916464, 0.04725744, 0.77263783, 170.95427630, 74.01692503),
    "neptune": (30.06992276, 0.00859048, 1.77004347, 44.96476227, 131.78422574),
}
SAMPLES = 600


def positions(elements, samples=SAMPLES):
    """Heliocentric positions at ``samples`` mean anomalies, ecliptic of J2000 (m), and the orbit's unit normal."""
    a, e, inc, varpi, node = elements
    inc, varpi, node = map(math.radians, (inc, varpi, node))
    mean = 2 * math.pi * (np.arange(samples) + 0.5) / samples
    ecc = mean.copy()
    for _ in range(30):  # Kepler's equation by Newton's method
        ecc -= (ecc - e * np.sin(ecc) - mean) / (1 - e * np.cos(ecc))
    x, y = a * AU * (np.cos(ecc) - e), a * AU * math.sqrt(1 - e * e) * np.sin(ecc)

    def about_z(angle):
        return np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])

    tilt = np.array([[1, 0, 0], [0, math.cos(inc), -math.sin(inc)], [0, math.sin(inc), math.cos(inc)]])
    rot = about_z(node) @ tilt @ about_z(varpi - node)
    return np.stack([x, y, 0 * x], axis=1) @ rot.T, rot[:, 2]


def ratio(body, planet, elements=ELEMENTS):
    """The real orbits' strength over equation (7)'s (1 for circular orbits in one plane)."""
    rb, n = positions(elements[body])
    rk, _ = positions(elements[planet])
    d = (rk[None] - rb[:, None]).reshape(-1, 3)
    w = d / np.linalg.norm(d, axis=1)[:, None] ** 2.5
    tensor = w.T @ w / len(d)  # <d d^T / d^5>
    along = n @ tensor @ n
    across = 0.5 * (np.trace(tensor) - along)
    return (
        1.5 * (across - along) / (0.75 * mean_inverse_cube_distance(elements[body][0] * AU, elements[planet][0] * AU))
    )


def _gm(name):
    return measured(load_perturber(name), "gm", u.m**3 / u.s**2).value


def main() -> None:
    for body in ("earth", "mars"):
        r = ELEMENTS[body][0] * AU
        circular = real = 0.0
        print(f"{body}: planet, real orbits over equation (7)")
        for planet in ELEMENTS:
            if planet == body:
                continue
            k = _gm(planet) * mean_inverse_cube_distance(r, ELEMENTS[planet][0] * AU)
            f = ratio(body, planet)
            circular += k
            real += k * f
            print(f"  {planet:<8} {f:.4f}")
        print(f"  all planets: {real / circular - 1:+.2%}")
        if body == "earth":
            model = -wobble.precession_rate("earth").planetary.to_value(u.arcsec / (100 * u.yr))  # IAU's sign
            print(f'  "/cy: equation (7) {model:.4f}, real orbits {model * real / circular:.4f}, Williams {WILLIAMS}')
    flat_venus = {**ELEMENTS, "venus": (*ELEMENTS["venus"][:2], 0.0, *ELEMENTS["venus"][3:])}
    round_mars = {**ELEMENTS, "mars": (ELEMENTS["mars"][0], 0.0, *ELEMENTS["mars"][2:])}
    print(f"Venus on Earth with Venus' inclination set to 0: {ratio('earth', 'venus', flat_venus):.4f}")
    print(f"Earth-Moon on Mars with Mars' eccentricity set to 0: {ratio('mars', 'earth', round_mars):.4f}")


if __name__ == "__main__":
    main()
