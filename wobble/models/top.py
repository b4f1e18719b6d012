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

Modules: this one is the model (:class:`HeavyTopModel`, its constructors and checks);
:mod:`wobble.models.top_setup` is the analysis in 60-digit decimal arithmetic,
:mod:`wobble.models.top_closed_form` evaluates the closed form and
:mod:`wobble.models.top_series` is its Fourier/Taylor accelerator.
"""

from __future__ import annotations

import decimal
import math
from dataclasses import dataclass, field
from decimal import Decimal

import numpy as np

from wobble.errors import InputError
from wobble.models import top_series
from wobble.models.top_closed_form import Elliptic
from wobble.models.top_setup import DIGITS, TopSetup, analyse, context, to_decimal
from wobble.numerics import compiled
from wobble.numerics import highprec as hp
from wobble.numerics.floats import EPS, TINY
from wobble.numerics.phase import REACH

__all__ = [
    "NUTATION_CLASSES",
    "MAX_TURNS",
    "HeavyTopModel",
    "TopMotion",
    "heavy_top",
    "heavy_top_from_state",
    "check_top_parameters",
    "regular_precession_rates",
    "sleeping_top_stable",
]

NUTATION_CLASSES = ("undulating", "cusps", "loops", "regular", "sleeping")
#: Whole periods (nutation periods, or turns of phi or psi when theta is constant) up to which the phases
#: are reduced exactly (:data:`wobble.numerics.phase.REACH`); checked against mpmath at 1.9 x 2^49
#: nutation periods (tests/references/heavy_top_very_long.json).
MAX_TURNS = REACH
_COMPILED_SETUP_FROM = compiled.LONG_ARRAY


def _f(x: Decimal) -> float:
    return float(x)


# --------------------------------------------------------------------------
# Parameters and checks
# --------------------------------------------------------------------------
def _sin_cos_of_tilt(theta: float, halved: bool = False) -> tuple[Decimal, Decimal]:
    """sin and cos of theta (of theta / 2 when ``halved``) to DIGITS digits, reading a right angle as exact.

    The float nearest pi/2 (what 90 deg converts to) stands for pi/2 itself, and numpy.pi (180 deg)
    for pi: those floats lie 6.1e-17 and 1.2e-16 rad short of the angles anyone writing 90 or 180
    deg means, and taken literally they gave a horizontal top cos theta = 6.1e-17, a fast steady
    precession of 8.2e16 rad/s instead of none, and a top hanging straight down a nutation of
    1.2e-16 rad (cusps below the bottom) instead of its equilibrium. No double lies nearer those
    angles, so nothing else is read differently.
    """
    if theta == np.pi:
        return (Decimal(1), Decimal(0)) if halved else (Decimal(0), Decimal(-1))
    if theta == np.pi / 2:
        if not halved:
            return Decimal(1), Decimal(0)
        with decimal.localcontext(context()):
            root_half = (Decimal(1) / 2).sqrt()
        return root_half, root_half
    return hp.sin_cos(0.5 * theta if halved else theta, DIGITS)


def _finite(name: str, value, allowed: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, allowed) from None
    if not np.isfinite(x):
        raise InputError(name, value, allowed)
    return x + 0.0  # -0.0 given (--theta0 -0.0) is 0, not "theta min, max -0, -0 deg" in every report


def check_top_parameters(I1: float, I3: float, mgl: float, ml2: float | None = None) -> tuple[float, float, float]:
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
    I1 = _finite("I1", I1, "a positive, finite moment of inertia (kg m2)")
    I3 = _finite("I3", I3, "a positive, finite moment of inertia (kg m2)")
    mgl = _finite("mgl", mgl, "a finite, non-negative M g l (J)")
    if I1 <= 0:
        raise InputError("I1", I1, "a positive moment of inertia about the tip (kg m2)")
    if I3 <= 0:
        raise InputError("I3", I3, "a positive moment of inertia about the symmetry axis (kg m2)")
    # Subnormal inputs keep a few digits, or none, and every product of them prints wrong figures (I1 = 1.2e-315
    # kg m2 printed p_phi = 2.5e-315 to seven digits): the smallest normal double, as for theta0 and the solids.
    # Before I3 <= 2 I1, which blamed I3 = 0.5 for a subnormal I1 ("I3 <= 2 I1 = 1.99998e-320 kg m2").
    for name, value in (("I1", I1), ("I3", I3)):
        if value < TINY:
            raise InputError(name, value, f"a moment of at least {TINY:.4g} kg m2, the smallest normal double")
    if I3 > 2 * I1 * (1 + 8 * EPS):
        raise InputError("I3", I3, f"I3 <= 2 I1 = {2 * I1:g} kg m2 (a real body has I3 <= I1 + I2)")
    if mgl < 0:
        raise InputError("mgl", mgl, "M g l >= 0 (J): the centre of mass on the symmetry axis, above the tip")
    if 0 < mgl < TINY:
        raise InputError("mgl", mgl, f"0 (no gravity) or at least {TINY:.4g} J, the smallest normal double")
    if ml2 is not None:
        ml2 = _finite("M l^2", ml2, "a finite M l^2 (kg m2)")
        if I1 < ml2 * (1 - 8 * EPS):
            raise InputError(
                "I1",
                I1,
                f"I1 >= M l^2 = {ml2:g} kg m2 (the moment about the tip includes M l^2; "
                "I1 must be about the tip, not the centre of mass)",
            )
    return I1, I3, mgl


def sleeping_top_stable(I1: float, I3: float, mgl: float, omega3: float) -> bool:
    """True when the sleeping top is stable: I3^2 omega3^2 > 4 M g l I1 (Kibble & Berkshire eq. 12.26)."""
    I1, I3, mgl = (hp.exact(float(v)) for v in (I1, I3, mgl))
    w = hp.exact(float(omega3))
    return I3 * I3 * w * w > 4 * mgl * I1


def regular_precession_rates(I1: float, I3: float, mgl: float, omega3: float, theta: float) -> tuple[float, float]:
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
    I1, I3, mgl = check_top_parameters(I1, I3, mgl)
    theta = _finite("theta", theta, "an angle in [0, pi] rad")
    if not 0 <= theta <= np.pi:
        raise InputError("theta", theta, "an angle in [0, pi] rad")
    with decimal.localcontext(context()):
        s, c = _sin_cos_of_tilt(theta)
        a = to_decimal(I3) * to_decimal(omega3) / to_decimal(I1)
        beta = 2 * to_decimal(mgl) / to_decimal(I1)
        disc = a * a - 2 * c * beta
        if disc < 0:
            raise InputError(
                "theta",
                theta,
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
    """The top's state at many times (SI: rad, rad/s, J, kg m^2/s), arrays of shape (N,) or (N, k).

    ``energy``, ``p_phi`` and ``p_psi`` are recomputed from omega and the attitude
    (:meth:`HeavyTopModel.invariants`): their drifts from the initial values
    (``energy_drift``, ``p_phi_drift``, ``p_psi_drift``) measure the error of the motion.
    """

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
    energy: np.ndarray
    p_phi: np.ndarray
    p_psi: np.ndarray
    energy_drift: np.ndarray  # energy - E at t = 0
    p_phi_drift: np.ndarray
    p_psi_drift: np.ndarray


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

    # -- the analysis -------------------------------------------------------
    def f(self, u) -> np.ndarray:
        """f(u) = (1 - u^2)(alpha - beta u) - (b - a u)^2 = udot^2 (1/s^2), notes p. 71."""
        u = np.asarray(u, dtype=float)
        return (1 - u * u) * (self.alpha - self.beta * u) - (self.b - self.a * u) ** 2

    def f_about_u2(self, d) -> np.ndarray:
        """f at u = u2 + d (1/s^2) from the cubic's roots, beta (u - u1)(u - u2)(u - u3), notes p. 71, with
        u - u1 = d + (x1 - x2) and u - u3 = d + (x3 - x2): the roots are kept to 60 digits as x_i = 1 - u_i,
        so this has no cancellation at any scale. :meth:`f`, expanded in floats, cancels: 2e-14 s^-2 of
        rounding at a regular precession of 30 deg. For M g l = 0 (no third root) f is the quadratic."""
        d = np.asarray(d, dtype=float)
        if not np.isfinite(self.x3):
            return self.f(self.u2 + d)
        return self.beta * (d + (self.x1 - self.x2)) * d * (d + (self.x3 - self.x2))

    def well(self, theta) -> np.ndarray:
        """V'(theta) - E' (J) from the roots: -I1 f / (2 sin^2 theta) (notes p. 71) with f from
        :meth:`f_about_u2` at x = 1 - cos theta = 2 sin^2(theta/2). Next to the vertical both V' - E' formed
        directly (two numbers near E') and f(cos theta) lose all but 1e-4 of their digits at 1e-6 rad; at
        theta = 0 it is 0/0 (NaN)."""
        theta = np.asarray(theta, dtype=float)
        x = 2.0 * np.sin(0.5 * theta) ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            return -0.5 * self.I1 * self.f_about_u2(self.x2 - x) / (x * (2.0 - x))

    def effective_potential(self, theta) -> np.ndarray:
        """V'(theta) = M g l cos theta + (I1/2) ((b - a cos theta)/sin theta)^2 (J), notes p. 71."""
        theta = np.asarray(theta, dtype=float)
        with np.errstate(divide="ignore"):
            return self.mgl * np.cos(theta) + 0.5 * self.I1 * ((self.b - self.a * np.cos(theta)) / np.sin(theta)) ** 2

    def phidot_of_u(self, u) -> np.ndarray:
        """Precession rate phidot = (b - a u)/(1 - u^2) (rad/s), notes p. 72.

        At a pole the formula is 0/0 for a top whose axis passes through it (b = a at u = 1,
        b = -a at u = -1), where phidot is the limit a/(1 + u) = a/2, or -a/(1 - u) = -a/2
        (as :func:`~wobble.models.top_setup.nutation_class` takes it); at a pole the top cannot
        reach (f(u) < 0 there) it is the formula's infinity.
        """
        u = np.asarray(u, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = (self.b - self.a * u) / (1 - u * u)
        out = np.where((u == 1.0) & (self.b == self.a), 0.5 * self.a, out)
        return np.where((u == -1.0) & (self.b == -self.a), -0.5 * self.a, out)

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
    def evaluator(self, n: int = top_series.MIN_SAMPLES, method: str = "auto"):
        """The evaluation path for ``n`` samples: 'direct' (Jacobi + Carlson per sample),
        'fourier' (verified Fourier series of the periodic parts, built once and cached)
        or 'auto' (Fourier from 1024 samples on, where it has been verified).
        Returns the implementation object (its class name tells which)."""
        if method not in ("auto", "direct", "fourier"):
            raise InputError("method", method, "'auto', 'direct' or 'fourier'")
        if method == "direct" or not isinstance(self._impl, Elliptic):
            return self._impl
        if method == "auto" and n < top_series.MIN_SAMPLES:
            return self._impl
        # The table lives in top_series' cache (keyed by this model and the set-up path), not in the
        # frozen model. Set up with the compiled helpers where the evaluation itself is compiled (from
        # _COMPILED_SETUP_FROM samples: compiled.LONG_ARRAY as imported, so that a test forcing the NumPy
        # evaluation by raising LONG_ARRAY compares the two evaluations of one table).
        fast = n >= _COMPILED_SETUP_FROM and compiled.available()
        return top_series.series_of(self, self._impl, self.error_estimate, fast) or self._impl

    def motion(self, t, method: str = "auto") -> TopMotion:
        """theta, phi, psi, their rates, omega (body), the quaternion and the axis at times t (s).

        phi and psi are wrapped to [-pi, pi]; theta is in [0, pi]. Shapes: t.shape
        (+ (3,) or (4,)). Vectorised; the error does not grow with t. ``method``:
        see :meth:`evaluator`.
        """
        t = np.asarray(t, dtype=float)
        flat = t.reshape(-1)
        self.check_times(flat)
        impl = self.evaluator(flat.size, method)
        shape = t.shape

        def r(a, extra=()):
            return a.reshape(shape + extra)

        if isinstance(impl, top_series.Fourier):  # every output from the verified series, in one pass
            c = impl.motion(flat, (self.I1, self.I3, self.mgl), (self.energy, self.p_phi, self.p_psi))
            return TopMotion(t=t, **{k: r(v, v.shape[1:]) for k, v in c.items()})
        c = top_series.blocked(impl.core, flat)
        sh, ch, sig, dlt = c["sh"], c["ch"], c["sigma"], c["delta"]
        flip = (sh < 0) != (ch < 0)
        theta = 2.0 * np.arctan2(np.abs(sh), np.abs(ch))
        sig_f = np.where(flip, sig + np.pi, sig)
        phic = c["phi"]  # sigma + delta from its own secular phase (no fast spin to cancel)
        phi = top_series.wrap_angle(np.where(flip, phic + np.pi, phic))
        psi = top_series.wrap_angle(sig_f - dlt)
        thetadot = np.where(flip, -c["thetadot"], c["thetadot"])
        q = np.stack([ch * np.cos(sig), sh * np.cos(dlt), sh * np.sin(dlt), ch * np.sin(sig)], axis=-1)
        sin_t = 2.0 * sh * ch
        psic = sig - dlt
        axis = np.stack([sin_t * np.sin(phic), -sin_t * np.cos(phic), c["u"]], axis=-1)
        ps = c["phidot_sin"]
        tdc = c["thetadot"]
        spsi, cpsi = np.sin(psic), np.cos(psic)
        omega = np.stack([ps * spsi + tdc * cpsi, ps * cpsi - tdc * spsi, np.full_like(ps, self.omega3)], axis=-1)
        inv = self._invariants(omega, q, c["u"])
        for key, start in (("energy", self.energy), ("p_phi", self.p_phi), ("p_psi", self.p_psi)):
            inv[key + "_drift"] = inv[key] - start
        return TopMotion(
            t=t,
            theta=r(theta),
            phi=r(phi),
            psi=r(psi),
            thetadot=r(thetadot),
            phidot=r(c["phidot"]),
            psidot=r(c["psidot"]),
            omega=r(omega, (3,)),
            quaternion=r(q, (4,)),
            axis=r(axis, (3,)),
            u=r(c["u"]),
            **{k: r(v) for k, v in inv.items()},
        )

    @property
    def max_time(self) -> float:
        """The largest time (s) from t = 0, either way, at which the motion is evaluated:
        :data:`MAX_TURNS` - 1 periods of :attr:`limiting_period`, the reach of the exact reductions of
        the phases (:func:`wobble.numerics.phase.reduce_phase`,
        :meth:`wobble.models.top_closed_form.Secular.far`); unlimited for a top at rest."""
        period, _ = self.limiting_period
        return (MAX_TURNS - 1.0) * period

    @property
    def limiting_period(self) -> tuple[float, str]:
        """The period (s) whose count the phases' reductions limit, and what it is: the nutation period
        of a nutating top; for theta constant, a turn of phi or psi, whichever is faster (the phases
        reduced, phi and the half angles (phi +- psi)/2, turn no faster); inf for a top at rest."""
        impl = self._impl
        if isinstance(impl, Elliptic):
            return self.nutation_period, "nutation periods"
        fastest = max(abs(impl.phidot), abs(impl.psidot))
        return (2.0 * math.pi / fastest if fastest > 0.0 else math.inf), "turns of phi or psi"

    def check_times(self, t: np.ndarray) -> None:
        """Refuse times outside [-max_time, max_time] (and non-finite ones), naming the limit."""
        if t.size == 0:
            return
        if not np.all(np.isfinite(t)):
            raise InputError("t", f"{t[~np.isfinite(t)][0]} s", "finite times")
        worst = float(np.max(np.abs(t)))
        if worst > self.max_time:
            period, what = self.limiting_period
            raise InputError(
                "t",
                f"{worst:g} s",
                f"|t| up to {self.max_time:.6g} s, 2^50 {what} ({period:.6g} s each): beyond, the exact "
                "reduction of the phases loses its digits",
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
        if isinstance(impl, top_series.Fourier):
            return tuple(a.reshape(t.shape) for a in impl.angles(t.reshape(-1)))
        mo = self.motion(t, method)
        return mo.theta, mo.phi, mo.psi

    def invariants(self, mo: TopMotion) -> dict:
        """E (J), p_phi and p_psi (kg m^2/s) recomputed from a :class:`TopMotion` (for drift checks).

        From omega and the vertical seen in the body, gamma = R^T e_z (no Euler angle,
        so no loss next to the poles): E = I1 (w1^2 + w2^2)/2 + I3 w3^2/2 + M g l gamma3,
        p_phi = L . e_z = I1 (w1 gamma1 + w2 gamma2) + I3 w3 gamma3, p_psi = I3 w3.
        """
        return self._invariants(mo.omega, mo.quaternion, mo.u)

    def _invariants(self, w, q, g3) -> dict:
        # The series path computes the same in one pass (wobble.numerics.taylor_table.motion).
        qw, qx, qy, qz = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
        g1 = 2 * (qx * qz - qw * qy)
        g2 = 2 * (qy * qz + qw * qx)
        # (I w) w, not I w^2: the squares of the rates of a top of I1 = 5e-324 kg m2 (1e157 rad/s) overflow;
        # in units of S (top_series.energy_terms, 1 unless the energy nears the largest double), as the
        # compiled pass computes it, operation for operation.
        ei1, ei3, emgl, scale = top_series.energy_terms(self.I1, self.I3, self.mgl, self.energy)
        l1, l2, l3 = ei1 * w[..., 0], ei1 * w[..., 1], ei3 * w[..., 2]
        e = ((0.5 * (l1 * w[..., 0] + l2 * w[..., 1]) + 0.5 * (l3 * w[..., 2])) + emgl * g3) * scale
        p_phi = self.I1 * (w[..., 0] * g1 + w[..., 1] * g2) + self.I3 * w[..., 2] * g3
        return {"energy": e, "p_phi": p_phi, "p_psi": self.I3 * w[..., 2]}


# --------------------------------------------------------------------------
# Construction
# --------------------------------------------------------------------------
@hp.isolated(context)  # all of its decimal arithmetic at DIGITS digits, none in the caller's context
def heavy_top(
    I1: float,
    I3: float,
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
        Initial tilt of the symmetry axis from the upward vertical, in [0, pi] (rad);
        ``numpy.pi`` (and so 180 deg) is pi itself, hanging straight down, and the float nearest
        pi/2 (90 deg) is pi/2 itself, a horizontal axis.
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
        non-finite rates, rates whose energy or angular momentum overflows a double,
        both or neither of omega3 and psidot0.
    """
    I1, I3, mgl = check_top_parameters(I1, I3, mgl, ml2)
    theta0 = _finite("theta0", theta0, "an angle in [0, pi] rad")
    if not 0.0 <= theta0 <= np.pi:
        raise InputError("theta0", theta0, "an angle in [0, pi] rad (0 = upright)")
    if 0.0 < theta0 < TINY:
        # A subnormal tilt keeps a few of its digits (1e-320 rad was reported as 5.729531e-319 deg).
        raise InputError(
            "theta0",
            theta0,
            f"0 (upright) or a tilt of at least {TINY:.4g} rad ({np.degrees(TINY):.4g} deg), the smallest normal "
            "double",
        )
    thetadot0 = _finite("thetadot0", thetadot0, "a finite rate (rad/s)")
    phidot0 = _finite("phidot0", phidot0, "a finite rate (rad/s)")
    phi0 = _finite("phi0", phi0, "a finite angle (rad)")
    psi0 = _finite("psi0", psi0, "a finite angle (rad)")
    if (omega3 is None) == (psidot0 is None):
        raise InputError("omega3, psidot0", (omega3, psidot0), "exactly one of omega3 and psidot0")
    sh, ch = _sin_cos_of_tilt(theta0, halved=True)
    with decimal.localcontext(context()):
        s0 = 2 * sh * ch
        u0 = ch * ch - sh * sh
        if omega3 is not None:
            w3 = to_decimal(_finite("omega3", omega3, "a finite spin rate (rad/s)"))
        else:
            w3 = to_decimal(_finite("psidot0", psidot0, "a finite spin rate (rad/s)")) + to_decimal(phidot0) * u0
        v0 = to_decimal(phidot0) * s0
        td = to_decimal(thetadot0)
        kin = td * td + v0 * v0
        energy = to_decimal(I1) * kin / 2 + to_decimal(I3) * w3 * w3 / 2 + to_decimal(mgl) * u0
        p_psi = to_decimal(I3) * w3
    # As for the free body: a motion whose energy, squared tilt rate or spin momentum overflows a double has
    # no floating-point answer (its nutation period underflows, its phases lose every digit). The rates'
    # own terms only: a heavy top of M g l = 1.7e308 J at rest is as finite as before.
    if not all(np.isfinite(float(x)) for x in (energy, kin, p_psi)):
        spin = ("omega3", omega3) if omega3 is not None else ("psidot0", psidot0)
        raise InputError(
            f"thetadot0, phidot0, {spin[0]}",
            (thetadot0, phidot0, spin[1]),
            f"rates whose energy fits double precision: E = I1 (thetadot^2 + phidot^2 sin^2 theta)/2 + I3 w3^2/2 "
            f"+ M g l cos theta, thetadot^2 + phidot^2 sin^2 theta and I3 w3 below {np.finfo(float).max:.4g} in SI",
        )
    setup = TopSetup(
        I1=I1,
        I3=I3,
        mgl=mgl,
        theta0=theta0,
        sin_half=sh,
        cos_half=ch,
        thetadot0=to_decimal(thetadot0),
        v0=v0,
        omega3=w3,
        phi0=to_decimal(phi0),
        psi0=to_decimal(psi0),
        phidot0=phidot0,
    )
    return HeavyTopModel(**analyse(setup))


@hp.isolated(context)
def heavy_top_from_state(I1: float, I3: float, mgl: float, omega0, q0, *, ml2: float | None = None) -> HeavyTopModel:
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
    I1, I3, mgl = check_top_parameters(I1, I3, mgl, ml2)
    w = np.asarray(omega0, dtype=float).reshape(-1)
    q = np.asarray(q0, dtype=float).reshape(-1)
    if w.size != 3 or not np.all(np.isfinite(w)):
        raise InputError("omega0", omega0, "three finite body-frame angular-velocity components (rad/s)")
    # |q| = 1 to 1e-6, as a scene's attitude: a float32 unit quaternion (7 digits) is one; q is normalised.
    if q.size != 4 or not np.all(np.isfinite(q)) or abs(np.linalg.norm(q) - 1.0) > 1e-6:
        raise InputError("q0", q0, "a unit quaternion (w, x, y, z) with |q| = 1 to 1e-6")
    q = q / np.linalg.norm(q)
    sh_f = float(np.hypot(q[1], q[2]))
    ch_f = float(np.hypot(q[0], q[3]))
    # A tilt from a pole below the rounding of the attitude (2 sin(theta/2) or 2 cos(theta/2) under eps) is the
    # pole itself: followed from there, a sideways rate sent the axis off along the start's azimuth instead of
    # its own (3 rad off from 1e-16 rad; an audit of exact special cases). Moving the start onto the pole
    # changes the attitude by less than its own rounding.
    if 0 < ch_f and 2 * ch_f < EPS * sh_f:
        q = np.array([0.0, q[1], q[2], 0.0]) / sh_f
        sh_f, ch_f = 1.0, 0.0
    elif 0 < sh_f and 2 * sh_f < EPS * ch_f:
        q = np.array([q[0], 0.0, 0.0, q[3]]) / ch_f
        sh_f, ch_f = 0.0, 1.0
    theta0 = 2.0 * float(np.arctan2(sh_f, ch_f))
    sigma0 = float(np.arctan2(q[3], q[0]))
    sideways = w[0] != 0 or w[1] != 0
    if ch_f == 0:
        # Hanging straight down: only delta = (phi - psi)/2 is defined, sigma = atan2(0, 0) is not. psi0 is chosen
        # so that the sideways rate is all thetadot, leaving the bottom (thetadot <= 0); from sigma's arbitrary value
        # part of it went into phidot sin(theta), which is 0 there, and was lost (a pendulum kicked from rest at
        # the bottom did not move).
        delta0 = float(np.arctan2(q[2], q[1]))
        psi0 = float(np.arctan2(w[1], -w[0])) if sideways else 0.0
        sigma0 = psi0 + delta0
    elif sh_f > 0:
        delta0 = float(np.arctan2(q[2], q[1]))
        psi0 = sigma0 - delta0
    else:  # upright: choose psi0 so that the axis leaves the vertical with thetadot >= 0
        psi0 = float(np.arctan2(-w[1], w[0])) if sideways else 0.0
        delta0 = sigma0 - psi0
    cpsi, spsi = np.cos(psi0), np.sin(psi0)
    thetadot0 = float(w[0] * cpsi - w[1] * spsi)
    phidot_sin = float(w[0] * spsi + w[1] * cpsi)
    # theta/2 in decimal from the exact half-angle sines (full relative accuracy).
    with decimal.localcontext(context()):
        norm = (to_decimal(sh_f) ** 2 + to_decimal(ch_f) ** 2).sqrt()
        sh, ch = to_decimal(sh_f) / norm, to_decimal(ch_f) / norm
    phidot0 = phidot_sin / float(2 * sh * ch) if sh_f > 0 and ch_f > 0 else 0.0
    phi0_d = to_decimal(sigma0) + to_decimal(delta0)  # in context() (hp.isolated), not the caller's
    psi0_d = to_decimal(sigma0) - to_decimal(delta0)
    setup = TopSetup(
        I1=I1,
        I3=I3,
        mgl=mgl,
        theta0=theta0,
        sin_half=sh,
        cos_half=ch,
        thetadot0=to_decimal(thetadot0),
        v0=to_decimal(phidot_sin),
        omega3=to_decimal(float(w[2])),
        phi0=phi0_d,
        psi0=psi0_d,
        phidot0=phidot0,
    )
    return HeavyTopModel(**analyse(setup))
