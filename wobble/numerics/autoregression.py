"""Autoregressive models of a real series: conditional least squares, order by AIC, forecasts with their variance.

An AR(p) model with a constant,

    y_t = c + a_1 y_{t-1} + ... + a_p y_{t-p} + e_t,    e_t ~ N(0, s^2),        (1)

is fitted by ordinary least squares on the lagged values (the conditional
maximum-likelihood estimate; statsmodels' ``AutoReg`` computes the same, and
the tests compare the two). The h-step forecast follows (1) with future
shocks set to zero; its error variance is s^2 (psi_0^2 + ... + psi_{h-1}^2)
with the psi weights of the MA(infinity) form (Box & Jenkins 1976, ch. 5).
Plain float64 arrays; no units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ARFit", "fit_ar", "is_stationary", "select_ar", "ar_forecast"]


@dataclass(frozen=True, eq=False)
class ARFit:
    """An AR(p) fit of equation (1).

    Attributes
    ----------
    const : float
        The constant c.
    coeffs : ndarray, shape (p,)
        a_1 .. a_p.
    sigma2 : float
        Variance of the innovations, the residual sum of squares over the
        number of fitted values (the maximum-likelihood estimate, as AutoReg's
        ``sigma2``).
    nobs : int
        Number of values fitted (the series length minus p).
    aic : float
        Akaike's criterion of the conditional likelihood, ln sigma2 + 2 (p + 1) / nobs
        (per observation; compared between orders on the same sample).
    """

    const: float
    coeffs: np.ndarray
    sigma2: float
    nobs: int
    aic: float

    @property
    def order(self) -> int:
        return int(self.coeffs.size)


def _design(y: np.ndarray, p: int, skip: int) -> tuple[np.ndarray, np.ndarray]:
    """Rows t = skip .. n-1 of [1, y_{t-1}, ..., y_{t-p}] and the targets y_t."""
    n = y.size
    x = np.empty((n - skip, p + 1))
    x[:, 0] = 1.0
    for j in range(1, p + 1):
        x[:, j] = y[skip - j : n - j]
    return x, y[skip:]


def fit_ar(y, p: int, *, skip: int | None = None) -> ARFit:
    """Equation (1) of order ``p`` by least squares (``skip`` first values used only as lags; default p)."""
    y = np.asarray(y, dtype=float)
    skip = p if skip is None else skip
    if p < 0 or skip < p or y.size - skip < p + 2:
        raise ValueError(f"AR({p}) needs more than {skip + p + 2} values, got {y.size}")
    x, target = _design(y, p, skip)
    beta, *_ = np.linalg.lstsq(x, target, rcond=None)
    resid = target - x @ beta
    nobs = target.size
    sigma2 = float(resid @ resid) / nobs
    return ARFit(float(beta[0]), beta[1:].copy(), sigma2, nobs, math.log(sigma2) + 2.0 * (p + 1) / nobs)


def is_stationary(coeffs) -> bool:
    """Whether y_t = a_1 y_{t-1} + ... + a_p y_{t-p} + e_t is stationary: every root of
    z^p - a_1 z^{p-1} - ... - a_p (the companion matrix's eigenvalues) strictly inside the unit circle."""
    c = np.asarray(coeffs, dtype=float)
    return c.size == 0 or bool(np.max(np.abs(np.roots(np.r_[1.0, -c]))) < 1.0)


def select_ar(y, max_order: int) -> ARFit:
    """The stationary AR fit of order 1 to ``max_order`` with the smallest AIC, every order compared on the same values.

    The models are nested (order p uses the first p + 1 columns of the design
    of order ``max_order``), so one QR decomposition gives every residual sum
    of squares: RSS_p = |y|^2 - |(Q^T y)_{0..p}|^2, with Q^T y the last column
    of R for the design augmented by y (Q itself is never formed). The orders
    are refitted on all the values they can use, least AIC first, until a fit
    is stationary (:func:`is_stationary`): least squares does not guarantee it,
    and an explosive fit's forecast grows without bound (a root of 1.08 is
    1e12 after a year). Without any stationary order, AR(0): the mean.
    """
    y = np.asarray(y, dtype=float)
    x, target = _design(y, max_order, max_order)
    nobs = target.size
    if nobs < max_order + 2:
        raise ValueError(f"AR({max_order}) needs more than {2 * max_order + 2} values, got {y.size}")
    r = np.linalg.qr(np.column_stack([x, target]), mode="r")
    proj = np.cumsum(r[:-1, -1] ** 2)
    rss = np.maximum(float(target @ target) - proj[1:], np.finfo(float).tiny)  # orders 1 .. max_order
    orders = np.arange(1, max_order + 1)
    aic = np.log(rss / nobs) + 2.0 * (orders + 1) / nobs
    for p in orders[np.argsort(aic, kind="stable")]:
        fit = fit_ar(y, int(p))
        if is_stationary(fit.coeffs):
            return fit
    return fit_ar(y, 0)


def ar_forecast(fit: ARFit, history, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Forecasts 1 .. ``steps`` ahead from the last values of ``history``, and their error variances.

    Both are the recursion (1) run as a linear filter (:func:`scipy.signal.lfilter`):
    the means with the constant as input and the history as initial state, the
    psi weights as the impulse response of 1 / (1 - a_1 L - ... - a_p L^p).
    """
    from scipy.signal import lfilter  # (imported here: scipy.signal costs ~0.4 s to import)

    p = fit.order
    c = np.asarray(fit.coeffs, dtype=float)
    a = np.r_[1.0, -c]
    drive = np.full(steps, float(fit.const))
    if p:
        past = np.asarray(history, dtype=float)[-p:][::-1]  # y_{t-1}, y_{t-2}, ...
        # The filter's initial state (transposed direct form II): zi_k = sum_{j > k} a_j y_{t-(j-k)}.
        zi = np.array([c[k:] @ past[: p - k] for k in range(p)])
        out, _ = lfilter([1.0], a, drive, zi=zi)
    else:
        out = drive
    impulse = np.zeros(steps)
    impulse[0] = 1.0
    psi = lfilter([1.0], a, impulse)
    return out, fit.sigma2 * np.cumsum(psi**2)
