"""One estimate of the Chandler wobble with units (:func:`chandler_wobble`), and the published value beside it."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from astropy import units as u
from astropy.time import Time

from wobble.api.polar_motion.record import MJD_J2000, RAD_PER_ARCSEC, resolve_data, series, short_span_error
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.io.dates import iso_date, mjd_time
from wobble.io.json_keys import deprecate
from wobble.models import polar_motion as _pm

__all__ = [
    "published_chandler_period",
    "ChandlerEstimate",
    "chandler_wobble",
    "num",
    "q_arg",
    "DEPRECATED_KEYS",
]

#: JSON keys renamed for one vocabulary (the annual terms are annual_prograde_* and
#: annual_retrograde_*), kept as aliases for one release: old name -> new name.
DEPRECATED_KEYS = {
    "annual_amplitude_mas": "annual_prograde_amplitude_mas",
    "annual_amplitude_uncertainty_mas": "annual_prograde_amplitude_uncertainty_mas",
}


def published_chandler_period(earth=None) -> dict:
    """The published Chandler period we compare with, from the Earth catalogue.

    ``data/bodies/earth.toml`` (``observed_chandler_period``) holds the value,
    its uncertainty and source, so the model comparison and this one use the
    same number. ``earth``: the catalogue's Earth already loaded
    (``wobble.load_planet("earth")``), to save reading the file again.
    """
    from wobble.api.chandler import load_planet

    entry = load_planet(earth if earth is not None else "earth").parameter("observed_chandler_period")
    return {
        "period": entry.value.to(u.day),
        "uncertainty": entry.uncertainty.to(u.day),
        "reference": f"{entry.source}. {entry.note}".strip(),
    }


_MAS = u.mas


def _parts(unc: _pm.Uncertainty, unit, scale) -> dict[str, u.Quantity]:
    return {
        k: (getattr(unc, k) * scale) << unit
        for k in ("formal", "autocorrelation", "subspans", "excitation", "model", "adopted")
    }


@dataclass(frozen=True)
class ChandlerEstimate:
    """The Chandler wobble, the annual terms and the mean-pole drift measured over one span.

    Attributes
    ----------
    method : str
        ``least_squares`` (nonlinear least squares of the complex series) or
        ``spectrum`` (peak of the two-sided spectrum).
    start, end, epoch : astropy.time.Time
        First and last sample; the mid epoch at which the phases are given.
    period, period_uncertainty : Quantity
        Chandler period and its adopted one-sigma uncertainty, days of 86400 s.
    period_uncertainty_parts : dict of Quantity
        ``formal`` (white residuals; far too small, shown for contrast),
        ``autocorrelation``, ``subspans``, ``excitation``, ``model``, ``adopted``
        (see :mod:`wobble.models.polar_motion`); NaN where not computed.
    amplitude, amplitude_uncertainty : Quantity
        Radius of the Chandler circle over the span, mas.
    phase, phase_uncertainty : Quantity
        Argument of the Chandler term of p = x_p - i y_p at ``epoch``, deg
        (the uncertainty is the autocorrelation part only).
    annual_prograde_amplitude, annual_retrograde_amplitude (and ``_uncertainty``) : Quantity
        The annual terms, mas.
    mean_pole_x, mean_pole_y : Quantity
        The drift polynomial at ``epoch``, arcsec.
    drift_rate : Quantity
        Speed of the mean pole at ``epoch``, mas per Julian year.
    drift_direction : Quantity
        Its direction as a longitude west of Greenwich, deg.
    residual_rms : Quantity
        RMS distance of the data from the fitted model, mas.
    caveats : tuple of str
        What limits this estimate (short span, unresolved peak, ...).
    raw : ChandlerFit
        The SI result of the model layer.

    :attr:`resolved` says whether the span resolves a Chandler term at all (:attr:`unresolved_because` why
    not): when it does not, the period and amplitudes are those of the search, not of the wobble.
    """

    method: str
    start: Time
    end: Time
    epoch: Time
    n_samples: int
    period: u.Quantity
    period_uncertainty: u.Quantity
    period_uncertainty_parts: dict
    amplitude: u.Quantity
    amplitude_uncertainty: u.Quantity
    amplitude_uncertainty_parts: dict
    phase: u.Quantity
    phase_uncertainty: u.Quantity
    annual_prograde_amplitude: u.Quantity
    annual_prograde_amplitude_uncertainty: u.Quantity
    annual_retrograde_amplitude: u.Quantity
    annual_retrograde_amplitude_uncertainty: u.Quantity
    mean_pole_x: u.Quantity
    mean_pole_y: u.Quantity
    drift_rate: u.Quantity
    drift_direction: u.Quantity
    residual_rms: u.Quantity
    caveats: tuple
    raw: _pm.ChandlerFit

    @classmethod
    def from_fit(cls, fit: _pm.ChandlerFit) -> ChandlerEstimate:
        rad_mas = 1.0 / (RAD_PER_ARCSEC * 1e-3)

        def to_mjd(ts):
            return MJD_J2000 + ts / _pm.DAY

        mean = complex(fit.mean_pole(fit.epoch))
        # d(mean pole)/dt at the epoch: c_1 / h (rad/s)
        speed = complex(fit.drift[1] / fit.half_span) if fit.drift.size > 1 else 0j
        vx, vy = speed.real, -speed.imag
        ch = fit.chandler
        return cls(
            method=fit.method,
            start=mjd_time(to_mjd(fit.start)),
            end=mjd_time(to_mjd(fit.end)),
            epoch=mjd_time(to_mjd(fit.epoch)),
            n_samples=fit.n_samples,
            period=(ch.period / _pm.DAY) << u.day,
            period_uncertainty=(ch.period_sigma / _pm.DAY) << u.day,
            period_uncertainty_parts=_parts(fit.period_uncertainty, u.day, 1.0 / _pm.DAY),
            amplitude=(ch.amplitude * rad_mas) << _MAS,
            amplitude_uncertainty=(ch.amplitude_sigma * rad_mas) << _MAS,
            amplitude_uncertainty_parts=_parts(fit.amplitude_uncertainty, _MAS, rad_mas),
            phase=(math.degrees(ch.phase)) << u.deg,
            phase_uncertainty=(math.degrees(ch.phase_sigma)) << u.deg,
            annual_prograde_amplitude=(fit.annual_prograde.amplitude * rad_mas) << _MAS,
            annual_prograde_amplitude_uncertainty=(fit.annual_prograde.amplitude_sigma * rad_mas) << _MAS,
            annual_retrograde_amplitude=(fit.annual_retrograde.amplitude * rad_mas) << _MAS,
            annual_retrograde_amplitude_uncertainty=(fit.annual_retrograde.amplitude_sigma * rad_mas) << _MAS,
            mean_pole_x=(mean.real / RAD_PER_ARCSEC) << u.arcsec,
            mean_pole_y=(-mean.imag / RAD_PER_ARCSEC) << u.arcsec,
            drift_rate=(math.hypot(vx, vy) * rad_mas * _pm.JULIAN_YEAR) << (_MAS / u.yr),
            drift_direction=(math.degrees(math.atan2(vy, vx)) % 360.0) << u.deg,
            residual_rms=(fit.residual_rms * rad_mas) << _MAS,
            caveats=tuple(fit.caveats),
            raw=fit,
        )

    @property
    def resolved(self) -> bool:
        """Whether the span resolves a Chandler term (:attr:`wobble.models.polar_motion.ChandlerFit.resolved`):
        its period inside the search band, not at an edge, and, for the least squares, its term separable from
        the annual ones (variance inflation at most 10)."""
        return self.raw.resolved

    @property
    def annual_note(self) -> str:
        """What to say after the annual terms: where the Chandler term cannot be told from the prograde annual one,
        that; else "" (one wording for the text report and the summary)."""
        return "" if self.raw.details.get("separable", True) else " (prograde not separable from the Chandler term)"

    @property
    def unresolved_because(self) -> str:
        """Why no Chandler term is resolved, in a few words ("" when one is)."""
        details = self.raw.details
        reasons = []
        if details.get("at_edge"):
            lo, hi = (b / _pm.DAY for b in details.get("band", _pm.CHANDLER_BAND))
            reasons.append(f"its period is at the edge of the search band {lo:.0f}-{hi:.0f} d")
        if not details.get("separable", True):
            reasons.append(
                f"it cannot be told from the annual terms (variance inflation {details['variance_inflation']:.3g})"
            )
        return " and ".join(reasons)

    def __repr__(self) -> str:
        """The span and the Chandler term with their uncertainties (the dataclass repr was 3,000 characters of
        raw SI fit)."""
        from wobble.io.text import with_uncertainty

        def text(q, sigma, unit):
            return f"{with_uncertainty(q.to_value(unit), sigma.to_value(unit))} {unit}"

        span = f"{iso_date(float(self.start.mjd))} to {iso_date(float(self.end.mjd))}"
        unresolved = "" if self.resolved else f", not resolved: {self.unresolved_because}"
        return (
            f"<ChandlerEstimate ({self.method}) {span}, {self.n_samples} samples: period "
            f"{text(self.period, self.period_uncertainty, 'd')}, amplitude "
            f"{text(self.amplitude, self.amplitude_uncertainty, 'mas')}{unresolved}>"
        )

    def to_dict(self) -> dict:
        """A JSON-ready summary (days of 86400 s, mas, deg; null where not computed).

        ``annual_amplitude_mas`` and ``annual_amplitude_uncertainty_mas`` are
        deprecated aliases of the ``annual_prograde_*`` keys (one release), listed
        under ``deprecated_keys`` as every command's renames are.
        """
        return deprecate(
            {
                "method": self.method,
                "start": iso_date(self.start),
                "end": iso_date(self.end),
                "epoch": iso_date(self.epoch),
                "n_samples": self.n_samples,
                "chandler_period_days": num(self.period),
                "chandler_period_uncertainty_days": num(self.period_uncertainty),
                "chandler_period_uncertainty_parts_days": {k: num(v) for k, v in self.period_uncertainty_parts.items()},
                "chandler_amplitude_mas": num(self.amplitude),
                "chandler_amplitude_uncertainty_mas": num(self.amplitude_uncertainty),
                "chandler_phase_deg": num(self.phase),
                "chandler_phase_uncertainty_deg": num(self.phase_uncertainty),
                "annual_prograde_amplitude_mas": num(self.annual_prograde_amplitude),
                "annual_prograde_amplitude_uncertainty_mas": num(self.annual_prograde_amplitude_uncertainty),
                "annual_retrograde_amplitude_mas": num(self.annual_retrograde_amplitude),
                "annual_retrograde_amplitude_uncertainty_mas": num(self.annual_retrograde_amplitude_uncertainty),
                "mean_pole_x_arcsec": num(self.mean_pole_x),
                "mean_pole_y_arcsec": num(self.mean_pole_y),
                "drift_rate_mas_per_year": num(self.drift_rate),
                "drift_direction_deg_west": num(self.drift_direction),
                "residual_rms_mas": num(self.residual_rms),
                "chandler_resolved": self.resolved,
                "caveats": list(self.caveats),
            },
            DEPRECATED_KEYS,
        )


def num(q) -> float | None:
    """A Quantity or number as a JSON float (None where missing or not finite)."""
    if q is None:
        return None
    x = float(q.value if isinstance(q, u.Quantity) else q)
    return x if math.isfinite(x) else None


def _band_si(band) -> tuple[float, float]:
    arr = to_si(band, "band", u.s, positive=True, shape=(2,))
    return float(arr[0]), float(arr[1])


def q_arg(excitation_q):
    """The Monte-Carlo Q as a float, or None to leave the excitation term out."""
    if excitation_q is None:
        return None
    try:
        return float(excitation_q)
    except (TypeError, ValueError):
        raise InputError("excitation_q", excitation_q, "a quality factor above 1, or None") from None


def chandler_wobble(
    data=None,
    *,
    start=None,
    end=None,
    method: str = "least_squares",
    drift_degree: int = 2,
    band: u.Quantity = [390, 500] * u.day,
    excitation_q: float | None = 100.0,
    draws: int = 64,
) -> ChandlerEstimate:
    """Measure the Chandler wobble in a polar-motion record.

    Parameters
    ----------
    data : Dataset, path or None
        A Dataset from :func:`load_polar_motion` (or any Dataset with ``time``
        in CF units and ``x_p``, ``y_p`` with angle units), a file, or None
        for the shipped IERS 20 C04 series.
    start, end : date, optional
        The span to analyse (UTC dates; default: all of ``data``).
    method : str
        ``least_squares`` (default) or ``spectrum``: two independent
        estimators (see :mod:`wobble.models.polar_motion`).
    drift_degree : int
        Degree of the mean-pole polynomial (default 2).
    band : Quantity
        Search interval for the Chandler period (default 390 to 500 d).
    excitation_q : float or None
        Q assumed for the Monte-Carlo excitation term of the uncertainty
        (default 100; None leaves it out).
    draws : int
        Monte-Carlo realisations for that term.

    Returns
    -------
    ChandlerEstimate
    """
    ds = resolve_data(data, None, start, end)
    mjd, t, z = series(ds)
    if t.size < 2 or t[-1] - t[0] < _pm.MIN_SPAN:
        # The estimators' own check named their argument, 'series', which the caller never saw.
        why = " (two Julian years) to measure a period"
        name = "data" if start is None and end is None else "start/end"
        raise short_span_error(mjd, start, end, _pm.MIN_SPAN / _pm.DAY, why, name=name)
    estimator = {"least_squares": _pm.fit_least_squares, "spectrum": _pm.fit_spectrum}.get(method)
    if estimator is None:
        raise InputError("method", method, "'least_squares' or 'spectrum'")
    if isinstance(draws, bool) or not isinstance(draws, (int, np.integer)) or not 4 <= draws <= 10000:
        raise InputError("draws", draws, "an integer from 4 to 10000")
    reference = published_chandler_period()["period"].to_value(u.s)
    fit = estimator(
        t,
        z,
        reference_period=reference,
        drift_degree=drift_degree,
        band=_band_si(band),
        excitation_q=q_arg(excitation_q),
        draws=int(draws),
    )
    return ChandlerEstimate.from_fit(fit)
