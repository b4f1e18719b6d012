"""The Chandler wobble: the rigid (Euler) period and the physics that lengthens it.

One formula carries every step. For a body spinning at Omega about the axis
of its largest (or smallest) principal moment C, with equatorial moments
A <= B, the free wobble frequency is

    sigma = Omega * sqrt( (C - A - D)(C - B - D) / ((A - A_f)(B - A_f)) )     (1)

* rigid body (notes, sec. 5.6): D = A_f = 0, giving Euler's
  sigma = Omega sqrt((C - A)(C - B)/(AB)), which for A = B is the notes'
  Omega (I3 - I1)/I1;
* elastic yielding: the centrifugal potential of the wobble deforms the body
  and adds D = k2 a^5 Omega^2/(3 G) to the products of inertia, i.e.
  sigma = sigma_E (1 - k2/k_s) with the secular Love number
  k_s = 3 G (C - A)/(a^5 Omega^2) (Munk & MacDonald 1960; Smith & Dahlen 1981);
* a liquid core does not follow the mantle's wobble: the equatorial moment
  that carries it is the mantle's, A_m = A - A_f (Smith & Dahlen 1981;
  Sasao, Okubo & Saito 1980: sigma = Omega (A/A_m)(e - kappa));
* the equilibrium ocean pole tide adds to the deformation: k2 -> k2 + k_ocean
  (Dahlen 1976; Desai 2002; IERS Conventions 2010, sec. 6.5);
* mantle anelasticity makes k2 depend on frequency; it is evaluated at the
  wobble's own frequency, self-consistently, with the absorption-band model of
  IERS Conventions (2010) eq. 6.12 (Wahr & Bergen 1986; Mathews et al. 2002):

      k(f) = k_ref + I cot(alpha pi/2) [(f_I/f)^alpha - (f_I/f_ref)^alpha],
      Im k(f) = I (f_I/f)^alpha,

  where I is the out-of-phase part of k at f_I (k2/Q for a small lag).

k_s as defined here uses the body's actual C - A (for Mars it includes the
non-hydrostatic Tharsis bulge); equation (1) needs exactly that quantity, so no
hydrostatic assumption enters.

All quantities are SI floats; (C - A)/C and (C - B)/C are formed from H and
J22 directly (see :mod:`wobble.models.planet`), never from differences of
large moments.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from wobble.errors import InputError
from wobble.models.planet import Measured, PlanetParameters

__all__ = [
    "STEPS",
    "MODEL_NAMES",
    "STEP_LABELS",
    "STEP_DESCRIPTIONS",
    "Step",
    "Budget",
    "free_wobble_rate",
    "secular_love_number",
    "anelastic_love_number",
    "resolve_model",
    "chandler_budget",
]

STEPS = ("rigid", "elastic", "fluid_core", "ocean_pole_tide", "anelastic")
MODEL_NAMES = (*STEPS, "full")
_ALIASES = {"core": "fluid_core", "ocean": "ocean_pole_tide", "euler": "rigid"}

STEP_LABELS = {
    "rigid": ("rigid body: Euler free precession", "notes sec. 5.6; Euler 1765"),
    "elastic": ("elastic yielding, k2 against k_s", "Munk & MacDonald 1960; Smith & Dahlen 1981"),
    "fluid_core": ("liquid core does not follow the mantle, A -> A_m", "Sasao, Okubo & Saito 1980; Smith & Dahlen 1981"),
    "ocean_pole_tide": ("equilibrium ocean pole tide, k2 + k_ocean", "Dahlen 1976; Desai 2002; IERS Conventions 2010 sec. 6.5"),
    "anelastic": ("mantle anelasticity: k2 at the wobble's frequency", "Wahr & Bergen 1986; Mathews et al. 2002; IERS Conventions 2010 eq. 6.12"),
}
STEP_DESCRIPTIONS = {name: f"{label} ({refs})" for name, (label, refs) in STEP_LABELS.items()}

# Parameters each step needs (beyond the figure and rotation of the rigid step).
_SCALE = ("love_number_k2", "gm", "equatorial_radius")
_REQUIRES = {
    "rigid": (),
    "elastic": _SCALE,
    "fluid_core": ("gm", "equatorial_radius"),
    "ocean_pole_tide": (*_SCALE, "ocean_pole_tide_love_number"),
    "anelastic": (
        *_SCALE,
        "love_number_k2_period",
        "love_number_k2_imaginary",
        "love_number_k2_imaginary_period",
        "anelastic_exponent",
    ),
}
_FIXED_POINT_TOL = 1e-15
_FIXED_POINT_MAX = 200


@dataclass(frozen=True)
class Step:
    """The wobble after one more piece of physics.

    Attributes
    ----------
    name : str
        One of :data:`STEPS`.
    rate : float
        Signed wobble frequency sigma in rad/s (same sign as the spin: prograde).
    love_number : float
        Effective real k2 used (0 for the rigid step).
    love_number_imaginary : float
        Out-of-phase part of k2 at the wobble frequency (anelastic step only).
    core_fraction : float
        A_f/Abar used (0 before the core step).
    uses : tuple of str
        Parameter names this step brings in (for their sources).
    """

    name: str
    rate: float
    love_number: float = 0.0
    love_number_imaginary: float = 0.0
    core_fraction: float = 0.0
    uses: tuple[str, ...] = ()

    @property
    def period(self) -> float:
        """abs(2 pi / sigma) in s; inf when there is no wobble."""
        return math.inf if self.rate == 0 else abs(2.0 * math.pi / self.rate)


@dataclass(frozen=True)
class Budget:
    """A planet's Chandler budget: the steps in order and the propagated uncertainty.

    Attributes
    ----------
    name, model : str
        Body and (resolved) model name.
    steps : tuple of Step
        In the order of :data:`STEPS`; the last is the model's answer.
    spin_rate : float
        Omega, rad/s.
    secular_love_number : float or None
        k_s of equation (1), when the scale of the body is known.
    quality_factor : float or None
        Q = Re sigma / (2 abs(Im sigma)) from the out-of-phase k2 (anelastic step).
    period_sigma : float
        Linearly propagated one-sigma uncertainty of the final period, s.
    contributions : dict
        Signed period change (s) for a +1 sigma change of each parameter.
    observed : Measured or None
        The observed period, s.
    """

    name: str
    model: str
    steps: tuple[Step, ...]
    spin_rate: float
    secular_love_number: float | None
    quality_factor: float | None
    period_sigma: float
    contributions: dict[str, float] = field(default_factory=dict)
    observed: Measured | None = None

    @property
    def rate(self) -> float:
        """The model's signed wobble frequency, rad/s."""
        return self.steps[-1].rate

    @property
    def period(self) -> float:
        """The model's period, s (inf without a wobble)."""
        return self.steps[-1].period

    @property
    def sense(self) -> str:
        """``prograde`` (with the spin), ``retrograde`` (prolate body) or ``none``."""
        if self.rate == 0:
            return "none"
        return "prograde" if (self.rate > 0) == (self.spin_rate > 0) else "retrograde"


def free_wobble_rate(spin: float, c_minus_a: float, c_minus_b: float, d: float = 0.0, core: float = 0.0) -> float:
    """Signed free-wobble frequency of equation (1), everything in units of C.

    Parameters
    ----------
    spin : float
        Omega, rad/s.
    c_minus_a, c_minus_b : float
        (C - A)/C and (C - B)/C, formed without cancellation by the caller.
    d : float
        D/C = k2 a^5 Omega^2/(3 G C), the rotational deformation (0: rigid).
    core : float
        A_f/C, the liquid core's equatorial moment (0: no core).

    Returns
    -------
    float
        sigma in rad/s, with the sign of ``spin`` for an oblate body (C largest:
        prograde) and the opposite sign for a prolate one (C smallest:
        retrograde); 0 for a sphere.

    Raises
    ------
    wobble.errors.InputError
        C is the intermediate moment (rotation about it is unstable, no
        periodic wobble), or the core is as large as the equatorial moment.
    """
    ea, eb = c_minus_a - d, c_minus_b - d
    den = (1.0 - c_minus_a - core) * (1.0 - c_minus_b - core)
    if not den > 0:
        raise InputError(
            "fluid_core",
            f"A_f/C = {core:.6g}",
            "a liquid core smaller than the equatorial moment (A_f < A)",
        )
    num = ea * eb
    if num < 0:
        raise InputError(
            "figure",
            f"(C-A)/C = {c_minus_a:.6g}, (C-B)/C = {c_minus_b:.6g}",
            "C the largest or the smallest principal moment: rotation about the intermediate "
            "axis is unstable (no periodic wobble)",
        )
    if num == 0:
        return 0.0
    sign = 1.0 if ea > 0 else -1.0
    return sign * spin * math.sqrt(num / den)


def secular_love_number(p: PlanetParameters) -> float | None:
    """k_s = 3 G (C - Abar)/(a^5 Omega^2) = 3 GM J2/(a^3 Omega^2); None without the scale.

    Uses the body's actual C - Abar (H C), so for a non-hydrostatic body it is
    the quantity equation (1) needs, not a fluid-body Love number.
    """
    c = p.c_factor
    if c is None or p.gm is None or p.equatorial_radius is None:
        return None
    a = p.equatorial_radius.value
    return 3.0 * p.gm.value * p.flattening * c / (a**3 * p.rotation_rate.value**2)


def _deformation(p: PlanetParameters, k: complex) -> complex:
    """D/C = k a^3 Omega^2 / (3 GM C/(M a^2)) for the Love number k."""
    a = p.equatorial_radius.value
    return k * a**3 * p.rotation_rate.value**2 / (3.0 * p.gm.value * p.c_factor)


def _core_over_c(p: PlanetParameters) -> float:
    return p.fluid_core_moment / p.polar_moment


def anelastic_love_number(p: PlanetParameters, rate: float) -> tuple[float, float]:
    """(Re k2, Im k2) at the wobble frequency abs(rate)/(2 pi) (IERS 2010 eq. 6.12 form).

    Parameters
    ----------
    p : PlanetParameters
        Needs ``love_number_k2`` at ``love_number_k2_period``, the out-of-phase
        ``love_number_k2_imaginary`` at its period, and ``anelastic_exponent``.
    rate : float
        Wobble frequency, rad/s.
    """
    alpha = p.anelastic_exponent.value
    if not 0 < alpha < 1:
        raise InputError("anelastic_exponent", alpha, "a number in (0, 1)")
    f = abs(rate) / (2.0 * math.pi)
    f_ref = 1.0 / p.love_number_k2_period.value
    f_im = 1.0 / p.love_number_k2_imaginary_period.value
    im_ref = p.love_number_k2_imaginary.value
    cot = 1.0 / math.tan(alpha * math.pi / 2.0)
    real = p.love_number_k2.value + im_ref * cot * ((f_im / f) ** alpha - (f_im / f_ref) ** alpha)
    return real, im_ref * (f_im / f) ** alpha


def _missing(p: PlanetParameters, step: str) -> list[str]:
    missing = [k for k in _REQUIRES[step] if getattr(p, k) is None]
    if step != "rigid" and p.c_factor is None:
        missing.append("polar_moment_factor (or j2 with dynamical_flattening)")
    if step == "fluid_core" and p.fluid_core_moment is None:
        missing.append("fluid_core_equatorial_moment (or fluid_core_radius and fluid_core_density)")
    return missing


def available_steps(p: PlanetParameters) -> tuple[str, ...]:
    """The steps this planet's parameters support, in order."""
    return tuple(s for s in STEPS if not _missing(p, s))


def resolve_model(p: PlanetParameters, model: str) -> tuple[str, tuple[str, ...]]:
    """Turn a model name into the list of steps to run.

    ``full`` runs every step the parameters support; a step name runs every
    supported step up to and including it (a step the parameters cannot
    support is an error naming what is missing).
    """
    name = _ALIASES.get(model, model)
    if name not in MODEL_NAMES:
        raise InputError(
            "model", model, "one of rigid, elastic, fluid_core (core), ocean_pole_tide (ocean), anelastic, full"
        )
    supported = available_steps(p)
    if name == "full":
        return "full", supported
    missing = _missing(p, name)
    if missing:
        raise InputError(
            "model",
            model,
            f"a model {p.name} supports ({', '.join((*supported, 'full'))}); "
            f"'{name}' needs {', '.join(missing)}",
        )
    upto = STEPS.index(name)
    return name, tuple(s for s in supported if STEPS.index(s) <= upto)


def _rigid_uses(p: PlanetParameters) -> tuple[str, ...]:
    keys = ["rotation_rate", *(k for k in ("dynamical_flattening", "j2", "polar_moment_factor") if getattr(p, k))]
    if p.c_factor is not None:
        keys += [k for k in ("c22", "s22") if getattr(p, k) is not None]
    return tuple(keys)


def _run_steps(p: PlanetParameters, steps: tuple[str, ...]) -> tuple[list[Step], float | None]:
    """Evaluate equation (1) step by step; return the steps and the quality factor."""
    omega = p.rotation_rate.value
    ca, cb = p.equatorial_excess()
    k, core, ocean = 0.0, 0.0, 0.0
    quality = None
    out: list[Step] = []
    for name in steps:
        k_imag = 0.0
        if name == "rigid":
            uses = _rigid_uses(p)
        elif name == "elastic":
            k, uses = p.love_number_k2.value, ("love_number_k2", "gm", "equatorial_radius")
        elif name == "fluid_core":
            core = _core_over_c(p)
            uses = tuple(
                key
                for key in ("fluid_core_equatorial_moment", "fluid_core_radius", "fluid_core_density", "gravitational_constant")
                if getattr(p, key) is not None
            )
        elif name == "ocean_pole_tide":
            ocean = p.ocean_pole_tide_love_number.value
            k, uses = p.love_number_k2.value + ocean, ("ocean_pole_tide_love_number",)
        else:  # anelastic: k2 at the wobble's own frequency, solved by fixed point
            rate = out[-1].rate if out else free_wobble_rate(omega, ca, cb)
            k, k_imag, rate = _anelastic_fixed_point(p, omega, ca, cb, core, ocean, rate)
            quality = _quality_factor(p, omega, ca, cb, core, k, k_imag)
            uses = (
                "love_number_k2_period",
                "love_number_k2_imaginary",
                "love_number_k2_imaginary_period",
                "anelastic_exponent",
            )
        d = _deformation(p, k).real if k else 0.0
        _check_below_fluid_limit(p, k, d, ca, cb)
        rate = free_wobble_rate(omega, ca, cb, d, core)
        frac = core / (1.0 - 0.5 * (ca + cb)) if core else 0.0
        out.append(Step(name, rate, k, k_imag, frac, uses))
    return out, quality


def _check_below_fluid_limit(p, k, d, ca, cb):
    # k2 >= k_s would mean the body yields more than a fluid: no restoring torque.
    if d and ca > 0 and cb > 0 and d >= min(ca, cb):
        ks = secular_love_number(p)
        raise InputError(
            "love_number_k2",
            f"{k:.6g} (effective)",
            f"below the secular Love number k_s = {ks:.6g} of this figure (a body cannot yield more than a fluid)",
        )


def _anelastic_fixed_point(p, omega, ca, cb, core, ocean, rate):
    """Solve rate = sigma(k(rate)) (the contraction factor is ~1e-3: a few iterations)."""
    for _ in range(_FIXED_POINT_MAX):
        k_real, k_imag = anelastic_love_number(p, rate)
        k = k_real + ocean
        d = _deformation(p, k).real
        _check_below_fluid_limit(p, k, d, ca, cb)
        new = free_wobble_rate(omega, ca, cb, d, core)
        if abs(new - rate) <= _FIXED_POINT_TOL * abs(new):
            return k, k_imag, new
        rate = new
    raise InputError("anelastic_exponent", p.anelastic_exponent.value, "parameters for which k2(frequency) converges")


def _quality_factor(p, omega, ca, cb, core, k_real, k_imag) -> float | None:
    """Q = Re sigma / (2 abs(Im sigma)) with the complex k2 in equation (1)."""
    if k_imag == 0:
        return None
    d = _deformation(p, complex(k_real, k_imag))
    den = (1.0 - ca - core) * (1.0 - cb - core)
    sigma = omega * ((ca - d) * (cb - d) / den) ** 0.5
    return abs(sigma.real) / (2.0 * abs(sigma.imag))


def _period_of(p: PlanetParameters, steps: tuple[str, ...]) -> float:
    return _run_steps(p, steps)[0][-1].period


def _propagate(p: PlanetParameters, steps: tuple[str, ...]) -> tuple[float, dict[str, float]]:
    """First-order propagation: central differences over +-1 sigma, parameters independent."""
    contributions = {}
    for key, m in p.measured_fields().items():
        if key == "observed_chandler_period":
            continue
        up = _period_of(replace(p, **{key: Measured(m.value + m.sigma, m.sigma)}), steps)
        down = _period_of(replace(p, **{key: Measured(m.value - m.sigma, m.sigma)}), steps)
        delta = 0.5 * (up - down)
        if delta != 0 and math.isfinite(delta):
            contributions[key] = delta
    total = math.sqrt(sum(v * v for v in contributions.values()))
    return total, contributions


def chandler_budget(p: PlanetParameters, model: str = "full") -> Budget:
    """Run the Chandler model on a planet.

    Parameters
    ----------
    p : PlanetParameters
        The planet (SI).
    model : str
        ``full`` (every step the parameters support, the default) or the last
        step to include: ``rigid``, ``elastic``, ``fluid_core`` (``core``),
        ``ocean_pole_tide`` (``ocean``), ``anelastic``.

    Returns
    -------
    Budget
        The steps with their periods, the propagated uncertainty and Q.
    """
    name, steps = resolve_model(p, model)
    out, quality = _run_steps(p, steps)
    if out[-1].rate == 0:
        sigma, contributions = math.nan, {}
    else:
        sigma, contributions = _propagate(p, steps)
    return Budget(
        name=p.name,
        model=name,
        steps=tuple(out),
        spin_rate=p.rotation_rate.value,
        secular_love_number=secular_love_number(p),
        quality_factor=quality,
        period_sigma=sigma,
        contributions=contributions,
        observed=p.observed_chandler_period,
    )
