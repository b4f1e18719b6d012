"""The Chandler wobble: the rigid (Euler) period and the physics that lengthens it.

One formula carries every step. For a body spinning at Omega about the axis
of its largest (or smallest) principal moment C, with equatorial moments
A <= B, the free wobble frequency is

    sigma = Omega * sqrt( (C - A - D)(C - B - D) / ((A - A_f + D)(B - A_f + D)) )     (1)

* rigid body (notes, sec. 5.6; Goldstein, Poole & Safko 2002, sec. 5.6): D = A_f = 0, giving Euler's
  sigma = Omega sqrt((C - A)(C - B)/(AB)), which for A = B is the notes'
  Omega (I3 - I1)/I1;
* elastic yielding: the centrifugal potential of the wobble deforms the body
  and adds D = k2 a^5 Omega^2/(3 G) to the products of inertia, i.e.
  sigma = sigma_E (1 - k2/k_s) with the secular Love number
  k_s = 3 G (C - A)/(a^5 Omega^2) (Munk & MacDonald 1960; Smith & Dahlen 1981);
  the D in the denominator is the angular momentum the deformation itself carries
  as it turns with the wobble, the (1 + sigma) kappa term of the linearised Liouville
  equations (Sasao, Okubo & Saito 1980): a factor 1/(1 + D/A_m) on sigma, about 1e-3,
  which the classic first-order formula drops. With it this budget is exactly the
  Chandler mode of :mod:`wobble.models.modes` with the core-mantle coupling off;
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
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from wobble.errors import InputError
from wobble.models.planet import FIGURE_KEYS, POSITIVE_KEYS, SCALE_RANGE, Measured, PlanetParameters, scales

__all__ = [
    "STEPS",
    "MODEL_NAMES",
    "STEP_LABELS",
    "STEP_DESCRIPTIONS",
    "Step",
    "Budget",
    "ParameterValues",
    "free_wobble_rate",
    "free_wobble_rate_array",
    "secular_love_number",
    "anelastic_love_number",
    "anelastic_love_number_function",
    "inertia_ratios",
    "resolve_model",
    "missing_parameters",
    "chandler_budget",
    "Samples",
    "chandler_samples",
    "love_number_samples",
    "INVALID_REASONS",
]

STEPS = ("rigid", "elastic", "fluid_core", "ocean_pole_tide", "anelastic")
MODEL_NAMES = (*STEPS, "full")
_ALIASES = {"core": "fluid_core", "ocean": "ocean_pole_tide", "euler": "rigid"}

STEP_LABELS = {
    "rigid": ("rigid body: Euler free precession", "Euler 1765; Goldstein, Poole & Safko 2002 sec. 5.6"),
    "elastic": ("elastic yielding, k2 against k_s", "Munk & MacDonald 1960; Smith & Dahlen 1981"),
    "fluid_core": (
        "liquid core does not follow the mantle, A -> A_m",
        "Sasao, Okubo & Saito 1980; Smith & Dahlen 1981",
    ),
    "ocean_pole_tide": (
        "equilibrium ocean pole tide, k2 + k_ocean",
        "Dahlen 1976; Desai 2002; IERS Conventions 2010 sec. 6.5",
    ),
    "anelastic": (
        "mantle anelasticity: k2 at the wobble's frequency",
        "Wahr & Bergen 1986; Mathews et al. 2002; IERS Conventions 2010 eq. 6.12",
    ),
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
_FIXED_POINT_TOL = 1e-14
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
        Q = Re sigma / (2 abs(Im sigma)) from the out-of-phase k2 (anelastic step); inf
        where k2 has no out-of-phase part (no dissipation), None without an anelastic step.
    period_sigma : float
        One-sigma uncertainty of the final period, s: the standard deviation over
        :data:`MC_DRAWS` Monte Carlo draws of every uncertain parameter (the model is
        not linear over the parameters' ranges, e.g. the anelastic exponent's). NaN
        when the budget was run with ``uncertainty=False`` (as are ``period_sigma_linear``
        and ``valid_fraction``; ``contributions`` is then empty).
    contributions : dict
        Signed period change (s) for a +1 sigma change of each parameter (linear).
    observed : Measured or None
        The observed period, s.
    period_sigma_linear : float
        The first-order (linear) propagation of the same uncertainties, s.
    valid_fraction : float
        Fraction of the Monte Carlo draws inside every parameter's physical range.
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
    period_sigma_linear: float = math.nan
    valid_fraction: float = 1.0

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


# Validity codes of the vectorised evaluation (0: valid), for sweeps that mark
# unphysical members instead of stopping.
INVALID_REASONS = {
    0: "",
    1: "C is the intermediate principal moment: rotation about it is unstable (no periodic wobble)",
    2: "the liquid core is as large as the equatorial moment (A_f >= A)",
    3: "k2 at or above the secular Love number k_s: the body would yield more than a fluid",
    4: "k2(frequency) did not converge",
    5: "a parameter is outside its physical range (e.g. a negative moment, density or Love number)",
}


def free_wobble_rate_array(spin, c_minus_a, c_minus_b, d=0.0, core=0.0):
    """Vectorised equation (1): signed rates and validity codes.

    Parameters
    ----------
    spin, c_minus_a, c_minus_b, d, core : float or array_like
        As in :func:`free_wobble_rate`; broadcast together.

    Returns
    -------
    rate : numpy.ndarray
        sigma in rad/s (NaN where invalid).
    code : numpy.ndarray of int8
        0 valid, 1 intermediate-axis spin, 2 core too large (see :data:`INVALID_REASONS`).
    """
    ea = np.asarray(c_minus_a, dtype=float) - d
    eb = np.asarray(c_minus_b, dtype=float) - d
    mantle_a = 1.0 - np.asarray(c_minus_a) - core  # (A - A_f)/C
    mantle_b = 1.0 - np.asarray(c_minus_b) - core  # (B - A_f)/C
    # The deformation's own angular momentum, D, rides with the mantle's (equation (1)).
    den = (mantle_a + d) * (mantle_b + d)
    num = ea * eb
    # Each factor must be positive: a core larger than both A and B makes den > 0 too.
    code = np.where(~((mantle_a > 0) & (mantle_b > 0)), 2, np.where(num < 0, 1, 0)).astype(np.int8)
    ok = code == 0
    ratio = np.divide(num, den, out=np.full(np.broadcast(num, den).shape, np.nan), where=ok)
    magnitude = np.sqrt(ratio, out=np.full_like(ratio, np.nan), where=ok & (ratio >= 0))
    # ea == 0 means num == 0: a rate of zero, given as +0 (not -0.0, which printed as '-0.0 rad / s' for a sphere).
    sign = np.where(ea < 0, -1.0, 1.0)
    return sign * spin * magnitude, code


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
    rate, code = free_wobble_rate_array(spin, c_minus_a, c_minus_b, d, core)
    if code == 2:
        raise InputError(
            "fluid_core", f"A_f/C = {core:.6g}", "a liquid core smaller than the equatorial moment (A_f < A)"
        )
    if code == 1:
        raise InputError(
            "figure",
            f"(C-A)/C = {c_minus_a:.6g}, (C-B)/C = {c_minus_b:.6g}",
            "C the largest or the smallest principal moment: rotation about the intermediate "
            "axis is unstable (no periodic wobble)",
        )
    return float(rate)


def principal_moments(planet: PlanetParameters):
    """Principal moments (A, B, C) in kg m^2 and the mass in kg of a catalogued planet.

    C = (C/(M a^2)) M a^2 with M = GM/G; A and B from (C - A)/C and (C - B)/C formed
    from H and J22 without cancellation (:meth:`ParameterValues.equatorial_excess`). None when
    the file does not give the absolute scale (GM, a and C/(M a^2), or J2 with H).
    """
    vals = ParameterValues(planet.values())
    c_factor = vals.c_factor
    if c_factor is None or vals["gm"] is None or vals["equatorial_radius"] is None:
        return None
    mass = float(vals["gm"] / vals["gravitational_constant"])
    c = float(c_factor) * mass * float(vals["equatorial_radius"]) ** 2
    ca, cb = vals.equatorial_excess()
    return (c * (1.0 - float(ca)), c * (1.0 - float(cb)), c), mass


# -- the parameters as arrays ----------------------------------------------------------


class ParameterValues:
    """A planet's parameters as float64 arrays broadcast to one shape, with the derived figure.

    The one place the Chandler budget, the normal modes, the sweeps and the inversion turn
    a parameter mapping (with per-member overrides) into arrays, and form the figure from
    it: H, C/(M a^2), (C - A)/C and (C - B)/C from H and J22 without cancellation, the
    deformation D/C, the core's A_f/C, the secular Love number and the anelastic k2.

    Parameters
    ----------
    base : Mapping[str, float or None]
        Every parameter by name (SI), as :meth:`wobble.models.planet.PlanetParameters.values` gives it; None
        where the body file does not give it.
    overrides : Mapping[str, array_like], optional
        Values that replace entries of ``base`` (scalars or arrays, broadcast together
        with the rest); a key that ``base`` does not have raises :class:`InputError`.

    Attributes
    ----------
    shape : tuple of int
        The broadcast shape of every given parameter.
    v : dict
        Parameter name -> array of that shape, or None where the parameter is not given
        (``values[name]`` reads it).
    out_of_range : numpy.ndarray of bool
        True for members with a parameter outside its physical range (a non-positive
        mass, radius or moment, a negative Love number, an anelastic exponent outside
        (0, 1)).

    Examples
    --------
    >>> from wobble.io.catalog import load_planet
    >>> earth, _ = load_planet("earth")
    >>> values = ParameterValues(earth.values(), {"love_number_k2": [0.29, 0.30]})
    >>> values.shape
    (2,)
    >>> values.deformation(values["love_number_k2"]).round(6)  # D/C = H k2/k_s
    array([0.001012, 0.001047])
    """

    def __init__(self, base: Mapping[str, float | None], overrides: Mapping[str, object] | None = None):
        merged = dict(base)
        for key, val in (overrides or {}).items():
            if key not in merged:
                raise InputError("parameter", key, f"one of {', '.join(sorted(merged))}")
            merged[key] = val
        given = {k: np.asarray(v, dtype=float) for k, v in merged.items() if v is not None}
        self.shape = np.broadcast_shapes(*(a.shape for a in given.values())) if given else ()
        self.v = {k: None for k in merged}
        # Broadcast to one shape (np.full for the many scalars: np.broadcast_arrays costs
        # ten times more, and this runs on every call of a sweep chunk or an inversion step).
        self.v.update(
            {
                k: a
                if a.shape == self.shape
                else (np.full(self.shape, a) if a.ndim == 0 else np.broadcast_to(a, self.shape))
                for k, a in given.items()
            }
        )
        bad = np.zeros(self.shape, dtype=bool)
        for _key, _allowed, inside in self._ranges():
            bad |= ~inside
        self.out_of_range = bad

    def _ranges(self):
        """(key, what is allowed, mask of the members inside it) for every range-checked parameter given."""
        for key in POSITIVE_KEYS:
            if self.v[key] is not None:
                yield key, "a positive value", self.v[key] > 0
        for key in ("love_number_k2", "love_number_k2_imaginary", "ocean_pole_tide_love_number"):
            if self.v[key] is not None:
                yield key, "a non-negative Love number", self.v[key] >= 0
        if self.v["anelastic_exponent"] is not None:
            alpha = self.v["anelastic_exponent"]
            yield "anelastic_exponent", "an exponent in (0, 1)", (alpha > 0) & (alpha < 1)
        # The scales a planet file is held to (wobble.models.planet.scales, within SCALE_RANGE), for the members of
        # a sweep or a Monte Carlo: a sweep's spin of 1e-300 rad/s was a valid member with a period of 2e298 d,
        # and NumPy's overflow warnings came with an infinite spread.
        lo, hi = SCALE_RANGE
        with np.errstate(all="ignore"):
            for keys, formula, value in scales(self.v):
                inside = (np.abs(value) >= lo) & (np.abs(value) <= hi)
                yield keys[0], f"values whose {formula} lies from {lo:.2g} to {hi:.2g} in SI units", inside

    def first_out_of_range(self):
        """(key, value, allowed) of the first parameter outside its range (of the first member outside
        one), for a message that names it; None when every member is inside."""
        for key, allowed, inside in self._ranges():
            outside = np.flatnonzero(~np.asarray(inside))
            if outside.size:
                return key, float(np.ravel(self.v[key])[outside[0]]), allowed
        return None

    def __getitem__(self, key):
        return self.v[key]

    @property
    def flattening(self):
        if self["dynamical_flattening"] is not None:
            return self["dynamical_flattening"]
        return self["j2"] / self["polar_moment_factor"]

    @property
    def c_factor(self):
        if self["polar_moment_factor"] is not None:
            return self["polar_moment_factor"]
        if self["j2"] is not None and self["dynamical_flattening"] is not None:
            return self["j2"] / self["dynamical_flattening"]
        return None

    def equatorial_excess(self):
        """((C - A)/C, (C - B)/C) from H and J22 without cancellation."""
        h = self.flattening
        c = self.c_factor
        if c is None or (self["c22"] is None and self["s22"] is None):
            return h, h
        c22 = self["c22"] if self["c22"] is not None else 0.0
        s22 = self["s22"] if self["s22"] is not None else 0.0
        split = 2.0 * math.sqrt(5.0 / 12.0) * np.hypot(c22, s22) / c
        return h + split, h - split

    def deformation(self, k):
        """D/C = k a^3 Omega^2 / (3 GM C/(M a^2)) for the (possibly complex) Love number k."""
        a = self["equatorial_radius"]
        return k * a**3 * self["rotation_rate"] ** 2 / (3.0 * self["gm"] * self.c_factor)

    def core_over_c(self):
        """A_f/C, with A_f given or that of a uniform core (8 pi/15) rho R^5."""
        if self["fluid_core_equatorial_moment"] is not None:
            af = self["fluid_core_equatorial_moment"]
        else:
            af = 8.0 * math.pi / 15.0 * self["fluid_core_density"] * self["fluid_core_radius"] ** 5
        mass = self["gm"] / self["gravitational_constant"]
        return af / (self.c_factor * mass * self["equatorial_radius"] ** 2)

    def secular_love_number(self):
        c = self.c_factor
        if c is None or self["gm"] is None or self["equatorial_radius"] is None:
            return None
        a = self["equatorial_radius"]
        return 3.0 * self["gm"] * self.flattening * c / (a**3 * self["rotation_rate"] ** 2)

    def anelastic_k(self, rate):
        """(Re k2, Im k2) at the frequency abs(rate)/(2 pi), IERS 2010 eq. 6.12 form."""
        alpha = self["anelastic_exponent"]
        # Overflow too: reference periods far from the wobble's make k2 infinite, which the callers refuse
        # (dispersion_error) instead of printing NumPy's warning.
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            f = np.abs(rate) / (2.0 * math.pi)
            f_ref = 1.0 / self["love_number_k2_period"]
            f_im = 1.0 / self["love_number_k2_imaginary_period"]
            im_ref = self["love_number_k2_imaginary"]
            cot = 1.0 / np.tan(alpha * math.pi / 2.0)
            real = self["love_number_k2"] + im_ref * cot * ((f_im / f) ** alpha - (f_im / f_ref) ** alpha)
            return real, im_ref * (f_im / f) ** alpha


def secular_love_number(p: PlanetParameters) -> float | None:
    """k_s = 3 G (C - Abar)/(a^5 Omega^2) = 3 GM J2/(a^3 Omega^2); None without the scale.

    Uses the body's actual C - Abar (H C), so for a non-hydrostatic body it is
    the quantity equation (1) needs, not a fluid-body Love number.
    """
    ks = ParameterValues(p.values()).secular_love_number()
    return None if ks is None else float(ks)


def inertia_ratios(p: PlanetParameters) -> dict[str, float | None]:
    """The figure in units of C, as equation (1) uses it (for other models of the same planet).

    Returns
    -------
    dict
        ``c_minus_a`` and ``c_minus_b``: (C - A)/C and (C - B)/C (from H and J22,
        without cancellation); ``core``: A_f/C (None without a liquid core or the
        absolute scale); ``deformation_per_k``: D/C for k2 = 1, i.e.
        a^3 Omega^2/(3 GM C/(M a^2)) (None without the scale).
    """
    values = ParameterValues(p.values())
    ca, cb = values.equatorial_excess()
    scaled = values.c_factor is not None and values["gm"] is not None and values["equatorial_radius"] is not None
    core = None
    if scaled and p.fluid_core_moment is not None:
        core = float(values.core_over_c())
    return {
        "c_minus_a": float(ca),
        "c_minus_b": float(cb),
        "core": core,
        "deformation_per_k": float(values.deformation(1.0)) if scaled else None,
    }


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
    return anelastic_love_number_function(p)(rate)


def dispersion_error(p: PlanetParameters, k2: float, ks: float | None = None) -> InputError:
    """The refusal of reference periods that make k2 at the wobble's frequency (``k2``) infinite or
    at least the secular Love number ``ks``.

    The dispersion law scales by (f_ref / f)^alpha: a period of 1e-303 s (a mistyped unit) makes
    that ratio overflow, and k2 at any wobble's frequency infinite.
    """
    periods = (p.love_number_k2_period, p.love_number_k2_imaginary_period)
    below = "" if ks is None else f" and below the secular Love number k_s = {ks:.6g}"
    return InputError(
        "love_number_k2_period, love_number_k2_imaginary_period",
        ", ".join("None" if q is None else f"{q.value:g} s" for q in periods) + f" (k2 = {k2:.6g} at the wobble)",
        f"reference periods for which the anelastic k2 at the wobble's frequency is finite{below} "
        "(IERS 2010 eq. 6.12 scales by (f_ref/f)^alpha)",
    )


def anelastic_love_number_function(p: PlanetParameters):
    """``rate -> (Re k2, Im k2)`` of :func:`anelastic_love_number`, the parameters read once.

    For callers that iterate on the frequency (the normal modes): building the
    parameter arrays costs more than evaluating the dispersion law.
    """
    alpha = p.anelastic_exponent.value
    if not 0 < alpha < 1:
        raise InputError("anelastic_exponent", alpha, "a number in (0, 1)")
    values = ParameterValues(p.values())

    def k_at(rate: float) -> tuple[float, float]:
        real, imag = values.anelastic_k(rate)
        return float(real), float(imag)

    return k_at


def missing_parameters(p: PlanetParameters, step: str) -> list[str]:
    """The parameters ``p`` lacks for ``step`` (empty when the step can run)."""
    missing = [k for k in _REQUIRES[step] if getattr(p, k) is None]
    if step != "rigid" and p.c_factor is None:
        missing.append("polar_moment_factor (or j2 with dynamical_flattening)")
    if step == "fluid_core" and p.fluid_core_moment is None:
        missing.append("fluid_core_equatorial_moment (or fluid_core_radius and fluid_core_density)")
    return missing


def available_steps(p: PlanetParameters) -> tuple[str, ...]:
    """The steps this planet's parameters support, in order."""
    return tuple(s for s in STEPS if not missing_parameters(p, s))


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
    missing = missing_parameters(p, name)
    if missing:
        raise InputError(
            "model",
            model,
            f"a model {p.name} supports ({', '.join((*supported, 'full'))}); '{name}' needs {', '.join(missing)}",
        )
    upto = STEPS.index(name)
    return name, tuple(s for s in supported if STEPS.index(s) <= upto)


def _rigid_uses(p: PlanetParameters) -> tuple[str, ...]:
    keys = ["rotation_rate", *(k for k in ("dynamical_flattening", "j2", "polar_moment_factor") if getattr(p, k))]
    if p.c_factor is not None:
        keys += [k for k in ("c22", "s22") if getattr(p, k) is not None]
    return tuple(keys)


_USES = {
    "elastic": ("love_number_k2", "gm", "equatorial_radius"),
    "fluid_core": ("fluid_core_equatorial_moment", "fluid_core_radius", "fluid_core_density", "gravitational_constant"),
    "ocean_pole_tide": ("ocean_pole_tide_love_number",),
    "anelastic": (
        "love_number_k2_period",
        "love_number_k2_imaginary",
        "love_number_k2_imaginary_period",
        "anelastic_exponent",
    ),
}


@dataclass(frozen=True)
class _StepArrays:
    name: str
    rate: np.ndarray
    love_number: np.ndarray
    love_number_imaginary: np.ndarray
    core_fraction: np.ndarray


def _evaluate(vals: ParameterValues, steps: tuple[str, ...]):
    """Equation (1) step by step on arrays; returns step arrays, validity code, Q.

    Members whose parameters overflow (an infinite k2 from the dispersion law, ...) get a
    code and NaN, and the callers report them: NumPy's warnings on the way are noise.
    """
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return _evaluate_steps(vals, steps)


def _evaluate_steps(vals: ParameterValues, steps: tuple[str, ...]):
    omega = vals["rotation_rate"]
    ca, cb = vals.equatorial_excess()
    zeros = np.zeros(vals.shape)
    code = np.where(vals.out_of_range, 5, 0).astype(np.int8)
    k, core, ocean = zeros, zeros, zeros
    quality = np.full(vals.shape, np.nan)
    ks = vals.secular_love_number()
    out = []
    rate = zeros
    for name in steps:
        k_imag = zeros
        if name == "elastic":
            k = vals["love_number_k2"] + zeros
        elif name == "fluid_core":
            core = vals.core_over_c() + zeros
        elif name == "ocean_pole_tide":
            ocean = vals["ocean_pole_tide_love_number"] + zeros
            k = vals["love_number_k2"] + ocean
        elif name == "anelastic":
            k, k_imag, rate, step_code = _anelastic_fixed_point(vals, omega, ca, cb, core, ocean, rate)
            code = np.where(code == 0, step_code, code)
            quality = _quality_factor(vals, omega, ca, cb, core, k, k_imag)
        d = vals.deformation(k) if name != "rigid" else zeros
        if ks is not None and name != "rigid":
            # k2 >= k_s: the body would yield more than a fluid (no restoring torque). Without an oblate figure
            # (H <= 0: k_s <= 0) any yielding is more than the figure holds: H = 0 gave an "elastic" 953-day
            # retrograde wobble of a sphere, which wobble modes refused.
            softer = (d >= np.minimum(ca, cb)) & ((np.minimum(ca, cb) > 0) | (d > 0))
            code = np.where((code == 0) & softer, 3, code)
        rate, step_code = free_wobble_rate_array(omega, ca, cb, d, core)
        code = np.where(code == 0, step_code, code)
        frac = core / (1.0 - 0.5 * (np.asarray(ca) + np.asarray(cb)))
        out.append(_StepArrays(name, rate, k + zeros, k_imag + zeros, frac + zeros))
    return out, code, quality


def _anelastic_fixed_point(vals, omega, ca, cb, core, ocean, rate):
    """Solve sigma = F(sigma) = rate with k2(sigma) for every member.

    F is a contraction (factor ~1e-3 for Earth and Mars), but near k_s the
    dispersion drives k2 up as the frequency falls; a safeguarded secant on
    F(sigma) - sigma converges there too, and members whose k2 reaches k_s
    (no restoring torque left) are flagged (code 3), as are members that do not
    converge (code 4) -- only those.
    """

    def step(x):
        k_real, _ = vals.anelastic_k(x)
        d = vals.deformation(k_real + ocean)
        softer = (np.asarray(ca) > 0) & (np.asarray(cb) > 0) & (d >= np.minimum(ca, cb))
        new, c = free_wobble_rate_array(omega, ca, cb, d, core)
        return new, np.where(softer & (c == 0), 3, c).astype(np.int8)

    code = np.zeros(vals.shape, dtype=np.int8)
    x0 = rate
    f0, c = step(x0)
    code = np.where(code == 0, c, code)
    x1 = np.where(code == 0, f0, x0)
    done = code != 0
    for _ in range(_FIXED_POINT_MAX):
        f1, c = step(x1)
        code = np.where(code == 0, c, code)
        g0, g1 = f0 - x0, f1 - x1
        with np.errstate(invalid="ignore", divide="ignore"):
            converged = np.abs(g1) <= _FIXED_POINT_TOL * np.abs(x1)
            # Rounding floor: no further progress and already tiny.
            stalled = (np.abs(g1) >= np.abs(g0)) & (np.abs(g1) <= 1e-12 * np.abs(x1))
            done = (code != 0) | converged | stalled
            if np.all(done):
                break
            secant = x1 - g1 * (x1 - x0) / (g1 - g0)
        usable = np.isfinite(secant) & (np.sign(secant) == np.sign(x1))
        x0, f0 = x1, f1
        x1 = np.where(done, x1, np.where(usable, secant, f1))
    code = np.where((code == 0) & ~done, 4, code).astype(np.int8)
    k_real, k_imag = vals.anelastic_k(x1)
    return k_real + ocean, k_imag, x1, code


def _quality_factor(vals, omega, ca, cb, core, k_real, k_imag):
    """Q = Re sigma / (2 abs(Im sigma)) with the complex k2 in equation (1)."""
    d = vals.deformation(k_real + 1j * k_imag)
    with np.errstate(divide="ignore", invalid="ignore"):  # members already marked invalid carry NaN
        den = (1.0 - ca - core + d) * (1.0 - cb - core + d)
        sigma = omega * np.sqrt((ca - d) * (cb - d) / den + 0j)
        return np.abs(sigma.real) / (2.0 * np.abs(sigma.imag))


def _raise_for(p: PlanetParameters, code: int, steps, values: ParameterValues):
    if code == 1:
        ca, cb = values.equatorial_excess()
        raise InputError(
            "figure",
            f"(C-A)/C = {float(ca):.6g}, (C-B)/C = {float(cb):.6g}",
            "C the largest or the smallest principal moment: rotation about the intermediate "
            "axis is unstable (no periodic wobble)",
        )
    if code == 2:
        raise InputError(
            "fluid_core",
            f"A_f/C = {float(values.core_over_c()):.6g}",
            "a liquid core smaller than the equatorial moment (A_f < A)",
        )
    if code == 3:
        ks = values.secular_love_number()
        if float(ks) <= 0:
            # Not oblate (H <= 0): "k2 below k_s = -0.857" named the wrong number and asked the impossible.
            name = "dynamical_flattening" if values["dynamical_flattening"] is not None else "j2"
            raise InputError(
                name,
                f"{values[name]:.6g}",
                f"a positive value (an oblate figure, C > A) for the steps past 'rigid': they scale the yielding by "
                f"k_s = 3G(C-A)/(a^5 Omega^2), {float(ks):.6g} here (model 'rigid' takes any figure)",
            )
        if "anelastic" in steps:
            # A k2 that only the dispersion law takes to k_s (or to infinity): name its cause instead.
            ca, cb = values.equatorial_excess()
            k_real = float(values.anelastic_k(values["rotation_rate"] * np.sqrt(np.abs(ca * cb)))[0])
            if not math.isfinite(k_real) or (p.love_number_k2.value < float(ks) <= k_real):
                raise dispersion_error(p, k_real, float(ks))
        raise InputError(
            "love_number_k2",
            f"{p.love_number_k2.value:.6g}",
            f"below the secular Love number k_s = {float(ks):.6g} of this figure (a body cannot yield more than a "
            "fluid)",
        )
    if code == 4:
        raise InputError(
            "anelastic_exponent", p.anelastic_exponent.value, "parameters for which k2(frequency) converges"
        )
    if code == 5:
        key, value, allowed = values.first_out_of_range()
        raise InputError(key, value, allowed)


# Monte Carlo propagation of the catalogue's uncertainties (JCGM 101:2008): enough draws
# that the standard deviation is known to 0.2 % (1/sqrt(2N)), a fixed seed so that the
# same planet gives the same number every run. It costs ~60 ms for 10^5 draws.
MC_DRAWS = 100_000
MC_SEED = 20_240_901


#: The parameters beyond _REQUIRES that a step reads: the rigid step the figure, its equatorial split and the spin;
#: the liquid core its moment (or radius and density) and, for the planet's mass GM/G, the gravitational constant.
_READS = {
    "rigid": (*FIGURE_KEYS, "c22", "s22", "rotation_rate"),
    "fluid_core": ("fluid_core_equatorial_moment", "fluid_core_radius", "fluid_core_density", "gravitational_constant"),
}


def parameters_used(steps: tuple[str, ...]) -> frozenset[str]:
    """The planet parameters the budget's ``steps`` read (each step includes the ones before it)."""
    return frozenset(k for s in ("rigid", *steps) for k in (*_REQUIRES[s], *_READS.get(s, ())))


def _monte_carlo(
    p: PlanetParameters, steps: tuple[str, ...], draws: int = MC_DRAWS, seed: int = MC_SEED
) -> tuple[float, float]:
    """Standard deviation of the period (s) over normal draws of every uncertain parameter.

    Draws outside a parameter's physical range (a negative Love number or density, a
    core as large as the planet) are dropped: the model has no answer there. The draws
    come from :mod:`wobble.numerics.draws`, as a sweep's do, so a sweep over the same
    parameters reproduces this number within its sampling error.

    Returns
    -------
    (sigma, valid_fraction)
    """
    from wobble.numerics.draws import standard_normal

    measured = {k: m for k, m in p.measured_fields().items() if k != "observed_chandler_period"}
    used = parameters_used(steps)
    if not any(k in used for k in measured):
        return 0.0, 1.0
    # Only the parameters the steps use are drawn (a draw of an unused one outside its range dropped the draw:
    # Mars's rigid period lost 2.3 % of its draws to the anelastic exponent); each keeps its stream number, so
    # the draws of a model that uses them all are unchanged.
    overrides = {
        k: m.value + m.sigma * standard_normal(seed, i, 0, draws)
        for i, (k, m) in enumerate(measured.items())
        if k in used
    }
    out, code, _ = _evaluate(ParameterValues(p.values(), overrides), steps)
    ok = code == 0
    if np.count_nonzero(ok) < 2:  # no spread to measure (an uncertainty of 1e300 left none: NumPy's warnings, nan)
        return math.nan, float(np.mean(ok))
    with np.errstate(divide="ignore"):
        period = np.abs(2.0 * math.pi / out[-1].rate[ok])
    return float(np.std(period, ddof=1)), float(np.mean(ok))


def _propagate(p: PlanetParameters, steps: tuple[str, ...]) -> tuple[float, dict[str, float]]:
    """First-order propagation: central differences over +-1 sigma, parameters independent.

    All 2n perturbed planets are evaluated in one vectorised call.
    """
    measured = {k: m for k, m in p.measured_fields().items() if k != "observed_chandler_period"}
    if not measured:
        return 0.0, {}
    keys = list(measured)
    n = len(keys)
    base = p.values()
    overrides = {}
    for i, key in enumerate(keys):
        col = np.full(2 * n, base[key])
        col[2 * i] += measured[key].sigma
        col[2 * i + 1] -= measured[key].sigma
        overrides[key] = col
    out, code, _ = _evaluate(ParameterValues(base, overrides), steps)
    with np.errstate(divide="ignore"):
        period = np.where(code == 0, np.abs(2.0 * math.pi / out[-1].rate), np.nan)
    contributions = {}
    for i, key in enumerate(keys):
        delta = 0.5 * (period[2 * i] - period[2 * i + 1])
        if delta != 0 and math.isfinite(delta):
            contributions[key] = float(delta)
    total = math.sqrt(sum(v * v for v in contributions.values()))
    return total, contributions


def chandler_budget(p: PlanetParameters, model: str = "full", *, uncertainty: bool = True) -> Budget:
    """Run the Chandler model on a planet.

    Parameters
    ----------
    p : PlanetParameters
        The planet (SI).
    model : str
        ``full`` (every step the parameters support, the default) or the last
        step to include: ``rigid``, ``elastic``, ``fluid_core`` (``core``),
        ``ocean_pole_tide`` (``ocean``), ``anelastic``.
    uncertainty : bool
        False skips the propagation (``period_sigma`` and ``valid_fraction`` NaN, no
        contributions): the steps alone cost ~1 ms, the 10^5 Monte Carlo draws ~150 ms,
        and a caller that wants only the period (the normal modes' tie to the budget)
        should not pay for them.

    Returns
    -------
    Budget
        The steps with their periods, the propagated uncertainty and Q.
    """
    name, steps = resolve_model(p, model)
    values = ParameterValues(p.values())
    arrays, code, quality = _evaluate(values, steps)
    _raise_for(p, int(code), steps, values)
    out = []
    for s in arrays:
        uses = _rigid_uses(p) if s.name == "rigid" else tuple(k for k in _USES[s.name] if getattr(p, k) is not None)
        out.append(
            Step(
                s.name,
                float(s.rate),
                float(s.love_number),
                float(s.love_number_imaginary),
                float(s.core_fraction),
                uses,
            )
        )
    if out[-1].rate == 0 or not uncertainty:
        sigma, linear, contributions, valid = math.nan, math.nan, {}, math.nan
    else:
        linear, contributions = _propagate(p, steps)
        sigma, valid = _monte_carlo(p, steps)
    q = float(quality)
    ks = values.secular_love_number()
    return Budget(
        name=p.name,
        model=name,
        steps=tuple(out),
        spin_rate=p.rotation_rate.value,
        secular_love_number=None if ks is None else float(ks),
        # inf (k2 without an out-of-phase part: no dissipation) is a value, told apart from "no anelastic
        # step" (NaN -> None): both were None, and the text then said nothing of a dissipation-free wobble.
        quality_factor=None if math.isnan(q) else q,
        period_sigma=sigma,
        contributions=contributions,
        observed=p.observed_chandler_period,
        period_sigma_linear=linear,
        valid_fraction=valid,
    )


@dataclass(frozen=True)
class Samples:
    """The Chandler model evaluated on many parameter sets at once (for sweeps).

    Attributes
    ----------
    steps : tuple of str
        The steps run, in order.
    rate : numpy.ndarray
        Final signed wobble frequency per member, rad/s (NaN where invalid).
    period : numpy.ndarray
        abs(2 pi / rate), s (NaN where invalid, inf for a sphere).
    step_periods : numpy.ndarray
        Shape (n_steps, *members): the period after each step, s.
    code : numpy.ndarray of int8
        0 for valid members, else a key of :data:`INVALID_REASONS`.
    quality_factor : numpy.ndarray
        Q per member (NaN without the anelastic step).
    """

    steps: tuple[str, ...]
    rate: np.ndarray
    period: np.ndarray
    step_periods: np.ndarray
    code: np.ndarray
    quality_factor: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        return self.code == 0


def chandler_samples(p: PlanetParameters, overrides: Mapping[str, object], model: str = "full") -> Samples:
    """Evaluate the Chandler model with some parameters replaced by arrays.

    Vectorised over members (no Python loop): this is what a Monte-Carlo sweep
    over a planet's uncertain parameters calls, chunk by chunk. Members whose
    parameters are unphysical are marked with a code, not raised.

    Parameters
    ----------
    p : PlanetParameters
        The nominal planet; its model steps decide which parameters matter.
    overrides : mapping
        Parameter name -> array of values (SI), broadcast together.
    model : str
        As for :func:`chandler_budget`.
    """
    _, steps = resolve_model(p, model)
    arrays, code, quality = _evaluate(ParameterValues(p.values(), overrides), steps)

    def period_of(rate):
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(code == 0, np.abs(2.0 * math.pi / rate), np.nan)

    return Samples(
        steps=steps,
        rate=np.where(code == 0, arrays[-1].rate, np.nan),
        period=period_of(arrays[-1].rate),
        step_periods=np.stack([period_of(s.rate) for s in arrays]),
        code=code,
        quality_factor=np.where(code == 0, quality, np.nan),
    )


def love_number_samples(p: PlanetParameters, overrides: Mapping[str, object], period) -> tuple[np.ndarray, np.ndarray]:
    """(Re k2, Im k2) at the forcing period ``period`` (s), vectorised like :func:`chandler_samples`.

    The catalogue's ``love_number_k2`` is k2 at ``love_number_k2_period``; at any other
    period the absorption-band model of IERS Conventions (2010) eq. 6.12 (Wahr & Bergen
    1986; Mathews et al. 2002) gives

        Re k2(f) = k2_ref + I cot(alpha pi/2) [(f_I/f)^alpha - (f_I/f_ref)^alpha],
        Im k2(f) = I (f_I/f)^alpha,

    which reduces to k2_ref at f = f_ref. A planet without the anelastic parameters is
    elastic: Re k2 = k2_ref and Im k2 = 0 at every period. Members whose parameters are
    out of range give NaN.

    Parameters
    ----------
    p : PlanetParameters
        The nominal planet (must give ``love_number_k2``).
    overrides : mapping
        Parameter name -> array of values (SI), broadcast together.
    period : float or array_like
        Forcing period, s (positive).
    """
    if p.love_number_k2 is None and "love_number_k2" not in overrides:
        raise InputError("love_number_k2", "not given", "a planet with a Love number k2")
    vals = ParameterValues(p.values(), overrides)
    period = np.asarray(period, dtype=float)
    if "anelastic" in available_steps(p):
        real, imag = vals.anelastic_k(2.0 * math.pi / period)
    else:
        real = vals["love_number_k2"] + np.zeros(np.broadcast_shapes(vals.shape, period.shape))
        imag = np.zeros_like(real)
    bad = vals.out_of_range | ~(period > 0)
    return np.where(bad, np.nan, real), np.where(bad, np.nan, imag)
