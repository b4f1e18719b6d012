"""The Chandler term by nonlinear least squares of equation (2) on the complex series.

The frequency maximises the profile (variable-projection) gain, the drop of the
residual sum of squares when exp(i sigma s) joins the drift and annual columns,
searched on an oversampled grid and refined by bounded Brent; then
:func:`scipy.optimize.least_squares` polishes every parameter together and
gives the Jacobian for the covariances (:mod:`.uncertainty`). Times in s,
angles in rad, rates in rad/s.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy import optimize

from wobble.errors import InputError
from wobble.models.polar_motion.fit import ChandlerFit, Uncertainty, make_fit, with_changes
from wobble.models.polar_motion.record import (
    ANNUAL_RATE,
    CHANDLER_BAND,
    DAY,
    as_series,
    beat_period,
    check_band,
    check_degree,
    check_q,
    span_caveats,
)
from wobble.models.polar_motion.search import at_band_edge, band_grid, refine_peaks
from wobble.models.polar_motion.uncertainty import (
    HAC_MAX_B,
    TRACKED,
    amp_phase_sigma,
    annual_sigmas,
    combine,
    excitation_scatter,
    hac_meat,
    largest_change,
    model_sensitivity,
    scaled_inverse,
    sqrt_var,
    subspan_scatter,
    tracked_columns,
)
from wobble.numerics.phasor import uniform_grid
from wobble.numerics.spectral import dtft, exponentials
from wobble.numerics.threads import one_blas_thread

__all__ = ["MAX_VARIANCE_INFLATION", "fit_least_squares", "separation", "vp_periods", "vp_rates", "vp_tracked"]

#: The largest variance inflation of the Chandler column (1 / (1 - R^2) of its regression on the drift and annual
#: columns) at which the Chandler and annual terms count as told apart: 10, the usual bound of severe collinearity
#: (Marquardt 1970; Kutner, Nachtsheim & Neter 2004, sec. 10.5). It is 1 over whole beat periods (6.4 yr at 433 d);
#: a Chandler term near 433 d over two years gives 4 to 8, one at the band's lower edge (390 d) 30.
MAX_VARIANCE_INFLATION = 10.0


def _fixed_columns(s: np.ndarray, half: float, degree: int) -> np.ndarray:
    tau = s / half
    cols = [tau**j for j in range(degree + 1)]
    cols += [np.exp(1j * ANNUAL_RATE * s), np.exp(-1j * ANNUAL_RATE * s)]
    return np.stack(cols, axis=1).astype(complex)


def _profile(s, z, fixed):
    """QR of the fixed columns and the residual r0 of the fit without the Chandler term."""
    q, _ = np.linalg.qr(fixed)
    r0 = z - q @ (q.conj().T @ z)
    return q, r0


def _gains(s, r0, q, grid):
    """``gains(rates, index)``: the gain of column ``index[j]`` of ``r0`` at ``rates[j]`` (one rate each),
    for :func:`~wobble.models.polar_motion.search.refine_peaks`."""
    r0_rows = np.ascontiguousarray(r0.T)

    def gains(rates, index):
        phase = exponentials(s, rates, grid)
        f0 = np.einsum("kn,kn->k", phase, r0_rows[index])
        denom = s.size - np.sum(np.abs(phase @ q) ** 2, axis=-1)
        return np.abs(f0) ** 2 / np.maximum(denom, 1e-12 * s.size)

    return gains


def vp_periods(t, zs, *, drift_degree: int, band) -> np.ndarray:
    """Chandler periods (s) of many series on the same times by variable projection (no polish).

    Column k of ``zs`` gives the period ``fit_least_squares(t, zs[:, k],
    uncertainty=False)`` would (the Monte Carlo of
    :func:`~wobble.models.polar_motion.uncertainty.excitation_scatter`); see :func:`vp_rates`.
    """
    return 2 * math.pi / np.abs(vp_rates(t, zs, drift_degree=drift_degree, band=band))


def vp_rates(t, zs, *, drift_degree: int, band) -> np.ndarray:
    """Chandler rates (rad/s, signed) of many series on the same times by variable projection (no polish).

    Column k of ``zs`` gives the rate the search of ``fit_least_squares(t, zs[:, k])`` finds before its
    polish: the drift and annual columns, their QR and their Fourier sums are shared, the grid search
    is one matrix product for all columns, and so are the bounded Brent refinements
    (:func:`~wobble.models.polar_motion.search.refine_peaks`: the same steps as one refinement per
    column, each step one array operation for all of them).
    """
    epoch = 0.5 * (t[0] + t[-1])
    half = 0.5 * (t[-1] - t[0])
    s = t - epoch
    lo_rate, hi_rate = 2 * math.pi / band[1], 2 * math.pi / band[0]
    fixed = _fixed_columns(s, half, drift_degree)
    q, r0 = _profile(s, zs, fixed)
    rates, d = band_grid(lo_rate, hi_rate, s[-1] - s[0])
    m = zs.shape[1]
    f = dtft(s, np.column_stack([r0, q]), rates[0], d, rates.size)
    denom = np.maximum(s.size - np.sum(np.abs(f[:, m:]) ** 2, axis=1), 1e-12 * s.size)
    gains = np.abs(f[:, :m]) ** 2 / denom[:, None]
    return refine_peaks(_gains(s, r0, q, uniform_grid(s)), rates, gains, d, lo_rate, hi_rate)


def vp_tracked(t, zs, rates, *, drift_degree: int) -> list[dict[str, float]]:
    """What ``fit_least_squares(t, zs[:, k], rate=rates[k], uncertainty=False)`` gives of the tracked
    quantities (:func:`~wobble.models.polar_motion.uncertainty.tracked`), for many series on the same
    times, each at its own Chandler rate.

    The least-squares coefficients come from the drift and annual columns' QR, shared by all
    series: with P the projection off those columns and e = exp(i rate s), the Chandler amplitude is
    (P e)^H z / |P e|^2 and the others solve R a = Q^H (z - c e); the same solution as a
    least-squares solver's, to rounding.
    """
    epoch = 0.5 * (t[0] + t[-1])
    half = 0.5 * (t[-1] - t[0])
    s = t - epoch
    q, r = np.linalg.qr(_fixed_columns(s, half, drift_degree))
    e = np.exp(1j * np.multiply.outer(s, rates))
    e_off = e - q @ (q.conj().T @ e)
    chandler = np.sum(e_off.conj() * zs, axis=0) / np.sum(np.abs(e_off) ** 2, axis=0)
    fixed_coeffs = np.linalg.solve(r, q.conj().T @ (zs - e * chandler))
    return tracked_columns(rates, chandler, fixed_coeffs[drift_degree + 1], fixed_coeffs[drift_degree + 2])


def _ls_solve(s, z, half, fixed, band, rate, polish=True):
    """The linear fit at the variable projection's ``rate`` (:func:`vp_rates`), then (``polish``) a full
    nonlinear least-squares polish.

    ``fixed`` are the drift and annual columns (:func:`_fixed_columns`). Returns
    (coefficients, rate, at_edge); the coefficients are ordered as the
    columns: drift (degree + 1), annual +, annual -, Chandler.
    """
    lo_rate, hi_rate = 2 * math.pi / band[1], 2 * math.pi / band[0]
    step = band_grid(lo_rate, hi_rate, s[-1] - s[0])[1]
    coeffs = np.linalg.lstsq(np.column_stack([fixed, np.exp(1j * rate * s)]), z, rcond=None)[0]
    if polish:
        polished, polished_rate = _polish(s, z, half, fixed, coeffs, rate)
        # The polish is unbounded: from the band's edge it ran on to the annual frequency itself (two years
        # of 2024-2026 gave a "Chandler" term of 365.2 d and 11.9 million mas cancelling an annual one of the
        # same size). The period searched for lies in the band; outside it, the search's own optimum stands.
        if lo_rate <= polished_rate <= hi_rate:
            coeffs, rate = polished, polished_rate
    return coeffs, rate, at_band_edge(rate, lo_rate, hi_rate, step)


def separation(s, fixed, rate) -> float:
    """1 - R^2 of the Chandler column exp(i rate s) regressed on the ``fixed`` (drift and annual) columns.

    The inverse of the Chandler amplitude's variance inflation: 1 when the columns are orthogonal (whole
    Chandler-annual beat periods), near 0 when the Chandler term can hardly be told from the others, and
    the fit's covariance then trades one amplitude for the other.
    """
    q, _ = np.linalg.qr(fixed)
    e = np.exp(1j * rate * s)
    off = e - q @ (q.conj().T @ e)
    return float(np.sum(np.abs(off) ** 2) / np.sum(np.abs(e) ** 2))


def _polish(s, z, half, fixed, coeffs, rate):
    """scipy.optimize.least_squares on all real parameters of equation (2).

    Parameters: real and imaginary parts of every complex amplitude, and
    u = rate * h (the phase the Chandler term gains over half the span), so
    that all parameters are of comparable scale. Starting from the
    variable-projection optimum it confirms it (and would correct a grid or
    Brent inaccuracy).
    """
    ncols = coeffs.size

    def unpack(theta):
        c = theta[0 : 2 * ncols : 2] + 1j * theta[1 : 2 * ncols : 2]
        return c, theta[-1] / half

    def residual(theta):
        c, r = unpack(theta)
        d = z - fixed @ c[:-1] - c[-1] * np.exp(1j * r * s)
        return np.concatenate([d.real, d.imag])

    def jacobian(theta):
        c, r = unpack(theta)
        jc = _jacobian_complex(s, half, fixed, c, r)
        return -np.concatenate([jc.real, jc.imag])

    theta0 = np.empty(2 * ncols + 1)
    theta0[0 : 2 * ncols : 2] = coeffs.real
    theta0[1 : 2 * ncols : 2] = coeffs.imag
    theta0[-1] = rate * half
    scale = np.full(theta0.size, max(np.abs(coeffs).max(), 1e-300))
    scale[-1] = 1.0
    sol = optimize.least_squares(residual, theta0, jac=jacobian, method="lm", x_scale=scale)
    if not sol.success or sol.cost > 0.5 * np.sum(residual(theta0) ** 2) * (1 + 1e-12):
        return coeffs, rate
    return unpack(sol.x)


def _jacobian_complex(s, half, fixed, c, rate) -> np.ndarray:
    """d(model)/d(real parameters), complex, shape (n, 2 ncols + 1); last column per u = rate h."""
    e = np.exp(1j * rate * s)
    n, nfix = fixed.shape
    j = np.empty((n, 2 * (nfix + 1) + 1), dtype=complex)
    j[:, 0 : 2 * nfix : 2] = fixed
    j[:, 1 : 2 * nfix : 2] = 1j * fixed
    j[:, 2 * nfix] = e
    j[:, 2 * nfix + 1] = 1j * e
    j[:, -1] = c[-1] * 1j * (s / half) * e
    return j


@one_blas_thread
def fit_least_squares(
    t,
    z,
    *,
    reference_period: float,
    drift_degree: int = 2,
    band: tuple[float, float] = CHANDLER_BAND,
    uncertainty: bool = True,
    subspans: bool = True,
    excitation_q: float | None = 100.0,
    draws: int = 64,
    seed: int = 0,
    rate: float | None = None,
    model_check: list[dict] | None = None,
    polish: bool | None = None,
) -> ChandlerFit:
    """Nonlinear least-squares fit of equation (2) to the complex pole series.

    Parameters
    ----------
    t : ndarray
        Sample times, s, strictly increasing; gaps and uneven spacing are fine.
    z : ndarray, complex
        The pole p = x_p - i y_p (equation 1), rad.
    reference_period : float
        A published Chandler period, s (the Earth catalogue's
        ``observed_chandler_period``; :mod:`wobble.api` passes it). It only
        places the Chandler-annual beat period that decides what a short span
        is (:func:`~wobble.models.polar_motion.record.beat_period`); it is
        never a prior on the estimate.
    drift_degree : int
        Degree of the mean-pole polynomial (default 2: the pole's drift turned
        toward the east after about 2005, which a line cannot follow).
    band : (float, float)
        Search interval for the Chandler period, s (default 390 to 500 d).
    uncertainty : bool
        Compute the uncertainty breakdown (off for the inner fits of the
        sub-span and model checks).
    subspans : bool
        Include the sub-span scatter (needs a span of six beat periods, 38 yr).
    excitation_q : float or None
        Q of the randomly excited wobble assumed by the Monte-Carlo
        ``excitation`` term (default 100; None leaves the term out).
    draws, seed : int
        Monte-Carlo realisations and the seed of their generator (fixed, so
        results are reproducible).
    rate : float, optional
        The variable projection's Chandler rate of this series (rad/s), found
        already (by :func:`vp_rates`, for many series at once, as
        :func:`~wobble.models.polar_motion.windows.sliding_windows` does): the
        search is skipped.
    model_check : list of dict, optional
        The fits of the drift model's check (degrees one less and one more),
        as :func:`~wobble.models.polar_motion.uncertainty.tracked` values,
        found already (:func:`vp_tracked`); otherwise they are fitted here.
    polish : bool, optional
        Polish every parameter with :func:`scipy.optimize.least_squares` (default: with
        ``uncertainty``). The search's bounded Brent places the period to about sqrt(eps) of
        itself, as any search by function values of a smooth maximum must (2e-7 d of 432.6 d on the
        whole record); the polish's Jacobian takes it to rounding. A period another result is
        compared with, digit for digit, is polished.

    Returns
    -------
    ChandlerFit
        ``method = "least_squares"``. Equal weights: the misfit (tens of mas)
        is geophysical, far above the formal errors of modern data, which
        would otherwise give the last decades nearly all the weight.
        ``details`` holds ``at_edge`` (the period at the band's edge),
        ``variance_inflation`` (of the Chandler column against the drift and
        annual columns, :func:`separation`) and ``separable`` (at most
        :data:`MAX_VARIANCE_INFLATION`); ``fit.resolved`` combines them.

    Notes
    -----
    The frequency maximises the profile gain (the residual-sum-of-squares drop
    of adding the Chandler column to the drift and annual columns), searched
    on a grid oversampled 8 times over the Rayleigh resolution and refined by
    bounded Brent; :func:`scipy.optimize.least_squares` then polishes all
    parameters together and gives the Jacobian for the covariances. A
    polished period outside the band is not taken (the polish is unbounded:
    from the band's edge it could run on to the annual frequency).
    """
    t, z = as_series(t, z)
    degree = check_degree(drift_degree)
    band = check_band(band)
    if rate is not None and not (math.isfinite(rate) and 2 * math.pi / band[1] <= rate <= 2 * math.pi / band[0]):
        raise InputError(
            "rate", rate, f"a rate within the band, {2 * math.pi / band[1]:.6g} to {2 * math.pi / band[0]:.6g} rad/s"
        )
    beat = beat_period(reference_period)
    epoch = 0.5 * (t[0] + t[-1])
    half = 0.5 * (t[-1] - t[0])
    s = t - epoch
    fixed = _fixed_columns(s, half, degree)
    if rate is None:  # the search, as for many series at once (one column here)
        rate = float(vp_rates(t, z[:, None], drift_degree=degree, band=band)[0])
    coeffs, rate, at_edge = _ls_solve(s, z, half, fixed, band, rate, polish=uncertainty if polish is None else polish)
    resid = z - fixed @ coeffs[:-1] - coeffs[-1] * np.exp(1j * rate * s)
    inflation = 1.0 / max(separation(s, fixed, rate), 1e-300)
    caveats = _caveats(t, beat, band, rate, at_edge, inflation)
    details: dict = {
        "solver": "variable projection + scipy.optimize.least_squares (lm)",
        "at_edge": bool(at_edge),
        "band": band,
        "variance_inflation": inflation,
        "separable": bool(inflation <= MAX_VARIANCE_INFLATION),
    }
    nan = math.nan
    sig_rate = sig_amp = sig_phase = nan
    ann_sig = [(nan, nan), (nan, nan)]
    pu = au = Uncertainty(nan, nan, nan, nan, nan)
    if uncertainty:
        cov = _covariance_sigmas(t, s, half, fixed, degree, coeffs, rate, resid, beat)
        details["hac_bandwidth_days"] = cov["hac_bandwidth"] / DAY
        sub = dict.fromkeys(TRACKED, nan)
        if subspans:

            def batch(tm, zs):
                return vp_tracked(tm, zs, vp_rates(tm, zs, drift_degree=degree, band=band), drift_degree=degree)

            sub, details["subspans"] = subspan_scatter(
                t, z, fit_least_squares, beat, batch, reference_period=reference_period, band=band, drift_degree=degree
            )
        base = make_fit("least_squares", t, epoch, half, degree, coeffs, rate, resid, 0, 0, 0, ann_sig)
        if model_check is None:
            mod = model_sensitivity(t, z, fit_least_squares, degree, base, reference_period=reference_period, band=band)
        else:
            mod = largest_change(base, model_check)
        p_exc = math.nan
        if excitation_q is not None:
            batch = functools.partial(vp_periods, drift_degree=degree, band=band)
            p_exc = excitation_scatter(t, base, batch, check_q(excitation_q), draws, seed)
            details["excitation_q"] = float(excitation_q)
        pu = combine(cov["period_formal"], cov["period_hac"], sub["period"], mod["period"], p_exc)
        au = combine(cov["amplitude_formal"], cov["amplitude_hac"], sub["amplitude"], mod["amplitude"])
        sig_rate = pu.adopted * rate**2 / (2 * math.pi)
        sig_amp = au.adopted
        sig_phase = cov["phase_hac"]
        ann_sig = annual_sigmas(cov["annual_hac"], sub, mod)
    fit = make_fit("least_squares", t, epoch, half, degree, coeffs, rate, resid, sig_rate, sig_amp, sig_phase, ann_sig)
    return with_changes(fit, period_uncertainty=pu, amplitude_uncertainty=au, caveats=tuple(caveats), details=details)


def _caveats(t, beat: float, band, rate: float, at_edge: bool, inflation: float) -> list[str]:
    """What the fit cannot say over this span: a short span, a period at the band's edge, a Chandler
    column the annual terms cannot be told from."""
    caveats = span_caveats(t[-1] - t[0], beat)
    if at_edge:
        caveats.append(
            f"the best period lies at the edge of the search band {band[0] / DAY:.0f}-{band[1] / DAY:.0f} d: "
            "no Chandler term is resolved in this span"
        )
    if inflation > MAX_VARIANCE_INFLATION:
        caveats.append(
            f"over this span a Chandler term of {2 * math.pi / rate / DAY:.0f} d cannot be told from the annual "
            f"terms: its column is nearly collinear with theirs (variance inflation {inflation:.3g}, above "
            f"{MAX_VARIANCE_INFLATION:g}), so the Chandler and annual amplitudes are not determined, only their sum"
        )
    return caveats


def _covariance_sigmas(t, s, half, fixed, degree, coeffs, rate, resid, beat) -> dict:
    """The formal and heteroscedasticity-and-autocorrelation-consistent (HAC, Bartlett) sigmas of the period,
    the Chandler amplitude and phase and the annual and semi-annual terms, from the fit's Jacobian; with the
    HAC bandwidth, s."""
    jc = _jacobian_complex(s, half, fixed, coeffs, rate)
    bread = scaled_inverse((jc.conj().T @ jc).real)
    npar = jc.shape[1]
    s2 = float(np.sum(np.abs(resid) ** 2)) / max(2 * s.size - npar, 1)
    cov_formal = s2 * bread
    scores = (jc.conj() * resid[:, None]).real
    lag = min(beat, (t[-1] - t[0]) * HAC_MAX_B)
    b = lag / (t[-1] - t[0])
    # Fixed-b bias of the Bartlett estimator, E = (1 - b + b^2/3) x the true
    # long-run variance (Kiefer & Vogelsang 2005): divided out.
    cov_hac = bread @ hac_meat(t, scores, lag) @ bread / (1.0 - b + b * b / 3.0)
    # period sigma from u = rate * half: sigma_P = 2 pi sigma_u / (half rate^2)
    to_period = 2 * math.pi / (half * rate**2)
    ic = 2 * (coeffs.size - 1)  # (Re, Im) of the Chandler amplitude
    a_hac, phase_hac = amp_phase_sigma(coeffs[-1], cov_hac[ic : ic + 2, ic : ic + 2])
    annual = [
        amp_phase_sigma(
            coeffs[degree + 1 + k],
            cov_hac[2 * (degree + 1 + k) : 2 * (degree + 2 + k), 2 * (degree + 1 + k) : 2 * (degree + 2 + k)],
        )
        for k in (0, 1)
    ]
    return {
        "hac_bandwidth": lag,
        "period_formal": sqrt_var(cov_formal[-1, -1]) * to_period,
        "period_hac": sqrt_var(cov_hac[-1, -1]) * to_period,
        "amplitude_formal": amp_phase_sigma(coeffs[-1], cov_formal[ic : ic + 2, ic : ic + 2])[0],
        "amplitude_hac": a_hac,
        "phase_hac": phase_hac,
        "annual_hac": annual,
    }
