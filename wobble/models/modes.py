"""Rotational normal modes of a planet with a liquid core: Chandler wobble and free core nutation (SI).

The linearised Liouville equations of a deformable mantle enclosing a liquid
core (Sasao, Okubo & Saito 1980; Mathews, Buffett, Herring & Shapiro 1991;
Mathews, Herring & Buffett 2002). Seen from the mantle, which turns at
Omega (m1, m2, 1), the whole planet obeys Euler's equation tau = dH/dt + w x H
(notes sec. 5.5) with no torque, and the core, turning at Omega (m + m_f),
feels only the pressure of its flattened boundary. With H = I w + A_f Omega m_f,
the deformation's products of inertia c = D m + xi A m_f (D = k2 a^5 Omega^2/(3G),
as in the Chandler budget) and c_f/A_f = gamma m + beta m_f, in units of C:

    (A + D) m1' + F mf1' + Omega [(C - B - D) m2 - F mf2] = 0
    (B + D) m2' + F mf2' - Omega [(C - A - D) m1 - F mf1] = 0           (M)
    (1 + gamma) m1' + (1 + beta) mf1' - Omega (1 + e_f) mf2 = 0
    (1 + gamma) m2' + (1 + beta) mf2' + Omega (1 + e_f) mf1 = 0

with F = A_f + xi A = A_f (1 + gamma) (reciprocity xi A = gamma A_f, Sasao et al.
1980) and e_f = (C_f - A_f)/A_f the core's dynamical ellipticity. For A = B this
is the familiar pair (sigma in cycles per sidereal day, e^{i sigma Omega t})

    (sigma - e + (1 + sigma) kappa) m + (1 + sigma)(A_f/A + xi) m_f = 0
    sigma (1 + gamma) m + (1 + e_f + sigma (1 + beta)) m_f = 0,

whose roots are the Chandler wobble, sigma ~ (A/A_m)(e - kappa), prograde, and
the free core nutation, sigma ~ -1 - (A/A_m)(e_f - beta), retrograde and nearly
diurnal in the planet's frame; in space the FCN turns at (sigma + 1) Omega.

The equations are solved as a 4 x 4 real eigenproblem, so a triaxial mantle
(A != B) is exact. Mantle anelasticity makes k2 depend on the frequency; each
mode is solved with k2 at its own frequency (the Chandler budget's model,
IERS Conventions 2010 eq. 6.12), by iteration.

The tie to the Chandler budget (:mod:`wobble.models.chandler`): with the
coupling off (e_f = beta = gamma = 0) the core rows give m + m_f fixed in
space, and the mantle rows decouple *exactly* to
sigma^2 = (C - A - D)(C - B - D)/((A_m + D)(B_m + D)), the budget's equation (1).
Dropping the deformation's own angular momentum D m' as well (a product of two
small quantities) gives the classic first-order formula, reported beside it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from wobble.errors import InputError
from wobble.models import chandler
from wobble.models.planet import PlanetParameters
from wobble.numerics.roots import bracketed_root

__all__ = [
    "MODES",
    "Mode",
    "NormalModes",
    "find_mode",
    "mode_rates",
    "mode_rates_samples",
    "normal_modes",
    "required_core_ellipticity",
    "love_number_at",
]

MODES = ("CW", "FCN")
MODE_LABELS = {
    "CW": "Chandler wobble",
    "FCN": "free core nutation",
}
_K_TOL = 1e-14
_K_MAX = 100


def love_number_at(p: PlanetParameters, rate: float) -> float:
    """Real k2 (with the ocean term) at the frequency ``abs(rate)``, as the budget's last step uses it.

    0 for a planet without k2 (rigid); the anelastic model of IERS Conventions
    (2010) eq. 6.12 where the catalogue has its parameters.
    """
    return _love_number_function(p)(rate)


def _love_number_function(p: PlanetParameters):
    """``rate -> Re k2`` of :func:`love_number_at` for one planet, its parameters read once.

    The mode iteration calls it a few times per mode and per perturbed planet; building
    the parameter arrays on every call cost more than the eigenproblem.
    """
    steps = chandler.available_steps(p)
    ocean = p.ocean_pole_tide_love_number.value if "ocean_pole_tide" in steps else 0.0
    if "anelastic" in steps:
        k_at = chandler.anelastic_love_number_function(p)
        return lambda rate: k_at(rate)[0] + ocean
    if "elastic" in steps:
        k = p.love_number_k2.value + ocean
        return lambda rate: k
    return lambda rate: 0.0


def _matrices(ratios, k, e_f, beta, gamma, coupled, second_order):
    ca, cb = ratios["c_minus_a"], ratios["c_minus_b"]
    d = k * (ratios["deformation_per_k"] or 0.0)
    af = ratios["core"] or 0.0
    if not coupled:
        e_f = beta = gamma = 0.0
    f = af * (1.0 + gamma)
    a_, b_ = 1.0 - ca, 1.0 - cb
    carry = d if second_order else 0.0
    m = np.array(
        [
            [a_ + carry, 0.0, f, 0.0],
            [0.0, b_ + carry, 0.0, f],
            [1.0 + gamma, 0.0, 1.0 + beta, 0.0],
            [0.0, 1.0 + gamma, 0.0, 1.0 + beta],
        ]
    )
    kmat = np.array(
        [
            [0.0, cb - d, 0.0, -f],
            [-(ca - d), 0.0, f, 0.0],
            [0.0, 0.0, 0.0, -(1.0 + e_f)],
            [0.0, 0.0, 1.0 + e_f, 0.0],
        ]
    )
    return m, kmat


def _signed_frequencies(m, kmat, spin):
    """Signed mode frequencies (rad/s; positive = prograde) of M x' + Omega K x = 0."""
    lam, vec = np.linalg.eig(-spin * np.linalg.solve(m, kmat))
    out = []
    for i in np.flatnonzero(lam.imag > 0):
        v = vec[:, i]
        # (1, -i) is prograde for e^{+i w t}: Re gives (cos, sin).
        s = (np.conj(v[0]) * v[1] + np.conj(v[2]) * v[3]).imag
        out.append(lam[i].imag if s < 0 else -lam[i].imag)
    return np.array(out)


def mode_rates(
    p: PlanetParameters, e_f: float, *, coupled: bool = True, second_order: bool = True, which: tuple[str, ...] = MODES
) -> dict[str, tuple[float, float]]:
    """Signed terrestrial-frame rates (rad/s) of the CW and the FCN, each with k2 at its own frequency.

    Parameters
    ----------
    p : PlanetParameters
        The planet (figure, k2 and its frequency dependence, the liquid core,
        beta and gamma).
    e_f : float
        The core's dynamical ellipticity (C_f - A_f)/A_f.
    coupled : bool
        False turns the core-mantle coupling off (e_f = beta = gamma = 0): the
        core keeps its orientation in space and only the mantle wobbles.
    second_order : bool
        False drops the deformation's own angular momentum D m' (the classic
        first-order formula; equation (1) of the budget keeps it).
    which : tuple of str
        The modes wanted.

    Returns
    -------
    dict
        ``{"CW": (rate, k2), "FCN": (rate, k2)}``; the FCN only with a liquid core
        and only when coupled. Rates have the sign of the spin when prograde.
    """
    ratios = chandler.inertia_ratios(p)
    # A planet spinning the other way is the mirror image: solve for |Omega|, flip the rates.
    sign = 1.0 if p.rotation_rate.value > 0 else -1.0
    spin = abs(p.rotation_rate.value)
    beta = p.core_compliance_beta.value if p.core_compliance_beta else 0.0
    gamma = p.core_compliance_gamma.value if p.core_compliance_gamma else 0.0
    guesses = {}
    if "CW" in which:
        # The budget's check first: a spin about the intermediate axis has no periodic wobble (and no
        # real guess), a core as large as the equatorial moment no mantle to wobble.
        chandler.free_wobble_rate(spin, ratios["c_minus_a"], ratios["c_minus_b"], core=ratios["core"] or 0.0)
        guesses["CW"] = _cw_guess(ratios, spin)
    if ratios["core"] is not None and coupled and "FCN" in which:
        guesses["FCN"] = -spin * (1.0 + e_f / (1.0 - ratios["core"]))
    out = {}
    k_at = _love_number_function(p)
    for name, rate in guesses.items():
        step = math.inf
        for _ in range(_K_MAX):
            k = k_at(rate)
            if not math.isfinite(k):
                raise chandler.dispersion_error(p, k)
            m, kmat = _matrices(ratios, k, e_f, beta, gamma, coupled, second_order)
            freqs = _signed_frequencies(m, kmat, spin)
            new = float(freqs[np.argmin(np.abs(freqs - rate))])
            # Converged, or stalled at the rounding floor of the eigensolver.
            last, step = step, abs(new - rate)
            rate = new
            if step <= _K_TOL * abs(new) or (step >= last and step <= 1e-12 * abs(new)):
                break
        else:  # pragma: no cover - the contraction factor is ~1e-3
            raise InputError(
                "anelastic_exponent", p.anelastic_exponent, f"parameters for which the {name} frequency converges"
            )
        out[name] = (sign * rate, k_at(rate))
    return out


def _biquadratic_frequencies(a_, b_, f, g, bt, a, b, e):
    """|omega|/Omega of the two modes of M x' + Omega K x = 0 in closed form (arrays).

    For x = v e^{lambda t} the determinant of lambda M + Omega K, with the state
    ordered (m1, mf1 | m2, mf2), is the 2 x 2 block determinant
    det(s D1 M2 - Omega^2 N)/D1 with s = lambda^2, M1 = [[A', F], [G, Bt]],
    M2 = [[B', F], [G, Bt]], D1 = det M1 and N = Q2 adj(M1) Q1/Omega^2 (Q1, Q2 the
    coupling blocks of K): a *quadratic in s*, exact for a triaxial mantle (A != B).
    Both roots are negative for an oscillating system, s = -omega^2. The stable
    quadratic formula gives the small (Chandler) root without cancellation:
    its product with the large root is the constant term, det N = a b E^2 D1.

    Parameters are the matrix entries of :func:`_matrices` (units of C): a_ = A' =
    1 - (C-A)/C + D, b_ = B', f = F, g = 1 + gamma, bt = 1 + beta, a = (C-A)/C - D,
    b = (C-B)/C - D, e = 1 + e_f.

    Returns
    -------
    small, large : numpy.ndarray
        omega/Omega of the Chandler-like and FCN-like modes (NaN where a root is
        not a real frequency: no oscillation).
    """
    d1 = a_ * bt - f * g
    d2 = b_ * bt - f * g
    n00 = -b * (a * bt + f * g)
    n01 = f * (a * bt + f * g) - e * f * (a + a_)
    n10 = -e * g * b
    n11 = e * g * f - e * e * a_
    # det(s X - Y) with X = D1 M2, Y = N (Omega = 1): s^2 det X - s tr(adj-pairing) + det Y.
    qa = d1 * d1 * d2
    qb = -d1 * (b_ * n11 + bt * n00 - f * n10 - g * n01)
    qc = a * b * e * e * d1
    disc = qb * qb - 4.0 * qa * qc
    with np.errstate(invalid="ignore", divide="ignore"):
        root = np.sqrt(disc)
        q = -0.5 * (qb + np.copysign(root, qb))
        s_large = q / qa
        s_small = qc / q
        ok = (disc >= 0) & (s_large < 0) & (s_small < 0)
        return np.where(ok, np.sqrt(-s_small), np.nan), np.where(ok, np.sqrt(-s_large), np.nan)


def mode_rates_samples(
    p: PlanetParameters,
    overrides,
    e_f=0.0,
    *,
    coupled: bool = True,
    second_order: bool = True,
    which: tuple[str, ...] = MODES,
    values=None,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """:func:`mode_rates` vectorised over members: some parameters (and e_f) as arrays.

    The same Liouville equations (M), solved in closed form instead of as a 4 x 4
    eigenproblem per member (:func:`_biquadratic_frequencies`: the characteristic
    polynomial is a quadratic in the square of the frequency, exactly, also for
    A != B), and the same iteration of each mode's k2 at its own frequency, on all
    members at once. With the coupling off, the Chandler root is the Chandler
    budget's equation (1) (:func:`wobble.models.chandler.chandler_samples`, last step).

    Members get NaN where the model has no free wobble, as the budget flags them
    (:data:`wobble.models.chandler.INVALID_REASONS`): a parameter outside its
    physical range, a liquid core as large as the equatorial moment, C the
    intermediate moment, k2 at or above the secular Love number, no convergence of
    k2 at the mode's frequency; and where a root is not a real frequency.

    Parameters
    ----------
    p : PlanetParameters
        The nominal planet (which model steps apply: elastic, ocean, anelastic).
    overrides : mapping
        Parameter name -> array of values (SI), broadcast together (as for
        :func:`wobble.models.chandler.chandler_samples`).
    e_f : float or array_like
        The core's dynamical ellipticity of each member (unused when not coupled).
    coupled, second_order, which
        As for :func:`mode_rates`.
    values : optional
        The parameter arrays already built from ``p`` and ``overrides``
        (:class:`wobble.models.chandler.ParameterValues`), shared by callers that evaluate
        several models of one batch.

    Returns
    -------
    dict
        ``{"CW": (rate, k2), "FCN": (rate, k2)}`` (arrays; rad/s signed like the spin
        when prograde); the FCN only with a liquid core and only when coupled.
    """
    vals = chandler.ParameterValues(p.values(), overrides) if values is None else values
    e_f = np.asarray(e_f, dtype=float)
    shape = np.broadcast_shapes(vals.shape, e_f.shape)
    zeros = np.zeros(shape)
    omega = vals["rotation_rate"] + zeros
    sign = np.where(omega > 0, 1.0, -1.0)
    spin = np.abs(omega)
    ca, cb = (np.asarray(x) + zeros for x in vals.equatorial_excess())
    steps = chandler.available_steps(p)
    scaled = "elastic" in steps
    d_per_k = vals.deformation(1.0) + zeros if scaled else zeros
    has_core = p.fluid_core_moment is not None and scaled
    core = vals.core_over_c() + zeros if has_core else zeros
    if coupled:
        beta = vals["core_compliance_beta"] + zeros if vals["core_compliance_beta"] is not None else zeros
        gamma = vals["core_compliance_gamma"] + zeros if vals["core_compliance_gamma"] is not None else zeros
        ef = e_f + zeros
    else:
        ef, beta, gamma = zeros, zeros, zeros
    ocean = vals["ocean_pole_tide_love_number"] + zeros if "ocean_pole_tide" in steps else zeros
    # The budget's invalid members: out of range (code 5), the core as large as A or B (code 2).
    bad = vals.out_of_range | ~np.isfinite(ef) | ~((1.0 - ca - core > 0) & (1.0 - cb - core > 0))
    k_s = vals.secular_love_number() if scaled else None

    def love(rate):
        if "anelastic" in steps:
            with np.errstate(invalid="ignore", divide="ignore"):
                return vals.anelastic_k(rate)[0] + ocean
        if "elastic" in steps:
            return vals["love_number_k2"] + ocean
        return zeros

    def frequencies(k):
        d = k * d_per_k
        carry = d if second_order else zeros
        if coupled:
            f = core * (1.0 + gamma)
            small, large = _biquadratic_frequencies(
                1.0 - ca + carry, 1.0 - cb + carry, f, 1.0 + gamma, 1.0 + beta, ca - d, cb - d, 1.0 + ef
            )
        else:
            # Coupling off: the mantle rows decouple, and the small root is the budget's
            # equation (1), sigma^2 = (C - A - D)(C - B - D)/((A_m + D)(B_m + D)) (units of C).
            with np.errstate(invalid="ignore", divide="ignore"):
                small = np.sqrt((ca - d) * (cb - d) / ((1.0 - ca - core + carry) * (1.0 - cb - core + carry)))
            large = zeros
        # No free wobble where C is the intermediate moment (code 1) or k2 >= k_s (code 3):
        # the deformation's D then reaches the smaller of C - A, C - B.
        unstable = (ca - d) * (cb - d) < 0
        if k_s is not None:
            unstable |= (ca > 0) & (cb > 0) & (d >= np.minimum(ca, cb))
        small = np.where(unstable, np.nan, small)
        # The Chandler mode turns with the spin for C largest (oblate), against it for C
        # smallest; the FCN is retrograde, near -Omega (Sasao, Okubo & Saito 1980).
        return {"CW": np.where(ca - d > 0, 1.0, -1.0) * spin * small, "FCN": np.where(unstable, np.nan, -spin * large)}

    guesses = {}
    if "CW" in which:
        with np.errstate(invalid="ignore"):
            guesses["CW"] = spin * np.sqrt(np.abs(ca * cb)) / (1.0 - core) * np.where(ca > 0, 1.0, -1.0)
    if has_core and coupled and "FCN" in which:
        guesses["FCN"] = -spin * (1.0 + ef / (1.0 - core))
    out = {}
    for name, guess in guesses.items():
        rate = _own_frequency(lambda x, name=name: frequencies(love(x))[name], np.where(bad, np.nan, guess))
        out[name] = (sign * rate, love(rate))
    return out


def _own_frequency(update, x0):
    """Solve x = update(x) (a mode's frequency with k2 at that frequency) for every member.

    update is a contraction (factor 1e-2 to 1e-4), so the fixed-point iteration
    of :func:`mode_rates` converges; a secant step on g(x) = update(x) - x (as the
    Chandler budget's, :func:`wobble.models.chandler._anelastic_fixed_point`) gets
    there in three or four evaluations instead of seven. Stops at |g| <= 1e-14 |x|
    or at the rounding floor; members that do not converge get NaN.
    """
    f0 = update(x0)
    failed = ~np.isfinite(f0)
    done = failed.copy()
    x1 = np.where(done, x0, f0)
    g0 = f0 - x0
    for _ in range(_K_MAX):
        f1 = update(x1)
        g1 = f1 - x1
        failed |= ~done & ~np.isfinite(f1)
        with np.errstate(invalid="ignore", divide="ignore"):
            converged = np.abs(g1) <= _K_TOL * np.abs(f1)
            stalled = (np.abs(g1) >= np.abs(g0)) & (np.abs(g1) <= 1e-12 * np.abs(f1))
            secant = x1 - g1 * (x1 - x0) / (g1 - g0)
        new_done = done | converged | stalled | failed
        # Converged members keep the last evaluation (as the per-member iteration does).
        result = np.where(done, x1, f1)
        if np.all(new_done):
            return np.where(failed, np.nan, result)
        usable = np.isfinite(secant) & (np.sign(secant) == np.sign(x1))
        x0, g0 = x1, g1
        x1 = np.where(new_done, result, np.where(usable, secant, f1))
        done = new_done
    return np.where(done & ~failed, x1, np.nan)


def _cw_guess(ratios, spin):
    core = ratios["core"] or 0.0
    return spin * math.sqrt(ratios["c_minus_a"] * ratios["c_minus_b"]) / (1.0 - core)


def _fcn_space_rate(p, e_f):
    return mode_rates(p, e_f, which=("FCN",))["FCN"][0] + p.rotation_rate.value


def required_core_ellipticity(p: PlanetParameters, observed_space_rate: float, guess: float) -> float:
    """The e_f for which the FCN turns in space at ``observed_space_rate`` (rad/s, signed).

    An output, never an input: the root of FCN(e_f) = observed, bracketed
    and found to the last bits (:func:`wobble.numerics.roots.bracketed_root`),
    so that putting it back gives the observed period exactly.
    """
    lo, hi = 0.2 * guess, 5.0 * guess
    rates = [_fcn_space_rate(p, lo), _fcn_space_rate(p, hi)]
    f_lo, f_hi = (r - observed_space_rate for r in rates)
    if not f_lo * f_hi <= 0:  # no sign change, or no FCN at an end (NaN)
        # The periods the model does reach say which input is off: often not the period but the
        # planet it is compared with (a rotation rate far from the one the period was measured on).
        reach = ""
        if all(math.isfinite(r) for r in rates):
            days = [f"{2 * math.pi / r / 86400:.6g} d" if r != 0 else "an infinite period" for r in rates]
            span, turn = (days[0] if days[0] == days[1] else f"{days[0]} to {days[1]}"), ""
            if rates[0] * rates[1] < 0:  # the rate passes through 0: the periods reached are the two long ends
                span = f"periods beyond {days[0]} and beyond {days[1]}"
                turn = " (between the two the mode changes sense through an infinite period)"
            reach = (
                f"; it reaches {span} there, with this planet's rotation rate {p.rotation_rate.value:.6g} rad/s{turn}"
            )
        raise InputError(
            "observed_fcn_period",
            f"{2 * math.pi / observed_space_rate / 86400:.6g} d",
            f"a period this model reaches with e_f between {lo:.3g} and {hi:.3g}{reach}",
        )
    return bracketed_root(lambda e: _fcn_space_rate(p, e) - observed_space_rate, lo, hi, f_lo=f_lo, f_hi=f_hi)


@dataclass(frozen=True)
class Mode:
    """One free mode in one frame (SI).

    Attributes
    ----------
    name : str
        ``CW`` or ``FCN``.
    frame : str
        ``terrestrial`` (seen from the mantle) or ``celestial`` (seen from space).
    rate : float
        Frequency about the planet's axis, rad/s (the spin's sign when prograde).
    rate_sigma : float
        One-sigma uncertainty of ``rate`` (linear propagation), rad/s.
    love_number : float
        Real k2 used (at this mode's frequency in the planet's frame).
    observed_period, observed_sigma : float or None
        The observed signed period and its uncertainty, s.
    """

    name: str
    frame: str
    rate: float
    rate_sigma: float
    love_number: float
    observed_period: float | None = None
    observed_sigma: float | None = None
    spin_sign: float = 1.0

    @property
    def period(self) -> float:
        """Period in s, signed relative to the spin (negative: retrograde)."""
        return self.spin_sign * 2.0 * math.pi / self.rate

    @property
    def period_sigma(self) -> float:
        """One-sigma uncertainty of the period, s."""
        return 2.0 * math.pi * self.rate_sigma / self.rate**2

    @property
    def sense(self) -> str:
        """``prograde`` (with the spin) or ``retrograde``."""
        return "prograde" if self.rate * self.spin_sign > 0 else "retrograde"


def find_mode(modes, name: str, frame: str = "terrestrial"):
    """The entry of ``modes`` (anything with ``name`` and ``frame``) that is mode ``name`` in ``frame``;
    an InputError listing those there are otherwise."""
    for m in modes:
        if m.name == name and m.frame == frame:
            return m
    raise InputError("mode", f"{name} ({frame})", ", ".join(f"{m.name} ({m.frame})" for m in modes))


@dataclass(frozen=True)
class NormalModes:
    """A planet's free modes, the core flattening both ways, and the tie to the Chandler budget (SI).

    Attributes
    ----------
    name : str
    spin_rate : float
        Omega, rad/s.
    modes : tuple of Mode
        The modes asked for (default: all): CW (terrestrial), and with a liquid core
        FCN (terrestrial, celestial), from the hydrostatic core flattening (a forward
        prediction).
    computed : tuple of Mode
        Every mode the parameters support, whichever were asked for: the physics
        (coupling, periods, uncertainties) is always that of the whole planet.
    core_ellipticity_hydrostatic : float or None
        e_f used for the forward prediction.
    core_ellipticity_hydrostatic_sigma : float or None
        Its one-sigma uncertainty, when it is computed from the planet's own
        uncertain parameters (0 for a fixed profile such as PREM).
    core_ellipticity_required, core_ellipticity_required_sigma : float or None
        The e_f the observed FCN period requires, and its one-sigma uncertainty
        (observed period and model parameters, linear propagation).
    fcn_period_required : float or None
        The FCN period in space with the required e_f put back, s (the round trip).
    cw_rate_uncoupled : float
        CW rate with the core-mantle coupling off (same Liouville equations), rad/s.
    cw_rate_first_order : float
        CW rate with the coupling off and D m' dropped: the classic first-order formula.
    core_flattening_excess_sigma : float or None
        One-sigma uncertainty of required/hydrostatic - 1 (shared parameters correlated).
    contributions : dict
        Signed change, for +1 sigma of each parameter, of each mode's rate (rad/s; the FCN's
        in both frames, ``FCN`` and ``FCN_celestial``), of the required e_f, the hydrostatic
        e_f and the excess.
    """

    name: str
    spin_rate: float
    modes: tuple[Mode, ...]
    core_ellipticity_hydrostatic: float | None
    core_ellipticity_hydrostatic_sigma: float | None
    core_ellipticity_required: float | None
    core_ellipticity_required_sigma: float | None
    fcn_period_required: float | None
    cw_rate_uncoupled: float
    cw_rate_first_order: float
    core_flattening_excess_sigma: float | None
    contributions: dict
    computed: tuple[Mode, ...] = ()

    def mode(self, name: str, frame: str = "terrestrial") -> Mode:
        """The mode ``name`` in ``frame`` (any computed mode, asked for or not)."""
        return find_mode(self.computed or self.modes, name, frame)

    @property
    def core_flattening_excess(self) -> float | None:
        """Required over hydrostatic e_f, minus one."""
        if self.core_ellipticity_required is None or not self.core_ellipticity_hydrostatic:
            return None
        return self.core_ellipticity_required / self.core_ellipticity_hydrostatic - 1.0


def _requirements(p: PlanetParameters, e_f):
    """Missing parameters of the FCN (empty when it can be computed)."""
    missing = []
    if p.fluid_core_moment is None:
        missing.append("fluid_core_equatorial_moment (or fluid_core_radius and fluid_core_density)")
    if chandler.inertia_ratios(p)["deformation_per_k"] is None:
        missing.append("gm, equatorial_radius and polar_moment_factor (the absolute scale)")
    for key in ("core_compliance_beta", "core_compliance_gamma"):
        if getattr(p, key) is None:
            missing.append(key)
    if e_f is None:
        missing.append("core_dynamical_ellipticity (a density profile with a liquid core)")
    return missing


def supported_modes(p: PlanetParameters, e_f) -> tuple[str, ...]:
    """The modes this planet's parameters support."""
    return ("CW", "FCN") if not _requirements(p, e_f) else ("CW",)


def _perturbed(p: PlanetParameters):
    """(key, sigma, +1 sigma planet, -1 sigma planet) for every uncertain parameter the modes use."""
    skip = ("observed_chandler_period", "observed_fcn_period")
    for key, m in p.measured_fields().items():
        if key in skip:
            continue
        try:
            yield (
                key,
                replace(p, **{key: replace(m, value=m.value + m.sigma)}),
                replace(p, **{key: replace(m, value=m.value - m.sigma)}),
            )
        except InputError:  # pragma: no cover - a +-1 sigma step outside the physical range
            continue


def normal_modes(p: PlanetParameters, core_ellipticity, modes: tuple[str, ...] | None = None) -> NormalModes:
    """The free modes of a planet, the FCN both ways, and the budget tie.

    Parameters
    ----------
    p : PlanetParameters
        The planet.
    core_ellipticity : float, callable or None
        The hydrostatic e_f of the liquid core (:mod:`wobble.models.hydrostatic`),
        or a function of the planet that computes it, so that the planet's
        uncertainties propagate into it (e.g. a profile rebuilt from the
        catalogued core).
    modes : tuple of str, optional
        The modes to return in ``modes``: ``("CW",)``, ``("FCN",)``, ``("CW", "FCN")``;
        default: every mode the parameters support. The choice never changes the
        physics: every supported mode is computed (the Chandler wobble coupled to the
        liquid core whenever the FCN can be computed) and kept in ``computed``.
        A requested mode whose parameters are missing is an InputError naming them.
    """
    e_of = core_ellipticity if callable(core_ellipticity) else None
    if e_of is not None:
        core_ellipticity = e_of(p)
    supported = supported_modes(p, core_ellipticity)
    wanted = supported if modes is None else tuple(modes)
    for name in wanted:
        if name not in MODES:
            raise InputError("mode", name, f"one of {', '.join(MODES)}")
    if "FCN" in wanted:
        missing = _requirements(p, core_ellipticity)
        if missing:
            raise InputError(
                missing[0].split(" ")[0], "not given", f"the free core nutation needs {', '.join(missing)}"
            )
    with_fcn = "FCN" in supported
    e_f = core_ellipticity if with_fcn else 0.0
    spin = p.rotation_rate.value
    rates = mode_rates(p, e_f, coupled=with_fcn)
    sign = 1.0 if spin > 0 else -1.0
    obs_fcn = p.observed_fcn_period if with_fcn else None
    if obs_fcn is not None:
        # Catalogued periods are signed relative to the spin (negative: retrograde); rates are absolute.
        obs_fcn = replace(obs_fcn, value=sign * obs_fcn.value)
    required = required_core_ellipticity(p, 2 * math.pi / obs_fcn.value, e_f) if obs_fcn is not None else None
    contributions = _contributions(p, e_f, with_fcn, obs_fcn, required, e_of if with_fcn else None)
    sig = {
        k: math.sqrt(sum(v[k] ** 2 for v in contributions.values()))
        for k in ("CW", "FCN", "FCN_celestial", "e_f", "e_hyd", "excess")
    }
    cw_obs = p.observed_chandler_period
    # Observed periods are catalogued relative to the spin (the Chandler period unsigned, prograde).
    shown = p.observed_fcn_period if with_fcn else None
    out = [Mode("CW", "terrestrial", rates["CW"][0], sig["CW"], rates["CW"][1], *_obs(cw_obs), spin_sign=sign)]
    if with_fcn:
        fcn, k_fcn = rates["FCN"]
        out.append(Mode("FCN", "terrestrial", fcn, sig["FCN"], k_fcn, *_terrestrial(shown, spin), spin_sign=sign))
        out.append(Mode("FCN", "celestial", fcn + spin, sig["FCN_celestial"], k_fcn, *_obs(shown), spin_sign=sign))
    round_trip = sign * 2 * math.pi / _fcn_space_rate(p, required) if required is not None else None
    return NormalModes(
        name=p.name,
        spin_rate=spin,
        modes=tuple(m for m in out if m.name in wanted),
        core_ellipticity_hydrostatic=core_ellipticity if with_fcn else None,
        core_ellipticity_hydrostatic_sigma=sig["e_hyd"] if with_fcn else None,
        core_ellipticity_required=required,
        core_ellipticity_required_sigma=sig["e_f"] if required is not None else None,
        fcn_period_required=round_trip,
        cw_rate_uncoupled=mode_rates(p, 0.0, coupled=False)["CW"][0],
        cw_rate_first_order=mode_rates(p, 0.0, coupled=False, second_order=False)["CW"][0],
        core_flattening_excess_sigma=sig["excess"] if required is not None else None,
        contributions=contributions,
        computed=tuple(out),
    )


def _obs(m):
    return (None, None) if m is None else (m.value, m.sigma)


def _terrestrial(m, spin):
    """An observed space-frame period (signed relative to the spin) seen from the planet: rate - Omega."""
    if m is None:
        return None, None
    sign = 1.0 if spin > 0 else -1.0
    rate = sign * 2 * math.pi / m.value - spin
    if rate == 0:  # a prograde sidereal day in space stands still on the planet
        raise InputError(
            "observed_fcn_period",
            f"{m.value / 86400:.6g} d",
            "a period other than the planet's sidereal day (that mode would stand still in the planet's frame)",
        )
    rate_sigma = 2 * math.pi * m.sigma / m.value**2
    return sign * 2 * math.pi / rate, 2 * math.pi * rate_sigma / rate**2


def _contributions(p, e_f, with_fcn, obs_fcn, required, e_of=None):
    """Changes for +1 sigma of each parameter: mode rates (rad/s), required and hydrostatic e_f, excess.

    The required e_f moves by -dF/dF_e (implicit function theorem), F the FCN's
    space rate at the required e_f: linear propagation, as for the periods. A
    parameter that moves the hydrostatic e_f too (``e_of``) moves the FCN, the
    hydrostatic e_f and the excess together (their correlation is kept).
    """
    out = {}
    slope = None
    if required is not None:
        h = 1e-6 * required
        slope = (_fcn_space_rate(p, required + h) - _fcn_space_rate(p, required - h)) / (2 * h)
    which = MODES if with_fcn else ("CW",)
    for key, plus, minus in _perturbed(p):
        e_plus, e_minus = (e_of(plus), e_of(minus)) if e_of is not None else (e_f, e_f)
        r_plus = mode_rates(plus, e_plus, coupled=with_fcn, which=which)
        r_minus = mode_rates(minus, e_minus, coupled=with_fcn, which=which)
        row = {
            "CW": 0.5 * (r_plus["CW"][0] - r_minus["CW"][0]),
            "FCN": 0.0,
            "FCN_celestial": 0.0,
            "e_f": 0.0,
            "e_hyd": 0.5 * (e_plus - e_minus),
            "excess": 0.0,
        }
        if with_fcn:
            row["FCN"] = 0.5 * (r_plus["FCN"][0] - r_minus["FCN"][0])
            # In space the rate is the terrestrial one plus the spin: an uncertain spin moves the two differently.
            row["FCN_celestial"] = 0.5 * (
                (r_plus["FCN"][0] + plus.rotation_rate.value) - (r_minus["FCN"][0] + minus.rotation_rate.value)
            )
            if slope is not None:
                dfdp = 0.5 * (_fcn_space_rate(plus, required) - _fcn_space_rate(minus, required))
                row["e_f"] = -dfdp / slope
                row["excess"] = 0.5 * ((required + row["e_f"]) / e_plus - (required - row["e_f"]) / e_minus)
        if any(row.values()):
            out[key] = row
    if slope is not None and obs_fcn.sigma > 0:
        # The observation's own uncertainty moves only the required e_f.
        d_obs = 0.5 * abs(2 * math.pi / (obs_fcn.value + obs_fcn.sigma) - 2 * math.pi / (obs_fcn.value - obs_fcn.sigma))
        out["observed_fcn_period"] = {
            "CW": 0.0,
            "FCN": 0.0,
            "FCN_celestial": 0.0,
            "e_f": d_obs / slope,
            "e_hyd": 0.0,
            "excess": d_obs / slope / e_f,
        }
    return out
