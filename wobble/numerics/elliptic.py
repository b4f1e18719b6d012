"""Jacobi elliptic functions and elliptic integrals in float64, with m1 = 1 - m given.

Every function takes the parameter ``m`` (= k^2) **and** its complement
``m1 = 1 - m`` supplied by the caller. Near the separatrix of a free rigid body
m is within 1e-12 of 1, and a float64 ``m`` has then already lost the digits of
``1 - m`` that decide the answer; callers that know ``m1`` from the physics
(e.g. ``m1 = (I3-I1)(L^2-2EI2) / ((I3-I2)(L^2-2EI1))``) pass it here and keep
them. When ``m1`` is omitted it is taken as ``1 - m`` (exact for m >= 1/2).

Algorithms
----------
* Complete K(m) and E(m): the arithmetic-geometric mean started from ``sqrt(m1)``
  (Abramowitz & Stegun 17.6.1), with Gauss's sum for E (17.6.3-4), in double-double
  arithmetic (:mod:`wobble.numerics.double_double`) and rounded once, so both keep
  full relative accuracy down to ``m1 = 2.2e-308`` and for ``m`` near 0.
  :class:`LandenLevels` keeps the float64 AGM (within 6e-16) for the models' evaluators.
* sn, cn, dn, am (:func:`jacobi`, :func:`jacobi_am`): ``u = q K + x`` with
  ``|x| <= K/2``, K as a double-double from the AGM in double-double arithmetic
  (:func:`ellipk_dd`) and split in three pieces (Cody & Waite), so that x
  carries a few ulps of x itself however many periods u spans; then sn, cn, dn
  of x, and the exact quarter-period identities (A&S 16.8.1). For ``m <= 1/2``
  the descending Landen (AGM) recurrence for the amplitude (A&S 16.4.3); for
  ``m > 1/2`` Jacobi's imaginary transformation (A&S 16.20), the same recurrence
  for the complementary parameter at an imaginary argument, where every term is
  positive: ``sn = tanh psi``, ``cn = sech psi``, so cn and dn keep their
  *relative* accuracy however small they are (``sech x`` for m next to 1).
  ``dn = sqrt(m1 + m cn^2)`` or ``sqrt(cn^2 + m1 sn^2)`` (no cancellation).
  scipy.special.ellipj instead reduces u in float64 (errors growing like
  ``|u| eps``) and switches for ``1 - m < 1e-9`` to a near-unity series valid
  only for u < K (scipy issue #8480).
* :func:`jacobi_reduced` and :func:`jacobi_quarter` (the free body's and the
  heavy top's evaluators, which reduce ``rate t`` themselves): the descending
  Landen recurrence on ``|x| <= K/2`` with the same quarter-period identities.
* Incomplete integrals: Carlson's symmetric forms (scipy.special.elliprf,
  elliprd, elliprj, elliprc) written with only positive terms, using
  ``Delta^2 = 1 - m sin^2 phi = cos^2 phi + m1 sin^2 phi``:
  F = s R_F(c^2, Delta^2, 1) (DLMF 19.25.5);
  E = m1 F + (m m1/3) s^3 R_D(c^2, 1, Delta^2) + m s c / Delta (DLMF 19.25.10);
  Pi for n <= 0 by DLMF 19.21.12 turned into three positive terms (see
  :func:`ellippi_inc`), for 0 < n < 1 by DLMF 19.25.14 with
  ``1 - n sin^2 phi = cos^2 phi + (1 - n) sin^2 phi``.
* Complete Pi(n | m): Bulirsch's ``cel`` in double-double arithmetic
  (:func:`ellippi`).

Accuracy
--------
Relative errors against mpmath (40+ digits) at the very same float inputs, in
eps = 2^-52 = 2.2e-16; each bound is checked on the worst rows of Boost.Math's
elliptic tables and on grids over m1 from 2.2e-308 to 1
(``tests/test_elliptic_bounds.py``; the peer comparison itself is
``scripts/check_reference_tables.py``, docs/accuracy.md):

* K, E, Pi(n | m) complete: half an ulp (1.2e-16), for any m1 in [2.2e-308, 1]
  and n < 1; :func:`ellipk_dd` within 1e-31.
* F(phi | m), E(phi | m): 1e-15 (Boost's worst row 1.8 eps), any phi through
  :func:`reduce_amplitude`.
* Pi(n; phi | m), :func:`pi_positive_scd`, :func:`pi_negative_scd`: 3e-15 (Boost's
  worst row 3.9 eps), except in a corner where ``cos^2 phi``, m1 and 1 - n are all
  tiny (below 1e-20, 1e-10 and 1e-4) and SciPy's R_J loses digits: 2e-14 there
  (75 eps at n = 0.999999, phi = 1.5707963267948966, m1 = 1e-16).
* sn, cn, dn of :func:`jacobi`: each within 4 eps (Boost's worst row 2.2 eps), next to
  the zeros of cn and dn included, for m1 in [2.2e-308, 1] and |u| up to 2^25 K;
  within 1e-30 |q| K absolute where u is within 1e-15 |q| K of a multiple q K of the
  quarter period (the double-double K's floor: u = float(q K) itself). am within
  4 eps. A vectorised call returns the very floats of per-row calls.
* :func:`jacobi_quarter` and :func:`jacobi_reduced` (after an exact reduction):
  within 4e-16 absolute; cn and dn within about ``eps (2 + m1^(-1/4))`` relative
  (cos of a rounded amplitude near pi/2: 17 eps at m1 = 7e-6, 8e3 eps at
  m1 = 1e-16). :func:`jacobi_reduced` takes a float argument ``|r| <= K``, whose
  own rounding next to ``|r| = K`` reaches cn (34 eps on Boost's large-argument table).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special as _sp

from wobble.numerics.floats import EPS
from wobble.numerics import double_double as dd

__all__ = [
    "M1_MIN",
    "ellipk",
    "ellipk_dd",
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
    "carlson_rf_scd",
    "pi_negative_scd",
    "pi_positive_scd",
    "reduce_half_period",
    "reduce_quarter_period",
    "reduce_amplitude",
    "jacobi_quarter",
    "jacobi_quarter_inverse",
]

#: The smallest 1 - m (other than 0, the separatrix) whose integrals of the third kind the
#: kernels evaluate: below it SciPy's R_J overflows inside (its value near 1e155 and more),
#: and a state closer to the separatrix than sqrt(M1_MIN) ~ 1e-75 leaves double precision.
M1_MIN = 1e-150
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
        ``inf`` where ``m1 == 0``; or the ``K`` given to the constructor.
    ratios : list of numpy.ndarray
        ``c_n / a_n`` for n = 1..N (A&S 16.4.3).
    scale : numpy.ndarray
        ``2^N a_N``, so that ``phi_N = scale * u``.
    """

    def __init__(self, m, m1=None, K=None):
        if np.ndim(m) == 0 and np.ndim(m1) == 0:
            self._scalar(m, m1, K)
            return
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
            if not np.any(c > EPS * a * 0.5):
                break
            a, b, c = 0.5 * (a + b), np.sqrt(a * b), 0.5 * (a - b)
            ratios.append(c / a)
            ratios_b.append(b / a)  # sqrt(1 - (c/a)^2) without cancellation
            scale = 2.0 * scale
        with np.errstate(divide="ignore"):
            self.K = np.where(m1 > 0, 0.5 * np.pi / a, np.inf) if K is None else np.asarray(K, dtype=float)
        self.ratios = ratios
        self.ratios_b = ratios_b
        self.scale = scale * a

    def _scalar(self, m, m1, K):
        """The same sequence for one parameter in Python floats (the same roundings: +, *, /
        and sqrt are correctly rounded either way), without NumPy's per-call cost."""
        mf = float(m)
        m1f = 1.0 - mf if m1 is None else float(m1)
        if mf < 0 or mf > 1 or m1f < 0 or m1f > 1:
            raise ValueError("elliptic parameter m and complement m1 must lie in [0, 1]")
        self.m, self.m1 = np.asarray(mf), np.asarray(m1f)
        a, b = 1.0, math.sqrt(m1f)
        c = math.sqrt(mf) if m1f > 0 else 0.0
        ratios, ratios_b, scale = [], [], 1.0
        for _ in range(_MAX_LEVELS):
            if not c > EPS * a * 0.5:
                break
            a, b, c = 0.5 * (a + b), math.sqrt(a * b), 0.5 * (a - b)
            ratios.append(np.float64(c / a))
            ratios_b.append(np.float64(b / a))
            scale = 2.0 * scale
        if K is None:
            self.K = np.asarray(0.5 * np.pi / a if m1f > 0 else np.inf)
        else:
            self.K = np.asarray(K, dtype=float)
        self.ratios = ratios
        self.ratios_b = ratios_b
        self.scale = np.float64(scale * a)


def landen_levels(m, m1=None, K=None) -> LandenLevels:
    """Precompute the Landen/AGM sequence of ``m`` (reuse it for many arguments).

    ``K``, if given, is the complete integral the levels carry instead of their own
    float64 AGM value: a caller that reduces its arguments with a higher-precision K
    (the exact solutions) folds with the same K.
    """
    return LandenLevels(m, m1, K)


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
        K(m), by the AGM of 1 and sqrt(m1) (A&S 17.6.1) in double-double
        arithmetic (:func:`ellipk_dd`), rounded once: relative error below
        1.2e-16 (half an ulp) against mpmath for m1 from 2.2e-308 to 1; ``inf``
        for m1 = 0. (The float64 AGM of :class:`LandenLevels` is within 6e-16.)
    """
    return ellipk_dd(m, m1)[0]


def ellipk_dd(m, m1=None):
    """K(m) as a double-double ``(hi, lo)``, hi + lo to about 32 digits, with m1 = 1 - m given.

    The AGM (A&S 17.6.1) from the exact ``m1`` in double-double arithmetic
    (:func:`wobble.numerics.double_double.agm_k`: ~30 us for a scalar, ~0.5 us per
    element of an array, each element exactly as if alone); ``(inf, 0)`` for
    ``m1 = 0``.

    Returns
    -------
    hi, lo : numpy.ndarray
        Broadcast shape of ``m`` and ``m1``.
    """
    m, m1 = _params(m, m1)
    m, m1 = np.broadcast_arrays(m, m1)
    return dd.agm_k(m1)


def ellipe(m, m1=None):
    """Complete elliptic integral of the second kind E(m), with m1 = 1 - m given.

    The AGM with Gauss's sum, ``E = K (1 - sum 2^(n-1) c_n^2)`` (A&S 17.6.3-4), in
    double-double arithmetic from the exact ``m1``
    (:func:`wobble.numerics.double_double.agm_ke`), rounded once: relative error
    below 1.2e-16 (half an ulp) for m1 from 2.2e-308 to 1; E = 1 for m1 = 0.
    (SciPy's ``2 R_G(0, m1, 1)``, DLMF 19.25.1, is off by up to 15 eps for m1 < 1e-30.)
    """
    m, m1 = _params(m, m1)
    m, m1 = np.broadcast_arrays(m, m1)
    return dd.agm_ke(m1)[1][0]


def _carlson_args(phi, m, m1):
    phi = np.asarray(phi, dtype=float)
    if np.any(np.abs(phi) > 0.5 * np.pi * (1 + 4 * EPS)):
        raise ValueError("incomplete integrals take |phi| <= pi/2; add multiples of the complete one")
    s = np.sin(phi)
    c = np.cos(phi)
    # The float nearest pi/2 lies 6.1e-17 below it: its cosine (exact to an ulp) matters
    # when m1 is tiny (F has a log singularity there); the few ulps allowed beyond pi/2
    # are taken as pi/2.
    c = np.where(np.abs(phi) > 0.5 * np.pi, 0.0, c)
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


def pi_negative_scd(nu, s, c, d2, m1, rf=None):
    """Pi(-nu; phi | m) for nu >= 0 from s = sin phi, c = cos phi >= 0, d2 = 1 - m s^2.

    The three positive terms of :func:`ellippi_inc`; callers that already have
    sn, cn, dn of a reduced argument (so s, c, dn^2) skip the trigonometry, and
    ``rf`` = R_F(c^2, d2, 1) where they have it (:func:`carlson_rf_scd`).
    Relative error below 3e-15 (module docstring).
    """
    sign = np.sign(s)
    s = np.abs(s)
    c2 = c * c
    s2 = s * s
    with np.errstate(invalid="ignore", divide="ignore"):
        rf = _sp.elliprf(c2, d2, 1.0) if rf is None else rf
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


def carlson_rf_scd(c, d2):
    """R_F(c^2, d2, 1), the first-kind term that :func:`pi_positive_scd` and
    :func:`pi_negative_scd` share (pass it as ``rf`` to both: one evaluation)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return _sp.elliprf(c * c, d2, 1.0)


def pi_positive_scd(n, one_minus_n, s, c, d2, rf=None):
    """Pi(n; phi | m) for 0 <= n < 1 from s = sin phi, c = cos phi >= 0, d2 = 1 - m s^2.

    DLMF 19.25.14 with positive terms only, ``s R_F(c^2, d2, 1) + (n/3) s^3
    R_J(c^2, d2, 1, p)``, where the caller supplies ``1 - n`` exactly so that
    ``p = 1 - n s^2 = c^2 + (1 - n) s^2`` is formed without cancellation: n next to
    1 (a heavy top whose axis passes next to the vertical) keeps full relative
    accuracy, the integrand's near-pole at phi = pi/2 included: below 3e-15, except
    in SciPy's R_J corner (module docstring: 2e-14 there). ``rf``: R_F(c^2, d2, 1) where
    the caller has it (:func:`carlson_rf_scd`).
    """
    sign = np.sign(s)
    s = np.abs(s)
    c2 = c * c
    s2 = s * s
    p = c2 + one_minus_n * s2
    with np.errstate(invalid="ignore", divide="ignore"):
        out = s * (_sp.elliprf(c2, d2, 1.0) if rf is None else rf)
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

    accurate for any nu >= 0. For 0 < n < 1 the DLMF 19.25.14 form
    F + (n/3) s^3 R_J(c^2, D^2, 1, p) has positive terms, with
    ``p = 1 - n s^2`` formed as ``c^2 + (1 - n) s^2`` so that it keeps its digits
    as ``n sin^2 phi -> 1`` (the integrand's near-pole; as :func:`pi_positive_scd`).
    Relative error below 3e-15 against mpmath, except in SciPy's R_J corner (module
    docstring: 2e-14 there). For |phi| > pi/2 see :func:`reduce_amplitude`.
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
        # p = 1 - n s^2 = c^2 + (1 - n) s^2: no cancellation as n s^2 -> 1 (1 - n is
        # exact for n >= 1/2), as in pi_positive_scd.
        p_pos = c2 + (1.0 - npos) * s2
        pos = s * rf + np.where(
            npos > 0, (npos / 3.0) * s * s2 * _sp.elliprj(c2, d2, 1.0, np.where(p_pos > 0, p_pos, 1.0)), 0.0
        )
    return sign * np.where(n <= 0, neg, pos)


def ellippi(n, m, m1=None):
    """Complete integral of the third kind Pi(n | m) = Pi(n; pi/2 | m), n < 1.

    Bulirsch's general complete integral ``Pi(n | m) = cel(k', 1 - n, 1, 1)``
    (R. Bulirsch, Numer. Math. 13, 305 (1969); Numerical Recipes 3rd ed. sec. 6.12),
    a Gauss (Landen) transformation with quadratic convergence and only positive
    terms for n < 1, run in vectorised double-double arithmetic
    (:mod:`wobble.numerics.double_double`) from ``k' = sqrt(m1)`` and ``1 - n``
    formed exactly. The result is rounded once: relative error below 1 eps
    (2.2e-16) against mpmath for any n < 1 and m1 in (0, 1], at the cost of the
    Carlson form (Carlson's R_J in float64 loses up to 4 eps as n -> 1).
    ``inf`` for m1 = 0.
    """
    m, m1 = _params(m, m1)
    n = np.asarray(n, dtype=float)
    if np.any(n >= 1):
        raise ValueError("ellippi takes characteristic n < 1")
    n, m1 = np.broadcast_arrays(n, m1)
    sep = m1 == 0
    if n.ndim == 0:  # NumPy scalars: twenty times faster than 0-d arrays in the loop
        out = _cel_pi(n[()], 1.0 if sep else m1[()])
        return np.asarray(np.inf if sep else out)
    out = _cel_pi(n, np.where(sep, 1.0, m1))
    return np.where(sep, np.inf, out)


def _cel_pi(n, m1):
    """cel(sqrt(m1), 1 - n, 1, 1) in double-double (Bulirsch 1969, the p > 0 branch: all terms positive)."""
    kc = dd.sqrt_float(m1)
    p = dd.sqrt(*dd.two_sum(1.0, -n))
    e = kc
    em = (1.0 + 0.0 * m1, 0.0 * m1)
    a = em
    b = dd.div(1.0, 0.0, *p)
    for _ in range(40):
        f = a
        a = dd.add_same_sign(*a, *dd.div(*b, *p))
        g = dd.div(*e, *p)
        b = dd.add_same_sign(*b, *dd.mul(*f, *g))
        b = (2.0 * b[0], 2.0 * b[1])
        p = dd.add_same_sign(*g, *p)
        g = em
        em = dd.add_same_sign(*kc, *em)
        # Quadratic convergence: |g - kc| ~ 1e-16 g leaves an error ~1e-32.
        if np.all(np.abs(g[0] - kc[0]) <= 2.0**-50 * g[0]):
            break
        kc = dd.sqrt(*e)
        kc = (2.0 * kc[0], 2.0 * kc[1])
        e = dd.mul(*kc, *em)
    num = dd.add_same_sign(*b, *dd.mul(*a, *em))
    den = dd.mul(*em, *dd.add_same_sign(*em, *p))
    r = dd.mul(*dd.div(*num, *den), 0.5 * dd.PI[0], 0.5 * dd.PI[1])
    return r[0] + r[1]


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
        Argument (any size: reduced modulo the quarter period K, with K to ~32
        digits, see :func:`reduce_quarter_period`).
    m : array_like
        Parameter in [0, 1]; broadcast with ``u``.
    m1 : array_like, optional
        Complement 1 - m, exact from the caller (essential for m near 1).

    Returns
    -------
    sn, cn, dn : numpy.ndarray

    Notes
    -----
    ``u = q K + x`` with ``|x| <= K/2``; sn, cn, dn of x by the descending Landen
    recurrence, then the quarter-period identities of :func:`jacobi_quarter`, so
    each function keeps its *relative* accuracy, next to its zeros included, for
    any number of periods in u. A scalar parameter and an array of parameters
    reduce alike (K from :func:`ellipk_dd`), so a vectorised call agrees with
    per-row calls to a few ulps.

    For ``m1 == 0`` the functions are tanh, sech, sech. Accuracy: see the
    module docstring (scipy.special.ellipj is wrong in the first digit for
    m1 = 1e-12 and u > K, and off by up to 4e4 eps for |u| ~ 200).

    A modulus k > 1 (parameter m = k^2 > 1) is outside [0, 1]; reduce it by the
    reciprocal-modulus transformation (A&S 16.11.1-3, DLMF 22.17.2-4) with
    ``mu = 1/m``, ``1 - mu = (m - 1)/m``::

        sn(u | m) = sn(k u | mu) / k,   cn(u | m) = dn(k u | mu),   dn(u | m) = cn(k u | mu).
    """
    u = np.asarray(u, dtype=float)
    (sn, cn, dn), _, _ = _jacobi_parts(u, m, m1)
    return sn, cn, dn


def reduce_quarter_period(u, k_hi, k_lo=0.0):
    """Reduce ``u`` modulo the quarter period: ``u = q K + x`` with ``|x| <= K/2`` (to rounding).

    K is given as a double-double ``(k_hi, k_lo)`` (:func:`ellipk_dd`) and split in
    three pieces (:func:`wobble.numerics.double_double.split3`), so that
    ``x = ((u - q p1) - q p2) - q p3`` carries an error of a few ulps of ``x``
    itself, not of ``u`` or K, for ``|q| < 2^26`` (Cody & Waite 1980), and beyond,
    where ``q K`` is Dekker's exact product (:func:`~wobble.numerics.double_double.minus_multiple`),
    to ``|q|`` ~ 2^40, where ``q`` times K's own error (~1e-32) reaches it: sn, cn and
    dn of ``u`` then keep their relative accuracy next to their zeros however
    many periods ``u`` spans. Elements with ``K = inf`` (m1 = 0) give ``q = 0``,
    ``x = u``.

    Returns
    -------
    x : numpy.ndarray
    q : numpy.ndarray of float (integer values)
    """
    x, _, q = _reduce_dd(u, k_hi, k_lo)
    return x, q


def _reduce_dd(u, k_hi, k_lo):
    """:func:`reduce_quarter_period` with the rounding error of x: ``x + x_lo`` to ~|q| K 1e-31."""
    u = np.asarray(u, dtype=float)
    k_hi = np.asarray(k_hi, dtype=float)
    finite = np.isfinite(k_hi)
    p1, p2, p3 = dd.split3(np.where(finite, k_hi, 0.0), np.where(finite, k_lo, 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        q = np.where(finite, np.rint(u / np.where(finite, k_hi, 1.0)), 0.0)
    # u - q p1 and its difference with q p2 are exact (Cody & Waite) for |q| < 2^26; the last
    # step rounds. Beyond, q K by Dekker's exact product (dd.minus_multiple).
    x, x_lo = dd.two_sum((u - q * p1) - q * p2, -(q * p3))
    far = np.abs(q) >= dd.WHOLE_PIECES
    if np.any(far):
        fx, fx_lo = dd.minus_multiple(u, q, np.where(finite, k_hi, 0.0), np.where(finite, k_lo, 0.0))
        x, x_lo = np.where(far, fx, x), np.where(far, fx_lo, x_lo)
    return x, x_lo, q


def reduce_amplitude(phi):
    """Reduce an amplitude modulo pi: ``phi = j pi + r`` with ``|r| <= pi/2``, exactly.

    The incomplete integrals take ``|phi| <= pi/2``; their integrands have period pi,
    so for any phi (A&S 17.4.3 for F; likewise E and Pi)::

        F(phi | m) = 2 j K(m) + F(r | m),   E(phi | m) = 2 j E(m) + E(r | m),
        Pi(n; phi | m) = 2 j Pi(n | m) + Pi(n; r | m).

    pi is carried as a double-double, so ``r`` has an error of a few ulps of ``r``
    (a float ``phi - j * np.pi`` is off by ``|j|`` 1.2e-16): by three pieces of pi for
    ``|j| < 2^26``, by Dekker's exact ``j pi`` beyond, to ``|j|`` ~ 2^40.

    Returns
    -------
    r : numpy.ndarray
    j : numpy.ndarray of float (integer values)
    """
    phi = np.asarray(phi, dtype=float)
    j = np.rint(phi / dd.PI[0])
    r = _minus_pi(phi, j)
    # rint of the rounded quotient can leave |r| a rounding above pi/2: step back inside.
    step = (r > 0.5 * dd.PI[0]).astype(float) - (r < -0.5 * dd.PI[0])
    if np.any(step != 0):
        j = j + step
        r = _minus_pi(phi, j)
    return r, j


def _minus_pi(phi, j):
    """phi - j pi: Cody & Waite's three pieces for |j| < 2^26, Dekker's exact j pi beyond."""
    p1, p2, p3 = dd.split3(dd.PI[0], dd.PI[1])
    r = ((phi - j * p1) - j * p2) - j * p3
    far = np.abs(j) >= dd.WHOLE_PIECES
    if np.any(far):
        r = np.where(far, dd.minus_multiple(phi, j, dd.PI[0], dd.PI[1])[0], r)
    return r


class _Levels:
    """The descending AGM of one parameter per element (A&S 17.6), frozen where converged.

    ``a_0 = 1``, ``b_0``, ``c_0`` with ``c_0^2 = 1 - b_0^2``; ``c_(n+1) = c_n^2 / (4 a_(n+1))``
    is ``(a_n - b_n)/2`` without its cancellation. An element whose ``c`` is below
    ``stop * a`` takes no further steps (``c = 0``, ``a`` and ``b`` kept), so that the
    extra levels an array runs for its slowest element are exact no-ops for the others
    in the recurrences below (halvings and doublings only): a vectorised call then
    gives the very floats of a per-row call.
    """

    def __init__(self, b0, c0, stop):
        a = np.ones_like(b0)
        b, c = b0, c0
        self.ratios = []
        self.csum = np.zeros_like(b0)  # sum of c_n, n >= 1: 1 - a_N without cancellation
        for _ in range(_MAX_LEVELS):
            active = c > stop * a
            if not np.any(active):
                break
            a_next = np.where(active, 0.5 * (a + b), a)
            b = np.where(active, np.sqrt(a * b), b)
            c = np.where(active, c * c / (4.0 * a_next), 0.0)
            a = a_next
            self.ratios.append(c / a)
            self.csum = self.csum + c
        self.a = a


def _direct(x, x_lo, m, lev: _Levels):
    """sn, cn of ``x + x_lo``, ``|x| <= K/2``, m <= 1/2: descending Landen (A&S 16.4.3), ratios <= 0.18."""
    phi = np.ldexp(x - x * lev.csum, len(lev.ratios))  # 2^N a_N x, with a_N = 1 - sum c_n
    for ratio in reversed(lev.ratios):
        phi = 0.5 * (phi + np.arcsin(ratio * np.sin(phi)))
    s = np.sin(phi)
    phi = phi + x_lo * np.sqrt(1.0 - m * s * s)  # d am / dx = dn
    return np.sin(phi), np.cos(phi)


def _imaginary(x, x_lo, m1, lev: _Levels):
    """sn, cn of ``x + x_lo``, ``|x| <= K/2``, m > 1/2, by Jacobi's imaginary transformation.

    ``sn(x | m) = -i sc(i x | m1)``, ``cn(x | m) = nc(i x | m1)`` (A&S 16.20.1-3): the
    descending Landen recurrence of the *complementary* parameter m1 (``lev``) at the
    imaginary argument stays imaginary, ``am(i x | m1) = i psi`` with
    ``psi_(n-1) = (psi_n + arsinh(r_n sinh psi_n))/2``, ``psi_N = 2^N a_N x``, and then
    ``sn = tanh psi``, ``cn = sech psi``. Every term is positive: cn keeps its
    relative accuracy where it is small (``sqrt(k')`` at K/2, and ``sech x`` for m
    next to 1), which ``cos(am x)`` of a rounded amplitude cannot. The recurrence
    runs on ``delta_n = psi_n - 2^n x`` (``delta_N = -2^N x sum c_n``), so that
    ``psi = x + delta`` is never rounded: ``cosh psi = cosh x cosh delta + sinh x sinh delta``;
    the low part of the reduced argument enters as ``x_lo dpsi/dx = x_lo dn/cn``, since
    ``sech psi`` amplifies an error of psi by psi (up to K/2 ~ 170 for m1 = 1e-300).
    """
    levels = len(lev.ratios)
    # sinh overflows only on levels an element does not use (ratio 0: the slowest element's
    # extra levels, m1 = 0 where x = u is unreduced, m1 >= 1/2 on the direct path); on its own
    # levels |x| <= K/2 keeps sinh(2^n x) below 1e160.
    with np.errstate(over="ignore", invalid="ignore"):
        delta = -np.ldexp(x * lev.csum, levels)
        for n in range(levels, 0, -1):
            ratio = lev.ratios[n - 1]
            term = np.arcsinh(ratio * np.sinh(np.ldexp(x, n) + delta))
            delta = 0.5 * (delta + np.where(ratio > 0, term, 0.0))
        delta = delta + x_lo * np.sqrt(1.0 + m1 * np.sinh(x + delta) ** 2)
        chx, shx, chd, shd = np.cosh(x), np.sinh(x), np.cosh(delta), np.sinh(delta)
        ch = chx * chd + shx * shd
        return (shx * chd + chx * shd) / ch, 1.0 / ch


def _jacobi_parts(u, m, m1):
    """sn, cn, dn of u, with the reduction ``u = q K + x`` and the functions of x.

    Returns ``(sn, cn, dn), (q, x), (s, c, d)`` where ``s, c, d`` are of x.
    """
    m, m1 = _params(m, m1)
    m, m1 = np.broadcast_arrays(m, m1)
    sep = m1 == 0
    imag = m1 < 0.5
    direct = _Levels(np.sqrt(m1), np.where(sep, 0.0, np.sqrt(m)), 0.5 * EPS)
    with np.errstate(divide="ignore"):
        k = np.where(sep, np.inf, 0.5 * np.pi / direct.a)
    x, x_lo, q = _quarter_reduce(u, m, m1, k)
    s = c = d = 0.0
    if not np.all(imag):
        s, c = _direct(x, x_lo, m, direct)
        d = np.sqrt(m1 + m * c * c)  # = sqrt(1 - m s^2), positive terms (1 exactly for m = 0)
    if np.any(imag):
        # Stop at c < 1e-35 a: the neglected level's term grows like sinh, not sin.
        s_i, c_i = _imaginary(x, x_lo, m1, _Levels(np.sqrt(m), np.where(imag, np.sqrt(m1), 0.0), 1e-35))
        # sqrt(c^2 + m1 s^2): relative accuracy where cn and dn are both small (m next to 1).
        s, c, d = np.where(imag, s_i, s), np.where(imag, c_i, c), np.where(imag, np.sqrt(c_i * c_i + m1 * s_i * s_i), d)
    of_u, of_x = _quarter_shift(q, s, c, d, m, m1, sep, x)
    return of_u, of_x, (q, x)


def _quarter_reduce(u, m, m1, k):
    """``u = q K + x + x_lo`` for :func:`jacobi` and :func:`jacobi_am`, with K to ~32
    digits (:func:`ellipk_dd`). Where every ``|u| <= K/2`` (``k``: K in float64)
    nothing needs reducing.
    """
    if np.all(np.abs(u) <= 0.5 * k * (1.0 - 4.0 * EPS)):
        shape = np.broadcast_shapes(u.shape, k.shape)
        return np.broadcast_to(u, shape).copy(), np.zeros(shape), np.zeros(shape)
    return _reduce_dd(u, *ellipk_dd(m, m1))


def jacobi_am(u, m, m1=None):
    """Jacobi amplitude am(u | m), continuous and increasing in u.

    With ``u = q K + x``, ``|x| <= K/2`` (:func:`reduce_quarter_period`),
    ``am(u) = q pi/2 + atan2(sn x, cn x)`` for even q and
    ``q pi/2 + atan2(k' sn x, cn x)`` for odd q (from A&S 16.8.1), with pi/2 as a
    double-double; for ``m1 == 0`` it is the Gudermannian ``2 atan(tanh(u/2))``.
    """
    u = np.asarray(u, dtype=float)
    _, (s, c, _), (q, _) = _jacobi_parts(u, m, m1)
    m, m1 = _params(m, m1)
    odd = np.mod(q, 2.0) == 1.0
    delta = np.arctan2(np.where(odd, np.sqrt(m1) * s, s), c)
    am = q * (0.5 * dd.PI[0]) + (q * (0.5 * dd.PI[1]) + delta)
    return np.where(m1 == 0, 2.0 * np.arctan(np.tanh(0.5 * u)), am)


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
    return _quarter_shift(n, s, c, d, lv.m, lv.m1, separatrix, x)


def _quarter_shift(n, s, c, d, m, m1, separatrix=None, x=None):
    """sn, cn, dn of ``n K + x`` from those of x (A&S 16.8.1), and those of x.

    Where ``separatrix`` (or ``m1 == 0``) the functions of x are replaced by
    tanh, sech, sech of ``x`` (n must be 0 there).
    """
    sep = m1 == 0 if separatrix is None else separatrix
    if np.any(sep):
        with np.errstate(over="ignore"):
            sech = 1.0 / np.cosh(x)
        s = np.where(sep, np.tanh(x), s)
        c = np.where(sep, sech, c)
        d = np.where(sep, sech, d)
    kp = np.where(sep, 0.0, np.sqrt(m1))
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
