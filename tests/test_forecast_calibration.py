"""Intervals calibrated on past forecasts: the split-conformal quantiles, coverage on synthetic records,
the past forecasts equal to the forecasts themselves, and no calibration reading after its cut-off."""

from __future__ import annotations

import math

import numpy as np
import pytest
from polar_synthetic import DAY, MAS, state_space_record

from wobble.errors import InputError
from wobble.models.polar_motion import forecast_calibration as fcal
from wobble.models.polar_motion import state_space as ssm
from wobble.models.polar_motion.forecast import PastForecasts
from wobble.models.polar_motion.ls_ar import forecast_ls_ar, past_forecasts_ls_ar
from wobble.numerics.threads import single_blas_thread

PERIOD = 433.0 * DAY
Q = 80.0
YEAR = 365.25 * DAY

# ---------------------------------------------------------------------------
# The quantiles themselves, on errors of known distribution
# ---------------------------------------------------------------------------


def _record_and_past(rng, scale_x, scale_y, horizon, latency, span):
    """A daily record and "past forecasts" of it whose errors at lead l are N(0, scale(l)^2) per component,
    each stating half its true scale as its sigma (a model too confident by two)."""
    t = DAY * np.arange(30 * 365)
    z = np.zeros(t.size, dtype=complex)
    issued = t[-1] + latency
    times = fcal.past_issue_times(issued, latency, horizon, span)
    lead = np.arange(1, horizon + 1)
    idx = np.rint((times[:, None] + lead[None, :] * DAY - t[0]) / DAY).astype(int)
    truth = z[np.minimum(idx, t.size - 1)]
    noise = scale_x(lead) * rng.standard_normal(idx.shape) - 1j * scale_y(lead) * rng.standard_normal(idx.shape)
    stated = (
        0.5
        * np.stack(np.broadcast_arrays(scale_x(lead)[None, :], scale_y(lead)[None, :]), axis=2)
        * np.ones((times.size, 1, 1))
    )
    return t, z, issued, PastForecasts(times, truth + noise, stated)


def test_half_widths_are_the_conformal_order_statistics():
    """With n errors the half-width is the ceil((n+1)p)-th smallest |error| / stated sigma, times this forecast's
    sigma: for Gaussian errors twice the stated sigma, the true sigma and 1.96 times it."""
    rng = np.random.default_rng(1)
    horizon, latency, span = 40, 3 * DAY, 10 * YEAR

    def sx(lead):
        return (1.0 + 0.1 * lead) * MAS

    def sy(lead):
        return 0.5 * sx(lead)

    t, z, issued, past = _record_and_past(rng, sx, sy, horizon, latency, span)
    lead = np.arange(1, horizon + 1)
    cal = fcal.calibrate(t, z, issued, latency, horizon, past, (0.5 * sx(lead), 0.5 * sy(lead)), span=span)
    n = fcal.count_per_lead(span)
    assert np.all(cal.count == n) and n == 522
    # Lead 10 by hand: the most recent n issues whose outcome (issue + 10 d) is on or before issued - latency.
    times = past.issued
    ok = times + 10 * DAY <= issued - latency + 1e-6
    use = np.flatnonzero(ok)[-n:]
    ex = np.sort(np.abs(past.mean[use, 9].real) / past.sigma[use, 9, 0])
    assert cal.scale68[9, 0] == ex[math.ceil((n + 1) * fcal.P68) - 1]
    assert cal.scale95[9, 0] == ex[math.ceil((n + 1) * fcal.P95) - 1]
    assert cal.half68[9, 0] == cal.scale68[9, 0] * 0.5 * sx(10)
    # Against the Gaussian quantiles 1 and 1.96 sigma: within 4 standard errors of a quantile of 522 values.
    for half, z_p, p in ((cal.half68, 1.0, fcal.P68), (cal.half95, 1.959964, fcal.P95)):
        density = 2 * np.exp(-0.5 * z_p**2) / math.sqrt(2 * math.pi)
        se = math.sqrt(p * (1 - p) / n) / density
        np.testing.assert_allclose(half[:, 0] / sx(lead), z_p, atol=4 * se)
        np.testing.assert_allclose(half[:, 1] / sy(lead), z_p, atol=4 * se)
    assert cal.last_outcome <= issued - latency and cal.cutoff == issued - latency


def test_calibrated_intervals_cover_new_outcomes_at_the_nominal_rate():
    """Calibrate on n past errors, then count new errors of the same law inside: 68 % and 95 % within sampling error."""
    rng = np.random.default_rng(2)
    horizon, latency, span = 20, DAY, 2 * YEAR
    inside68, inside95 = [], []
    for _ in range(40):
        t, z, issued, past = _record_and_past(rng, lambda d: d * MAS, lambda d: 2 * d * MAS, horizon, latency, span)
        lead = np.arange(1, horizon + 1)
        cal = fcal.calibrate(t, z, issued, latency, horizon, past, (0.5 * lead * MAS, lead * MAS), span=span)
        new_x, new_y = lead * MAS * rng.standard_normal(horizon), 2 * lead * MAS * rng.standard_normal(horizon)
        inside68 += list(np.abs(new_x) <= cal.half68[:, 0]) + list(np.abs(new_y) <= cal.half68[:, 1])
        inside95 += list(np.abs(new_x) <= cal.half95[:, 0]) + list(np.abs(new_y) <= cal.half95[:, 1])
    # 1600 independent outcomes: the standard error of a coverage is ~1.2 % (68 %) and 0.5 % (95 %).
    assert abs(np.mean(inside68) - 0.6827) < 0.04
    assert abs(np.mean(inside95) - 0.95) < 0.02


# ---------------------------------------------------------------------------
# A record of the state-space model: past forecasts, a miscalibrated model made honest
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def simulated():
    return state_space_record(np.random.default_rng(11), 32, PERIOD, Q, ssm.DEFAULT_NOISE)


@pytest.fixture(scope="module")
def setup(simulated):
    return ssm.KalmanSetup.build(PERIOD, Q, ssm.DEFAULT_NOISE, int(round(ssm.FIT_SPAN / DAY)) + 1)


def test_past_forecasts_are_the_forecasts_themselves(simulated, setup):
    """The vectorised past forecasts (Kalman: one product) equal forecast_kalman / forecast_ls_ar issue by issue."""
    t, p = simulated
    issues = t[-1] - DAY * np.array([400, 250, 33, 1])
    with single_blas_thread():
        past = ssm.past_forecasts_kalman(t, p, issues, 60, setup=setup, latency=2 * DAY)
        for k, s in enumerate(issues):
            f = ssm.forecast_kalman(t, p, s, 60, chandler_period=PERIOD, q=Q, latency=2 * DAY, setup=setup)
            np.testing.assert_allclose(past.mean[k], f.mean, rtol=0, atol=1e-9 * MAS)
        past_ls = past_forecasts_ls_ar(t, p, issues[:2], 30, chandler_period=PERIOD, latency=2 * DAY)
        for k, s in enumerate(issues[:2]):
            np.testing.assert_array_equal(
                past_ls.mean[k], forecast_ls_ar(t, p, s, 30, chandler_period=PERIOD, latency=2 * DAY).mean
            )


def test_calibration_makes_a_wrong_model_honest(simulated):
    """The Kalman model given an excitation 2.5 times too small: its Gaussian 68 % intervals hold far too few
    outcomes; calibrated on its own past forecasts, they hold 68 % within sampling error."""
    t, p = simulated
    wrong = ssm.NoiseParameters(**{**ssm.DEFAULT_NOISE.__dict__, "excitation": ssm.DEFAULT_NOISE.excitation / 6.25})
    span, horizon, latency = 3 * YEAR, 30, DAY
    bad = ssm.KalmanSetup.build(PERIOD, Q, wrong, int(round(ssm.FIT_SPAN / DAY)) + 1)
    first = t[0] + DAY * math.ceil((ssm.FIT_SPAN + span) / DAY + 60)
    issues = first + 41 * DAY * np.arange(int((t[-1] - horizon * DAY - first) / (41 * DAY)))
    with single_blas_thread():
        times = np.unique(
            np.round(np.concatenate([fcal.past_issue_times(s, latency, horizon, span) for s in issues]), 3)
        )
        past = ssm.past_forecasts_kalman(t, p, np.unique(np.r_[times, issues]), horizon, setup=bad, latency=latency)
        now = past.take(issues)
        lead = np.arange(1, horizon + 1)
        truth = p[np.rint((issues[:, None] + lead * DAY - t[0]) / DAY).astype(int)]
        err = now.mean - truth
        raw, cal68, cal95 = [], [], []
        sigma = now.sigma[0, :, 0]  # the model's own (the same at every issue)
        for k, s in enumerate(issues):
            cal = fcal.calibrate(t, p, s, latency, horizon, past, (sigma, sigma), span=span)
            for col, e in ((0, err[k].real), (1, err[k].imag)):
                raw.append(np.abs(e) <= sigma)
                cal68.append(np.abs(e) <= cal.half68[:, col])
                cal95.append(np.abs(e) <= cal.half95[:, col])
    raw, cal68, cal95 = (np.array(a) for a in (raw, cal68, cal95))
    assert issues.size > 150
    # Leads of 1, 5 and 30 days; about 2 x 170 outcomes each, the 68 % standard error ~2.5 % (correlated at 30 d).
    for d in (1, 5, 30):
        assert raw[:, d - 1].mean() < 0.45, (d, raw[:, d - 1].mean())
        assert abs(cal68[:, d - 1].mean() - 0.6827) < 0.09, (d, cal68[:, d - 1].mean())
        assert abs(cal95[:, d - 1].mean() - 0.95) < 0.05, (d, cal95[:, d - 1].mean())


# ---------------------------------------------------------------------------
# Nothing after the cut-off
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["kalman", "ls_ar"])
def test_calibrated_forecast_never_reads_after_its_cutoff(simulated, setup, method):
    """Garbage after issue - latency leaves forecast and intervals unchanged to the bit; garbage in the last
    sample before the cut-off changes the intervals (the test can fail: that outcome is used)."""
    t, p = simulated
    issued, latency = t[-1] - 1096 * DAY, 5 * DAY
    kwargs = {"method": method, "chandler_period": PERIOD, "q": Q, "latency": latency, "span": YEAR, "setup": setup}

    def run(z):
        with single_blas_thread():
            return fcal.forecast(t, z, issued, 45, **kwargs)

    a = run(p)
    after = p.copy()
    after[t > issued - latency] = 1e3 + 1e3j
    b = run(after)
    np.testing.assert_array_equal(a.mean, b.mean)
    for level in (68, 95):
        for ha, hb in zip(a.half_widths(level), b.half_widths(level)):
            np.testing.assert_array_equal(ha, hb)
    assert a.calibration.last_outcome == issued - latency
    at = p.copy()
    at[np.flatnonzero(t <= issued - latency)[-1]] += (
        1e3 * MAS
    )  # the cut-off's own sample: an outcome of the calibration
    c = run(at)
    assert not np.array_equal(a.half_widths(68)[0], c.half_widths(68)[0])


def test_hindcast_calibrations_never_read_the_future(simulated):
    """A hindcast block's first issue: forecasts and calibrated intervals unchanged by garbage after its cut-off,
    although the block computes past forecasts for its later issues from the whole record."""
    from wobble.models.polar_motion import hindcast as hc

    t, p = simulated
    issues = t[-1] - 1096 * DAY + 7 * DAY * np.arange(3)
    block = hc.blocks(
        issues, 20, ("ls_ar", "kalman"), DAY, Q, PERIOD, refit=3, chandler_period=PERIOD, calibration_span=YEAR
    )[0]
    spoiled = p.copy()
    spoiled[t > issues[0] - DAY] = 1e3 + 1e3j
    first_a = hc.run_block(t, p, block)[0]
    first_b = hc.run_block(t, spoiled, block)[0]
    for fa, fb in zip(first_a, first_b):
        np.testing.assert_array_equal(fa.mean, fb.mean)
        np.testing.assert_array_equal(fa.calibration.half68, fb.calibration.half68)
        np.testing.assert_array_equal(fa.calibration.half95, fb.calibration.half95)


# ---------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------


def test_calibration_span_outside_the_record_is_named(simulated, setup):
    t, p = simulated
    issued = t[0] + ssm.FIT_SPAN + 2 * YEAR  # room for the forecast, not for 5 years of past forecasts
    with pytest.raises(InputError, match=r"calibration_span: got 5 yr; allowed: at most 1\.\d\d yr"):
        fcal.forecast(t, p, issued, 30, method="kalman", chandler_period=PERIOD, q=Q, setup=setup, span=5 * YEAR)
    with pytest.raises(InputError, match="calibration_span: got 70 d"):
        fcal.count_per_lead(70 * DAY)
    fcal.forecast(
        t, p, issued, 30, method="kalman", chandler_period=PERIOD, q=Q, setup=setup, span=YEAR
    )  # one year fits


def test_shipped_spans_are_the_rule_s_choice_on_2006_2015():
    """forecast_calibration.SPANS are what scripts/calibration_span.py's rule picks from its committed
    2006-2015 table: of the spans whose 68 % intervals held 63-73 % at every lead with both latencies,
    the least sum of the 68 % and 95 % interval scores. Re-applied here to the table, so a new run of the
    script that picks otherwise, or a changed constant, fails."""
    import json
    from pathlib import Path

    table = json.loads((Path(__file__).resolve().parents[1] / "docs/figures/calibration_span.json").read_text())
    for method, rows in table["methods"].items():
        eligible = {
            int(years): sum(r["interval_score_68_mas"] + r["interval_score_95_mas"] for r in row.values())
            for years, row in rows.items()
            if len(row) == 2 and all(r["leads_outside_63_73"] == 0 for r in row.values())
        }
        chosen = min(eligible, key=eligible.get)
        assert chosen == table["chosen_years"][method]
        assert fcal.SPANS[method] == chosen * YEAR


def test_the_2021_table_beside_bulletin_a_quotes_its_measured_file():
    """docs/forecast.md's 2021 table is docs/figures/forecast_2021.json (scripts/hindcast_polar_motion.py
    --bulletin-a), rounded: the page cannot drift from the run it cites."""
    import json
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    numbers = json.loads((root / "docs/figures/forecast_2021.json").read_text())
    page = (root / "docs/forecast.md").read_text()
    leads = ["1", "5", "10", "30", "90", "180", "270", "365"]
    for comp, sym in (("mae_x", "x_p"), ("mae_y", "y_p")):
        expected = {
            f"kalman ${sym}$, 2021 (latency 1 d)": numbers["wobble"]["kalman"][f"{comp}_mas"],
            f"ls_ar ${sym}$, 2021 (latency 1 d)": numbers["wobble"]["ls_ar"][f"{comp}_mas"],
            f"IERS Bulletin A ${sym}$, 2021": numbers["bulletin_a"][f"{comp}_mas"],
            f"Wang & Zhang's own LS+AR ${sym}$, 2021": numbers["their_ls_ar"][f"{comp}_mas"],
        }
        for label, values in expected.items():
            row = re.search(rf"^\| {re.escape(label)} \|(.*)\|$", page, re.MULTILINE)
            assert row, label
            assert [c.strip() for c in row.group(1).split("|")] == [f"{values[d]:.2f}" for d in leads], label
    assert numbers["hindcast"]["issues"] == 53 and numbers["hindcast"]["latency_days"] == 1
