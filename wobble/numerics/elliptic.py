"""Jacobi elliptic functions and elliptic integrals in float64, with m1 = 1 - m given.

Every function takes the parameter ``m`` (= k^2) **and** its complement
``m1 = 1 - m`` supplied by the caller. Near the separatrix of a free rigid body
m is within 1e-12 of 1, and a float64 ``m`` has then already lost the digits of
``1 - m`` that decide the answer; callers that know ``m1`` from the physics
(e.g. ``m1 = (I3-I1)(L^2-2EI2) / ((I3-I2)(L^2-2EI1))``) pass it here and keep
them. When ``m1`` is omitted it is taken as ``1 - m`` (exact for m >= 1/2).

Algorithms
----------
* Complete K(m): the arithmetic-geometric mean started from ``sqrt(m1)``
  (Abramowitz & Stegun 17.6), so K keeps full relative accuracy down to
  ``m1 = 1e-300`` and for ``m`` near 0.
* sn, cn, dn, am: argument reduction modulo 2K with a two-piece (Cody-Waite)
  split of 2K; the quarter period is folded to ``[0, K/2]`` with the exact
  identities ``sn(K-w) = cn w/dn w``, ``cn(K-w) = k' sn w/dn w``,
  ``dn(K-w) = k'/dn w`` (A&S 16.8), so that cn and dn keep their *relative*
  accuracy next to u = K even when they are of size ``sqrt(m1)``; then the
  descending Landen (AGM) recurrence for the amplitude (A&S 16.4.3), and
  ``dn = sqrt(m1 + m cn^2)`` (no cancellation). This is the method that
  fails in scipy.special.ellipj for ``1 - m < 1e-9`` and u > K (scipy issue
  #8480: scipy switches to a near-unity series valid only for u < K).
* Incomplete integrals: Carlson's symmetric forms (scipy.special.elliprf,
  elliprd, elliprj, elliprc) written with only positive terms, using
  ``Delta^2 = 1 - m sin^2 phi = cos^2 phi + m1 sin^2 phi``:
  F = s R_F(c^2, Delta^2, 1) (DLMF 19.25.5);
  E = m1 F + (m m1/3) s^3 R_D(c^2, 1, Delta^2) + m s c / Delta (DLMF 19.25.10);
  Pi for n <= 0 by DLMF 19.21.12 turned into three positive terms (see
  :func:`ellippi_inc`), for 0 < n < 1 by DLMF 19.25.14.

Accuracy (measured against mpmath at 40 digits with the very same float
inputs, ``tests/test_elliptic.py``; max over the grids there): sn, cn, dn
within 2e-15 absolute and, for cn and dn next to K, within 1e-11 relative for
m in [0, 1 - 1e-16] and u up to 1e6 K beyond the error ``|u| eps`` that the
float argument itself carries (for a scalar parameter the reduction uses K to
~30 digits, so sn, cn, dn stay within 2e-15 absolute up to u = 1e6 K); K within
4e-16, E within 8e-16, F and E(phi) within 1e-15 and Pi within 3e-15 relative.
"""

from __future__ import annotations

import numpy as np
from scipy import special as _sp

from wobble.numerics import highprec as hp
from wobble.numerics.phase import reduce_phase

__all__ = [
    "ellipk",
    "ellipe",
    "ellippi",
    "ellipf_inc",
    "ellipe_inc",
    "ellippi_inc",
    "jacobi",
    "jacobi_am",
    "jacobi_reduced",
    "landen_levels",
    "LandenLevels",
    "pi_negative_scd",
    "pi_positive_scd",
    "reduce_half_period",
    "jacobi_quarter",
    "jacobi_quarter_inverse",
]

_EPS = np.finfo(float).eps
_MAX_LEVELS = 40
# Landen levels whose ratio c/a exceeds this use the atan2 form of arcsin.
_ASIN_SAFE = 0.5
# Below this parameter sn, cn, dn come from their first-order expansion in m.
_SMALL_M = 1e-9


def _params(m, m1):
    m = np.asarray(m, dtype=float)
    m1 = 1.0 - m if m1 is None else np.asarray(m1, dtype=float)
    if np.any((m < 0) | (m > 1) | (m1 < 0) | (m1 > 1)):
        raise ValueError("elliptic parameter m and complement m1 must lie in [0, 1]")
    return m, m1


class LandenLevels:
    """The descending Landen (AGM) sequence for a parameter m, with m1 = 1 - m.

    Attributes
    ----------
    m, m1 : numpy.ndarray
        The parameter and its complement (broadcast together).
    K : numpy.ndarray
        Complete integral of the first kind K(m) = pi / (2 a_N) (A&S 17.6.1);
        ``inf`` where ``m1 == 0``.
    ratios : list of numpy.ndarray
        ``c_n / a_n`` for n = 1..N (A&S 16.4.3).
    scale : numpy.ndarray
        ``2^N a_N``, so that ``phi_N = scale * u``.
    """

    def __init__(self, m, m1=None):
        m, m1 = _params(m, m1)
        m, m1 = np.broadcast_arrays(m, m1)
        self.m, self.m1 = m, m1
        a = np.ones_like(m)
        b = np.sqrt(m1)
        c = np.where(m1 > 0, np.sqrt(m), 0.0)  # m1 = 0: no period, tanh/sech
        ratios = []
        scale = np.ones_like(m)
        ratios_b = []
        for _ in range(_MAX_LEVELS):
            if not np.any(c > _EPS * a * 0.5):
                break
            a, b, c = 0.5 * (a + b), np.sqrt(a * b), 0.5 * (a - b)
            ratios.append(c / a)
            ratios_b.append(b / a)  # sqrt(1 - (c/a)^2) without cancellation
            scale = 2.0 * scale
        with np.errstate(divide="ignore"):
            self.K = np.where(m1 > 0, 0.5 * np.pi / a, np.inf)
        self.ratios = ratios
        self.ratios_b = ratios_b
        self.scale = scale * a


def landen_levels(m, m1=None) -> LandenLevels:
    """Precompute the Landen/AGM sequence of ``m`` (reuse it for many arguments)."""
    return LandenLevels(m, m1)


def ellipk(m, m1=None):
    """Complete elliptic integral of the first kind K(m), with m1 = 1 - m given.

    Parameters
    ----------
    m : array_like
        Parameter in [0, 1].
    m1 : array_like, optional
        Complementary parameter 1 - m, supplied exactly by the caller.

    Returns
    -------
    numpy.ndarray
        K(m), by the AGM of 1 and sqrt(m1) (A&S 17.6.1); ``inf`` for m1 = 0.
        Relative error below 4e-16 against mpmath for m1 from 1e-300 to 1.
    """
    return LandenLevels(m, m1).K


def ellipe(m, m1=None):
    """Complete elliptic integral of the second kind E(m) = 2 R_G(0, m1, 1) (DLMF 19.25.1)."""
    m, m1 = _params(m, m1)
    m, m1 = np.broadcast_arrays(m, m1)
    return 2.0 * _sp.elliprg(0.0, m1, 1.0)


def _carlson_args(phi, m, m1):
    phi = np.asarray(phi, dtype=float)
    if np.any(np.abs(phi) > 0.5 * np.pi * (1 + 4 * _EPS)):
        raise ValueError("incomplete integrals take |phi| <= pi/2; add multiples of the complete one")
    s = np.sin(phi)
    c = np.cos(phi)
    c = np.where(np.abs(phi) >= 0.5 * np.pi, 0.0, c)
    c2 = c * c
    s2 = s * s
    d2 = c2 + m1 * s2  # = 1 - m sin^2(phi), without cancellation
    return s, c, c2, s2, d2


def ellipf_inc(phi, m, m1=None):
    """Incomplete integral of the first kind F(phi | m) = s R_F(c^2, Delta^2, 1), |phi| <= pi/2.

    Relative error below 1e-15 against mpmath (DLMF 19.25.5).
    """
    m, m1 = _params(m, m1)
    s, c, c2, s2, d2 = _carlson_args(phi, m, m1)
    return s * _sp.elliprf(c2, d2, 1.0)


def ellipe_inc(phi, m, m1=None):
    """Incomplete integral of the second kind E(phi | m), |phi| <= pi/2.

    Uses the positive-term form (DLMF 19.25.10, all terms >= 0 for
    0 <= phi <= pi/2), accurate also for m near 1:
    E = m1 F + (m m1 / 3) s^3 R_D(c^2, 1, Delta^2) + m s c / Delta.
    """
    m, m1 = _params(m, m1)
    s, c, c2, s2, d2 = _carlson_args(phi, m, m1)
    with np.errstate(invalid="ignore", divide="ignore"):
        rf = _sp.elliprf(c2, d2, 1.0)
        rd = _sp.elliprd(c2, 1.0, d2)
        tail = np.where(d2 > 0, m * s * c / np.sqrt(d2), 0.0)
        return m1 * s * rf + (m * m1 / 3.0) * s * s2 * np.where(m1 > 0, rd, 0.0) + tail


def pi_negative_scd(nu, s, c, d2, m1):
    """Pi(-nu; phi | m) for nu >= 0 from s = sin phi, c = cos phi >= 0, d2 = 1 - m s^2.

    The three positive terms of :func:`ellippi_inc`; callers that already have
    sn, cn, dn of a reduced argument (so s, c, dn^2) skip the trigonometry.
    """
    sign = np.sign(s)
    s = np.abs(s)
    c2 = c * c
    s2 = s * s
    with np.errstate(invalid="ignore", divide="ignore"):
        rf = _sp.elliprf(c2, d2, 1.0)
        p = 1.0 + nu * s2
        q = c2 + m1 * s2 / (1.0 + nu)
        out = s * rf / (1.0 + nu)
        # nu and m1 may be arrays (one body per element): each term is added
        # where it is non-zero, so a scalar nu = 0 still skips R_C and R_J.
        if np.any(nu > 0):
            out = out + np.where(nu > 0, nu * s * c * _sp.elliprc(d2, p * q), 0.0) / (1.0 + nu)
            if np.any(m1 > 0):
                rj = _sp.elliprj(c2, d2, 1.0, np.where(q > 0, q, 1.0))
                out = out + np.where(nu * m1 * s > 0, nu * m1 * s * s2 * rj, 0.0) / (3.0 * (1.0 + nu) ** 2)
    return sign * out


def pi_positive_scd(n, one_minus_n, s, c, d2):
    """Pi(n; phi | m) for 0 <= n < 1 from s = sin phi, c = cos phi >= 0, d2 = 1 - m s^2.

    DLMF 19.25.14 with positive terms only, ``s R_F(c^2, d2, 1) + (n/3) s^3
    R_J(c^2, d2, 1, p)``, where the caller supplies ``1 - n`` exactly so that
    ``p = 1 - n s^2 = c^2 + (1 - n) s^2`` is formed without cancellation: n next to
    1 (a heavy top whose axis passes next to the vertical) keeps full relative
    accuracy, the integrand's near-pole at phi = pi/2 included.
    """
    sign = np.sign(s)
    s = np.abs(s)
    c2 = c * c
    s2 = s * s
    p = c2 + one_minus_n * s2
    with np.errstate(invalid="ignore", divide="ignore"):
        out = s * _sp.elliprf(c2, d2, 1.0)
        if n > 0:
            rj = _sp.elliprj(c2, d2, 1.0, np.where(p > 0, p, 1.0))
            out = out + np.where(s > 0, (n / 3.0) * s * s2 * rj, 0.0)
    return sign * out


def ellippi_inc(n, phi, m, m1=None):
    """Incomplete integral of the third kind Pi(n; phi | m), n < 1, |phi| <= pi/2.

    Pi(n; phi | m) = int_0^phi dtheta / ((1 - n sin^2 theta) sqrt(1 - m sin^2 theta)).

    For n <= 0 (nu = -n) the usual Carlson form F + (n/3) s^3 R_J cancels
    when nu is large; DLMF 19.21.12 with (p - x)(q - x) = (y - x)(z - x)
    turns it into three positive terms::

        Pi = s R_F(c^2, D^2, 1) / (1 + nu)
             + nu s c R_C(D^2, p q) / (1 + nu)
             + nu m1 s^3 R_J(c^2, D^2, 1, q) / (3 (1 + nu)^2),
        p = 1 + nu s^2,  q = c^2 + m1 s^2 / (1 + nu),  D^2 = c^2 + m1 s^2,

    accurate for any nu >= 0 (relative error below 3e-15 against mpmath).
    For 0 < n < 1 the DLMF 19.25.14 form F + (n/3) s^3 R_J has positive terms.
    """
    m, m1 = _params(m, m1)
    n = np.asarray(n, dtype=float)
    if np.any(n >= 1):
        raise ValueError("ellippi_inc takes characteristic n < 1")
    s, c, c2, s2, d2 = _carlson_args(phi, m, m1)
    sign = np.sign(s)
    s = np.abs(s)
    nu = np.maximum(-n, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        rf = _sp.elliprf(c2, d2, 1.0)
        p = 1.0 + nu * s2
        q = c2 + m1 * s2 / (1.0 + nu)
        neg = (
            s * rf / (1.0 + nu)
            + np.where(nu > 0, nu * s * c * _sp.elliprc(d2, p * q), 0.0) / (1.0 + nu)
            + np.where(nu * m1 * s > 0, nu * m1 * s * s2 * _sp.elliprj(c2, d2, 1.0, np.where(q > 0, q, 1.0)), 0.0)
            / (3.0 * (1.0 + nu) ** 2)
        )
        npos = np.maximum(n, 0.0)
        pos = s * rf + np.where(npos > 0, (npos / 3.0) * s * s2 * _sp.elliprj(c2, d2, 1.0, 1.0 - npos * s2), 0.0)
    return sign * np.where(n <= 0, neg, pos)


def ellippi(n, m, m1=None):
    """Complete integral of the third kind Pi(n | m) = Pi(n; pi/2 | m), n < 1."""
    return ellippi_inc(n, 0.5 * np.pi, m, m1)


def _landen_amplitude(w, lv: LandenLevels):
    """am(w | m) by the descending Landen recurrence (A&S 16.4.3), for |w| <= K/2."""
    phi = lv.scale * w
    for ratio, ratio_b in zip(reversed(lv.ratios), reversed(lv.ratios_b)):
        x = ratio * np.sin(phi)
        if np.max(ratio) > _ASIN_SAFE:
            # arcsin(x) near |x| = 1 amplifies the rounding of x; 1 - x^2 =
            # cos^2 phi + (b/a)^2 sin^2 phi is formed without cancellation.
            cphi = np.cos(phi)
            sphi = np.sin(phi)
            phi = 0.5 * (phi + np.arctan2(x, np.sqrt(cphi * cphi + (ratio_b * sphi) ** 2)))
        else:
            phi = 0.5 * (phi + np.arcsin(x))
    return phi


def jacobi_reduced(r, lv: LandenLevels, k_lo: float = 0.0):
    """sn, cn, dn of an argument already reduced to ``|r| <= K`` (cn >= 0 there).

    Folds ``K/2 < |r| <= K`` onto ``w = K - |r|`` with the exact quarter-period
    identities, evaluates the amplitude of ``w`` by descending Landen, and
    forms dn from cn as ``sqrt(m1 + m cn^2)``.

    Parameters
    ----------
    r : numpy.ndarray
        Reduced argument.
    lv : LandenLevels
        Precomputed sequence for the parameter (from :func:`landen_levels`).
    k_lo : float
        Low part of K when the caller knows it as a double-double
        ``(lv.K, k_lo)``: then ``K - |r|`` is exact and cn keeps its relative
        accuracy right up to its zero at K.

    Returns
    -------
    sn, cn, dn : numpy.ndarray
    """
    m, m1, K = lv.m, lv.m1, lv.K
    if np.max(m) < _SMALL_M:
        # First order in m (A&S 16.13.1-3): the neglected terms are O(m^2) < 1e-18.
        s, c = np.sin(r), np.cos(r)
        corr = 0.25 * m * (r - s * c)
        cn = c + corr * s
        return s - corr * c, cn, np.sqrt(m1 + m * cn * cn)
    v = np.abs(r)
    far = v > 0.5 * K
    w = np.where(far, (K - v) + k_lo, v)
    phi = _landen_amplitude(w, lv)
    s = np.sin(phi)
    c = np.cos(phi)
    d = np.sqrt(m1 + m * c * c)
    kp = np.sqrt(m1)
    sn = np.where(far, c / d, s)
    cn = np.where(far, kp * s / d, c)
    dn = np.where(far, kp / d, d)
    return np.copysign(sn, r), cn, dn


def _split(x):
    """Cody-Waite split: x = hi + lo with hi carrying 26 significant bits."""
    scale = 2.0 ** np.ceil(np.log2(np.maximum(np.abs(x), 1e-300)) - 26)
    hi = np.round(x / scale) * scale
    return hi, x - hi


def reduce_half_period(u, K):
    """Reduce ``u`` modulo 2K: ``u = 2K j + r`` with ``|r| <= K``.

    2K is split in two pieces so that ``j * (2K)_hi`` is exact for
    ``|j| < 2^27`` (u up to about 2.7e8 K): the reduction adds no error beyond
    that of the float ``u`` and ``K`` themselves.

    Returns
    -------
    r : numpy.ndarray
    j : numpy.ndarray of float (integer values)
    """
    two_k = 2.0 * K
    with np.errstate(invalid="ignore"):
        j = np.where(np.isfinite(two_k), np.rint(u / two_k), 0.0)
    hi, lo = _split(np.where(np.isfinite(two_k), two_k, 0.0))
    r = (u - j * hi) - j * lo
    return r, j


def jacobi(u, m, m1=None):
    """Jacobi elliptic functions sn, cn, dn of (u | m), with m1 = 1 - m supplied.

    Parameters
    ----------
    u : array_like
        Argument (any size: reduced modulo 2K internally, see
        :func:`reduce_half_period`).
    m : array_like
        Parameter in [0, 1]; broadcast with ``u``.
    m1 : array_like, optional
        Complement 1 - m, exact from the caller (essential for m near 1).

    Returns
    -------
    sn, cn, dn : numpy.ndarray

    Notes
    -----
    For ``m1 == 0`` the functions are tanh, sech, sech. Accuracy: see the
    module docstring (absolute error ~4e-16 after reduction; scipy.special.ellipj
    is wrong in the first digit for m1 = 1e-12 and u > K).
    """
    u = np.asarray(u, dtype=float)
    lv = LandenLevels(m, m1)
    return _jacobi_with(u, lv)


def _reduce(u, lv: LandenLevels):
    """Reduce modulo 2K; a scalar parameter gets K to ~30 digits (exact reduction)."""
    if lv.m1.ndim == 0 and 0.0 < float(lv.m1):
        k_hi, k_lo = hp.to_dd(hp.agm_k(float(lv.m1)))
        lv.K = np.asarray(k_hi)
        r, j = reduce_phase(u, (1.0, 0.0), (2.0 * k_hi, 2.0 * k_lo))
        return r, j, k_lo
    r, j = reduce_half_period(u, lv.K)
    return r, j, 0.0


def _jacobi_with(u, lv: LandenLevels):
    r, j, k_lo = _reduce(u, lv)
    sn, cn, dn = jacobi_reduced(r, lv, k_lo)
    odd = np.floor(0.5 * j) != 0.5 * j  # (np.fmod is ten times slower)
    sn = np.where(odd, -sn, sn)
    cn = np.where(odd, -cn, cn)
    sep = lv.m1 == 0
    if np.any(sep):
        with np.errstate(over="ignore"):
            sech = 1.0 / np.cosh(u)
        sn = np.where(sep, np.tanh(u), sn)
        cn = np.where(sep, sech, cn)
        dn = np.where(sep, sech, dn)
    return sn, cn, dn


def jacobi_am(u, m, m1=None):
    """Jacobi amplitude am(u | m), continuous and increasing in u.

    ``am(u) = j pi + atan2(sn r, cn r)`` with ``u = 2K j + r``, ``|r| <= K``;
    for ``m1 == 0`` it is the Gudermannian ``2 atan(tanh(u/2))``.
    """
    u = np.asarray(u, dtype=float)
    lv = LandenLevels(m, m1)
    r, j, k_lo = _reduce(u, lv)
    sn, cn, _ = jacobi_reduced(r, lv, k_lo)
    am = j * np.pi + np.arctan2(sn, cn)
    return np.where(lv.m1 == 0, 2.0 * np.arctan(np.tanh(0.5 * u)), am)


# --------------------------------------------------------------------------
# Quarter-period representation u = n K + x, |x| <= K/2 (one parameter per
# element): the flow map of the free rigid body (wobble.models.free_flow.free_flow)
# steps u by lambda h from a state, never from t = 0.
# --------------------------------------------------------------------------
def jacobi_quarter(n, x, lv: LandenLevels, separatrix=None):
    """sn, cn, dn of ``u = n K + x`` for integer ``n`` and ``|x| <= K/2``.

    ``x`` goes through the descending Landen recurrence; the quarter shifts
    use the exact identities (A&S 16.8.1)
    ``sn(x + K) = cn x / dn x``, ``cn(x + K) = -k' sn x / dn x``,
    ``dn(x + K) = k' / dn x`` (k' = sqrt(m1)), so cn and dn keep their
    relative accuracy next to u = K however small m1 is. The parameter may
    differ per element (``lv`` built from arrays); where ``m1 == 0`` (K
    infinite) ``n`` must be 0 and the functions are tanh, sech, sech of x.
    ``separatrix`` (boolean array) marks those elements explicitly, so that a
    caller can build ``lv`` with a harmless placeholder parameter there (the
    Landen sequence of m = 1 never converges).

    Returns
    -------
    sn, cn, dn : numpy.ndarray
        Of u; also ``(snx, cnx, dnx)`` of x, as a second triple.
    """
    x = np.asarray(x, dtype=float)
    phi = _landen_amplitude(x, lv)
    s = np.sin(phi)
    c = np.cos(phi)
    d = np.sqrt(lv.m1 + lv.m * c * c)
    sep = lv.m1 == 0 if separatrix is None else separatrix
    if np.any(sep):
        with np.errstate(over="ignore"):
            sech = 1.0 / np.cosh(x)
        s = np.where(sep, np.tanh(x), s)
        c = np.where(sep, sech, c)
        d = np.where(sep, sech, d)
    kp = np.where(sep, 0.0, np.sqrt(lv.m1))
    quarter = np.mod(np.asarray(n, dtype=float), 4.0)
    odd = (quarter == 1.0) | (quarter == 3.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        sn = np.where(odd, c / d, s)
        cn = np.where(odd, -kp * s / d, c)
        dn = np.where(odd, kp / d, d)
    flip = quarter >= 2.0  # u + 2K: sn and cn change sign
    sn = np.where(flip, -sn, sn)
    cn = np.where(flip, -cn, cn)
    return (sn, cn, dn), (s, c, d)


def jacobi_quarter_inverse(sn, cn, dn, m, m1):
    """The inverse of :func:`jacobi_quarter`: ``(n, x)`` with ``u = n K + x``.

    Given sn, cn, dn of some u (dn > 0, one parameter per element), returns
    ``n`` in {-1, 0, 1, 2} and ``x`` with ``|x| <= K/2`` (up to rounding)
    by Carlson's R_F (DLMF 19.25.5): near an even multiple of K
    (``dn^2 >= k'``) ``x = +-sn R_F(cn^2, dn^2, 1)``; near an odd one the
    complementary amplitude of x is used, ``sn x = -+cn/dn``,
    ``cn x = k' |sn| / dn``, ``dn x^2 = m1 / dn^2``, so that x keeps its
    relative accuracy where ``u`` is next to K (the unstable axis of a
    body near its separatrix). Where ``m1 == 0`` the result is ``n = 0``
    and ``x = artanh(sn)`` through the same R_F.

    Returns
    -------
    n : numpy.ndarray of float (integer values)
    x : numpy.ndarray
    snx, cnx, dnx : numpy.ndarray
        sn, cn, dn of x (cnx >= 0).
    """
    sn = np.asarray(sn, dtype=float)
    cn = np.asarray(cn, dtype=float)
    dn = np.asarray(dn, dtype=float)
    m = np.asarray(m, dtype=float)
    m1 = np.asarray(m1, dtype=float)
    kp = np.sqrt(m1)
    even = dn * dn >= kp
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_d = 1.0 / dn
        snx = np.where(even, np.where(cn >= 0, sn, -sn), np.where(sn > 0, -cn * inv_d, cn * inv_d))
        cnx = np.where(even, np.abs(cn), kp * np.abs(sn) * inv_d)
        dnx = np.where(even, dn, kp * inv_d)
    n = np.where(even, np.where(cn >= 0, 0.0, 2.0), np.where(sn > 0, 1.0, -1.0))
    d2 = np.where(even, cnx * cnx + m1 * snx * snx, m1 * inv_d * inv_d)
    x = snx * _sp.elliprf(cnx * cnx, d2, 1.0)
    return n, x, snx, cnx, dnx
