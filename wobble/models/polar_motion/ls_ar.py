"""The operational baseline: least squares of trend + Chandler + annual + semi-annual terms, AR of the residuals.

The LS+AR scheme of the IERS Rapid Service and of most entries of the EOP
prediction comparison campaigns (Kosek et al. 1998; Kalarus et al. 2010):

    p(t) = c_0 + c_1 s + A_c e^{i sigma_c s}
           + sum_{k=1,2} (A_k+ e^{i k Omega_a s} + A_k- e^{-i k Omega_a s}) + r(t)   (1)

with s = t - t_last in years, fitted by complex linear least squares over the
last ``ls_span`` of the information set (the Chandler frequency sigma_c is not
fitted here: it is wobble's own estimate, passed in), and the residuals'
components r_x, r_y each modelled by an AR(p) process (order by AIC up to
``max_order``) on their last ``ar_span``; the forecast is the LS extrapolation
plus the AR forecasts. Its variance is the AR forecast error variance
(:func:`wobble.numerics.autoregression.ar_forecast`) plus that of the LS
extrapolation, from the coefficients' sandwich covariance with the residuals'
autocorrelation over a year (Newey & West 1987, the estimator of
:mod:`.uncertainty`): after a month the extrapolation's error dominates, and
the AR variance alone would give intervals far too narrow. The LS
extrapolation alone is the ``baseline`` (skill reference). Times in s, angles
in rad.
"""

from __future__ import annotations

import numpy as np

from wobble.models.polar_motion.forecast import Forecast, PastForecasts, daily, information_set
from wobble.models.polar_motion.record import ANNUAL_RATE, DAY, pole_xy
from wobble.models.polar_motion.uncertainty import hac_meat
from wobble.numerics.autoregression import ARFit, ar_forecast, select_ar
from wobble.numerics.threads import one_blas_thread

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = ["LS_SPAN", "AR_SPAN", "MAX_ORDER", "harmonic_columns", "forecast_ls_ar", "past_forecasts_ls_ar"]

#: Default fitting span of the least squares: six years (Chao 1985's optimum base for polar-motion prediction).
LS_SPAN = 6.0 * JULIAN_YEAR
#: Default span of residuals the AR model is fitted to.
AR_SPAN = 3.0 * JULIAN_YEAR
#: Highest AR order tried.
MAX_ORDER = 30


def harmonic_columns(s, chandler_rate: float) -> np.ndarray:
    """The columns of equation (1) at times ``s`` (s from the last sample): 1, s/yr, Chandler, +/- annual,
    +/- semi-annual."""
    s = np.asarray(s, dtype=float)
    cols = [np.ones_like(s), s / JULIAN_YEAR, np.exp(1j * chandler_rate * s)]
    for k in (1, 2):
        cols += [np.exp(1j * k * ANNUAL_RATE * s), np.exp(-1j * k * ANNUAL_RATE * s)]
    return np.stack(cols, axis=1).astype(complex)


def _extrapolation_variance(
    t, cols, resid, future_cols, carried, lag: float = JULIAN_YEAR
) -> tuple[np.ndarray, np.ndarray]:
    """Variances of x_p and y_p of the LS extrapolation's error that the AR forecast does not carry.

    An error d of the coefficients misplaces the pole by c(t) . d; the residuals
    end with -c(t_last) . d, which the AR carries forward by the factor
    ``carried[k]`` (its forecast of a constant offset; per component), so the
    forecast's error is (c(t) - carried c(t_last)) . d. Its variance uses the
    coefficients' sandwich covariance with the residuals' autocorrelation over
    ``lag`` (Newey & West 1987, fixed-b corrected as in :mod:`.uncertainty`).
    """
    # Real parameters (Re a_j, Im a_j); d model / d Re a_j = c_j, d model / d Im a_j = i c_j.
    jac = np.concatenate([cols, 1j * cols], axis=1)
    bread = np.linalg.inv((jac.conj().T @ jac).real)
    scores = (jac.conj() * resid[:, None]).real
    b = min(lag / (t[-1] - t[0]), 1.0)
    cov = bread @ hac_meat(t, scores, lag) @ bread / (1.0 - b + b * b / 3.0)
    g = np.concatenate([future_cols, 1j * future_cols], axis=1)  # d forecast / d parameters, complex
    g_last = np.concatenate([cols[-1], 1j * cols[-1]])
    gx = g.real - carried[0][:, None] * g_last.real[None, :]  # x_p = Re p
    gy = -g.imag + carried[1][:, None] * g_last.imag[None, :]  # y_p = -Im p
    return np.einsum("ij,jk,ik->i", gx, cov, gx), np.einsum("ij,jk,ik->i", gy, cov, gy)


@one_blas_thread
def forecast_ls_ar(
    t,
    z,
    issued: float,
    horizon_days: int,
    *,
    chandler_period: float,
    latency: float = DAY,
    ls_span: float = LS_SPAN,
    ar_span: float = AR_SPAN,
    max_order: int = MAX_ORDER,
) -> Forecast:
    """Forecast the pole 1 .. ``horizon_days`` days after ``issued`` with LS+AR (equation 1).

    Parameters
    ----------
    t, z : ndarray
        The record: times (s) and the pole p = x_p - i y_p (rad), daily.
    issued : float
        Issue time, s; only samples up to ``issued - latency`` are used.
    horizon_days : int
        Number of daily lead times.
    chandler_period : float
        The Chandler period of the LS term, s (wobble's estimate from the data
        before the issue date).
    latency, ls_span, ar_span : float
        Publication delay of the record, LS fitting span and AR span, s.
    max_order : int
        Highest AR order tried (AIC).
    """
    ti, zi = information_set(t, z, issued, latency, ls_span, "LS+AR")
    daily(ti, "LS+AR")
    rate = 2 * np.pi / chandler_period
    s = ti - ti[-1]
    cols = harmonic_columns(s, rate)
    coeffs, *_ = np.linalg.lstsq(cols, zi, rcond=None)
    resid = zi - cols @ coeffs
    rx, ry = pole_xy(resid)
    tail = s >= s[-1] - ar_span
    lead = DAY * np.arange(1, horizon_days + 1)
    ahead = np.rint((issued + lead - ti[-1]) / DAY).astype(int)  # steps past the last sample
    steps = int(ahead[-1])
    fits, means, variances, carried = [], [], [], []
    for r in (rx[tail], ry[tail]):
        fit = select_ar(r, max_order)
        m, v = ar_forecast(fit, r, steps)
        fits.append(fit)
        means.append(m[ahead - 1])
        variances.append(v[ahead - 1])
        # How the AR carries a constant offset of the residuals forward (no constant term).
        offset = ARFit(0.0, fit.coeffs, fit.sigma2, fit.nobs, fit.aic)
        carried.append(ar_forecast(offset, np.ones(max(fit.order, 1)), steps)[0][ahead - 1])
    future_cols = harmonic_columns(issued + lead - ti[-1], rate)
    ls_future = future_cols @ coeffs
    mean = ls_future + (means[0] - 1j * means[1])
    var_lx, var_ly = _extrapolation_variance(ti, cols, resid, future_cols, carried)
    sigma_x, sigma_y = np.sqrt(variances[0] + var_lx), np.sqrt(variances[1] + var_ly)
    return Forecast(
        method="ls_ar",
        issued=float(issued),
        last_data=float(ti[-1]),
        lead=lead,
        mean=mean,
        sigma_x=sigma_x,
        sigma_y=sigma_y,
        baseline=ls_future,
        details={
            "ls_span_days": ls_span / DAY,
            "ar_span_days": ar_span / DAY,
            "ar_order_x": fits[0].order,
            "ar_order_y": fits[1].order,
            "chandler_period_days": chandler_period / DAY,
            "ls_residual_rms_mas": float(np.sqrt(np.mean(np.abs(resid) ** 2))) / (np.pi / 648e6),
        },
    )


@one_blas_thread
def past_forecasts_ls_ar(t, z, issues, horizon_days: int, *, chandler_period: float, latency: float = DAY, **kwargs):
    """The forecasts :func:`forecast_ls_ar` issues at each of ``issues`` (a :class:`~.forecast.PastForecasts`)."""
    issues = np.asarray(issues, dtype=float)
    fs = [
        forecast_ls_ar(t, z, s, horizon_days, chandler_period=chandler_period, latency=latency, **kwargs)
        for s in issues
    ]
    mean = np.array([f.mean for f in fs], dtype=complex).reshape(issues.size, horizon_days)
    sigma = np.array([np.stack([f.sigma_x, f.sigma_y], axis=1) for f in fs]).reshape(issues.size, horizon_days, 2)
    return PastForecasts(issues, mean, sigma)
