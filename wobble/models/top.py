"""The heavy symmetric top with one point fixed, exactly (SI, float64; notes section 5.7).

Course notes section 5.7 (pages 70-72); Goldstein, Classical Mechanics, section 5.7;
Kibble & Berkshire, Classical Mechanics, section 12.

Conventions (the notes'). The body axes x_j are principal axes about the fixed
point (the tip), x_3 the symmetry axis, which points from the tip to the centre of
mass at distance l. The space axes x'_j have x'_3 vertical, gravity -g x'_3. The
Euler angles (phi, theta, psi) are the z-x-z angles of the notes: the rotation
body -> space is R = R_z(phi) R_x(theta) R_z(psi), its unit quaternion (scalar first)

    q = (cos(theta/2) cos((phi+psi)/2), sin(theta/2) cos((phi-psi)/2),
         sin(theta/2) sin((phi-psi)/2), cos(theta/2) sin((phi+psi)/2)),

and the body angular velocity is the notes' (p. 70)

    omega_1 = phidot sin(theta) sin(psi) + thetadot cos(psi),
    omega_2 = phidot sin(theta) cos(psi) - thetadot sin(psi),
    omega_3 = phidot cos(theta) + psidot.

The symmetry axis in space is (sin theta sin phi, -sin theta cos phi, cos theta).

Analysis (notes p. 71-72). p_psi = I3 omega3 = I1 a, p_phi = I1 b, E' = E - I3 omega3^2/2,
alpha = 2E'/I1, beta = 2Mgl/I1, u = cos theta, udot^2 = f(u) = beta u^3 - (alpha + a^2) u^2
+ (2ab - beta) u + (alpha - b^2) = beta (u - u1)(u - u2)(u - u3), u1 <= u <= u2 <= 1 < u3.
The roots are found in x = 1 - u and y = 1 + u from the exact float inputs in
50-60-digit decimal arithmetic (:mod:`wobble.numerics.cubic`), so the turning
angles keep their relative digits next to the vertical (nearly sleeping top) and
the bottom, at double roots (regular precession) and for beta -> 0.

Exact motion. With w = lambda t + w0, lambda = sqrt(beta (u3 - u1))/2, m = (u2 - u1)/(u3 - u1),

    x = 1 - u = x1 cn^2(w|m) + x2 sn^2(w|m)      (u = u1 + (u2 - u1) sn^2, no cancellation),

and with phidot = (b - a u)/(1 - u^2) = (B/x + C/y)/2, B = b - a, C = b + a,
psidot = omega3 - u phidot = omega3 - a - (B/x - C/y)/2, the half angles
sigma = (phi + psi)/2 and delta = (phi - psi)/2 are

    sigma(t) = sigma0 + [(omega3 - a) t + C J_-(t)]/2,   delta(t) = delta0 + [B J_+(t) - (omega3 - a) t]/2,
    J_+ = int dt / x = Pi(n_+; am w | m) / (lambda x1),   n_+ = (x1 - x2)/x1 in [0, 1),
    J_- = int dt / y = Pi(n_-; am w | m) / (lambda y1),   n_- = -(x1 - x2)/y1 <= 0,

elliptic integrals of the third kind evaluated with Carlson's symmetric forms in
positive terms (:func:`wobble.numerics.elliptic.pi_positive_scd`,
:func:`~wobble.numerics.elliptic.pi_negative_scd`). Each is split into a secular
part (mean rate Pi(n|m)/(K x1) etc., computed once to ~30 digits with Bulirsch's
cel) and a 2K-periodic part of the reduced phase; the secular phases are carried in
double-double and reduced exactly modulo 2 pi, the nutation phase modulo 2K
(:mod:`wobble.numerics.phase`), so nothing grows with t.

Singular Euler angles. phi and psi are undefined at theta = 0 and pi; the
quaternion is built from sin(theta/2), cos(theta/2), sigma and delta and is regular
there: only delta carries the term B J_+ that blows up as the axis nears the vertical,
and it enters multiplied by sin(theta/2). A motion that passes exactly through the
vertical (b = a, started at theta0 = 0) or the bottom (b = -a) is followed through
it with a signed theta; the reported Euler angles are folded back to theta in
[0, pi] with (theta, phi, psi) -> (-theta, phi + pi, psi + pi).
"""

from __future__ import annotations

import decimal
from dataclasses import dataclass, field, replace
from decimal import Decimal

import numpy as np

from wobble.errors import InputError
from wobble.numerics import compiled, cubic
from wobble.numerics import elliptic as ell
from wobble.numerics import highprec as hp
from wobble.numerics.phase import reduce_phase, split_dd

__all__ = [
    "NUTATION_CLASSES",
    "HeavyTopModel",
    "TopMotion",
    "heavy_top",
    "heavy_top_from_state",
    "check_top_parameters",
    "regular_precession_rates",
    "sleeping_top_stable",
]

NUTATION_CLASSES = ("undulating", "cusps", "loops", "regular", "sleeping")
_EPS = float(np.finfo(float).eps)
_TWO_PI_DD = hp.to_dd(2 * hp.PI)
_TWO_PI_PIECES = split_dd(*_TWO_PI_DD)
_TWO_PI_PIECES_SUM = float(2 * hp.PI)
_DIGITS = cubic.DIGITS
_BLOCK = 8192


def _ctx() -> decimal.Context:
    return decimal.Context(prec=_DIGITS)


def _D(x) -> Decimal:
    """The exact Decimal of a float (Decimal(float) is exact; arithmetic rounds to the context)."""
    return x if isinstance(x, Decimal) else Decimal(float(x))


def _f(x: Decimal) -> float:
    return float(x)


# --------------------------------------------------------------------------
# Parameters and checks
# --------------------------------------------------------------------------
def _finite(name: str, value, allowed: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, allowed) from None
    if not np.isfinite(x):
        raise InputError(name, value, allowed)
    return x


def check_top_parameters(I1: float, I3: float, mgl: float, ml2: float | None = None) -> tuple[float, float, float]:  # noqa: N803
    """Check a top's moments about the tip (kg m^2) and M g l (J); return them as floats.

    Parameters
    ----------
    I1, I3 : float
        Transverse and axial principal moments about the fixed point (kg m^2).
    mgl : float
        M g l (J), >= 0 (l = distance from the tip to the centre of mass along the axis).
    ml2 : float, optional
        M l^2 (kg m^2) when mass and length were given: I1 about the tip is at
        least M l^2 (parallel axes).

    Raises
    ------
    wobble.errors.InputError
        I1 <= 0, I3 <= 0, I3 > 2 I1 (no real body has I3 > I1 + I2), mgl < 0,
        I1 < M l^2, or non-finite values; the message names the parameter.
    """
    I1 = _finite("I1", I1, "a positive, finite moment of inertia (kg m2)")  # noqa: N806
    I3 = _finite("I3", I3, "a positive, finite moment of inertia (kg m2)")  # noqa: N806
    mgl = _finite("mgl", mgl, "a finite, non-negative M g l (J)")
    if I1 <= 0:
        raise InputError("I1", I1, "a positive moment of inertia about the tip (kg m2)")
    if I3 <= 0:
        raise InputError("I3", I3, "a positive moment of inertia about the symmetry axis (kg m2)")
    if I3 > 2 * I1 * (1 + 8 * _EPS):
        raise InputError("I3", I3, f"I3 <= 2 I1 = {2 * I1:g} kg m2 (a real body has I3 <= I1 + I2)")
    if mgl < 0:
        raise InputError("mgl", mgl, "M g l >= 0 (J): the centre of mass on the symmetry axis, above the tip")
    if ml2 is not None:
        ml2 = _finite("M l^2", ml2, "a finite M l^2 (kg m2)")
        if I1 < ml2 * (1 - 8 * _EPS):
            raise InputError(
                "I1", I1, f"I1 >= M l^2 = {ml2:g} kg m2 (the moment about the tip includes M l^2; "
                "I1 must be about the tip, not the centre of mass)",
            )
    return I1, I3, mgl


def sleeping_top_stable(I1: float, I3: float, mgl: float, omega3: float) -> bool:  # noqa: N803
    """True when the sleeping top is stable: I3^2 omega3^2 > 4 M g l I1 (Kibble & Berkshire eq. 12.26)."""
    I1, I3, mgl = (hp.exact(float(v)) for v in (I1, I3, mgl))  # noqa: N806
    w = hp.exact(float(omega3))
    return I3 * I3 * w * w > 4 * mgl * I1


def regular_precession_rates(I1: float, I3: float, mgl: float, omega3: float, theta: float) -> tuple[float, float]:  # noqa: N803
    """Slow and fast rates (rad/s) of steady (regular) precession at tilt theta.

    Regular precession needs f(u0) = 0 and df/du(u0) = 0 at u0 = cos theta (notes
    p. 72); with thetadot = 0 this is 2 u0 phidot^2 - 2 a phidot + beta = 0, i.e.

        phidot = [I3 omega3 +- sqrt(I3^2 omega3^2 - 4 I1 M g l cos theta)] / (2 I1 cos theta),

    solved without cancellation (the slow root as beta / q). Slow ~ M g l /(I3 omega3),
    fast ~ I3 omega3 / (I1 cos theta) for a fast top. At theta = pi/2 the fast rate is
    infinite (returned as +-inf).

    Returns
    -------
    (slow, fast) : tuple of float
        The rate of smaller magnitude first.

    Raises
    ------
    wobble.errors.InputError
        ``theta`` outside [0, pi], or no steady precession at that tilt
        (I3^2 omega3^2 < 4 I1 M g l cos theta).
    """
    I1, I3, mgl = check_top_parameters(I1, I3, mgl)  # noqa: N806
    theta = _finite("theta", theta, "an angle in [0, pi] rad")
    if not 0 <= theta <= np.pi:
        raise InputError("theta", theta, "an angle in [0, pi] rad")
    with decimal.localcontext(_ctx()):
        s, c = hp.sin_cos(theta, _DIGITS)
        a = _D(I3) * _D(omega3) / _D(I1)
        beta = 2 * _D(mgl) / _D(I1)
        disc = a * a - 2 * c * beta
        if disc < 0:
            raise InputError(
                "theta", theta,
                "a tilt where steady precession exists: I3^2 omega3^2 >= 4 I1 M g l cos(theta)",
            )
        if c == 0:
            if a == 0:
                raise InputError("omega3", omega3, "a spinning top (no steady precession at theta = pi/2 without spin)")
            return _f(beta / (2 * a)), float(np.copysign(np.inf, _f(a)))
        sgn = 1 if a >= 0 else -1
        q = a + sgn * disc.sqrt()
        r1 = q / (2 * c)
        r2 = beta / q if q != 0 else Decimal(0)
        slow, fast = (r2, r1) if abs(r2) <= abs(r1) else (r1, r2)
        return _f(slow), _f(fast)


# --------------------------------------------------------------------------
# The motion
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class TopMotion:
    """The top's state at many times (SI: rad, rad/s), arrays of shape (N,) or (N, k)."""

    t: np.ndarray
    theta: np.ndarray
    phi: np.ndarray
    psi: np.ndarray
    thetadot: np.ndarray
    phidot: np.ndarray
    psidot: np.ndarray
    omega: np.ndarray  # body frame (N, 3)
    quaternion: np.ndarray  # body -> space (N, 4)
    axis: np.ndarray  # symmetry axis in space (N, 3)
    u: np.ndarray  # cos theta


@dataclass(frozen=True)
class _Uniform:
    """theta constant (sleeping top, regular precession, hanging at rest)."""

    sh: float
    ch: float
    u: float
    sigma_rate: tuple[float, float]
    delta_rate: tuple[float, float]
    sigma0: float
    delta0: float
    phidot: float
    psidot: float

    def core(self, t):
        n = t.shape
        sig, _ = reduce_phase(t, self.sigma_rate, _TWO_PI_DD, self.sigma0)
        dlt, _ = reduce_phase(t, self.delta_rate, _TWO_PI_DD, self.delta0)
        sh = np.full(n, self.sh)
        ch = np.full(n, self.ch)
        zero = np.zeros(n)
        return dict(
            sh=sh, ch=ch, sigma=sig, delta=dlt, thetadot=zero, phidot=np.full(n, self.phidot),
            psidot=np.full(n, self.psidot), u=np.full(n, self.u), phidot_sin=np.full(n, self.phidot * 2 * self.sh * self.ch),
        )


@dataclass(frozen=True)
class _Secular:
    """A secular phase Omega t + offset from the reduced nutation phase (no second pass over t).

    With lambda t + w0 = 2K j + r (j an exact integer, |r| <= K),
    Omega t = j A + c (r - w0), A = (2K Omega / lambda) mod 2 pi (to ~30 digits, split in three
    floats so that j a1 and j a2 are exact for |j| < 2^26) and c = Omega / lambda. The product
    j a1 is reduced modulo 2 pi by Cody-Waite before the small terms are added, so the error
    is a few ulps of 2 pi whatever t is -- the bound of :func:`wobble.numerics.phase.reduce_phase`
    at a third of its cost.
    """

    a: tuple[float, float, float]
    c: float
    offset: float

    def __call__(self, j, r, w0):
        a1, a2, a3 = self.a
        z = j * a1  # exact
        k = np.rint(z * (1.0 / _TWO_PI_PIECES_SUM))
        z = ((z - k * _TWO_PI_PIECES[0]) - k * _TWO_PI_PIECES[1]) - k * _TWO_PI_PIECES[2]
        return z + (j * a2 + (j * a3 + (self.c * (r - w0) + self.offset)))


def _secular(rate: Decimal, lam: Decimal, kdec: Decimal, offset) -> _Secular:
    """The :class:`_Secular` of a phase rate (rad/s) for nutation rate lambda and quarter period K."""
    with decimal.localcontext(_ctx()):
        two_pi = 2 * hp.PI
        adv = 2 * kdec * rate / lam
        adv = adv - two_pi * (adv / two_pi).to_integral_value()
        hi, lo = hp.to_dd(adv)
        # split_dd cannot split below the normal range; j times such an advance is far
        # below rounding anyway.
        pieces = split_dd(hi, lo) if abs(hi) > 1e-280 else (0.0, 0.0, hi + lo)
        return _Secular(a=pieces, c=_f(rate / lam), offset=float(offset))


@dataclass(frozen=True)
class _Elliptic:
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
    p_plus0: float
    p_minus0: float
    sigma_sec: _Secular
    delta_sec: _Secular
    levels: object = field(repr=False, compare=False)

    def phase(self, t):
        return reduce_phase(t, self.lam, (2 * self.K[0], 2 * self.K[1]), self.w0)

    def _periodic(self, r, sn, cn, dn):
        """P_+(r) and P_-(r): the 2K-periodic parts Pi(n; am r | m) - (Pi(n|m)/K) r, |r| <= K."""
        d2 = dn * dn
        p_plus = p_minus = np.zeros_like(r)
        if self.k_plus != 0.0:
            pi = ell.pi_positive_scd(self.n_plus, self.one_minus_n_plus, sn, cn, d2)
            p_plus = pi - self.pi_plus_over_k * r
        if self.k_minus != 0.0:
            pi = ell.pi_negative_scd(self.nu_minus, sn, cn, d2, self.m1)
            p_minus = pi - self.pi_minus_over_k * r
        return p_plus, p_minus

    def _scaled(self, sn, cn):
        sn2, cn2 = sn * sn, cn * cn
        return np.sqrt(cn2 + self.rho_x * sn2), np.sqrt(self.rho_y * cn2 + sn2)

    def periodic_of_r(self, r):
        """theta(r), k_- P_-(r), k_+ P_+(r) and dtheta/dr for a reduced phase |r| <= K.

        The 2K-periodic functions of the nutation phase that the Fourier evaluator
        expands (used only when the axis stays off the poles, so no sign folding);
        dtheta/dr = -W sn cn dn / (sx sy), thetadot = lambda dtheta/dr.
        """
        sn, cn, dn = ell.jacobi_reduced(r, self.levels, self.K[1])
        sx, sy = self._scaled(sn, cn)
        theta = 2.0 * np.arctan2(self.hx1 * sx, self.hy2 * sy)
        p_plus, p_minus = self._periodic(r, sn, cn, dn)
        return theta, self.k_minus * p_minus, self.k_plus * p_plus, -self.W * sn * cn * dn / (sx * sy)

    def core(self, t):
        r, j = self.phase(t)
        sn, cn, dn = ell.jacobi_reduced(r, self.levels, self.K[1])
        odd = np.floor(0.5 * j) != 0.5 * j
        par = np.where(odd, -1.0, 1.0)  # sn(w) = par sn(r), cn(w) = par cn(r)
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
        sh = self.hx1 * sx
        ch = self.hy2 * sy
        phidot = 0.5 * (bx + cy)
        psidot = (self.omega3 - self.a) - 0.5 * (bx - cy)
        p_plus, p_minus = self._periodic(r, sn, cn, dn)
        sig = self.sigma_sec(j, r, self.w0) + self.k_minus * (p_minus - self.p_minus0)
        dlt = self.delta_sec(j, r, self.w0) + self.k_plus * (p_plus - self.p_plus0)
        x = self.x1 * (sx * sx)
        y = self.y2 * (sy * sy)
        u = np.where(x <= 1.0, 1.0 - x, y - 1.0)
        return dict(sh=sh, ch=ch, sigma=sig, delta=dlt, thetadot=thetadot, phidot=phidot, psidot=psidot, u=u,
                    phidot_sin=b_term + c_term)


_TAYLOR_ORDER = 5


@dataclass(frozen=True)
class _Fourier:
    """The periodic parts as Fourier series in the nutation phase (fast evaluation).

    theta(r) (even), k_- P_-(r), k_+ P_+(r) and dtheta/dr (odd) are analytic and
    2K-periodic in the reduced phase r while the axis stays off the poles; their
    Fourier coefficients in vartheta = pi r / K decay geometrically and are computed
    once by an FFT of exact values (:meth:`_Elliptic.periodic_of_r`). For evaluation
    the series are tabulated with their derivatives up to order 5 at S equispaced
    phases (one batched inverse FFT), and each output takes a degree-5 Taylor
    polynomial from the nearest node: one gather per order and 5 Horner steps per series,
    whatever the series' length. The table is accepted only after it agrees with the
    direct evaluation between the nodes to within the solution's error estimate
    (:func:`_build_fourier`); otherwise the direct path is used.
    """

    base: _Elliptic
    coef: np.ndarray  # (4, L + 1): theta (cos), sigma_p (sin), delta_p (sin), dtheta/dr (sin)
    kinds: tuple  # "cos" or "sin" per row
    scale: float  # pi / K
    table: np.ndarray  # (4, order + 1, S): f^(j)(node) / j! in units of r
    h: float  # node spacing in r
    error_theta: float
    error_phase: float

    def clenshaw(self, r, rows):
        """The series summed directly (Clenshaw), for building and checking the table."""
        vt = r * self.scale
        c, s_ = np.cos(vt), np.sin(vt)
        alpha = 2.0 * c
        coef = self.coef[list(rows)]
        nrow, ncoef = coef.shape
        b1 = np.zeros((nrow,) + r.shape)
        b2 = np.zeros_like(b1)
        tmp = np.empty_like(b1)
        for k in range(ncoef - 1, 0, -1):
            np.multiply(alpha, b1, out=tmp)
            tmp -= b2
            tmp += coef[:, k, None]
            b1, b2, tmp = tmp, b1, b2
        out = []
        for i, row in enumerate(rows):
            out.append(coef[i, 0] + b1[i] * c - b2[i] if self.kinds[row] == "cos" else b1[i] * s_)
        return out

    def series(self, r, rows):
        """The series at reduced phases r from the Taylor table (nearest node, Horner).

        One contiguous 1-D table per series and order, gathered with np.take (the
        tables stay in cache; fancy indexing of a 3-D table was three times slower);
        long arrays in one compiled pass instead (:mod:`wobble.numerics.taylor_table`).
        """
        if r.size >= compiled.LONG_ARRAY and compiled.available():  # one pass, bit for bit the sum below
            from wobble.numerics import taylor_table

            return taylor_table.series(r, self.base.K[0], self.h, self.table, rows)
        u = (r + self.base.K[0]) * (1.0 / self.h)
        idx = np.rint(u)
        d = (u - idx) * self.h
        ii = idx.astype(np.intp)
        nodes = self.table.shape[2]
        ii[ii >= nodes] -= nodes  # r = +K is the node of r = -K
        out = []
        for row in rows:
            tab = self.table[row]
            acc = np.take(tab[_TAYLOR_ORDER], ii)
            for j in range(_TAYLOR_ORDER - 1, -1, -1):
                acc *= d
                acc += np.take(tab[j], ii)
            out.append(acc)
        return out

    def angles_core(self, t):
        e = self.base
        r, j = e.phase(t)
        theta, sp, dp = self.series(r, (0, 1, 2))
        sig = e.sigma_sec(j, r, e.w0)
        dlt = e.delta_sec(j, r, e.w0)
        return theta, sig + (sp - e.k_minus * e.p_minus0), dlt + (dp - e.k_plus * e.p_plus0)

    def core(self, t):
        e = self.base
        r, j = e.phase(t)
        theta, sp, dp, dth = self.series(r, (0, 1, 2, 3))
        half = 0.5 * theta
        sh, ch = np.sin(half), np.cos(half)
        x, y = 2.0 * sh * sh, 2.0 * ch * ch
        bx, cy = e.B / x, e.C / y
        sig = e.sigma_sec(j, r, e.w0)
        dlt = e.delta_sec(j, r, e.w0)
        return dict(
            sh=sh, ch=ch, sigma=sig + (sp - e.k_minus * e.p_minus0), delta=dlt + (dp - e.k_plus * e.p_plus0),
            thetadot=e.lam[0] * dth, phidot=0.5 * (bx + cy), psidot=(e.omega3 - e.a) - 0.5 * (bx - cy),
            u=np.where(x <= 1.0, 1.0 - x, y - 1.0), phidot_sin=0.5 * (e.B * ch / sh + e.C * sh / ch),
        )


_FOURIER_MIN_SAMPLES = 1024
_FOURIER_MAX_N = 512
_FOURIER_MAX_TERMS = 96
_TAYLOR_MAX_NODES = 1 << 15


def _build_fourier(e: _Elliptic, est: dict) -> _Fourier | None:
    """Fourier series of the periodic parts of ``e``, verified; None where not worth it.

    Four 2K-periodic functions of the reduced phase are sampled exactly at N
    equispaced phases: theta (even), k_- P_- and k_+ P_+ (odd) and dtheta/dr (odd,
    sampled from its closed form rather than by differentiating the theta series,
    which would amplify the rounding of theta's samples). N doubles until the upper
    half of every spectrum is at rounding level; the series must then reproduce the
    direct evaluation between the nodes within the solution's error estimate.
    Used only off the poles (x, y > 0 on the orbit).
    """
    if e.through_top or e.through_bottom:
        return None
    k = e.K[0]
    noise = 8 * _EPS  # the FFT of exact values has a noise floor of a few eps
    sample = e.periodic_of_r
    # Check points between the nodes (phases offset by an irrational fraction of the spacing).
    m = 41
    vt = -np.pi + 2 * np.pi * (np.arange(m) + 0.6180339887498949) / m
    r_check = vt * (k / np.pi)
    want = None
    for n in (64, 128, 256, _FOURIER_MAX_N):
        vt = 2 * np.pi * np.arange(n) / n
        vt = np.where(vt > np.pi, vt - 2 * np.pi, vt)
        if want is None:  # nodes and check points in one pass of the direct path
            both = sample(np.concatenate([vt * (k / np.pi), r_check]))
            vals = [v[:n] for v in both]
            want = [v[n:] for v in both]
        else:
            vals = sample(vt * (k / np.pi))
        spectra = [np.fft.rfft(v) / n for v in vals]
        scales = [max(float(np.max(np.abs(v))), 1e-300) for v in vals]
        scales[1] = scales[2] = max(1.0, scales[1], scales[2])  # phases: absolute (rad)
        # Aliasing folds c_{n-k} onto c_k: only the top of the band must be at rounding
        # level; the check against the direct evaluation below decides.
        if not all(np.max(np.abs(sp[7 * n // 16 :])) <= noise * sc for sp, sc in zip(spectra, scales)):
            continue
        fo = _fourier_from_spectra(e, spectra, scales, k)
        if fo is None:
            return None  # too long a series: the direct path is about as fast
        checked = _check_fourier(fo, r_check, want, scales[3], est, k)
        if checked is not None:
            return checked
    return None


def _fourier_from_spectra(e, spectra, scales, k):
    kinds = ("cos", "sin", "sin", "sin")
    rows = []
    for sp, kind in zip(spectra, kinds):
        if kind == "cos":
            c = 2 * sp.real
            c[0] = sp[0].real
        else:
            c = -2 * sp.imag
            c[0] = 0.0
        rows.append(c)
    big = np.maximum.reduce([np.abs(c) / sc for c, sc in zip(rows, scales)])
    keep = np.nonzero(big > 0.25 * _EPS)[0]
    last = int(keep.max()) if keep.size else 1
    if last > _FOURIER_MAX_TERMS:
        return None
    coef = np.stack([c[: last + 1] for c in rows])
    scale = np.pi / k
    nodes = 1 << max(8, int(np.ceil(np.log2(32 * (last + 1)))))
    return _Fourier(base=e, coef=coef, kinds=kinds, scale=scale, table=_taylor_table(coef, kinds, nodes, scale),
                    h=2 * k / nodes, error_theta=0.0, error_phase=0.0)


def _check_fourier(fo, r, want, dscale, est, k):
    """The table if it reproduces the direct values within the error estimate (finer tables
    are tried first); None otherwise."""
    while fo.table.shape[2] <= _TAYLOR_MAX_NODES:
        got = fo.series(r, (0, 1, 2, 3))
        err_t = float(np.max(np.abs(got[0] - want[0])))
        err_p = max(float(np.max(np.abs(got[1] - want[1]))), float(np.max(np.abs(got[2] - want[2]))))
        err_d = float(np.max(np.abs(got[3] - want[3]))) / dscale
        if err_t <= est["theta_rad"] and err_p <= est["attitude_rad"] and err_d <= 64 * _EPS * (1 + k):
            return replace(fo, error_theta=err_t, error_phase=err_p)
        nodes = 2 * fo.table.shape[2]
        if nodes > _TAYLOR_MAX_NODES:
            break
        fo = replace(fo, table=_taylor_table(fo.coef, fo.kinds, nodes, fo.scale), h=fo.h / 2)
    return None


def _taylor_table(coef, kinds, nodes, scale):
    """f^(j)(r_i)/j! (j = 0.._TAYLOR_ORDER, r-units) of every series at the nodes r_i = -K + i h.

    With vartheta_i = -pi + 2 pi i / S, e^{i k vartheta_i} = (-1)^k e^{2 pi i k i / S}, so
    Re sum_k c_k (i k scale)^j e^{i k vartheta_i} for all rows and orders is one batched
    real inverse FFT (cos series: c_k = a_k; sin series: c_k = -i b_k).
    """
    nrow, ncoef = coef.shape
    kk = np.arange(ncoef)
    sign = np.where(kk % 2 == 0, 1.0, -1.0)
    orders = np.arange(_TAYLOR_ORDER + 1)
    fact = np.cumprod(np.concatenate([[1.0], np.arange(1, _TAYLOR_ORDER + 1)]))
    rot = np.array([1.0 if k == "cos" else -1j for k in kinds])[:, None, None]
    power = (1j * kk[None, :] * scale) ** orders[:, None]  # (order + 1, ncoef)
    c = coef[:, None, :] * sign * power[None] * rot / fact[None, :, None]  # (rows, order + 1, ncoef)
    spec = np.zeros((nrow, _TAYLOR_ORDER + 1, nodes // 2 + 1), dtype=complex)
    spec[..., :ncoef] = c
    spec[..., 1:] *= 0.5  # irfft counts each k >= 1 twice (Hermitian extension)
    return np.fft.irfft(spec, n=nodes, axis=-1) * nodes


def _wrap(a):
    """Angles to [-pi, pi] (a few times faster than np.remainder; |a| here is < 10 pi)."""
    return a - (2 * np.pi) * np.rint(a * (0.5 / np.pi))


def _blocked_tuple(fn, t, block=_BLOCK):
    if t.size <= block:
        return fn(t)
    parts = [fn(t[i : i + block]) for i in range(0, t.size, block)]
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(len(parts[0])))


def _blocked(fn, t):
    """Evaluate fn on cache-sized blocks of t and concatenate the dict outputs."""
    if t.size <= _BLOCK:
        return fn(t)
    parts = [fn(t[i : i + _BLOCK]) for i in range(0, t.size, _BLOCK)]
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


# --------------------------------------------------------------------------
# The model: what the API, the CLI and the engine see
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class HeavyTopModel:
    """Exact motion of a heavy symmetric top (SI: kg m^2, J, rad, rad/s, s).

    Build with :func:`heavy_top` (Euler-angle initial state) or
    :func:`heavy_top_from_state` (body angular velocity and attitude quaternion).

    Attributes
    ----------
    I1, I3, mgl : float
        Moments about the tip (kg m^2) and M g l (J).
    theta0, thetadot0, phidot0, psidot0, phi0, psi0 : float
        Initial Euler angles (rad) and rates (rad/s); phidot0 is 0 for a top
        started exactly upright (only phidot0 + psidot0 = omega3 is defined there).
    omega3 : float
        Spin about the symmetry axis, constant (rad/s).
    a, b : float
        p_psi / I1 and p_phi / I1 (1/s).
    p_psi, p_phi : float
        Conserved momenta I3 omega3 and I1 b (kg m^2 / s).
    energy, energy_prime : float
        E and E' = E - I3 omega3^2 / 2 (J), potential zero at the tip's height.
    alpha, beta : float
        2 E'/I1 and 2 M g l / I1 (1/s^2).
    u1, u2, u3 : float
        Roots of f(u), u1 <= u2 <= 1 <= u3 (u3 = inf for M g l = 0).
    x1, x2, x3 : float
        The same roots as 1 - u_i, each rounded from its 60-digit value (so they keep
        the digits that u_i loses next to the vertical; x3 = -inf for M g l = 0).
    theta_min, theta_max : float
        Turning angles (rad) of the motion: arccos u2 and arccos u1.
    nutation : str
        One of :data:`NUTATION_CLASSES`.
    m, m1 : float
        Parameter (u2 - u1)/(u3 - u1) of the Jacobi functions and 1 - m,
        formed without cancellation.
    nutation_period : float
        4 K(m) / sqrt(beta (u3 - u1)) (s); for a sleeping top or regular
        precession the period of small nutations about it; inf on the separatrix.
    mean_precession_rate, mean_spin_rate : float
        Mean of phidot and psidot over a nutation period (rad/s).
    sleeping_stable : bool
        I3^2 omega3^2 > 4 M g l I1 (stability of the sleeping top with this spin).
    error_estimate : dict
        Bounds on the errors of theta (rad), of the attitude angle (rad) and of
        the turning points and period (relative), checked against mpmath in the tests.
    """

    I1: float
    I3: float
    mgl: float
    theta0: float
    thetadot0: float
    phidot0: float
    psidot0: float
    phi0: float
    psi0: float
    omega3: float
    a: float
    b: float
    p_psi: float
    p_phi: float
    energy: float
    energy_prime: float
    alpha: float
    beta: float
    u1: float
    u2: float
    u3: float
    x1: float
    x2: float
    x3: float
    theta_min: float
    theta_max: float
    nutation: str
    m: float
    m1: float
    nutation_period: float
    mean_precession_rate: float
    mean_spin_rate: float
    sleeping_stable: bool
    error_estimate: dict
    _impl: object = field(repr=False)
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    # -- the analysis -------------------------------------------------------
    def f(self, u) -> np.ndarray:
        """f(u) = (1 - u^2)(alpha - beta u) - (b - a u)^2 = udot^2 (1/s^2), notes p. 71."""
        u = np.asarray(u, dtype=float)
        return (1 - u * u) * (self.alpha - self.beta * u) - (self.b - self.a * u) ** 2

    def effective_potential(self, theta) -> np.ndarray:
        """V'(theta) = M g l cos theta + (I1/2) ((b - a cos theta)/sin theta)^2 (J), notes p. 71."""
        theta = np.asarray(theta, dtype=float)
        with np.errstate(divide="ignore"):
            return self.mgl * np.cos(theta) + 0.5 * self.I1 * ((self.b - self.a * np.cos(theta)) / np.sin(theta)) ** 2

    def phidot_of_u(self, u) -> np.ndarray:
        """Precession rate phidot = (b - a u)/(1 - u^2) (rad/s), notes p. 72."""
        u = np.asarray(u, dtype=float)
        return (self.b - self.a * u) / (1 - u * u)

    def psidot_of_u(self, u) -> np.ndarray:
        """Spin rate psidot = I1 a / I3 - u phidot (rad/s), notes p. 71."""
        u = np.asarray(u, dtype=float)
        return self.I1 * self.a / self.I3 - u * self.phidot_of_u(u)

    def regular_precession_rates(self, theta: float | None = None) -> tuple[float, float]:
        """(slow, fast) steady precession rates (rad/s) of this top at tilt ``theta`` (default theta0)."""
        th = self.theta0 if theta is None else theta
        return regular_precession_rates(self.I1, self.I3, self.mgl, self.omega3, th)

    @property
    def turning_points(self) -> tuple[float, float]:
        """(theta_min, theta_max) in rad."""
        return self.theta_min, self.theta_max

    # -- the motion ----------------------------------------------------------
    def evaluator(self, n: int = _FOURIER_MIN_SAMPLES, method: str = "auto"):
        """The evaluation path for ``n`` samples: 'direct' (Jacobi + Carlson per sample),
        'fourier' (verified Fourier series of the periodic parts, built once and cached)
        or 'auto' (Fourier from 1024 samples on, where it has been verified).
        Returns the implementation object (its class name tells which)."""
        if method not in ("auto", "direct", "fourier"):
            raise InputError("method", method, "'auto', 'direct' or 'fourier'")
        if method == "direct" or not isinstance(self._impl, _Elliptic):
            return self._impl
        if method == "auto" and n < _FOURIER_MIN_SAMPLES:
            return self._impl
        if "fourier" not in self._cache:
            self._cache["fourier"] = _build_fourier(self._impl, self.error_estimate)
        return self._cache["fourier"] or self._impl

    def _core(self, t, method):
        t = np.asarray(t, dtype=float)
        flat = t.reshape(-1)
        impl = self.evaluator(flat.size, method)
        return t.shape, _blocked(impl.core, flat)

    def motion(self, t, method: str = "auto") -> TopMotion:
        """theta, phi, psi, their rates, omega (body), the quaternion and the axis at times t (s).

        phi and psi are wrapped to [-pi, pi]; theta is in [0, pi]. Shapes: t.shape
        (+ (3,) or (4,)). Vectorised; the error does not grow with t. ``method``:
        see :meth:`evaluator`.
        """
        shape, c = self._core(t, method)
        sh, ch, sig, dlt = c["sh"], c["ch"], c["sigma"], c["delta"]
        flip = (sh < 0) != (ch < 0)
        theta = 2.0 * np.arctan2(np.abs(sh), np.abs(ch))
        sig_f = np.where(flip, sig + np.pi, sig)
        phi = _wrap(sig_f + dlt)
        psi = _wrap(sig_f - dlt)
        thetadot = np.where(flip, -c["thetadot"], c["thetadot"])
        q = np.stack([ch * np.cos(sig), sh * np.cos(dlt), sh * np.sin(dlt), ch * np.sin(sig)], axis=-1)
        sin_t = 2.0 * sh * ch
        phic = sig + dlt
        psic = sig - dlt
        axis = np.stack([sin_t * np.sin(phic), -sin_t * np.cos(phic), c["u"]], axis=-1)
        ps = c["phidot_sin"]
        tdc = c["thetadot"]
        spsi, cpsi = np.sin(psic), np.cos(psic)
        omega = np.stack([ps * spsi + tdc * cpsi, ps * cpsi - tdc * spsi, np.full_like(ps, self.omega3)], axis=-1)
        t = np.asarray(t, dtype=float)

        def r(a, extra=()):
            return a.reshape(shape + extra)

        return TopMotion(
            t=t, theta=r(theta), phi=r(phi), psi=r(psi), thetadot=r(thetadot), phidot=r(c["phidot"]),
            psidot=r(c["psidot"]), omega=r(omega, (3,)), quaternion=r(q, (4,)), axis=r(axis, (3,)), u=r(c["u"]),
        )

    def evaluate(self, t, method: str = "auto") -> tuple[np.ndarray, np.ndarray]:
        """Body angular velocity (N, 3) in rad/s and attitude quaternion (N, 4), body -> space.

        The interface the engine uses: the quaternion is continuous in t (never
        flips sign on its own) and equals q0 at t = 0 for :func:`heavy_top_from_state`.
        """
        mo = self.motion(t, method)
        return mo.omega, mo.quaternion

    def attitude(self, t, method: str = "auto") -> np.ndarray:
        """Unit quaternions (w, x, y, z) rotating body vectors into space, shape t.shape + (4,)."""
        return self.motion(t, method).quaternion

    def angles(self, t, method: str = "auto") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Euler angles (theta, phi, psi) in rad at times t (phi, psi wrapped to [-pi, pi]).

        The cheapest output: with the Fourier path no quaternion, rate or axis is formed.
        """
        t = np.asarray(t, dtype=float)
        impl = self.evaluator(t.size, method)
        if isinstance(impl, _Fourier):
            theta, sig, dlt = _blocked_tuple(impl.angles_core, t.reshape(-1), 1 << 16)
            shape = t.shape
            return theta.reshape(shape), _wrap(sig + dlt).reshape(shape), _wrap(sig - dlt).reshape(shape)
        mo = self.motion(t, method)
        return mo.theta, mo.phi, mo.psi

    def invariants(self, mo: TopMotion) -> dict:
        """E (J), p_phi and p_psi (kg m^2/s) recomputed from a :class:`TopMotion` (for drift checks).

        From omega and the vertical seen in the body, gamma = R^T e_z (no Euler angle,
        so no loss next to the poles): E = I1 (w1^2 + w2^2)/2 + I3 w3^2/2 + M g l gamma3,
        p_phi = L . e_z = I1 (w1 gamma1 + w2 gamma2) + I3 w3 gamma3, p_psi = I3 w3.
        """
        w = mo.omega
        q = mo.quaternion
        qw, qx, qy, qz = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
        g1 = 2 * (qx * qz - qw * qy)
        g2 = 2 * (qy * qz + qw * qx)
        g3 = mo.u
        e = 0.5 * self.I1 * (w[..., 0] ** 2 + w[..., 1] ** 2) + 0.5 * self.I3 * w[..., 2] ** 2 + self.mgl * g3
        p_phi = self.I1 * (w[..., 0] * g1 + w[..., 1] * g2) + self.I3 * w[..., 2] * g3
        return {"energy": e, "p_phi": p_phi, "p_psi": self.I3 * w[..., 2]}


# --------------------------------------------------------------------------
# Construction
# --------------------------------------------------------------------------
def heavy_top(
    I1: float,  # noqa: N803
    I3: float,  # noqa: N803
    mgl: float,
    theta0: float,
    thetadot0: float = 0.0,
    phidot0: float = 0.0,
    *,
    omega3: float | None = None,
    psidot0: float | None = None,
    phi0: float = 0.0,
    psi0: float = 0.0,
    ml2: float | None = None,
) -> HeavyTopModel:
    """The exact motion of a heavy symmetric top from its Euler-angle initial state (SI).

    Parameters
    ----------
    I1, I3 : float
        Principal moments about the tip (kg m^2), I1 = I2 transverse, I3 axial.
    mgl : float
        M g l (J), >= 0.
    theta0 : float
        Initial tilt of the symmetry axis from the upward vertical, in [0, pi] (rad).
    thetadot0, phidot0 : float
        Initial nutation and precession rates (rad/s).
    omega3, psidot0 : float
        The spin: either omega3 = psidot0 + phidot0 cos theta0 or psidot0 (rad/s), exactly one.
    phi0, psi0 : float
        Initial precession and spin angles (rad).
    ml2 : float, optional
        M l^2 (kg m^2) to check I1 >= M l^2.

    Returns
    -------
    HeavyTopModel

    Raises
    ------
    wobble.errors.InputError
        Bad moments (see :func:`check_top_parameters`), theta0 outside [0, pi],
        non-finite rates, both or neither of omega3 and psidot0.
    """
    I1, I3, mgl = check_top_parameters(I1, I3, mgl, ml2)  # noqa: N806
    theta0 = _finite("theta0", theta0, "an angle in [0, pi] rad")
    if not 0.0 <= theta0 <= np.pi:
        raise InputError("theta0", theta0, "an angle in [0, pi] rad (0 = upright)")
    thetadot0 = _finite("thetadot0", thetadot0, "a finite rate (rad/s)")
    phidot0 = _finite("phidot0", phidot0, "a finite rate (rad/s)")
    phi0 = _finite("phi0", phi0, "a finite angle (rad)")
    psi0 = _finite("psi0", psi0, "a finite angle (rad)")
    if (omega3 is None) == (psidot0 is None):
        raise InputError("omega3, psidot0", (omega3, psidot0), "exactly one of omega3 and psidot0")
    sh, ch = hp.sin_cos(0.5 * theta0, _DIGITS)
    with decimal.localcontext(_ctx()):
        s0 = 2 * sh * ch
        u0 = ch * ch - sh * sh
        if omega3 is not None:
            w3 = _D(_finite("omega3", omega3, "a finite spin rate (rad/s)"))
        else:
            w3 = _D(_finite("psidot0", psidot0, "a finite spin rate (rad/s)")) + _D(phidot0) * u0
        v0 = _D(phidot0) * s0
    return _build(I1, I3, mgl, theta0, sh, ch, _D(thetadot0), v0, w3, _D(phi0), _D(psi0), phidot0)


def heavy_top_from_state(I1: float, I3: float, mgl: float, omega0, q0, *, ml2: float | None = None) -> HeavyTopModel:  # noqa: N803
    """The exact top from an engine-style state: body angular velocity and attitude (SI).

    Parameters
    ----------
    I1, I3, mgl : float
        As in :func:`heavy_top`; the body z axis is the symmetry axis, pointing
        from the tip (at the origin) to the centre of mass; gravity is -z in space.
    omega0 : sequence of 3 float
        Angular velocity in the body frame at t = 0 (rad/s).
    q0 : sequence of 4 float
        Unit quaternion (w, x, y, z) rotating body vectors into space at t = 0.

    Returns
    -------
    HeavyTopModel
        Its :meth:`~HeavyTopModel.evaluate` returns q0 (same sign) and omega0 at t = 0.
    """
    I1, I3, mgl = check_top_parameters(I1, I3, mgl, ml2)  # noqa: N806
    w = np.asarray(omega0, dtype=float).reshape(-1)
    q = np.asarray(q0, dtype=float).reshape(-1)
    if w.size != 3 or not np.all(np.isfinite(w)):
        raise InputError("omega0", omega0, "three finite body-frame angular-velocity components (rad/s)")
    if q.size != 4 or not np.all(np.isfinite(q)) or abs(np.linalg.norm(q) - 1.0) > 1e-9:
        raise InputError("q0", q0, "a unit quaternion (w, x, y, z) with |q| = 1 to 1e-9")
    q = q / np.linalg.norm(q)
    sh_f = float(np.hypot(q[1], q[2]))
    ch_f = float(np.hypot(q[0], q[3]))
    theta0 = 2.0 * float(np.arctan2(sh_f, ch_f))
    sigma0 = float(np.arctan2(q[3], q[0]))
    if sh_f > 0:
        delta0 = float(np.arctan2(q[2], q[1]))
        psi0 = sigma0 - delta0
    else:  # upright: choose psi0 so that the axis leaves the vertical with thetadot >= 0
        psi0 = float(np.arctan2(-w[1], w[0])) if (w[0] != 0 or w[1] != 0) else 0.0
        delta0 = sigma0 - psi0
    cpsi, spsi = np.cos(psi0), np.sin(psi0)
    thetadot0 = float(w[0] * cpsi - w[1] * spsi)
    phidot_sin = float(w[0] * spsi + w[1] * cpsi)
    # theta/2 in decimal from the exact half-angle sines (full relative accuracy).
    with decimal.localcontext(_ctx()):
        norm = (_D(sh_f) ** 2 + _D(ch_f) ** 2).sqrt()
        sh, ch = _D(sh_f) / norm, _D(ch_f) / norm
    phidot0 = phidot_sin / float(2 * sh * ch) if sh_f > 0 and ch_f > 0 else 0.0
    return _build(
        I1, I3, mgl, theta0, sh, ch, _D(thetadot0), _D(phidot_sin), _D(float(w[2])),
        _D(sigma0) + _D(delta0), _D(sigma0) - _D(delta0), phidot0,
    )


def _theta_of(x: Decimal, y: Decimal) -> float:
    """theta = 2 atan2(sqrt(x/2), sqrt(y/2)) from exact x = 1 - u and y = 1 + u.

    The square roots are taken in decimal: x itself underflows float64 for theta below
    1e-154 rad, its root does not.
    """
    with decimal.localcontext(_ctx()):
        sx = (max(x, Decimal(0)) / 2).sqrt()
        sy = (max(y, Decimal(0)) / 2).sqrt()
    return float(2.0 * np.arctan2(float(sx), float(sy)))


def _build(I1, I3, mgl, theta0, sh, ch, thetadot0, v0, w3, phi0, psi0, phidot0_user):  # noqa: N803
    """Analysis and motion from the state in decimal (sh, ch = sin, cos of theta0/2; v0 = phidot0 sin theta0)."""
    with decimal.localcontext(_ctx()):
        i1, i3, mg = _D(I1), _D(I3), _D(mgl)
        x0, y0 = 2 * sh * sh, 2 * ch * ch
        s0 = 2 * sh * ch
        u0 = ch * ch - sh * sh
        # A top started exactly at a pole moving "outwards" across it: the same motion
        # with (theta, phi, psi) -> (-theta, phi + pi, psi + pi) keeps theta in [0, pi].
        sigma_shift = Decimal(0)
        if (x0 == 0 and thetadot0 < 0) or (y0 == 0 and thetadot0 > 0):
            thetadot0 = -thetadot0
            sigma_shift = hp.PI
        a = i3 * w3 / i1
        beta = 2 * mg / i1
        b = v0 * s0 + a * u0
        kin = thetadot0 * thetadot0 + v0 * v0  # thetadot^2 + phidot^2 sin^2 theta
        alpha = kin + beta * u0
        A = kin - beta * x0  # alpha - beta  # noqa: N806
        B = v0 * s0 - a * x0  # b - a  # noqa: N806
        C = v0 * s0 + a * y0  # b + a  # noqa: N806
        g0 = s0 * s0 * thetadot0 * thetadot0
        energy = i1 * kin / 2 + i3 * w3 * w3 / 2 + mg * u0
        e_prime = i1 * kin / 2 + mg * u0
        cub = cubic.TopCubic(A=A, B=B, C=C, a=a, beta=beta)
        roots = cubic.top_roots(cub, x0, y0, g0)
        stable = bool(i3 * i3 * w3 * w3 > 4 * mg * i1)
        sigma0 = (phi0 + psi0) / 2 + sigma_shift
        delta0 = (phi0 - psi0) / 2
        # Uniform motions: at rest on a pole, or regular precession to rounding.
        e0 = 2 * u0 * v0 * v0 + beta * s0 * s0 - 2 * a * v0 * s0  # g'(x0) when thetadot0 = 0
        e0_scale = 2 * abs(u0) * v0 * v0 + beta * s0 * s0 + 2 * abs(a * v0 * s0)
        uniform = None
        # Regular precession to rounding (the bracket of df/du vanishes within the rounding of
        # the inputs): reported as such (u1 = u2 = u0, m = 0), but the motion keeps the
        # exact, tiny nutation of the given floats, so the phases stay exact over long spans.
        regular = thetadot0 == 0 and abs(e0) <= 16 * Decimal(_EPS) * e0_scale
        if thetadot0 == 0 and x0 == 0:
            uniform = "sleeping"
        elif thetadot0 == 0 and y0 == 0:
            uniform = "regular"  # hanging straight down, spinning
        elif roots.x1 - roots.x2 <= Decimal(10) ** (-_DIGITS + 8) * roots.x1:
            uniform = "regular"  # a nutation below the working precision of the roots
        elif roots.beta_gap <= 0 or roots.beta_span <= 0 or roots.beta_gap < Decimal("1e-150") * roots.beta_span:
            if regular:  # e.g. at rest without gravity (f vanishes identically): nothing moves
                uniform = "regular"
            elif roots.beta_gap <= 0:
                raise InputError("thetadot0", _f(thetadot0), "an initial state off the separatrix (the motion "
                                 "would approach an unstable equilibrium for ever; 1 - m = 0)")
        common = dict(
            I1=I1, I3=I3, mgl=mgl, theta0=theta0, thetadot0=_f(thetadot0), phi0=_f(phi0), psi0=_f(psi0),
            omega3=_f(w3), a=_f(a), b=_f(b), p_psi=_f(i3 * w3), p_phi=_f(i1 * b), energy=_f(energy),
            energy_prime=_f(e_prime), alpha=_f(alpha), beta=_f(beta), sleeping_stable=stable,
        )
        if uniform is not None:
            return _uniform_model(uniform, common, roots, x0, y0, sh, ch, u0, v0, s0, w3, sigma0, delta0, phidot0_user, a)
        model = _elliptic_model(common, cub, roots, x0, y0, thetadot0, w3, a, sigma0, delta0, phidot0_user, u0, v0, s0)
        if regular:
            u_0 = _f(u0) if x0 <= 1 else _f(y0 - 1)
            model = replace(model, nutation="regular", u1=u_0, u2=u_0, x1=_f(x0), x2=_f(x0), m=0.0, m1=1.0,
                            theta_min=theta0, theta_max=theta0)
        return model


def _report_roots(roots: cubic.TopRoots, x1=None, x2=None):
    x1 = roots.x1 if x1 is None else x1
    x2 = roots.x2 if x2 is None else x2
    y1, y2 = 2 - x1, 2 - x2
    u1 = _f(1 - x1) if x1 <= 1 else _f(y1 - 1)
    u2 = _f(1 - x2) if x2 <= 1 else _f(y2 - 1)
    u3 = float("inf") if roots.x3.is_infinite() else _f(1 - roots.x3)
    return u1, u2, u3


def _uniform_model(kind, common, roots, x0, y0, sh, ch, u0, v0, s0, w3, sigma0, delta0, phidot0_user, a):
    with decimal.localcontext(_ctx()):
        if s0 != 0:
            phidot = v0 / s0
        else:
            phidot = _D(phidot0_user) if kind == "sleeping" else Decimal(0)
        psidot = w3 - u0 * phidot
        if kind == "sleeping" and not roots.x3.is_infinite() and roots.x3 >= 0:
            # Unstable sleeping top: an equilibrium; the roots are 1 - c2/beta, 1, 1.
            u1, u2, u3 = _f(1 - roots.x1), 1.0, 1.0
            period = float("inf")
            m, m1 = 1.0, 0.0
        else:
            # Regular precession (or a stable sleeping top): u1 = u2 = u0, m = 0, and the
            # period of small nutations about it, 2 pi / sqrt(beta (u3 - u0)).
            u1 = u2 = _f(u0) if x0 <= 1 else _f(y0 - 1)
            if roots.x3.is_infinite():
                span = roots.beta_span
                u3 = float("inf")
            else:
                span = roots.beta_span * (x0 - roots.x3) / (roots.x1 - roots.x3)
                u3 = _f(1 - roots.x3)
            period = _f(2 * hp.PI / span.sqrt()) if span > 0 else float("inf")
            m, m1 = 0.0, 1.0
        theta0 = common["theta0"]
        impl = _Uniform(
            sh=_f(sh), ch=_f(ch), u=_f(u0), sigma_rate=hp.to_dd((phidot + psidot) / 2),
            delta_rate=hp.to_dd((phidot - psidot) / 2), sigma0=_f(sigma0), delta0=_f(delta0),
            phidot=_f(phidot), psidot=_f(psidot),
        )
        est = {"theta_rad": 4 * _EPS * max(theta0, _EPS), "attitude_rad": 8 * _EPS, "turning_points_relative": 2 * _EPS,
               "period_relative": 4 * _EPS}
        return HeavyTopModel(
            phidot0=_f(phidot), psidot0=_f(psidot), u1=u1, u2=u2, u3=u3, x1=_f(x0), x2=_f(x0),
            x3=-float("inf") if roots.x3.is_infinite() else _f(roots.x3), theta_min=theta0, theta_max=theta0,
            nutation=kind, m=m, m1=m1, nutation_period=period, mean_precession_rate=_f(phidot),
            mean_spin_rate=_f(psidot), error_estimate=est, _impl=impl, **common,
        )


def _nutation_class(B, a, x1, x2, y1, y2, C):
    """'undulating', 'cusps' or 'loops' from the sign of phidot at the two turning points."""

    def sign_at(x, y):
        if x == 0 and B == 0:  # through the vertical: phidot = a/(1 + u) = a/2
            n, scale = a, abs(a)
        elif y == 0 and C == 0:  # through the bottom: phidot = -a/(1 - u) = -a/2
            n, scale = -a, abs(a)
        elif x <= 1:  # b - a u in the form without cancellation next to u = +1 ...
            n = B + a * x
            scale = abs(B) + abs(a * x)
        else:  # ... and next to u = -1
            n = C - a * y
            scale = abs(C) + abs(a * y)
        if abs(n) <= 64 * Decimal(_EPS) * scale:
            return 0
        return 1 if n > 0 else -1

    s1, s2 = sign_at(x1, y1), sign_at(x2, y2)
    if s1 == 0 or s2 == 0:
        return "cusps"
    return "undulating" if s1 == s2 else "loops"


# x2/x1 (or y1/y2) below this: the axis passes the pole closer than sqrt(_POLE) theta_max,
# i.e. below the rounding of theta_max, and the motion is followed as a pass through it.
_POLE = Decimal("1e-32")


def _elliptic_model(common, cub, roots, x0, y0, thetadot0, w3, a, sigma0, delta0, phidot0_user, u0, v0, s0):
    from scipy.special import elliprf

    with decimal.localcontext(_ctx()):
        x1, x2, y1, y2 = roots.x1, roots.x2, roots.y1, roots.y2
        span, gap = roots.beta_span, roots.beta_gap
        beta = cub.beta
        B, C = cub.B, cub.C  # noqa: N806
        m = beta * (x1 - x2) / span
        m1 = gap / span
        if m1 < Decimal("1e-150"):
            raise InputError(
                "thetadot0", _f(thetadot0),
                f"a state farther from the separatrix: 1 - m = {_f(m1):.3g} is below what float64 "
                "Carlson integrals resolve (1e-150); the top would creep away from an unstable "
                "equilibrium for a time of order ln(1/(1 - m)) nutation periods",
            )
        lam = span.sqrt() / 2
        kdec = hp.agm_k(m1)
        K = hp.to_dd(kdec)  # noqa: N806
        period = 2 * kdec / lam
        # Mean rates of J_+ = int dt/x and J_- = int dt/y (complete Pi by Bulirsch's cel).
        kc = m1.sqrt()
        pi_plus = hp.cel(kc, x2 / x1, 1, 1) if B != 0 else Decimal(0)
        pi_minus = hp.cel(kc, y2 / y1, 1, 1) if C != 0 else Decimal(0)
        mean_inv_x = pi_plus / (kdec * x1)
        mean_inv_y = pi_minus / (kdec * y1) if C != 0 else Decimal(0)
        w3ma = w3 - a
        mean_phidot = (B * mean_inv_x + C * mean_inv_y) / 2
        mean_psidot = w3ma - (B * mean_inv_x - C * mean_inv_y) / 2
        # A pass closer to a pole than sqrt(x2/x1) = 1e-16 of theta_max (below the rounding
        # of theta) is followed as a pass through it (signed theta; the pi jumps of phi
        # and psi come from the fold): the difference is O(sqrt(x2/x1)) theta_max, and the
        # floats stay far from overflow.
        rho_x = x2 / x1
        rho_y = y1 / y2
        top = x2 == 0 or rho_x < _POLE
        bottom = y1 == 0 or rho_y < _POLE
        b_eff = Decimal(0) if top else B
        c_eff = Decimal(0) if bottom else C
        sigma_rate = (w3ma + c_eff * mean_inv_y) / 2
        delta_rate = (b_eff * mean_inv_x - w3ma) / 2
        # Initial nutation phase w0 in (-K, K]: x0 = x1 cn^2 + x2 sn^2, sn w0 of the sign of -thetadot0.
        width = x1 - x2
        sn0_2 = min(max((x1 - x0) / width, Decimal(0)), Decimal(1))
        cn0_2 = min(max((x0 - x2) / width, Decimal(0)), Decimal(1))
        dn0_2 = cn0_2 + m1 * sn0_2  # = 1 - m sn0^2 without cancellation next to m = 1
        sgn = -1 if thetadot0 > 0 else 1
        sn0 = sgn * sn0_2.sqrt()
        levels = ell.landen_levels(_f(m), _f(m1))
        levels.K = np.asarray(K[0])
        if cn0_2 == 0:
            w0 = sgn * K[0]
        else:
            w0 = _f(sn0) * float(elliprf(_f(cn0_2), _f(dn0_2), 1.0))
        hx1, hy2 = (x1 / 2).sqrt(), (y2 / 2).sqrt()
        impl0 = dict(
            hx1=_f(hx1), hy2=_f(hy2), rho_x=0.0 if top else _f(rho_x), rho_y=0.0 if bottom else _f(rho_y),
            x1=_f(x1), y2=_f(y2), B=_f(b_eff), C=_f(c_eff), B_x1=_f(b_eff / x1), C_y2=_f(c_eff / y2),
            Bp=_f(b_eff / x1 * hx1 * hy2), Cp=_f(c_eff / y2 * hx1 * hy2), W=_f(width / (hx1 * hy2)),
            through_top=bool(top), through_bottom=bool(bottom), a=_f(a), omega3=_f(w3),
            lam=hp.to_dd(lam), K=K, w0=w0, m=_f(m), m1=_f(m1), n_plus=_f(width / x1), one_minus_n_plus=_f(rho_x),
            nu_minus=_f(width / y1) if not bottom else 0.0, pi_plus_over_k=_f(pi_plus / kdec),
            pi_minus_over_k=_f(pi_minus / kdec),
            k_plus=_f(b_eff / (2 * lam * x1)), k_minus=_f(c_eff / (2 * lam * y1)) if not bottom else 0.0,
            sigma_sec=_secular(sigma_rate, lam, kdec, sigma0), delta_sec=_secular(delta_rate, lam, kdec, delta0),
            levels=levels,
        )
        # The periodic parts at t = 0, through the very path the evaluation takes (so that
        # the attitude at t = 0 is q0 to the last bit).
        probe = _Elliptic(p_plus0=0.0, p_minus0=0.0, **impl0)
        r0, _ = probe.phase(np.zeros(1))
        s_, c_, d_ = ell.jacobi_reduced(r0, levels, K[1])
        p_plus0, p_minus0 = probe._periodic(r0, s_, c_, d_)
        impl = _Elliptic(p_plus0=float(p_plus0[0]), p_minus0=float(p_minus0[0]), **impl0)
        u1, u2, u3 = _report_roots(roots)
        nut = _nutation_class(B, a, x1, x2, y1, y2, C)
        if s0 != 0:
            phidot0 = v0 / s0
        else:
            phidot0 = _D(phidot0_user) if x0 == 0 else Decimal(0)
        psidot0 = w3 - u0 * phidot0
        kf = float(K[0])
        swing = abs(_f(b_eff * pi_plus / (lam * x1))) + (abs(_f(c_eff * pi_minus / (lam * y1))) if not bottom else 0.0)
        est = {
            "theta_rad": 32 * _EPS * (1 + kf) * max(_theta_of(x1, y1), _EPS),
            "attitude_rad": 64 * _EPS * (1 + kf) * (1 + swing),
            "turning_points_relative": 4 * _EPS,
            "period_relative": 4 * _EPS,
        }
        return HeavyTopModel(
            phidot0=_f(phidot0), psidot0=_f(psidot0), u1=u1, u2=u2, u3=u3, x1=_f(x1), x2=_f(x2),
            x3=-float("inf") if roots.x3.is_infinite() else _f(roots.x3),
            theta_min=_theta_of(x2, y2), theta_max=_theta_of(x1, y1), nutation=nut, m=_f(m), m1=_f(m1),
            nutation_period=_f(period), mean_precession_rate=_f(mean_phidot), mean_spin_rate=_f(mean_psidot),
            error_estimate=est, _impl=impl, **common,
        )
