"""The batched Chandler estimators of the Monte Carlo against their per-series computation, and a closed form.

``vp_periods`` and ``spectrum_periods`` measure many realisations at once (one grid
product, Brent refinements in lockstep, exponentials by block rotation on uniform
grids). The references here are the loops they replace, one series at a time, as they
stood: SciPy's bounded Brent on Fourier sums with exact exponentials. The periods must
agree to rounding. Near the peak Brent's parabolic steps divide differences of nearly
equal sums, so a 1e-15 change in a sum (another summation order) moves the period by up
to ~1e-11 relative; a step taken differently would move it by ~1e-7. Hence RTOL = 1e-9.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, REFERENCE_PERIOD, TRUTH, YEAR, damped_wobble
from scipy import optimize

from wobble.models.polar_motion.least_squares import fit_least_squares, vp_periods, vp_rates
from wobble.models.polar_motion.record import ANNUAL_RATE, CHANDLER_BAND, bin_means
from wobble.models.polar_motion.search import band_grid, refine_peak
from wobble.models.polar_motion.spectrum import fit_spectrum, spectrum_periods
from wobble.models.polar_motion.uncertainty import damped_oscillator
from wobble.numerics.spectral import dtft, dtft_at

RTOL = 1e-9


def _columns(years, *, gaps, bin_days=None, m=6, seed=3):
    """(t, zs): drift, annual terms and ``m`` excited wobbles of Q = 100 (the Monte Carlo's realisations)."""
    rng = np.random.default_rng(seed)
    t = DAY * np.arange(int(years * 365.25)) - 15 * YEAR
    if gaps:
        keep = rng.random(t.size) > 0.1
        keep[[0, -1]] = True
        t = t[keep]
    if bin_days:
        t, _ = bin_means(t, np.zeros(t.size, dtype=complex), bin_days * DAY)
    s = t - 0.5 * (t[0] + t[-1])
    base = (40 + 300j) * MAS + (20 - 60j) * MAS * s / s.max() + 90 * MAS * np.exp(1j * ANNUAL_RATE * s)
    sims = damped_oscillator(t, 2 * math.pi / TRUTH["period"], 100.0, TRUTH["chandler_amplitude"] ** 2, m, rng)
    return t, base[:, None] + sims


def _old_vp_period(t, z, degree=2, band=CHANDLER_BAND):
    """The variable-projection period as fit_least_squares(..., uncertainty=False) computed it, one series."""
    s = t - 0.5 * (t[0] + t[-1])
    half = 0.5 * (t[-1] - t[0])
    tau = s / half
    fixed = np.stack(
        [tau**j for j in range(degree + 1)] + [np.exp(1j * ANNUAL_RATE * s), np.exp(-1j * ANNUAL_RATE * s)], axis=1
    ).astype(complex)
    q, _ = np.linalg.qr(fixed)
    r0 = z - q @ (q.conj().T @ z)
    cols = np.column_stack([r0, q])
    lo, hi = 2 * math.pi / band[1], 2 * math.pi / band[0]
    rates, d = band_grid(lo, hi, s[-1] - s[0])

    def gain(f):
        return np.abs(f[..., 0]) ** 2 / np.maximum(s.size - np.sum(np.abs(f[..., 1:]) ** 2, axis=-1), 1e-12 * s.size)

    grid = gain(dtft(s, cols, rates[0], d, rates.size))
    rate = refine_peak(lambda r: float(gain(dtft_at(s, cols, r))), rates, grid, d, lo, hi)
    return 2 * math.pi / abs(rate)


def _old_spectrum_period(t, z, taper, degree=2, band=CHANDLER_BAND):
    """The spectral period as fit_spectrum(..., uncertainty=False) computed it, one series (its loop verbatim)."""
    span = t[-1] - t[0]
    s = t - 0.5 * (t[0] + t[-1])
    tau = s / (0.5 * span)
    v = np.stack([tau**j for j in range(degree + 1)], axis=1).astype(complex)
    y = z - v @ np.linalg.lstsq(v, z, rcond=None)[0]
    w = np.sin(np.pi * (t - t[0]) / span) ** 2 if taper == "hann" else np.ones_like(t)
    lo, hi = 2 * math.pi / band[1], 2 * math.pi / band[0]
    rates, d = band_grid(lo, hi, span)
    annual_cols = np.exp(1j * ANNUAL_RATE * np.outer(s, [1.0, -1.0]))
    ann = np.zeros(2, dtype=complex)
    rate = math.nan
    for _ in range(30):
        wy = w * (y - annual_cols @ ann)
        power = np.abs(dtft(s, wy, rates[0], d, rates.size)) ** 2
        previous = rate
        rate = refine_peak(lambda r: float(np.abs(dtft_at(s, wy, r)) ** 2), rates, power, d, lo, hi)
        chandler = complex(dtft_at(s, wy, rate)) / w.sum()
        ann = dtft_at(s, w * (y - chandler * np.exp(1j * rate * s)), np.array([ANNUAL_RATE, -ANNUAL_RATE])) / w.sum()
        if abs(rate - previous) < 1e-3 * d:
            break
    return 2 * math.pi / abs(rate)


# Uniform daily and five-day grids (block-rotated exponentials) and gappy ones (exact exponentials);
# 30 years (Hann taper) and 5 years (no taper: under one Chandler-annual beat).
CASES = [
    pytest.param(30, False, 5, id="30yr-5day-bins"),
    pytest.param(30, True, None, id="30yr-daily-gaps"),
    pytest.param(5, False, None, id="5yr-daily"),
    pytest.param(5, True, 5, id="5yr-5day-bins-gaps"),
]


@pytest.mark.parametrize(("years", "gaps", "bin_days"), CASES)
def test_vp_periods_equal_one_series_at_a_time(years, gaps, bin_days):
    t, zs = _columns(years, gaps=gaps, bin_days=bin_days)
    got = vp_periods(t, zs, drift_degree=2, band=CHANDLER_BAND)
    for k in range(zs.shape[1]):
        old = _old_vp_period(t, zs[:, k])
        assert got[k] == pytest.approx(old, rel=RTOL)
        kw = {"reference_period": REFERENCE_PERIOD, "uncertainty": False}
        assert fit_least_squares(t, zs[:, k], **kw).chandler.period == pytest.approx(old, rel=RTOL)


@pytest.mark.parametrize(("years", "gaps", "bin_days"), CASES)
def test_spectrum_periods_equal_one_series_at_a_time(years, gaps, bin_days):
    t, zs = _columns(years, gaps=gaps, bin_days=bin_days)
    taper = "hann" if years > 7 else "none"
    got = spectrum_periods(t, zs, reference_period=REFERENCE_PERIOD, drift_degree=2, band=CHANDLER_BAND, taper=taper)
    for k in range(zs.shape[1]):
        old = _old_spectrum_period(t, zs[:, k], taper)
        assert got[k] == pytest.approx(old, rel=RTOL)
        kw = {"reference_period": REFERENCE_PERIOD, "uncertainty": False, "taper": taper}
        assert fit_spectrum(t, zs[:, k], **kw).chandler.period == pytest.approx(old, rel=RTOL)


def test_vp_periods_recover_exact_circles():
    """Ground truth: records that are exactly drift + annual terms + a circle of period P_k have their
    largest gain at P_k (the residual vanishes there): each is found within Brent's tolerance."""
    t = DAY * np.arange(int(20 * 365.25)) - 10 * YEAR
    s = t - 0.5 * (t[0] + t[-1])
    periods = np.array([400.0, 418.5, 433.0, 447.25, 480.0]) * DAY
    base = (30 - 200j) * MAS + 5 * MAS * s / s.max() + 80 * MAS * np.exp(1j * ANNUAL_RATE * s)
    zs = base[:, None] + 150 * MAS * np.exp(1j * np.outer(s, 2 * math.pi / periods) + 0.4)
    got = vp_periods(t, zs, drift_degree=2, band=CHANDLER_BAND)
    _, d = band_grid(2 * math.pi / CHANDLER_BAND[1], 2 * math.pi / CHANDLER_BAND[0], s[-1] - s[0])
    rate_tolerance = 2e-4 * d  # refine_peak's xatol is 1e-4 of the grid step
    np.testing.assert_array_less(np.abs(2 * math.pi / got - 2 * math.pi / periods), rate_tolerance)


@pytest.mark.parametrize("gaps", [False, True])
def test_windows_equal_one_window_at_a_time(gaps, monkeypatch):
    """sliding_windows searches the windows that share their centred times (a gap-free daily record)
    together; each window's result equals its own fit_least_squares, search included, to rounding.
    The uncertainties hold the drift-model term, a difference of two periods that agree to ~1e-4:
    their rounding shows at ~1e-8 of it (a different Brent step would show at ~1e-4)."""
    from wobble.models.polar_motion import windows

    rng = np.random.default_rng(5)
    t = DAY * np.arange(int(16 * 365.25))
    s = t - t.mean()
    z = 150 * MAS * np.exp(1j * 2 * math.pi / TRUTH["period"] * s) + 90 * MAS * np.exp(1j * ANNUAL_RATE * s)
    z = z + (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size)) * 20 * MAS
    if gaps:
        keep = rng.random(t.size) > 0.05
        t, z = t[keep], z[keep]
    calls = []
    monkeypatch.setattr(windows, "vp_rates", lambda *a, **k: calls.append(1) or vp_rates(*a, **k))
    w = windows.sliding_windows(t, z, 6 * YEAR, 1 * YEAR, reference_period=REFERENCE_PERIOD)
    assert bool(calls) != gaps  # shared searches on the daily grid, none when every window has its own gaps
    for i in range(w.centre.size):
        m = (t >= w.start[i]) & (t <= w.end[i])
        f = fit_least_squares(t[m], z[m], reference_period=REFERENCE_PERIOD, subspans=False, excitation_q=None)
        assert w.period[i] == pytest.approx(f.chandler.period, rel=RTOL)
        assert w.amplitude[i] == pytest.approx(f.chandler.amplitude, rel=RTOL)
        assert w.annual_prograde_amplitude[i] == pytest.approx(f.annual_prograde.amplitude, rel=RTOL)
        assert w.period_sigma[i] == pytest.approx(f.chandler.period_sigma, rel=1e-6)
        assert w.amplitude_sigma[i] == pytest.approx(f.chandler.amplitude_sigma, rel=1e-6)


@pytest.mark.parametrize(("years", "gaps"), [(12, False), (12, True), (5, False)])
def test_spectral_model_check_equals_its_own_fits(years, gaps):
    """fit_spectrum's drift-model term (its series of one degree less and one more go through the peak
    search with the fit's own): the largest change against fit_spectrum at those degrees, fitted alone.
    The term is a difference of nearly equal periods: compared in absolute terms, to rounding."""
    t, zs = _columns(years, gaps=gaps, m=1, seed=11)
    kw = {"reference_period": REFERENCE_PERIOD, "subspans": False, "excitation_q": None}
    fit = fit_spectrum(t, zs[:, 0], **kw)
    alone = [fit_spectrum(t, zs[:, 0], drift_degree=k, uncertainty=False, **kw) for k in (1, 3)]
    period = max(abs(f.chandler.period - fit.chandler.period) for f in alone)
    amplitude = max(abs(f.chandler.amplitude - fit.chandler.amplitude) for f in alone)
    assert fit.period_uncertainty.model == pytest.approx(period, abs=RTOL * fit.chandler.period)
    assert fit.amplitude_uncertainty.model == pytest.approx(amplitude, abs=RTOL * fit.chandler.amplitude)


def _whittle_by_definition(lik, x, q):
    """Whittle's negative log-likelihood sum(ln E + I/E) over the ordinates, from the definitions: I the
    periodogram of the binned series, E = (P/n) sum over all pairs of samples of exp(i (sigma0 - omega)
    (t_j - t_k) - gamma |t_j - t_k|) + B, a damped line at sigma0 = rate + 2 pi x0 / span with gamma =
    sigma0 / (2 Q), P = scale e^x1 / n and B = scale e^x2 (no lag counts, no closed form)."""
    t, n = lik.t, lik.n
    spec = np.abs(np.exp(-1j * np.multiply.outer(lik.ords, t - t[0])) @ lik.y) ** 2 / n
    scale = np.mean(spec)
    sigma0 = lik.rate + x[0] * 2 * math.pi / lik.span
    gamma = 0.0 if math.isinf(q) else sigma0 / (2 * q)
    tau = np.subtract.outer(t, t)
    kernel = np.exp(1j * sigma0 * tau - gamma * np.abs(tau))
    pairs = np.array([np.sum(kernel * np.exp(-1j * w * tau)).real for w in lik.ords])
    e = scale * math.exp(x[1]) / n * pairs / n + scale * math.exp(x[2])
    return float(np.sum(np.log(e) + spec / e))


@pytest.mark.parametrize("gaps", [False, True])
def test_q_profile_equals_one_search_at_a_time(gaps, monkeypatch):
    """quality_factor runs the fresh-start searches of its profile (one per Q) in lockstep on the
    batched likelihood; with each run alone by SciPy on the one-point likelihood, as before, the
    result is the same (and the two likelihoods agree at every point)."""
    from wobble.models.polar_motion import quality

    rng = np.random.default_rng(21)
    n = int(30 * 365.25)
    t = DAY * np.arange(n)
    y = damped_wobble(rng, n, TRUTH["period"], 60.0, 150 * MAS) + rng.standard_normal(n) * 2 * MAS
    if gaps:  # empty ten-day bins: the likelihood's sum over the lags the record holds
        keep = np.ones(n, dtype=bool)
        keep[1000:1040] = keep[5000:5025] = False
        t, y = t[keep], y[keep]
    rate = 2 * math.pi / TRUTH["period"]
    fast = quality.quality_factor(t, y, rate)

    def one_at_a_time(func, simplexes, lower, upper, **options):
        lik = func.__self__
        assert lik.complete != gaps
        runs = [
            optimize.minimize(
                lik.nll,
                simplex[0],
                args=(j,),
                method="Nelder-Mead",
                bounds=list(zip(lower, upper)),
                options={"initial_simplex": simplex, **options},
            )
            for j, simplex in enumerate(simplexes)
        ]
        # The likelihood itself against its definition, at points spread over the box.
        for j in (0, 7, len(runs) - 1):  # Q = 3.2, 45 and infinity
            x = rng.uniform(lower, upper)
            x[1:] = rng.uniform(-2.0, 2.0, 2)  # powers where E > 0 and the value is finite
            assert lik.nll(x, j) == pytest.approx(_whittle_by_definition(lik, x, quality._Q_GRID[j]), rel=1e-10)
        return np.array([r.x for r in runs]), np.array([r.fun for r in runs])

    monkeypatch.setattr(quality, "minimize_nelder_mead", one_at_a_time)
    slow = quality.quality_factor(t, y, rate)
    for name in ("value", "low", "high", "lower_bound_95", "period"):
        assert getattr(fast, name) == pytest.approx(getattr(slow, name), rel=1e-12), name


@pytest.mark.parametrize("degree", [1, 3])
def test_vp_tracked_equals_the_least_squares_solver(degree):
    """The model check's coefficients from the shared QR (vp_tracked) against fit_least_squares at the
    same rates (NumPy's least-squares solver), series by series: the same solution to rounding."""
    from wobble.models.polar_motion.least_squares import vp_tracked
    from wobble.models.polar_motion.uncertainty import tracked

    t, zs = _columns(8, gaps=True, seed=4)
    rates = vp_rates(t, zs, drift_degree=degree, band=CHANDLER_BAND)
    got = vp_tracked(t, zs, rates, drift_degree=degree)
    for k in range(zs.shape[1]):
        kw = {"reference_period": REFERENCE_PERIOD, "drift_degree": degree, "uncertainty": False}
        want = tracked(fit_least_squares(t, zs[:, k], rate=rates[k], **kw))
        for name, value in want.items():
            # 5e-12: the cubic drift's columns condition the solve; the small retrograde annual term (1e-3 of the
            # series) differs by 1.1e-12 of itself between the two solvers (approx's abs 1e-12 had hidden it).
            assert got[k][name] == pytest.approx(value, rel=5e-12), name


@pytest.mark.parametrize("method", ["least_squares", "spectrum"])
def test_subspans_measured_together_equal_one_at_a_time(method):
    """subspan_scatter measures the sub-spans that share their times (a gap-free daily record's) with
    the estimator's batch; the scatter equals that of the estimator run on each sub-span alone."""
    import functools

    from wobble.models.polar_motion.least_squares import vp_tracked
    from wobble.models.polar_motion.record import beat_period, same_times
    from wobble.models.polar_motion.spectrum import spectrum_tracked
    from wobble.models.polar_motion.uncertainty import subspan_scatter

    t, zs = _columns(40, gaps=False, m=1, seed=8)
    z = zs[:, 0]
    beat = beat_period(REFERENCE_PERIOD)
    kw = {"reference_period": REFERENCE_PERIOD, "band": CHANDLER_BAND, "drift_degree": 2}
    if method == "least_squares":
        estimator = fit_least_squares

        def batch(tm, zm):
            return vp_tracked(tm, zm, vp_rates(tm, zm, drift_degree=2, band=CHANDLER_BAND), drift_degree=2)
    else:
        estimator = functools.partial(fit_spectrum, taper="hann")
        batch = functools.partial(spectrum_tracked, taper="hann", **kw)
    together, n = subspan_scatter(t, z, estimator, beat, batch, **kw)
    alone, n_alone = subspan_scatter(t, z, estimator, beat, **kw)
    count = int((t[-1] - t[0]) // (2 * beat))
    assert n == n_alone == count >= 3
    edges = t[0] + (t[-1] - t[0]) * np.arange(count + 1) / count
    masks = {j: (t >= a) & (t <= b) for j, (a, b) in enumerate(zip(edges[:-1], edges[1:]))}
    assert same_times(t, masks)  # the batch did measure some together
    for name in together:
        assert together[name] == pytest.approx(alone[name], rel=1e-9), name


@pytest.mark.parametrize("rate", [math.nan, -1.0, 2 * math.pi / (300 * DAY)])
def test_a_given_rate_outside_the_band_is_refused(rate):
    # Was: LAPACK's "DLASCL parameter number 4" and a LinAlgError for nan, a 7e-5 d period for -1.
    from wobble.errors import InputError

    t = np.arange(0.0, 12 * YEAR, DAY)
    z = np.exp(2j * math.pi * t / (433 * DAY))
    with pytest.raises(InputError, match=r"^rate: got .*; allowed: a rate within the band, .* rad/s$"):
        fit_least_squares(t, z, reference_period=REFERENCE_PERIOD, uncertainty=False, rate=rate)
