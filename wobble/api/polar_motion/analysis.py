"""Everything ``wobble polar-motion`` reports: both estimates, sliding windows, the spectrum, Q, the model
beside them."""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass

import numpy as np
from astropy import units as u

from wobble.api.polar_motion.estimate import (
    DEPRECATED_KEYS,
    ChandlerEstimate,
    num,
    published_chandler_period,
    q_arg,
)
from wobble.api.polar_motion.record import SIGN_NOTE, record_attrs, record_dataset, resolve_series, short_span_error
from wobble.api._progress import stage_messages
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.io.dates import iso_date
from wobble.io.json_keys import deprecate
from wobble.models import polar_motion as _pm
from wobble.numerics.floats import HUGE

__all__ = ["QualityFactorEstimate", "PolarMotionAnalysis", "polar_motion_analysis", "JSON_RENAMES"]

# What the windows' spacing is allowed to be (finite besides).
_STEP = "at least 1 d (the sampling of the record)"

#: Keys of ``wobble polar-motion --json`` renamed for the vocabulary the other commands use (README, "Commands"),
#: kept under their old names for one release: old path -> new path. ``quality_factor`` held this object where
#: excitation and forecast hold the number; in the next release it becomes that number.
JSON_RENAMES = {
    "quality_factor": "quality_factor_estimate",
    "comparison[].uncertainty_days": "comparison[].period_uncertainty_days",
    "comparison[].residual_sigma_days": "comparison[].residual_uncertainty_days",  # a sigma in days, not a z-score
    "published.period": "published.period_days",
    "published.uncertainty": "published.period_uncertainty_days",
    "published.reference": "published.source",
    # The annual terms' old names where they are nested (each estimate also lists them in its own deprecated_keys).
    "estimates.*.annual_amplitude_mas": "estimates.*.annual_prograde_amplitude_mas",
    "estimates.*.annual_amplitude_uncertainty_mas": "estimates.*.annual_prograde_amplitude_uncertainty_mas",
    "windows.annual_amplitude_mas": "windows.annual_prograde_amplitude_mas",
}


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
            "value": num(self.value),
            "interval_68": [num(self.low), num(self.high)],
            "lower_bound_95": num(self.lower_bound_95),
            "resolved": self.resolved,
            "method": "Whittle likelihood of a randomly excited damped oscillator (Lorentzian line) near the "
            "Chandler peak",
            "caveats": list(self.caveats),
        }


class PolarMotionAnalysis:
    """Everything ``wobble polar-motion`` reports: both estimates, windows, spectrum, Q, the model beside it.

    Build with :func:`polar_motion_analysis`. The Datasets (``data``, ``windows``,
    ``spectrum``) are built on first use: the JSON and the text report read the
    same numbers from plain arrays, so they never import xarray.

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
    window_fits : wobble.models.polar_motion.WindowedFits
        The same in SI units (plain arrays).
    spectrum : xarray.Dataset
        Two-sided amplitude spectrum (dimension ``frequency``).
    quality_factor_estimate : QualityFactorEstimate or None
        Q from the Chandler line's shape (spans of 20 years or more), with its intervals. Until 2026-11-30
        this was ``quality_factor``, the name that is the number Q in the excitation, the forecast and the
        budget; the old name stays one release as a deprecated alias.
    budget : wobble.ChandlerBudget
        The model of ``wobble.chandler_budget("earth")``.
    source_file : str or None
        The file the record was read from.
    """

    def __init__(self, data, least_squares, spectral, windows, spectrum, quality_factor_estimate, budget, caveats):
        """``data`` is the record (a Dataset, or the :class:`~wobble.io.eop.PoleRecord` read from a file),
        ``windows`` the :class:`~wobble.models.polar_motion.WindowedFits` and ``spectrum`` the
        :class:`~wobble.models.polar_motion.Spectrum` of the model layer, or a function of no arguments
        that computes it (the JSON and the text do not show the spectrum: it is computed for the file
        and the figure, on first use)."""
        self._record = data
        self.least_squares = least_squares
        self.spectral = spectral
        self.window_fits = windows
        self._spectrum = spectrum
        self.quality_factor_estimate = quality_factor_estimate
        self.budget = budget
        self.method = "least_squares"
        self.caveats = tuple(caveats)

    @property
    def quality_factor(self) -> QualityFactorEstimate | None:
        """Deprecated alias of :attr:`quality_factor_estimate` (one release): elsewhere ``quality_factor`` is
        the number Q, which ``quality_factor_estimate.value`` holds."""
        warnings.warn(
            "PolarMotionAnalysis.quality_factor is deprecated; use quality_factor_estimate (its .value is Q), "
            "as the JSON's key is; the old name goes in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.quality_factor_estimate

    @functools.cached_property
    def data(self):
        """The record analysed (xarray.Dataset)."""
        from wobble.io.eop import PoleRecord

        return record_dataset(self._record) if isinstance(self._record, PoleRecord) else self._record

    @functools.cached_property
    def windows(self):
        """Sliding-window estimates (xarray.Dataset on the dimension ``window``)."""
        from wobble.api.polar_motion.dataset import windows_dataset

        return windows_dataset(self.window_fits)

    @functools.cached_property
    def spectrum(self):
        """Two-sided amplitude spectrum (xarray.Dataset on the dimension ``frequency``)."""
        from wobble.api.polar_motion.dataset import spectrum_dataset

        spectrum = self._spectrum() if callable(self._spectrum) else self._spectrum
        return spectrum_dataset(spectrum)

    @property
    def source_file(self) -> str | None:
        """The file the record was read from (None for a Dataset that does not say)."""
        from wobble.io.eop import PoleRecord

        if isinstance(self._record, PoleRecord):
            return record_attrs(self._record)["source_file"]
        return self._record.attrs.get("source_file")

    @functools.cached_property
    def published(self) -> dict:
        """The published Chandler period beside the estimate (:func:`published_chandler_period`)."""
        return published_chandler_period(self.budget.planet)

    @functools.cached_property
    def window_columns(self) -> dict:
        """The variables of :attr:`windows` as plain arrays (MJD, mas, days, degrees), without xarray."""
        from wobble.api.polar_motion.dataset import window_columns

        return window_columns(self.window_fits)

    @functools.cached_property
    def window_attrs(self) -> dict:
        """``window_years`` and ``step_years``: the attributes of :attr:`windows`."""
        from wobble.api.polar_motion.dataset import window_attrs

        return window_attrs(self.window_fits)

    @property
    def estimate(self) -> ChandlerEstimate:
        """The headline estimate (least squares)."""
        return self.least_squares

    @property
    def comparable(self) -> bool:
        """Whether both estimates resolve a Chandler term, so that their periods can be compared."""
        return self.least_squares.resolved and self.spectral.resolved

    @property
    def methods_agree(self) -> bool | None:
        """Whether the two periods differ by less than twice their combined one-sigma uncertainty (in quadrature);
        None when either estimate resolves no Chandler term (:attr:`comparable`): a period at the band's edge, or
        a term traded against the annual one, agrees or disagrees with nothing."""
        return self.agreement <= 2.0 if self.comparable else None

    @property
    def agreement(self) -> float:
        """``|P_ls - P_spectrum|`` / sqrt(sigma_ls^2 + sigma_spectrum^2); NaN when not :attr:`comparable`."""
        if not self.comparable:
            return math.nan
        a, b = self.least_squares, self.spectral
        diff = abs((a.period - b.period).to_value(u.day))
        return diff / math.hypot(a.period_uncertainty.to_value(u.day), b.period_uncertainty.to_value(u.day))

    def agreement_text(self) -> str:
        """The methods' agreement in words, as the text and the summary print it."""
        if self.comparable:
            verdict = "agree" if self.methods_agree else "DISAGREE"
            return f"the two methods differ by {self.agreement:.1f} sigma ({verdict})"
        which = [
            name for name, e in (("least squares", self.least_squares), ("spectrum", self.spectral)) if not e.resolved
        ]
        who = "neither method resolves a" if len(which) == 2 else f"the {which[0]} resolves no"
        return f"the two methods are not compared: {who} Chandler term in this span (the caveats say why)"

    def comparison(self) -> list[dict]:
        """The observed period beside every step of the model and the published value.

        Each row: ``name``, ``kind``, ``period`` (Quantity, d), ``period_uncertainty`` (or None),
        ``residual`` = period - observed (Quantity, d, or None for the observed row) and
        ``residual_uncertainty`` (the combined one-sigma of the residual, in days, where both sides
        have one), the names of the JSON. ``uncertainty`` and ``sigma``, their older names, are kept
        (``sigma`` is a one-sigma in days, not a number of sigmas).
        """
        obs = self.estimate
        # Residuals from a period the span does not resolve would measure the search, not the wobble: left out.
        compared = obs.resolved
        rows = [
            {
                "name": f"observed ({obs.method.replace('_', ' ')})",
                "kind": "observed",
                "period": obs.period,
                "uncertainty": obs.period_uncertainty,
                "residual": None,
                "sigma": None,
            }
        ]
        for step in self.budget.steps:
            final = step is self.budget.steps[-1]
            unc = self.budget.period_uncertainty if final else None
            sigma = np.hypot(unc, obs.period_uncertainty) if final and compared else None
            rows.append(
                {
                    "name": f"model: {step.name}",
                    "kind": "model",
                    "period": step.period,
                    "uncertainty": unc,
                    "residual": step.period - obs.period if compared else None,
                    "sigma": sigma,
                }
            )
        pub = self.published
        rows.append(
            {
                "name": "published (Vicente & Wilson 1997)",
                "kind": "published",
                "period": pub["period"],
                "uncertainty": pub["uncertainty"],
                "residual": pub["period"] - obs.period if compared else None,
                "sigma": np.hypot(pub["uncertainty"], obs.period_uncertainty) if compared else None,
            }
        )
        for r in rows:
            r.update(period_uncertainty=r["uncertainty"], residual_uncertainty=r["sigma"])
        return rows

    def to_dict(self) -> dict:
        """The JSON of ``wobble polar-motion --json``."""
        est = self.estimate
        out = {
            "chandler_period_days": num(est.period),
            "chandler_period_uncertainty_days": num(est.period_uncertainty),
            "chandler_amplitude_mas": num(est.amplitude),
            "chandler_amplitude_uncertainty_mas": num(est.amplitude_uncertainty),
            "annual_prograde_amplitude_mas": num(est.annual_prograde_amplitude),
            "annual_prograde_amplitude_uncertainty_mas": num(est.annual_prograde_amplitude_uncertainty),
            "annual_retrograde_amplitude_mas": num(est.annual_retrograde_amplitude),
            "annual_retrograde_amplitude_uncertainty_mas": num(est.annual_retrograde_amplitude_uncertainty),
            "start": iso_date(est.start),
            "end": iso_date(est.end),
            "method": est.method,
            "chandler_resolved": est.resolved,
            "source_file": self.source_file,
            "sign_convention": SIGN_NOTE,
            "day": "days of 86400 s",
            "estimates": {e.method: e.to_dict() for e in (self.least_squares, self.spectral)},
            # null when either estimate resolves no Chandler term (the caveats say why): nothing to agree with.
            "methods_agree": None if self.methods_agree is None else bool(self.methods_agree),
            "agreement_sigma": num(self.agreement),
            # An object here (with its interval and method), a number in excitation and forecast.
            "quality_factor_estimate": None
            if self.quality_factor_estimate is None
            else self.quality_factor_estimate.to_dict(),
            "windows": _windows_dict(self.window_columns, self.window_attrs),
            "comparison": [
                {
                    "name": r["name"],
                    "kind": r["kind"],
                    "period_days": num(r["period"]),
                    "period_uncertainty_days": num(r["uncertainty"]),
                    "residual_days": num(r["residual"]),
                    "residual_uncertainty_days": num(r["sigma"]),
                }
                for r in self.comparison()
            ],
            "published": {
                "period_days": num(self.published["period"]),
                "period_uncertainty_days": num(self.published["uncertainty"]),
                "source": self.published["reference"],
            },
            "caveats": list(self.caveats),
        }
        return deprecate(out, {**DEPRECATED_KEYS, **JSON_RENAMES})

    def to_dataset(self):
        """The series, the fitted model, the residuals, the windows, the spectrum and the estimates, CF-ready
        (xarray.Dataset)."""
        from wobble.api.polar_motion.dataset import analysis_dataset

        return analysis_dataset(self)

    def summary(self) -> str:
        """A few lines for a person: both estimates, the annual terms, Q, the model and the published value.

        ``wobble polar-motion`` prints a longer report (uncertainty parts, the
        model step by step, the windows).
        """
        e, s = self.least_squares, self.spectral

        def pm(q, sigma, digits):
            x, dx = q.value, sigma.value
            return f"{x:.{digits}f} +/- {dx:.{digits}f}" if math.isfinite(dx) else f"{x:.{digits}f}"

        lines = [
            f"Chandler wobble {iso_date(e.start)} to {iso_date(e.end)} "
            f"({e.n_samples} days; p = x_p - i y_p, prograde):",
            f"  least squares {pm(e.period, e.period_uncertainty, 1)} d, "
            f"{pm(e.amplitude, e.amplitude_uncertainty, 0)} mas{_unresolved(e)}",
            f"  spectrum      {pm(s.period, s.period_uncertainty, 1)} d, "
            f"{pm(s.amplitude, s.amplitude_uncertainty, 0)} mas{_unresolved(s)}"
            + (
                f" ({'agree' if self.methods_agree else 'DISAGREE'}: {self.agreement:.1f} sigma apart)"
                if self.comparable
                else ""
            ),
            "  annual wobble: prograde "
            f"{pm(e.annual_prograde_amplitude, e.annual_prograde_amplitude_uncertainty, 1)} mas, "
            f"retrograde {pm(e.annual_retrograde_amplitude, e.annual_retrograde_amplitude_uncertainty, 1)} mas"
            + e.annual_note,
        ]
        if not self.comparable:
            lines.append(f"  {self.agreement_text()}")
        if self.quality_factor_estimate is not None:
            q = self.quality_factor_estimate
            hi = "inf" if not math.isfinite(q.high) else f"{q.high:.0f}"
            lines.append(
                f"  Q (line shape): 68 % interval {q.low:.0f} to {hi}, 95 % lower bound {q.lower_bound_95:.0f}"
            )
            lines += [f"    Q caveat: {c}" for c in q.caveats]
        pub = self.published
        lines.append(
            f"  model (wobble.chandler_budget('earth')) {pm(self.budget.period, self.budget.period_uncertainty, 1)} d; "
            f"published {pm(pub['period'], pub['uncertainty'], 1)} d (Vicente & Wilson 1997)"
        )
        lines += [f"  caveat: {c}" for c in self.caveats]
        return "\n".join(lines)

    def __repr__(self) -> str:
        e = self.estimate
        return (
            f"PolarMotionAnalysis({iso_date(e.start)} to {iso_date(e.end)}, "
            f"period={e.period.value:.1f} +/- {e.period_uncertainty.value:.1f} d"
            f"{'' if e.resolved else ', not resolved'})"
        )


def _unresolved(estimate) -> str:
    """ " (not resolved: why)" after an estimate that resolves no Chandler term, "" otherwise."""
    return "" if estimate.resolved else f" (not resolved: {estimate.unresolved_because})"


def _windows_dict(w: dict, a: dict) -> dict:
    return {
        "window_years": float(a["window_years"]),
        "step_years": float(a["step_years"]),
        "centre": [iso_date(float(m)) for m in w["window_time"]],
        "chandler_amplitude_mas": [num(v) for v in w["chandler_amplitude"]],
        "chandler_amplitude_uncertainty_mas": [num(v) for v in w["chandler_amplitude_uncertainty"]],
        "chandler_period_days": [num(v) for v in w["chandler_period"]],
        "chandler_period_uncertainty_days": [num(v) for v in w["chandler_period_uncertainty"]],
        "annual_prograde_amplitude_mas": [num(v) for v in w["annual_prograde_amplitude"]],
    }


#: The sliding windows' default length, s: 8 Julian years (the span instead, when shorter).
DEFAULT_WINDOW = 8 * _pm.JULIAN_YEAR


def polar_motion_analysis(
    data=None,
    *,
    start=None,
    end=None,
    window: u.Quantity | None = None,
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
    window : Quantity, optional
        Length of the sliding windows (default 8 Julian years, or the span when
        it is shorter; at least 2 years of samples and at most the span; under
        the 6.4-yr Chandler-annual beat the windows barely separate the two terms).
    step : Quantity
        Spacing of the windows (default 1 year; at least 1 d, the sampling).
    quality_factor : bool
        Also estimate Q from the line shape (spans of 20 years or more).
    progress : bool or callable, optional
        ``progress(message)`` is called at each stage (True prints a line on stderr for each; the CLI shows
        them on a terminal).

    Returns
    -------
    PolarMotionAnalysis
    """
    from wobble.api.chandler import chandler_budget, load_planet

    say = stage_messages(progress)
    # A file (or None, the shipped C04 series) is read into plain arrays: the Dataset is built only if
    # the caller asks for it (PolarMotionAnalysis.data), so the JSON and the text never import xarray.
    mjd, t, z, record = resolve_series(data, start, end)
    window_s, step_s, default_window = _window_and_step(mjd, t, start, end, window, step)
    q_value = q_arg(excitation_q)
    span = t[-1] - t[0]
    say("least-squares fit")
    earth = load_planet("earth")  # read once: the reference period here, the budget and the comparison below
    reference = published_chandler_period(earth)["period"].to_value(u.s)
    ls = _pm.fit_least_squares(
        t, z, reference_period=reference, drift_degree=drift_degree, excitation_q=q_value, draws=draws
    )
    say("spectral estimate")
    sp = _pm.fit_spectrum(
        t, z, reference_period=reference, drift_degree=drift_degree, excitation_q=q_value, draws=draws
    )
    # Only the file and the figure show the spectrum (23,648 samples at 1,600 frequencies): computed on first use.
    spectrum = functools.partial(_pm.two_sided_spectrum, t, z, reference_period=reference, drift_degree=drift_degree)

    def window_progress(done, total):
        if done % 5 == 0 or done == total:
            say(f"windows {done}/{total}")

    wf = _pm.sliding_windows(
        t, z, window_s, step_s, reference_period=reference, drift_degree=drift_degree, progress=window_progress
    )
    caveats = _analysis_caveats(ls, sp, wf, window_s, default_window, reference)
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
        data=record,
        least_squares=ChandlerEstimate.from_fit(ls),
        spectral=ChandlerEstimate.from_fit(sp),
        windows=wf,
        spectrum=spectrum,
        quality_factor_estimate=qf,
        budget=chandler_budget(earth),
        caveats=caveats,
    )


def _window_and_step(mjd, t, start, end, window, step) -> tuple[float, float, bool]:
    """The sliding windows' length and spacing (s), checked against the span, and whether the length is the
    default one."""
    # Non-positive and non-finite lengths meet the range checks below (which say what is allowed).
    window_s = None if window is None else to_si(window, "window", u.s, finite=False, shape=())
    step_s = to_si(step, "step", u.s, finite=False, shape=())
    if not math.isfinite(step_s):
        # 1e400 (inf once read) had been told "at least 1 d", which it is: the fault is that it is not a number.
        raise InputError(
            "step", step, f"a finite time (not NaN, inf, or past the largest double of seconds, {HUGE:.4g} s), {_STEP}"
        )
    if not step_s >= _pm.DAY * (1 - 1e-9):
        # Windows moved by less than a sample are the same windows (and 0.001 yr made 64,000 of them).
        raise InputError("step", step, _STEP)
    span = t[-1] - t[0]
    shortest = _pm.shortest_window(t)
    if span < shortest:
        # The least span is the shortest sliding window's: two Julian years of samples in it (730.5 d, which
        # the message had rounded to 730) and a sample at each end; 731-732 d passed this check and were
        # refused by the window's.
        # --start alone is told the latest start, --end alone the earliest end (both named "--start/--end").
        raise short_span_error(
            mjd,
            start,
            end,
            shortest / _pm.DAY,
            f" (two Julian years, {_pm.MIN_SPAN / _pm.DAY:g} d, of samples in each sliding window)",
        )
    default_window = window_s is None
    if default_window:  # 8 years, or the span when shorter (a five-year span was refused its default window)
        window_s = min(DEFAULT_WINDOW, span)
    if not (math.isfinite(window_s) and shortest <= window_s <= span * (1 + 1e-9)):
        raise InputError("window", window, _pm.window_allowed(t))
    return window_s, step_s, default_window


def _analysis_caveats(ls, sp, wf, window_s: float, default_window: bool, reference: float) -> list[str]:
    """What the analysis cannot say: the least squares' caveats, the spectrum's band edge, unresolved
    windows, a default window cut to the span, windows shorter than the Chandler-annual beat."""
    caveats = list(ls.caveats)
    # The spectral estimate's own, where it resolves no peak (its edge caveat had stayed in its JSON alone, while
    # the text compared its band-edge 390 d with the least squares).
    edge = sp.details.get("edge_caveat")
    if edge and edge not in caveats:
        caveats.append(edge)
    if wf.unresolved:
        lo, hi = (b / _pm.DAY for b in _pm.CHANDLER_BAND)
        caveats.append(
            f"{wf.unresolved} of {wf.centre.size} windows found no Chandler term inside the search band "
            f"({lo:.0f}-{hi:.0f} d), or none separable from the annual terms: their values are left out"
        )
    if default_window and window_s < DEFAULT_WINDOW:
        caveats.append(
            f"one window, the whole span ({window_s / _pm.JULIAN_YEAR:.2f} yr): the default window of "
            f"{DEFAULT_WINDOW / _pm.JULIAN_YEAR:g} yr is longer than the span"
        )
    if window_s < _pm.beat_period(reference):
        caveats.append(
            f"windows of {window_s / _pm.JULIAN_YEAR:.1f} yr are shorter than the 6.4-yr Chandler-annual beat: "
            "the windowed terms are barely separable"
        )
    return caveats
