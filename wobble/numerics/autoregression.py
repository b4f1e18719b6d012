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

__all__ = ["ARFit", "fit_ar", "select_ar", "ar_forecast"]


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


def select_ar(y, max_order: int) -> ARFit:
    """The AR order from 1 to ``max_order`` with the smallest AIC, every order fitted on the same values."""
    fits = [fit_ar(y, p, skip=max_order) for p in range(1, max_order + 1)]
    best = min(fits, key=lambda f: f.aic)
    return fit_ar(y, best.order)


def ar_forecast(fit: ARFit, history, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Forecasts 1 .. ``steps`` ahead from the last values of ``history``, and their error variances."""
    p = fit.order
    hist = list(np.asarray(history, dtype=float)[-p:]) if p else []
    out = np.empty(steps)
    for h in range(steps):
        value = fit.const + sum(fit.coeffs[j] * hist[-1 - j] for j in range(p))
        out[h] = value
        hist.append(value)
    psi = np.zeros(steps)
    psi[0] = 1.0
    for h in range(1, steps):
        psi[h] = sum(fit.coeffs[j] * psi[h - 1 - j] for j in range(min(p, h)))
    return out, fit.sigma2 * np.cumsum(psi**2)
