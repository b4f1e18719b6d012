"""The heavy top's set-up in 60-digit decimal arithmetic (SI; notes section 5.7, pp. 71-72).

From the exact float inputs (moments about the tip, M g l and the initial state,
gathered in a :class:`TopSetup`) :func:`analyse` computes, once per top, what the
model reports and what its evaluators (:mod:`wobble.models.top_closed_form`) need:

* the conserved quantities p_psi = I3 omega3 = I1 a, p_phi = I1 b, E and
  E' = E - I3 omega3^2 / 2, alpha = 2 E'/I1, beta = 2 M g l / I1 (notes p. 71);
* the roots of f(u) = beta (u - u1)(u - u2)(u - u3), found in x = 1 - u and
  y = 1 + u (:mod:`wobble.numerics.cubic`), so the turning angles keep their
  relative digits next to both poles and at double roots;
* the nutation class from the sign of phidot = (b - a u)/(1 - u^2) at the turning
  points (notes p. 72), the parameter m and 1 - m without cancellation, K(m), the
  nutation period 4 K / sqrt(beta (u3 - u1)), the complete Pi(n|m) and the mean
  precession and spin rates (Goldstein, Poole & Safko 2002, sec. 5.7), the secular phase
  rates as double-double pairs, and the initial nutation phase w0, whose rest past its double
  the periodic parts of the half angles take up at the start (the anchors): next to a pole
  it would turn the whole motion.

Everything is decimal at :data:`DIGITS` digits until it is rounded once to float64;
Decimal(float) is exact, so the inputs enter without rounding.
"""

from __future__ import annotations

import decimal
from dataclasses import dataclass
from decimal import Decimal

import numpy as np

from wobble.numerics.floats import EPS
from wobble.errors import InputError
from wobble.models.top_closed_form import Elliptic, Secular, Uniform
from wobble.numerics import cubic
from wobble.numerics import elliptic as ell
from wobble.numerics import highprec as hp
from wobble.numerics.phase import reduce_phase, split_dd

__all__ = ["DIGITS", "TopSetup", "analyse", "context", "to_decimal"]

#: Working precision of the set-up (significant digits).
DIGITS = cubic.DIGITS
# x2/x1 (or y1/y2) below this: the axis passes the pole closer than sqrt(_POLE) theta_max,
# i.e. below the rounding of theta_max, and the motion is followed as a pass through it.
_POLE = Decimal("1e-32")


_CONTEXT = hp.make_context(DIGITS)  # every setting given: none from decimal.DefaultContext


def context() -> decimal.Context:
    """The decimal context of the set-up (:data:`DIGITS` significant digits): one shared
    template, which decimal.localcontext copies."""
    return _CONTEXT


def to_decimal(x) -> Decimal:
    """The exact Decimal of a float (Decimal(float) is exact; arithmetic rounds to the context)."""
    return x if isinstance(x, Decimal) else Decimal.from_float(float(x))  # no FloatOperation signal


def _f(x: Decimal) -> float:
    return float(x)


@dataclass(frozen=True)
class TopSetup:
    """A top and its initial state, exact, as the analysis takes them (SI).

    Attributes
    ----------
    I1, I3, mgl : float
        Moments about the tip (kg m^2) and M g l (J), already checked.
    theta0 : float
        Initial tilt (rad), in [0, pi].
    sin_half, cos_half : Decimal
        sin and cos of theta0 / 2 to :data:`DIGITS` digits (full relative accuracy
        next to both poles).
    thetadot0 : Decimal
        Initial nutation rate (rad/s).
    v0 : Decimal
        phidot0 sin theta0 (rad/s): finite at the poles, where phidot0 is not defined.
    omega3 : Decimal
        Spin about the symmetry axis (rad/s).
    phi0, psi0 : Decimal
        Initial precession and spin angles (rad).
    phidot0 : float
        The precession rate as given, reported for a top started exactly upright
        (where phidot0 sin theta0 = 0 says nothing about it).
    """

    I1: float
    I3: float
    mgl: float
    theta0: float
    sin_half: Decimal
    cos_half: Decimal
    thetadot0: Decimal
    v0: Decimal
    omega3: Decimal
    phi0: Decimal
    psi0: Decimal
    phidot0: float


@dataclass(frozen=True)
class _Start:
    """The initial state in the variables of the analysis (decimal)."""

    x0: Decimal  # 1 - cos theta0
    y0: Decimal  # 1 + cos theta0
    s0: Decimal  # sin theta0
    u0: Decimal  # cos theta0
    thetadot0: Decimal  # signed so that theta stays in [0, pi]
    a: Decimal
    beta: Decimal
    sigma0: Decimal  # (phi0 + psi0)/2 (+ pi for a start across a pole)
    delta0: Decimal  # (phi0 - psi0)/2


def theta_of(x: Decimal, y: Decimal) -> float:
    """theta = 2 atan2(sqrt(x/2), sqrt(y/2)) from exact x = 1 - u and y = 1 + u.

    The square roots are taken in decimal: x itself underflows float64 for theta below
    1e-154 rad, its root does not.
    """
    with decimal.localcontext(context()):
        sx = (max(x, Decimal(0)) / 2).sqrt()
        sy = (max(y, Decimal(0)) / 2).sqrt()
    return float(2.0 * np.arctan2(float(sx), float(sy)))


def secular_phase(rate: Decimal, lam: Decimal, kdec: Decimal, offset) -> Secular:
    """The :class:`~wobble.models.top_closed_form.Secular` of a phase rate (rad/s) for nutation
    rate lambda and quarter period K: its advance 2 K rate / lambda over a nutation period,
    reduced modulo 2 pi at :data:`DIGITS` digits."""
    with decimal.localcontext(context()):
        two_pi = 2 * hp.PI
        adv = 2 * kdec * rate / lam
        adv = adv - two_pi * (adv / two_pi).to_integral_value()
        hi, lo = hp.to_dd(adv)
        # split_dd cannot split below the normal range; j times such an advance is far
        # below rounding anyway.
        pieces = split_dd(hi, lo) if abs(hi) > 1e-280 else (0.0, 0.0, hi + lo)
        return Secular(a=pieces, c=_f(rate / lam), offset=float(offset))


def complete_pi_pair(kc: Decimal, p_plus, p_minus) -> tuple[Decimal, Decimal]:
    """``hp.cel(kc, p, 1, 1)`` for p = ``p_plus`` and ``p_minus`` (None: 0 returned), in one loop
    (:func:`wobble.numerics.highprec.cel_many`: one square root per step for both)."""
    given = [p for p in (p_plus, p_minus) if p is not None]
    values = iter(hp.cel_many(kc, [(p, 1, 1) for p in given]) if given else [])
    return tuple(Decimal(0) if p is None else next(values) for p in (p_plus, p_minus))


def analyse(setup: TopSetup) -> dict:
    """The analysis and the evaluator of a top: the fields of :class:`wobble.models.top.HeavyTopModel`.

    Returns
    -------
    dict
        Every field of the model, the evaluator under ``"_impl"``.

    Raises
    ------
    wobble.errors.InputError
        A state on the separatrix (1 - m = 0) or within 1e-150 of it.
    """
    s = setup
    sh, ch = s.sin_half, s.cos_half
    v0, w3 = s.v0, s.omega3
    with decimal.localcontext(context()):
        i1, i3, mg = to_decimal(s.I1), to_decimal(s.I3), to_decimal(s.mgl)
        x0, y0 = 2 * sh * sh, 2 * ch * ch
        s0 = 2 * sh * ch
        u0 = ch * ch - sh * sh
        thetadot0, sigma_shift = _across_a_pole(x0, y0, s.thetadot0)
        a = i3 * w3 / i1
        beta = 2 * mg / i1
        kin = thetadot0 * thetadot0 + v0 * v0  # thetadot^2 + phidot^2 sin^2 theta
        A = kin - beta * x0  # alpha - beta
        B = v0 * s0 - a * x0  # b - a
        C = v0 * s0 + a * y0  # b + a
        g0 = s0 * s0 * thetadot0 * thetadot0
        cub = cubic.TopCubic(A=A, B=B, C=C, a=a, beta=beta)
        # g'(x0) without cancellation (A + beta x0 = kin, B + a x0 = v0 s0): the offsets of the turning
        # points from x0 keep their digits however narrow the nutation (M g l -> 0 with a fast spin).
        dg0 = 2 * u0 * kin + beta * x0 * y0 - 2 * a * v0 * s0
        roots = cubic.top_roots(cub, x0, y0, g0, dg0)
        start = _Start(
            x0=x0,
            y0=y0,
            s0=s0,
            u0=u0,
            thetadot0=thetadot0,
            a=a,
            beta=beta,
            sigma0=(s.phi0 + s.psi0) / 2 + sigma_shift,
            delta0=(s.phi0 - s.psi0) / 2,
        )
        # Regular precession to rounding (the bracket of df/du vanishes within the rounding of
        # the inputs): reported as such (u1 = u2 = u0, m = 0), but the motion keeps the
        # exact, tiny nutation of the given floats, so the phases stay exact over long spans.
        e0 = 2 * u0 * v0 * v0 + beta * s0 * s0 - 2 * a * v0 * s0  # g'(x0) when thetadot0 = 0
        e0_scale = 2 * abs(u0) * v0 * v0 + beta * s0 * s0 + 2 * abs(a * v0 * s0)
        regular = thetadot0 == 0 and abs(e0) <= 16 * Decimal(EPS) * e0_scale
        uniform = _uniform_kind(s, start, roots, regular)
        common = _common_fields(s, start, i1, i3, mg, kin)
        if uniform is not None:
            return {**common, **_uniform(uniform, s, start, roots)}
        fields = {**common, **_elliptic(s, start, cub, roots)}
        if regular:
            fields.update(_regular_to_rounding(s, start))
        return fields


def _across_a_pole(x0: Decimal, y0: Decimal, thetadot0: Decimal) -> tuple[Decimal, Decimal]:
    """``(thetadot0, sigma shift)``: a top started exactly at a pole moving "outwards" across it is
    the same motion with (theta, phi, psi) -> (-theta, phi + pi, psi + pi), which keeps theta in [0, pi]."""
    if (x0 == 0 and thetadot0 < 0) or (y0 == 0 and thetadot0 > 0):
        return -thetadot0, hp.PI
    return thetadot0, Decimal(0)


def _uniform_kind(s: TopSetup, st: _Start, roots: cubic.TopRoots, regular: bool) -> str | None:
    """Which motion with theta constant the state is ("sleeping", "regular"), or None.

    Raises
    ------
    wobble.errors.InputError
        A state on the separatrix (1 - m = 0) or within 1e-150 of it.
    """
    if st.thetadot0 == 0 and st.x0 == 0:
        return "sleeping"
    if st.thetadot0 == 0 and st.y0 == 0:
        return "regular"  # hanging straight down, spinning
    if roots.width == 0:
        return "regular"  # no nutation at all (a double root)
    if roots.beta_gap <= 0 or roots.beta_span <= 0 or roots.beta_gap < Decimal("1e-150") * roots.beta_span:
        if regular:  # e.g. at rest without gravity (f vanishes identically): nothing moves
            return "regular"
        if roots.beta_gap <= 0:
            raise InputError(
                "thetadot0",
                _f(s.thetadot0),
                "an initial state off the separatrix (the motion "
                "would approach an unstable equilibrium for ever; 1 - m = 0)",
            )
    return None


def _common_fields(s: TopSetup, st: _Start, i1: Decimal, i3: Decimal, mg: Decimal, kin: Decimal) -> dict:
    """The fields every kind of motion has: the parameters, the constants of the motion (Goldstein, Poole &
    Safko 2002, sec. 5.7: a = p_psi/I1, b = p_phi/I1, alpha = 2E'/I1, beta = 2 M g l/I1) and the sleeping top's
    stability (I3^2 omega3^2 > 4 M g l I1)."""
    w3, v0 = s.omega3, s.v0
    b = v0 * st.s0 + st.a * st.u0
    return dict(
        I1=s.I1,
        I3=s.I3,
        mgl=s.mgl,
        theta0=s.theta0,
        thetadot0=_f(s.thetadot0),  # as given: a start across a pole is analysed with its sign turned
        phi0=_f(s.phi0),
        psi0=_f(s.psi0),
        omega3=_f(w3),
        a=_f(st.a),
        b=_f(b),
        p_psi=_f(i3 * w3),
        p_phi=_f(i1 * b),
        energy=_f(i1 * kin / 2 + i3 * w3 * w3 / 2 + mg * st.u0),
        energy_prime=_f(i1 * kin / 2 + mg * st.u0),
        alpha=_f(kin + st.beta * st.u0),
        beta=_f(st.beta),
        sleeping_stable=bool(i3 * i3 * w3 * w3 > 4 * mg * i1),
    )


def _regular_to_rounding(s: TopSetup, st: _Start) -> dict:
    """The fields reported for regular precession to rounding (u1 = u2 = u0, m = 0); the motion itself
    keeps the exact nutation of the given floats."""
    u_0 = _f(st.u0) if st.x0 <= 1 else _f(st.y0 - 1)
    return dict(
        nutation="regular",
        u1=u_0,
        u2=u_0,
        x1=_f(st.x0),
        x2=_f(st.x0),
        m=0.0,
        m1=1.0,
        theta_min=s.theta0,
        theta_max=s.theta0,
    )


def _report_roots(roots: cubic.TopRoots):
    x1, x2 = roots.x1, roots.x2
    y1, y2 = 2 - x1, 2 - x2
    u1 = _f(1 - x1) if x1 <= 1 else _f(y1 - 1)
    u2 = _f(1 - x2) if x2 <= 1 else _f(y2 - 1)
    u3 = float("inf") if roots.x3.is_infinite() else _f(1 - roots.x3)
    return u1, u2, u3


def _uniform(kind: str, s: TopSetup, st: _Start, roots: cubic.TopRoots) -> dict:
    """Fields of a motion with theta constant: the sleeping top, regular precession, hanging."""
    with decimal.localcontext(context()):
        if st.s0 != 0:
            phidot = s.v0 / st.s0
        else:
            phidot = to_decimal(s.phidot0) if kind == "sleeping" else Decimal(0)
        psidot = s.omega3 - st.u0 * phidot
        if kind == "sleeping" and not roots.x3.is_infinite() and roots.x3 >= 0:
            # Unstable sleeping top: an equilibrium; the roots are 1 - c2/beta, 1, 1.
            u1, u2, u3 = _f(1 - roots.x1), 1.0, 1.0
            period = float("inf")
            m, m1 = 1.0, 0.0
        else:
            # Regular precession (or a stable sleeping top): u1 = u2 = u0, m = 0, and the
            # period of small nutations about it, 2 pi / sqrt(beta (u3 - u0)).
            u1 = u2 = _f(st.u0) if st.x0 <= 1 else _f(st.y0 - 1)
            if roots.x3.is_infinite():
                span = roots.beta_span
                u3 = float("inf")
            else:
                span = roots.beta_span * (st.x0 - roots.x3) / (roots.x1 - roots.x3)
                u3 = _f(1 - roots.x3)
            period = _f(2 * hp.PI / span.sqrt()) if span > 0 else float("inf")
            m, m1 = 0.0, 1.0
        theta0 = s.theta0
        impl = Uniform(
            sh=_f(s.sin_half),
            ch=_f(s.cos_half),
            u=_f(st.u0),
            sigma_rate=hp.to_dd((phidot + psidot) / 2),
            delta_rate=hp.to_dd((phidot - psidot) / 2),
            sigma0=_f(st.sigma0),
            delta0=_f(st.delta0),
            phi_rate=hp.to_dd(phidot),
            phi0=_f(st.sigma0 + st.delta0),
            phidot=_f(phidot),
            psidot=_f(psidot),
        )
        est = {
            "theta_rad": 4 * EPS * max(theta0, EPS),
            "attitude_rad": 8 * EPS,
            "turning_points_relative": 2 * EPS,
            "period_relative": 4 * EPS,
            "mean_precession_rate_rad_per_s": 2 * EPS * abs(_f(phidot)),  # the rate itself, rounded once
        }
        return dict(
            phidot0=_f(phidot),
            psidot0=_f(psidot),
            u1=u1,
            u2=u2,
            u3=u3,
            x1=_f(st.x0),
            x2=_f(st.x0),
            x3=-float("inf") if roots.x3.is_infinite() else _f(roots.x3),
            theta_min=theta0,
            theta_max=theta0,
            nutation=kind,
            m=m,
            m1=m1,
            nutation_period=period,
            mean_precession_rate=_f(phidot),
            mean_spin_rate=_f(psidot),
            error_estimate=est,
            _impl=impl,
        )


def nutation_class(B, a, x1, x2, C, v0s0, d_low, d_high) -> str:
    """'undulating', 'cusps' or 'loops' from the sign of phidot at the two turning points (notes p. 72).

    phidot = (b - a u)/(1 - u^2), and b - a u at a turning point is v0 s0 + a (x - x0) (B + a x0 = v0 s0 =
    phidot0 sin^2 theta0): v0 s0 - a d_low at x2 and v0 s0 + a d_high at x1, from the roots' own offsets
    (:class:`wobble.numerics.cubic.TopRoots`), so no 60-digit x cancels into it. It is zero (a cusp) only
    within the set-up's digits; a zero within 64 eps of its terms, as before, called loops 1e-12 rad wide
    cusps (a fast top with phidot0 = -1e-10 rad/s). At a pole passed through, phidot is +-a/2.
    """
    zero = Decimal(10) ** (15 - DIGITS)

    def sign_at(x, offset):
        if x == 0 and B == 0:  # through the vertical: phidot = a/(1 + u) = a/2
            n, scale = a, abs(a)
        elif 2 - x == 0 and C == 0:  # through the bottom: phidot = -a/(1 - u) = -a/2
            n, scale = -a, abs(a)
        else:
            with decimal.localcontext(context()):
                n, scale = v0s0 + a * offset, abs(v0s0) + abs(a * offset)
        if abs(n) <= zero * scale:
            return 0
        return 1 if n > 0 else -1

    s1, s2 = sign_at(x1, d_high), sign_at(x2, -d_low)
    if s1 == 0 or s2 == 0:
        return "cusps"
    return "undulating" if s1 == s2 else "loops"


#: Digits of the mean precession rate's two terms before they are added: the complete integrals (Bulirsch's cel)
#: run at 50 digits and the roots' offsets at 60, so 45 is what the sum can cancel into (tests at 80-400 digits).
MEAN_RATE_DIGITS = 45


def _mean_phidot(n2, a, width, x1, x2, y1, y2, kc, kdec) -> tuple[Decimal, Decimal]:
    """The mean of phidot = (b - a u)/(1 - u^2) over a nutation period (rad/s), and a bound on its error.

    (B <1/x> + C <1/y>)/2 cancels as the nutation narrows: each term is about a/2 and their sum the
    slow precession, M g l/(I3 omega3) for a fast top, so at M g l = 1e-48 J (a = 5/s) the 50-digit
    complete integrals kept no digit of it. Here b - a u = n2 + a delta, with n2 = b - a u2 (from the
    offset x0 - x2, the caller's) and delta = x - x2 = (x1 - x2) cn^2 w, and

        delta/(x y) mean = (<delta/x> + <delta/y>)/2   (x2 <1/x> = 1 - <delta/x>, y2 <1/y> = 1 + <delta/y>),
        <delta/x> = (x1 - x2)/x1 cel(kc, x2/x1, 1, 0)/K,   <delta/y> = (x1 - x2)/y1 cel(kc, y2/y1, 1, 0)/K,

    (x = x1 (cos^2 + (x2/x1) sin^2), y = y1 (cos^2 + (y2/y1) sin^2) with sin = sn w; Bulirsch's cel).
    The second term is positive; the first has the sign of phidot at the turning point u2 (notes p. 72).
    Where phidot keeps its sign (cusps, undulating) the two add; where it changes sign (loops) they
    cancel, and under weak gravity the mean is 1e-60 of each: the bound, |terms| 10^-MEAN_RATE_DIGITS,
    says how many of the mean's digits survive (a review found loops at M g l = 1e-50 J printed with the
    wrong sign and no bound).
    """
    pi_x, pi_y, c_x, c_y = hp.cel_many(kc, [(x2 / x1, 1, 1), (y2 / y1, 1, 1), (x2 / x1, 1, 0), (y2 / y1, 1, 0)])
    with decimal.localcontext(context()):
        first = n2 * (pi_x / x1 + pi_y / y1)
        second = a * width * (c_x / x1 + c_y / y1)
        bound = (abs(first) + abs(second)) / (2 * kdec) * Decimal(10) ** (-MEAN_RATE_DIGITS)
        return (first + second) / (2 * kdec), bound


def _step_anchor(rate: Decimal, linear: Decimal, p1, p2, sn0, cn0, dn0, h: tuple[Decimal, Decimal]) -> float:
    """k (P(w0) - P(w0 - h)) for a periodic part k P with k P' = rate / q(w) - linear, q = p1 cn^2 + p2 sn^2
    (x = 1 - u for delta's, y = 1 + u for sigma's), over a step h far below the period (rad). ``h`` is the
    pair (step of Pi's argument, step of the secular term): they differ where the evaluation mirrors r0.

    Over the step sn and cn are linear in s = w - w0 to O(s^2): sn = sn0 + s cn0 dn0, cn = cn0 - s sn0 dn0
    (Jacobi's addition theorems), so q is the quadratic Q(s) = C + 2 B s + A s^2 with C = q(w0),
    B = p2 sn0 cn0 dn0 - p1 cn0 sn0 dn0 and A C - B^2 = (sqrt(p1 p2) dn0)^2 = D^2, whose integral is exact:

        int_{-h}^0 ds / Q(s) = atan2(h D, C - h B) / D.

    The neglected terms are relative h^2 (1e-34) of cn (and h^3 absolute), so this holds next to a pole too,
    where q(w0) may be 1e-32 of p1 and P turns by pi over a phase of sqrt(p2 / p1) about the pass: there the
    rest of w0 past its double is what turned the whole motion.
    """
    h, h_lin = h
    if rate == 0:
        return 0.0
    with decimal.localcontext(context()):
        c = p1 * cn0 * cn0 + p2 * sn0 * sn0
        b = (p2 - p1) * sn0 * cn0 * dn0
        d = (p1 * p2).sqrt() * dn0
        num, den = h * d, c - h * b
        if den > 0 and abs(num) < Decimal("1e-30") * den:
            z = num / den
            integral = h / den * (1 - z * z / 3)  # arctan z / z to 1e-120
        else:
            big = max(abs(num), abs(den))
            integral = Decimal(float(np.arctan2(_f(num / big), _f(den / big)))) / d
        return _f(rate * integral - linear * h_lin)


def _through_anchor(n_pole: Decimal, scale: Decimal, sn0, across: Decimal, along: Decimal, top: bool) -> float:
    """The turn a pass followed as one through a pole misses when the start lies within the pass (rad).

    Passed at sqrt(p2) << sqrt(p1) from the pole, sigma (bottom) or delta (top) turns by pi over a phase of
    about sqrt(p2 / p1) about the pass (w = K at the top, where x = x1 cn^2 + x2 sn^2; w = 0 at the bottom,
    where y = y1 cn^2 + y2 sn^2). Followed through the pole, that turn is the fold's step of pi at the pass,
    exact for a start outside the pass; a start inside it has made part of the turn already. In t = sc of the
    phase from the pass, n / (2 x) dt = n / (2 lambda) dn dt / (x1 m1 t^2 + x2) (top) and
    n / (2 y) dt = n / (2 lambda) dt / (dn (y1 + y2 t^2)) (bottom); with dn = 1 the part made is

        top:    n / (2 lambda sqrt(x1 x2 m1)) atan2(|sn0| sqrt(x2), cn0 sqrt(x1)),
        bottom: n / (2 lambda sqrt(y1 y2)) atan2(cn0 sqrt(y1), |sn0| sqrt(y2)),

    signed by sn0 (the bottom's fold adds its pi at sn0 < 0), each factor n / (2 lambda sqrt(...)) being +-1 to
    O(x2) (f(u) at u = +-1). Taking dn = 1 is exact to 2 sqrt(x2 / (x1 m1)) (or sqrt(y1 / (y2 m1))).
    ``n_pole`` is B (top) or C (bottom), ``scale`` lambda sqrt(x1 x2 m1) or lambda sqrt(y1 y2), ``across``
    cn0 sqrt(x1) (or sqrt(y1)) and ``along`` sqrt(x2) (or sqrt(y2)).
    """
    if n_pole == 0 or scale == 0:
        return 0.0
    with decimal.localcontext(context()):
        side = -1 if sn0 < 0 else 1
        f = n_pole / (2 * scale)
        big = max(abs(sn0) * along, across)
        if top:
            angle = np.arctan2(_f(abs(sn0) * along / big), _f(across / big))
            return _f(side * f * Decimal(float(angle)))
        angle = np.arctan2(_f(across / big), _f(abs(sn0) * along / big))
        return _f(-side * f * Decimal(float(angle)))


@dataclass(frozen=True)
class _Nutation:
    """A nutating top's constants (decimal, at :data:`DIGITS` digits): the parameter m and 1 - m, the
    rate lambda and quarter period K of the nutation phase, the complete Pi of the mean rates, and
    whether the axis passes a pole (followed as a pass through it)."""

    m: Decimal
    m1: Decimal
    lam: Decimal
    kdec: Decimal
    K: tuple[float, float]  # K as a double-double
    period: Decimal
    pi_plus: Decimal
    pi_minus: Decimal
    mean_inv_x: Decimal  # mean of 1/x over the nutation
    mean_inv_y: Decimal
    mean_phidot: Decimal
    mean_bound: Decimal  # the rounding of mean_phidot
    mean_psidot: Decimal
    top: bool  # the axis passes the upward pole (closer than its own rounding)
    bottom: bool
    rho_x: Decimal  # x2 / x1
    rho_y: Decimal  # y1 / y2
    b_eff: Decimal  # B, or 0 for a pass through the top
    c_eff: Decimal


def _nutation(s: TopSetup, st: _Start, cub: cubic.TopCubic, roots: cubic.TopRoots) -> _Nutation:
    """The :class:`_Nutation` of a top whose theta oscillates between the roots x2 < x1."""
    w3, a, thetadot0 = s.omega3, st.a, st.thetadot0
    x1, x2, y1, y2 = roots.x1, roots.x2, roots.y1, roots.y2
    B, C = cub.B, cub.C
    width = roots.width  # x1 - x2 with its own digits (the roots alone lose it below 1e-60 of x)
    m = cub.beta * width / roots.beta_span
    m1 = roots.beta_gap / roots.beta_span
    if m1 < Decimal("1e-150"):
        # The whole initial state sets 1 - m (theta0 = 1e-100 rad below the sleeping spin gives 1e-200): it
        # blamed thetadot0 alone, which the user may not have given.
        raise InputError(
            "theta0, thetadot0, phidot0, omega3",
            (s.theta0, _f(thetadot0), s.phidot0, _f(w3)),
            f"a state farther from the separatrix: 1 - m = {m1:.3g} is below what float64 "
            "Carlson integrals resolve (1e-150); the top would creep away from an unstable "
            "equilibrium for a time of order ln(1/(1 - m)) nutation periods",
        )
    lam = roots.beta_span.sqrt() / 2
    kdec = hp.agm_k(m1)
    # Mean rates of J_+ = int dt/x and J_- = int dt/y (complete Pi by Bulirsch's cel).
    kc = m1.sqrt()
    pi_plus, pi_minus = complete_pi_pair(kc, x2 / x1 if B != 0 else None, y2 / y1 if C != 0 else None)
    mean_inv_x = pi_plus / (kdec * x1)
    mean_inv_y = pi_minus / (kdec * y1) if C != 0 else Decimal(0)
    mean_phidot = (B * mean_inv_x + C * mean_inv_y) / 2
    # One of B and C zero: a single term, no cancellation; its rounding at the precision of the integrals.
    mean_bound = abs(mean_phidot) * Decimal(10) ** (-MEAN_RATE_DIGITS)
    if B != 0 and C != 0:
        mean_phidot, mean_bound = _mean_phidot(s.v0 * st.s0 - a * roots.d_low, a, width, x1, x2, y1, y2, kc, kdec)
    # A pass closer to a pole than sqrt(x2/x1) = 1e-16 of theta_max (below the rounding
    # of theta) is followed as a pass through it (signed theta; the pi jumps of phi
    # and psi come from the fold): the difference is O(sqrt(x2/x1)) theta_max, and the
    # floats stay far from overflow.
    rho_x, rho_y = x2 / x1, y1 / y2
    top = x2 == 0 or rho_x < _POLE
    bottom = y1 == 0 or rho_y < _POLE
    return _Nutation(
        m=m,
        m1=m1,
        lam=lam,
        kdec=kdec,
        K=hp.to_dd(kdec),
        period=2 * kdec / lam,
        pi_plus=pi_plus,
        pi_minus=pi_minus,
        mean_inv_x=mean_inv_x,
        mean_inv_y=mean_inv_y,
        mean_phidot=mean_phidot,
        mean_bound=mean_bound,
        mean_psidot=w3 - a - (B * mean_inv_x - C * mean_inv_y) / 2,
        top=bool(top),
        bottom=bool(bottom),
        rho_x=rho_x,
        rho_y=rho_y,
        b_eff=Decimal(0) if top else B,
        c_eff=Decimal(0) if bottom else C,
    )


def _start_phase(st: _Start, roots: cubic.TopRoots, nu: _Nutation) -> tuple[Decimal, Decimal, Decimal, Decimal]:
    """The initial nutation phase w0 in (-K, K] (decimal) with sn w0, cn^2 w0 and dn^2 w0:
    x0 = x1 cn^2 + x2 sn^2, sn w0 of the sign of -thetadot0."""
    width = roots.width
    sn0_2 = min(max(roots.d_high / width, Decimal(0)), Decimal(1))
    cn0_2 = min(max(roots.d_low / width, Decimal(0)), Decimal(1))
    dn0_2 = cn0_2 + nu.m1 * sn0_2  # = 1 - m sn0^2 without cancellation next to m = 1
    sgn = -1 if st.thetadot0 > 0 else 1
    sn0 = sgn * sn0_2.sqrt()
    # w0 = sn0 R_F(cn0^2, dn0^2, 1) at DIGITS digits, rounded once: the evaluation takes the double, and
    # the anchors make up for the rest (w0_dec - r0), which next to a pole turns the whole motion.
    w0_dec = sgn * nu.kdec if cn0_2 == 0 else sn0 * hp.carlson_rf(cn0_2, dn0_2, Decimal(1), context())
    return w0_dec, sn0, cn0_2, dn0_2


def _anchors(cub: cubic.TopCubic, roots: cubic.TopRoots, nu: _Nutation, start, lam_dd) -> tuple[float, float, float]:
    """The reduced phase r0 at t = 0 and the anchors of sigma and delta: the periodic parts' offsets
    P(w0) - P(r0) over the sub-ulp step between the exact start and its double."""
    w0_dec, sn0, cn0_2, dn0_2 = start
    w0, K, kdec = _f(w0_dec), nu.K, nu.kdec
    x1, x2, y1, y2, B, C, lam = roots.x1, roots.x2, roots.y1, roots.y2, cub.B, cub.C, nu.lam
    # The reduced phase at t = 0. The reduction of lambda t + w0
    # (wobble.numerics.phase.reduce_phase) forms x = 0 + w0 with no error term and, for
    # |w0| <= K (x / 2K in [-1/2, 1/2], which rint takes to 0, ties to even), j = 0 and
    # r = x: it is 0.0 + w0 exactly (the sum turns -0.0 into +0.0, as there). The periodic
    # parts there are taken by the evaluator when first needed, through the evaluation's own
    # path, so the attitude at t = 0 is q0 but for the anchors.
    if abs(w0) <= K[0]:
        r0, j0 = 0.0 + w0, 0.0
    else:
        r_, j_ = reduce_phase(np.zeros(1), lam_dd, (2 * K[0], 2 * K[1]), w0)
        r0, j0 = float(r_[0]), float(j_[0])
    # A double r0 past +-K by less than an ulp (K rounded up) is evaluated as the phase mirrored about +-K
    # (sn and |cn|: Pi(n; am r) takes cn >= 0) with the secular term at r0 itself.
    r0_dec = Decimal.from_float(r0)
    r0_seen = r0_dec if abs(r0_dec) <= kdec else (2 * kdec if r0 > 0 else -2 * kdec) - r0_dec
    w0_red = w0_dec - 2 * kdec * Decimal(j0)
    h = (w0_red - r0_seen, w0_red - r0_dec)
    cn0_, dn0_ = cn0_2.sqrt(), dn0_2.sqrt()
    if nu.top:
        delta = _through_anchor(B, lam * (x1 * x2 * nu.m1).sqrt(), sn0, cn0_ * x1.sqrt(), x2.sqrt(), True)
    else:
        delta = _step_anchor(B / (2 * lam), nu.pi_plus / kdec * nu.b_eff / (2 * lam * x1), x1, x2, sn0, cn0_, dn0_, h)
    if nu.bottom:
        sigma = _through_anchor(C, lam * (y1 * y2).sqrt(), sn0, cn0_ * y1.sqrt(), y2.sqrt(), False)
    else:
        sigma = _step_anchor(C / (2 * lam), nu.pi_minus / kdec * nu.c_eff / (2 * lam * y1), y1, y2, sn0, cn0_, dn0_, h)
    return r0, sigma, delta


def _evaluator(s: TopSetup, st: _Start, cub: cubic.TopCubic, roots: cubic.TopRoots, nu: _Nutation) -> Elliptic:
    """The :class:`~wobble.models.top_closed_form.Elliptic` evaluator of the motion: Jacobi functions for
    u(t), Pi(n; am w | m) for phi and psi, the secular phases and the anchors."""
    w3, a = s.omega3, st.a
    x1, y1, y2, width = roots.x1, roots.y1, roots.y2, roots.width
    lam, kdec, b_eff, c_eff, top, bottom = nu.lam, nu.kdec, nu.b_eff, nu.c_eff, nu.top, nu.bottom
    w3ma = w3 - a
    sigma_rate = (w3ma + c_eff * nu.mean_inv_y) / 2
    delta_rate = (b_eff * nu.mean_inv_x - w3ma) / 2
    start = _start_phase(st, roots, nu)
    sn0 = start[1]
    hx1, hy2 = (x1 / 2).sqrt(), (y2 / 2).sqrt()
    # Through the bottom, cos(theta/2) is carried signed, hy2 sn(w): negative at t = 0 when the top
    # starts towards the bottom (sn w0 < 0). The quaternion (ch cos sigma, sh cos delta, sh sin delta,
    # ch sin sigma) is then the start's only if sigma carries pi more; without it a top released with
    # thetadot0 > 0 (a planar pendulum swinging down) started mirrored, R_x(-theta0) for R_x(theta0).
    # (Through the top sin(theta/2) = hx1 cn(w) needs nothing: cn w0 >= 0 for |w0| <= K.)
    sigma0 = st.sigma0 + (hp.PI if bottom and sn0 < 0 else 0)
    lam_dd = hp.to_dd(lam)
    r0, anchor_sigma, anchor_delta = _anchors(cub, roots, nu, start, lam_dd)
    return Elliptic(
        r0=r0,
        anchor_sigma=anchor_sigma,
        anchor_delta=anchor_delta,
        start_scd=(_f(sn0), _f(start[2].sqrt()), _f(start[3].sqrt())),
        hx1=_f(hx1),
        hy2=_f(hy2),
        rho_x=0.0 if top else _f(nu.rho_x),
        rho_y=0.0 if bottom else _f(nu.rho_y),
        x1=_f(x1),
        y2=_f(y2),
        B=_f(b_eff),
        C=_f(c_eff),
        B_x1=_f(b_eff / x1),
        C_y2=_f(c_eff / y2),
        Bp=_f(b_eff / x1 * hx1 * hy2),
        Cp=_f(c_eff / y2 * hx1 * hy2),
        W=_f(width / (hx1 * hy2)),
        through_top=top,
        through_bottom=bottom,
        a=_f(a),
        omega3=_f(w3),
        lam=lam_dd,
        K=nu.K,
        w0=_f(start[0]),
        m=_f(nu.m),
        m1=_f(nu.m1),
        n_plus=_f(width / x1),
        one_minus_n_plus=_f(nu.rho_x),
        nu_minus=_f(width / y1) if not bottom else 0.0,
        pi_plus_over_k=_f(nu.pi_plus / kdec),
        pi_minus_over_k=_f(nu.pi_minus / kdec),
        k_plus=_f(b_eff / (2 * lam * x1)),
        k_minus=_f(c_eff / (2 * lam * y1)) if not bottom else 0.0,
        sigma_sec=secular_phase(sigma_rate, lam, kdec, sigma0),
        delta_sec=secular_phase(delta_rate, lam, kdec, st.delta0),
        phi_sec=secular_phase(
            nu.mean_phidot if not (top or bottom) else (b_eff * nu.mean_inv_x + c_eff * nu.mean_inv_y) / 2,
            lam,
            kdec,
            sigma0 + st.delta0,
        ),
        psi_sec=secular_phase(sigma_rate - delta_rate, lam, kdec, sigma0 - st.delta0),
        # The fold K - |r| uses the 60-digit K of the reduction, given at construction.
        levels=ell.landen_levels(_f(nu.m), _f(nu.m1), K=nu.K[0]),
    )


def _elliptic_estimate(roots: cubic.TopRoots, nu: _Nutation, impl: Elliptic, theta_max: float) -> dict:
    """The error estimate of the elliptic evaluation: theta, the attitude, the turning points, the period and
    the mean precession rate."""
    x1, x2, y1, y2, lam = roots.x1, roots.x2, roots.y1, roots.y2, nu.lam
    kf = float(nu.K[0])
    swing = abs(_f(nu.b_eff * nu.pi_plus / (lam * x1)))
    if not nu.bottom:
        swing += abs(_f(nu.c_eff * nu.pi_minus / (lam * y1)))
    # psi's secular phase over a period, c (r - w0) with c = (omega3 - a)/(2 lambda) + ...,
    # is a fast spin's turns per nutation: its rounding (and that of the reduced phase r,
    # a few ulps of K) grows with c. That is psi's own conditioning in t, |psidot| t eps
    # for t of a period; phi = sigma + delta has no such term (its own secular phase).
    spin = 8 * EPS * kf * (abs(impl.sigma_sec.c) + abs(impl.delta_sec.c))
    # The anchors (the periodic parts' offsets at the exact start) are rounded once from their
    # closed forms and take an atan2 in float64: a few eps of themselves. A start within a pass followed as
    # one through a pole takes its turn with dn = 1 across the pass, exact to 2 sqrt(x2 / (x1 m1)) (or
    # 2 sqrt(y1 / (y2 m1))): below 1e-16 rad unless the motion also lies next to the separatrix.
    anchor = 4 * EPS * (abs(impl.anchor_sigma) + abs(impl.anchor_delta))
    if nu.top and x2 != 0:
        anchor += _f(2 * (x2 / (x1 * nu.m1)).sqrt())
    if nu.bottom and y1 != 0:
        anchor += _f(2 * (y1 / (y2 * nu.m1)).sqrt())
    return {
        "theta_rad": 32 * EPS * (1 + kf) * max(theta_max, EPS),
        "attitude_rad": 64 * EPS * (1 + kf) * (1 + swing) + spin + anchor,
        "turning_points_relative": 4 * EPS,
        "period_relative": 4 * EPS,
        # Its rounding to a double, or what the 45 digits of its terms leave when they cancel (loops under
        # weak gravity): the mean itself, not phi(t), whose secular part it is only to within attitude_rad.
        "mean_precession_rate_rad_per_s": max(_f(nu.mean_bound), 2 * EPS * abs(_f(nu.mean_phidot))),
    }


def _elliptic(s: TopSetup, st: _Start, cub: cubic.TopCubic, roots: cubic.TopRoots) -> dict:
    """Fields of a nutating top: Jacobi functions for u(t), Pi(n; am w | m) for phi and psi."""
    with decimal.localcontext(context()):
        nu = _nutation(s, st, cub, roots)
        impl = _evaluator(s, st, cub, roots, nu)
        u1, u2, u3 = _report_roots(roots)
        x1, x2, y1, y2 = roots.x1, roots.x2, roots.y1, roots.y2
        if st.s0 != 0:
            phidot0 = s.v0 / st.s0
        else:
            phidot0 = to_decimal(s.phidot0) if st.x0 == 0 else Decimal(0)
        theta_max = theta_of(x1, y1)
        return dict(
            phidot0=_f(phidot0),
            psidot0=_f(s.omega3 - st.u0 * phidot0),
            u1=u1,
            u2=u2,
            u3=u3,
            x1=_f(x1),
            x2=_f(x2),
            x3=-float("inf") if roots.x3.is_infinite() else _f(roots.x3),
            theta_min=theta_of(x2, y2),
            theta_max=theta_max,
            nutation=nutation_class(cub.B, st.a, x1, x2, cub.C, s.v0 * st.s0, roots.d_low, roots.d_high),
            m=_f(nu.m),
            m1=_f(nu.m1),
            nutation_period=_f(nu.period),
            mean_precession_rate=_f(nu.mean_phidot),
            mean_spin_rate=_f(nu.mean_psidot),
            error_estimate=_elliptic_estimate(roots, nu, impl, theta_max),
            _impl=impl,
        )
