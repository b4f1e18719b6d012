"""Measuring precession and nutation from a time series of the spin-axis direction.

Given unit vectors s(t) of the spin axis (or of the angular momentum) in an
inertial ecliptic frame (z the pole of the reference plane, x its origin of
longitudes), the axis' obliquity and the longitude of the ascending node of its
equator are

    eps = arccos(s_z),   psi = atan2(s_x, -s_y)                               (1)

(s = (sin eps sin psi, -sin eps cos psi, cos eps)). Both are fitted by linear
least squares to

    psi(t) = psi_0 + psi_dot t + sum_k [a_k sin(theta_k) + b_k cos(theta_k)]
    eps(t) = eps_0 + eps_dot t + sum_k [c_k sin(theta_k) + d_k cos(theta_k)]  (2)

with theta_k = phase_k + rate_k t: the node of the perturber (18.6 yr for the
Moon) and any other argument the caller names (2 L_sun, semi-annual; 2 L_moon,
fortnightly). The principal nutation is reported in the IAU convention
(Delta psi = -(psi - mean), so Delta psi = A sin Omega with A < 0 for Earth;
Delta eps = B cos Omega), the secular rate in the node-longitude convention
of :mod:`wobble.models.precession` (negative: retrograde).

Standard errors come from the residual scatter (ordinary least squares); they
describe the fit, not a physical uncertainty. SI throughout (s, rad).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from wobble.errors import InputError

__all__ = ["axis_angles", "check_times", "PrecessionFit", "fit_precession_nutation", "synthetic_axis"]


def axis_angles(axis) -> tuple[np.ndarray, np.ndarray]:
    """Equation (1): (psi, eps) in rad from unit axis vectors of shape (N, 3); psi unwrapped."""
    s = np.asarray(axis, dtype=float)
    if s.ndim != 2 or s.shape[1] != 3:
        raise InputError("axis", f"shape {s.shape}", "unit vectors of shape (N, 3)")
    norm = np.linalg.norm(s, axis=1)
    if not np.all(np.isfinite(norm)) or np.any(np.abs(norm - 1.0) > 1e-6):
        raise InputError("axis", "vectors of length != 1", "unit vectors (normalise them first)")
    s = s / norm[:, None]
    eps = np.arccos(np.clip(s[:, 2], -1.0, 1.0))
    if np.any(np.sin(eps) < 1e-8):
        raise InputError(
            "axis",
            "an axis along the reference pole",
            "an obliquity away from 0 and 180 deg (the node is undefined there)",
        )
    psi = np.unwrap(np.arctan2(s[:, 0], -s[:, 1]))
    return psi, eps


def synthetic_axis(times, psi, eps) -> np.ndarray:
    """Unit vectors from node longitude and obliquity (the inverse of equation 1), shape (N, 3)."""
    psi = np.asarray(psi, dtype=float) + 0.0 * np.asarray(times, dtype=float)
    eps = np.asarray(eps, dtype=float) + 0.0 * psi
    return np.stack([np.sin(eps) * np.sin(psi), -np.sin(eps) * np.cos(psi), np.cos(eps)], axis=-1)


@dataclass(frozen=True)
class PrecessionFit:
    """Result of :func:`fit_precession_nutation` (SI: rad, s).

    Attributes
    ----------
    rate, rate_sigma : float
        Secular rate of the node longitude psi (negative: retrograde), rad/s.
    obliquity, obliquity_rate : float
        eps at t = 0 (rad) and its secular rate (rad/s).
    nutation_longitude, nutation_obliquity : float
        IAU-convention amplitudes of the principal term: Delta psi = A sin(Omega),
        Delta eps = B cos(Omega), rad.
    nutation_longitude_sigma, nutation_obliquity_sigma : float
        Their standard errors, rad.
    nutation_longitude_out_of_phase, nutation_obliquity_out_of_phase : float
        The cos(Omega) part of Delta psi and the sin(Omega) part of Delta eps, rad.
    terms : dict
        Every other named argument: name -> (psi sin, psi cos, eps sin, eps cos)
        amplitudes in the IAU convention, rad.
    residual_rms_longitude, residual_rms_obliquity : float
        RMS of the fit residuals, rad.
    """

    rate: float
    rate_sigma: float
    obliquity: float
    obliquity_rate: float
    nutation_longitude: float
    nutation_obliquity: float
    nutation_longitude_sigma: float
    nutation_obliquity_sigma: float
    nutation_longitude_out_of_phase: float
    nutation_obliquity_out_of_phase: float
    residual_rms_longitude: float
    residual_rms_obliquity: float
    terms: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)


def check_times(times) -> np.ndarray:
    """``times`` as float64 (s), refused unless at least 8 finite, strictly increasing values: what a fit of the
    secular line and one periodic term needs, at the least."""
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size < 8 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise InputError("times", f"{t.size} samples", "at least 8 finite, strictly increasing times in s")
    return t


def _design(t, arguments):
    cols = [np.ones_like(t), t]
    for rate, phase in arguments:
        theta = phase + rate * t
        cols += [np.sin(theta), np.cos(theta)]
    return np.stack(cols, axis=1)


def _solve(design, y):
    # Columns scaled to unit RMS so that the secular column (t ~ 1e9 s) and the
    # periodic ones (~1) are equally conditioned.
    scale = np.sqrt(np.mean(design**2, axis=0))
    scale[scale == 0] = 1.0
    a = design / scale
    coef, _, rank, _ = np.linalg.lstsq(a, y, rcond=None)
    if rank < a.shape[1]:
        raise InputError(
            "times",
            "a span that cannot separate the terms",
            "a series longer than the longest period fitted, sampled often enough",
        )
    resid = y - a @ coef
    dof = max(len(y) - a.shape[1], 1)
    s2 = float(resid @ resid) / dof
    cov = s2 * np.linalg.inv(a.T @ a)
    return coef / scale, np.sqrt(np.diag(cov)) / scale, float(np.sqrt(np.mean(resid**2)))


def fit_precession_nutation(
    times,
    axis,
    node_rate: float,
    node_phase: float = 0.0,
    extra: Mapping[str, tuple[float, float]] | None = None,
) -> PrecessionFit:
    """Least-squares fit of equation (2) to a spin-axis series.

    Parameters
    ----------
    times : array_like, shape (N,)
        Times in s (increasing; any origin: the fit's t = 0 is ``times``' zero).
    axis : array_like, shape (N, 3)
        Unit spin-axis (or angular-momentum) vectors in the inertial ecliptic frame.
    node_rate : float
        Rate of the perturber's node longitude Omega, rad/s (the Moon: -1.07e-8).
    node_phase : float
        Omega at t = 0, rad (counted from the frame's x axis).
    extra : mapping, optional
        Other arguments to fit: name -> (rate rad/s, phase at t = 0 rad).

    Returns
    -------
    PrecessionFit
    """
    t = check_times(times)
    if not (math.isfinite(node_rate) and node_rate != 0):
        raise InputError("node_rate", node_rate, "a non-zero, finite rate in rad/s")
    psi, eps = axis_angles(axis)
    if psi.shape[0] != t.size:
        raise InputError("axis", f"{psi.shape[0]} vectors for {t.size} times", "one axis vector per time")
    names = list(extra or {})
    arguments = [(node_rate, node_phase)] + [tuple(map(float, (extra or {})[n])) for n in names]
    design = _design(t, arguments)
    cp, sp, rms_p = _solve(design, psi)
    ce, se, rms_e = _solve(design, eps)
    # IAU convention: Delta psi counts westward, the opposite of the node longitude.
    terms = {n: (-cp[4 + 2 * i], -cp[5 + 2 * i], ce[4 + 2 * i], ce[5 + 2 * i]) for i, n in enumerate(names)}
    return PrecessionFit(
        rate=float(cp[1]),
        rate_sigma=float(sp[1]),
        obliquity=float(ce[0]),
        obliquity_rate=float(ce[1]),
        nutation_longitude=float(-cp[2]),
        nutation_obliquity=float(ce[3]),
        nutation_longitude_sigma=float(sp[2]),
        nutation_obliquity_sigma=float(se[3]),
        nutation_longitude_out_of_phase=float(-cp[3]),
        nutation_obliquity_out_of_phase=float(ce[2]),
        residual_rms_longitude=rms_p,
        residual_rms_obliquity=rms_e,
        terms={k: tuple(float(x) for x in v) for k, v in terms.items()},
    )
