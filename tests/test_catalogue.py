"""The catalogue's derived numbers, re-derived from their published inputs."""

from __future__ import annotations

import math

import mpmath as mp
import pytest
from astropy import units as u

from wobble.io.catalog import catalogue_names, load_planet
from wobble.io.parameter_file import STATUSES

mp.mp.dps = 30


def test_catalogue_lists_earth_and_mars():
    assert {"earth", "mars"} <= set(catalogue_names())


@pytest.mark.parametrize("name", ["earth", "mars"])
def test_every_entry_has_value_uncertainty_unit_source_status(name):
    _, pf = load_planet(name)
    for key, p in pf.parameters.items():
        assert p.source, key
        assert p.status in STATUSES, key
        assert p.uncertainty.unit == p.value.unit, key
        if p.status in ("derived", "assumed"):
            assert p.note or "Derived" in p.source or "assumed" in p.source.lower(), f"{key}: say how"


def test_earth_fluid_core_moment_is_prems_outer_core():
    # PREM (Dziewonski & Anderson 1981) outer core, 1221.5-3480 km, x = r/6371 km.
    a = mp.mpf(6371e3)

    def rho(r):
        x = r / a
        return 1000 * (mp.mpf("12.5815") - mp.mpf("1.2638") * x - mp.mpf("3.6426") * x**2 - mp.mpf("5.5281") * x**3)

    moment = 8 * mp.pi / 3 * mp.quad(lambda r: rho(r) * r**4, [mp.mpf(1221.5e3), mp.mpf(3480e3)])
    _, pf = load_planet("earth")
    catalogued = pf.parameters["fluid_core_equatorial_moment"].value.to_value(u.kg * u.m**2)
    assert catalogued == pytest.approx(float(moment), rel=1e-4)  # catalogued to 5 digits


def test_earth_ocean_pole_tide_love_number_from_iers_coefficients():
    # TN36 eq. 6.24 (ocean) against the dC21 of a unit Love number (eq. 6.22's form).
    _, pf = load_planet("earth")
    gm = pf.parameters["gm"].value.to_value(u.m**3 / u.s**2)
    a = pf.parameters["equatorial_radius"].value.to_value(u.m)
    om = pf.parameters["rotation_rate"].value.to_value(u.rad / u.s)
    per_arcsec = om**2 * a**3 / gm / (3 * math.sqrt(5 / 3)) * math.pi / 648000
    # Check the unit-Love-number coefficient against TN36's solid pole tide: k2 = 0.3077 <-> 1.333e-9.
    assert 0.3077 * per_arcsec == pytest.approx(1.333e-9, rel=5e-4)
    prograde = (2.1778e-10 + 1.7232e-10) / 2
    catalogued = pf.parameters["ocean_pole_tide_love_number"].value.value
    assert catalogued == pytest.approx(prograde / per_arcsec, rel=1e-4)


def test_mars_phobos_tidal_period():
    p_orb, p_rot = 27554.0, 2 * math.pi / (350.891985307 * math.pi / 180 / 86400)
    _, pf = load_planet("mars")
    catalogued = pf.parameters["love_number_k2_imaginary_period"].value.to_value(u.s)
    assert catalogued == pytest.approx(1 / (2 * (1 / p_orb - 1 / p_rot)), rel=1e-4)


def test_mars_j2_from_c20_and_j22():
    p, _ = load_planet("mars")
    assert p.j2.value == pytest.approx(1.956609e-3, rel=1e-6)  # reference values: J2 derived
    j22 = math.sqrt(5 / 12) * math.hypot(p.c22.value, p.s22.value)
    assert j22 == pytest.approx(6.31e-5, rel=1e-3)  # reference values: J22 derived
