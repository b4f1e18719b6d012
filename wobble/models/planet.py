"""A planet as the Chandler model sees it: SI numbers with standard uncertainties.

Every field is a :class:`Measured` (value and one-sigma uncertainty, SI) or
``None`` when the description does not give it; which model steps can run
depends on which fields are present (see :mod:`wobble.models.chandler`).
Field names are the catalogue's parameter names (``data/bodies/*.toml``).

The figure is described by dimensionless numbers, so that the small
differences (C - A)/C never come from subtracting two large moments:

* ``dynamical_flattening`` H = (C - Abar)/C with Abar = (A + B)/2,
* ``j2`` = (C - Abar)/(M a^2) (unnormalised),
* ``polar_moment_factor`` C/(M a^2),
* ``c22``, ``s22`` fully normalised; J22 = sqrt(5/12) sqrt(C22^2 + S22^2) and
  B - A = 4 J22 M a^2 (principal axes of the equator).

Any two of H, J2, C/(Ma^2) fix the third (H = J2 / (C/Ma^2)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from wobble.numerics.floats import SQRT_HUGE, SQRT_TINY
from wobble.errors import InputError

__all__ = ["Measured", "PlanetParameters", "FIGURE_KEYS", "POSITIVE_KEYS", "SCALE_RANGE", "scales"]

FIGURE_KEYS = ("dynamical_flattening", "j2", "polar_moment_factor")
# Parameters that are positive by their nature (catalogue checks, sweep validity).
POSITIVE_KEYS = (
    "gm",
    "equatorial_radius",
    "gravitational_constant",
    "polar_moment_factor",
    "love_number_k2_period",
    "love_number_k2_imaginary_period",
    "fluid_core_equatorial_moment",
    "fluid_core_radius",
    "fluid_core_density",
    "observed_chandler_period",
    "orbit_semi_major_axis",
)


#: The range each scale a planet's values form must lie in (SI): the square root of the float range, so that the
#: uncertainty propagation's squares of them stay finite (PlanetParameters checks a file; the Chandler model's
#: members of a sweep or a Monte Carlo are marked invalid outside it).
SCALE_RANGE = (SQRT_TINY, SQRT_HUGE)


def scales(v):
    """(parameters, formula, values) of each combination the models form from a planet's values: the mapping
    ``v`` of :meth:`PlanetParameters.values` (scalars) or of a sweep's members (arrays), None where not given.

    In NumPy floats, so that an overflow gives inf rather than Python's OverflowError; the callers hold each
    to :data:`SCALE_RANGE` (a planet file refused, a sweep's member invalid) under ``np.errstate(all="ignore")``.
    """

    def get(key):
        return None if v.get(key) is None else np.asarray(v[key], dtype=np.float64)

    omega = get("rotation_rate")
    yield ("rotation_rate",), "Omega^2", omega * omega
    gm, a = get("gm"), get("equatorial_radius")
    if gm is not None and a is not None:
        # q = Omega^2 a^3/(GM): the centrifugal ratio, and 3 H C/(M a^2) over it the secular Love number k_s.
        yield ("gm", "equatorial_radius", "rotation_rate"), "Omega^2 a^3 / GM", omega * omega * a * a * a / gm
        yield ("gm", "equatorial_radius"), "M a^2 = (GM / G) a^2", gm / get("gravitational_constant") * a * a
    r, rho = get("fluid_core_radius"), get("fluid_core_density")
    if r is not None and rho is not None:
        yield ("fluid_core_radius", "fluid_core_density"), "A_f = (8 pi/15) rho R^5", 8 * np.pi / 15 * rho * r**5
    fcn = get("observed_fcn_period")
    if fcn is not None:
        # Compared with the model as a rate, 2 pi / T, and its variance: a period of 0 or 1e300 d ended in
        # ZeroDivisionError or OverflowError.
        yield ("observed_fcn_period",), "2 pi / T_FCN", 2 * np.pi / fcn
    orbit = get("orbit_semi_major_axis")
    if orbit is not None:
        yield ("orbit_semi_major_axis",), "a^3 of the orbit", orbit * orbit * orbit


@dataclass(frozen=True)
class Measured:
    """A value with its standard (one-sigma) uncertainty, in SI units."""

    value: float
    sigma: float = 0.0

    def __post_init__(self):
        # Plain floats, whatever numeric type came in (NumPy scalars print badly).
        object.__setattr__(self, "value", float(self.value))
        object.__setattr__(self, "sigma", float(self.sigma))
        if not math.isfinite(self.value):
            raise ValueError(f"non-finite value {self.value!r}")
        if not (math.isfinite(self.sigma) and self.sigma >= 0):
            raise ValueError(f"uncertainty must be finite and >= 0, got {self.sigma!r}")


@dataclass(frozen=True)
class PlanetParameters:
    """The physical description of a planet (SI: kg, m, s, rad).

    Attributes
    ----------
    name : str
        Identifier (``"earth"``).
    rotation_rate : Measured
        Sidereal spin rate Omega, rad/s (the sign gives the sense of rotation).
    dynamical_flattening, j2, polar_moment_factor : Measured or None
        The figure; see the module docstring. At least H, or two of the three.
    c22, s22 : Measured or None
        Fully normalised degree-2 sectoral coefficients (triaxiality).
    gm : Measured or None
        G M, m^3/s^2.
    equatorial_radius : Measured or None
        Reference radius a of J2 and the Love numbers, m.
    gravitational_constant : Measured
        G, m^3 kg^-1 s^-2 (turns G M into M for absolute moments).
    love_number_k2, love_number_k2_period : Measured or None
        Real part of the degree-2 potential Love number at the given period (s).
    love_number_k2_imaginary, love_number_k2_imaginary_period : Measured or None
        Its out-of-phase part (k2/Q for a small lag) at the given period (s).
    anelastic_exponent : Measured or None
        alpha of the power-law Q(frequency) ~ frequency^alpha.
    ocean_pole_tide_love_number : Measured or None
        The equilibrium ocean pole tide's increment of k2.
    fluid_core_equatorial_moment : Measured or None
        A_f of the liquid core, kg m^2; or else
    fluid_core_radius, fluid_core_density : Measured or None
        A uniform liquid core, m and kg/m^3: A_f = (8 pi/15) rho R^5.
    observed_chandler_period : Measured or None
        The observed period, s.
    obliquity : Measured or None
        Angle between the spin axis and the normal of the body's orbit, rad
        (for the forced precession, :mod:`wobble.models.precession`).
    orbit_semi_major_axis, orbit_eccentricity : Measured or None
        The body's heliocentric orbit (m; dimensionless): the Sun's orbit as
        the body sees it.
    observed_precession_rate : Measured or None
        The observed precession rate of the node of the equator, rad/s
        (negative: retrograde).
    observed_precession_includes_geodesic : Measured or None
        1 when the observed rate includes geodesic precession (IAU psi_A),
        0 when relativistic terms were modelled separately (default 1).
    core_compliance_beta, core_compliance_gamma : Measured or None
        Deformability of the liquid core (Sasao, Okubo & Saito 1980): the core's
        products of inertia per unit differential rotation (beta) and per unit
        mantle wobble (gamma), in units of A_f (:mod:`wobble.models.modes`).
    observed_fcn_period : Measured or None
        The observed free core nutation period in space, s (negative: retrograde).
    core_flattening_excess : Measured or None
        The liquid core's dynamical ellipticity over its hydrostatic value, minus
        one: e_f = e_f,hydrostatic (1 + excess). Not given: a hydrostatic core. A
        parameter of the inversion's FCN model (:mod:`wobble.models.inversion`);
        ``wobble modes`` reports the excess the observed FCN requires instead.
    """

    name: str
    rotation_rate: Measured
    gravitational_constant: Measured
    dynamical_flattening: Measured | None = None
    j2: Measured | None = None
    polar_moment_factor: Measured | None = None
    c22: Measured | None = None
    s22: Measured | None = None
    gm: Measured | None = None
    equatorial_radius: Measured | None = None
    love_number_k2: Measured | None = None
    love_number_k2_period: Measured | None = None
    love_number_k2_imaginary: Measured | None = None
    love_number_k2_imaginary_period: Measured | None = None
    anelastic_exponent: Measured | None = None
    ocean_pole_tide_love_number: Measured | None = None
    fluid_core_equatorial_moment: Measured | None = None
    fluid_core_radius: Measured | None = None
    fluid_core_density: Measured | None = None
    observed_chandler_period: Measured | None = None
    obliquity: Measured | None = None
    orbit_semi_major_axis: Measured | None = None
    orbit_eccentricity: Measured | None = None
    observed_precession_rate: Measured | None = None
    observed_precession_includes_geodesic: Measured | None = None
    core_compliance_beta: Measured | None = None
    core_compliance_gamma: Measured | None = None
    observed_fcn_period: Measured | None = None
    core_flattening_excess: Measured | None = None

    def __post_init__(self):
        given = [k for k in FIGURE_KEYS if getattr(self, k) is not None]
        if not given:
            raise InputError("figure", "none given", "dynamical_flattening (H), or two of H, j2, polar_moment_factor")
        if len(given) == 1 and given[0] != "dynamical_flattening":
            raise InputError(
                "figure", f"only {given[0]}", "dynamical_flattening (H), or two of H, j2, polar_moment_factor"
            )
        if self.rotation_rate.value == 0:
            raise InputError("rotation_rate", 0.0, "a non-zero spin rate (a body at rest does not wobble)")
        if self.polar_moment_factor is None and self.j2 is not None and self.dynamical_flattening is not None:
            # C/(M a^2) = J2 / H: H = 0 divided by zero, H < 0 with J2 > 0 gave a negative C/(M a^2).
            h, j2 = self.dynamical_flattening.value, self.j2.value
            if h == 0 or not 0 < j2 / h <= 2.0 / 3.0:
                raise InputError(
                    "polar_moment_factor",
                    f"C/(M a^2) = J2 / H = {j2:g} / {h:g}",
                    "a value in (0, 2/3] (all the mass in a thin shell at the surface gives 2/3)",
                )
        if len(given) == 3:
            self._check_figure_agrees()
        # H = (C - Abar)/C <= 1/2 for any body (A + B >= C); H = 1 made C/(M a^2) = j2/H meaningless downstream.
        if not self.flattening <= 0.5:
            raise InputError(
                "dynamical_flattening",
                f"H = {self.flattening:g}" + ("" if self.dynamical_flattening else " (j2 / polar_moment_factor)"),
                "H = (C - A)/C at most 1/2 (the moments' triangle inequality A + B >= C)",
            )
        self._check_core()
        self._check_scales()
        self._check_core_size()  # after the scales: A = (1 - H) C M a^2 overflowed for a radius of 1e300 m

    def _check_figure_agrees(self):
        """H, J2 and C/(M a^2) all given: H = J2 / (C/(M a^2)) within three combined sigmas and 0.1 % (values
        printed to four digits). The models take H and C/(M a^2) and never read J2, so a file whose J2 disagreed
        ran on H alone without a word (H = 0.01 beside J2/C = 0.00625 halved a Chandler period)."""
        h, j2, c = self.dynamical_flattening, self.j2, self.polar_moment_factor
        if c.value == 0:
            return  # refused as a scale below
        implied = j2.value / c.value
        sigma = math.hypot(h.sigma, math.hypot(j2.sigma, implied * c.sigma) / abs(c.value))
        if abs(h.value - implied) > 3.0 * sigma + 1e-3 * abs(implied):
            raise InputError(
                "dynamical_flattening, j2, polar_moment_factor",
                f"H = {h.value:.6g} but J2 / (C/(M a^2)) = {j2.value:.6g} / {c.value:.6g} = {implied:.6g}",
                "two of H, j2 and polar_moment_factor, or all three with H = J2 / (C/(M a^2)) within 3 sigma and 0.1 %",
            )

    def _check_scales(self):
        """Every combination of the given values that the models form is a normal float.

        Without it a planet file with a rotation period of 1e-300 s, a radius of 1e300 m or an orbit of 1e300 AU
        would end in ZeroDivisionError or OverflowError, NumPy's overflow warnings and k_s = inf printed, or a
        refusal that blames dynamical_flattening for k_s = 0.
        """
        # The square roots of the float range: the Monte Carlo's variances and the propagation's products square
        # these scales (a period of 1e150 h passed a check at the range itself, and the draws' variance overflowed).
        tiny, huge = SCALE_RANGE
        with np.errstate(all="ignore"):
            for keys, formula, value in scales(self.values()):
                if not (np.isfinite(value) and tiny <= abs(value) <= huge):
                    raise InputError(
                        ", ".join(keys),
                        f"{formula} = {float(value):.3g}",
                        f"values whose combinations lie from {tiny:.2g} to {huge:.2g} in SI units (their squares, "
                        "which the uncertainty propagation forms, must be finite floats)",
                    )

    def _check_core(self):
        if self.fluid_core_equatorial_moment is not None and (
            self.fluid_core_radius is not None or self.fluid_core_density is not None
        ):
            raise InputError(
                "fluid_core",
                "fluid_core_equatorial_moment and fluid_core_radius/density",
                "either the core's equatorial moment or its radius and density, not both",
            )
        if (self.fluid_core_radius is None) != (self.fluid_core_density is None):
            raise InputError(
                "fluid_core", "only one of radius and density", "both fluid_core_radius and fluid_core_density"
            )

    def _check_core_size(self):
        """A liquid core inside the planet: its radius below the planet's, its moment below A."""
        radius = self.equatorial_radius.value if self.equatorial_radius is not None else None
        if self.fluid_core_radius is not None and radius is not None and not self.fluid_core_radius.value < radius:
            raise InputError(
                "fluid_core_radius",
                f"{self.fluid_core_radius.value / 1e3:g} km",
                f"a radius smaller than the planet's equatorial radius ({radius / 1e3:g} km)",
            )
        core, equatorial = self.fluid_core_moment, self._equatorial_moment()
        if core is not None and equatorial is not None and not core < equatorial:
            # The model refused it later as "A_f/C = 5.4 ... (A_f < A)", naming neither the file's keys nor A.
            keys = (
                "fluid_core_equatorial_moment"
                if self.fluid_core_equatorial_moment is not None
                else ("fluid_core_radius, fluid_core_density")
            )
            raise InputError(
                keys,
                f"the core's moment A_f = {core:.4g} kg m2, {core / equatorial:.3g} times the planet's A = "
                f"{equatorial:.4g} kg m2",
                "a liquid core smaller than the planet that holds it (A_f < A = (1 - H) C, C = C/(M a^2) GM/G a^2)",
            )

    def _equatorial_moment(self) -> float | None:
        """A = (1 - H) C in kg m^2, when the file gives C/(M a^2) (or J2 and H), GM and the radius; else None."""
        c = self.c_factor
        if c is None or self.gm is None or self.equatorial_radius is None:
            return None
        try:
            mass = self.gm.value / self.gravitational_constant.value
            return (1.0 - self.flattening) * c * mass * self.equatorial_radius.value**2
        except (OverflowError, ZeroDivisionError):  # past the float range: nothing to compare the core with
            return None

    def values(self) -> dict[str, float | None]:
        """Every parameter's value (SI) by name, None where not given."""
        out: dict[str, float | None] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, Measured):
                out[f.name] = v.value
            elif f.name != "name":
                out[f.name] = None
        return out

    # -- the figure, in units of C and of M a^2, without cancellation ---------------

    def measured_fields(self) -> dict[str, Measured]:
        """All given parameters with a non-zero uncertainty (for error propagation).

        Observations other than the Chandler period (``observed_fcn_period``, ...)
        are left out: they are never model inputs, so nothing propagates or draws
        them. (``observed_chandler_period`` stays, as its callers expect.)
        """
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name.startswith("observed_") and f.name != "observed_chandler_period":
                continue
            if isinstance(v, Measured) and v.sigma > 0:
                out[f.name] = v
        return out

    # Scalar views used to decide which model steps a planet supports; the
    # vectorised evaluation lives in wobble.models.chandler.

    @property
    def flattening(self) -> float:
        """H = (C - Abar)/C."""
        if self.dynamical_flattening is not None:
            return self.dynamical_flattening.value
        return self.j2.value / self.polar_moment_factor.value

    @property
    def c_factor(self) -> float | None:
        """C/(M a^2), or None when only H is known."""
        if self.polar_moment_factor is not None:
            return self.polar_moment_factor.value
        if self.j2 is not None and self.dynamical_flattening is not None:
            return self.j2.value / self.dynamical_flattening.value
        return None

    @property
    def fluid_core_moment(self) -> float | None:
        """A_f in kg m^2 (uniform sphere when given by radius and density)."""
        if self.fluid_core_equatorial_moment is not None:
            return self.fluid_core_equatorial_moment.value
        if self.fluid_core_radius is not None:
            return 8.0 * math.pi / 15.0 * self.fluid_core_density.value * self.fluid_core_radius.value**5
        return None
