"""The two-sided spectrum of the pole and the Chandler term from its peak (independent of the least squares).

Negative rates are retrograde terms, positive prograde (equation 1 of
:mod:`wobble.models.polar_motion.record`). Times in s, angles in rad, rates
in rad/s.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from wobble.errors import InputError
from wobble.models.polar_motion.fit import ChandlerFit, Uncertainty, make_fit, with_changes
from wobble.models.polar_motion.record import (
    ANNUAL_RATE,
    CHANDLER_BAND,
    DAY,
    TROPICAL_YEAR,
    as_series,
    beat_period,
    check_band,
    check_degree,
    check_q,
    span_caveats,
)
from wobble.models.polar_motion.search import at_band_edge, band_grid, refine_peaks
from wobble.models.polar_motion.uncertainty import (
    TRACKED,
    annual_sigmas,
    combine,
    excitation_scatter,
    largest_change,
    model_degrees,
    subspan_scatter,
    tracked_columns,
)
from wobble.numerics.phasor import uniform_grid
from wobble.numerics.spectral import dtft, exponentials
from wobble.numerics.threads import one_blas_thread

__all__ = ["Spectrum", "two_sided_spectrum", "fit_spectrum", "spectrum_periods", "spectrum_tracked"]

_PREWHITEN = 30


@dataclass(frozen=True, eq=False)
class Spectrum:
    """Two-sided amplitude spectrum of a detrended pole series.

    ``amplitude[k]`` is |sum w z exp(-i rate_k s)| / sum w: the radius (rad) of
    a circular term at ``rate[k]`` (rad/s; negative = retrograde).
    """

    rate: np.ndarray
    amplitude: np.ndarray
    taper: str
    drift_degree: int


def _detrend(s, z, half, degree):
    tau = s / half
    v = np.stack([tau**j for j in range(degree + 1)], axis=1).astype(complex)
    c = np.linalg.lstsq(v, z, rcond=None)[0]
    return z - v @ c, c


def _taper(t, kind: str) -> np.ndarray:
    if kind == "hann":
        return np.sin(np.pi * (t - t[0]) / (t[-1] - t[0])) ** 2
    return np.ones_like(t)


def _auto_taper(span: float, taper: str, beat: float) -> str:
    if taper not in ("auto", "hann", "none"):
        raise InputError("taper", taper, "'auto', 'hann' or 'none'")
    if taper == "auto":
        # With the annual terms prewhitened, the Hann main lobe (half-width 2/T)
        # may overlap the annual peak; under one beat period it is too wide.
        return "hann" if span >= beat else "none"
    return taper


@one_blas_thread
def two_sided_spectrum(
    t,
    z,
    *,
    reference_period: float,
    max_rate: float = 3.0 * 2 * math.pi / TROPICAL_YEAR,
    drift_degree: int = 2,
    taper: str = "auto",
    oversample: int = 4,
) -> Spectrum:
    """Amplitude spectrum |sum w y e^{-i sigma s}| / sum w of the detrended series, for -max_rate..max_rate.

    Negative rates are retrograde terms, positive prograde (equation 1). The
    grid is ``oversample`` times finer than the Rayleigh resolution 2 pi / T.
    ``taper="auto"`` is Hann when the span is at least one Chandler-annual beat
    period (from ``reference_period``, a published Chandler period in s, as in
    :func:`fit_spectrum`), otherwise none.
    """
    t, z = as_series(t, z)
    degree = check_degree(drift_degree)
    span = t[-1] - t[0]
    kind = _auto_taper(span, taper, beat_period(reference_period))
    epoch = 0.5 * (t[0] + t[-1])
    s = t - epoch
    y, _ = _detrend(s, z, 0.5 * span, degree)
    w = _taper(t, kind)
    d = 2 * math.pi / (oversample * span)
    count = int(2 * math.ceil(max_rate / d)) + 1
    rates = -math.ceil(max_rate / d) * d + d * np.arange(count)
    amp = np.abs(dtft(s, w * y, rates[0], d, count)) / w.sum()
    return Spectrum(rates, amp, kind, degree)


@one_blas_thread
def fit_spectrum(
    t,
    z,
    *,
    reference_period: float,
    drift_degree: int = 2,
    band: tuple[float, float] = CHANDLER_BAND,
    taper: str = "auto",
    uncertainty: bool = True,
    subspans: bool = True,
    excitation_q: float | None = 100.0,
    draws: int = 64,
    seed: int = 0,
) -> ChandlerFit:
    """The Chandler term from the peak of the two-sided spectrum (independent of the least squares).

    The series is detrended with a polynomial of ``drift_degree``, tapered
    (Hann when the span is at least one beat period, otherwise none) and
    Fourier-summed at its own sample times (gaps need no filling). The peak in
    the prograde band is refined by bounded Brent on the sum (on a uniform grid
    of times its exponentials by block rotation, within a few ulps:
    :func:`~wobble.numerics.spectral.phases`); the amplitude is |F|/sum w. The
    annual terms are read at +/- one cycle per tropical year and removed before the peak is sought again (prewhitening,
    repeated until the peak stops moving), so the annual peak's main lobe does not pull the Chandler
    peak in short spans. Nothing is fitted jointly: this is a spectral
    estimator, independent of :func:`fit_least_squares`.

    The ``autocorrelation`` error is the peak-location variance in coloured
    noise, var(sigma) = S sum(w^2 s^2) / (2 |A|^2 (sum w s^2)^2), with S the
    level of the residual spectrum (the three terms removed) beside the peak
    (Whittle 1952; Hannan 1973); ``subspans``, ``excitation`` and ``model`` as
    in :func:`~wobble.models.polar_motion.least_squares.fit_least_squares`,
    which also describes the parameters (``reference_period`` included).
    """
    t, z = as_series(t, z)
    degree = check_degree(drift_degree)
    band = check_band(band)
    beat = beat_period(reference_period)
    span = t[-1] - t[0]
    kind = _auto_taper(span, taper, beat)
    epoch = 0.5 * (t[0] + t[-1])
    half = 0.5 * span
    s = t - epoch
    y, drift = _detrend(s, z, half, degree)
    w = _taper(t, kind)
    lo_rate, hi_rate = 2 * math.pi / band[1], 2 * math.pi / band[0]
    d = band_grid(lo_rate, hi_rate, span)[1]
    annual_cols = np.exp(1j * ANNUAL_RATE * np.outer(s, [1.0, -1.0]))
    # The drift model's check (one degree less and one more) searches the same times with the same
    # taper: its series go through the prewhitening with this one (the grid's exponentials shared).
    checks = model_degrees(degree) if uncertainty else []
    ys = np.column_stack([y] + [_detrend(s, z, half, k)[0] for k in checks])
    rates, chandlers, anns = _prewhitened_peaks(s, ys, w, lo_rate, hi_rate, span)
    rate, chandler, ann = float(rates[0]), complex(chandlers[0]), anns[:, 0]
    f = np.array([chandler, ann[0], ann[1]])
    coeffs = np.concatenate([drift, [f[1], f[2], f[0]]])
    resid = y - f[0] * np.exp(1j * rate * s) - annual_cols @ ann
    caveats = span_caveats(span, beat)
    if kind == "none" and taper == "auto":
        caveats.append(
            "span under one beat period: no taper, so the side lobes of other terms leak into the Chandler peak"
        )
    edge_caveat = _edge_caveat(rate, lo_rate, hi_rate, d, band)
    at_edge = edge_caveat is not None
    if at_edge:
        caveats.append(edge_caveat)
    nan = math.nan
    ann_sig = [(nan, nan), (nan, nan)]
    sig_rate = sig_amp = sig_phase = nan
    pu = au = Uncertainty(nan, nan, nan, nan, nan)
    # The edge caveat by itself too: the analysis passes on this one of the spectrum's caveats (not its span's).
    details: dict = {
        "taper": kind,
        "at_edge": bool(at_edge),
        "band": band,
        "edge_caveat": edge_caveat,
    }
    if uncertainty:
        p_formal, a_formal, p_auto, a_auto, ann_auto = _peak_sigmas(s, w, resid, f, rate, span, kind)
        sig_phase = a_auto / abs(f[0])
        sub = dict.fromkeys(TRACKED, nan)
        if subspans:
            sub, details["subspans"] = _subspans(t, z, reference_period, degree, band, kind, beat)
        base = make_fit("spectrum", t, epoch, half, degree, coeffs, rate, resid, 0, 0, 0, ann_auto)
        # What fit_spectrum(t, z, drift_degree=k, uncertainty=False) gives for the model check's degrees.
        mod = largest_change(base, tracked_columns(rates[1:], chandlers[1:], anns[0, 1:], anns[1, 1:]))
        p_sub, a_sub, p_mod, a_mod = sub["period"], sub["amplitude"], mod["period"], mod["amplitude"]
        ann_sig = annual_sigmas(ann_auto, sub, mod)
        p_exc = math.nan
        if excitation_q is not None:
            batch = functools.partial(
                spectrum_periods, reference_period=reference_period, drift_degree=degree, band=band, taper=kind
            )
            p_exc = excitation_scatter(t, base, batch, check_q(excitation_q), draws, seed)
            details["excitation_q"] = float(excitation_q)
        pu = combine(p_formal, p_auto, p_sub, p_mod, p_exc)
        au = combine(a_formal, a_auto, a_sub, a_mod)
        sig_rate = pu.adopted * rate**2 / (2 * math.pi)
        sig_amp = au.adopted
    fit = make_fit("spectrum", t, epoch, half, degree, coeffs, rate, resid, sig_rate, sig_amp, sig_phase, ann_sig)
    return with_changes(fit, period_uncertainty=pu, amplitude_uncertainty=au, caveats=tuple(caveats), details=details)


def _edge_caveat(rate: float, lo_rate: float, hi_rate: float, step: float, band) -> str | None:
    """The caveat of a peak within half a grid step of the search band's edge (no Chandler peak resolved), or
    None."""
    if not at_band_edge(rate, lo_rate, hi_rate, step):
        return None
    return (
        f"the spectral peak lies at the edge of the search band {band[0] / DAY:.0f}-{band[1] / DAY:.0f} d: "
        "no Chandler peak is resolved in this span"
    )


def _subspans(t, z, reference_period: float, degree: int, band, kind: str, beat: float):
    """The scatter of the tracked quantities over sub-spans (:func:`subspan_scatter`, this estimator with the same
    settings), and how many sub-spans there were."""
    batch = functools.partial(
        spectrum_tracked, reference_period=reference_period, drift_degree=degree, band=band, taper=kind
    )
    return subspan_scatter(
        t, z, fit_spectrum, beat, batch, reference_period=reference_period, band=band, drift_degree=degree, taper=kind
    )


def _peak_sigmas(s, w, resid, f, rate: float, span: float, kind: str):
    """The white-noise ("formal") and coloured-noise ("autocorrelation") sigmas of the Chandler period and
    amplitude, and the annual terms' (amplitude, phase) sigmas, from the peak-location variance
    var(sigma) = S sum(w^2 s^2) / (2 |A|^2 (sum w s^2)^2) (Whittle 1952; Hannan 1973)."""
    fitted = (rate, ANNUAL_RATE, -ANNUAL_RATE)
    level = _local_level(s, w * resid, w, rate, span, kind, fitted)
    sw, sw2 = w.sum(), np.sum(w**2)
    sc = s - np.sum(w * s) / sw
    amp = abs(f[0])
    var_rate = level * np.sum(w**2 * sc**2) / (2 * amp**2 * np.sum(w * sc**2) ** 2)
    var_amp = level * sw2 / (2 * sw**2)
    to_period = 2 * math.pi / rate**2
    white = np.mean(np.abs(resid) ** 2)
    p_formal = math.sqrt(white * np.sum(w**2 * sc**2) / (2 * amp**2 * np.sum(w * sc**2) ** 2)) * to_period
    a_formal = math.sqrt(white * sw2 / (2 * sw**2))
    ann_auto = []
    for k, sign in ((1, 1.0), (2, -1.0)):
        a_k = math.sqrt(_local_level(s, w * resid, w, sign * ANNUAL_RATE, span, kind, fitted) * sw2 / (2 * sw**2))
        ann_auto.append((a_k, a_k / max(abs(f[k]), 1e-300)))
    return p_formal, a_formal, math.sqrt(var_rate) * to_period, math.sqrt(var_amp), ann_auto


def _prewhitened_peaks(s, y, w, lo_rate, hi_rate, span):
    """The Chandler peak of each column of ``y`` (n, m; detrended), by the prewhitening of :func:`fit_spectrum`.

    Returns the rates (m,), the Chandler terms |F|/sum w (m,) and the annual terms (2, m: prograde,
    retrograde). The columns go through the loop together, each for as many rounds as it needs
    alone: the grid's Fourier sums are one matrix product for all of them, the bounded Brent
    refinements one array operation per step (:func:`~wobble.models.polar_motion.search.refine_peaks`,
    their exponentials by block rotation on a uniform grid), and a column leaves the loop when its
    peak stops moving.
    """
    m = y.shape[1]
    rates, d = band_grid(lo_rate, hi_rate, span)
    grid = uniform_grid(s)
    annual_cols = np.exp(1j * ANNUAL_RATE * np.outer(s, [1.0, -1.0]))
    annual_phase = np.exp(-1j * np.multiply.outer(np.array([ANNUAL_RATE, -ANNUAL_RATE]), s))
    sw = w.sum()
    rate = np.full(m, math.nan)
    chandler = np.zeros(m, dtype=complex)
    ann = np.zeros((2, m), dtype=complex)
    running = np.arange(m)
    for _ in range(_PREWHITEN):
        # Prewhitening (CLEAN-like): remove the current annual terms, find the
        # Chandler peak, remove it, read the annual terms again; repeat until the
        # peak stops moving (block relaxation, which converges however much the
        # main lobes overlap, only more slowly).
        i = running
        wy = w[:, None] * (y[:, i] - annual_cols @ ann[:, i])
        rows = np.ascontiguousarray(wy.T)
        power = np.abs(dtft(s, wy, rates[0], d, rates.size)) ** 2

        def power_at(r, index, rows=rows):
            return np.abs(np.einsum("kn,kn->k", exponentials(s, r, grid), rows[index])) ** 2

        previous = rate[i]
        rate[i] = refine_peaks(power_at, rates, power, d, lo_rate, hi_rate)
        phase = exponentials(s, rate[i], grid)
        chandler[i] = np.einsum("kn,kn->k", phase, rows) / sw
        line = chandler[i] * phase.conj().T  # the Chandler term, exp(+i rate s) = conj(exp(-i rate s))
        ann[:, i] = annual_phase @ (w[:, None] * (y[:, i] - line)) / sw
        running = i[~(np.abs(rate[i] - previous) < 1e-3 * d)]
        if not running.size:
            break
    return rate, chandler, ann


def spectrum_periods(t, zs, *, reference_period: float, drift_degree: int, band, taper: str) -> np.ndarray:
    """Chandler periods (s) of many series on the same times by the spectral estimator (no uncertainty).

    Column k of ``zs`` gives the period ``fit_spectrum(t, zs[:, k], uncertainty=False, ...)`` would
    (the same detrending, taper and prewhitened peak search, all columns at once: the Monte Carlo
    of :func:`~wobble.models.polar_motion.uncertainty.excitation_scatter`).
    """
    rates, _, _ = _spectral_peaks(t, zs, reference_period, drift_degree, band, taper)
    return 2 * math.pi / np.abs(rates)


def spectrum_tracked(t, zs, *, reference_period: float, drift_degree: int, band, taper: str) -> list[dict]:
    """What ``fit_spectrum(t, zs[:, k], uncertainty=False, ...)`` gives of the tracked quantities
    (:func:`~wobble.models.polar_motion.uncertainty.tracked`), for many series on the same times at once
    (the sub-spans of :func:`~wobble.models.polar_motion.uncertainty.subspan_scatter`)."""
    rates, chandlers, anns = _spectral_peaks(t, zs, reference_period, drift_degree, band, taper)
    return tracked_columns(rates, chandlers, anns[0], anns[1])


def _spectral_peaks(t, zs, reference_period, drift_degree, band, taper):
    """:func:`_prewhitened_peaks` of many series on the same times, detrended and tapered as by fit_spectrum."""
    t = np.asarray(t, dtype=float)
    degree = check_degree(drift_degree)
    band = check_band(band)
    span = t[-1] - t[0]
    kind = _auto_taper(span, taper, beat_period(reference_period))
    epoch = 0.5 * (t[0] + t[-1])
    s = t - epoch
    y, _ = _detrend(s, np.asarray(zs, dtype=complex), 0.5 * span, degree)
    lo_rate, hi_rate = 2 * math.pi / band[1], 2 * math.pi / band[0]
    return _prewhitened_peaks(s, y, _taper(t, kind), lo_rate, hi_rate, span)


def _outside_lobe(count: int, centre: int, steps: int) -> np.ndarray:
    """Which of ``count`` grid points lie strictly more than ``steps`` grid steps from point ``centre``.

    The main lobe is a whole number of steps of the ring's grid (4 or 8 of 2 pi / (4 span)),
    so its edge points are told apart by their index: |grid - rate| > lobe compared two
    roundings of the same number there, and which way it went depended on the BLAS build.
    """
    return np.abs(np.arange(count) - centre) > steps


def _local_level(s, wr, w, rate, span, kind, fitted=()) -> float:
    """Mean |F_w r|^2 / sum w^2 in a ring 0.1 cycle per year wide just outside the peak's main lobe.

    For white noise of variance sigma^2 this is sigma^2; for coloured noise it
    is the noise spectral density near ``rate`` in the same units (the "S"
    of the peak-location variance). The main lobes of the fitted terms
    (``rate`` and ``fitted``) are left out: their removal leaves holes in
    the residual spectrum there.
    """
    year_rate = 2 * math.pi / TROPICAL_YEAR
    lobe = (2.0 if kind == "hann" else 1.0) * 2 * math.pi / span
    reach = lobe + 0.1 * year_rate
    d = 2 * math.pi / (4 * span)
    half = math.ceil(reach / d)
    count = int(2 * half) + 1
    grid = rate - half * d + d * np.arange(count)
    p = np.abs(dtft(s, wr, grid[0], d, count)) ** 2 / np.sum(w**2)
    side = _outside_lobe(count, half, round(lobe / d))
    for other in fitted:
        side &= np.abs(grid - other) > lobe
    return float(np.mean(p[side]))
