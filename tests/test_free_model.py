"""Exact torque-free motion against mpmath (tests/references/free_rotation.json) and invariants."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from wobble.errors import InputError
from wobble.models.free import free_rotation, symmetric_from_energy
from wobble.numerics import quaternion as Q

REF = json.loads((Path(__file__).parent / "references" / "free_rotation.json").read_text())
ODE = {c["name"]: c for c in REF["ode"]}
CLOSED = {c["name"]: c for c in REF["closed"]}
VERY_LONG = json.loads((Path(__file__).parent / "references" / "free_rotation_very_long.json").read_text())["closed"]


def _case(c):
    I = [float(x) for x in c["moments"]]
    w = [float(x) for x in c["omega0"]]
    return free_rotation(I, w)


def _omega_error(c, model, key="t", values="omega"):
    """Max over times of |omega - ref| / |omega_ref|, and per component relative to its amplitude."""
    t = np.array([float(x) for x in c[key]])
    want = np.array([[float(v) for v in row] for row in c[values]])
    got = model.omega(t)
    norm = np.max(np.linalg.norm(want - got, axis=1) / np.linalg.norm(want, axis=1))
    amp = np.maximum(np.max(np.abs(want), axis=0), 1e-300)
    comp = np.max(np.abs(want - got) / amp)
    return norm, comp


def _attitude_error(model, c, key, values):
    t = np.array([float(x) for x in c[key]])
    want = np.array([[float(v) for v in row] for row in c[values]])
    got = model.attitude(t)
    # Angle of the rotation got * want^-1 (rad); sign of the quaternion immaterial.
    d = Q.multiply(got, Q.conjugate(want))
    return np.max(2 * np.arctan2(np.linalg.norm(d[:, 1:], axis=1), np.abs(d[:, 0])))


@pytest.mark.parametrize("name", sorted(ODE))
def test_against_mpmath_taylor_integration(name):
    """omega and attitude against an mpmath ODE integration (no elliptic functions in it)."""
    c = ODE[name]
    model = _case(c)
    norm, comp = _omega_error(c, model)
    assert norm < 1e-13 and comp < 1e-12, (norm, comp)
    assert _attitude_error(model, c, "t", "attitude") < 1e-13


def test_generic_case_relative_error():
    c = CLOSED["generic 1000 s"]
    model = _case(c)
    norm, comp = _omega_error(c, model)
    assert norm < 1e-13 and comp < 1e-13
    assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-12
    assert abs(model.period / float(c["period"]) - 1) < 1e-15
    flips = model.flip_times(0.0, 1000.0)
    want = np.array([float(x) for x in c["flip_times"]])
    assert flips.shape == want.shape and np.max(np.abs(flips - want)) < 1e-12


@pytest.mark.parametrize("name", ["separatrix 2e-12", "separatrix 5e-13", "separatrix minor side"])
def test_next_to_the_separatrix(name):
    """1 - m = 2e-12, 5e-13, 6e-12: omega to 1e-9 (we reach ~1e-13), flip times to 1e-9 s."""
    c = CLOSED[name]
    model = _case(c)
    assert abs(model.m1 / float(c["m1"]) - 1) < 1e-15
    norm, comp = _omega_error(c, model)
    assert norm < 1e-12 and comp < 1e-12, (norm, comp)
    assert norm < model.error_estimate["omega_relative"]
    flips = model.flip_times(0.0, 200.0)
    want = np.array([float(x) for x in c["flip_times"]])
    assert flips.shape == want.shape and np.max(np.abs(flips - want)) < 1e-12
    assert abs(model.time_between_flips / float(c["time_between_flips"]) - 1) < 1e-15
    if c["attitude"]:
        assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-12


def test_long_span_phase_bound():
    """10^6 periods of the generic body: no loss with t (double-double phase)."""
    c = CLOSED["generic 1e6 periods"]
    model = _case(c)
    norm, comp = _omega_error(c, model)
    assert norm < 1e-13 and comp < 1e-13
    assert norm < model.error_estimate["omega_relative"]
    assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-12


@pytest.mark.parametrize("c", VERY_LONG, ids=[c["name"] for c in VERY_LONG])
def test_up_to_two_to_the_fifty_half_periods(c):
    """From just past 2^26 to 1.9 x 2^48 periods of omega (2^49.9 half-periods, the whole steps of the
    phase reduction), against mpmath at 60 digits (``build_free_references.py --very-long``, checked
    at 80): omega and the attitude within their stated bounds. Until 2026-11-29 the set-up formed the
    precession rate in decimal's default 28 digits: 1.5e-12 rad at the last time, 40 times the bound."""
    model = _case(c)
    t = np.array([float(x) for x in c["t"]])
    inside = t <= model.max_time  # near the separatrix the precession's turns limit first: the last time is out
    assert np.sum(inside) >= 4
    c = {**c, "t": c["t"][: np.sum(inside)], "omega": c["omega"][: np.sum(inside)]}
    c.update(attitude_t=c["t"], attitude=c["attitude"][: np.sum(inside)])
    norm, _ = _omega_error(c, model)
    assert norm < model.error_estimate["omega_relative"]
    err = _attitude_error(model, c, "attitude_t", "attitude")
    assert err < model.error_estimate["attitude_rad"] and err < 1e-14
    if not inside.all():
        with pytest.raises(InputError, match="2\\^50 turns of its fastest phase"):
            model.attitude(t)


def test_the_set_up_does_not_depend_on_the_caller_s_decimal_context():
    """A script that has set decimal's precision (here 6 digits) gets the same motion: the set-up's
    Decimal arithmetic runs in wobble's own 50-digit context. It ran in the caller's: 6 digits gave
    attitudes 1.5 rad off at 1.7 s, and decimal's default 28 digits the error of the test above."""
    import decimal

    c = VERY_LONG[0]
    with decimal.localcontext(decimal.Context(prec=6)):
        model = _case(c)
    assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-14
    for args in (((2.0, 2.0, 3.0), (0.3, 0.1, 1.0)), ((1.0, 2.0, 3.0), (0.0, 0.0, 0.1))):  # symmetric, steady
        with decimal.localcontext(decimal.Context(prec=6)):
            low = free_rotation(*args)
        ref = free_rotation(*args)
        t = np.array([1.7, 1e9, 1e15])
        np.testing.assert_array_equal(low.attitude(t), ref.attitude(t))
        np.testing.assert_array_equal(low.omega(t), ref.omega(t))


def test_times_beyond_the_reach_of_the_phase_reductions_are_refused():
    """2^50 whole reductions of the fastest phase (a half-period of omega here): past them the phases
    lose their digits. Until 2026-11-29 any time ran: 1e300 s gave an attitude with no meaning."""
    model = _case(VERY_LONG[0])
    half = model.time_between_flips
    assert model.limiting_period == half and model.max_time == (2.0**50 - 1) * half
    model.attitude(np.array([-model.max_time, model.max_time]))  # the limit itself runs
    for call in (model.omega, model.attitude, model.state):
        with pytest.raises(InputError, match=r"^t: got 1e\+300 s; allowed: \|t\| up to 3\.90102e\+15 s, 2\^50 turns"):
            call(np.array([0.0, 1e300]))
    with pytest.raises(InputError, match=r"^t: got 1e\+17 s"):
        model.flip_times(-1e17, 0.0)
    # a steady spin: 2^50 turns of its half angle |omega| t / 2; a body at rest: no limit
    assert free_rotation([1.0, 2.0, 3.0], [0.0, 0.0, 0.1]).max_time == (2.0**50 - 1) * 4 * np.pi / 0.1
    assert np.isinf(free_rotation([1.0, 2.0, 3.0], [0.0, 0.0, 0.0]).max_time)
    assert np.isnan(model.omega(np.array([np.nan]))).all()  # NaN passes through, as before
    # Earth's near-circular wobble on a long uniform grid takes the compiled nome series, which checks the
    # grid's two ends only
    earth = free_rotation((8.01012e37, 8.01032e37, 8.03652e37), (7.292115e-11, 0.0, 7.292115e-05))
    with pytest.raises(InputError, match=r"^t: got 3\.6525e\+20 s; allowed: \|t\| up to 1\.94024e\+20 s"):
        earth.omega(np.arange(36526) * 1e16)


def test_earth_100_years_daily():
    """Earth-like wobble (IERS A, B, C), 100 years: wobble phase error below 1e-12 rad."""
    c = CLOSED["Earth 100 years"]
    model = _case(c)
    t = np.array([float(x) for x in c["t"]])
    want = np.array([[float(v) for v in row] for row in c["omega"]])
    got = model.omega(t)
    amp = np.hypot(want[:, 0], want[:, 1])
    # Wobble phase error = distance of the equatorial components over their amplitude.
    phase = np.max(np.hypot(got[:, 0] - want[:, 0], got[:, 1] - want[:, 1]) / amp)
    assert phase < 1e-12
    assert np.max(np.abs(got[:, 2] / want[:, 2] - 1)) < 1e-15
    assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-12
    days = model.omega(np.arange(36526) * 86400.0)
    assert days.shape == (36526, 3) and days.flags.c_contiguous


def test_earth_daily_grid_takes_the_nome_series_path_and_matches_mpmath():
    """The uniform-grid path (DLMF 22.11 nome series, block rotation) at mpmath's days: 1e-15."""
    c = CLOSED["Earth 100 years"]
    model = _case(c)
    assert model._impl.fourier is not None  # m ~ 8e-15: the near-circular path applies
    days = model.omega(np.arange(36526) * 86400.0)
    idx = [round(float(x) / 86400.0) for x in c["t"]]
    want = np.array([[float(v) for v in row] for row in c["omega"]])
    got = days[idx]
    phase = np.max(np.hypot(got[:, 0] - want[:, 0], got[:, 1] - want[:, 1]) / np.hypot(want[:, 0], want[:, 1]))
    assert phase < 1e-15
    assert np.max(np.abs(got[:, 2] / want[:, 2] - 1)) < 1e-15


@pytest.mark.parametrize("n", [10_001, 4001])  # compiled (>= compiled.LONG_ARRAY samples), NumPy's
@pytest.mark.parametrize(
    "moments, omega0",
    [
        ((1.0, 1.0 + 1e-9, 1.5), (0.1, 0.05, 1.0)),  # m ~ 1e-9: nome series with its 3v harmonic
        ((1.0, 1.0, 1.5), (0.1, 0.05, 1.0)),  # symmetric: exp(i (Omega t + beta)) by block rotation
        ((1.5, 1.0, 1.0 + 1e-9), (1.0, 0.05, 0.1)),  # the same body with its axes permuted
    ],
)
def test_grid_path_equals_the_per_sample_path(moments, omega0, n):
    """Every sample of a grid (over ~300 wobble periods) against omega_at sample by sample."""
    from wobble.models.free import _blocked
    from wobble.models.principal_axes import to_user

    from wobble.numerics import compiled

    if n >= compiled.LONG_ARRAY and compiled.available():
        import numba  # noqa: F401  (the compiled grid runs only where Numba is loaded already)
    model = free_rotation(moments, omega0)
    # Exactly representable times (k/4 s): both paths see the same instants, so they agree to rounding.
    t = np.arange(n) * 0.25
    direct = to_user(_blocked(model._impl.omega_at, t, 3), model._order, model._signs)
    scale = np.max(np.abs(direct))
    assert np.max(np.abs(model.omega(t) - direct)) <= 1e-15 * scale
    # A linspace grid: its float samples are the exact grid rounded (half an ulp), and the grid path
    # evaluates the exact grid: the two differ by at most rate * amplitude * a few ulps of t.
    t = np.linspace(0.0, (n - 1) / 5, n)
    direct = to_user(_blocked(model._impl.omega_at, t, 3), model._order, model._signs)
    fig = int(np.argmax(moments))  # the figure axis; the wobble is in the other two components
    amp = np.max(np.linalg.norm(np.delete(direct, fig, axis=1), axis=1))
    rate = 0.5 * omega0[fig]  # (I3 - I1)/I1 omega3 for these moments
    bound = 1e-15 * scale + amp * rate * 4 * np.finfo(float).eps * t[-1]
    assert np.max(np.abs(model.omega(t) - direct)) <= bound


@pytest.mark.parametrize("n", [10, 8192, 8193, 20_001])  # one block, at and across its end (8192)
@pytest.mark.parametrize(
    "moments, omega0",
    [
        ((1.0, 2.0, 3.0), (1.0, 0.1, 1.0)),  # generic: the shared evaluation
        ((2.0, 3.0, 1.0), (0.1, 1.0, 1.0)),  # the same body relabelled: the shared one in the user's order
        ((3.0, 4.0, 6.0), (1.0, 0.31, 0.5)),  # next to the separatrix
        ((1.0, 1.0 + 1e-9, 1.5), (0.1, 0.05, 1.0)),  # a nome series: omega takes its own path
        ((1.0, 1.0, 1.5), (0.1, 0.05, 1.0)),  # symmetric: closed forms
    ],
)
def test_state_is_omega_and_attitude_bit_for_bit(moments, omega0, n):
    """FreeRotationModel.state(t) (what FreeRotation.to_dataset uses) gives omega(t) and attitude(t)
    to the bit, whichever path omega takes and where the blocks end."""
    model = free_rotation(moments, omega0)
    t = np.linspace(0.0, 300.0, n)
    omega, q = model.state(t)
    np.testing.assert_array_equal(omega, model.omega(t))
    np.testing.assert_array_equal(q, model.attitude(t))


def test_nearly_symmetric_reduces_to_symmetric_closed_form():
    """(I2 - I1)/I1 = 1e-12: matches mpmath, and the symmetric closed form within O(1e-12)."""
    c = CLOSED["nearly symmetric 1e-12"]
    model = _case(c)
    norm, comp = _omega_error(c, model)
    assert norm < 1e-13 and comp < 1e-13
    assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-12
    assert model.m < 1e-11
    sym = free_rotation([1.0, 1.0, 1.5], [float(x) for x in c["omega0"]])
    t = np.linspace(0, 10, 11)
    np.testing.assert_allclose(model.omega(t), sym.omega(t), atol=1e-11)
    assert sym.regime == "symmetric"


@pytest.mark.parametrize("omega0", [(0.6, 0.8, 0.0), (0.3, 0.4, 0.0)])
def test_a_start_in_the_equator_of_a_nearly_symmetric_body_turns_about_omega(omega0):
    """I = (2, 2 + k 2^-51, 3), omega3 = 0: the phase starts at the rounded K, where cn came out -3.5e-17 for
    about one k in five and the attitude was off by up to 2e-9 rad (its estimate: 4e-14). The symmetric body
    with omega3 = 0 turns about the fixed omega0 (Euler: omega constant); the asymmetry moves the attitude
    by |omega3| t / 2 with omega3 = (I1 - I2)/I3 omega1 omega2 t, below 2e-15 rad at t = 3 s."""
    w0 = np.array(omega0)
    spin = np.linalg.norm(w0)
    t = np.array([0.5, 1.0, 3.0])
    exact = np.concatenate([np.cos(spin * t / 2)[:, None], np.sin(spin * t / 2)[:, None] * w0 / spin], axis=1)
    for k in range(1, 41):
        model = free_rotation(np.array([2.0, 2.0 + k * 2.0**-51, 3.0]), w0)
        _, q = model.state(t)
        err = 2 * np.arcsin(np.minimum(1.0, np.linalg.norm(Q.multiply(Q.conjugate(exact), q)[:, 1:], axis=1)))
        assert err.max() <= model.error_estimate["attitude_rad"], (k, err.max())


def test_minor_axis_permuted():
    c = CLOSED["minor-axis permuted"]
    model = _case(c)
    assert model.regime == "minor-axis"
    norm, comp = _omega_error(c, model)
    assert norm < 1e-13 and comp < 1e-13
    assert _attitude_error(model, c, "attitude_t", "attitude") < 1e-12


def test_symmetric_closed_form_of_the_notes():
    """Notes 5.6: omega1 = A cos(Omega t), omega2 = A sin(Omega t), Omega = (I3 - I1) omega3 / I1."""
    I1, I3, A, w3 = 2.0, 3.0, 0.25, 1.5
    model = free_rotation([I1, I1, I3], [A, 0.0, w3])
    t = np.linspace(0, 100, 201)
    Om = (I3 - I1) / I1 * w3
    want = np.stack([A * np.cos(Om * t), A * np.sin(Om * t), np.full_like(t, w3)], -1)
    np.testing.assert_allclose(model.omega(t), want, atol=1e-15 * 100)
    # A and omega3 back from T and L^2 (notes p. 69).
    L2 = (I1 * A) ** 2 + (I3 * w3) ** 2
    a_back, w_back = symmetric_from_energy(I1, I3, model.energy, L2)
    assert abs(a_back - A) < 1e-15 and abs(w_back - w3) < 1e-15
    # Body cone on space cone: the figure axis precesses about L at L/I1.
    q = model.attitude(t)
    axis = Q.rotate(q, [0.0, 0.0, 1.0])
    L = model.angular_momentum_inertial / model.angular_momentum
    np.testing.assert_allclose(axis @ L, I3 * w3 / model.angular_momentum, atol=1e-14)
    assert model.precession_rate == pytest.approx(model.angular_momentum / I1, rel=1e-15)


def test_sphere_principal_axis_and_zero():
    for I, w in [
        ((2.0, 2.0, 2.0), (0.3, -1.0, 0.2)),
        ((1.0, 2.0, 3.0), (0.0, 0.0, 2.0)),
        ((1.0, 2.0, 3.0), (0.0, 1.0, 0.0)),
        ((1.0, 2.0, 3.0), (0.0, 0.0, 0.0)),
    ]:
        model = free_rotation(I, w)
        assert model.regime == "steady"
        t = np.linspace(0, 50, 11)
        assert np.all(model.omega(t) == np.asarray(w))
        q = model.attitude(t)
        n = np.linalg.norm(w)
        if n:
            want = Q.from_axis_angle(np.asarray(w) / n, n * t)
            np.testing.assert_allclose(q, want, atol=1e-14)
        else:
            assert np.all(q == [1.0, 0.0, 0.0, 0.0])


def test_exactly_on_the_separatrix():
    """L^2 = 2 E I2 exactly: I = (3, 4, 6), omega = (1, 0.3, 0.5): D2 = 3 (1) + 6 (0.25)(-2) = 0."""
    model = free_rotation([3.0, 4.0, 6.0], [1.0, 0.3, 0.5])
    assert model.regime == "separatrix" and model.m == 1.0 and model.m1 == 0.0
    assert model.period == np.inf
    t = np.linspace(0, 60, 13)
    w = model.omega(t)
    I = np.array([3.0, 4.0, 6.0])
    np.testing.assert_allclose(0.5 * np.sum(I * w * w, -1), model.energy, rtol=1e-15)
    # Approaches steady rotation about the intermediate axis.
    assert abs(abs(w[-1, 1]) - model.angular_momentum / 4.0) < 1e-12
    assert model.flip_times(-1e3, 1e3).size == 1


moment = st.floats(0.5, 5.0)
rate = st.floats(-2.0, 2.0)


@settings(max_examples=60)
@given(moment, moment, moment, rate, rate, rate, st.permutations([0, 1, 2]))
def test_invariants_and_relabelling(i1, i2, i3, w1, w2, w3, perm):
    I = np.array([i1, i2, i3])
    if sorted(I)[0] + sorted(I)[1] < sorted(I)[2]:
        return
    w = np.array([w1, w2, w3])
    try:
        model = free_rotation(I, w)
    except InputError as exc:
        # The documented refusals of rates too slow for doubles (subnormal rates drawn here): a kinetic
        # energy below the normal doubles, or a period past the largest (tests/test_free_extremes.py).
        assume(exc.parameter == "omega0" and ("smallest normal double" in str(exc) or "period of omega" in str(exc)))
        raise
    t = np.linspace(0.0, 37.0, 41)
    om = model.omega(t)
    q = model.attitude(t)
    scale = max(np.linalg.norm(w), 1e-300)
    # Conservation of T and |L| along the exact solution.
    T = 0.5 * np.sum(I * om * om, -1)
    Lm = np.linalg.norm(I * om, axis=-1)
    assert np.max(np.abs(T - model.energy)) <= 1e-13 * max(model.energy, 1e-300) + 1e-300
    assert np.max(np.abs(Lm - model.angular_momentum)) <= 1e-13 * max(model.angular_momentum, 1e-300) + 1e-300
    # Unit quaternions, identity at t = 0.
    assert np.max(np.abs(np.linalg.norm(q, axis=-1) - 1)) < 1e-14
    np.testing.assert_allclose(q[0], [1, 0, 0, 0], atol=1e-14)
    # Attitude consistency: q (I omega) q* is the constant inertial L.
    L_in = Q.rotate(q, I * om)
    assert np.max(np.abs(L_in - I * w)) <= 1e-12 * max(model.angular_momentum, 1e-300)
    # Relabelling the axes: a cyclic relabelling permutes omega and the
    # quaternion's vector part; a swap of two axes is a mirror image
    # (P(a x b) = -Pa x Pb), whose motion runs backwards in time:
    # omega~(t) = P omega(-t), q~(t) = (w(-t), -P v(-t)).
    p = list(perm)
    odd = np.linalg.det(np.eye(3)[p]) < 0
    other = free_rotation(I[p], w[p])
    ref_om = model.omega(-t) if odd else om
    ref_q = model.attitude(-t) if odd else q
    np.testing.assert_allclose(other.omega(t), ref_om[:, p], atol=1e-12 * scale)
    q2 = other.attitude(t)
    np.testing.assert_allclose(q2[:, 0], ref_q[:, 0], atol=1e-11)
    np.testing.assert_allclose(q2[:, 1:], (-1.0 if odd else 1.0) * ref_q[:, 1:][:, p], atol=1e-11)


@pytest.mark.parametrize(
    "I, w, msg",
    [
        ((1.0, 2.0, 4.0), (1.0, 0.0, 0.0), "triangle"),
        ((1.0, -2.0, 3.0), (1.0, 0.0, 0.0), "positive"),
        ((1.0, np.nan, 3.0), (1.0, 0.0, 0.0), "finite"),
        ((1.0, 2.0, 3.0), (1.0, np.inf, 0.0), "finite"),
        ((1.0, 2.0), (1.0, 0.0, 0.0), "three"),
    ],
)
def test_bad_input(I, w, msg):
    with pytest.raises(InputError, match=msg):
        free_rotation(I, w)


@pytest.mark.parametrize("omega0", [(1.0, 0.1, 1.0), (1.0, 0.3, 0.2), (0.2, 0.1, 1.0)])
def test_precession_rate_is_the_mean_of_landau_lifshitz_phidot(omega0):
    """Mean over a period of phidot = L (I_a w_a^2 + I_b w_b^2)/(I_a^2 w_a^2 + I_b^2 w_b^2) (L&L sec. 37),
    with a, b the two axes other than the circulation axis, by Gauss-Legendre quadrature of the exact omega."""
    moments = np.array([1.0, 2.0, 3.0])
    model = free_rotation(moments, omega0)
    c = 2 if model.regime == "major-axis" else 0  # the axis omega circulates about
    a, b = [k for k in range(3) if k != c]
    x, w = np.polynomial.legendre.leggauss(200)
    t = 0.5 * model.period * (x + 1.0)
    om = model.omega(t)
    num = moments[a] * om[:, a] ** 2 + moments[b] * om[:, b] ** 2
    den = moments[a] ** 2 * om[:, a] ** 2 + moments[b] ** 2 * om[:, b] ** 2
    mean = 0.5 * np.sum(w * model.angular_momentum * num / den)
    assert model.precession_rate == pytest.approx(mean, rel=1e-12)


def test_precession_rate_is_continuous_in_the_symmetric_limit():
    for moments in ((1.0, 1.0 + 1e-9, 1.5), (1.0, 1.5, 1.5 + 1e-9)):
        near = free_rotation(moments, (0.1, 0.05, 1.0))
        exact = free_rotation(np.round(moments, 6), (0.1, 0.05, 1.0))
        assert exact.regime == "symmetric"
        assert near.precession_rate == pytest.approx(exact.precession_rate, rel=1e-8)
