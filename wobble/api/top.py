"""The heavy symmetric top with units: :class:`HeavyTop` (Quantities in, xarray out).

The physics is :mod:`wobble.models.top` (Goldstein, Poole & Safko 2002, sec. 5.7); this module
converts units once on the way in and once on the way out and lays the motion out
as a CF Dataset.

Example
-------
>>> import astropy.units as u
>>> from wobble import HeavyTop
>>> top = HeavyTop(I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J,
...                theta0=60 * u.deg, omega3=10 * u.rad / u.s)
>>> top.nutation
'cusps'
>>> print(f"{top.nutation_period:.6f}")
1.304630 s
>>> ds = top.to_dataset(t_end=10 * u.s, samples=101)
>>> ds.theta.attrs["units"], ds.omega.dims
('rad', ('time', 'axis'))
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from astropy import units as u

from wobble.api.sampling import sample_times
from wobble.api.units import as_given, plain_array, to_si
from wobble.errors import InputError
from wobble.io import cf
from wobble.io.json_keys import deprecate, error_estimate_renames
from wobble.models import top as _top
from wobble.models.torques import STANDARD_GRAVITY as _STANDARD_GRAVITY

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["HeavyTop", "STANDARD_GRAVITY", "BYTES_PER_SAMPLE"]

MOMENT_UNIT = u.kg * u.m**2
_RATE = u.rad / u.s
_LMOM = u.kg * u.m**2 / u.s
STANDARD_GRAVITY = _STANDARD_GRAVITY * u.m / u.s**2  # 9.80665 m / s2 (CGPM 1901), the models' one number
# Float64 values held per sample while a Dataset is built (outputs and temporaries), bytes.
BYTES_PER_SAMPLE = 8 * 120
# The defaults of the optional initial state: zero, so not converted again for every top.
_ZERO_RATE = 0 * _RATE
_ZERO_ANGLE = 0 * u.rad


def _as_quantity(value):
    """A list of Quantities (e.g. [top.theta_min, top.theta_max]) as one Quantity array."""
    if isinstance(value, (list, tuple)) and value and all(isinstance(v, u.Quantity) for v in value):
        try:
            return u.Quantity(value)
        except u.UnitsError:
            return value
    return value


def _angle(value, name, shape=()):
    """An angle in rad; a scalar unless ``shape`` is None (theta0 = [60, 70] deg raised a bare ValueError)."""
    if value is _ZERO_ANGLE:
        return 0.0
    return to_si(_as_quantity(value), name, u.rad, shape=shape)


def _rate(value, name, shape=None):
    if value is _ZERO_RATE:
        return 0.0
    # No dimensionless_angles(): it reads 1/s (and Hz, cycles per second) as rad/s, a factor 2 pi off.
    return to_si(value, name, _RATE, shape=shape)


def _cosines(values, name="u_values"):
    """u = cos theta: plain numbers or a dimensionless Quantity (a unit, 0.1 m, was dropped) in [-1, 1]
    (phidot(2.0) gave 2.5 rad/s for a cosine no angle has)."""
    allowed = "u = cos(theta): plain numbers in [-1, 1]"
    out = plain_array(values, name, allowed)
    if not np.all((out >= -1.0) & (out <= 1.0)):  # NaN fails both comparisons
        bad = out[~((out >= -1.0) & (out <= 1.0))]
        raise InputError(name, bad.flat[0] if out.ndim else float(out), allowed)
    return out


def _from_body(body):
    """I1, I3 about the tip (kg m2), M (kg), l (m) from a duck-typed rigid body.

    The body needs ``mass``, ``center_of_mass``, ``reference_point`` (the tip) and
    ``tensor`` (about the reference point): the symmetry axis is the line from the
    tip to the centre of mass, and the tensor must be symmetric about it.
    """
    try:
        mass = to_si(body.mass, "body.mass", u.kg, positive=True, shape=())
        com = to_si(body.center_of_mass, "body.center_of_mass", u.m, shape=(3,))
        ref = to_si(body.reference_point, "body.reference_point", u.m, shape=(3,))
        tensor = to_si(body.tensor, "body.tensor", MOMENT_UNIT, shape=(3, 3))
    except AttributeError as exc:
        raise InputError(
            "body",
            type(body).__name__,
            "a rigid body with mass, center_of_mass, reference_point and tensor (e.g. "
            "RigidBody.spinning_top(...).shifted_to('origin'))",
        ) from exc
    r = com - ref
    length = float(np.linalg.norm(r))
    if not length > 0:
        raise InputError(
            "body",
            "centre of mass at the pivot",
            "a top whose centre of mass is off the fixed point (use FreeRotation otherwise)",
        )
    n = r / length
    i3 = float(n @ tensor @ n)
    i1 = 0.5 * (float(np.trace(tensor)) - i3)
    model = i1 * (np.eye(3) - np.outer(n, n)) + i3 * np.outer(n, n)
    scale = float(np.max(np.abs(tensor)))
    if float(np.max(np.abs(tensor - model))) > 1e-9 * scale:
        raise InputError(
            "body",
            "inertia tensor not symmetric about the tip-to-centre-of-mass line",
            "a symmetric top: I1 = I2 about the axis from the tip (reference_point) to the centre of mass",
        )
    return i1, i3, mass, length


# The heavy top's CF variables (wobble.io.cf, table "top"): dims and attributes, read once.
_TOP_VARIABLES = {name: (spec.dims, spec.attrs()) for name, spec in cf.TOP.items()}


def mean_rate_text(rate: float, bound: float | None) -> str:
    """The mean precession rate for a person, to the digits its error bound leaves: all seven where the bound
    is a rounding, fewer where the set-up's terms cancelled (loops under weak gravity), and 'not resolved'
    where none is left (its sign then is not known either)."""
    from wobble.io.text import number, with_uncertainty_g
    from wobble.models.top_setup import MEAN_RATE_DIGITS as digits_kept

    if bound is None or not bound > 1e-14 * abs(rate):
        return f"{number(rate)} rad/s"
    if bound >= abs(rate):
        return f"not resolved: |mean| below {bound:.2g} rad/s (its terms cancel past the set-up's {digits_kept} digits)"
    return f"{with_uncertainty_g(rate, bound)} rad/s (its terms cancel in the set-up's {digits_kept} digits)"


class HeavyTop:
    """The heavy symmetric top with one point fixed: analysis and exact motion.

    Parameters
    ----------
    I1, I3 : astropy.units.Quantity, optional
        Transverse and axial moments of inertia about the fixed tip (kg m2).
    mgl : astropy.units.Quantity, optional
        M g l (J): weight times the distance from the tip to the centre of mass.
        Alternatively give ``M`` (mass) and ``l`` (length), with ``g`` (default
        standard gravity 9.80665 m/s2); then I1 >= M l^2 is checked.
    body : object, optional
        Instead of I1, I3, M, l: a rigid body about its tip exposing ``mass``,
        ``center_of_mass``, ``reference_point`` and ``tensor`` (Quantities), e.g.
        ``RigidBody.spinning_top(...).shifted_to("origin")``.
    theta0 : astropy.units.Quantity
        Initial tilt of the symmetry axis from the upward vertical, in [0, 180] deg
        (any angular unit).
    thetadot0, phidot0 : astropy.units.Quantity
        Initial nutation and precession rates (angle / time; default 0).
    omega3, psidot0 : astropy.units.Quantity
        The spin: exactly one of omega3 (about the symmetry axis) and psidot0.
    phi0, psi0 : astropy.units.Quantity
        Initial precession and spin angles (default 0).

    Raises
    ------
    wobble.errors.InputError
        Missing or inconsistent parameters, wrong units, I1 <= 0, I3 <= 0, I3 > 2 I1,
        I1 < M l^2, theta0 outside [0, pi], rates whose energy overflows a double; the message
        names the parameter.

    Notes
    -----
    Goldstein, Poole & Safko 2002, sec. 5.7, and docs/heavy-top.md: the analysis (p_psi = I1 a, p_phi = I1 b,
    E', alpha, beta, V'(theta), the cubic f(u) and its roots, the nutation class,
    regular precession, the sleeping top) and the exact motion by Jacobi elliptic

    Examples
    --------
    Started precessing backwards, the top's axis traces loops:

    >>> import wobble
    >>> from astropy import units as u
    >>> top = wobble.HeavyTop(I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J,
    ...                       theta0=60 * u.deg, phidot0=-0.3 * u.rad / u.s, omega3=10 * u.rad / u.s)
    >>> print(top.nutation, f"{top.theta_min.to(u.deg):.1f} to {top.theta_max.to(u.deg):.1f}")
    loops 60.0 deg to 70.3 deg
    >>> print(f"nutation period {top.nutation_period:.3f}")
    nutation period 1.295 s
    """

    def __init__(
        self,
        I1=None,
        I3=None,
        *,
        mgl=None,
        M=None,
        l=None,
        g=None,
        body=None,
        theta0=None,
        thetadot0=_ZERO_RATE,
        phidot0=_ZERO_RATE,
        psidot0=None,
        omega3=None,
        phi0=_ZERO_ANGLE,
        psi0=_ZERO_ANGLE,
    ):
        with as_given(I1=I1, I3=I3, mgl=mgl, M=M, l=l, g=g):
            i1, i3, mgl_si, ml2 = self._parameters(I1, I3, mgl, M, l, g, body)
        if theta0 is None:
            raise InputError("theta0", None, "the initial tilt, an angle in [0, 180] deg")
        if (omega3 is None) == (psidot0 is None):
            raise InputError("omega3, psidot0", (omega3, psidot0), "exactly one of omega3 and psidot0 (angle / time)")
        th = _angle(theta0, "theta0")
        if not 0.0 <= th <= np.pi * (1 + 1e-15):
            raise InputError("theta0", theta0, "an angle in [0, 180] deg (0 = upright, 180 = hanging down)")
        th = min(th, np.pi)
        kwargs = dict(
            thetadot0=_rate(thetadot0, "thetadot0", ()),
            phidot0=_rate(phidot0, "phidot0", ()),
            phi0=_angle(phi0, "phi0"),
            psi0=_angle(psi0, "psi0"),
        )
        if omega3 is not None:
            kwargs["omega3"] = _rate(omega3, "omega3", ())
        else:
            kwargs["psidot0"] = _rate(psidot0, "psidot0", ())
        with as_given(I1=I1, I3=I3, mgl=mgl, omega3=omega3, psidot0=psidot0, thetadot0=thetadot0, phidot0=phidot0):
            self._model = _top.heavy_top(i1, i3, mgl_si, th, ml2=ml2, **kwargs)
        # The start as typed, in deg: a turning point at the start reads 60 deg, not the 59.99999999999999 deg
        # that the round trip through rad gives (None where theta0 was clipped to pi).
        typed = _as_quantity(theta0)
        self._theta0_deg = typed.to(u.deg) if th == typed.to_value(u.rad) else None

    @classmethod
    def from_state(cls, omega0, q0, I1=None, I3=None, *, mgl=None, M=None, l=None, g=None, body=None):
        """A top from its body angular velocity ``omega0`` (angle/time, 3) and attitude ``q0``.

        ``q0`` is a unit quaternion (w, x, y, z), body -> space, body z the symmetry axis
        (tip to centre of mass), gravity along -z in space.
        """
        i1, i3, mgl_si, ml2 = cls._parameters(I1, I3, mgl, M, l, g, body)
        w = np.atleast_1d(_rate(omega0, "omega0"))
        self = cls.__new__(cls)
        q = plain_array(q0, "q0", "a unit quaternion (w, x, y, z) of plain numbers")
        self._model = _top.heavy_top_from_state(i1, i3, mgl_si, w, q, ml2=ml2)
        return self

    @staticmethod
    def _parameters(I1, I3, mgl, M, l, g, body):
        ml2 = None
        if body is not None:
            if any(v is not None for v in (I1, I3, M, l)):
                raise InputError("body", "body with I1/I3/M/l", "either body or I1, I3 with mgl (or M, l), not both")
            i1, i3, mass, length = _from_body(body)
            gg = to_si(STANDARD_GRAVITY if g is None else g, "g", u.m / u.s**2, nonnegative=True, shape=())
            if mgl is not None:
                raise InputError(
                    "mgl", mgl, "no mgl with body (it comes from the body's mass and centre of mass, and g)"
                )
            return i1, i3, mass * gg * length, None
        if I1 is None or I3 is None:
            raise InputError("I1, I3", (I1, I3), "both moments about the tip (kg m2), or body=")
        i1 = to_si(I1, "I1", MOMENT_UNIT, shape=())
        i3 = to_si(I3, "I3", MOMENT_UNIT, shape=())
        if mgl is not None:
            if M is not None or l is not None:
                raise InputError("mgl", mgl, "either mgl or M and l (with g), not both")
            mgl_si = to_si(mgl, "mgl", u.J, shape=())
        elif M is not None and l is not None:
            mass = to_si(M, "M", u.kg, nonnegative=True, shape=())
            length = to_si(l, "l", u.m, nonnegative=True, shape=())
            gg = to_si(STANDARD_GRAVITY if g is None else g, "g", u.m / u.s**2, nonnegative=True, shape=())
            mgl_si = mass * gg * length
            ml2 = mass * length * length
        else:
            raise InputError("mgl", None, "M g l (J), or the mass M and the tip-to-centre-of-mass length l")
        _top.check_top_parameters(i1, i3, mgl_si, ml2)
        return i1, i3, mgl_si, ml2

    # -- the analysis ---------------------------------------------------------
    @property
    def model(self) -> _top.HeavyTopModel:
        """The SI model underneath (floats and arrays, no units)."""
        return self._model

    @property
    def I1(self) -> u.Quantity:
        """Transverse moment about the tip (kg m2)."""
        return self._model.I1 << MOMENT_UNIT

    @property
    def I3(self) -> u.Quantity:
        """Axial moment (kg m2)."""
        return self._model.I3 << MOMENT_UNIT

    @property
    def mgl(self) -> u.Quantity:
        """M g l (J)."""
        return self._model.mgl << u.J

    @property
    def omega3(self) -> u.Quantity:
        """Spin about the symmetry axis, constant (rad/s)."""
        return self._model.omega3 << _RATE

    @property
    def a(self) -> u.Quantity:
        """a = p_psi / I1 = I3 omega3 / I1 (1/s)."""
        return self._model.a << (1 / u.s)

    @property
    def b(self) -> u.Quantity:
        """b = p_phi / I1 (1/s)."""
        return self._model.b << (1 / u.s)

    @property
    def p_psi(self) -> u.Quantity:
        """Conserved momentum p_psi = I3 omega3 (kg m2/s)."""
        return self._model.p_psi << _LMOM

    @property
    def p_phi(self) -> u.Quantity:
        """Conserved momentum p_phi = I1 b (kg m2/s), the vertical angular momentum."""
        return self._model.p_phi << _LMOM

    @property
    def energy(self) -> u.Quantity:
        """Total energy E = T + M g l cos theta (J)."""
        return self._model.energy << u.J

    @property
    def energy_prime(self) -> u.Quantity:
        """E' = E - I3 omega3^2 / 2 (J)."""
        return self._model.energy_prime << u.J

    @property
    def alpha(self) -> u.Quantity:
        """alpha = 2 E' / I1 (1/s2)."""
        return self._model.alpha << (1 / u.s**2)

    @property
    def beta(self) -> u.Quantity:
        """beta = 2 M g l / I1 (1/s2)."""
        return self._model.beta << (1 / u.s**2)

    @property
    def roots(self) -> tuple[float, float, float]:
        """(u1, u2, u3): roots of f(u), u1 <= u2 <= 1 <= u3 (u = cos theta)."""
        m = self._model
        return m.u1, m.u2, m.u3

    @property
    def theta_min(self) -> u.Quantity:
        """Smallest tilt of the motion (turning angle at u2), in deg."""
        return self._turning_angle(self._model.theta_min)

    @property
    def theta_max(self) -> u.Quantity:
        """Largest tilt of the motion (turning angle at u1), in deg."""
        return self._turning_angle(self._model.theta_max)

    def _turning_angle(self, theta: float) -> u.Quantity:
        if getattr(self, "_theta0_deg", None) is not None and theta == self._model.theta0:
            return self._theta0_deg.copy()
        return (theta * u.rad).to(u.deg)

    @property
    def nutation(self) -> str:
        """'undulating', 'cusps', 'loops', 'regular' or 'sleeping'."""
        return self._model.nutation

    @property
    def parameter(self) -> float:
        """m = (u2 - u1)/(u3 - u1), the parameter of the Jacobi functions."""
        return self._model.m

    @property
    def complementary_parameter(self) -> float:
        """1 - m = (u3 - u2)/(u3 - u1), formed without cancellation."""
        return self._model.m1

    @property
    def nutation_period(self) -> u.Quantity:
        """4 K(m) / sqrt(beta (u3 - u1)) (s); for regular precession or a sleeping top, of small nutations."""
        return self._model.nutation_period << u.s

    @property
    def max_time(self) -> u.Quantity:
        """The largest time from t = 0, either way, at which the motion is given (s): 2^50 - 1 nutation
        periods for a nutating top, 2^50 - 1 turns of its fastest phase when theta is constant (the
        phases are reduced exactly up to there), inf for a top at rest."""
        return self._model.max_time << u.s

    @property
    def mean_precession_rate(self) -> u.Quantity:
        """phidot averaged over a nutation period (rad/s)."""
        return self._model.mean_precession_rate << _RATE

    @property
    def mean_spin_rate(self) -> u.Quantity:
        """psidot averaged over a nutation period (rad/s)."""
        return self._model.mean_spin_rate << _RATE

    @property
    def sleeping_stable(self) -> bool:
        """I3^2 omega3^2 > 4 M g l I1: a sleeping top with this spin is stable."""
        return self._model.sleeping_stable

    @property
    def error_estimate(self) -> dict:
        """Error bounds: theta and attitude (rad), turning points and period (relative)."""
        return dict(self._model.error_estimate)

    def effective_potential(self, theta) -> u.Quantity:
        """V'(theta) = M g l cos theta + (I1/2)((b - a cos theta)/sin theta)^2 (J)."""
        return self._model.effective_potential(_angle(theta, "theta", shape=None)) << u.J

    def f(self, u_values) -> u.Quantity:
        """f(u) = udot^2 (1/s2) at u = cos theta (plain numbers in [-1, 1])."""
        return self._model.f(_cosines(u_values)) << u.s**-2  # a unit: 1 / u.s**2 is a Quantity, and a float << it fails

    def phidot(self, u_values) -> u.Quantity:
        """Precession rate (b - a u)/(1 - u^2) at u = cos theta (rad/s)."""
        return self._model.phidot_of_u(_cosines(u_values)) << _RATE

    def psidot(self, u_values) -> u.Quantity:
        """Spin rate I1 a / I3 - u phidot at u = cos theta (rad/s)."""
        return self._model.psidot_of_u(_cosines(u_values)) << _RATE

    def regular_precession_rates(self, theta=None) -> tuple[u.Quantity, u.Quantity]:
        """(slow, fast) steady precession rates at tilt ``theta`` (default theta0), rad/s."""
        th = None if theta is None else _angle(theta, "theta")
        slow, fast = self._model.regular_precession_rates(th)
        return slow << _RATE, fast << _RATE

    def to_dict(self) -> dict:
        """A JSON-ready summary in SI (keys end in their unit; turning angles also in degrees)."""
        m = self._model

        def fin(x):
            return float(x) if np.isfinite(x) else None

        try:
            slow, fast = m.regular_precession_rates()
            reg = {"slow_rad_per_s": fin(slow), "fast_rad_per_s": fin(fast)}
        except InputError:
            reg = None
        err = dict(m.error_estimate)
        out = {
            "nutation_class": m.nutation,
            "u1": m.u1,
            "u2": m.u2,
            "u3": fin(m.u3),
            "theta_min_deg": float(np.degrees(m.theta_min)),
            "theta_max_deg": float(np.degrees(m.theta_max)),
            "theta_min_rad": m.theta_min,
            "theta_max_rad": m.theta_max,
            "nutation_period_s": fin(m.nutation_period),
            "mean_precession_rate_rad_per_s": m.mean_precession_rate,
            "mean_spin_rate_rad_per_s": m.mean_spin_rate,
            "sleeping_stable": bool(m.sleeping_stable),
            "parameter_m": m.m,
            "complementary_parameter_1_minus_m": m.m1,
            "a_per_s": m.a,
            "b_per_s": m.b,
            "alpha_per_s2": m.alpha,
            "beta_per_s2": m.beta,
            "energy_J": m.energy,
            "energy_prime_J": m.energy_prime,
            "p_phi_kg_m2_per_s": m.p_phi,
            "p_psi_kg_m2_per_s": m.p_psi,
            "omega3_rad_per_s": m.omega3,
            "psidot0_rad_per_s": m.psidot0,
            "I1_kg_m2": m.I1,
            "I3_kg_m2": m.I3,
            "mgl_J": m.mgl,
            "theta0_rad": m.theta0,
            "thetadot0_rad_per_s": m.thetadot0,
            "phidot0_rad_per_s": m.phidot0,
            "regular_precession_at_theta0": reg,
            **{f"error_estimate_{k}": v for k, v in err.items()},
            "error_estimate": {},
        }
        # The nested error_estimate object is the deprecated form: it keeps the keys it had; the mean rate's
        # bound is newer than it and is given flat only.
        old = [k for k in err if k != "mean_precession_rate_rad_per_s"]
        return deprecate(out, {"nutation": "nutation_class", **error_estimate_renames(old)})

    def summary(self) -> str:
        """The motion in words: the nutation class, the turning angles and the periods."""
        from wobble.io.text import duration, number

        m = self._model
        return (
            f"{m.nutation} nutation between theta = {number(np.degrees(m.theta_min))} and "
            f"{number(np.degrees(m.theta_max))} deg, period {duration(m.nutation_period)}; mean precession "
            f"{mean_rate_text(m.mean_precession_rate, m.error_estimate.get('mean_precession_rate_rad_per_s'))}"
        )

    def __repr__(self) -> str:
        return f"HeavyTop(nutation={self._model.nutation!r}, I1={self.I1}, I3={self.I3}, mgl={self.mgl})"

    # -- the motion --------------------------------------------------------------
    def motion(self, t) -> xr.Dataset:
        """The exact motion at times ``t`` (a time Quantity, 1-D) as a CF Dataset (see :meth:`to_dataset`).

        From 1024 times on every output comes from the verified Fourier series of the motion
        in one pass (compiled from 8192 on); the first call builds the series (about a
        millisecond), later calls reuse it.
        """
        return self.to_dataset(t)

    def to_dataset(self, t=None, *, t_end=None, samples: int | None = None) -> xr.Dataset:
        """The motion as a CF Dataset at times ``t`` or at ``samples`` times in [0, t_end].

        Returns
        -------
        xarray.Dataset
            ``time`` (s, CF units ``seconds since 2000-01-01 12:00:00``); ``theta``,
            ``phi``, ``psi`` (rad; phi and psi wrapped to [-pi, pi]), ``thetadot``,
            ``phidot``, ``psidot`` (rad s-1); ``omega(time, axis)`` in the body frame;
            ``attitude(time, component)`` (unit quaternion body -> space);
            ``symmetry_axis(time, inertial_axis)`` (X, Y, Z with Z up: the trace on the unit sphere);
            ``energy``, ``p_phi``, ``p_psi`` recomputed from the motion and their
            drifts from the initial values.

        Raises
        ------
        wobble.errors.InputError
            Neither or both of ``t`` and ``t_end``; bad ``samples``; a request that
            would not fit in memory; times beyond :attr:`max_time`.
        """
        ts = self._times(t, t_end, samples)
        try:
            motion = self._model.motion(ts)
        except InputError as exc:
            if exc.parameter != "t" or t is not None:
                raise
            raise InputError("t_end", t_end, exc.allowed) from None
        return self._dataset(ts, motion)

    def _times(self, t, t_end, samples):
        return sample_times(t, t_end, samples, BYTES_PER_SAMPLE)

    def _dataset(self, ts, mo) -> xr.Dataset:
        from wobble.api.dataset import build

        m = self._model

        def var(name, data):  # cf.variable("top", name, data), from the registry's entries read once
            dims, attrs = _TOP_VARIABLES[name]
            return dims, data, dict(attrs)

        data = {
            "theta": var("theta", mo.theta),
            "phi": var("phi", mo.phi),
            "psi": var("psi", mo.psi),
            "thetadot": var("thetadot", mo.thetadot),
            "phidot": var("phidot", mo.phidot),
            "psidot": var("psidot", mo.psidot),
            "omega": var("omega", mo.omega),
            "attitude": var("attitude", mo.quaternion),
            "symmetry_axis": var("symmetry_axis", mo.axis),
            "energy": var("energy", mo.energy),  # recomputed from omega and q, and the drifts from t = 0
            "energy_drift": var("energy_drift", mo.energy_drift),
            "p_phi": var("p_phi", mo.p_phi),
            "p_phi_drift": var("p_phi_drift", mo.p_phi_drift),
            "p_psi": var("p_psi", mo.p_psi),
            "p_psi_drift": var("p_psi_drift", mo.p_psi_drift),
        }
        coords = {
            "time": cf.time_coordinate(ts),
            "axis": cf.label_coordinate("axis"),
            "inertial_axis": cf.label_coordinate("inertial_axis"),
            "component": cf.label_coordinate("component"),
        }

        def fin(x):
            return float(x) if np.isfinite(x) else "inf"

        return build(
            data,
            coords,
            {
                "title": "Heavy symmetric top with one point fixed (exact solution)",
                "references": "Goldstein, Poole & Safko 2002, Classical Mechanics, section 5.7; Landau & Lifshitz, "
                "Mechanics, section 35",
                "nutation": m.nutation,
                "I1_kg_m2": m.I1,
                "I3_kg_m2": m.I3,
                "mgl_J": m.mgl,
                "u1": m.u1,
                "u2": m.u2,
                "u3": fin(m.u3),
                "theta_min_rad": m.theta_min,
                "theta_max_rad": m.theta_max,
                "nutation_period_s": fin(m.nutation_period),
                "mean_precession_rate_rad_per_s": m.mean_precession_rate,
                "elliptic_parameter_m": m.m,
                "elliptic_complementary_parameter": m.m1,
                "energy_J": m.energy,
                "p_phi_kg_m2_per_s": m.p_phi,
                "p_psi_kg_m2_per_s": m.p_psi,
                "sleeping_stable": int(m.sleeping_stable),
            },
        )
