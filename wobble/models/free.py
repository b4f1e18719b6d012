"""Torque-free rigid-body rotation, exactly: angular velocity and attitude (SI, float64).

Course notes section 5.6 (free precession of a symmetric body, pages 68-69)
taken to the asymmetric body with Landau & Lifshitz, Mechanics, section 37.

Frames. The user's principal axes (any order of the moments) are mapped to a
right-handed *model frame* by a signed permutation (det +1) with
``I1 <= I2 <= I3``; results are mapped back, so outputs keep the user's axis
order. The attitude quaternion ``q(t)`` (scalar first) rotates body vectors
into the inertial frame and is the identity at t = 0; the inertial angular
momentum is then ``L_in = I omega0``.

Solutions (chosen from the exact inputs, see :func:`free_rotation`):

* ``steady``: omega0 is a principal direction (sphere, principal-axis spin,
  omega0 = 0): omega constant, attitude a uniform rotation about it.
* ``symmetric`` (two equal moments, notes p. 69): omega_1 = A cos(Omega t + beta),
  omega_2 = A sin(Omega t + beta), omega_3 constant, Omega = (I3 - I1) omega3 / I1;
  the body cone rolls on the space cone: q(t) = R_L(L t / I1) R_3(-Omega t).
* ``major-axis`` (L^2 > 2 E I2) and ``minor-axis`` (L^2 < 2 E I2), LL section 37:
  omega_a = A_a cn(u), omega_b = s A_b sn(u), omega_c = s A_c dn(u),
  u = lambda t + u0, with (a, b, c) = (1, 2, 3) or (3, 2, 1).
* ``separatrix`` (L^2 = 2 E I2 exactly): the same with m = 1 (tanh, sech).

Exact attitude (derived in docs/free-rotation.md): with l = I omega / L and
z = sign(omega_c) e_c, q(t) = S(0)* R_z(psi(t)) S(t), where S(t) is the
shortest-arc rotation taking l(t) to z (never singular: l.z = L_c / L > 0) and

    psi' = L / I_c + (D_c / I_c) / (L + I_c A_c dn u),    D_c = 2 E I_c - L^2,

whose integral is an elliptic integral of the third kind with characteristic
n = -nu, nu = I_c (I_b - I_a) / (I_a (I_c - I_b)) (evaluated with Carlson's
forms in :func:`wobble.numerics.elliptic.pi_negative_scd`) plus an arctangent.

Accuracy. All invariants (2 E I_j - L^2, 1 - m, amplitudes, rates) are formed
from the exact float inputs in exact rational arithmetic, then rates, K and
the mean precession rate to ~30 digits (:mod:`wobble.numerics.highprec`);
phases are carried in double-double and reduced exactly
(:mod:`wobble.numerics.phase`), so the phase error does not grow with t
(measured below 1e-15 rad of wobble phase after 10^6 periods; see
docs/free-rotation.md for the measured error budget).
"""

from __future__ import annotations

import decimal
import math
import sys
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from wobble.numerics.scaled_norm import norm
from wobble.numerics.floats import EPS, HUGE, TINY
from wobble.errors import InputError
from wobble.models.principal_axes import proper_signs, to_sorted, to_user
from wobble.models.vocabulary import Regime
from wobble.numerics import compiled
from wobble.numerics import elliptic as ell
from wobble.numerics import highprec as hp
from wobble.numerics import quaternion as quat
from wobble.numerics.double_double import two_prod
from wobble.numerics.phase import REACH, reduce_phase
from wobble.numerics.phasor import block_parts, block_phasors, uniform_grid

__all__ = [
    "intermediate_axis_alignment",
    "steady_axis",
    "FreeRotationModel",
    "free_rotation",
    "symmetric_from_energy",
    "REGIMES",
]

REGIMES = tuple(r.value for r in Regime)
_TWO_PI_DD = hp.TWO_PI_DD


def _proper_frame(order):
    """``(order, signs)`` of the proper signed permutation taking user axes to model axes ``order``."""
    order = tuple(int(i) for i in order)
    return order, tuple(float(s) for s in proper_signs(order))


# --------------------------------------------------------------------------
# The three kinds of exact solution, each in its own right-handed frame
# --------------------------------------------------------------------------
def _turn(rate) -> float:
    """Time (s) per turn of a phase of double-double ``rate`` (rad/s); inf if it does not move."""
    return 2.0 * math.pi / abs(rate[0]) if rate[0] != 0.0 else math.inf


@dataclass(frozen=True)
class _Steady:
    """omega constant (principal-axis spin, sphere, zero): uniform rotation."""

    omega: tuple[float, float, float]
    half_rate: tuple[float, float]  # |omega| / 2 as double-double (rad/s)

    def omega_at(self, t):
        return np.broadcast_to(np.asarray(self.omega), t.shape + (3,)).copy()

    def reduction_periods(self):
        """Time (s) per whole turn of each reduced phase: the half angle |omega| t / 2."""
        return (_turn(self.half_rate),)

    def attitude_at(self, t):
        w = np.asarray(self.omega)
        # A scaled norm: the squares of a spin of 1e-200 rad/s (a body of 1e200 kg m2) underflow, and the axis
        # of its rotation would fall back to z.
        length = float(norm(w))
        axis = w / length if length > 0 else np.array([0.0, 0.0, 1.0])
        half, _ = reduce_phase(t, self.half_rate, _TWO_PI_DD)
        return np.concatenate([np.cos(half)[..., None], np.sin(half)[..., None] * axis], axis=-1)


@dataclass(frozen=True)
class _Symmetric:
    """I1 = I2 (axis 3 the symmetry axis of this frame): notes section 5.6."""

    i_perp: float
    i_axis: float
    amplitude: float  # A (rad/s)
    omega3: float
    beta: float  # phase of (omega1, omega2) at t = 0 (rad)
    rate: tuple[float, float]  # Omega = (I3 - I1) omega3 / I1, double-double
    half_space_rate: tuple[float, float]  # L / (2 I1), double-double
    l_dir: tuple[float, float, float]  # L / |L| in this frame at t = 0

    def reduction_periods(self):
        """Time (s) per whole turn of each reduced phase: Omega t, L t / (2 I1) and -Omega t / 2."""
        return (_turn(self.rate), _turn(self.half_space_rate), 2.0 * _turn(self.rate))

    def omega_at(self, t):
        phase, _ = reduce_phase(t, self.rate, _TWO_PI_DD, 0.0)
        ang = phase + self.beta
        return np.stack(
            [self.amplitude * np.cos(ang), self.amplitude * np.sin(ang), np.full_like(ang, self.omega3)], -1
        )

    def _phasor(self, t):
        phase, _ = reduce_phase(t, self.rate, _TWO_PI_DD, 0.0)
        ang = phase + self.beta
        z = np.empty(t.shape, dtype=complex)
        z.real = np.cos(ang)
        z.imag = np.sin(ang)
        return z

    def grid_polynomial(self):
        """(cos-, sin-, constant-type axes), (ka0, ka1, kb0, kb1, kc0, kc1) of :mod:`wobble.numerics.nome_grid`."""
        return (0, 1, 2), (0.0, self.amplitude, 0.0, self.amplitude, 0.0, self.omega3)

    def omega_on_grid(self, t0, dt, n):
        """omega at t0 + k dt (k < n): exp(i (Omega t + beta)) by block rotation."""
        z = block_phasors(self._phasor, t0, dt, n)
        out = np.empty((n, 3))
        out[:, 0] = self.amplitude * z.real
        out[:, 1] = self.amplitude * z.imag
        out[:, 2] = self.omega3
        return out

    def attitude_at(self, t):
        half_space, _ = reduce_phase(t, self.half_space_rate, _TWO_PI_DD)
        half_body, _ = reduce_phase(t, (-0.5 * self.rate[0], -0.5 * self.rate[1]), _TWO_PI_DD)
        space = np.concatenate(
            [np.cos(half_space)[..., None], np.sin(half_space)[..., None] * np.asarray(self.l_dir)], -1
        )
        body = np.stack([np.cos(half_body), 0 * half_body, 0 * half_body, np.sin(half_body)], -1)
        return quat.multiply(space, body)


@dataclass(frozen=True)
class _Elliptic:
    """I1 < I2 < I3 in this frame: Jacobi elliptic solution (LL section 37)."""

    a: int
    b: int
    c: int
    amp: tuple[float, float, float]  # A_a, A_b, A_c (rad/s)
    sign_bc: float  # s: omega_b = s A_b sn, omega_c = s A_c dn
    m: float
    m1: float
    lam: tuple[float, float]  # lambda (1/s), double-double
    K: tuple[float, float]  # quarter period K(m), double-double (inf on the separatrix)
    u0: float
    moments: tuple[float, float, float]
    L: float
    nu: float
    c_pi: float
    c_g: float
    pi_over_k: float  # Pi(-nu | m) / K
    half_prec_rate: tuple[float, float]  # Omega_psi / 2, double-double
    levels: object = field(repr=False, compare=False)
    # Near-circular motion (m <= _FOURIER_MAX_M): pi/(2K) and the nome-series
    # coefficients (sn1, sn3, cn1, cn3, dn0, dn2) of DLMF 22.11.1-3, else None.
    fourier: tuple | None = field(default=None, repr=False, compare=False)

    def reduction_periods(self):
        """Time (s) per whole reduction of each phase: a half-period 2K / lambda of omega (none on the
        separatrix, whose phase is not reduced) and a turn of the half precession angle Omega_psi t / 2."""
        half = 2.0 * self.K[0] / self.lam[0] if np.isfinite(self.K[0]) else math.inf
        return (half, _turn(self.half_prec_rate))

    def phase(self, t):
        """u = lambda t + u0 reduced modulo 2K: returns (r, j) with |r| <= K."""
        return reduce_phase(t, self.lam, (2 * self.K[0], 2 * self.K[1]), self.u0)

    def _scd(self, r, j):
        sn, cn, dn = ell.jacobi_reduced(r, self.levels, self.K[1])
        if np.isinf(self.K[0]):
            with np.errstate(over="ignore"):
                sech = 1.0 / np.cosh(r)
            sn, cn, dn = np.tanh(r), sech, sech
        odd = np.floor(0.5 * j) != 0.5 * j  # (np.fmod is ten times slower)
        sgn = np.where(odd, -1.0, 1.0)
        return sn, cn, dn, sgn

    def omega_at(self, t):
        r, j = self.phase(t)
        sn, cn, dn, sgn = self._scd(r, j)
        out = np.empty(t.shape + (3,))
        out[..., self.a] = self.amp[0] * sgn * cn
        out[..., self.b] = self.sign_bc * self.amp[1] * sgn * sn
        out[..., self.c] = self.sign_bc * self.amp[2] * dn
        return out

    def _phasor(self, t):
        """exp(i v), v = pi u / (2K): the angle of the nome series, from the exact reduction."""
        r, j = self.phase(t)
        w = r * self.fourier[0]
        sgn = np.where(np.floor(0.5 * j) != 0.5 * j, -1.0, 1.0)
        z = np.empty(t.shape, dtype=complex)
        z.real = sgn * np.cos(w)
        z.imag = sgn * np.sin(w)
        return z

    def grid_polynomial(self):
        """(cos-, sin-, constant-type axes), (ka0, ka1, kb0, kb1, kc0, kc1): the nome series of
        :meth:`omega_on_grid` as polynomials in cos v and sin v (:mod:`wobble.numerics.nome_grid`)."""
        if self.fourier is None:
            return None
        _, a1, a3, c1, c3, d0, d2 = self.fourier
        s, (amp_a, amp_b, amp_c) = self.sign_bc, self.amp
        return (self.a, self.b, self.c), (
            4.0 * c3 * amp_a,
            (c1 - 3.0 * c3) * amp_a,
            -4.0 * a3 * s * amp_b,
            (a1 + 3.0 * a3) * s * amp_b,
            2.0 * d2 * s * amp_c,
            (d0 - d2) * s * amp_c,
        )

    def omega_on_grid(self, t0, dt, n):
        """omega at t0 + k dt (k < n) for m <= _FOURIER_MAX_M, without per-sample sn, cn, dn.

        DLMF 22.11.1-3 with v = pi u/(2K) and the nome q = exp(-pi K'/K) ~ m/16:
        sn = a1 sin v + a3 sin 3v, cn = c1 cos v + c3 cos 3v, dn = d0 + d2 cos 2v,
        dropping terms of relative size q^2 <= 4e-17; exp(i v) by block rotation
        (:func:`wobble.numerics.phasor.block_phasors`).
        """
        _, a1, a3, c1, c3, d0, d2 = self.fourier
        z = block_phasors(self._phasor, t0, dt, n)
        out = np.empty((3, n))  # component-major: contiguous rows, one transpose at the end
        # cos 3v = c (4c^2 - 3), sin 3v = s (3 - 4s^2), cos 2v = 2c^2 - 1, in place:
        c2 = np.multiply(z.real, z.real)
        row = out[self.c]
        np.multiply(c2, 2.0 * d2 * self.sign_bc * self.amp[2], out=row)
        row += (d0 - d2) * self.sign_bc * self.amp[2]
        row = out[self.a]
        np.multiply(c2, 4.0 * c3 * self.amp[0], out=row)
        row += (c1 - 3.0 * c3) * self.amp[0]
        row *= z.real
        row = out[self.b]
        np.multiply(z.imag, z.imag, out=row)
        row *= -4.0 * a3 * self.sign_bc * self.amp[1]
        row += (a1 + 3.0 * a3) * self.sign_bc * self.amp[1]
        row *= z.imag
        return out.T

    def _periodic(self, r, sn, cn, dn):
        """P(r): the 2K-periodic part of psi, from sn, cn, dn of |r| <= K."""
        # r may lie past the true K by the rounding of K (a start with omega_a = 0: cn = -3.5e-17). The Carlson
        # form's R_C term is odd in cn, its other terms even in it: past 0 it is not Pi's continuation, and c_pi
        # (1e7 for I2 - I1 = 2e-15 I1) made that an attitude error of 2e-9 rad. Pi at the quarter period instead
        # errs by the distance times Pi's slope there, 1/((1 + nu) sqrt(m1)).
        cn = np.maximum(cn, 0.0)
        pi_inc = ell.pi_negative_scd(self.nu, sn, cn, dn * dn, self.m1)
        g = np.arctan2(np.sqrt(1.0 + self.nu) * sn, cn)
        k = self.K[0]
        if np.isinf(k):  # the separatrix: no period, no linear part (0 * inf would be NaN)
            return self.c_pi * pi_inc - self.c_g * g
        lin = r / k
        return self.c_pi * (pi_inc - self.pi_over_k * lin * k) - self.c_g * (g - 0.5 * np.pi * lin)

    def attitude_at(self, t):
        return self._state(t)[1]

    def state_at(self, t):
        """omega (model frame) and the attitude at times t side by side, shape t.shape + (7,): one
        reduction and one set of Jacobi functions for both (:meth:`omega_at`'s omega, term for term)."""
        omega, q = self._state(t)
        return np.concatenate([omega, q], axis=-1)

    def _state(self, t):
        r, j = self.phase(t)
        sn, cn, dn, sgn = self._scd(r, j)
        periodic = self._periodic(r, sn, cn, dn)
        r0, j0 = self.phase(np.zeros(1))
        sn0, cn0, dn0, sgn0 = self._scd(r0, j0)
        periodic0 = self._periodic(r0, sn0, cn0, dn0)[0]
        half_secular, _ = reduce_phase(t, self.half_prec_rate, _TWO_PI_DD)
        half = half_secular + 0.5 * (periodic - periodic0)
        z = np.zeros(3)
        z[self.c] = self.sign_bc
        omega = np.empty(t.shape + (3,))
        omega[..., self.a] = self.amp[0] * sgn * cn
        omega[..., self.b] = self.sign_bc * self.amp[1] * sgn * sn
        omega[..., self.c] = self.sign_bc * self.amp[2] * dn
        lvec = omega * np.asarray(self.moments) / self.L
        s_t = quat.shortest_arc(lvec, z)
        omega0 = self.omega_at(np.zeros(1))
        # [0]: one quaternion, shape (4,), so that the result is t.shape + (4,) (a scalar t gave (1, 4)).
        s_0 = quat.shortest_arc(omega0 * np.asarray(self.moments) / self.L, z)[0]
        twist = np.concatenate([np.cos(half)[..., None], np.sin(half)[..., None] * z], -1)
        return omega, quat.multiply(quat.conjugate(s_0), quat.multiply(twist, s_t))


# --------------------------------------------------------------------------
# The model: what the API and CLI see
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class FreeRotationModel:
    """Exact torque-free motion of a rigid body (SI: kg m^2, rad/s, s, J).

    Build with :func:`free_rotation`. All arrays are in the user's axis order.

    Attributes
    ----------
    moments : tuple of float
        Principal moments (kg m^2), user order.
    omega0 : tuple of float
        Angular velocity at t = 0 in the body frame (rad/s), user order.
    regime : str
        One of :data:`REGIMES`.
    energy : float
        Kinetic energy T = 1/2 sum I_j omega_j^2 (J).
    angular_momentum : float
        |L| (kg m^2 / s).
    m, m1 : float
        Parameter of the elliptic functions and 1 - m from the exact
        invariants (m = 0, m1 = 1 for steady and symmetric motion).
    period : float
        Period of omega(t) (s): 4K / lambda for elliptic motion, 2 pi / |Omega|
        for symmetric precession; ``inf`` on the separatrix and for steady spin.
    time_between_flips : float or None
        2K / lambda (s): the time between sign changes of the intermediate-axis
        component (half the period); None where there is no flip.
    error_estimate : dict
        Bounds on the relative error of omega and on the attitude angle (rad),
        from the error analysis in docs/free-rotation.md, checked against
        mpmath in tests/test_free_model.py.
    precession_rate : float
        Mean precession rate about L (rad/s): the mean over a period of Landau &
        Lifshitz's Euler-angle rate phidot = L (I_a w_a^2 + I_b w_b^2)/(I_a^2 w_a^2 + I_b^2 w_b^2)
        (section 37), L / I1 for a symmetric body (notes 5.6), ``|omega|`` for steady spin.
        Continuous in the symmetric limit; undefined (the attitude angle's rate) on the separatrix.
    """

    moments: tuple[float, float, float]
    omega0: tuple[float, float, float]
    regime: str
    energy: float
    angular_momentum: float
    m: float
    m1: float
    period: float
    time_between_flips: float | None
    error_estimate: dict
    precession_rate: float
    _order: tuple[int, int, int] = field(repr=False)
    _signs: tuple[float, float, float] = field(repr=False)
    _impl: object = field(repr=False)
    _flip: tuple = field(repr=False, default=())

    @property
    def angular_momentum_inertial(self) -> np.ndarray:
        """L in the inertial frame (kg m^2/s), equal to I omega0 since q(0) = identity."""
        return np.asarray(self.moments) * np.asarray(self.omega0)

    @property
    def limiting_period(self) -> float:
        """The shortest time (s) of one whole reduction among the phases (:meth:`max_time`): a half-period
        2K / lambda of omega, or a turn of a secular phase; inf when nothing turns."""
        return min(self._impl.reduction_periods())

    @property
    def max_time(self) -> float:
        """The largest time (s) from t = 0, either way, at which the motion is evaluated: 2^50 - 1
        :attr:`limiting_period` (:data:`wobble.numerics.phase.REACH`), the reach of the exact phase
        reductions; checked against mpmath at 2^49.9 half-periods (tests/references/free_rotation_very_long.json).
        Unlimited for a body at rest."""
        return (REACH - 1.0) * self.limiting_period

    def check_times(self, t: np.ndarray) -> None:
        """Refuse times beyond :attr:`max_time` either way, naming the limit (NaN passes through)."""
        if t.size == 0:
            return
        worst = float(max(-np.min(t), np.max(t)))
        if worst > self.max_time:
            raise InputError(
                "t",
                f"{worst:g} s",
                f"|t| up to {self.max_time:.6g} s, 2^50 turns of its fastest phase ({self.limiting_period:.6g} s "
                "each): beyond, the exact reduction of the phases loses its digits",
            )

    def omega(self, t) -> np.ndarray:
        """Body-frame angular velocity (rad/s) at times ``t`` (s), shape t.shape + (3,)."""
        t = np.asarray(t, dtype=float)
        fast = self._omega_compiled_grid(t)  # checks the grid's two ends against max_time
        if fast is not None:
            return fast
        self.check_times(t)
        return to_user(self._omega_model_frame(t), self._order, self._signs)

    def _omega_compiled_grid(self, t):
        """The grid path compiled (:mod:`wobble.numerics.nome_grid`), in the user's frame; None where it
        does not apply (grids shorter than :data:`wobble.numerics.compiled.LONG_ARRAY` or not uniform,
        m > 1e-7, no Numba) and the NumPy paths take over. A century of days: ~0.5-0.7 ms against
        ~1.3-1.9 ms in NumPy, measured with a garbage collection before each call. Only where Numba is
        loaded already (a scene run, a sweep): importing it and loading the kernel costs about a second,
        which a millisecond a call never repays in a `wobble free` (3.9 s against 3.2 s, 2026-11-30)."""
        poly = getattr(self._impl, "grid_polynomial", None)
        if poly is None or t.ndim != 1 or t.size < compiled.LONG_ARRAY:
            return None
        if "numba" not in sys.modules or not compiled.available():
            return None
        parts = poly()
        if parts is None:
            return None
        from wobble.numerics import nome_grid

        grid = nome_grid.uniform_grid(t)
        if grid is None:
            return None
        self.check_times(t[[0, -1]])  # a uniform grid's extremes are its ends: no pass over t (12 us a century)
        starts, step = block_parts(self._impl._phasor, grid[0], grid[1], t.size)
        axes, k = parts
        # Model axis i goes to the user's column order[i] with sign signs[i] (_to_user): exact.
        sg = [self._signs[i] for i in axes]
        coef = (sg[0] * k[0], sg[0] * k[1], sg[1] * k[2], sg[1] * k[3], sg[2] * k[4], sg[2] * k[5])
        return nome_grid.polynomial_omega(starts, step, t.size, [self._order[i] for i in axes], coef)

    def _jacobi_only(self) -> bool:
        """Whether omega is the per-sample Jacobi evaluation (``omega_at``) whatever the times: an
        elliptic body without a nome series, which both grid paths need (its ``grid_polynomial`` is
        None too). :meth:`state` shares that evaluation with the attitude only then."""
        return getattr(self._impl, "fourier", True) is None

    def _omega_model_frame(self, t):
        # A long uniform grid of a near-circular wobble (Earth, Mars) takes the
        # block-rotation path: no per-sample reduction, trigonometry or elliptic functions.
        on_grid = getattr(self._impl, "omega_on_grid", None)
        if on_grid is not None and not self._jacobi_only():
            grid = uniform_grid(t)
            if grid is not None:
                return on_grid(grid[0], grid[1], t.size)
        return _blocked(self._impl.omega_at, t, 3)

    def attitude(self, t) -> np.ndarray:
        """Unit quaternions (w, x, y, z) rotating body vectors into the inertial frame."""
        t = np.asarray(t, dtype=float)
        self.check_times(t)
        return self._attitude_to_user(_blocked(self._impl.attitude_at, t, 4))

    def _attitude_to_user(self, q):
        out = q.copy()
        out[..., 1:] = to_user(q[..., 1:], self._order, self._signs)
        return out

    def state(self, t) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`omega` and :meth:`attitude` at times ``t`` (s), bit for bit, in one evaluation.

        A triaxial body far from a circular wobble (no nome series: generic bodies) evaluates its
        Jacobi functions once for both, instead of once each; elsewhere omega takes its own path
        (the nome series on a uniform grid, or closed forms) and this is the two calls.
        """
        t = np.asarray(t, dtype=float)
        self.check_times(t)
        state_at = getattr(self._impl, "state_at", None)
        if state_at is None or not self._jacobi_only():
            return self.omega(t), self.attitude(t)
        both = _blocked(state_at, t, 7)
        return to_user(both[..., :3], self._order, self._signs), self._attitude_to_user(both[..., 3:])

    def flip_times(self, t_start: float, t_end: float) -> np.ndarray:
        """Times (s) in [t_start, t_end] at which the intermediate component changes sign.

        Exact: t_j = (2K j - u0) / lambda with 2K / lambda and u0 / lambda in
        double-double. Empty where the motion has no flips.
        """
        if not self._flip:
            return np.empty(0)
        self.check_times(np.array([t_start, t_end], dtype=float))
        (h_hi, h_lo), (o_hi, o_lo) = self._flip
        if not np.isfinite(h_hi):  # the separatrix: a single crossing
            t = np.array([o_hi + o_lo])
            return t[(t >= t_start) & (t <= t_end)]
        j0, j1 = self._flip_indices(t_start, t_end)
        t = self._flip_time(np.arange(j0, j1 + 1.0))
        return t[(t >= t_start) & (t <= t_end)]

    def flip_count(self, t_start: float, t_end: float) -> int:
        """How many times :meth:`flip_times` lists in [t_start, t_end], without making the list (a body
        flipping every 7 s over 1e13 s has 1.4e12 of them: 11 TB as an array)."""
        if not self._flip:
            return 0
        if not np.isfinite(self._flip[0][0]):  # the separatrix: at most one crossing
            return int(self.flip_times(t_start, t_end).size)
        self.check_times(np.array([t_start, t_end], dtype=float))
        j0, j1 = self._flip_indices(t_start, t_end)
        if j1 < j0:
            return 0
        ends = self._flip_time(np.unique([j0, j1]))  # only the end indices can fall outside
        return int(j1 - j0 + 1) - int(np.sum((ends < t_start) | (ends > t_end)))

    def _flip_indices(self, t_start: float, t_end: float) -> tuple[float, float]:
        """The first and last j whose flip t_j may lie in [t_start, t_end] (one either side to spare)."""
        (h_hi, _), (o_hi, _) = self._flip
        return np.ceil((t_start - o_hi) / h_hi - 1e-9), np.floor((t_end - o_hi) / h_hi + 1e-9)

    def _flip_time(self, j: np.ndarray) -> np.ndarray:
        """t_j = (2K j - u0) / lambda in double-double, rounded (see :meth:`flip_times`)."""
        (h_hi, h_lo), (o_hi, o_lo) = self._flip
        p, e = two_prod(j, h_hi)
        return (p + o_hi) + (e + j * h_lo + o_lo)


_BLOCK = 8192


def _blocked(fn, t, width):
    """Evaluate ``fn`` on blocks of samples that stay in cache (large temporaries
    cost page faults: this is twice as fast for 10^4-10^6 samples)."""
    if t.size <= _BLOCK:
        return fn(t)
    flat = t.reshape(-1)
    out = np.empty((flat.size, width))
    for start in range(0, flat.size, _BLOCK):
        out[start : start + _BLOCK] = fn(flat[start : start + _BLOCK])
    return out.reshape(t.shape + (width,))


def _check(moments, omega0):
    moments = tuple(float(x) for x in np.asarray(moments, dtype=float).reshape(-1))
    omega0 = tuple(float(x) for x in np.asarray(omega0, dtype=float).reshape(-1))
    if len(moments) != 3 or not all(np.isfinite(moments)) or min(moments) <= 0:
        raise InputError("moments", moments, "three positive, finite principal moments (kg m2)")
    if min(moments) < TINY:
        # Subnormal moments keep a few digits, or none (1e-320 kg m2 ran and printed |L| = 3.168561e-313 to seven
        # digits): the smallest normal double, as the heavy top's I1 and I3 are refused.
        raise InputError(
            "moments", moments, f"three principal moments of at least {TINY:.4g} kg m2 each, the smallest normal double"
        )
    srt = sorted(moments)
    # A lamina has I1 + I2 = I3 exactly; allow the few ulps a unit conversion adds.
    if srt[0] + srt[1] < srt[2] * (1 - 8 * EPS):
        raise InputError(
            "moments", moments, "principal moments obeying the triangle inequality I1 + I2 >= I3 (a real body)"
        )
    if len(omega0) != 3 or not all(np.isfinite(omega0)):
        raise InputError("omega0", omega0, "three finite angular-velocity components (rad/s)")
    return moments, omega0


def _fits_double(x: Fraction) -> bool:
    """Whether the exact ``x`` rounds to a finite float64 (``float`` raises past the largest)."""
    try:
        return math.isfinite(float(x))
    except OverflowError:
        return False


def _check_energy_normal(omega0, w_user, two_e: Fraction) -> None:
    """Refuse rates whose kinetic energy is below the normal doubles (but not zero).

    The energy is reported (and written, with its drift, at every sample): below 2.2e-308 J it is
    subnormal or 0 in float64, printed as 0 J or with a few wrong digits, and the squares of such
    rates underflow wherever they are formed. The period of a motion this slow is also near or past
    the largest double (|omega| = 1e-310 rad/s of a body of 1 kg m2: 6e310 s). Tiny rates of a body
    with large moments are kept: the energy is the bound, not the rates.
    """
    tiny = Fraction(TINY)
    if 0 < two_e < 2 * tiny:
        w2 = sum(x * x for x in w_user)
        least = hp.sqrt(w2 * 2 * tiny / two_e)
        least = least.quantize(decimal.Decimal(1).scaleb(least.adjusted() - 2), rounding=decimal.ROUND_CEILING)
        raise InputError(
            "omega0",
            omega0,
            f"rates whose kinetic energy 1/2 sum I w^2 is 0 or at least {TINY:.4g} J, the "
            f"smallest normal double (here {hp.dec(two_e / 2):.3g} J): in this direction "
            f"|omega| >= {least:.3g} rad/s",
        )


def _check_period(omega0, period) -> None:
    """Refuse a periodic motion whose period (a Decimal, s) is past the largest double: it would be
    reported as inf, and as "never repeats", with flips "inf" apart."""
    if not math.isfinite(float(period)):
        raise InputError(
            "omega0",
            omega0,
            f"rates whose period of omega fits double precision (here {period:.3g} s, past "
            f"{HUGE:.4g} s): faster rates, or moments less nearly equal",
        )


@hp.isolated(hp.context)
def free_rotation(moments, omega0) -> FreeRotationModel:
    """The exact torque-free motion for principal ``moments`` (kg m^2) and ``omega0`` (rad/s).

    Parameters
    ----------
    moments : sequence of 3 float
        Principal moments in any order (kg m^2); positive, finite, with
        I1 + I2 >= I3 for the two smallest and the largest.
    omega0 : sequence of 3 float
        Body-frame angular velocity at t = 0 (rad/s), same axis order; zero
        is allowed (no motion).

    Returns
    -------
    FreeRotationModel

    Raises
    ------
    wobble.errors.InputError
        Non-finite, non-positive or subnormal moments, triangle inequality violated,
        non-finite omega0.
    """
    # Every Decimal operation of the set-up at hp.DIGITS digits (hp.isolated): a bare one takes the
    # caller's context (decimal's default 28 digits, or whatever a script has set): 28 digits leave
    # 1.5e-12 rad of attitude after 2^49.9 half-periods, and a script that had set 6 digits would get
    # attitudes 1.5 rad off at 1.7 s.
    moments, omega0 = _check(moments, omega0)
    order = tuple(int(i) for i in np.argsort(moments, kind="stable"))
    I = [Fraction(moments[i]) for i in order]
    w_user = [Fraction(x) for x in omega0]
    two_e = sum(Fraction(moments[i]) * w_user[i] ** 2 for i in range(3))
    l2 = sum((Fraction(moments[i]) * w_user[i]) ** 2 for i in range(3))
    if not (_fits_double(two_e) and _fits_double(l2)):
        raise InputError(
            "omega0",
            omega0,
            f"rates whose energy fits double precision: 2E = sum I w^2 and L^2 = sum (I w)^2 below {HUGE:.4g} in SI",
        )
    _check_energy_normal(omega0, w_user, two_e)
    energy = float(two_e / 2)
    big_l = float(hp.sqrt(l2)) if l2 > 0 else 0.0
    lw = [Fraction(moments[i]) * w_user[i] for i in range(3)]
    steady = all(lw[i] * w_user[k] - lw[k] * w_user[i] == 0 for i, k in ((0, 1), (1, 2), (0, 2)))
    common = dict(
        moments=moments,
        omega0=omega0,
        energy=energy,
        angular_momentum=big_l,
    )
    if steady:
        order, signs = (0, 1, 2), (1.0, 1.0, 1.0)
        norm2 = sum(x * x for x in w_user)
        half_rate = hp.to_dd(hp.sqrt(norm2) / 2) if norm2 > 0 else (0.0, 0.0)
        impl = _Steady(omega=omega0, half_rate=half_rate)
        return FreeRotationModel(
            regime="steady",
            m=0.0,
            m1=1.0,
            period=np.inf,
            time_between_flips=None,
            error_estimate={"omega_relative": 0.0, "attitude_rad": 4 * EPS},
            precession_rate=float(hp.sqrt(norm2)) if norm2 > 0 else 0.0,
            _order=order,
            _signs=signs,
            _impl=impl,
            **common,
        )
    if I[0] == I[1] or I[1] == I[2]:
        return _symmetric_model(moments, omega0, I, order, common, two_e, l2)
    return _elliptic_model(moments, omega0, I, order, common, two_e, l2)


def steady_axis(moments, omega0) -> tuple[int, str | None]:
    """The principal axis (0, 1, 2, in the order given) a steady spin ``omega0`` is about, and its kind:
    ``"largest"`` or ``"smallest"`` moment (stable) or ``"intermediate"`` (unstable: the least disturbance
    grows into the tennis-racket flip; Landau & Lifshitz section 37), or None where the axis's moment is
    shared with another axis (every axis of their plane is principal)."""
    axis = max(range(3), key=lambda k: abs(omega0[k]))
    moments = list(moments)
    if moments.count(moments[axis]) > 1:
        return axis, None
    order = sorted(range(3), key=lambda k: moments[k])
    return axis, ("smallest", "intermediate", "largest")[order.index(axis)]


def intermediate_axis_alignment(moments, omega0) -> float | None:
    """Largest |cos| of the angle between the intermediate principal axis and L over the motion.

    The intermediate axis e2 oscillates about the plane perpendicular to L, between
    angles arccos(c) and pi - arccos(c) from L, where c = I2 max|omega2| / L and, with
    D_k = sum_j I_j (I_j - I_k) omega_j^2 (Landau & Lifshitz section 37),

    * L^2 > 2 E I2 (about the major axis): I2 omega2max^2 = -D_3 / (I3 - I2),
    * L^2 < 2 E I2 (about the minor axis): I2 omega2max^2 = D_1 / (I2 - I1),
    * L^2 = 2 E I2 (separatrix): c = 1.

    The body turns over (a tennis-racket flip) when c is close to 1, and merely
    wobbles when c is small (Earth: c ~ 1e-6). Exact rational arithmetic: the
    D_k never suffer cancellation.

    Returns
    -------
    float or None
        c in [0, 1]; None for a symmetric body (no distinct intermediate axis) or no rotation.
    """
    moments, omega0 = _check(moments, omega0)
    order = np.argsort(moments, kind="stable")
    I = [Fraction(moments[i]) for i in order]
    w = [Fraction(omega0[i]) for i in order]
    if I[0] == I[1] or I[1] == I[2] or not any(w):
        return None
    l2 = sum((i * x) ** 2 for i, x in zip(I, w))

    def d(k):
        return sum(i * (i - I[k]) * x * x for i, x in zip(I, w))

    d2 = d(1)
    if d2 > 0:
        i2w2 = -d(2) / (I[2] - I[1])
    elif d2 < 0:
        i2w2 = d(0) / (I[1] - I[0])
    else:
        return 1.0
    return min(1.0, float(hp.sqrt(I[1] * i2w2 / l2)))


def _symmetric_model(moments, omega0, I, order, common, two_e, l2):
    # Oblate (I1 = I2 < I3): the symmetry axis is the largest; prolate
    # (I1 < I2 = I3): the smallest. Put it last in a right-handed frame.
    if I[0] == I[1]:
        frame = order
    else:
        frame = (order[1], order[2], order[0])  # cyclic: still proper
    frame, signs = _proper_frame(frame)
    w = to_sorted(np.asarray(omega0), frame, signs)
    wf = [Fraction(float(w[k])) for k in range(3)]  # exact: a signed permutation
    i_perp = Fraction(moments[frame[0]])
    i_axis = Fraction(moments[frame[2]])
    rate = (i_axis - i_perp) * wf[2] / i_perp
    big_l = hp.sqrt(l2)
    l_dir = tuple(float(hp.dec(Fraction(moments[frame[k]]) * wf[k]) / big_l) for k in range(3))
    impl = _Symmetric(
        i_perp=float(i_perp),
        i_axis=float(i_axis),
        amplitude=float(hp.sqrt(wf[0] ** 2 + wf[1] ** 2)),
        omega3=float(wf[2]),
        beta=float(np.arctan2(float(wf[1]), float(wf[0]))),
        rate=hp.to_dd(rate),
        half_space_rate=hp.to_dd(big_l / hp.dec(2 * i_perp)),
        l_dir=l_dir,
    )
    if rate != 0:
        _check_period(omega0, 2 * hp.PI / abs(hp.dec(rate)))
    period = float(2 * hp.PI / abs(hp.dec(rate))) if rate != 0 else np.inf
    return FreeRotationModel(
        regime="symmetric",
        m=0.0,
        m1=1.0,
        period=period,
        time_between_flips=None,
        error_estimate={"omega_relative": 4 * EPS, "attitude_rad": 8 * EPS},
        precession_rate=float(big_l / hp.dec(i_perp)),
        _order=frame,
        _signs=signs,
        _impl=impl,
        **common,
    )


#: Largest parameter m for the nome-series grid path: q ~ m/16, so the dropped
#: fifth harmonics and q^2 corrections are below 4e-17 of the amplitudes.
_FOURIER_MAX_M = 1e-7


def _nome_series(m, kdec):
    """(pi/(2K), sn1, sn3, cn1, cn3, dn0, dn2): DLMF 22.11.1-3 to first order in q, at 50 digits.

    q = exp(-pi K'/K) with K' = K(1 - m); sn = (2 pi/(K k)) sum q^(n+1/2) sin((2n+1)v)/(1 - q^(2n+1)),
    cn likewise with cos and 1 + q^(2n+1), dn = pi/(2K) + (2 pi/K) sum_{n>=1} q^n cos(2nv)/(1 + q^(2n)).
    """
    with decimal.localcontext(hp.context()):
        k_prime = hp.agm_k(m)  # K(1 - m): agm_k takes the complement of its parameter
        q = (-hp.PI * k_prime / kdec).exp()
        k = hp.sqrt(m)
        lead = 2 * hp.PI / (kdec * k)
        rq = q.sqrt()
        coeffs = (
            hp.PI / (2 * kdec),
            lead * rq / (1 - q),
            lead * rq * q / (1 - q**3),
            lead * rq / (1 + q),
            lead * rq * q / (1 + q**3),
            hp.PI / (2 * kdec),
            2 * hp.PI / kdec * q / (1 + q * q),
        )
    return tuple(float(x) for x in coeffs)


def _check_separatrix_distance(name: str, value, m1) -> None:
    """Refuse a state so near the separatrix that 1 - m leaves double precision.

    On the separatrix itself (1 - m = 0) the motion is tanh/sech and exact; between 0 and
    :data:`wobble.numerics.elliptic.M1_MIN` the period and the attitude integrals are out
    of the float range (the state is within ~1e-75 of the intermediate axis's separatrix).
    """
    if 0 < m1 < ell.M1_MIN:  # m1 exact (a Fraction): an underflowing 1 - m is caught too
        raise InputError(
            name,
            value,
            f"a state farther from the separatrix: 1 - m = {hp.dec(m1):.3g} is below {ell.M1_MIN:g} (a state within "
            "~1e-75 of the separatrix), where the elliptic integrals leave double precision; the exact "
            "separatrix (1 - m = 0) and anything farther than 1e-75 are computed",
        )


def _circulation(omega0, I, order):
    """The frame of the solution and the axis omega circulates about: (frame, signs, exact omega in the frame,
    D_j = 2 E I_j - L^2, the axes (a, b, c), the regime)."""
    frame, signs = _proper_frame(order)
    w = to_sorted(np.asarray(omega0), frame, signs)
    wf = [Fraction(float(x)) for x in w]
    # D_j = 2 E I_j - L^2 = sum_i I_i w_i^2 (I_j - I_i): exact, no cancellation.
    d = [sum(I[i] * wf[i] ** 2 * (I[j] - I[i]) for i in range(3)) for j in range(3)]
    if d[1] > 0:
        return frame, signs, wf, d, (2, 1, 0), "minor-axis"
    # L^2 >= 2 E I2: omega circulates about the axis of largest moment.
    regime = "major-axis" if d[1] < 0 else "separatrix"
    if regime == "separatrix" and wf[0] < 0:
        # On the separatrix omega_a = A_a sech u never changes sign (K is infinite: no u0 = 2K - f
        # reaches omega_a < 0). The rotation by pi about the intermediate axis, omega -> (-w_a, w_b, -w_c),
        # maps Euler's equations to themselves and the attitude q to (q_w, R q_xyz): the same motion
        # is the solution in the model frame with the signs of axes a and c turned (still proper).
        signs = (-signs[0], signs[1], -signs[2])
        w = to_sorted(np.asarray(omega0), frame, signs)
        wf = [Fraction(float(x)) for x in w]
    return frame, signs, wf, d, (0, 1, 2), regime


def _initial_phase(wf, amp, sign_bc: float, axes, K) -> float:
    """Initial phase u0 from sn, cn, dn at t = 0 (all known from omega0 without cancellation):
    |u0| <= K via Carlson's R_F, else through 2K - u."""
    from scipy.special import elliprf

    a, b, c = axes
    c0 = float(wf[a]) / amp[0]
    s0 = float(sign_bc * float(wf[b])) / amp[1]
    d0 = abs(float(wf[c])) / amp[2]
    c0, s0 = float(np.clip(c0, -1, 1)), float(np.clip(s0, -1, 1))
    f = s0 * float(elliprf(c0 * c0, d0 * d0, 1.0))
    return f if c0 >= 0 else (1.0 if s0 >= 0 else -1.0) * 2 * K[0] - f


def _mean_rate(omega0, I, axes, amp2, nu, lam, big_l, kdec, m1, u0) -> dict:
    """The mean rate of the attitude angle, Pi_c / K, the period, the half period and the flip phase
    (docs/free-rotation.md, "Attitude"); on the separatrix (``kdec`` None) the period is infinite."""
    ia, ic = I[axes[0]], I[axes[2]]
    if kdec is None:
        return dict(
            mean=big_l / hp.dec(ic),
            pi_over_k=0.0,
            period=np.inf,
            flip=((np.inf, 0.0), hp.to_dd(-hp.dec(u0) / lam)),
            tbf=None,
        )
    pi_c = hp.cel(hp.sqrt(m1), 1 + nu, 1, 1)
    mean = (
        big_l / hp.dec(ic)
        + (
            hp.dec(ic - ia) * big_l * pi_c / hp.dec(ia * ic)
            - hp.dec(ic - ia) * hp.sqrt(amp2[2]) * hp.PI / (2 * hp.dec(ia) * hp.sqrt(1 + nu))
        )
        / kdec
    )
    _check_period(omega0, 4 * kdec / lam)
    half = 2 * kdec / lam
    return dict(
        mean=mean,
        pi_over_k=float(pi_c / kdec),
        period=float(4 * kdec / lam),
        flip=(hp.to_dd(half), hp.to_dd(-hp.dec(u0) / lam)),
        tbf=float(half),
    )


def _elliptic_model(moments, omega0, I, order, common, two_e, l2):
    frame, signs, wf, d, (a, b, c), regime = _circulation(omega0, I, order)
    amp2 = (
        d[c] / (I[a] * (I[c] - I[a])),
        d[c] / (I[b] * (I[c] - I[b])),
        -d[a] / (I[c] * (I[c] - I[a])),
    )
    lam2 = (I[c] - I[b]) * (-d[a]) / (I[0] * I[1] * I[2])
    m = (I[b] - I[a]) * d[c] / ((I[c] - I[b]) * (-d[a]))
    m1 = (I[c] - I[a]) * (-d[b]) / ((I[c] - I[b]) * (-d[a]))
    assert m + m1 == 1
    _check_separatrix_distance("omega0", omega0, m1)
    nu = I[c] * (I[b] - I[a]) / (I[a] * (I[c] - I[b]))
    amp = tuple(float(hp.sqrt(x)) for x in amp2)
    sign_bc = 1.0 if wf[c] > 0 else -1.0
    lam = hp.sqrt(lam2)
    big_l = hp.sqrt(l2)
    kdec = hp.agm_k(m1) if m1 > 0 else None
    K = hp.to_dd(kdec) if kdec is not None else (np.inf, 0.0)
    # The fold K - |r| uses the same K as the reduction of the phase.
    levels = ell.landen_levels(float(m), float(m1), K=K[0] if kdec is not None else None)
    u0 = _initial_phase(wf, amp, sign_bc, (a, b, c), K)
    # Attitude constants (docs/free-rotation.md, "Attitude").
    ic, ia = I[c], I[a]
    c_pi = float(hp.dec(ic - ia) * big_l / (hp.dec(ia * ic) * lam))
    c_g = float(hp.dec(ic - ia) * hp.sqrt(amp2[2]) / (hp.dec(ia) * lam * hp.sqrt(1 + nu)))
    rates = _mean_rate(omega0, I, (a, b, c), amp2, nu, lam, big_l, kdec, m1, u0)
    impl = _Elliptic(
        a=a,
        b=b,
        c=c,
        amp=amp,
        sign_bc=sign_bc,
        m=float(m),
        m1=float(m1),
        lam=hp.to_dd(lam),
        K=K,
        u0=u0,
        moments=tuple(float(x) for x in I),
        L=float(big_l),
        nu=float(nu),
        c_pi=c_pi,
        c_g=c_g,
        pi_over_k=rates["pi_over_k"],
        half_prec_rate=hp.to_dd(rates["mean"] / 2),
        levels=levels,
        fourier=_nome_series(m, kdec) if (kdec is not None and 0 < m <= _FOURIER_MAX_M) else None,
    )
    kf = K[0] if np.isfinite(K[0]) else 1.0
    est = {"omega_relative": 16 * EPS * (1 + kf), "attitude_rad": 64 * EPS * (1 + kf)}
    # Omega_psi is the mean rate of the attitude angle measured from the shortest-arc frame,
    # which turns once per period 4K/lambda about L (forwards circulating about the major
    # axis, backwards about the minor one): L&L's mean phidot is Omega_psi +- 2 pi / period.
    circulation = 0
    if kdec is not None:
        circulation = (1 if regime == "major-axis" else -1) * hp.PI * lam / (2 * kdec)
    return FreeRotationModel(
        regime=regime,
        m=float(m),
        m1=float(m1),
        period=rates["period"],
        time_between_flips=rates["tbf"],
        error_estimate=est,
        precession_rate=float(rates["mean"] + circulation),
        _order=frame,
        _signs=signs,
        _impl=impl,
        _flip=rates["flip"],
        **common,
    )


def symmetric_from_energy(i_perp: float, i_axis: float, energy: float, l2: float) -> tuple[float, float]:
    """Amplitude A and axial rate omega3 (rad/s) of a symmetric body from T and L^2 (notes p. 69).

    From T = 1/2 I1 A^2 + 1/2 I3 omega3^2 and L^2 = I1^2 A^2 + I3^2 omega3^2:
    A^2 = (2 T I3 - L^2) / (I1 (I3 - I1)), omega3^2 = (L^2 - 2 T I1) / (I3 (I3 - I1)).
    omega3 is returned non-negative (the sign of the spin is not fixed by T and L^2).

    Raises
    ------
    wobble.errors.InputError
        I1 = I3 (a sphere: A and omega3 are not separately defined), or T and
        L^2 not compatible (2 T min(I) <= L^2 <= 2 T max(I) violated).
    """
    i1, i3 = Fraction(i_perp), Fraction(i_axis)
    t2, l2f = 2 * Fraction(energy), Fraction(l2)
    if i1 == i3:
        raise InputError("moments", (i_perp, i_axis), "I1 != I3 (a sphere has no precession)")
    a2 = (t2 * i3 - l2f) / (i1 * (i3 - i1))
    w2 = (l2f - t2 * i1) / (i3 * (i3 - i1))
    if a2 < 0 or w2 < 0:
        raise InputError("energy, l2", (energy, l2), "2 T min(I1, I3) <= L^2 <= 2 T max(I1, I3)")
    return float(hp.sqrt(a2)), float(hp.sqrt(w2))
