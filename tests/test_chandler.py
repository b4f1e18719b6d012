"""The Chandler model against ground truth.

References used here, all independent of wobble's code path:
* mpmath at 40 digits, from the catalogue's raw inputs through absolute moments
  A, B, C in kg m^2 (the code works with ratios (C-A)/C instead);
* published values computed from physical inputs: the rigid Earth period
  range 303-306 d, the IERS pole-tide Love number 0.3077 + 0.0036i (TN36 sec.
  6.4) that eq. 6.12 must reproduce at the Chandler frequency, the observed
  periods (433.1 d, 206.9 d) that the full model must approach.
"""

from __future__ import annotations

import math
from dataclasses import replace

import mpmath as mp
import numpy as np
import pytest
from astropy import units as u
from hypothesis import given
from hypothesis import strategies as st

import wobble
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import load_planet as load_si
from wobble.models.chandler import MC_DRAWS, anelastic_love_number, chandler_budget, free_wobble_rate
from wobble.models.planet import Measured

mp.mp.dps = 40
DAY = 86400
SIDEREAL_DAY = 86164.0905


def _mp_moments(p):
    """A, B, C (kg m^2) and Omega at 40 digits, straight from the catalogue numbers."""
    gm, a, g = (mp.mpf(float(x.value)) for x in (p.gm, p.equatorial_radius, p.gravitational_constant))
    mass = gm / g
    if p.polar_moment_factor is not None:
        cfac = mp.mpf(float(p.polar_moment_factor.value))
    else:
        cfac = mp.mpf(float(p.j2.value)) / mp.mpf(float(p.dynamical_flattening.value))
    j2 = mp.mpf(float(p.j2.value)) if p.j2 is not None else mp.mpf(float(p.dynamical_flattening.value)) * cfac
    c = cfac * mass * a**2
    abar = c - j2 * mass * a**2
    c22 = mp.mpf(float(p.c22.value)) if p.c22 else 0
    s22 = mp.mpf(float(p.s22.value)) if p.s22 else 0
    j22 = mp.sqrt(mp.mpf(5) / 12) * mp.sqrt(c22**2 + s22**2)
    return (
        abar - 2 * j22 * mass * a**2,
        abar + 2 * j22 * mass * a**2,
        c,
        mp.mpf(float(p.rotation_rate.value)),
        mass,
        a,
        g,
    )


def _mp_period_days(sigma):
    return float(2 * mp.pi / sigma / DAY)


@pytest.fixture(scope="module")
def earth():
    return load_si("earth")[0]


@pytest.fixture(scope="module")
def mars():
    return load_si("mars")[0]


# -- the rigid (Euler) period ---------------------------------------------------


def test_earth_rigid_period_matches_mpmath_and_published_range(earth):
    A, B, C, om, *_ = _mp_moments(earth)
    ref = _mp_period_days(om * mp.sqrt((C - A) * (C - B) / (A * B)))
    got = chandler_budget(earth, "rigid").period / DAY
    assert got == pytest.approx(ref, rel=1e-13)
    # Published: 303-306 d; A/(C-A) sidereal days = 304.456 sd = 303.62 solar days.
    assert 303 < got < 306
    assert got == pytest.approx(303.62, abs=0.01)
    assert got * DAY / SIDEREAL_DAY == pytest.approx(304.456, abs=0.002)


def test_using_h_instead_of_c_minus_a_over_a_is_the_common_slip(earth):
    # T_E = A/(C-A) sidereal days, not C/(C-A) (= 1/H = 305.46 sd).
    sym = replace(earth, c22=None, s22=None)
    h = earth.dynamical_flattening.value
    assert chandler_budget(sym, "rigid").period / SIDEREAL_DAY == pytest.approx((1 - h) / h, rel=2e-7)
    assert abs(chandler_budget(sym, "rigid").period / SIDEREAL_DAY - 1 / h) > 0.9


def test_mars_triaxial_rigid_period_matches_mpmath(mars):
    A, B, C, om, *_ = _mp_moments(mars)
    ref = _mp_period_days(om * mp.sqrt((C - A) * (C - B) / (A * B)))
    assert chandler_budget(mars, "rigid").period / DAY == pytest.approx(ref, rel=1e-12)
    # Triaxiality lengthens the period by ~(2 J22/J2)^2/2 = 0.2 % over the mean-moment value.
    mean = _mp_period_days(om * ((C - (A + B) / 2) / ((A + B) / 2)))
    assert ref / mean - 1 == pytest.approx(0.0021, abs=0.0002)


def test_notes_formula_symmetric_body():
    # Omega = (I3 - I1)/I1 * omega3 (notes p. 68).
    i1, i3, w3 = 2.0, 3.0, 5.0
    rate = wobble.free_precession_rate([i1, i3] * u.kg * u.m**2, spin=w3 * u.rad / u.s)
    assert rate.to_value(u.rad / u.s) == pytest.approx((i3 - i1) / i1 * w3, rel=1e-15)


def test_prolate_body_wobbles_retrograde_and_says_so():
    res = wobble.rigid_wobble([3.0, 2.0] * u.kg * u.m**2, spin=1 * u.rad / u.s)
    assert res.rate.to_value(u.rad / u.s) == pytest.approx(-1 / 3, rel=1e-15)
    assert res.sense == "retrograde" and "retrograde" in res.message
    assert res.period.to_value(u.s) == pytest.approx(6 * math.pi, rel=1e-15)


def test_sphere_has_no_wobble_infinite_period_no_crash():
    res = wobble.rigid_wobble([1.0, 1.0, 1.0] * u.kg * u.m**2, spin=1 * u.rad / u.s)
    assert res.rate.value == 0 and math.isinf(res.period.value)
    assert not math.copysign(1.0, res.rate.value) < 0, "a zero rate printed as '-0.0 rad / s'"
    assert res.sense == "none" and "no free wobble" in res.message


def test_a_body_at_rest_is_not_called_spherical():
    """Zero spin gives no wobble for any body: Earth's moments at rest were reported as a spherical body."""
    res = wobble.rigid_wobble([8.0101e37, 8.0365e37] * u.kg * u.m**2, spin=0 * u.rad / u.s)
    assert res.rate.value == 0 and math.isinf(res.period.value) and res.sense == "none"
    assert res.message.startswith("no spin") and "spherical" not in res.message


def test_ratio_inputs_agree_with_moments():
    spin = 1 * u.sday
    h = 3.273795e-3
    by_h = wobble.euler_period(dynamical_flattening=h, spin=spin)
    by_e = wobble.euler_period(inertia_ratio=h / (1 - h), spin=spin)
    by_m = wobble.euler_period([1 - h, 1.0] * u.kg * u.m**2, spin=spin)
    assert by_h.to_value(u.day) == pytest.approx(by_e.to_value(u.day), rel=1e-14)
    assert by_h.to_value(u.day) == pytest.approx(by_m.to_value(u.day), rel=1e-12)
    assert by_h.to_value(u.day) == pytest.approx(303.62, abs=0.01)


def test_intermediate_axis_spin_has_no_periodic_wobble():
    with pytest.raises(InputError, match="intermediate"):
        wobble.rigid_wobble([1.0, 3.0, 2.0] * u.kg * u.m**2, spin=1 * u.rad / u.s)


@given(
    i1=st.floats(0.5, 2.0),
    i3=st.floats(0.5, 2.0),
    scale=st.floats(1e-6, 1e38),
    w=st.floats(1e-3, 1e3),
)
def test_rate_is_scale_invariant_and_symmetric_in_i1_i2(i1, i3, scale, w):
    if i3 > 2 * i1:  # outside the triangle inequality
        return
    m = np.array([i1, i1, i3])
    r1 = free_wobble_rate(w, (i3 - i1) / i3, (i3 - i1) / i3)
    r2 = wobble.free_precession_rate(m * scale * u.kg * u.m**2, spin=w * u.rad / u.s).to_value(u.rad / u.s)
    assert r2 == pytest.approx(r1, rel=1e-9, abs=1e-300)
    assert r1 == pytest.approx((i3 - i1) / i1 * w, rel=1e-9, abs=1e-12 * w)


@given(period_hours=st.floats(0.1, 1e5))
def test_spin_as_period_or_rate_and_unit_round_trip(period_hours):
    h = 0.01
    a = wobble.euler_period(dynamical_flattening=h, spin=period_hours * u.h)
    b = wobble.euler_period(dynamical_flattening=h, spin=(2 * math.pi / (period_hours * 3600)) * u.rad / u.s)
    assert a.to_value(u.h) == pytest.approx(b.to_value(u.h), rel=1e-12)
    assert a.to(u.min).to_value(u.h) == pytest.approx(period_hours * (1 - h) / h, rel=1e-12)


# -- the corrections -----------------------------------------------------------------


def test_elastic_and_core_steps_match_the_closed_forms(earth):
    sym = replace(earth, c22=None, s22=None)
    A, _, C, om, mass, a, g = _mp_moments(sym)
    k = mp.mpf(float(sym.love_number_k2.value))
    ks = 3 * g * (C - A) / (a**5 * om**2)
    af = mp.mpf(float(sym.fluid_core_equatorial_moment.value))
    # D = k (C - A)/k_s: the deformation's products of inertia per unit wobble; it lowers the
    # numerator (Munk & MacDonald's 1 - k/k_s) and, as the deformation's own angular momentum,
    # adds to the moment that carries the wobble (Sasao, Okubo & Saito 1980).
    big_d = k * (C - A) / ks
    steps = {s.name: s.period / DAY for s in chandler_budget(sym, "fluid_core").steps}
    assert steps["elastic"] == pytest.approx(_mp_period_days(om * (C - A - big_d) / (A + big_d)), rel=1e-12)
    assert steps["fluid_core"] == pytest.approx(_mp_period_days(om * (C - A - big_d) / (A - af + big_d)), rel=1e-12)
    # The secular Love number of TN36's Earth: 3G(C-A)/(Omega^2 a^5) = 0.93832 (reference values).
    assert chandler_budget(sym).secular_love_number == pytest.approx(0.93832, abs=1e-5)


def test_iers_anelastic_model_gives_the_published_pole_tide_love_number(earth):
    # TN36 sec. 6.4 uses k2 = 0.3077 + 0.0036i for the pole tide: eq. 6.12 at the Chandler frequency.
    rate = 2 * math.pi / (433.1 * DAY)
    real, imag = anelastic_love_number(earth, rate)
    assert real == pytest.approx(0.3077, abs=6e-5)
    assert imag == pytest.approx(0.0036, abs=6e-5)


def test_anelastic_step_is_self_consistent(earth, mars):
    for p in (earth, mars):
        budget = chandler_budget(p)
        last = budget.steps[-1]
        real, _ = anelastic_love_number(p, last.rate)
        ocean = p.ocean_pole_tide_love_number.value if p.ocean_pole_tide_love_number else 0.0
        assert last.love_number == pytest.approx(real + ocean, rel=1e-13)


def test_step_sizes_have_the_published_signs_and_sizes(earth):
    p = {s.name: s.period / DAY for s in chandler_budget(earth).steps}
    # Zharkov & Molodensky (1996): elasticity lengthens by "of the order of 143 days",
    # the liquid core shortens, the ocean pole tide and anelasticity lengthen.
    assert p["elastic"] - p["rigid"] == pytest.approx(143, rel=0.05)
    assert p["fluid_core"] < p["elastic"]
    assert p["ocean_pole_tide"] > p["fluid_core"] and p["anelastic"] > p["ocean_pole_tide"]


# -- the accuracy requirements, from physical parameters only ------------


def test_earth_full_model_within_one_percent_of_observed():
    b = wobble.chandler_budget("earth")
    assert b.model == "full" and [s.name for s in b.steps][0] == "rigid"
    assert abs(b.relative_residual) < 0.01
    assert b.observed.to_value(u.day) == pytest.approx(433.1)
    # The miss is honest: inside the model's own propagated uncertainty.
    assert abs(b.residual) < 2 * np.hypot(b.period_uncertainty, b.observed_uncertainty)


def test_mars_full_model_within_two_percent_of_observed():
    b = wobble.chandler_budget("mars")
    assert [s.name for s in b.steps] == ["rigid", "elastic", "fluid_core", "anelastic"]
    assert abs(b.relative_residual) < 0.02
    assert abs(b.residual) < 2 * np.hypot(b.period_uncertainty, b.observed_uncertainty)


def test_observed_period_is_never_an_input(earth):
    moved = replace(earth, observed_chandler_period=Measured(1e7, 1.0))
    assert chandler_budget(moved).period == chandler_budget(earth).period


def test_uncertainty_is_linear_propagation(earth):
    # Rigid symmetric Earth with only H uncertain: sigma_T = T sigma_H / (H (1 - H)).
    only_h = replace(
        earth,
        c22=None,
        s22=None,
        j2=Measured(earth.j2.value),
        gm=None,
        dynamical_flattening=Measured(earth.dynamical_flattening.value, 1e-6),
    )
    b = chandler_budget(only_h, "rigid")
    h = only_h.dynamical_flattening.value
    assert b.period_sigma_linear == pytest.approx(b.period * 1e-6 / (h * (1 - h)), rel=1e-6)
    assert set(b.contributions) == {"dynamical_flattening"}
    # Over so small a range the model is linear: the Monte Carlo sigma is the same within sampling error.
    assert b.period_sigma == pytest.approx(b.period_sigma_linear, rel=4 / np.sqrt(2 * MC_DRAWS))


def test_budget_without_uncertainty_has_the_same_steps_and_no_sigma(earth):
    """``uncertainty=False`` (what the normal modes use) skips the propagation, nothing else; the
    rigid step is the closed form T = T_sid (1 - H)/H of a symmetric body."""
    full, bare = chandler_budget(earth), chandler_budget(earth, uncertainty=False)
    assert bare.steps == full.steps
    assert math.isnan(bare.period_sigma) and math.isnan(bare.period_sigma_linear) and not bare.contributions
    symmetric = replace(earth, c22=None, s22=None)
    h = symmetric.dynamical_flattening.value
    rigid = chandler_budget(symmetric, "rigid", uncertainty=False)
    assert rigid.period == pytest.approx(2 * math.pi / earth.rotation_rate.value * (1 - h) / h, rel=1e-14)


def test_uncertainty_is_the_monte_carlo_spread_of_a_nonlinear_model(earth):
    """A 10 % uncertainty on H: T = T_sid (1 - H)/H is far from linear, and the budget's sigma is
    the standard deviation of T over the normal H, computed here by mpmath quadrature."""
    import mpmath as mp

    h, rel = earth.dynamical_flattening.value, 0.1
    only_h = replace(
        earth,
        c22=None,
        s22=None,
        j2=Measured(earth.j2.value),
        gm=None,
        dynamical_flattening=Measured(h, rel * h),
    )
    b = chandler_budget(only_h, "rigid")
    mp.mp.dps = 30
    sidereal = 2 * mp.pi / mp.mpf(earth.rotation_rate.value)

    def density(x):
        return mp.npdf(x, h, rel * h)

    def period(x):
        return sidereal * (1 - x) / x

    # H > 0 up to 5 sigma: the omitted tail (5e-7 of the draws) changes sigma by < 1e-4.
    lo, hi = h * (1 - 5 * rel), h * (1 + 5 * rel)
    weight = mp.quad(density, [lo, h, hi])
    mean = mp.quad(lambda x: period(x) * density(x), [lo, h, hi]) / weight
    sd = mp.sqrt(mp.quad(lambda x: (period(x) - mean) ** 2 * density(x), [lo, h, hi]) / weight)
    assert b.period_sigma == pytest.approx(float(sd), rel=4 / np.sqrt(2 * MC_DRAWS) + 2e-3)
    # ... which the first-order propagation underestimates by about 3 per cent.
    assert b.period_sigma_linear < 0.98 * b.period_sigma


def test_quality_factor_is_plausible():
    # Lambeck 1980: 60-100; Gross 2015: 32.5 (free decay). Q from the anelastic k2 alone.
    q = wobble.chandler_budget("earth").quality_factor
    assert 30 < q < 180


def test_a_wobble_without_dissipation_has_an_infinite_q_not_none(tmp_path, capsys):
    """k2 with no out-of-phase part: sigma is real, Q = Re sigma / (2 |Im sigma|) is infinite. It was None, as
    for a model without an anelastic step, and the text said nothing; a rigid model still has none."""
    from wobble.cli import main
    from wobble.io.catalog import catalogue_file

    text = catalogue_file("earth").read_text()
    block = text.index("[parameters.love_number_k2_imaginary]")
    end = text.index("\n[", block + 1)
    lossless = (
        text[:block]
        + text[block:end].replace("value = 5.796e-4", "value = 0.0").replace("uncertainty = 6e-5", "uncertainty = 0.0")
        + text[end:]
    )
    assert lossless != text
    path = tmp_path / "lossless.toml"
    path.write_text(lossless)
    assert wobble.chandler_budget(path).quality_factor == math.inf
    assert wobble.chandler_budget(path, "core").quality_factor is None
    assert main(["chandler", "--body-file", str(path)]) == 0
    assert "Q implied by the out-of-phase part of k2: infinite" in capsys.readouterr().out
    assert main(["chandler", "--body-file", str(path), "-o", str(tmp_path / "q.nc")]) == 0
    capsys.readouterr()
    assert wobble.load(tmp_path / "q.nc")["quality_factor"].values.tolist() == [math.inf]


# -- models, body files and bad input -----------------------------------------------


def test_model_choice_is_cumulative_and_named():
    names = [s.name for s in wobble.chandler_budget("earth", "core").steps]
    assert names == ["rigid", "elastic", "fluid_core"]
    with pytest.raises(InputError, match="model: got ocean; allowed: a model mars supports"):
        wobble.chandler_budget("mars", "ocean")
    with pytest.raises(InputError, match="model: got bogus"):
        wobble.chandler_budget("earth", "bogus")


def test_unknown_body_lists_the_known_ones():
    with pytest.raises(InputError, match="body: got pluto; allowed: one of earth, mars"):
        wobble.chandler_budget("pluto")


def test_user_body_file_minimal_and_malformed(tmp_path):
    minimal = tmp_path / "blob.toml"
    minimal.write_text(
        'schema = "wobble/1"\nkind = "planet"\nname = "blob"\n'
        '[parameters.rotation_period]\nvalue = 10\nuncertainty = 0\nunit = "h"\nsource = "test"\nstatus = "assumed"\n'
        '[parameters.dynamical_flattening]\nvalue = 0.01\nuncertainty = 0\nunit = ""\nsource = "test"\nstatus = '
        '"assumed"\n'
    )
    b = wobble.chandler_budget(minimal)
    assert [s.name for s in b.steps] == ["rigid"] and b.observed is None
    assert b.period.to_value(u.h) == pytest.approx(10 * 0.99 / 0.01, rel=1e-13)
    bad = tmp_path / "bad.toml"
    bad.write_text(minimal.read_text().replace('unit = "h"', 'unit = "m"'))
    with pytest.raises(FileFormatError, match=r"parameters\.rotation_period\.unit: got 'm'; allowed: a unit of s"):
        wobble.chandler_budget(bad)
    missing = tmp_path / "missing.toml"
    missing.write_text(minimal.read_text().split("[parameters.dynamical_flattening]")[0])
    with pytest.raises(FileFormatError, match="figure"):
        wobble.chandler_budget(missing)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"moments": [-1.0, 2.0] * u.kg * u.m**2}, "moments: .*positive"),
        ({"moments": [0.0, 2.0] * u.kg * u.m**2}, "moments: .*positive"),
        ({"moments": [np.nan, 2.0] * u.kg * u.m**2}, "moments: .*finite"),
        ({"moments": [1.0, 2.0]}, "moments: .*plain number has no unit"),
        ({"moments": [1.0, 3.0] * u.kg * u.m**2}, "triangle"),
        ({"dynamical_flattening": 1.5}, r"dynamical_flattening: got 1\.5; allowed: a number in \(-inf, 0\.5\]"),
        ({"inertia_ratio": -1.0}, r"inertia_ratio: got -1\.0; allowed: a number in \(-1, 1\]"),
        ({"inertia_ratio": 1.01}, r"inertia_ratio: got 1\.01; allowed: a number in \(-1, 1\]"),
        ({"dynamical_flattening": 0.7}, "triangle"),
        ({"dynamical_flattening": np.inf}, "dynamical_flattening: got inf; allowed: a finite number"),
    ],
)
def test_bad_rigid_inputs_name_the_parameter(kwargs, message):
    with pytest.raises(InputError, match=message):
        wobble.rigid_wobble(spin=1 * u.day, **kwargs)


def test_a_prolate_body_given_by_h_wobbles_as_given_by_its_moments():
    """A uniform cylinder of radius R and height 5R spun about its axis: C = M R^2/2, A = M (3 R^2 + 25 R^2)/12
    = 7/3 M R^2, so H = (C - A)/C = -11/3 and (C - A)/A = -11/14 (Goldstein, Poole & Safko 2002 sec. 5.6:
    Omega = (C - A)/A omega). H was refused below -1, though every H up to 1/2 is a body."""
    spin = 1 * u.rad / u.s
    want = -11.0 / 14.0
    by_h = wobble.rigid_wobble(dynamical_flattening=-11.0 / 3.0, spin=spin)
    by_moments = wobble.rigid_wobble([7.0 / 3.0, 0.5] * u.kg * u.m**2, spin=spin)
    for got in (by_h, by_moments, wobble.rigid_wobble(inertia_ratio=want, spin=spin)):
        assert got.rate.to_value(u.rad / u.s) == pytest.approx(want, rel=1e-15) and got.sense == "retrograde"
    # The flat disc, (C - A)/A = 1 and H = 1/2, is the other end: both spellings accepted, Omega = omega.
    for kwargs in ({"inertia_ratio": 1.0}, {"dynamical_flattening": 0.5}):
        assert wobble.rigid_wobble(spin=spin, **kwargs).rate.to_value(u.rad / u.s) == pytest.approx(1.0, rel=1e-15)


def test_spin_in_metres_is_refused():
    with pytest.raises(InputError, match="spin: got 1.0 m; allowed: an angular speed"):
        wobble.euler_period(dynamical_flattening=0.01, spin=1 * u.m)


def test_a_body_softer_than_a_fluid_is_refused(earth):
    soft = replace(earth, love_number_k2=Measured(1.2, 0.0))
    with pytest.raises(InputError, match="love_number_k2: .*secular Love number"):
        chandler_budget(soft, "elastic")


def test_astropy_is_configured_offline():
    from astropy.utils import iers

    assert iers.conf.auto_download is False


# -- the vectorised evaluation used by sweeps -------------------------------------------


def test_samples_agree_member_by_member_with_the_scalar_model(mars):
    from wobble.models.chandler import chandler_samples

    k2 = np.array([0.160, 0.169, 0.178])
    core_radius = np.array([1.79e6, 1.83e6, 1.87e6])
    s = chandler_samples(mars, {"love_number_k2": k2, "fluid_core_radius": core_radius})
    assert s.valid.all() and s.period.shape == (3,)
    for i in range(3):
        one = replace(mars, love_number_k2=Measured(k2[i], 0.0), fluid_core_radius=Measured(core_radius[i], 0.0))
        assert s.period[i] == pytest.approx(chandler_budget(one).period, rel=1e-14)
        assert s.step_periods[:, i] == pytest.approx([st.period for st in chandler_budget(one).steps], rel=1e-14)


def test_samples_mark_unphysical_members_instead_of_raising(earth):
    from wobble.models.chandler import INVALID_REASONS, chandler_samples

    s = chandler_samples(
        earth, {"love_number_k2": np.array([0.29525, 1.5, -0.1]), "c22": np.array([2.4e-6, 2.4e-6, 2.4e-6])}
    )
    assert list(s.code) == [0, 3, 5]
    assert np.isfinite(s.period[0]) and np.isnan(s.period[1:]).all()
    assert "fluid" in INVALID_REASONS[3]
    flip = chandler_samples(
        earth, {"dynamical_flattening": np.array([3.2e-3, 1e-6]), "c22": np.array([2.4e-6, 2e-3])}, "rigid"
    )
    assert list(flip.code) == [0, 1]  # C intermediate: no periodic wobble


def test_samples_refuse_unknown_parameter_names(earth):
    from wobble.models.chandler import chandler_samples

    with pytest.raises(InputError, match="parameter: got love_number"):
        chandler_samples(earth, {"love_number": np.array([0.3])})


def test_anelastic_solution_near_the_fluid_limit(mars):
    from wobble.models.chandler import chandler_samples

    k2 = np.array([0.169, 0.9, 1.05, 1.2, 1.27])
    s = chandler_samples(mars, {"love_number_k2": k2})
    ok = s.code == 0
    assert ok[:3].all()  # solutions exist and are found (slow contraction near k_s)
    assert (s.code[~ok] == 3).all()  # where k2(frequency) runs past k_s: no restoring torque left
    for k, period in zip(k2[ok], s.period[ok]):
        p = replace(mars, love_number_k2=Measured(k))
        last = chandler_budget(p).steps[-1]
        real, _ = anelastic_love_number(p, last.rate)
        assert last.love_number == pytest.approx(real, rel=1e-12)  # self-consistent
        assert last.period == pytest.approx(period, rel=1e-13)


@pytest.mark.parametrize(
    ("body", "model"),
    [
        (body, model)
        for body in ("earth", "mars")
        for model in ("rigid", "elastic", "fluid_core", "ocean_pole_tide", "anelastic")
        if (body, model) != ("mars", "ocean_pole_tide")  # Mars has no ocean
    ],
)
def test_the_monte_carlo_draws_every_parameter_the_model_reads_and_no_other(body, model):
    """Each uncertain parameter outside parameters_used(steps) must leave the period unchanged when moved by
    +-1 sigma (checked on a planet with only that parameter moved), and each inside it drawn; an unused one
    drawn out of range dropped the draw (Mars's rigid period lost 2.3 % of its draws to the anelastic exponent)."""
    from wobble.io.catalog import load_planet
    from wobble.models.chandler import ParameterValues, _evaluate, parameters_used, resolve_model

    planet, _ = load_planet(body)
    _, steps = resolve_model(planet, model)
    used = parameters_used(steps)
    for key, m in planet.measured_fields().items():
        if key in used or key == "observed_chandler_period":
            continue
        moved = ParameterValues(planet.values(), {key: [m.value - m.sigma, m.value, m.value + m.sigma]})
        out, code, _ = _evaluate(moved, steps)
        rates = out[-1].rate
        assert rates[0] == rates[1] == rates[2], key
    if model == "rigid":
        budget = wobble.chandler_budget(body, model="rigid")
        assert budget.to_dict()["monte_carlo_valid_fraction"] == 1.0


@pytest.mark.parametrize("body", [None, 3, 2.5])
def test_a_body_that_is_not_a_name_or_a_path_is_named(body):
    """None or 3 raised a bare TypeError from os.fspath."""
    with pytest.raises(InputError, match=r"^body: got .*; allowed: one of earth, mars, or the path of a planet file"):
        wobble.chandler_budget(body)


def test_chandler_dataset_takes_one_budget_and_names_what_is_not_one():
    mars = wobble.chandler_budget("mars")
    one, listed = wobble.chandler_dataset(mars), wobble.chandler_dataset([mars])
    assert one.identical(listed)
    with pytest.raises(InputError, match=r"^budgets: got 'earth'; allowed: ChandlerBudgets"):
        wobble.chandler_dataset(["earth"])
