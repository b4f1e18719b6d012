"""The geodetic excitation of polar motion with units (:func:`geodetic_excitation`).

>>> import wobble
>>> ex = wobble.geodetic_excitation(start="2000-01-01", end="2009-12-31")
>>> ex.to_dict()["round_trip_rms_mas"] < 1e-6
True

The excitation chi = chi_1 + i chi_2 is what drives the pole through the
Liouville equation with the complex Chandler frequency
sigma_c = 2 pi / T_c (1 + i / (2Q)) (:mod:`wobble.models.polar_motion.excitation`).
T_c and Q are wobble's own: the least-squares period of the whole record
given (also when ``start``/``end`` choose a part of it: the period is the
Earth's, and a few years of record measure it poorly) and the Q of the
Chandler budget's anelastic step, unless given. A given T_c must lie from
136 d to 1217 d (:data:`PERIOD_RANGE`), Q at least 1 (or inf).
"""

from __future__ import annotations

import math
import os

import numpy as np
from astropy import units as u

from wobble.api.polar_motion.estimate import published_chandler_period
from wobble.api.polar_motion.forecast import check_q, default_q
from wobble.api.polar_motion.record import (
    MJD_J2000,
    RAD_PER_MAS,
    observed_mas,
    series_with_attrs,
    short_span_error,
)
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.io.dates import MJD_UNITS, iso_date, select_dates
from wobble.models.polar_motion import excitation as _ex
from wobble.models.polar_motion.least_squares import fit_least_squares
from wobble.models.polar_motion.record import DAY, MIN_SPAN, pole_xy
from wobble.models.polar_motion.spectrum import two_sided_spectrum

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = ["GeodeticExcitation", "geodetic_excitation"]

#: The prograde Chandler band of the band-passed amplitudes: +/- 0.1 cycle per year around 1/T_c
#: (wobble.models.polar_motion.excitation.band_amplitude).
_BAND = 0.1 * 2 * math.pi / JULIAN_YEAR
#: The seasonal lines removed before the band-pass (prograde and retrograde annual and semi-annual, rad/s):
#: the annual's 17 mas of excitation leaked 0.5 mas into the band's RMS after 2015 (2.5 against 2.0).
_SEASONS = tuple(k * 2 * math.pi / JULIAN_YEAR for k in (1, -1, 2, -2))
#: The spectra cover -3 .. 3 cycles per year; the Chandler peak is compared with its neighbourhood
#: 0.1 to 0.3 cycle per year away (:meth:`GeodeticExcitation.to_dict`).
_SPECTRUM_CPY = 3.0
_NEIGHBOURHOOD_CPY = 0.3
#: The Chandler periods the analysis supports, s: a frequency from 0.3 to 2.7 cycles per year, so that
#: the Chandler band and its neighbourhood lie on the prograde side of the spectra, clear of zero
#: frequency (the mean pole) and inside their 3 cycles per year; 136 d to 1217 d, far above the
#: 2-d Nyquist period of the daily record.
PERIOD_RANGE = (JULIAN_YEAR / (_SPECTRUM_CPY - _NEIGHBOURHOOD_CPY), JULIAN_YEAR / _NEIGHBOURHOOD_CPY)
PERIOD_ALLOWED = (
    f"a Chandler period from {math.ceil(PERIOD_RANGE[0] / DAY):.0f} d to {math.floor(PERIOD_RANGE[1] / DAY):.0f} d "
    f"(a frequency of {_NEIGHBOURHOOD_CPY:g} to {_SPECTRUM_CPY - _NEIGHBOURHOOD_CPY:g} cycles per year: the "
    f"Chandler band and the neighbourhood it is compared with inside the {_SPECTRUM_CPY:g} cycles per year of the "
    "spectra, clear of the mean pole at zero frequency)"
)


def check_chandler_period(chandler_period) -> float:
    """A given T_c in s (a Quantity of time inside :data:`PERIOD_RANGE`), else InputError naming ``chandler_period``."""
    period = float(to_si(chandler_period, "chandler_period", u.s, finite=False, shape=()))
    if not (math.isfinite(period) and PERIOD_RANGE[0] <= period <= PERIOD_RANGE[1]):
        raise InputError("chandler_period", chandler_period, PERIOD_ALLOWED)
    return period


class GeodeticExcitation:
    """The excitation of a polar-motion record (build with :func:`geodetic_excitation`).

    Attributes
    ----------
    time_mjd : ndarray
        MJD (UTC) of the pole samples; the excitation of step k belongs to the
        step ending at ``time_mjd[k]`` (k >= 1).
    chi_1, chi_2 : Quantity
        The excitation, mas (NaN at the first sample, which starts the record).
    chandler_period : Quantity
    chandler_period_source : str
        Where T_c comes from: ``"given"``, or the span of the least-squares fit (the whole
        record, also when the excitation is of a part of it).
    quality_factor : float
    round_trip_rms : Quantity
        RMS distance between the record and the pole rebuilt by running the
        excitation forward (a check of the pair of equations; rounding only).
    band_chi, band_pole : ndarray or None
        Amplitudes (mas) of the excitation and the pole within +/- 0.1 cycle per year of the
        Chandler frequency, against time; NaN within :attr:`band_reach` (5 yr) of the record's
        ends, and None for unevenly sampled records and spans too short for a year of known
        amplitudes (11 yr).
    """

    def __init__(self, mjd, p, chi, p_back, period, q, source, period_source="given"):
        self.time_mjd = mjd
        self._p, self._chi, self._back = p, chi, p_back
        self.chandler_period = (period / DAY) << u.day
        self.chandler_period_source = period_source
        self.quality_factor = q
        self.source = source
        c = np.concatenate([[complex(np.nan, np.nan)], chi])  # nan + 0j had chi_2 = 0 at the first sample
        self.chi_1 = (c.real / RAD_PER_MAS) << u.mas
        self.chi_2 = (c.imag / RAD_PER_MAS) << u.mas
        self.round_trip_rms = (float(np.sqrt(np.mean(np.abs(p_back - p) ** 2))) / RAD_PER_MAS) << u.mas
        t = (mjd - MJD_J2000) * DAY
        sigma = 2 * math.pi / period
        uniform = np.allclose(np.diff(t), DAY, rtol=0, atol=1e-3)
        self.band_chi = self.band_pole = None
        # The band's amplitudes are known only beyond the kernel's reach of either end (5 yr): at least a
        # year of them, or none (a span of 11 years or more).
        resolved = t[-1] - t[1] >= 2 * _ex.band_reach(_BAND) + JULIAN_YEAR  # the excitation's span: from t[1]
        if uniform and resolved:
            self.band_chi = _ex.band_amplitude(t[1:], chi, sigma, _BAND, _SEASONS) / RAD_PER_MAS
            self.band_pole = _ex.band_amplitude(t, p, sigma, _BAND, _SEASONS) / RAD_PER_MAS

    @property
    def band_reach(self) -> u.Quantity:
        """How far the Chandler band-pass's kernel reaches either side (its amplitudes are NaN that near
        the record's ends; :func:`wobble.models.polar_motion.excitation.band_reach`)."""
        return (_ex.band_reach(_BAND) / JULIAN_YEAR) << u.yr

    def collapse(self, split="2015-01-01") -> dict | None:
        """RMS of the Chandler-band excitation and pole before and after ``split`` (mas; None if not computed)."""
        if self.band_chi is None:
            return None
        from wobble.io.dates import to_mjd

        cut = to_mjd(split, "split")
        mjd_chi = self.time_mjd[1:]
        # Where the band's amplitudes are known: beyond the kernel's reach of either end (band_amplitude).
        inner = np.isfinite(self.band_chi)
        before, after = inner & (mjd_chi < cut), inner & (mjd_chi >= cut)
        if before.sum() < 365 or after.sum() < 365:
            return None
        pole_inner = np.isfinite(self.band_pole)
        pb = pole_inner & (self.time_mjd < cut)
        pa = pole_inner & (self.time_mjd >= cut)

        def rms(v):
            return float(np.sqrt(np.mean(v**2)))

        return {
            "split": iso_date(cut),
            "before": [iso_date(mjd_chi[before][0]), iso_date(mjd_chi[before][-1])],
            "after": [iso_date(mjd_chi[after][0]), iso_date(mjd_chi[after][-1])],
            "excitation_before_mas": rms(self.band_chi[before]),
            "excitation_after_mas": rms(self.band_chi[after]),
            "pole_before_mas": rms(self.band_pole[pb]),
            "pole_after_mas": rms(self.band_pole[pa]),
            "band_cycles_per_year": [
                (1 / self.chandler_period.to_value(u.yr)) - 0.1,
                (1 / self.chandler_period.to_value(u.yr)) + 0.1,
            ],
        }

    def spectra(self, max_cpy: float = 3.0):
        """(frequency in cycles per year, excitation amplitude spectrum, pole amplitude spectrum), mas."""
        t = (self.time_mjd - MJD_J2000) * DAY
        reference = published_chandler_period()["period"].to_value(u.s)
        rate = max_cpy * 2 * math.pi / JULIAN_YEAR
        sp_p = two_sided_spectrum(t, self._p, reference_period=reference, max_rate=rate, drift_degree=2)
        sp_c = two_sided_spectrum(t[1:], self._chi, reference_period=reference, max_rate=rate, drift_degree=2)
        f = sp_p.rate / (2 * math.pi) * JULIAN_YEAR
        amp_c = np.interp(sp_p.rate, sp_c.rate, sp_c.amplitude)
        return f, amp_c / RAD_PER_MAS, sp_p.amplitude / RAD_PER_MAS

    def to_dict(self) -> dict:
        """The JSON of ``wobble excitation --json``."""
        f, ac, ap = self.spectra()
        pc = 1 / self.chandler_period.to_value(u.yr)
        # The peak: within 0.05 cycle/yr of 1/T_c, or the nearest frequency of the grid when it is coarser
        # (two years of record: 0.125 cycle/yr); the neighbourhood: 0.1 to 0.3 cycle/yr away, off the annual lines.
        step = float(f[1] - f[0])
        near = np.abs(f - pc) <= max(0.05, 0.5 * step * (1 + 1e-9))
        ring = (np.abs(f - pc) > 0.1) & (np.abs(f - pc) < _NEIGHBOURHOOD_CPY) & (np.abs(np.abs(f) - 1.0) > 0.05)
        return {
            "start": iso_date(float(self.time_mjd[0])),
            "end": iso_date(float(self.time_mjd[-1])),
            "n_samples": int(self.time_mjd.size),
            "chandler_period_days": float(self.chandler_period.value),
            "chandler_period_source": self.chandler_period_source,
            "quality_factor": self.quality_factor,
            "round_trip_rms_mas": float(self.round_trip_rms.value),
            "chi_1_rms_mas": float(np.sqrt(np.nanmean(self.chi_1.value**2))),
            "chi_2_rms_mas": float(np.sqrt(np.nanmean(self.chi_2.value**2))),
            "chandler_peak_over_neighbours": {
                "pole": float(np.mean(ap[near]) / np.mean(ap[ring])),
                "excitation": float(np.mean(ac[near]) / np.mean(ac[ring])),
            },
            "chandler_band_collapse": self.collapse(),
            "source_file": self.source,
            "method": "exact discrete inverse of the Liouville equation, excitation constant over each step "
            "(Wilson 1985; Gross 1992; Brzezinski 1992)",
        }

    def to_dataset(self):
        """The record, its excitation, the rebuilt pole, the Chandler-band amplitudes and both spectra (CF)."""
        from wobble.api.dataset import xarray
        from wobble.io import cf

        xr = xarray()
        mas = 1.0 / RAD_PER_MAS
        x, y = pole_xy(self._p)
        xb, yb = pole_xy(self._back)
        data = {
            "x_p": cf.variable("excitation", "x_p", observed_mas(x)),
            "y_p": cf.variable("excitation", "y_p", observed_mas(y)),
            "chi_1": cf.variable(
                "excitation",
                "chi_1",
                self.chi_1.value,
                comment="excitation of the step ending at each time; NaN at the first",
            ),
            "chi_2": cf.variable("excitation", "chi_2", self.chi_2.value),
            "x_p_round_trip": cf.variable("excitation", "x_p_round_trip", xb * mas),
            "y_p_round_trip": cf.variable("excitation", "y_p_round_trip", yb * mas),
            "chandler_period": cf.variable("excitation", "chandler_period", float(self.chandler_period.value)),
            "quality_factor": cf.variable("excitation", "quality_factor", float(self.quality_factor)),
            "round_trip_rms": cf.variable("excitation", "round_trip_rms", float(self.round_trip_rms.value)),
        }
        if self.band_chi is not None:
            reach = self.band_reach.to_value(u.yr)
            edges = (
                "the band within 0.1 cycle per year of the Chandler frequency; "
                f"NaN within {reach:.1f} yr of the record's ends, where the band-pass's kernel reaches past them"
            )
            data["chandler_band_chi"] = cf.variable(
                "excitation", "chandler_band_chi", np.concatenate([[np.nan], self.band_chi]), comment=edges
            )
            data["chandler_band_pole"] = cf.variable("excitation", "chandler_band_pole", self.band_pole, comment=edges)
        f, ac, ap = self.spectra()
        data["excitation_spectrum"] = cf.variable("excitation", "excitation_spectrum", ac)
        data["pole_spectrum"] = cf.variable("excitation", "pole_spectrum", ap)
        coords = {
            "time": cf.time_coordinate(self.time_mjd, MJD_UNITS, long_name="time (UTC)"),
            "frequency": cf.variable("excitation", "frequency", f),
        }
        ds = xr.Dataset(data, coords=coords)
        ds.attrs = {
            "title": "Geodetic excitation of polar motion",
            "summary": f"chi = chi_1 + i chi_2 from the pole {iso_date(float(self.time_mjd[0]))} to "
            f"{iso_date(float(self.time_mjd[-1]))}, "
            f"T_c = {self.chandler_period.value:.2f} d, Q = {self.quality_factor:.1f}",
            "references": "Munk & MacDonald 1960; Wilson 1985, J. Geophys. Res. 90; Gross 1992, Geophys. J. Int. "
            "109, 107; "
            "Brzezinski 1992, manuscripta geodaetica 17, 3",
            "source_file": self.source,
            "comment": "p = x_p - i y_p; p + (i/sigma_c) dp/dt = chi with sigma_c = 2 pi/T_c (1 + i/(2Q)); chi "
            "constant over each step",
        }
        return ds

    def __repr__(self) -> str:
        first, last = iso_date(float(self.time_mjd[0])), iso_date(float(self.time_mjd[-1]))
        return (
            f"GeodeticExcitation({first} to {last}, {self.time_mjd.size} days, "
            f"T_c={self.chandler_period.value:.1f} d, Q={self.quality_factor:g})"
        )

    def summary(self) -> str:
        """A few lines: sigma_c, the round trip, the excitation's size, the Chandler band before and after 2015."""
        d = self.to_dict()
        lines = [
            f"Geodetic excitation {d['start']} to {d['end']} ({d['n_samples']} samples): T_c = "
            f"{d['chandler_period_days']:.1f} d ({d['chandler_period_source']}), Q = {d['quality_factor']:.3g}",
            f"  chi_1 RMS {d['chi_1_rms_mas']:.1f} mas, chi_2 RMS {d['chi_2_rms_mas']:.1f} mas; round trip "
            f"(inverse then forward) RMS {d['round_trip_rms_mas']:.2e} mas",
            f"  Chandler peak over its neighbourhood: pole {d['chandler_peak_over_neighbours']['pole']:.1f}x, "
            f"excitation {d['chandler_peak_over_neighbours']['excitation']:.2f}x (broadband: no peak)",
        ]
        c = d["chandler_band_collapse"]
        if c:
            lines.append(
                f"  Chandler band (+/- 0.1 cycle/yr), RMS {c['before'][0]} to {c['before'][1]} / "
                f"{c['after'][0]} to {c['after'][1]}: excitation {c['excitation_before_mas']:.1f} / "
                f"{c['excitation_after_mas']:.1f} mas, pole {c['pole_before_mas']:.1f} / {c['pole_after_mas']:.1f} mas"
            )
        return "\n".join(lines)


def geodetic_excitation(
    data=None, *, file=None, start=None, end=None, chandler_period: u.Quantity | None = None, q: float | None = None
) -> GeodeticExcitation:
    """The excitation chi = chi_1 + i chi_2 of the pole, by the exact discrete Liouville equation, and its round trip.

    Parameters
    ----------
    data, file : Dataset, path or None
        The record (default: the shipped IERS 20 C04 series).
    start, end : date, optional
        The span (UTC dates).
    chandler_period : Quantity, optional
        T_c, from 136 d to 1217 d (default: wobble's least-squares period of the whole record given, also
        when ``start``/``end`` choose a part of it: T_c is the Earth's, not the span's).
    q : float, optional
        Q, at least 1 (default: the anelastic step of ``wobble.chandler_budget('earth')``, about 82; inf:
        undamped).

    Returns
    -------
    GeodeticExcitation

    Raises
    ------
    wobble.errors.InputError
        A ``chandler_period`` outside 136 d to 1217 d (:data:`PERIOD_RANGE`), Q below 1, a span
        (``start``/``end``) shorter than two years, the span of the spectra.
    """
    q_value = default_q() if q is None else check_q(q)
    given = None if chandler_period is None else check_chandler_period(chandler_period)
    # A file (or the shipped series) is read into plain arrays: the JSON and the text need no
    # Dataset, so xarray and pandas are imported only for -o and --plot (as in polar-motion).
    mjd_all, t_all, z_all, attrs = series_with_attrs(data, file)
    # Named as polar-motion names it ("the span of eopc04.1962-now"), where the record came from a file.
    whose = f"the span of {os.path.basename(attrs['source_file'])}" if attrs.get("source_file") else "the data"
    keep = slice(None) if start is None and end is None else select_dates(mjd_all, start, end, whose)
    mjd, t, z = mjd_all[keep], t_all[keep], z_all[keep]
    if t.size < 3 or t[-1] - t[1] < MIN_SPAN:
        # The spectra and the Chandler peak of to_dict() need two Julian years of excitation (a period needs two
        # cycles), which begins a sample after the pole: 731 d of daily pole had passed here and were refused
        # by the spectrum's own check, naming 'series'.
        step = float(t[1] - t[0]) if t.size > 1 else DAY
        why = (
            f": two Julian years ({MIN_SPAN / DAY:g} d) of excitation, which begins a sample after the pole, for "
            "the spectra and the Chandler peak"
        )
        # --start alone is told the latest start, --end alone the earliest end (both named "--start/--end").
        name = "data" if start is None and end is None else "start/end"
        raise short_span_error(mjd, start, end, (MIN_SPAN + step) / DAY, why, name=name)
    if given is None:
        reference = published_chandler_period()["period"].to_value(u.s)
        # Polished, as wobble polar-motion's is: the same period of the same record, to the last digit.
        fit = fit_least_squares(t_all, z_all, reference_period=reference, uncertainty=False, polish=True)
        period = fit.chandler.period
        source = f"least squares of the whole record, {iso_date(mjd_all[0])} to {iso_date(mjd_all[-1])}"
    else:
        period, source = given, "given"
    sigma = _ex.chandler_frequency(period, q_value)
    chi = _ex.excitation_from_pole(t, z, sigma)
    back = _ex.pole_from_excitation(t, chi, sigma, z[0])
    return GeodeticExcitation(mjd, z, chi, back, period, q_value, attrs.get("source_file", ""), source)
