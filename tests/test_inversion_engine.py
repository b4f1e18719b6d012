"""The inversion engine (models layer): priors, forward registry, posterior, sampler, calibration.

Ground truth: closed forms (the linear-Gaussian posterior, the priors' normalisation,
IERS Conventions 2010 eq. 6.12), SciPy's independent implementation of the truncated
normal, and statistical tolerances from the binomial and Monte-Carlo standard errors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, stats

from wobble.errors import InputError
from wobble.io.catalog import load_planet
from wobble.models.inversion.calibration import coverage, recover_one
from wobble.models.inversion.likelihood import Measurement, Parameter, Posterior
from wobble.models.inversion.observables import REGISTRY, Batch, ObservableModel, register_observable
from wobble.models.inversion.priors import LogUniform, Normal, Uniform
from wobble.models.inversion.sampling import SamplerSettings, draw_prior, run_emcee

# ---------------------------------------------------------------------------
# Priors
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "prior",
    [
        Uniform(-1.0, 3.0),
        LogUniform(1e-3, 10.0),
        Normal(0.2, 0.1, 0.0, 1.0),
        Normal(5.0, 2.0),
        Normal(-3.0, 1.0, 0.0, 2.0),
    ],
    ids=["uniform", "log_uniform", "normal_truncated", "normal", "normal_far_tail"],
)
def test_priors_are_normalised_and_their_ppf_inverts_the_cdf(prior):
    lo = prior.low if math.isfinite(prior.low) else -60.0
    hi = prior.high if math.isfinite(prior.high) else 60.0
    mass, _ = integrate.quad(lambda x: math.exp(prior.logpdf(x)), lo, hi, points=[prior.median], limit=200)
    assert mass == pytest.approx(1.0, abs=1e-9)
    for q in (0.025, 0.16, 0.5, 0.84, 0.975):
        x = float(prior.ppf(q))
        cdf, _ = integrate.quad(lambda t: math.exp(prior.logpdf(t)), lo, x, limit=200)
        assert cdf == pytest.approx(q, abs=1e-8)
    if math.isfinite(prior.high):
        assert np.isneginf(prior.logpdf(prior.high + 1.0))
    if math.isfinite(prior.low):
        assert np.isneginf(prior.logpdf(prior.low - 1.0))


def test_truncated_normal_matches_scipy():
    prior = Normal(0.2, 0.1, 0.0, 1.0)
    ref = stats.truncnorm(-2.0, 8.0, loc=0.2, scale=0.1)
    x = np.linspace(0.001, 0.999, 50)
    np.testing.assert_allclose(prior.logpdf(x), ref.logpdf(x), rtol=1e-12)


@pytest.mark.parametrize(
    "prior, why",
    [
        (Uniform(2.0, 1.0), "low < high"),
        (Uniform(0.0, math.inf), "finite bounds"),
        (LogUniform(0.0, 1.0), "0 < low"),
        (Normal(1.0, -0.5), "positive standard deviation"),
        (Normal(1.0, 0.0), "positive standard deviation"),
        (Normal(50.0, 1.0, 0.0, 1.0), "probability inside"),
    ],
)
def test_improper_or_contradictory_priors_are_refused(prior, why):
    with pytest.raises(InputError, match="prior of x") as err:
        Parameter("x", prior)
    assert why in str(err.value)


def test_priors_outside_the_physical_range_are_refused():
    with pytest.raises(InputError, match="physical range"):
        Parameter("anelastic_exponent", Uniform(0.5, 1.5))
    with pytest.raises(InputError, match="physical range"):
        Parameter("fluid_core_radius", Uniform(-1.0, 2.0e6))


@settings(max_examples=40, deadline=None)
@given(st.floats(-5, 5), st.floats(0.01, 3), st.floats(0.0, 1.0))
def test_normal_ppf_stays_inside_its_truncation(mean, sd, q):
    prior = Normal(mean, sd, mean - sd, mean + 2 * sd)
    x = float(prior.ppf(q))
    assert prior.low <= x <= prior.high


# ---------------------------------------------------------------------------
# Forward models
# ---------------------------------------------------------------------------


def test_tidal_k2_is_the_reference_k2_at_the_reference_period_and_eq_6_12_elsewhere():
    mars, _ = load_planet("mars")
    k2 = np.array([0.15, 0.169, 0.19])
    batch = Batch(mars, {"love_number_k2": k2})
    same = REGISTRY["tidal_k2"](batch, {"tidal_period": mars.love_number_k2_period.value})
    np.testing.assert_allclose(same, k2, rtol=0, atol=1e-15)
    # IERS Conventions 2010 eq. 6.12 by hand at the Phobos tidal period.
    alpha = mars.anelastic_exponent.value
    f, f_ref = 1 / 19991.0, 1 / mars.love_number_k2_period.value
    f_im = 1 / mars.love_number_k2_imaginary_period.value
    im = mars.love_number_k2_imaginary.value
    expect = k2 + im / math.tan(alpha * math.pi / 2) * ((f_im / f) ** alpha - (f_im / f_ref) ** alpha)
    other = REGISTRY["tidal_k2"](batch, {"tidal_period": 19991.0})
    np.testing.assert_allclose(other, expect, rtol=1e-14)


def test_earth_k2_at_the_chandler_frequency_is_the_iers_pole_tide_value():
    """IERS Conventions 2010 sec. 6.4: k2 = 0.3077 + 0.0036 i at the Chandler frequency (eq. 6.12)."""
    earth, _ = load_planet("earth")
    value = REGISTRY["love_number_k2_chandler"](Batch(earth, {"anelastic_exponent": np.array([0.15])}))
    assert value[0] == pytest.approx(0.3077, abs=5e-4)


def test_registering_a_name_twice_is_an_error():
    with pytest.raises(InputError, match="not registered yet"):
        register_observable("chandler_period", unit="s", description="", references="")(lambda batch: batch)


# ---------------------------------------------------------------------------
# A linear-Gaussian problem: the posterior in closed form
# ---------------------------------------------------------------------------

A = np.array([[1.0, 2.0], [1.0, -1.0], [3.0, 0.0]])
SIGMA_Y = np.array([0.5, 0.3, 0.8])
MU0, SD0 = np.array([1.0, -0.5]), np.array([2.0, 1.5])
Y = np.array([2.1, 1.4, 2.6])


def _linear(row):
    return ObservableModel(
        f"y{row}", lambda batch: A[row, 0] * batch["a"] + A[row, 1] * batch["b"], "", "", "linear test", "closed form"
    )


def linear_posterior(y=Y, prior_only=False) -> Posterior:
    params = [Parameter("a", Normal(MU0[0], SD0[0])), Parameter("b", Normal(MU0[1], SD0[1]))]
    meas = [Measurement(f"y{i}", float(y[i]), float(SIGMA_Y[i]), forward=_linear(i)) for i in range(3)]
    return Posterior(params, meas, planet=None, prior_only=prior_only)


def closed_form(y=Y):
    """Gaussian prior x Gaussian linear likelihood: mean and covariance of the posterior."""
    prec = np.diag(1 / SD0**2) + A.T @ np.diag(1 / SIGMA_Y**2) @ A
    cov = np.linalg.inv(prec)
    mean = cov @ (MU0 / SD0**2 + A.T @ (y / SIGMA_Y**2))
    return mean, cov


def test_log_posterior_is_the_closed_form_up_to_a_constant():
    post = linear_posterior()
    mean, cov = closed_form()
    x = np.random.default_rng(0).normal(size=(20, 2)) + mean
    exact = stats.multivariate_normal(mean, cov).logpdf(x)
    diff = post(x) - exact
    np.testing.assert_allclose(diff, diff[0], rtol=0, atol=1e-10)


def test_emcee_recovers_the_linear_gaussian_posterior_within_sampling_error():
    post = linear_posterior()
    mean, cov = closed_form()
    chains = run_emcee(post, SamplerSettings(walkers=16, steps=1500, burn=300), seed=11)
    flat = chains.samples.reshape(-1, 2)
    ess = flat.shape[0] / np.max(chains.autocorr)
    sd = np.sqrt(np.diag(cov))
    # Monte-Carlo standard errors: of the mean sd/sqrt(ESS), of the sd sd/sqrt(2 ESS); 4 of them.
    for i in range(2):
        assert flat[:, i].mean() == pytest.approx(mean[i], abs=4 * sd[i] / math.sqrt(ess))
        assert flat[:, i].std() == pytest.approx(sd[i], rel=4 / math.sqrt(2 * ess))
    corr = np.corrcoef(flat.T)[0, 1]
    assert corr == pytest.approx(cov[0, 1] / (sd[0] * sd[1]), abs=4 * (1 - corr**2) / math.sqrt(ess))


def test_same_seed_same_numbers_other_seed_other_numbers():
    post = linear_posterior()
    s = SamplerSettings(walkers=8, steps=50, burn=10)
    one, two, other = (run_emcee(post, s, seed) for seed in (3, 3, 4))
    np.testing.assert_array_equal(one.samples, two.samples)
    assert not np.array_equal(one.samples, other.samples)
    np.testing.assert_array_equal(draw_prior(post, 10, 5), draw_prior(post, 10, 5))


def test_prior_only_posterior_is_the_prior():
    post = linear_posterior(prior_only=True)
    x = np.array([[0.3, 0.2], [5.0, -4.0]])
    np.testing.assert_allclose(post(x), post.log_prior(x))


def test_injection_recovery_covers_at_the_nominal_rate_on_the_linear_problem():
    """Simulation-based calibration in small: 40 truths from the prior, each inverted.

    Per parameter the number of 68 % intervals holding the truth is Binomial(40, 0.68)
    for a calibrated inversion (sd 2.95 draws); 3.5 sd either side is the band. 150 steps after 50 of
    burn-in: the hits were 25/38 and 24/39 (68 %/95 %, per parameter), against 26/38 and 24/39 with 300
    after 100, at half the time.
    """
    post = linear_posterior()
    s = SamplerSettings(walkers=8, steps=150, burn=50)
    recoveries = [recover_one(post, s, seed=2024, index=i) for i in range(40)]
    cov = coverage(recoveries, post.names)
    for name in post.names:
        hits = cov[name]["68"] * 40
        assert abs(hits - 0.68 * 40) <= 3.5 * math.sqrt(40 * 0.68 * 0.32), (name, cov[name])
        assert cov[name]["95"] * 40 >= 40 * 0.95 - 3.5 * math.sqrt(40 * 0.95 * 0.05)


# ---------------------------------------------------------------------------
# Bad measurements
# ---------------------------------------------------------------------------


def test_an_observable_without_uncertainty_is_refused():
    with pytest.raises(InputError, match="uncertainty of observable chandler_period"):
        Measurement("chandler_period", 206.9 * 86400, None)
    with pytest.raises(InputError, match="uncertainty of observable chandler_period"):
        Measurement("chandler_period", 206.9 * 86400, 0.0)


def test_unknown_observable_and_parameter_names_are_refused():
    with pytest.raises(InputError, match="observable: got fcn_perod"):
        Measurement("fcn_perod", 1.0, 1.0)
    mars, _ = load_planet("mars")
    with pytest.raises(InputError, match="parameter: got core_radius"):
        Posterior([Parameter("core_radius", Uniform(1.0, 2.0))], [], mars)


def test_a_forward_model_failing_at_the_priors_centre_is_refused():
    """A 3150 km core of 6000 kg/m3 has A_f > B > A: no free wobble (Sasao, Okubo & Saito 1980)."""
    mars, _ = load_planet("mars")
    post = Posterior(
        [Parameter("fluid_core_radius", Uniform(3.0e6, 3.3e6), "km", 1e3)],
        [Measurement("chandler_period", 206.9 * 86400, 0.5 * 86400)],
        mars,
    )
    with pytest.raises(InputError, match="no prediction at the priors' centre.*core"):
        post.check_centre()
