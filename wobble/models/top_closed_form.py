"""The heavy top's exact motion evaluated from its constants (SI, float64; notes section 5.7).

The evaluators the model (:mod:`wobble.models.top`) hands the times to. Their
constants come from the 60-digit set-up (:mod:`wobble.models.top_setup`); here
everything is float64 and vectorised over the times.

* :class:`Uniform`: theta constant (the sleeping top, regular precession, a top
  hanging at rest): phi and psi advance at constant rates.
* :class:`Elliptic`: the nutating top. With w = lambda t + w0,
  lambda = sqrt(beta (u3 - u1))/2 and m = (u2 - u1)/(u3 - u1) (notes p. 72;
  Goldstein, Poole & Safko 2002, sec. 5.7),

      x = 1 - u = x1 cn^2(w|m) + x2 sn^2(w|m),

  and the half angles sigma = (phi + psi)/2, delta = (phi - psi)/2 are a secular
  part (:class:`Secular`) plus 2K-periodic parts Pi(n; am w | m) - (Pi(n|m)/K) w,
  elliptic integrals of the third kind in Carlson's forms with positive terms
  (:func:`wobble.numerics.elliptic.pi_positive_scd`, ``pi_negative_scd``).

Each evaluator's ``core(t)`` returns the pieces the model assembles into the
motion: sin and cos of theta/2 (signed through a pole), sigma, delta, phi = sigma + delta
(from its own secular phase), the rates, u = cos theta and phidot sin theta.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from wobble.numerics import elliptic as ell
from wobble.numerics import highprec as hp
from wobble.numerics.double_double import WHOLE_PIECES, minus_multiple, two_prod
from wobble.numerics.phase import reduce_phase, split_dd

__all__ = ["Uniform", "Secular", "Elliptic", "TWO_PI_DD", "TWO_PI_PIECES", "TWO_PI"]

#: 2 pi as a double-double pair (the period of the secular phases).
TWO_PI_DD = hp.TWO_PI_DD
#: 2 pi in three floats of 26, 26 and the rest bits (Cody-Waite reduction: k * piece exact).
TWO_PI_PIECES = split_dd(*TWO_PI_DD)
#: 2 pi rounded to float64.
TWO_PI = TWO_PI_DD[0]


@dataclass(frozen=True)
class Uniform:
    """theta constant (sleeping top, regular precession, hanging at rest)."""

    sh: float
    ch: float
    u: float
    sigma_rate: tuple[float, float]
    delta_rate: tuple[float, float]
    sigma0: float
    delta0: float
    # phi's own phase, as in Elliptic: sigma and delta each carry the spin psidot/2, so their sum
    # would add two reductions' roundings to a phi that may not move at all (one rounding here).
    phi_rate: tuple[float, float]
    phi0: float
    phidot: float
    psidot: float

    def core(self, t):
        n = t.shape
        sig, _ = reduce_phase(t, self.sigma_rate, TWO_PI_DD, self.sigma0)
        dlt, _ = reduce_phase(t, self.delta_rate, TWO_PI_DD, self.delta0)
        phi, _ = reduce_phase(t, self.phi_rate, TWO_PI_DD, self.phi0)
        sh = np.full(n, self.sh)
        ch = np.full(n, self.ch)
        zero = np.zeros(n)
        return dict(
            sh=sh,
            ch=ch,
            sigma=sig,
            delta=dlt,
            phi=phi,
            thetadot=zero,
            phidot=np.full(n, self.phidot),
            psidot=np.full(n, self.psidot),
            u=np.full(n, self.u),
            phidot_sin=np.full(n, self.phidot * 2 * self.sh * self.ch),
        )


@dataclass(frozen=True)
class Secular:
    """A secular phase Omega t + offset from the reduced nutation phase (no second pass over t).

    With lambda t + w0 = 2K j + r (j an exact integer, |r| <= K),
    Omega t = j A + c (r - w0), A = (2K Omega / lambda) mod 2 pi (to ~30 digits, split in three
    floats so that j a1 and j a2 are exact for |j| < 2^26) and c = Omega / lambda. The product
    j a1 is reduced modulo 2 pi by Cody-Waite before the small terms are added, so the error
    is a few ulps of 2 pi whatever t is -- the bound of :func:`wobble.numerics.phase.reduce_phase`
    at a third of its cost. From 2^26 whole periods on (:meth:`far`) j a1 and j a2 are taken by
    Dekker's exact product and each reduced by :func:`~wobble.numerics.double_double.minus_multiple`:
    the same few ulps to 2^50 periods, the nutation phase's own reach.
    """

    a: tuple[float, float, float]
    c: float
    offset: float

    def _near(self, j):
        z = j * self.a[0]  # exact for |j| < 2^26
        k = np.rint(z * (1.0 / TWO_PI))
        return ((z - k * TWO_PI_PIECES[0]) - k * TWO_PI_PIECES[1]) - k * TWO_PI_PIECES[2]

    def far(self, j):
        """j A modulo 2 pi as ``z + rest`` (|z| <= 2 pi, |rest| a few radians at most) for any
        integer-valued j below 2^50, where the three-piece products of :meth:`__call__` are not exact."""
        a1, a2, a3 = self.a
        p1, e1 = two_prod(j, a1)  # j a1 = p1 + e1 exactly; |e1| <= ulp(p1)/2 <= 1 for |j| < 2^50
        r1, l1 = minus_multiple(p1, np.rint(p1 * (1.0 / TWO_PI)), *TWO_PI_DD)
        p2, e2 = two_prod(j, a2)  # |j a2| < 2^51 pi 2^-25: reduced as well
        r2, l2 = minus_multiple(p2, np.rint(p2 * (1.0 / TWO_PI)), *TWO_PI_DD)
        # |j a3| <= 2 pi (a3 holds A's bits past the 52nd): one rounding of a few radians.
        return r1 + r2, ((l1 + l2) + (e1 + e2)) + j * a3

    def __call__(self, j, r, w0):
        _, a2, a3 = self.a
        tail = self.c * (r - w0) + self.offset
        out = self._near(j) + (j * a2 + (j * a3 + tail))
        big = np.abs(j) >= WHOLE_PIECES
        if np.any(big):
            z, rest = self.far(j)
            out = np.where(big, z + (rest + tail), out)
        return out

    def whole_periods(self, j):
        """j A modulo 2 pi (up to a few ulps of 2 pi): the advance over j whole nutation periods."""
        _, a2, a3 = self.a
        out = self._near(j) + (j * a2 + j * a3)
        big = np.abs(j) >= WHOLE_PIECES
        if np.any(big):
            z, rest = self.far(j)
            out = np.where(big, z + rest, out)
        return out


@dataclass(frozen=True)
class Elliptic:
    """Nutating top: u(t) by Jacobi functions, phi and psi by Pi(n; am w | m).

    Scaled so that nothing underflows next to the poles: with sx^2 = cn^2 + rho_x sn^2
    (rho_x = x2/x1) and sy^2 = rho_y cn^2 + sn^2 (rho_y = y1/y2),
    sin(theta/2) = hx1 sx, cos(theta/2) = hy2 sy (hx1 = sqrt(x1/2), hy2 = sqrt(y2/2)),
    B/x = (B/x1)/sx^2, C/y = (C/y2)/sy^2. A motion through the vertical (x2 = 0)
    has sin(theta/2) = hx1 cn(w), signed; through the bottom (y1 = 0), cos(theta/2) = hy2 sn(w).
    """

    hx1: float
    hy2: float
    rho_x: float
    rho_y: float
    x1: float
    y2: float
    B: float
    C: float
    B_x1: float  # B / x1
    C_y2: float  # C / y2
    Bp: float  # (B / x1) hx1 hy2: phidot sin(theta) = Bp sy/sx + Cp sx/sy
    Cp: float
    W: float  # (x1 - x2) / (hx1 hy2): thetadot = -lambda W sn cn dn / (sx sy)
    through_top: bool
    through_bottom: bool
    a: float
    omega3: float
    lam: tuple[float, float]
    K: tuple[float, float]
    w0: float
    m: float
    m1: float
    n_plus: float
    one_minus_n_plus: float
    nu_minus: float
    pi_plus_over_k: float
    pi_minus_over_k: float
    k_plus: float  # B / (2 lambda x1): delta = ... + k_plus P_+(w)
    k_minus: float  # C / (2 lambda y1): sigma = ... + k_minus P_-(w)
    r0: float  # the reduced nutation phase at t = 0 (what phase(0) gives)
    # What sigma's and delta's periodic parts miss at the start by taking the double r0 for the exact w0
    # (wobble.models.top_setup: k (P(w0) - P(r0)), or a pass through a pole's turn already made): next to a
    # pole these parts turn by pi over a phase of the tilt, so the ulp of w0 turned the whole motion.
    anchor_sigma: float
    anchor_delta: float
    # sn, cn, dn of the exact w0 (from its 60-digit value, so cn keeps its relative digits next to a pole):
    # the rates at phases that round to r0, which the anchors put at w0 (see :meth:`core`).
    start_scd: tuple[float, float, float]
    sigma_sec: Secular
    delta_sec: Secular
    # phi = sigma + delta has its own secular phase: its rate (B <1/x> + C <1/y>)/2 has no
    # spin term, where sigma's and delta's carry +-(omega3 - a)/2, so a fast spin's large
    # phases (c (r - w0) of order omega3 x nutation period) do not cancel into phi.
    phi_sec: Secular
    psi_sec: Secular  # psi = sigma - delta: the series' angles take it alone
    levels: object = field(repr=False, compare=False)

    def phase(self, t):
        return reduce_phase(t, self.lam, (2 * self.K[0], 2 * self.K[1]), self.w0)

    # P_+ and P_- at t = 0, through the very path the evaluation takes (so that the attitude
    # at t = 0 is q0 but for the anchors, the parts' change over the sub-ulp rest of w0, which
    # show only next to a pole, at about 6e-16 rad): computed on first use, or taken from the series' first
    # batch of NumPy samples, which holds r0 (wobble.models.top_series.build). Elementwise
    # NumPy and SciPy give each element the same value whatever the batch.
    @cached_property
    def _start(self) -> tuple[float, float]:
        r0 = np.array([self.r0])
        s_, c_, d_ = ell.jacobi_reduced(r0, self.levels, self.K[1])
        p_plus, p_minus = self.periodic_parts(r0, s_, c_, d_)
        return float(p_plus[0]), float(p_minus[0])

    @property
    def p_plus0(self) -> float:
        """P_+(r0), the periodic part of J_+ at t = 0."""
        return self._start[0]

    @property
    def p_minus0(self) -> float:
        """P_-(r0), the periodic part of J_- at t = 0."""
        return self._start[1]

    def periodic_parts(self, r, sn, cn, dn):
        """P_+(r) and P_-(r): the 2K-periodic parts Pi(n; am r | m) - (Pi(n|m)/K) r, |r| <= K."""
        d2 = dn * dn
        p_plus = p_minus = np.zeros_like(r)
        # R_F(cn^2, dn^2, 1) is common to both integrals: evaluated once when both are needed.
        rf = ell.carlson_rf_scd(cn, d2) if self.k_plus != 0.0 and self.k_minus != 0.0 else None
        if self.k_plus != 0.0:
            pi = ell.pi_positive_scd(self.n_plus, self.one_minus_n_plus, sn, cn, d2, rf)
            p_plus = pi - self.pi_plus_over_k * r
        if self.k_minus != 0.0:
            pi = ell.pi_negative_scd(self.nu_minus, sn, cn, d2, self.m1, rf)
            p_minus = pi - self.pi_minus_over_k * r
        return p_plus, p_minus

    def _scaled(self, sn, cn):
        sn2, cn2 = sn * sn, cn * cn
        return np.sqrt(cn2 + self.rho_x * sn2), np.sqrt(self.rho_y * cn2 + sn2)

    def periodic_of_r(self, r):
        """theta(r), k_- P_-(r), k_+ P_+(r) and dtheta/dr for a reduced phase |r| <= K.

        The 2K-periodic functions of the nutation phase that the series accelerator
        expands (used only when the axis stays off the poles, so no sign folding);
        dtheta/dr = -W sn cn dn / (sx sy), thetadot = lambda dtheta/dr.
        """
        sn, cn, dn = ell.jacobi_reduced(r, self.levels, self.K[1])
        sx, sy = self._scaled(sn, cn)
        theta = 2.0 * np.arctan2(self.hx1 * sx, self.hy2 * sy)
        p_plus, p_minus = self.periodic_parts(r, sn, cn, dn)
        return theta, self.k_minus * p_minus, self.k_plus * p_plus, -self.W * sn * cn * dn / (sx * sy)

    def periodic_with_half_angles(self, r):
        """:meth:`periodic_of_r` and sin(theta/2), cos(theta/2) at the same phases (|r| <= K)."""
        return self.periodic_with_half_angles_and_parts(r)[0]

    def periodic_with_half_angles_and_parts(self, r):
        """:meth:`periodic_with_half_angles` and the raw P_+(r), P_-(r) it scales (for the series' set-up)."""
        sn, cn, dn = ell.jacobi_reduced(r, self.levels, self.K[1])
        sx, sy = self._scaled(sn, cn)
        sh, ch = self.hx1 * sx, self.hy2 * sy
        theta = 2.0 * np.arctan2(sh, ch)
        p_plus, p_minus = self.periodic_parts(r, sn, cn, dn)
        rows = (theta, self.k_minus * p_minus, self.k_plus * p_plus, -self.W * sn * cn * dn / (sx * sy), sh, ch)
        return rows, (p_plus, p_minus)

    def _rates(self, sn, cn, dn, par):
        """sx, sy, thetadot, B/x and C/y of :meth:`core` from sn, cn, dn of the reduced phase and its parity."""
        sx, sy = self._scaled(sn, cn)
        lam = self.lam[0]
        scd = sn * cn * dn
        with np.errstate(divide="ignore", invalid="ignore"):
            # The signed forms through a pole cancel the vanishing factor analytically.
            if self.through_top and self.through_bottom:
                sx, sy = par * cn, par * sn
                thetadot = -lam * self.W * dn
            elif self.through_top:
                sx = par * cn
                thetadot = -lam * self.W * par * sn * dn / sy
            elif self.through_bottom:
                sy = par * sn
                thetadot = -lam * self.W * par * cn * dn / sx
            else:
                thetadot = -lam * self.W * scd / (sx * sy)
            zero = np.zeros_like(sx)
            bx = self.B_x1 / (sx * sx) if self.B_x1 != 0.0 else zero
            cy = self.C_y2 / (sy * sy) if self.C_y2 != 0.0 else zero
            b_term = self.Bp * sy / sx if self.Bp != 0.0 else zero
            c_term = self.Cp * sx / sy if self.Cp != 0.0 else zero
        return sx, sy, thetadot, bx, cy, b_term + c_term

    @cached_property
    def _start_rates(self) -> tuple[float, float]:
        """thetadot and phidot sin(theta) at the exact w0 (|w0| <= K, cn >= 0), for a motion off the poles."""
        sn0, cn0, dn0 = (np.array([x]) for x in self.start_scd)
        _, _, thetadot, _, _, phidot_sin = self._rates(sn0, cn0, dn0, np.ones(1))
        return float(thetadot[0]), float(phidot_sin[0])

    def core(self, t):
        r, j = self.phase(t)
        sn, cn, dn = ell.jacobi_reduced(r, self.levels, self.K[1])
        # A phase past the true K by K's rounding (cn < 0, below an ulp of phase) is taken mirrored about K,
        # as the anchors take r0 (wobble.models.top_setup._anchors): the rates, sigma and delta then describe
        # one point. The Pi of delta is even in cn and mirrored anyway; sigma's R_C term and the rates were not,
        # so next to a pole omega at such a phase (t = T for a top started 2e-9 rad from the vertical) was
        # off by 4e-8 rad/s.
        cn = np.abs(cn)
        odd = np.floor(0.5 * j) != 0.5 * j
        par = np.where(odd, -1.0, 1.0)  # sn(w) = par sn(r), cn(w) = par cn(r)
        sx, sy, thetadot, bx, cy, phidot_sin = self._rates(sn, cn, dn, par)
        sh = self.hx1 * sx
        ch = self.hy2 * sy
        phidot = 0.5 * (bx + cy)
        psidot = (self.omega3 - self.a) - 0.5 * (bx - cy)
        p_plus, p_minus = self.periodic_parts(r, sn, cn, dn)
        per_minus = self.k_minus * (p_minus - self.p_minus0) - self.anchor_sigma
        per_plus = self.k_plus * (p_plus - self.p_plus0) - self.anchor_delta
        start = r == self.r0
        if start.any() and not (self.through_top or self.through_bottom):
            # A phase that rounds to r0 (t = 0, and t = k T) stands for the exact w0 (+ 2K k), where the
            # periodic parts are back at their start and the rates are the start's. Evaluated at the double
            # r0 instead, an ulp of phase off, next to a pole (where sigma, delta and the frame of the rates
            # turn by pi over a phase of the tilt) the angles came out at the phase mirrored about the turning
            # point and the rates at r0 itself: omega(0) was off by up to 0.13 rad/s (a top started 2.3e-15
            # rad from the vertical), though the quaternion, which sin(theta/2) damps there, was q0. (A pass
            # followed through a pole has anchors of another kind, the part of its turn already made: kept.)
            td0, ps0 = self._start_rates
            thetadot = np.where(start, td0, thetadot)
            phidot_sin = np.where(start, ps0, phidot_sin)
            per_minus = np.where(start, 0.0, per_minus)
            per_plus = np.where(start, 0.0, per_plus)
        sig = self.sigma_sec(j, r, self.w0) + per_minus
        dlt = self.delta_sec(j, r, self.w0) + per_plus
        phi = self.phi_sec(j, r, self.w0) + (per_minus + per_plus)
        x = self.x1 * (sx * sx)
        y = self.y2 * (sy * sy)
        u = np.where(x <= 1.0, 1.0 - x, y - 1.0)
        return dict(
            sh=sh,
            ch=ch,
            sigma=sig,
            delta=dlt,
            phi=phi,
            thetadot=thetadot,
            phidot=phidot,
            psidot=psidot,
            u=u,
            phidot_sin=phidot_sin,
        )
