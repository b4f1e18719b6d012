"""The perturber catalogue re-derived from its sources.

The Moon's mean reciprocal distance and the factor by which the Sun's
perturbations of the lunar orbit change the mean tidal torque are derived
(data/precession/moon.toml) from the ELP-2000/82 series as abridged by Meeus
(1998, ch. 47), which ERFA implements as ``moon98``: a smoothly windowed time
average over fifty years (a weighted Birkhoff average, which converges faster
than any power of the span for quasi-periodic motion) must give them back.
"""

from __future__ import annotations

import math

import erfa
import numpy as np
import pytest

from wobble.io.perturbers import PERTURBER_UNITS, load_perturber, measured

KM = 1e3


@pytest.fixture(scope="module")
def lunar_averages():
    n = 60_000
    x = (np.arange(n) + 0.5) / n
    jd = 2451545.0 - 25 * 365.25 + 50 * 365.25 * x
    window = np.exp(-1.0 / (x * (1.0 - x)))
    window /= window.sum()
    p = erfa.moon98(jd, 0.0)["p"]
    # To the ecliptic of date; the ecliptic moves 47"/cy, so one matrix per 1000 samples is enough.
    rot = np.array([erfa.ecm06(j, 0.0) for j in jd[::1000]])
    pe = np.einsum("nij,nj->ni", rot[np.arange(n) // 1000], p)
    r = np.linalg.norm(p, axis=1) * erfa.DAU
    sin_beta = pe[:, 2] / np.linalg.norm(pe, axis=1)
    return window, r, sin_beta


def test_moon_semi_major_axis_is_the_mean_reciprocal_distance(lunar_averages):
    window, r, _ = lunar_averages
    moon = load_perturber("moon")
    a = measured(moon, "semi_major_axis", PERTURBER_UNITS["semi_major_axis"])
    assert 1.0 / np.sum(window / r) == pytest.approx(a.value, abs=0.1 * KM)


def test_moon_solar_perturbation_factor(lunar_averages):
    window, r, sin_beta = lunar_averages
    moon = load_perturber("moon")
    a = measured(moon, "semi_major_axis", PERTURBER_UNITS["semi_major_axis"]).value
    e = measured(moon, "eccentricity", PERTURBER_UNITS["eccentricity"]).value
    i = measured(moon, "inclination", PERTURBER_UNITS["inclination"]).value
    real = np.sum(window * (a / r) ** 3 * (1.0 - 3.0 * sin_beta**2))
    kepler = (1.0 - e**2) ** -1.5 * (1.0 - 1.5 * math.sin(i) ** 2)
    factor = measured(moon, "solar_perturbation_factor", PERTURBER_UNITS["solar_perturbation_factor"])
    assert real / kepler == pytest.approx(factor.value, abs=factor.sigma)


def test_moon_node_rate_is_18_6_years():
    node = measured(load_perturber("moon"), "node_rate", PERTURBER_UNITS["node_rate"]).value
    assert 2 * math.pi / abs(node) / (365.25 * 86400) == pytest.approx(18.61, abs=0.01)


# -- the rigid-Earth series (data/precession/rigid_earth_nutation.toml) -----------------

ARCSEC = math.pi / 180 / 3600


def test_rigid_earth_series_is_read_with_its_units():
    from wobble.io.perturbers import NUTATION_REFERENCE_UNITS, load_nutation_reference

    ref = load_nutation_reference()
    assert ref.kind == "nutation_reference"

    def si(key):
        return measured(ref, key, NUTATION_REFERENCE_UNITS[key]).value

    # The file's own units: picoradians, arcseconds, radians, arcsec per century.
    assert si("retrograde_amplitude") == pytest.approx(39031706.5e-12, rel=1e-12)
    assert si("prograde_amplitude") == pytest.approx(5706463.6e-12, rel=1e-12)
    assert si("nutation_longitude") == pytest.approx(-17.2805921 * ARCSEC, rel=1e-12)
    assert si("nutation_obliquity") == pytest.approx(9.2279100 * ARCSEC, rel=1e-12)
    assert si("dynamical_flattening") == 3.2737548e-3
    assert si("general_precession") == pytest.approx(5028.77 * ARCSEC / (36525 * 86400), rel=1e-12)
    assert {ref.get(k).status for k in ("nutation_longitude", "nutation_obliquity")} == {"derived"}
    assert all("REN-2000" in ref.get(k).source for k in ("retrograde_amplitude", "nutation_longitude"))


def test_rigid_earth_coefficients_follow_from_the_circular_components():
    """Delta eps = P_retro + P_pro, Delta psi sin(eps_0) = P_pro - P_retro: the sum the carrying code performs."""
    from wobble.io.perturbers import NUTATION_REFERENCE_UNITS, load_nutation_reference

    ref = load_nutation_reference()

    def si(key):
        return measured(ref, key, NUTATION_REFERENCE_UNITS[key]).value

    retro, pro, eps0 = si("retrograde_amplitude"), si("prograde_amplitude"), si("conversion_obliquity")
    assert (pro - retro) / math.sin(eps0) / ARCSEC == pytest.approx(si("nutation_longitude") / ARCSEC, abs=1e-7)
    assert (pro + retro) / ARCSEC == pytest.approx(si("nutation_obliquity") / ARCSEC, abs=1e-7)


def test_a_nutation_reference_without_its_coefficient_is_refused(tmp_path):
    from wobble.errors import FileFormatError, InputError
    from wobble.io.perturbers import load_nutation_reference

    path = tmp_path / "series.toml"
    path.write_text(
        'schema = "wobble/1"\nkind = "nutation_reference"\nname = "x"\n'
        "[parameters.dynamical_flattening]\nvalue = 3.27e-3\nuncertainty = 0\n"
        'unit = ""\nsource = "test"\nstatus = "assumed"\n'
    )
    with pytest.raises(FileFormatError, match="nutation_longitude"):
        load_nutation_reference(path)
    with pytest.raises(InputError, match="rigid_earth_nutation"):
        load_nutation_reference("no_such_series")
