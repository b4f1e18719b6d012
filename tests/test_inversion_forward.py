"""Forward models of the inversion's FCN, precession and Chandler observables, against ground truth.

Ground truth, independent of the vectorised code under test:

* the normal modes of mantle + liquid core: the per-member 4 x 4 real eigenproblem of
  :func:`wobble.models.modes.mode_rates` (NumPy's LAPACK eigensolver); for an
  axisymmetric planet the roots of the 2 x 2 complex determinant of Sasao, Okubo & Saito
  (1980), and for a triaxial one the eigenvalues of the 4 x 4 system, both with mpmath at
  40 digits, each with k2 iterated at the mode's own frequency (IERS Conventions 2010
  eq. 6.12 written out in mpmath);
* the Chandler budget (:func:`wobble.models.chandler.chandler_samples`), the FCN of
  ``wobble.normal_modes`` and the precession rate of ``wobble.precession_rate`` (the
  documented models the observables restate);
* the hydrostatic core: Clairaut's equation solved per profile by
  :func:`wobble.models.hydrostatic.hydrostatic_figure` (tested against closed forms in
  tests/test_hydrostatic.py), and :func:`~wobble.models.hydrostatic.check_profile`'s
  verdict on admissible profiles;
* the precession rate written out by hand, equation (3) of
  :mod:`wobble.models.precession` (Goldstein, Poole & Safko 2002, sec. 5.8).
"""

from __future__ import annotations

import math
from dataclasses import replace

import mpmath as mp
import numpy as np
import pytest
from astropy import units as u

import wobble
from wobble.errors import InputError
from wobble.io.catalog import load_planet
from wobble.io.inversion_file import read_setup
from wobble.models import chandler, hydrostatic
from wobble.models.inversion.context import TABLE_TOLERANCE, FixedCoreFigure, ForwardContext, LinearMantleCoreFigure
from wobble.models.inversion.observables import REGISTRY, Batch
from wobble.models.modes import mode_rates, mode_rates_samples
from wobble.models.planet import Measured

mp.mp.dps = 40
DAY = 86400.0


@pytest.fixture(scope="module")
def mars_setup():
    return read_setup("mars")


@pytest.fixture(scope="module")
def earth_setup():
    return read_setup("earth")


def _draws(p, keys, n, seed, spread=1.0):
    """n members with the catalogued parameters ``keys`` drawn within ``spread`` sigma (uniform)."""
    rng = np.random.default_rng(seed)
    return {k: getattr(p, k).value + spread * getattr(p, k).sigma * rng.uniform(-1, 1, n) for k in keys}


def _member(p, overrides, i):
    return replace(p, **{k: Measured(float(v[i])) for k, v in overrides.items()})


MODE_KEYS = {
    "earth": (
        "love_number_k2",
        "anelastic_exponent",
        "love_number_k2_imaginary",
        "ocean_pole_tide_love_number",
        "fluid_core_equatorial_moment",
        "core_compliance_beta",
        "core_compliance_gamma",
    ),
    "mars": (
        "love_number_k2",
        "anelastic_exponent",
        "love_number_k2_imaginary",
        "fluid_core_radius",
        "fluid_core_density",
        "polar_moment_factor",
        "core_compliance_beta",
        "core_compliance_gamma",
    ),
}


# ---------------------------------------------------------------------------
# Normal modes: vectorised closed form against the per-member eigenproblem and mpmath
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name, e_f", [("earth", 2.674e-3), ("mars", 4.35e-3)])
def test_vectorised_modes_equal_the_per_member_4x4_eigenproblem(name, e_f):
    """Triaxial, anelastic (k2 at each mode's own frequency): every member to 1e-12,
    the FCN also in space, where Omega cancels most of the terrestrial rate."""
    p, _ = load_planet(name)
    over = _draws(p, MODE_KEYS[name], 12, seed=1)
    ef = e_f * (1 + 0.1 * np.random.default_rng(2).uniform(-1, 1, 12))
    vec = mode_rates_samples(p, over, ef)
    spin = p.rotation_rate.value
    for i in range(12):
        ref = mode_rates(_member(p, over, i), float(ef[i]))
        for mode in ("CW", "FCN"):
            assert vec[mode][0][i] == pytest.approx(ref[mode][0], rel=1e-12)
            assert vec[mode][1][i] == pytest.approx(ref[mode][1], rel=1e-12)
        assert vec["FCN"][0][i] + spin == pytest.approx(ref["FCN"][0] + spin, rel=1e-12)


def _k2_mp(p, rate):
    """Re k2 (+ ocean) at |rate| from IERS Conventions 2010 eq. 6.12, in mpmath."""
    alpha = mp.mpf(p.anelastic_exponent.value)
    f = abs(rate) / (2 * mp.pi)
    f_ref = 1 / mp.mpf(p.love_number_k2_period.value)
    f_im = 1 / mp.mpf(p.love_number_k2_imaginary_period.value)
    im = mp.mpf(p.love_number_k2_imaginary.value)
    k = mp.mpf(p.love_number_k2.value) + im * mp.cot(alpha * mp.pi / 2) * (
        (f_im / f) ** alpha - (f_im / f_ref) ** alpha
    )
    if p.ocean_pole_tide_love_number is not None:
        k += mp.mpf(p.ocean_pole_tide_love_number.value)
    return k


def _entries(p, k, e_f):
    """The mode equations' coefficients (units of C) in mpmath: A', B', F, G, Bt, a, b, E."""
    r = chandler.inertia_ratios(p)
    ca, cb = mp.mpf(r["c_minus_a"]), mp.mpf(r["c_minus_b"])
    d = k * mp.mpf(r["deformation_per_k"])
    af = mp.mpf(r["core"])
    beta, gamma = mp.mpf(p.core_compliance_beta.value), mp.mpf(p.core_compliance_gamma.value)
    return 1 - ca + d, 1 - cb + d, af * (1 + gamma), 1 + gamma, 1 + beta, ca - d, cb - d, 1 + mp.mpf(e_f)


def _own_frequency_mp(p, e_f, root, guess):
    """Iterate sigma = root(k2(sigma)) in mpmath (sigma in units of Omega) to 35 digits."""
    spin = mp.mpf(p.rotation_rate.value)
    sigma = mp.mpf(guess)
    for _ in range(200):
        new = root(_entries(p, _k2_mp(p, sigma * spin), e_f))
        if abs(new - sigma) < mp.mpf(10) ** -35 * abs(new):
            return new
        sigma = new
    raise AssertionError("no convergence")


def _sos_quadratic_roots(entries):
    """A = B: (w A' - a)(w Bt + E) - F G w (w + 1) = 0 for w = sigma/Omega (signed: > 0 prograde)."""
    a_, _, f, g, bt, a, _, e = entries
    c2 = a_ * bt - f * g
    c1 = a_ * e - a * bt - f * g
    c0 = -a * e
    disc = mp.sqrt(c1 * c1 - 4 * c2 * c0)
    return sorted([(-c1 + disc) / (2 * c2), (-c1 - disc) / (2 * c2)], key=abs)


@pytest.mark.parametrize("name, e_f", [("earth", 2.674e-3), ("mars", 4.35e-3)])
def test_axisymmetric_modes_are_the_roots_of_the_2x2_determinant_in_mpmath(name, e_f):
    """With A = B the 4 x 4 system is the 2 x 2 complex determinant of Sasao, Okubo & Saito
    (1980), a quadratic in sigma: its roots at 40 digits, k2 at each root's own frequency."""
    p, _ = load_planet(name)
    p = replace(p, c22=None, s22=None)
    vec = mode_rates_samples(p, {}, e_f)
    spin = p.rotation_rate.value
    cw = _own_frequency_mp(p, e_f, lambda ent: _sos_quadratic_roots(ent)[0], 3e-3)
    fcn = _own_frequency_mp(p, e_f, lambda ent: _sos_quadratic_roots(ent)[1], -1.0)
    assert float(vec["CW"][0]) / spin == pytest.approx(float(cw), rel=1e-12)
    assert float(vec["FCN"][0]) / spin == pytest.approx(float(fcn), rel=1e-13)
    # The FCN in space, where the rate is 1/400 of the terrestrial one.
    assert float(vec["FCN"][0]) / spin + 1 == pytest.approx(float(fcn + 1), rel=1e-11)
    assert cw > 0 and -1.01 < fcn < -1


def _eig_4x4_mp(entries, which):
    """|frequency|/Omega of the triaxial 4 x 4 system M x' + K x = 0 from mpmath's eigensolver."""
    a_, b_, f, g, bt, a, b, e = entries
    m = mp.matrix([[a_, 0, f, 0], [0, b_, 0, f], [g, 0, bt, 0], [0, g, 0, bt]])
    k = mp.matrix([[0, b, 0, -f], [-a, 0, f, 0], [0, 0, 0, -e], [0, 0, e, 0]])
    eigenvalues = mp.eig(-(m**-1) * k, left=False, right=False)
    freqs = sorted({mp.nstr(abs(mp.im(x)), 35): abs(mp.im(x)) for x in eigenvalues}.values())
    return freqs[0] if which == "CW" else -freqs[-1]


def test_triaxial_mars_modes_against_the_4x4_eigenvalues_in_mpmath():
    p, _ = load_planet("mars")
    e_f = 4.35e-3
    vec = mode_rates_samples(p, {}, e_f)
    spin = p.rotation_rate.value
    for mode, guess in (("CW", 3e-3), ("FCN", -1.0)):
        ref = _own_frequency_mp(p, e_f, lambda ent, mode=mode: _eig_4x4_mp(ent, mode), guess)
        assert float(vec[mode][0]) / spin == pytest.approx(float(ref), rel=1e-12)


def test_uncoupled_chandler_root_is_the_budget_member_by_member():
    """The inversion's Chandler period (closed form, coupling off) is the budget's equation (1),
    with the budget's verdict on unphysical members (NaN where it has no wobble)."""
    for name in ("earth", "mars"):
        p, _ = load_planet(name)
        keys = [k for k in MODE_KEYS[name] if not k.startswith("core_compliance")]
        rng = np.random.default_rng(3)
        over = {k: getattr(p, k).value * (1 + 0.3 * rng.standard_normal(400)) for k in keys}
        # Unphysical members the budget flags: alpha outside (0, 1) (code 5), k2 above the
        # secular Love number (3), a liquid core as large as the mantle's moment (2).
        over["anelastic_exponent"][0] = 1.2
        over["love_number_k2"][1] = 5.0
        core = "fluid_core_equatorial_moment" if name == "earth" else "fluid_core_radius"
        over[core][2] *= 100.0 if name == "earth" else 1.8
        budget = chandler.chandler_samples(p, over)
        rate = mode_rates_samples(p, over, coupled=False, which=("CW",))["CW"][0]
        period = np.abs(2 * math.pi / rate)
        np.testing.assert_array_equal(np.isfinite(period), np.isfinite(budget.period))
        assert set(budget.code[:3]) == {2, 3, 5}
        ok = np.isfinite(period)
        np.testing.assert_allclose(period[ok], budget.period[ok], rtol=1e-12)
        batch = Batch(p, over)
        np.testing.assert_allclose(REGISTRY["chandler_period"](batch), budget.period, rtol=1e-12)


# ---------------------------------------------------------------------------
# The hydrostatic core: vectorised Clairaut and its table
# ---------------------------------------------------------------------------

G, MARS_R, MARS_A = 6.6743e-11, 3389.5e3, 3396e3


def _mars_numbers():
    p, _ = load_planet("mars")
    mass = p.gm.value / p.gravitational_constant.value
    return p, mass, p.polar_moment_factor.value * mass * p.equatorial_radius.value**2


def test_vectorised_core_flattening_is_clairauts_equation_per_profile():
    p, mass, moment = _mars_numbers()
    spin, g = p.rotation_rate.value, p.gravitational_constant.value
    rho_mean = mass / (4 / 3 * math.pi * MARS_R**3)
    q = spin**2 * MARS_R**3 / p.gm.value
    cases = [(1.83e6, 6000.0), (1.45e6, 7200.0), (2.15e6, 5400.0), (1.0e6, 9000.0)]
    x = np.array([r for r, _ in cases]) / MARS_R
    y = np.array([rho for _, rho in cases]) / rho_mean
    vec = q * hydrostatic.core_flattening_under_linear_mantle(x, y, moment / (mass * MARS_R**2))
    for (r, rho), value in zip(cases, vec):
        prof = hydrostatic.core_under_linear_mantle("m", mass, moment, MARS_R, r, rho)
        ref = hydrostatic.hydrostatic_figure(prof, spin, g).core_dynamical_ellipticity
        assert value == pytest.approx(ref, rel=1e-10)


def test_admissible_core_densities_are_the_profiles_check_profile_accepts():
    p, mass, moment = _mars_numbers()
    rho_mean = mass / (4 / 3 * math.pi * MARS_R**3)
    c = moment / (mass * MARS_R**2)
    for r in (1.2e6, 1.83e6, 2.2e6):
        lo, hi = hydrostatic.linear_mantle_core_density_range(r / MARS_R, c)
        assert 0 < lo < hi < np.inf
        for y in (lo * (1 + 1e-6), hi * (1 - 1e-6)):
            hydrostatic.core_under_linear_mantle("m", mass, moment, MARS_R, r, y * rho_mean)  # accepted
        for y in (lo * (1 - 1e-6), hi * (1 + 1e-6)):
            with pytest.raises(InputError, match="density"):
                hydrostatic.core_under_linear_mantle("m", mass, moment, MARS_R, r, y * rho_mean)
            assert np.isnan(hydrostatic.core_flattening_under_linear_mantle(r / MARS_R, y, c))


def test_tabulated_core_flattening_against_the_direct_solve(mars_setup):
    """The table's error, measured at fresh random points of its box (not the build's), is
    within the tolerance it states; outside the box or the admissible profiles: NaN."""
    fig = mars_setup.context.core_figure
    assert isinstance(fig, LinearMantleCoreFigure) and fig.max_error <= TABLE_TOLERANCE
    rng = np.random.default_rng(11)
    x, y, c = (rng.uniform(lo, hi, 300) for lo, hi in fig.box)
    lo_y, hi_y = hydrostatic.linear_mantle_core_density_range(x, c)
    ok = (y > lo_y) & (y < hi_y)
    direct = hydrostatic.core_flattening_under_linear_mantle(x[ok], y[ok], c[ok])
    from wobble.models.inversion.context import _evaluate

    table = _evaluate(fig.coefficients, fig.box, x[ok], y[ok], c[ok])
    np.testing.assert_allclose(table, direct, rtol=2 * TABLE_TOLERANCE)
    # Through a batch, in SI: e_f of the catalogued Mars equals the profile API's.
    p = mars_setup.planet
    batch = Batch(
        p,
        {
            "fluid_core_radius": np.array([1.83e6, 2.5e6, 1.83e6]),
            "fluid_core_density": np.array([6000.0, 6000.0, 1.0e4]),
        },
    )
    e = fig.hydrostatic(batch)
    assert e[0] == pytest.approx(wobble.normal_modes("mars").core_flattening_hydrostatic, rel=1e-9)
    assert np.isnan(e[1]) and np.isnan(e[2])  # outside the priors' box; a core too dense for the mantle


# ---------------------------------------------------------------------------
# The observables at the catalogue's values against the documented models
# ---------------------------------------------------------------------------


def _nominal(setup):
    post = setup.posterior()
    return post, np.array(
        [[getattr(setup.planet, n).value if getattr(setup.planet, n) is not None else 0.0 for n in post.names]]
    )


def test_fcn_observable_is_the_normal_modes_fcn_in_space(mars_setup, earth_setup):
    for setup, name in ((mars_setup, "mars"), (earth_setup, "earth")):
        post, theta = _nominal(setup)
        fcn = post.predict(theta, ["fcn_period"])["fcn_period"][0]
        ref = wobble.normal_modes(name).mode("FCN", "celestial").period.to_value(u.s)
        assert fcn == pytest.approx(ref, rel=1e-9), name
    # Earth: the hydrostatic PREM core gives about -459 d; +5.1 % flattening gives the observed -430 d.
    post, theta = _nominal(earth_setup)
    assert isinstance(earth_setup.context.core_figure, FixedCoreFigure)
    i = post.names.index("core_flattening_excess")
    theta = np.repeat(theta, 2, axis=0)
    theta[1, i] = wobble.normal_modes("earth").core_flattening_excess
    fcn = post.predict(theta, ["fcn_period"])["fcn_period"] / DAY
    assert fcn[0] == pytest.approx(-458.7, abs=0.1)
    assert fcn[1] == pytest.approx(earth_setup.planet.observed_fcn_period.value / DAY, rel=1e-9)


def test_precession_observable_is_equation_3_and_the_budgets_rate(mars_setup):
    post, theta = _nominal(mars_setup)
    rate = post.predict(theta, ["precession_rate"])["precession_rate"][0]
    assert rate == pytest.approx(wobble.precession_rate("mars").rate.to_value(u.rad / u.s), rel=1e-12)
    # By hand: -(3/2) G M_sun (1 - e^2)^(-3/2)/a^3 (J2/(C/(M R^2)))/Omega cos(eps); Mars' observed
    # rate excludes geodesic precession (the catalogue's flag), so none is added.
    p = mars_setup.planet
    gm_sun = 1.32712440041e20
    strength = gm_sun / p.orbit_semi_major_axis.value**3 / (1 - p.orbit_eccentricity.value**2) ** 1.5
    h = p.j2.value / p.polar_moment_factor.value
    by_hand = -1.5 * strength * h / p.rotation_rate.value * math.cos(p.obliquity.value)
    # The planets add 4.5e-5 of it (tests/test_precession_planets.py), and Phobos' and Deimos' rings multiply the
    # sum by 1 + 5.8e-5, as in the budget (tests/test_precession_rings.py).
    budget = wobble.precession_rate("mars")
    terms = {t.name: t.rate.value for t in budget.terms}
    sun = terms["sun"] + terms["sun_eccentricity"]
    planets = budget.planetary.value / sun
    rings = (terms["phobos"] + terms["deimos"]) / (sun + budget.planetary.value)
    assert 4.4e-5 < planets < 4.6e-5 and 5.7e-5 < rings < 5.9e-5
    assert rate == pytest.approx(by_hand * (1 + planets) * (1 + rings), rel=1e-12)
    # The sampled polar moment moves it as 1/C (the rings' angular momentum, 1.4e-6 of C omega, adds 1.4e-9).
    i = post.names.index("polar_moment_factor")
    moved = theta.copy()
    moved[0, i] *= 1.001
    assert post.predict(moved, ["precession_rate"])["precession_rate"][0] == pytest.approx(rate / 1.001, rel=1e-8)


def test_earth_precession_observable_includes_geodesic_and_the_moon():
    setup = wobble.load_inversion_setup(
        {
            "schema": "wobble-inversion/1",
            "name": "earth_precession",
            "body": "earth",
            "parameters": {"anelastic_exponent": {}},
            "observables": {"precession_rate": {}},
        }
    )
    planets = ["mercury", "venus", "mars", "jupiter", "saturn", "uranus", "neptune"]
    assert [o.name for o in setup.context.perturbers] == ["sun", "moon", *planets] and setup.context.geodesic_rate > 0
    post, theta = _nominal(setup)
    rate = post.predict(theta, ["precession_rate"])["precession_rate"][0]
    assert rate == pytest.approx(wobble.precession_rate("earth").rate.to_value(u.rad / u.s), rel=1e-12)


def test_forward_models_without_their_context_are_refused():
    mars, _ = load_planet("mars")
    batch = Batch(mars, {"fluid_core_radius": np.array([1.8e6])})
    with pytest.raises(InputError, match="core_figure"):
        REGISTRY["fcn_period"](batch)
    with pytest.raises(InputError, match="perturbers"):
        REGISTRY["precession_rate"](batch)
    assert ForwardContext().torque_strength == 0.0
