"""Clairaut's equation against closed forms, and the shipped density profiles against their sources.

Ground truth used here, all independent of wobble's code path:

* a homogeneous body: eps = 5q/4 at every radius (the first-order Maclaurin
  spheroid; Jeffreys 1976, *The Earth*, sec. 4.03), J2 = q/2, C/(Ma^2) = 2/5;
* a two-layer body (uniform core under a uniform mantle): in the mantle the
  P2 potential is alpha r^2 (mantle spheroid and rotation) + beta r^-3 (core
  excess), so the level surfaces have eps(r) = (P r^5 + Q)/(r^2 (rho_m r^3 + K)),
  K = (rho_c - rho_m) b^3, with eps'(b) = 0 (the core is homogeneous) and the
  surface condition a eps'(a) + 2 eps(a) = 5q/2; evaluated with mpmath at 40 digits;
* Clairaut's theorem J2 = (2 eps(a) - q)/3, exact for any first-order solution;
* PREM's mass and moments integrated with mpmath quadrature from its Table 1
  polynomials; the Mars profile re-derived from the catalogue's M, C and core;
* published values computed from physical inputs: Earth's hydrostatic flattening
  1/299.84 (Chambat, Ricard & Valette 2010) and the observed 1/298.257.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
from astropy import units as u
from hypothesis import given, settings
from hypothesis import strategies as st

import wobble
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import load_planet
from wobble.io.density_profile import load_profile
from wobble.models.hydrostatic import DensityProfile, check_profile, hydrostatic_figure

mp.mp.dps = 40
G = 6.6743e-11
SPIN = 7.292115e-5


def _two_layer_exact(b, a, rho_c, rho_m, spin):
    """eps(r) of the two-layer body in closed form (mpmath), and q."""
    b, a, rho_c, rho_m = (mp.mpf(x) for x in (b, a, rho_c, rho_m))
    k = (rho_c - rho_m) * b**3
    mass = 4 * mp.pi / 3 * (rho_m * a**3 + k)
    q = mp.mpf(spin) ** 2 * a**3 / (mp.mpf(G) * mass)
    p_, q_ = mp.mpf(1), 3 * k * b**5 / (5 * rho_m * b**3 + 2 * k)  # eps'(b) = 0

    def shape(r):
        return (p_ * r**5 + q_) / (r**2 * (rho_m * r**3 + k))

    scale = (5 * q / 2) / (a * mp.diff(shape, a) + 2 * shape(a))

    def eps(r):
        r = mp.mpf(r)
        return scale * shape(max(r, b))

    return eps, q


def test_homogeneous_body_is_the_maclaurin_limit():
    body = DensityProfile("uniform", (0.0, 6.4e6), ((5500.0,),), 6.4e6)
    fig = hydrostatic_figure(body, SPIN, G)
    q = fig.q
    assert fig.surface_flattening == pytest.approx(1.25 * q, rel=1e-12)
    assert np.allclose(fig.flattening, 1.25 * q, rtol=1e-12, atol=0)
    assert fig.moment_factor == pytest.approx(0.4, rel=1e-14)
    assert fig.j2 == pytest.approx(0.5 * q, rel=1e-12)
    assert fig.radau_darwin_flattening == pytest.approx(1.25 * q, rel=1e-14)  # exact for eta = 0


@pytest.mark.parametrize(
    ("b", "rho_c", "rho_m"),
    [
        (3.48e6, 11000.0, 4400.0),
        (1.83e6, 6000.0, 3500.0),
        (5.0e6, 5000.0, 4999.0),
        # Small liquid cores: the core's moment (~ b^5) is far below the body's. e_f was 2.5e-5 off at
        # b = 0.003 a (the moment integral's absolute tolerance), and b <= 0.001 a stopped with
        # "step size underflow" at the core-mantle boundary.
        (1.92e4, 8000.0, 4000.0),
        (6.4e3, 8000.0, 4000.0),
        (6.4e3, 1e9, 1000.0),
    ],
)
def test_two_layer_body_matches_the_closed_form_to_1e_10(b, rho_c, rho_m):
    a = 6.4e6
    body = DensityProfile("two", (0.0, b, a), ((rho_c,), (rho_m,)), a, fluid_core=(0.0, b))
    fig = hydrostatic_figure(body, SPIN, G)
    eps, q = _two_layer_exact(b, a, rho_c, rho_m, SPIN)
    assert fig.q == pytest.approx(float(q), rel=1e-14)
    exact = np.array([float(eps(r)) for r in fig.radius[1:]])
    assert np.max(np.abs(fig.flattening[1:] / exact - 1)) < 1e-10
    assert fig.surface_flattening == pytest.approx(float(eps(a)), rel=1e-10)
    # A homogeneous liquid core is a homogeneous spheroid: e_f = eps(b).
    assert fig.core_dynamical_ellipticity == pytest.approx(float(eps(b)), rel=1e-10)


def test_clairauts_theorem_holds_for_prem():
    prem, _ = load_profile("prem")
    fig = hydrostatic_figure(prem, SPIN, G)
    assert fig.j2 == pytest.approx(fig.j2_clairaut, rel=1e-10)
    # Radau-Darwin is an approximation: good to about 1e-3 for Earth.
    assert fig.radau_darwin_flattening == pytest.approx(fig.surface_flattening, rel=2e-3)


def _prem_mp():
    """PREM's Table 1 density polynomials (as shipped) integrated by mpmath quadrature."""
    prem, _ = load_profile("prem")
    a = mp.mpf(6371000)
    total = {2: mp.mpf(0), 4: mp.mpf(0)}
    for lo, hi, c in zip(prem.edges[:-1], prem.edges[1:], prem.coeffs):
        for n in total:
            total[n] += mp.quad(lambda r: sum(mp.mpf(cj) * (r / a) ** j for j, cj in enumerate(c)) * r**n, [lo, hi])
    return prem, 4 * mp.pi * total[2], 8 * mp.pi / 3 * total[4]


def test_prem_mass_and_moment_against_quadrature():
    prem, mass, moment = _prem_mp()
    assert prem.mass() == pytest.approx(float(mass), rel=1e-13)
    assert prem.moment() == pytest.approx(float(moment), rel=1e-13)
    # PREM's published C/(Ma^2) = 0.3308 (Dziewonski & Anderson 1981) from these polynomials.
    assert float(moment / (mass * mp.mpf(6371000) ** 2)) == pytest.approx(0.3308, abs=5e-5)


def test_prem_core_moment_is_the_catalogued_one():
    prem, _ = load_profile("prem")
    earth, _ = load_planet("earth")
    assert prem.moment(1221.5e3, 3480e3) == pytest.approx(earth.fluid_core_equatorial_moment.value, rel=2e-4)


def test_earth_hydrostatic_flattening_beside_the_published_values():
    fig = wobble.hydrostatic_figure("prem", spin=SPIN * u.rad / u.s)
    # First order, a = 6371 km: 1/299.96; Chambat et al. 2010 (second order): 1/299.84; observed 1/298.26.
    ref, _, _ = fig.anchors["reference_hydrostatic_flattening"]
    observed, _, _ = fig.anchors["observed_flattening"]
    assert fig.surface_flattening == pytest.approx(ref, rel=1e-3)
    assert observed > fig.surface_flattening  # the real Earth is flatter than hydrostatic
    assert 1 / observed == pytest.approx(298.257, abs=0.001)


def test_mars_profile_is_rederived_from_the_catalogue():
    mars, _ = load_planet("mars")
    prof, _ = load_profile("mars_layered")
    mass = mp.mpf(mars.gm.value) / mp.mpf(mars.gravitational_constant.value)
    c = mp.mpf(mars.polar_moment_factor.value) * mass * mp.mpf(mars.equatorial_radius.value) ** 2
    rc, rho_c, big_r = (mp.mpf(x) for x in (mars.fluid_core_radius.value, mars.fluid_core_density.value, 3389.5e3))
    m_core, c_core = 4 * mp.pi / 3 * rho_c * rc**3, 8 * mp.pi / 15 * rho_c * rc**5

    def integ(n, j):
        return (big_r ** (n + j + 1) - rc ** (n + j + 1)) / (n + j + 1) / big_r**j

    system = mp.matrix(
        [[4 * mp.pi * integ(2, 0), 4 * mp.pi * integ(2, 1)], [8 * mp.pi / 3 * integ(4, 0), 8 * mp.pi / 3 * integ(4, 1)]]
    )
    a0, a1 = mp.lu_solve(system, mp.matrix([mass - m_core, c - c_core]))
    assert prof.coeffs[1][0] == pytest.approx(float(a0), rel=1e-6)
    assert prof.coeffs[1][1] == pytest.approx(float(a1), rel=1e-6)
    assert prof.coeffs[0][0] == pytest.approx(float(rho_c), rel=1e-12)
    assert prof.edges[1] == pytest.approx(float(rc), rel=1e-12)


@settings(max_examples=15)
@given(scale=st.floats(0.1, 10.0), lam=st.floats(0.1, 10.0))
def test_figure_depends_only_on_q_and_the_shape_of_rho(scale, lam):
    """Scaling all radii by s and densities by l, with Omega^2 scaled by l, leaves eps(r/a) unchanged."""
    base = DensityProfile(
        "two", (0.0, 3.5e6, 6.4e6), ((10000.0, 0.0, -2000.0), (5000.0, -1000.0)), 6.4e6, fluid_core=(0.0, 3.5e6)
    )
    scaled = DensityProfile(
        "two",
        tuple(e * scale for e in base.edges),
        tuple(tuple(c * lam for c in row) for row in base.coeffs),
        base.scale * scale,
        fluid_core=(0.0, 3.5e6 * scale),
    )
    f0 = hydrostatic_figure(base, SPIN, G)
    f1 = hydrostatic_figure(scaled, SPIN * math.sqrt(lam), G)
    assert f1.q == pytest.approx(f0.q, rel=1e-12)
    assert np.allclose(f1.flattening, f0.flattening, rtol=1e-10, atol=0)
    assert f1.core_dynamical_ellipticity == pytest.approx(f0.core_dynamical_ellipticity, rel=1e-10)


# -- bad input ------------------------------------------------------------------


def _two(rho_c=11000.0, rho_m=4400.0, core=(0.0, 3.48e6), b=3.48e6):
    return DensityProfile("bad", (0.0, b, 6.4e6), ((rho_c,), (rho_m,)), 6.4e6, fluid_core=core)


@pytest.mark.parametrize(
    ("profile", "parameter", "fragment"),
    [
        (_two(rho_m=-1.0), "density", "positive"),
        (_two(rho_c=3000.0), "density", "does not increase outward"),
        (_two(core=(0.0, 7.0e6)), "fluid_core_outer_radius", "inside the planet"),
        # A negative inner radius was blamed on the outer one ("fluid_core_outer_radius: got 3480 km").
        (_two(core=(-5.0e3, 3.48e6)), "fluid_core_inner_radius", "at least 0"),
        (_two(core=(0.0, 3.0e6)), "fluid_core_outer_radius", "layer boundary"),
        (
            DensityProfile("x", (0.0, 3.48e6, 6.4e6), ((9000.0, 0.0, 3000.0), (4000.0,)), 6.4e6, (0.0, 3.48e6)),
            "density",
            "liquid core",
        ),
        (DensityProfile("x", (0.0, 6.4e6, 3.0e6), ((9000.0,), (4000.0,)), 6.4e6), "layer_top_radius", "increasing"),
    ],
)
def test_bad_profiles_name_the_parameter(profile, parameter, fragment):
    with pytest.raises(InputError, match=fragment) as info:
        check_profile(profile)
    assert info.value.parameter == parameter


def test_a_bare_gravitational_constant_is_refused_in_words():
    """astropy names the physical type of m3 / (kg s2) 'unknown': the refusal read 'units of unknown'."""
    with pytest.raises(InputError) as info:
        wobble.hydrostatic_figure("mars_layered", spin=1 * u.sday, gravitational_constant=6.674e-11)
    text = str(info.value)
    assert "unknown" not in text and "units of the gravitational constant (e.g. 6.6743e-11 m3 / (kg s2))" in text


def test_profile_mass_must_match_the_body():
    with pytest.raises(InputError, match="density profile mass"):
        wobble.normal_modes("mars", profile="prem")


def test_profile_file_with_a_wrong_unit_names_file_and_key(tmp_path):
    text = Path(load_profile("mars_layered")[1].path).read_text().replace('unit = "g cm-3"', 'unit = "kg"')
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(FileFormatError, match="density_coefficients.unit"):
        load_profile(path)


def test_plain_number_spin_is_refused():
    with pytest.raises(InputError, match="spin"):
        wobble.hydrostatic_figure("prem", spin=7.29e-5)


def test_negative_density_in_a_file_is_one_clear_error(tmp_path):
    text = (
        Path(load_profile("mars_layered")[1].path)
        .read_text()
        .replace("[[6.0, 0.0], [5.035803, -1.826654]]", "[[6.0, 0.0], [-5.0, 0.0]]")
    )
    path = tmp_path / "negative.toml"
    path.write_text(text)
    with pytest.raises(FileFormatError, match="positive density"):
        load_profile(path)
    with pytest.raises(InputError, match="increasing"):
        check_profile(replace(load_profile("prem")[0], edges=(0.0,)))


def test_core_under_linear_mantle_reproduces_mass_and_moment():
    from wobble.models.hydrostatic import core_under_linear_mantle

    mass, radius = 6.4e23, 3.3895e6
    moment = 0.365 * mass * radius**2
    prof = core_under_linear_mantle("x", mass, moment, radius, 1.83e6, 6000.0)
    assert prof.mass() == pytest.approx(mass, rel=1e-13)
    assert prof.moment() == pytest.approx(moment, rel=1e-13)
    with pytest.raises(InputError, match="fluid_core_radius"):
        core_under_linear_mantle("x", mass, moment, radius, 4.0e6, 6000.0)
    with pytest.raises(InputError, match="density"):
        core_under_linear_mantle(
            "x", mass, 0.2 * mass * radius**2, radius, 1.83e6, 6000.0
        )  # mantle denser than the core


def test_a_spin_past_break_up_is_refused():
    """At 1e-2 rad/s PREM came out with a surface flattening of 62.7 (the repr said 1/0.00). Break-up is
    Omega^2 a^3/(G M) = 1: q scales as Omega^2 from Earth's, so 0.01 rad/s is q = 64.9."""
    earth = wobble.hydrostatic_figure("prem", spin=7.292115e-5 * u.rad / u.s)
    q = float(earth.q) * (1e-2 / 7.292115e-5) ** 2
    with pytest.raises(InputError, match=rf"spin: got 0\.01 rad/s; allowed: a spin well below break-up.*here {q:.3g}"):
        wobble.hydrostatic_figure("prem", spin=1e-2 * u.rad / u.s)
