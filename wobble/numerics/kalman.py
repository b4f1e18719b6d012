"""The Kalman filter of a time-invariant complex state-space model with one complex observation per step.

    x_k = F x_{k-1} + w_k,   w_k ~ CN(0, Q)
    y_k = h . x_k + v_k,     v_k ~ CN(0, r)                                   (1)

Circular complex Gaussian noise (real and imaginary parts independent, each of
half the variance) makes the complex filter exactly the real filter of twice
the dimension (the tests compare it with statsmodels' state-space models).

Two filters:

* :func:`filter_exact` - the textbook recursion (Durbin & Koopman 2012, sec.
  4.3) from a given prior, one step at a time: exact, slow (a Python loop);
* :func:`filter_steady` - the same with the steady-state gain of the discrete
  algebraic Riccati equation (:func:`steady_state`) from the first step, so
  that the filter is a fixed linear recursion x_k = A x_{k-1} + K y_k, run
  component by component in the Schur basis of A with
  :func:`scipy.signal.lfilter`. After the
  exact filter has converged the two agree (a test checks it); the first
  steps differ, so callers leave a burn-in out of the likelihood.

* :func:`window_filter` - the exact filter over a window of n steps from a
  prior (x0, P0), written as the fixed linear map it is: the last filtered
  state is sum_k G_k y_k + Phi x0 with weights G_k that depend on the model
  and n only (the covariance recursion does not see the data). One set of
  weights filters every window of the same length, so the filtered states at
  many issue dates are one matrix product.

Forecasts (:func:`forecast`) propagate the mean and covariance h steps ahead;
:func:`forecast_map` gives the rows h F^a that turn a state into the means.
Plain complex128 arrays; no units.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import linalg

__all__ = [
    "SteadyState",
    "RICCATI_TOLERANCE",
    "UNIT_CIRCLE_TOLERANCE",
    "steady_state",
    "filter_steady",
    "filter_exact",
    "WindowFilter",
    "window_filter",
    "forecast",
    "forecast_map",
    "log_likelihood",
]


@dataclass(frozen=True, eq=False)
class SteadyState:
    """The steady-state filter of model (1).

    Attributes
    ----------
    prior : ndarray
        Covariance of the one-step prediction, P = F P+ F^H + Q.
    posterior : ndarray
        Covariance after the update, P+ = P - K h P.
    gain : ndarray
        Kalman gain K = P h^H / S.
    innovation_variance : float
        S = h P h^H + r.
    """

    prior: np.ndarray
    posterior: np.ndarray
    gain: np.ndarray
    innovation_variance: float


#: How far outside the unit circle a closed-loop eigenvalue of :func:`filter_steady` may lie: modes the data
#: barely see (the mean pole and its rate) sit on the circle to rounding (1 + 5e-10 on the 1960s record);
#: (1 + 1e-6)^3653 = 1.004 over ten years of days, harmless, where an unstable filter overflows.
UNIT_CIRCLE_TOLERANCE = 1e-6
#: Relative residual of the Riccati equation above which :func:`steady_state` refines SciPy's solution.
RICCATI_TOLERANCE = 1e-11


def steady_state(F, Q, h, r) -> SteadyState:
    """Solve the filter's discrete algebraic Riccati equation (scipy.linalg.solve_discrete_are), refined.

    P = F (P - P h^H h P / S) F^H + Q, S = h P h^H + r. SciPy's Schur-based
    solution leaves relative residuals of 1e-10 for the first-order excitation
    but 2e-5 for a third-order one (companion-form states, eigenvectors
    conditioned ~1e6), enough to move innovations by 1e-4 mas; up to two
    Newton-Kleinman steps, each kept only if it lowers the residual (Hewer 1971, IEEE Trans. Autom. Control 16, 382:
    solve P = A_L P A_L^H + Q + r L L^H for the closed loop A_L = F - L h
    with the predictive gain L = F P h^H / S of the previous P) bring it to
    1e-12.
    """
    F = np.asarray(F, dtype=complex)
    h = np.asarray(h, dtype=complex)
    Q = np.asarray(Q, dtype=complex)
    r = float(r)
    P = linalg.solve_discrete_are(F.conj().T, h.conj()[:, None], Q, np.array([[r]]))
    P = 0.5 * (P + P.conj().T)
    residual = _riccati_residual(F, Q, h, r, P)
    for _ in range(2):
        if residual <= RICCATI_TOLERANCE:
            break
        L = F @ (P @ h.conj()) / float((h @ P @ h.conj()).real + r)
        # Bartels-Stewart on the bilinear transform: the Kronecker ("direct") solve is singular to rounding
        # when two modes of the closed loop sit near the unit circle (the mean pole and its rate).
        with warnings.catch_warnings():
            # SciPy warns when the closed loop's modes sit near the unit circle and it perturbs the
            # transformed problem; the residual check below judges the result either way.
            warnings.simplefilter("ignore", RuntimeWarning)
            refined = linalg.solve_discrete_lyapunov(
                F - np.outer(L, h), Q + r * np.outer(L, L.conj()), method="bilinear"
            )
        refined = 0.5 * (refined + refined.conj().T)
        new_residual = _riccati_residual(F, Q, h, r, refined)
        if not new_residual < residual:
            break  # keep the better solution
        P, residual = refined, new_residual
    S = float((h @ P @ h.conj()).real + r)
    K = P @ h.conj() / S
    post = P - np.outer(K, h @ P)
    return SteadyState(P, 0.5 * (post + post.conj().T), K, S)


def _riccati_residual(F, Q, h, r: float, P) -> float:
    """max |P' - P| / max |P| for P' the Riccati map of P (one prediction-update step)."""
    Ph = P @ h.conj()
    nxt = F @ (P - np.outer(Ph, Ph.conj()) / float((h @ Ph).real + r)) @ F.conj().T + Q
    return float(np.max(np.abs(nxt - P)) / np.max(np.abs(P)))


def filter_steady(F, ss: SteadyState, h, y, x0) -> tuple[np.ndarray, np.ndarray]:
    """Filtered states (n, m) and innovations (n,) of ``y`` with the steady-state gain, from the prior mean ``x0``.

    x+_k = A x+_{k-1} + K y_k with A = (I - K h) F and x+_{-1} = F^-1 x0 in
    effect (the first prediction is ``x0``). The recursion runs in the
    complex Schur basis of A (A = U T U^H, U unitary, T upper triangular):
    u_k = T u_{k-1} + U^H K y_k is solved component by component from the
    last, each a first-order recursion (compiled, scipy.signal.lfilter) whose
    input adds the coupling T[j, i>j] u_{k-1}[i] of the components already
    solved. A unitary basis keeps the rounding of the data's own size however
    close to defective A is; eigenvectors (the filter before) were
    conditioned up to 1e8 with a third-order excitation, and a step-by-step
    Python loop took over there, four times slower than the whole fit.
    """
    F = np.asarray(F, dtype=complex)
    h = np.asarray(h, dtype=complex)
    y = np.asarray(y, dtype=complex)
    x0 = np.asarray(x0, dtype=complex)
    K = ss.gain
    m = F.shape[0]
    A = (np.eye(m) - np.outer(K, h)) @ F
    # First filtered state from the given prediction x0, then the recursion.
    first = x0 + K * (y[0] - h @ x0)
    T, U = linalg.schur(A, output="complex")
    if not np.max(np.abs(np.diag(T))) <= 1.0 + UNIT_CIRCLE_TOLERANCE:
        # A Riccati solution that does not stabilise the filter (parameters far from any optimum): its
        # recursion would grow without bound, so the likelihood has no value there.
        raise ValueError("the steady-state filter is unstable: a closed-loop eigenvalue outside the unit circle")
    Uh = U.conj().T
    kicks = np.outer(y[1:], Uh @ K)  # (n-1, m) inputs per Schur component
    u = np.empty((y.size, m), dtype=complex)
    u[0] = Uh @ first
    from scipy.signal import lfilter  # (imported here: scipy.signal costs ~0.4 s to import)

    for j in range(m - 1, -1, -1):
        drive = kicks[:, j] + u[:-1, j + 1 :] @ T[j, j + 1 :]
        u[1:, j], _ = lfilter([1.0], [1.0, -T[j, j]], drive, zi=[T[j, j] * u[0, j]])
    xs = u @ U.T
    pred = np.empty(y.size, dtype=complex)
    pred[0] = h @ x0
    pred[1:] = (xs[:-1] @ F.T) @ h
    return xs, y - pred


def filter_exact(F, Q, h, r, y, x0, P0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The exact filter from the prior (x0, P0): filtered states (n, m), their covariances (n, m, m),
    innovations (n,) and innovation variances (n,)."""
    F = np.asarray(F, dtype=complex)
    Q = np.asarray(Q, dtype=complex)
    h = np.asarray(h, dtype=complex)
    y = np.asarray(y, dtype=complex)
    x = np.asarray(x0, dtype=complex).copy()
    P = np.asarray(P0, dtype=complex).copy()
    n, m = y.size, F.shape[0]
    xs = np.empty((n, m), dtype=complex)
    Ps = np.empty((n, m, m), dtype=complex)
    innov = np.empty(n, dtype=complex)
    svar = np.empty(n)
    for k in range(n):
        if k:
            x = F @ x
            P = F @ P @ F.conj().T + Q
        S = float((h @ P @ h.conj()).real + r)
        e = y[k] - h @ x
        K = P @ h.conj() / S
        x = x + K * e
        P = P - np.outer(K, h @ P)
        P = 0.5 * (P + P.conj().T)
        xs[k], Ps[k], innov[k], svar[k] = x, P, e, S
    return xs, Ps, innov, svar


def log_likelihood(innovations, variances) -> float:
    """Gaussian log-likelihood of complex innovations: -sum(ln(pi S) + |e|^2 / S)."""
    e = np.asarray(innovations)
    s = np.asarray(variances, dtype=float) * np.ones(e.shape)
    return float(-np.sum(np.log(math.pi * s) + np.abs(e) ** 2 / s))


def forecast(F, Q, h, r, x, P, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Means and variances (E|y - mean|^2, observation noise included) of y 1 .. ``steps`` ahead of state (x, P)."""
    F = np.asarray(F, dtype=complex)
    Q = np.asarray(Q, dtype=complex)
    h = np.asarray(h, dtype=complex)
    x = np.asarray(x, dtype=complex).copy()
    P = np.asarray(P, dtype=complex).copy()
    mean = np.empty(steps, dtype=complex)
    var = np.empty(steps)
    for k in range(steps):
        x = F @ x
        P = F @ P @ F.conj().T + Q
        mean[k] = h @ x
        var[k] = float((h @ P @ h.conj()).real + r)
    return mean, var


@dataclass(frozen=True, eq=False)
class WindowFilter:
    """The exact filter of model (1) over a window of n steps, as a linear map of the window's data.

    Attributes
    ----------
    weights : ndarray, shape (n, m)
        G_k: the last filtered state is x_{n-1|n-1} = sum_k G_k y_k + prior_map x0.
    prior_map : ndarray, shape (m, m)
        Phi: how the prior mean x0 (of the first state) enters the last filtered state.
    posterior : ndarray, shape (m, m)
        P_{n-1|n-1}, the covariance of the last filtered state.
    """

    weights: np.ndarray
    prior_map: np.ndarray
    posterior: np.ndarray


def window_filter(F, Q, h, r, P0, n: int) -> WindowFilter:
    """The exact filter (Durbin & Koopman 2012, sec. 4.3) over ``n`` steps from the prior (x0, P0), as fixed weights.

    The filter is x_0 = (I - K_0 h) x0 + K_0 y_0 and x_k = A_k x_{k-1} + K_k y_k
    with A_k = (I - K_k h) F; the gains K_k come from the covariance
    recursion alone, so x_{n-1} = sum_k B_k K_k y_k + B_0 (I - K_0 h) x0 with
    B_{n-1} = I and B_{k-1} = B_k A_k. Equal to :func:`filter_exact` on any
    data (a test checks it).
    """
    F = np.asarray(F, dtype=complex)
    Q = np.asarray(Q, dtype=complex)
    h = np.asarray(h, dtype=complex)
    P = np.asarray(P0, dtype=complex).copy()
    m = F.shape[0]
    FH = F.conj().T
    hH = h.conj()
    gains = np.empty((n, m), dtype=complex)
    for k in range(n):
        if k:
            P = F @ P @ FH + Q
        Ph = P @ hH
        K = Ph / (float((h @ Ph).real) + r)
        gains[k] = K
        P = P - np.outer(K, Ph.conj())
        P = 0.5 * (P + P.conj().T)
    # Backward: B_{k-1} = B_k (I - K_k h) F = B_k F - (B_k K_k)(h F), and the weight of y_k is B_k K_k.
    weights = np.empty((n, m), dtype=complex)
    hF = h @ F
    B = np.eye(m, dtype=complex)
    for k in range(n - 1, 0, -1):
        BK = B @ gains[k]
        weights[k] = BK
        B = B @ F - np.outer(BK, hF)
    weights[0] = B @ gains[0]
    return WindowFilter(weights, B - np.outer(weights[0], h), P)


def forecast_map(F, h, steps: int) -> np.ndarray:
    """Rows h F^a, a = 1 .. ``steps`` (steps, m): the forecast means of y are ``forecast_map @ x``."""
    F = np.asarray(F, dtype=complex)
    row = np.asarray(h, dtype=complex).copy()
    out = np.empty((steps, F.shape[0]), dtype=complex)
    for a in range(steps):
        row = row @ F
        out[a] = row
    return out
