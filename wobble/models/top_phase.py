"""The heavy top's phase diagram, many initial states at once (SI, float64; notes section 5.7).

For each member (I1, I3, M g l, theta0, thetadot0 = 0, phidot0, omega3) this
returns what :func:`wobble.models.top.heavy_top` reports about the motion: the
nutation class, the turning angles, the nutation period, the mean precession
rate and the stability of the sleeping top, vectorised with numpy.

The cubic (notes p. 71). With a = I3 omega3 / I1, beta = 2 M g l / I1,
b = phidot0 sin^2 theta0 + a u0, alpha = phidot0^2 sin^2 theta0 + beta u0,

    f(u) = beta u^3 - (alpha + a^2) u^2 + (2ab - beta) u + (alpha - b^2) = udot^2.

A top started with thetadot0 = 0 starts at a turning point u0 = cos theta0, so
f(u0) = 0 and, with d = u - u0, f = d g(d) where

    g(d) = beta d^2 + P d + Q,   P = 2 u0 beta - phidot0^2 sin^2 theta0 - a^2,
    Q = f'(u0) = sin^2 theta0 (2 a phidot0 - 2 u0 phidot0^2 - beta).

Q = 0 is regular precession (f = 0 and f' = 0 at u0: 2 u0 phidot^2 - 2 a phidot
+ beta = 0, the notes' condition). The other turning point is the smaller root
d_s of g (between the poles; the larger is u3 - u0 > 1 - u0), taken without
cancellation; the motion runs between u0 and u0 + d_s. With
disc = P^2 - 4 beta Q, beta (u3 - u1) is (-P + sqrt(disc))/2 for Q > 0 and
sqrt(disc) for Q < 0, m = (u2 - u1)/(u3 - u1), and

    nutation period   = 4 K(m) / sqrt(beta (u3 - u1)),
    mean precession   = (B <1/x> + C <1/y>) / 2,   x = 1 - u, y = 1 + u, B = b - a, C = b + a,
    <1/x> = Pi(n+|m) / (K x1),  <1/y> = Pi(n-|m) / (K y1),  n+ = (x1 - x2)/x1,  n- = -(x1 - x2)/y1,

with the complete integrals from Carlson's R_F and R_J (DLMF 19.25.1-2).

Classes (notes p. 72): phidot = (b - a u)/(1 - u^2) has the sign of b - a u; at
u0 that is phidot0 sin^2 theta0, at the other turning point phidot0 sin^2 theta0
- a d_s. Same signs: undulating; opposite: loops; zero at a turning point:
cusps (exactly when phidot0 = 0 with thetadot0 = 0, for beta > 0).

Borderline members go to the exact scalar model. The float64 formulas decide
the class only where the decision is far from its threshold; a member is
analysed by :func:`wobble.models.top.heavy_top` itself (50-digit roots, one
member at a time) when it is within a relative 1e-8 of regular precession
(``|Q|``; the exact model's threshold is 16 eps), within 1e-4 of a double root of g (the separatrix),
of a cusp at either turning point (or where rounding could flip the sign of phidot at the far turning point),
passes within 1e-6 (in 1 - cos) of a pole, or has thetadot0 != 0,
theta0 = 0 (sleeping) or theta0 = pi. Elsewhere the float64 results agree with
the exact model to about 1e-8 relative (1e-10 typically) (checked per grid point in
tests/test_sweep_top.py).
"""

from __future__ import annotations

import numpy as np
from scipy import special as _sp

from wobble.numerics.floats import EPS
from wobble.errors import InputError
from wobble.models import top as _top
from wobble.numerics import elliptic as ell

__all__ = ["NUTATION_CLASSES", "INVALID_REASONS", "phase_analysis"]

NUTATION_CLASSES = _top.NUTATION_CLASSES  # codes 0..4
INVALID_REASONS = {
    0: "",
    1: "bad top parameters: need I1 > 0, 0 < I3 <= 2 I1, M g l >= 0, all finite",
    2: "theta0 outside [0, pi] or a non-finite rate",
    3: "on (or within float64 of) the separatrix: the top creeps towards an unstable equilibrium for ever",
}
#: The share of its two terms below which the float64 mean precession rate has lost more than six digits.
_CANCEL = 1e-6
_MARGIN = 1e-4
_POLE = 1e-6
_REGULAR = 1e-8
_CODES = {name: i for i, name in enumerate(NUTATION_CLASSES)}


def _theta_of(x):
    """theta = 2 atan2(sqrt(x/2), sqrt(y/2)) from x = 1 - cos theta (accurate near both poles)."""
    return 2.0 * np.arctan2(np.sqrt(0.5 * x), np.sqrt(np.maximum(0.5 * (2.0 - x), 0.0)))


def _vectorised(I1, I3, mgl, theta0, phidot0, omega3):
    """Float64 analysis of members started at a turning point; ``hard`` marks the borderline ones."""
    a = I3 * omega3 / I1
    beta = 2.0 * mgl / I1
    sh = np.sin(0.5 * theta0)
    ch = np.cos(0.5 * theta0)
    x0, y0 = 2.0 * sh * sh, 2.0 * ch * ch
    s2 = x0 * y0  # sin^2 theta0
    u0 = np.cos(theta0)
    v = phidot0 * s2  # b - a u0: the sign of phidot at u0
    P = 2.0 * u0 * beta - phidot0 * phidot0 * s2 - a * a
    Q = s2 * (2.0 * a * phidot0 - 2.0 * u0 * phidot0 * phidot0 - beta)
    q_scale = s2 * (2.0 * np.abs(a * phidot0) + 2.0 * np.abs(u0) * phidot0 * phidot0 + beta)
    disc = P * P - 4.0 * beta * Q
    root = np.sqrt(np.maximum(disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        d_s = np.where(P <= 0, 2.0 * Q / (-P + root), -(P + root) / (2.0 * np.where(beta > 0, beta, 1.0)))
        x_o, y_o = x0 - d_s, y0 + d_s  # the other turning point (x = 1 - u, y = 1 + u)
        n_o = v - a * d_s  # b - a u there
        big_b, big_c = v - a * x0, v + a * y0  # b - a and b + a
        scale0 = np.where(x0 <= 1, np.abs(big_b) + np.abs(a * x0), np.abs(big_c) + np.abs(a * y0))
        scale_o = np.where(x_o <= 1, np.abs(big_b) + np.abs(a * x_o), np.abs(big_c) + np.abs(a * y_o))
        x1, x2 = np.maximum(x0, x_o), np.minimum(x0, x_o)
        hard = (
            (np.abs(Q) <= _REGULAR * q_scale)  # near regular precession
            | (disc <= _MARGIN * (P * P + 4.0 * beta * np.abs(Q)))  # near the separatrix
            | ((v != 0) & (np.abs(v) <= _MARGIN * scale0))  # near a cusp at u0
            | (np.abs(n_o) <= _MARGIN * scale_o)  # near a cusp at the other turning point
            | (np.abs(n_o) <= 1e3 * EPS * (np.abs(v) + np.abs(a * d_s)))  # its sign lost in rounding
            | (x2 <= _POLE * x1)  # next to the upward vertical
            | (np.minimum(y0, y_o) <= _POLE * np.maximum(y0, y_o))  # next to the bottom
            | (np.abs(d_s) <= _MARGIN * x1)  # a nutation too small for float64 rounding of x
            | ~np.isfinite(d_s)
            | (theta0 <= 0)
            | (theta0 >= np.pi)
        )
        # beta (u3 - u1), m and 1 - m without cancellation (module docstring).
        up = Q > 0  # u0 is the lower turning point u1: the axis rises first
        w = -P + root  # > 0 for P <= 0
        pos_p = P > 0
        beta_ds = np.where(pos_p, -(P + root) / 2.0, 2.0 * beta * Q / w)
        beta_dl = np.where(pos_p, -2.0 * beta * Q / (P + root), w / 2.0)
        span = np.where(up, beta_dl, root)
        m = np.where(up, beta_ds / beta_dl, -beta_ds / root)
        m1 = np.where(up, root / beta_dl, beta_dl / root)
        m = np.where(beta > 0, m, 0.0)
        m1 = np.where(beta > 0, m1, 1.0)
        span = np.where(beta > 0, span, -P)
        # Harmless stand-ins where the member goes to the exact model (replaced there).
        m, m1, span = np.where(hard, 0.5, m), np.where(hard, 0.5, m1), np.where(hard, 1.0, span)
        x1, x2 = np.where(hard, 1.0, x1), np.where(hard, 0.5, x2)
        K = _sp.elliprf(0.0, m1, 1.0)
        period = 4.0 * K / np.sqrt(span)
        y1 = 2.0 - x1
        width = x1 - x2
        pi_plus = K + (width / x1 / 3.0) * _sp.elliprj(0.0, m1, 1.0, x2 / x1)
        # Pi(n-|m), n- <= 0, in positive terms (wobble.numerics.elliptic.ellippi).
        pi_minus = ell.ellippi(-width / y1, m, m1)
        plus, minus = big_b * pi_plus / (K * x1), big_c * pi_minus / (K * y1)
        mean_phidot = 0.5 * (plus + minus)
        # The two terms are each about a/2 and their sum the slow precession: under weak gravity they cancel
        # (as in the exact model's 50-digit set-up, which forms the mean without it). Members that lose more than
        # six of float64's digits there go to the exact model, with the others its turning points need.
        hard = hard | (np.abs(plus + minus) <= _CANCEL * (np.abs(plus) + np.abs(minus)))
        s_start = np.sign(v)
        s_other = np.sign(n_o)
        code = np.where(
            (s_start == 0) | (s_other == 0),
            _CODES["cusps"],
            np.where(s_start == s_other, _CODES["undulating"], _CODES["loops"]),
        )
    with np.errstate(invalid="ignore"):  # hard members only (replaced by the exact model)
        theta_o = _theta_of(x_o)
    theta_min = np.where(x0 <= x_o, theta0, theta_o)
    theta_max = np.where(x0 <= x_o, theta_o, theta0)
    return {
        "nutation_class": code.astype(np.int8),
        "nutation_period": period,
        "theta_min": theta_min,
        "theta_max": theta_max,
        "mean_precession_rate": mean_phidot,
    }, hard


def phase_analysis(I1, I3, mgl, theta0, omega3, phidot0=0.0, thetadot0=0.0) -> dict[str, np.ndarray]:
    """Nutation class, turning angles, period and mean precession of many heavy tops (notes section 5.7).

    All arguments broadcast against each other (SI: kg m^2, J, rad, rad/s).

    Parameters
    ----------
    I1, I3 : array_like
        Moments about the tip (kg m^2).
    mgl : array_like
        M g l (J).
    theta0 : array_like
        Initial tilt from the upward vertical (rad), in [0, pi].
    omega3 : array_like
        Spin about the symmetry axis (rad/s).
    phidot0, thetadot0 : array_like
        Initial precession and nutation rates (rad/s). Members with
        thetadot0 != 0 are analysed by the exact scalar model.

    Returns
    -------
    dict of numpy.ndarray
        ``nutation_class`` (int8 index into :data:`NUTATION_CLASSES`, -1 when
        invalid), ``nutation_period`` (s), ``theta_min``, ``theta_max`` (rad),
        ``mean_precession_rate`` (rad/s), ``sleeping_stable`` (bool: I3^2
        omega3^2 > 4 M g l I1, Kibble & Berkshire eq. 12.26), ``invalid_reason``
        (int8, :data:`INVALID_REASONS`) and ``scalar_fallback`` (bool: the
        member was analysed by :func:`wobble.models.top.heavy_top`).
    """
    arrays = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (I1, I3, mgl, theta0, omega3, phidot0, thetadot0))
    )
    shape = arrays[0].shape
    i1, i3, mg, th, w3, pd, td = (x.ravel() for x in arrays)
    n = i1.size
    with np.errstate(invalid="ignore"):
        bad_top = ~(
            np.isfinite(i1)
            & np.isfinite(i3)
            & np.isfinite(mg)
            & (i1 > 0)
            & (i3 > 0)
            & (mg >= 0)
            & (i3 <= 2 * i1 * (1 + 8 * EPS))
        )
        bad_state = ~(np.isfinite(th) & (th >= 0) & (th <= np.pi) & np.isfinite(w3) & np.isfinite(pd) & np.isfinite(td))
    reason = np.where(bad_top, 1, np.where(bad_state, 2, 0)).astype(np.int8)
    ok = reason == 0
    out = {
        "nutation_class": np.full(n, -1, dtype=np.int8),
        "nutation_period": np.full(n, np.nan),
        "theta_min": np.full(n, np.nan),
        "theta_max": np.full(n, np.nan),
        "mean_precession_rate": np.full(n, np.nan),
    }
    with np.errstate(all="ignore"):
        lhs = (i3 * w3) ** 2
        rhs = 4.0 * mg * i1
        stable = lhs > rhs
    near = ok & (np.abs(lhs - rhs) <= 1e-12 * (lhs + rhs))
    for j in np.flatnonzero(near):
        stable[j] = _top.sleeping_top_stable(i1[j], i3[j], mg[j], w3[j])
    fallback = ok & (td != 0)
    easy = np.flatnonzero(ok & (td == 0))
    if easy.size:
        res, hard = _vectorised(i1[easy], i3[easy], mg[easy], th[easy], pd[easy], w3[easy])
        keep = easy[~hard]
        for key, vals in res.items():
            out[key][keep] = vals[~hard]
        fallback[easy[hard]] = True
    for j in np.flatnonzero(fallback):  # the scalar exact model, one member at a time
        try:
            model = _top.heavy_top(i1[j], i3[j], mg[j], th[j], thetadot0=td[j], phidot0=pd[j], omega3=w3[j])
        except InputError:
            reason[j] = 3
            continue
        out["nutation_class"][j] = _CODES[model.nutation]
        out["nutation_period"][j] = model.nutation_period
        out["theta_min"][j] = model.theta_min
        out["theta_max"][j] = model.theta_max
        out["mean_precession_rate"][j] = model.mean_precession_rate
    out["sleeping_stable"] = stable & ok
    out["invalid_reason"] = reason
    out["scalar_fallback"] = fallback & (reason == 0)
    return {k: v.reshape(shape) for k, v in out.items()}
