"""Degenerate and extreme tops found by fuzzing the exact solution (regressions).

Each state once broke the root finder or the float evaluation: a non-spinning
pendulum (b = a = 0: x = 0 and x = 2 are both roots), tops 1e-200 rad from the
vertical, beta of 1e-174, free tops whose two turning points coincide to 1e-60,
a top hanging within 1e-16 rad of the bottom. They must give a finite, unit
quaternion, conserve E and p_phi, agree with the quaternion integration where
that is affordable, and refuse only what float64 cannot represent.
"""

from __future__ import annotations

import numpy as np
import pytest
from reference_odes import attitude_angle as angle

from wobble.errors import InputError
from wobble.models.top import heavy_top
from wobble.models.top_ode import integrate_top

CASES = {
    "pendulum released at rest (b = a = 0)": (1.0, 0.5, 1.0, 0.7, 0.0, 0.0, 0.0),
    "pendulum over the top (through both poles)": (1.0, 0.5, 1.0, 0.0, 3.0, 0.0, 0.0),
    "1e-129 rad from the vertical, kicked": (
        1.2850847296619075,
        2.570169459323815,
        1.3421870589272098,
        1.526628395667065e-129,
        1.4262213918742717,
        -0.0014225430536045636,
        2.625651008473973,
    ),
    "1e-202 rad, stable spin, at rest": (
        1.7598120598066005,
        3.519624119613201,
        1.8570975657557427,
        2.2668076975108654e-202,
        4.0781588274140786e-268,
        0.0,
        5.522021220858619,
    ),
    "beta 1e-173, nearly regular": (
        0.3362377248724901,
        0.6724754497449802,
        4.334619090657065e-174,
        1.976127142769412,
        0.0,
        -1.1194508951951661e-79,
        29.766500895369433,
    ),
    "free top, double root to 1e-60": (
        2.077592291776867,
        2.028804697451651,
        0.0,
        0.6211569051511763,
        0.0,
        -9.287056233989217e-64,
        -15.713577916202082,
    ),
    "hanging within 1e-16 rad of the bottom": (1.0, 0.5, 1.0, np.nextafter(np.pi, 0.0), -0.2, 0.0, 3.0),
    "hanging at the bottom (pi), spinning": (1.0, 0.5, 1.0, np.pi, -0.2, 0.0, 3.0),
    "free, no spin, at the bottom": (
        1.650704371191778,
        3.301408742383556,
        3.188565765155668e-25,
        np.pi,
        0.0,
        0.30521485278958504,
        -3.007787721976763e-55,
    ),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_extreme_state_is_finite_and_conservative(name):
    I1, I3, mgl, th, thd, phd, w3 = CASES[name]
    mdl = heavy_top(I1, I3, mgl, th, thd, phd, omega3=w3)
    t = np.array([0.0, 0.37, 1.3, 7.0, 77.0])
    mo = mdl.motion(t)
    assert np.all(np.isfinite(mo.quaternion)) and np.all(np.isfinite(mo.omega))
    np.testing.assert_allclose(np.linalg.norm(mo.quaternion, axis=-1), 1.0, rtol=1e-14)
    inv = mdl.invariants(mo)
    kin = 0.5 * I1 * (thd**2 + (phd * np.sin(th)) ** 2) + 0.5 * I3 * w3**2
    assert np.max(np.abs(inv["energy"] - mdl.energy)) <= 1e-12 * (kin + mgl + abs(mdl.energy))
    assert mdl.u1 <= mdl.u2 <= 1.0 <= mdl.u3
    assert mdl.theta_min <= th * (1 + 1e-15) + 1e-300 and th <= mdl.theta_max * (1 + 1e-15)


@pytest.mark.parametrize(
    "name",
    [
        "pendulum released at rest (b = a = 0)",
        "pendulum over the top (through both poles)",
        "hanging within 1e-16 rad of the bottom",
        "hanging at the bottom (pi), spinning",
        "beta 1e-173, nearly regular",
        "free top, double root to 1e-60",
    ],
)
def test_extreme_state_agrees_with_the_quaternion_integration(name):
    I1, I3, mgl, th, thd, phd, w3 = CASES[name]
    mdl = heavy_top(I1, I3, mgl, th, thd, phd, omega3=w3)
    t = np.linspace(0.0, 6.0, 31)
    w, q = mdl.evaluate(t)
    wn, qn = integrate_top(I1, I3, mgl, w[0], q[0], t, rtol=1e-12)
    assert np.max(angle(q, qn)) < 1e-9
    assert np.max(np.abs(w - wn)) < 1e-9 * max(1.0, np.max(np.abs(w)))


def test_pendulum_roots_are_exact():
    """b = a = 0: f(u) = (1 - u^2)(alpha - beta u), roots -1, u0 (released at rest) and +1."""
    mdl = heavy_top(1.0, 0.5, 1.0, 0.7, 0.0, 0.0, omega3=0.0)
    assert (mdl.u1, mdl.u2, mdl.u3) == (-1.0, pytest.approx(np.cos(0.7), rel=1e-15), 1.0)
    assert mdl.nutation == "cusps"


def test_a_state_beyond_float64_next_to_the_separatrix_is_refused():
    """An unstable sleeping top nudged by 1e-200 rad/s: 1 - m ~ 1e-400, refused with the reason."""
    with pytest.raises(InputError, match="separatrix") as err:
        heavy_top(1.0, 0.5, 1.0, 0.0, 1e-200, 0.0, omega3=1.0)
    # The whole initial state sets 1 - m (here the nudge; a tilt of 1e-100 rad does it too).
    assert err.value.parameter == "theta0, thetadot0, phidot0, omega3"


def test_pi_is_the_bottom_itself():
    """theta0 = numpy.pi (what 180 deg converts to) hangs straight down: an equilibrium spinning
    about the vertical, not cusps 1.2e-16 rad wide about it (float pi is short of pi)."""
    w3 = 10.0
    mdl = heavy_top(1.0, 0.5, 1.0, np.pi, 0.0, 0.0, omega3=w3)
    assert mdl.nutation == "regular" and mdl.theta_min == mdl.theta_max == np.pi
    assert (mdl.u1, mdl.u2, mdl.mean_precession_rate) == (-1.0, -1.0, 0.0)
    t = np.linspace(0.0, 5.0, 11)
    mo = mdl.motion(t)
    assert np.all(mo.theta == np.pi)
    # Axis 3 points down and the body turns about it at +omega3, i.e. about -z in space: a half-turn
    # about x, then R_z(-omega3 t): q = (cos(a/2), 0, 0, -sin(a/2)) (0, 1, 0, 0) = (0, cos(a/2), -sin(a/2), 0).
    expected = np.stack([np.zeros_like(t), np.cos(w3 * t / 2), -np.sin(w3 * t / 2), np.zeros_like(t)], axis=-1)
    assert np.max(angle(mo.quaternion, expected)) < 1e-14


def test_a_right_angle_is_horizontal_itself():
    """theta0 = the float nearest pi/2 (what 90 deg converts to) is a horizontal axis: cos theta0 = 0,
    so p_phi = I1 phidot0 sin^2 theta0 + p_psi cos theta0 = 0 at rest, E' = E - I3 omega3^2 / 2 = Mgl u0
    = 0, the turning point u0 = 0 is a root, and steady precession has one finite rate, Mgl / (I3 omega3)
    (notes p. 72: the fast root I3 omega3 / (I1 cos theta) has gone to infinity)."""
    I1, I3, mgl, w3 = 1.0, 0.5, 1.0, 10.0
    mdl = heavy_top(I1, I3, mgl, np.pi / 2, 0.0, 0.0, omega3=w3)
    assert mdl.u2 == 0.0 and mdl.energy_prime == 0.0 and mdl.p_phi == 0.0
    slow, fast = mdl.regular_precession_rates()
    assert slow == pytest.approx(mgl / (I3 * w3), rel=1e-15) and fast == np.inf
    # The neighbouring double is read as it is: its cosine, 1.6e-16, is not rounded away.
    below = heavy_top(I1, I3, mgl, np.nextafter(np.pi / 2, 0.0), 0.0, 0.0, omega3=w3)
    assert below.u2 == pytest.approx(np.cos(np.nextafter(np.pi / 2, 0.0)), rel=1e-12) and below.u2 > 0
    assert np.isfinite(below.regular_precession_rates()[1])


@pytest.mark.parametrize("samples", [5, 20000])  # NumPy, and the compiled series from 8192 samples on
def test_the_recomputed_energy_of_a_top_at_the_edge_of_the_float_range_stays_finite(samples):
    """I1 = I3 = 5e-324 kg m2 spun at 1e157 rad/s: w^2 overflowed in the energy the Dataset recomputes
    (fuzz seed 271: NumPy's overflow warning on stderr); (I w) w does not. Subnormal moments are refused now:
    the smallest normal ones, 2.3e-308 kg m2, under M g l = 1e10 J reach 6.6e158 rad/s, and w^2 overflows the same."""
    with pytest.raises(InputError, match="I1: got 5e-324; allowed: a moment of at least 2.225e-308 kg m2"):
        heavy_top(5e-324, 5e-324, 1e-9, np.radians(153.2), omega3=0.0)
    model = heavy_top(2.3e-308, 2.3e-308, 1e10, np.radians(153.2), omega3=0.0)
    mo = model.motion(np.linspace(0.0, 10 * model.nutation_period, samples))
    assert np.all(np.isfinite(mo.energy))
    np.testing.assert_allclose(mo.energy, model.energy, rtol=1e-12)


@pytest.mark.parametrize("samples", [1001, 20000])  # the NumPy series pass, and the compiled one from 8192 samples on
def test_the_recomputed_energy_of_a_top_near_the_largest_double_stays_finite(samples):
    """M g l = 1.7e308 J (energy 9.4e307 J): the kinetic part of the recomputed energy passes the largest
    double while the sum does not, and the sum overflowed (fuzz seed 307: NumPy's overflow warning). It is
    now summed in units of a power of two (top_series.energy_terms), in both passes alike; the ground
    truth is the conserved energy itself."""
    from wobble.models.top_series import energy_terms

    model = heavy_top(28.5939, 1e-12, 1.7e308, np.radians(56.47), omega3=-3.508e-184)
    assert energy_terms(1.0, 0.5, 1.0, 25.5) == (1.0, 0.5, 1.0, 1.0)  # an ordinary top: the sum as written
    mo = model.motion(np.linspace(0.0, 10 * model.nutation_period, samples))
    assert np.all(np.isfinite(mo.energy))
    np.testing.assert_allclose(mo.energy, model.energy, rtol=1e-13)
