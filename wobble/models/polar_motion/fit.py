"""The fitted model of a record (equation 2 of :mod:`wobble.models.polar_motion`) and its terms.

    p(t) = sum_j c_j tau^j + A_c e^{i sigma_c s} + A_+ e^{i Omega_a s}
           + A_- e^{-i Omega_a s},   s = t - t_e,  tau = s / h,              (2)

Times in s (the caller's origin), angles in rad, rates in rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from wobble.models.polar_motion.record import ANNUAL_RATE

__all__ = ["Harmonic", "Uncertainty", "ChandlerFit", "make_fit", "with_changes"]


@dataclass(frozen=True)
class Harmonic:
    """One circular term a exp(i (rate s + phase)) of equation (2).

    Attributes
    ----------
    rate : float
        Signed angular frequency, rad/s (positive: prograde).
    rate_sigma : float
        One-sigma uncertainty of the rate, rad/s (0 when the rate is fixed).
    amplitude, amplitude_sigma : float
        Radius of the circle and its uncertainty, rad.
    phase, phase_sigma : float
        Argument of the complex amplitude at the fit's epoch, rad.
    """

    rate: float
    rate_sigma: float
    amplitude: float
    amplitude_sigma: float
    phase: float
    phase_sigma: float

    @property
    def period(self) -> float:
        """2 pi / |rate|, s."""
        return 2.0 * math.pi / abs(self.rate)

    @property
    def period_sigma(self) -> float:
        """Uncertainty of the period, s (first order: 2 pi sigma_rate / rate^2)."""
        return 2.0 * math.pi * self.rate_sigma / self.rate**2

    @property
    def complex_amplitude(self) -> complex:
        return self.amplitude * complex(math.cos(self.phase), math.sin(self.phase))


@dataclass(frozen=True)
class Uncertainty:
    """The pieces of one quantity's uncertainty (same unit as the quantity; NaN: not computed).

    ``adopted = sqrt(max(autocorrelation, subspans, excitation)^2 + model^2)``;
    ``formal`` (white residuals) is shown only to say how much too small it is.
    """

    formal: float
    autocorrelation: float
    subspans: float
    model: float
    adopted: float
    excitation: float = math.nan


@dataclass(frozen=True, eq=False)
class ChandlerFit:
    """The Chandler and annual terms and the mean-pole drift of one span.

    Times are in the caller's seconds; angles in rad; rates in rad/s.
    ``chandler.rate_sigma`` and ``chandler.amplitude_sigma`` are the adopted
    uncertainties; the breakdown is in ``period_uncertainty`` (s) and
    ``amplitude_uncertainty`` (rad).
    """

    method: str
    epoch: float
    start: float
    end: float
    n_samples: int
    drift_degree: int
    chandler: Harmonic
    annual_prograde: Harmonic
    annual_retrograde: Harmonic
    drift: np.ndarray
    half_span: float
    period_uncertainty: Uncertainty
    amplitude_uncertainty: Uncertainty
    residual_rms: float
    caveats: tuple[str, ...] = ()
    details: dict = field(default_factory=dict)

    @property
    def span(self) -> float:
        return self.end - self.start

    @property
    def resolved(self) -> bool:
        """Whether the span resolves a Chandler term: its period inside the search band, not at an edge
        (``details["at_edge"]``), and, for the least squares, its column separable from the annual terms'
        (``details["separable"]``: variance inflation at most 10). Otherwise the period and the amplitudes
        describe the search, not the wobble."""
        return not self.details.get("at_edge", False) and self.details.get("separable", True)

    def mean_pole(self, t) -> np.ndarray:
        """The drift polynomial of equation (2) at times ``t`` (complex, rad)."""
        tau = (np.asarray(t, dtype=float) - self.epoch) / self.half_span
        return np.polynomial.polynomial.polyval(tau, self.drift)

    def model(self, t, *, terms=("drift", "chandler", "annual_prograde", "annual_retrograde")) -> np.ndarray:
        """Equation (2) at times ``t`` with the chosen terms (complex, rad)."""
        t = np.asarray(t, dtype=float)
        s = t - self.epoch
        out = np.zeros(t.shape, dtype=complex)
        if "drift" in terms:
            out += self.mean_pole(t)
        for name in ("chandler", "annual_prograde", "annual_retrograde"):
            if name in terms:
                h: Harmonic = getattr(self, name)
                out += h.complex_amplitude * np.exp(1j * h.rate * s)
        return out


def make_fit(method, t, epoch, half, degree, coeffs, rate, resid, sig_rate, sig_amp, sig_phase, ann_sig) -> ChandlerFit:
    """A :class:`ChandlerFit` from the coefficients of equation (2) (drift, annual +, annual -, Chandler) and
    the sigmas."""
    nan = math.nan
    c = coeffs
    chandler = Harmonic(rate, sig_rate, abs(c[-1]), sig_amp, float(np.angle(c[-1])), sig_phase)
    pro = Harmonic(ANNUAL_RATE, 0.0, abs(c[degree + 1]), ann_sig[0][0], float(np.angle(c[degree + 1])), ann_sig[0][1])
    retro = Harmonic(
        -ANNUAL_RATE, 0.0, abs(c[degree + 2]), ann_sig[1][0], float(np.angle(c[degree + 2])), ann_sig[1][1]
    )
    unc = Uncertainty(nan, nan, nan, nan, nan)
    return ChandlerFit(
        method=method,
        epoch=float(epoch),
        start=float(t[0]),
        end=float(t[-1]),
        n_samples=int(t.size),
        drift_degree=degree,
        chandler=chandler,
        annual_prograde=pro,
        annual_retrograde=retro,
        drift=np.array(c[: degree + 1]),
        half_span=float(half),
        period_uncertainty=unc,
        amplitude_uncertainty=unc,
        residual_rms=float(np.sqrt(np.mean(np.abs(resid) ** 2))),
    )


def with_changes(fit: ChandlerFit, **changes) -> ChandlerFit:
    """A copy of ``fit`` with some fields changed (the dataclass stays frozen)."""
    return replace(fit, **changes)
