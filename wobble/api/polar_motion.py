"""Observed polar motion with units: the IERS record, the Chandler wobble, and the model beside it.

>>> import wobble
>>> data = wobble.load_polar_motion(start="2000-01-01", end="2004-12-31")
>>> data["x_p"].attrs["units"], data.sizes["time"]
('arcsec', 1827)
>>> data["time"].attrs["units"]
'days since 1858-11-17 00:00:00'

The pole is the complex number p = x_p - i y_p; with that sign the Chandler
wobble is a *prograde* circle (counter-clockwise seen from above the north
pole), at a positive frequency of the two-sided spectrum. The estimation is
:mod:`wobble.models.polar_motion`; the method and the numbers are in
``docs/polar-motion.md``.
"""

from __future__ import annotations

import datetime as _dt
import math
import os
import re
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr
from astropy import units as u
from astropy.time import Time

from wobble.api._units import to_si
from wobble.errors import InputError
from wobble.io.eop import read_pole_file
from wobble.models import polar_motion as _pm

__all__ = [
    "MJD_UNITS",
    "published_chandler_period",
    "ChandlerEstimate",
    "QualityFactorEstimate",
    "PolarMotionAnalysis",
    "load_polar_motion",
    "chandler_wobble",
    "polar_motion_analysis",
]

#: CF units of wobble's time coordinates for dated series: the Modified Julian Date.
MJD_UNITS = "days since 1858-11-17 00:00:00"
_MJD_J2000 = 51544.5  # MJD of 2000-01-01 12:00; the origin of the models' seconds
_RAD_PER_ARCSEC = math.pi / (180.0 * 3600.0)
def published_chandler_period() -> dict:
    """The published Chandler period we compare with, from the Earth catalogue.

    ``data/bodies/earth.toml`` (``observed_chandler_period``) holds the value,
    its uncertainty and source, so the model comparison and this one use the
    same number.
    """
    from wobble.api.chandler import load_planet

    entry = load_planet("earth").parameter("observed_chandler_period")
    return {
        "period": entry.value.to(u.day),
        "uncertainty": entry.uncertainty.to(u.day),
        "reference": f"{entry.source}. {entry.note}".strip(),
    }


C04_REFERENCE = (
    "IERS EOP 20 C04 series (IERS Earth Orientation Centre, Paris Observatory; consistent with ITRF 2020), "
    "https://hpiers.obspm.fr/eoppc/eop/eopc04/, as shipped by the astropy-iers-data package"
)
FINALS_REFERENCE = "IERS Rapid Service/Prediction Centre, Bulletin A (finals2000A), observed (I) rows only"
SIGN_NOTE = (
    "complex pole p = x_p - i y_p (x_p toward Greenwich, y_p toward 90 deg W); terms exp(+i sigma t) with "
    "sigma > 0 are prograde (counter-clockwise seen from above the north pole)"
)


# ---------------------------------------------------------------------------
# Dates
# ---------------------------------------------------------------------------

_DATE_HELP = "a UTC date such as 2015-01-01, 2015-06, 2015 or 2015.5 (an astropy Time or datetime also works)"


def _to_mjd(value, name: str) -> float:
    """A user's date as MJD (UTC)."""
    try:
        from erfa import ErfaWarning
    except ImportError:  # pragma: no cover - erfa ships with astropy
        ErfaWarning = Warning  # noqa: N806
    try:
        with warnings.catch_warnings():
            # Dates before 1960 or past the leap-second table are "dubious" to ERFA
            # only for their UTC seconds; as calendar dates they are exact.
            warnings.simplefilter("ignore", ErfaWarning)
            if isinstance(value, Time):
                return float(value.utc.mjd)
            if isinstance(value, _dt.date) and not isinstance(value, _dt.datetime):
                value = _dt.datetime(value.year, value.month, value.day)
            if isinstance(value, (_dt.datetime, np.datetime64)):
                return float(Time(value, scale="utc").mjd)
            if isinstance(value, str):
                text = value.strip()
                if re.fullmatch(r"\d{4}(\.\d*)?", text):
                    return float(Time(float(text), format="decimalyear", scale="utc").mjd)
                if re.fullmatch(r"\d{4}-\d{1,2}", text):
                    text += "-01"
                return float(Time(text, scale="utc").mjd)
    except (ValueError, TypeError):
        pass
    raise InputError(name, value, _DATE_HELP)


def _iso(mjd: float) -> str:
    return Time(mjd, format="mjd", scale="utc").iso[:10]


def _time(mjd: float) -> Time:
    return Time(mjd, format="mjd", scale="utc")


def _select(mjd: np.ndarray, start, end, what: str = "the data") -> np.ndarray:
    first, last = float(mjd[0]), float(mjd[-1])
    span = f"a date from {_iso(first)} to {_iso(last)} ({what})"
    lo = first if start is None else _to_mjd(start, "start")
    hi = last if end is None else _to_mjd(end, "end")
    if not first - 0.5 <= lo <= last:
        raise InputError("start", start, span)
    if not first <= hi <= last + 0.5:
        raise InputError("end", end, span)
    if hi <= lo:
        raise InputError("end", end, f"a date after start ({_iso(lo)})")
    return (mjd >= lo) & (mjd <= hi)


# ---------------------------------------------------------------------------
# The record as a Dataset
# ---------------------------------------------------------------------------


def _attrs(units: str, long_name: str, **extra) -> dict:
    return {"units": units, "long_name": long_name, **extra}


def _time_coord(mjd, long_name="time (UTC)") -> tuple:
    return (
        "time",
        np.asarray(mjd, dtype=float),
        {"units": MJD_UNITS, "calendar": "standard", "standard_name": "time", "axis": "T", "long_name": long_name},
    )


def load_polar_motion(file: str | os.PathLike | None = None, *, start=None, end=None) -> xr.Dataset:
    """The pole coordinates of an IERS file as an xarray Dataset.

    Parameters
    ----------
    file : path-like, optional
        An IERS C04 or finals2000A file (recognised from its lines). Default:
        the IERS 20 C04 series shipped with astropy-iers-data (no download).
    start, end : str, astropy.time.Time or datetime, optional
        Keep the days from ``start`` to ``end`` inclusive (UTC; default: all).
        Dates outside the file are an error, not a silently shorter series.

    Returns
    -------
    xarray.Dataset
        ``x_p``, ``y_p``, ``x_p_error``, ``y_p_error`` (arcsec) on a ``time``
        coordinate in MJD (CF units ``days since 1858-11-17 00:00:00``).

    Examples
    --------
    >>> import wobble
    >>> pm = wobble.load_polar_motion(start="2020-01-01", end="2020-12-31")
    >>> pm.sizes["time"], list(pm.data_vars), pm["x_p"].attrs["units"]
    (366, ['x_p', 'y_p', 'x_p_error', 'y_p_error'], 'arcsec')
    """
    rec = read_pole_file(file)
    keep = _select(rec.mjd, start, end, f"the span of {os.path.basename(rec.path)}")
    if keep.sum() < 2:
        raise InputError("start/end", f"{start} to {end}", "an interval holding at least two days of data")
    c04 = rec.format == "c04"
    ds = xr.Dataset(
        {
            "x_p": ("time", rec.x[keep], _attrs("arcsec", "pole coordinate x_p (toward the Greenwich meridian)")),
            "y_p": ("time", rec.y[keep], _attrs("arcsec", "pole coordinate y_p (toward 90 deg W longitude)")),
            "x_p_error": ("time", rec.x_error[keep], _attrs("arcsec", "one-sigma error of x_p given in the file")),
            "y_p_error": ("time", rec.y_error[keep], _attrs("arcsec", "one-sigma error of y_p given in the file")),
        },
        coords={"time": _time_coord(rec.mjd[keep])},
        attrs={
            "title": f"Polar motion: {rec.title}",
            "source_file": rec.path,
            "source_format": rec.format,
            "references": C04_REFERENCE if c04 else FINALS_REFERENCE,
            "comment": "Times are UTC (C04: 0 h UTC each day). " + SIGN_NOTE,
        },
    )
    ds["x_p"].attrs["ancillary_variables"] = "x_p_error"
    ds["y_p"].attrs["ancillary_variables"] = "y_p_error"
    return ds


def _series(data: xr.Dataset) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(MJD, t in s since J2000, p = x - i y in rad) from a Dataset, checked."""
    for name in ("x_p", "y_p", "time"):
        if name not in data.variables:
            raise InputError("data", f"a Dataset without {name!r}", "a Dataset from load_polar_motion (time, x_p, y_p)")
    mjd = _mjd_values(data["time"])
    xy = []
    for name in ("x_p", "y_p"):
        unit = data[name].attrs.get("units")
        try:
            xy.append(to_si(np.asarray(data[name].values, dtype=float) * u.Unit(unit), name, u.rad, finite=False))
        except (ValueError, TypeError):
            raise InputError(name, f"units {unit!r}", "angle units such as 'arcsec' or 'milliarcsecond'") from None
    ok = np.isfinite(mjd) & np.isfinite(xy[0]) & np.isfinite(xy[1])
    mjd = mjd[ok]
    if mjd.size > 1 and not np.all(np.diff(mjd) > 0):
        raise InputError("data", "times not increasing", "a Dataset with strictly increasing times")
    t = (mjd - _MJD_J2000) * _pm.DAY
    return mjd, t, _pm.complex_pole(xy[0][ok], xy[1][ok])


def _mjd_values(time: xr.DataArray) -> np.ndarray:
    values = time.values
    if np.issubdtype(values.dtype, np.datetime64):
        return np.asarray(Time(values, scale="utc").mjd, dtype=float)
    units = str(time.attrs.get("units", ""))
    match = re.fullmatch(r"\s*(days?|d|hours?|h|minutes?|min|seconds?|s)\s+since\s+(.+?)\s*", units)
    if not match:
        raise InputError("time", f"units {units!r}", f"CF time units such as '{MJD_UNITS}'")
    scale = {"d": 1.0, "h": 1 / 24, "m": 1 / 1440, "s": 1 / 86400}[match.group(1)[0]]
    epoch = _to_mjd(match.group(2).replace(" ", "T", 1) if " " in match.group(2) else match.group(2), "time units epoch")
    return epoch + scale * np.asarray(values, dtype=float)


def _resolve_data(data, file, start, end) -> xr.Dataset:
    if data is None:
        return load_polar_motion(file, start=start, end=end)
    if isinstance(data, (str, os.PathLike)):
        return load_polar_motion(data, start=start, end=end)
    if not isinstance(data, xr.Dataset):
        raise InputError("data", type(data).__name__, "an xarray Dataset from load_polar_motion, a file path, or None")
    if start is None and end is None:
        return data
    keep = _select(_mjd_values(data["time"]), start, end)
    return data.isel(time=np.nonzero(keep)[0])


# ---------------------------------------------------------------------------
# Estimates with units
# ---------------------------------------------------------------------------

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
    def from_fit(cls, fit: _pm.ChandlerFit) -> "ChandlerEstimate":
        rad_mas = 1.0 / (_RAD_PER_ARCSEC * 1e-3)
        to_mjd = lambda ts: _MJD_J2000 + ts / _pm.DAY  # noqa: E731
        mean = complex(fit.mean_pole(fit.epoch))
        # d(mean pole)/dt at the epoch: c_1 / h (rad/s)
        speed = complex(fit.drift[1] / fit.half_span) if fit.drift.size > 1 else 0j
        vx, vy = speed.real, -speed.imag
        ch = fit.chandler
        return cls(
            method=fit.method,
            start=_time(to_mjd(fit.start)),
            end=_time(to_mjd(fit.end)),
            epoch=_time(to_mjd(fit.epoch)),
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
            mean_pole_x=(mean.real / _RAD_PER_ARCSEC) << u.arcsec,
            mean_pole_y=(-mean.imag / _RAD_PER_ARCSEC) << u.arcsec,
            drift_rate=(math.hypot(vx, vy) * rad_mas * 365.25 * _pm.DAY) << (_MAS / u.yr),
            drift_direction=(math.degrees(math.atan2(vy, vx)) % 360.0) << u.deg,
            residual_rms=(fit.residual_rms * rad_mas) << _MAS,
            caveats=tuple(fit.caveats),
            raw=fit,
        )

    def to_dict(self) -> dict:
        """A JSON-ready summary (days of 86400 s, mas, deg; null where not computed)."""
        return {
            "method": self.method,
            "start": self.start.iso[:10],
            "end": self.end.iso[:10],
            "epoch": self.epoch.iso[:10],
            "n_samples": self.n_samples,
            "chandler_period_days": _num(self.period),
            "chandler_period_uncertainty_days": _num(self.period_uncertainty),
            "chandler_period_uncertainty_parts_days": {k: _num(v) for k, v in self.period_uncertainty_parts.items()},
            "chandler_amplitude_mas": _num(self.amplitude),
            "chandler_amplitude_uncertainty_mas": _num(self.amplitude_uncertainty),
            "chandler_phase_deg": _num(self.phase),
            "chandler_phase_uncertainty_deg": _num(self.phase_uncertainty),
            "annual_amplitude_mas": _num(self.annual_prograde_amplitude),
            "annual_amplitude_uncertainty_mas": _num(self.annual_prograde_amplitude_uncertainty),
            "annual_retrograde_amplitude_mas": _num(self.annual_retrograde_amplitude),
            "annual_retrograde_amplitude_uncertainty_mas": _num(self.annual_retrograde_amplitude_uncertainty),
            "mean_pole_x_arcsec": _num(self.mean_pole_x),
            "mean_pole_y_arcsec": _num(self.mean_pole_y),
            "drift_rate_mas_per_year": _num(self.drift_rate),
            "drift_direction_deg_west": _num(self.drift_direction),
            "residual_rms_mas": _num(self.residual_rms),
            "caveats": list(self.caveats),
        }


def _num(q) -> float | None:
    if q is None:
        return None
    x = float(q.value if isinstance(q, u.Quantity) else q)
    return x if math.isfinite(x) else None


def _band_si(band) -> tuple[float, float]:
    arr = to_si(band, "band", u.s, positive=True, shape=(2,))
    return float(arr[0]), float(arr[1])


def _q_arg(excitation_q):
    if excitation_q is None:
        return None
    try:
        return float(excitation_q)
    except (TypeError, ValueError):
        raise InputError("excitation_q", excitation_q, "a quality factor above 1, or None") from None


def chandler_wobble(
    data: xr.Dataset | str | os.PathLike | None = None,
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
    ds = _resolve_data(data, None, start, end)
    _, t, z = _series(ds)
    estimator = {"least_squares": _pm.fit_least_squares, "spectrum": _pm.fit_spectrum}.get(method)
    if estimator is None:
        raise InputError("method", method, "'least_squares' or 'spectrum'")
    if isinstance(draws, bool) or not isinstance(draws, (int, np.integer)) or not 4 <= draws <= 10000:
        raise InputError("draws", draws, "an integer from 4 to 10000")
    fit = estimator(t, z, drift_degree=drift_degree, band=_band_si(band), excitation_q=_q_arg(excitation_q), draws=int(draws))
    return ChandlerEstimate.from_fit(fit)


# ---------------------------------------------------------------------------
# The full analysis
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class QualityFactorEstimate:
    """Q of the Chandler wobble from its line shape (see :func:`wobble.models.polar_motion.quality_factor`).

    ``value`` is inf when the line is not wider than the record's resolution;
    ``low``-``high`` is the 68 % interval, ``lower_bound_95`` the one-sided 95 % limit.
    """

    value: float
    low: float
    high: float
    lower_bound_95: float
    resolved: bool
    caveats: tuple

    def to_dict(self) -> dict:
        return {
            "value": _num(self.value),
            "interval_68": [_num(self.low), _num(self.high)],
            "lower_bound_95": _num(self.lower_bound_95),
            "resolved": self.resolved,
            "method": "Whittle likelihood of a randomly excited damped oscillator (Lorentzian line) near the Chandler peak",
            "caveats": list(self.caveats),
        }


class PolarMotionAnalysis:
    """Everything ``wobble polar-motion`` reports: both estimates, windows, spectrum, Q, the model beside it.

    Build with :func:`polar_motion_analysis`.

    Attributes
    ----------
    data : xarray.Dataset
        The record analysed.
    least_squares, spectral : ChandlerEstimate
        The two independent estimates.
    method : str
        Which of them is the headline (``least_squares``).
    windows : xarray.Dataset
        Sliding-window estimates (dimension ``window``).
    spectrum : xarray.Dataset
        Two-sided amplitude spectrum (dimension ``frequency``).
    quality_factor : QualityFactorEstimate or None
    budget : wobble.ChandlerBudget
        The model of ``wobble.chandler_budget("earth")``.
    """

    def __init__(self, data, least_squares, spectral, windows, spectrum, quality_factor, budget, caveats):
        self.data = data
        self.least_squares = least_squares
        self.spectral = spectral
        self.windows = windows
        self.spectrum = spectrum
        self.quality_factor = quality_factor
        self.budget = budget
        self.method = "least_squares"
        self.caveats = tuple(caveats)

    @property
    def estimate(self) -> ChandlerEstimate:
        """The headline estimate (least squares)."""
        return self.least_squares

    @property
    def methods_agree(self) -> bool:
        """Whether the two periods differ by less than twice their combined one-sigma uncertainty (in quadrature)."""
        return self.agreement <= 2.0

    @property
    def agreement(self) -> float:
        """``|P_ls - P_spectrum|`` / sqrt(sigma_ls^2 + sigma_spectrum^2)."""
        a, b = self.least_squares, self.spectral
        diff = abs((a.period - b.period).to_value(u.day))
        return diff / math.hypot(a.period_uncertainty.to_value(u.day), b.period_uncertainty.to_value(u.day))

    def comparison(self) -> list[dict]:
        """The observed period beside every step of the model and the published value.

        Each row: ``name``, ``period`` (Quantity, d), ``uncertainty`` (or None),
        ``residual`` = period - observed (Quantity, d, or None for the
        observed row) and ``sigma`` (the combined one-sigma of the residual
        where both sides have one).
        """
        obs = self.estimate
        rows = [
            {"name": f"observed ({obs.method.replace('_', ' ')})", "kind": "observed", "period": obs.period, "uncertainty": obs.period_uncertainty, "residual": None, "sigma": None}
        ]
        for step in self.budget.steps:
            final = step is self.budget.steps[-1]
            unc = self.budget.period_uncertainty if final else None
            sigma = np.hypot(unc, obs.period_uncertainty) if final else None
            rows.append({"name": f"model: {step.name}", "kind": "model", "period": step.period, "uncertainty": unc, "residual": step.period - obs.period, "sigma": sigma})
        pub = published_chandler_period()
        rows.append(
            {"name": "published (Vicente & Wilson 1997)", "kind": "published", "period": pub["period"], "uncertainty": pub["uncertainty"], "residual": pub["period"] - obs.period, "sigma": np.hypot(pub["uncertainty"], obs.period_uncertainty)}
        )
        return rows

    def to_dict(self) -> dict:
        """The JSON of ``wobble polar-motion --json``."""
        est = self.estimate
        out = {
            "chandler_period_days": _num(est.period),
            "chandler_period_uncertainty_days": _num(est.period_uncertainty),
            "chandler_amplitude_mas": _num(est.amplitude),
            "chandler_amplitude_uncertainty_mas": _num(est.amplitude_uncertainty),
            "annual_amplitude_mas": _num(est.annual_prograde_amplitude),
            "annual_amplitude_uncertainty_mas": _num(est.annual_prograde_amplitude_uncertainty),
            "annual_retrograde_amplitude_mas": _num(est.annual_retrograde_amplitude),
            "annual_retrograde_amplitude_uncertainty_mas": _num(est.annual_retrograde_amplitude_uncertainty),
            "start": est.start.iso[:10],
            "end": est.end.iso[:10],
            "method": est.method,
            "source_file": self.data.attrs.get("source_file"),
            "sign_convention": SIGN_NOTE,
            "day": "days of 86400 s",
            "estimates": {e.method: e.to_dict() for e in (self.least_squares, self.spectral)},
            "methods_agree": bool(self.methods_agree),
            "agreement_sigma": _num(self.agreement),
            "quality_factor": None if self.quality_factor is None else self.quality_factor.to_dict(),
            "windows": _windows_dict(self.windows),
            "comparison": [
                {
                    "name": r["name"],
                    "kind": r["kind"],
                    "period_days": _num(r["period"]),
                    "uncertainty_days": _num(r["uncertainty"]),
                    "residual_days": _num(r["residual"]),
                    "residual_sigma_days": _num(r["sigma"]),
                }
                for r in self.comparison()
            ],
            "published": {k: (_num(v) if isinstance(v, u.Quantity) else v) for k, v in published_chandler_period().items()},
            "caveats": list(self.caveats),
        }
        return out

    def to_dataset(self) -> xr.Dataset:
        """The series, the fitted model, the residuals, the windows, the spectrum and the estimates, CF-ready."""
        return _analysis_dataset(self)

    def summary(self) -> str:
        """The human-readable report of ``wobble polar-motion``."""
        return _summary(self)

    def __repr__(self) -> str:
        e = self.estimate
        return (
            f"PolarMotionAnalysis({e.start.iso[:10]} to {e.end.iso[:10]}, "
            f"period={e.period.value:.1f} +/- {e.period_uncertainty.value:.1f} d)"
        )


def _windows_dict(w: xr.Dataset) -> dict:
    return {
        "window_years": float(w.attrs["window_years"]),
        "step_years": float(w.attrs["step_years"]),
        "centre": [_iso(float(m)) for m in w["window_time"].values],
        "chandler_amplitude_mas": [_num(v) for v in w["chandler_amplitude"].values],
        "chandler_amplitude_uncertainty_mas": [_num(v) for v in w["chandler_amplitude_uncertainty"].values],
        "chandler_period_days": [_num(v) for v in w["chandler_period"].values],
        "chandler_period_uncertainty_days": [_num(v) for v in w["chandler_period_uncertainty"].values],
        "annual_amplitude_mas": [_num(v) for v in w["annual_amplitude"].values],
    }


def _windows_dataset(wf: _pm.WindowedFits) -> xr.Dataset:
    rad_mas = 1.0 / (_RAD_PER_ARCSEC * 1e-3)
    centre = _MJD_J2000 + wf.centre / _pm.DAY
    bounds = np.stack([_MJD_J2000 + wf.start / _pm.DAY, _MJD_J2000 + wf.end / _pm.DAY], axis=1)
    day = 1.0 / _pm.DAY
    note = "least-squares fit of drift, Chandler and annual terms in each window; uncertainty from the residuals' autocorrelation and the drift model"
    return xr.Dataset(
        {
            # CF 7.1: a boundary variable takes its units and calendar from its coordinate.
            "window_time_bounds": (("window", "nv"), bounds, {"long_name": "first and last day of each window"}),
            "chandler_amplitude": ("window", wf.amplitude * rad_mas, _attrs("milliarcsecond", "Chandler wobble amplitude in the window", comment=note)),
            "chandler_amplitude_uncertainty": ("window", wf.amplitude_sigma * rad_mas, _attrs("milliarcsecond", "one-sigma uncertainty of the windowed Chandler amplitude")),
            "chandler_period": ("window", wf.period * day, _attrs("day", "Chandler wobble period in the window", comment=note)),
            "chandler_period_uncertainty": ("window", wf.period_sigma * day, _attrs("day", "one-sigma uncertainty of the windowed Chandler period")),
            "chandler_phase": ("window", np.degrees(wf.phase), _attrs("degree", "argument of the Chandler term of x_p - i y_p at the window's centre")),
            "annual_amplitude": ("window", wf.annual_amplitude * rad_mas, _attrs("milliarcsecond", "prograde annual wobble amplitude in the window")),
            "annual_amplitude_uncertainty": ("window", wf.annual_amplitude_sigma * rad_mas, _attrs("milliarcsecond", "one-sigma uncertainty of the windowed prograde annual amplitude")),
            "retrograde_annual_amplitude": ("window", wf.retrograde_annual_amplitude * rad_mas, _attrs("milliarcsecond", "retrograde annual wobble amplitude in the window")),
            "window_samples": ("window", wf.n_samples.astype(np.int32), _attrs("1", "number of daily samples in the window")),
        },
        coords={
            "window_time": (
                "window",
                centre,
                {"units": MJD_UNITS, "calendar": "standard", "standard_name": "time", "long_name": "centre of the window (UTC)", "bounds": "window_time_bounds"},
            ),
        },
        attrs={"window_years": wf.window / (365.25 * _pm.DAY), "step_years": wf.step / (365.25 * _pm.DAY)},
    )


def _spectrum_dataset(sp: _pm.Spectrum) -> xr.Dataset:
    rad_mas = 1.0 / (_RAD_PER_ARCSEC * 1e-3)
    freq = sp.rate / (2 * math.pi) * _pm.DAY  # cycles per day
    return xr.Dataset(
        {
            "amplitude_spectrum": (
                "frequency",
                sp.amplitude * rad_mas,
                _attrs(
                    "milliarcsecond",
                    "two-sided amplitude spectrum of the detrended complex pole x_p - i y_p",
                    comment=f"radius of a circular term at each frequency; taper: {sp.taper}; drift polynomial degree {sp.drift_degree} removed",
                ),
            )
        },
        coords={"frequency": ("frequency", freq, _attrs("day-1", "frequency in cycles per day (positive: prograde, negative: retrograde)"))},
    )


def polar_motion_analysis(
    data: xr.Dataset | str | os.PathLike | None = None,
    *,
    start=None,
    end=None,
    window: u.Quantity = 8 * u.yr,
    step: u.Quantity = 1 * u.yr,
    drift_degree: int = 2,
    excitation_q: float | None = 100.0,
    draws: int = 64,
    quality_factor: bool = True,
    progress=None,
) -> PolarMotionAnalysis:
    """Both estimates of the Chandler wobble, sliding windows, the spectrum, Q, and the model beside them.

    Parameters
    ----------
    data, start, end, drift_degree, excitation_q, draws
        As in :func:`chandler_wobble`.
    window : Quantity
        Length of the sliding windows (default 8 Julian years; at least 2
        years and at most the span; under the 6.4-yr Chandler-annual beat
        the windows barely separate the two terms).
    step : Quantity
        Spacing of the windows (default 1 year).
    quality_factor : bool
        Also estimate Q from the line shape (spans of 20 years or more).
    progress : callable, optional
        ``progress(message)`` is called at each stage (the CLI prints it).

    Returns
    -------
    PolarMotionAnalysis
    """
    from wobble.api.chandler import chandler_budget

    say = progress or (lambda message: None)
    ds = _resolve_data(data, None, start, end)
    mjd, t, z = _series(ds)
    window_s = to_si(window, "window", u.s, positive=True, shape=())
    step_s = to_si(step, "step", u.s, positive=True, shape=())
    q_arg = _q_arg(excitation_q)
    span = t[-1] - t[0]
    if span < _pm.MIN_SPAN:
        raise InputError(
            "start/end", f"{_iso(mjd[0])} to {_iso(mjd[-1])}", f"a span of at least {_pm.MIN_SPAN / _pm.DAY:.0f} d (two years)"
        )
    if not _pm.MIN_SPAN <= window_s <= span * (1 + 1e-9):
        raise InputError(
            "window",
            window,
            f"a length from {_pm.MIN_SPAN / (365.25 * _pm.DAY):g} yr to the span analysed ({span / (365.25 * _pm.DAY):.2f} yr)",
        )
    say("least-squares fit")
    ls = _pm.fit_least_squares(t, z, drift_degree=drift_degree, excitation_q=q_arg, draws=draws)
    say("spectral estimate")
    sp = _pm.fit_spectrum(t, z, drift_degree=drift_degree, excitation_q=q_arg, draws=draws)
    spectrum = _pm.two_sided_spectrum(t, z, drift_degree=drift_degree)

    def window_progress(done, total):
        if done % 5 == 0 or done == total:
            say(f"windows {done}/{total}")

    wf = _pm.sliding_windows(t, z, window_s, step_s, drift_degree=drift_degree, progress=window_progress)
    caveats = list(ls.caveats)
    if window_s < _pm.BEAT_PERIOD:
        caveats.append(
            f"windows of {window_s / (365.25 * _pm.DAY):.1f} yr are shorter than the 6.4-yr Chandler-annual beat: "
            "the windowed terms are barely separable"
        )
    qf = None
    if quality_factor:
        if span >= _pm.MIN_Q_SPAN:
            say("quality factor")
            chandler_only = z - ls.model(t, terms=("drift", "annual_prograde", "annual_retrograde"))
            q = _pm.quality_factor(t, chandler_only, ls.chandler.rate)
            qf = QualityFactorEstimate(q.value, q.low, q.high, q.lower_bound_95, q.resolved, q.caveats)
        else:
            caveats.append("no Q estimate: the span is shorter than 20 years")
    return PolarMotionAnalysis(
        data=ds,
        least_squares=ChandlerEstimate.from_fit(ls),
        spectral=ChandlerEstimate.from_fit(sp),
        windows=_windows_dataset(wf),
        spectrum=_spectrum_dataset(spectrum),
        quality_factor=qf,
        budget=chandler_budget("earth"),
        caveats=caveats,
    )


# ---------------------------------------------------------------------------
# Dataset and text
# ---------------------------------------------------------------------------


def _analysis_dataset(a: PolarMotionAnalysis) -> xr.Dataset:
    mjd, t, z = _series(a.data)
    fit = a.least_squares.raw
    model = fit.model(t)
    mean = fit.mean_pole(t)
    arcsec = 1.0 / _RAD_PER_ARCSEC

    def xy(p):
        x, y = _pm.pole_xy(p)
        return x * arcsec, y * arcsec

    mx, my = xy(model)
    rx, ry = xy(z - model)
    px, py = xy(mean)
    series = a.data.isel(time=np.nonzero(np.isin(_mjd_values(a.data["time"]), mjd))[0])[["x_p", "y_p", "x_p_error", "y_p_error"]]
    ls_note = "nonlinear least-squares fit of drift, Chandler and annual terms (wobble.models.polar_motion)"
    ds = series.assign(
        x_p_model=("time", mx, _attrs("arcsec", "fitted model of x_p", comment=ls_note)),
        y_p_model=("time", my, _attrs("arcsec", "fitted model of y_p", comment=ls_note)),
        x_p_residual=("time", rx, _attrs("arcsec", "x_p minus its fitted model")),
        y_p_residual=("time", ry, _attrs("arcsec", "y_p minus its fitted model")),
        x_p_mean_pole=("time", px, _attrs("arcsec", "x_p of the fitted mean-pole drift")),
        y_p_mean_pole=("time", py, _attrs("arcsec", "y_p of the fitted mean-pole drift")),
    )
    ds = xr.merge([ds, a.windows, a.spectrum], combine_attrs="drop_conflicts")
    methods = [a.least_squares, a.spectral]

    def per_method(fn):
        return np.array([fn(e) for e in methods], dtype=float)

    est = {
        "chandler_period": ("day", "Chandler wobble period", lambda e: e.period.to_value(u.day)),
        "chandler_period_uncertainty": ("day", "adopted one-sigma uncertainty of the Chandler period", lambda e: e.period_uncertainty.to_value(u.day)),
        "chandler_period_uncertainty_formal": ("day", "white-noise (formal) uncertainty of the period, far too small", lambda e: e.period_uncertainty_parts["formal"].to_value(u.day)),
        "chandler_period_uncertainty_autocorrelation": ("day", "period uncertainty from the residuals' autocorrelation", lambda e: e.period_uncertainty_parts["autocorrelation"].to_value(u.day)),
        "chandler_period_uncertainty_subspans": ("day", "period uncertainty from the scatter over sub-spans", lambda e: e.period_uncertainty_parts["subspans"].to_value(u.day)),
        "chandler_period_uncertainty_excitation": ("day", "period uncertainty of a randomly excited wobble (Monte Carlo)", lambda e: e.period_uncertainty_parts["excitation"].to_value(u.day)),
        "chandler_period_uncertainty_model": ("day", "period uncertainty from the drift model", lambda e: e.period_uncertainty_parts["model"].to_value(u.day)),
        "chandler_amplitude": ("milliarcsecond", "Chandler wobble amplitude over the span", lambda e: e.amplitude.to_value(u.mas)),
        "chandler_amplitude_uncertainty": ("milliarcsecond", "one-sigma uncertainty of the Chandler amplitude", lambda e: e.amplitude_uncertainty.to_value(u.mas)),
        "chandler_phase": ("degree", "argument of the Chandler term of x_p - i y_p at the epoch", lambda e: e.phase.to_value(u.deg)),
        "annual_prograde_amplitude": ("milliarcsecond", "prograde annual wobble amplitude", lambda e: e.annual_prograde_amplitude.to_value(u.mas)),
        "annual_prograde_amplitude_uncertainty": ("milliarcsecond", "one-sigma uncertainty of the prograde annual amplitude", lambda e: e.annual_prograde_amplitude_uncertainty.to_value(u.mas)),
        "annual_retrograde_amplitude": ("milliarcsecond", "retrograde annual wobble amplitude", lambda e: e.annual_retrograde_amplitude.to_value(u.mas)),
        "annual_retrograde_amplitude_uncertainty": ("milliarcsecond", "one-sigma uncertainty of the retrograde annual amplitude", lambda e: e.annual_retrograde_amplitude_uncertainty.to_value(u.mas)),
    }
    for name, (unit, long_name, fn) in est.items():
        ds[name] = ("method", per_method(fn), _attrs(unit, long_name))
    ds = ds.assign_coords(method=("method", [e.method for e in methods], {"long_name": "estimation method"}))
    ds["epoch"] = ((), float(a.least_squares.epoch.mjd), {"units": MJD_UNITS, "calendar": "standard", "long_name": "epoch of the phases (mid-span)"})
    rows = a.comparison()
    model_rows = [r for r in rows if r["kind"] == "model"]
    ds = ds.assign_coords(model_step=("model_step", [r["name"].removeprefix("model: ") for r in model_rows], {"long_name": "step of the Chandler model of wobble.chandler_budget('earth')"}))
    ds["model_period"] = ("model_step", np.array([r["period"].to_value(u.day) for r in model_rows]), _attrs("day", "modelled Chandler period after each model step"))
    ds["model_minus_observed"] = ("model_step", np.array([r["residual"].to_value(u.day) for r in model_rows]), _attrs("day", "modelled minus observed (least-squares) Chandler period"))
    ds["model_period_uncertainty"] = ((), a.budget.period_uncertainty.to_value(u.day), _attrs("day", "one-sigma uncertainty of the full model's period"))
    pub = published_chandler_period()
    ds["published_period"] = ((), pub["period"].to_value(u.day), _attrs("day", "published Chandler period", references=pub["reference"]))
    ds["published_period_uncertainty"] = ((), pub["uncertainty"].to_value(u.day), _attrs("day", "one-sigma uncertainty of the published Chandler period"))
    if a.quality_factor is not None:
        q = a.quality_factor
        ds["quality_factor"] = ((), q.value, _attrs("1", "maximum-likelihood Q of the Chandler line (inf: unresolved)", comment="; ".join(q.caveats)))
        ds["quality_factor_low"] = ((), q.low, _attrs("1", "lower end of the 68 % interval of Q"))
        ds["quality_factor_high"] = ((), q.high, _attrs("1", "upper end of the 68 % interval of Q (inf: unbounded)"))
        ds["quality_factor_lower_bound_95"] = ((), q.lower_bound_95, _attrs("1", "one-sided 95 % lower bound of Q"))
    e = a.least_squares
    ds.attrs = {
        "title": "Observed polar motion and the Chandler wobble",
        "summary": (
            f"Chandler period {e.period.value:.1f} +/- {e.period_uncertainty.value:.1f} d and amplitude "
            f"{e.amplitude.value:.0f} +/- {e.amplitude_uncertainty.value:.0f} mas (least squares), "
            f"{a.spectral.period.value:.1f} +/- {a.spectral.period_uncertainty.value:.1f} d (spectrum), "
            f"{e.start.iso[:10]} to {e.end.iso[:10]}"
        ),
        "references": "; ".join([a.data.attrs.get("references", C04_REFERENCE), published_chandler_period()["reference"]]),
        "source_file": a.data.attrs.get("source_file", ""),
        "comment": SIGN_NOTE + ". Days are days of 86400 s. Windows: " + f"{a.windows.attrs['window_years']:g} yr every {a.windows.attrs['step_years']:g} yr.",
    }
    return ds


def _fmt(q, digits=1, unit=None) -> str:
    if q is None:
        return "-"
    x = float(q.to_value(unit) if unit is not None else q.value)
    return f"{x:.{digits}f}" if math.isfinite(x) else "-"


def _summary(a: PolarMotionAnalysis) -> str:
    e, s = a.least_squares, a.spectral
    lines = [
        f"Polar motion {e.start.iso[:10]} to {e.end.iso[:10]} ({e.n_samples} days; {os.path.basename(a.data.attrs.get('source_file', ''))})",
        "  p = x_p - i y_p: the Chandler term is at a positive (prograde) frequency",
        "",
        f"  Chandler wobble      {'period [d]':>18}  {'amplitude [mas]':>16}",
    ]
    for est, label in ((e, "least squares"), (s, "spectrum")):
        lines.append(
            f"  {label:<19}{_fmt(est.period):>9} +/- {_fmt(est.period_uncertainty):<5}  {_fmt(est.amplitude, 0):>7} +/- {_fmt(est.amplitude_uncertainty, 0):<5}"
        )
    parts = e.period_uncertainty_parts
    lines.append(
        "  period uncertainty (least squares): "
        + ", ".join(f"{k} {_fmt(v, 2)}" for k, v in parts.items() if k != "adopted")
        + " d; adopted = max(autocorrelation, subspans, excitation) with the model term in quadrature"
    )
    lines.append(f"  the two methods differ by {a.agreement:.1f} sigma ({'agree' if a.methods_agree else 'DISAGREE'})")
    lines.append(
        f"  annual wobble: prograde {_fmt(e.annual_prograde_amplitude, 1)} +/- {_fmt(e.annual_prograde_amplitude_uncertainty, 1)} mas, "
        f"retrograde {_fmt(e.annual_retrograde_amplitude, 1)} +/- {_fmt(e.annual_retrograde_amplitude_uncertainty, 1)} mas"
    )
    lines.append(
        f"  mean pole at {e.epoch.iso[:10]}: x {_fmt(e.mean_pole_x, 3)}\", y {_fmt(e.mean_pole_y, 3)}\", "
        f"drifting {_fmt(e.drift_rate, 1)} mas/yr toward {_fmt(e.drift_direction, 0)} deg W"
    )
    if a.quality_factor is not None:
        q = a.quality_factor
        value = "unresolved (inf)" if not math.isfinite(q.value) else f"{q.value:.0f}"
        hi = "inf" if not math.isfinite(q.high) else f"{q.high:.0f}"
        lines.append(f"  Q (line shape; see caveats): ML {value}, 68 % {q.low:.0f} to {hi}, 95 % lower bound {q.lower_bound_95:.0f}")
    lines += ["", "  Beside the model (wobble chandler earth) and the literature; days of 86400 s:"]
    lines.append(f"  {'':<44}{'period [d]':>11}{'residual [d]':>14}")
    for r in a.comparison():
        unc = "" if r["uncertainty"] is None else f" +/- {_fmt(r['uncertainty'])}"
        res = "" if r["residual"] is None else f"{r['residual'].to_value(u.day):+.1f}"
        if r["sigma"] is not None:
            res += f" ({abs(r['residual'] / r['sigma']).to_value(u.one):.1f} sigma)"
        lines.append(f"  {r['name']:<44}{_fmt(r['period']):>11}{unc:<9} {res}")
    w = a.windows
    amp = w["chandler_amplitude"].values
    mjd = w["window_time"].values
    lines += ["", f"  Windows of {w.attrs['window_years']:g} yr (centre: Chandler amplitude [mas], period [d]):"]
    for k in range(len(mjd)):
        if k % max(1, len(mjd) // 12) == 0 or k == len(mjd) - 1:
            lines.append(
                f"    {_iso(float(mjd[k]))}  {amp[k]:6.1f} +/- {w['chandler_amplitude_uncertainty'].values[k]:4.1f}   "
                f"{w['chandler_period'].values[k]:6.1f} +/- {w['chandler_period_uncertainty'].values[k]:4.1f}"
            )
    if a.caveats:
        lines += ["", "  Caveats:"] + [f"    - {c}" for c in a.caveats]
    return "\n".join(lines)
