"""The text report ``wobble polar-motion`` prints: both estimates, their uncertainty, Q, the model beside
them, the windows.

Imported by :mod:`wobble.cli.polar_motion` inside ``run()`` (so ``wobble --help``
stays light); the numbers come from a :class:`wobble.PolarMotionAnalysis`.
"""

from __future__ import annotations

import math
import os

from astropy import units as u

from wobble.io.dates import iso_date
from wobble.io.text import decimals_for

__all__ = ["report"]


def _fmt(q, digits=1, unit=None) -> str:
    if q is None:
        return "-"
    x = float(q.to_value(unit) if unit is not None else q.value)
    return f"{x:.{digits}f}" if math.isfinite(x) else "-"


def _pair(q, sigma) -> tuple[str, str]:
    """A value and its uncertainty, both to the uncertainty's two significant digits (as every other
    +/- wobble prints: the amplitude's fixed whole mas showed 173 +/- 8 for 8.13)."""
    if q is None or sigma is None or not math.isfinite(float(sigma.value)):
        return _fmt(q), _fmt(sigma)
    error = float(sigma.to_value(q.unit))
    d = decimals_for(error)
    return f"{float(q.value):.{d}f}", f"{error:.{d}f}"


def report(a) -> str:
    """The report of a :class:`wobble.PolarMotionAnalysis`: estimates, uncertainty, annual wobble, mean pole,
    Q, model, windows."""
    e, s = a.least_squares, a.spectral
    lines = [
        f"Polar motion {iso_date(e.start)} to {iso_date(e.end)} ({e.n_samples} days; "
        f"{os.path.basename(a.source_file or '')})",
        "  p = x_p - i y_p: the Chandler term is at a positive (prograde) frequency",
        "",
        f"  Chandler wobble      {'period [d]':>18}  {'amplitude [mas]':>16}",
    ]
    for est, label in ((e, "least squares"), (s, "spectrum")):
        period, period_sigma = _pair(est.period, est.period_uncertainty)
        amplitude, amplitude_sigma = _pair(est.amplitude, est.amplitude_uncertainty)
        # A span that resolves no Chandler term says so on the row (the caveats below say why).
        flag = "" if est.resolved else "  not resolved"
        lines.append(f"  {label:<19}{period:>9} +/- {period_sigma:<5}  {amplitude:>7} +/- {amplitude_sigma:<5}{flag}")
    parts = e.period_uncertainty_parts
    lines.append(
        "  period uncertainty (least squares): "
        + ", ".join(f"{k} {_fmt(v, 2)}" for k, v in parts.items() if k != "adopted")
        + " d; adopted = max(autocorrelation, subspans, excitation) with the model term in quadrature"
    )
    lines.append(f"  {a.agreement_text()}")
    lines.append(
        f"  annual wobble: prograde {_fmt(e.annual_prograde_amplitude, 1)} +/- "
        f"{_fmt(e.annual_prograde_amplitude_uncertainty, 1)} mas, "
        f"retrograde {_fmt(e.annual_retrograde_amplitude, 1)} +/- "
        f"{_fmt(e.annual_retrograde_amplitude_uncertainty, 1)} mas" + e.annual_note
    )
    lines.append(
        f'  mean pole at {iso_date(e.epoch)}: x {_fmt(e.mean_pole_x, 3)}", y {_fmt(e.mean_pole_y, 3)}", '
        f"drifting {_fmt(e.drift_rate, 1)} mas/yr toward {_fmt(e.drift_direction, 0)} deg W"
    )
    if a.quality_factor_estimate is not None:
        q = a.quality_factor_estimate
        value = "unresolved (inf)" if not math.isfinite(q.value) else f"{q.value:.0f}"
        hi = "inf" if not math.isfinite(q.high) else f"{q.high:.0f}"
        lines.append(
            f"  Q (line shape{'; caveats below' if q.caveats else ''}): ML {value}, 68 % {q.low:.0f} to {hi}, "
            f"95 % lower bound {q.lower_bound_95:.0f}"
        )
        lines += [f"    - {c}" for c in q.caveats]
    lines += ["", "  Beside the model (wobble chandler earth) and the literature; days of 86400 s:"]
    lines.append(f"  {'':<44}{'period [d]':>11}{'residual [d]':>14}")
    for r in a.comparison():
        unc = "" if r["uncertainty"] is None else f" +/- {_fmt(r['uncertainty'])}"
        if r["residual"] is not None:
            res = f"{r['residual'].to_value(u.day):+.1f}"
        elif r["kind"] == "observed":
            res = "" if e.resolved else "not resolved"
        else:  # no observed period to compare with
            res = "-"
        if r["sigma"] is not None:
            res += f" ({abs(r['residual'] / r['sigma']).to_value(u.one):.1f} sigma)"
        lines.append(f"  {r['name']:<44}{_fmt(r['period']):>11}{unc:<9} {res}")
    w = a.window_columns  # the numbers of a.windows, without building the Dataset (no xarray)
    amp = w["chandler_amplitude"]
    mjd = w["window_time"]
    every = max(1, len(mjd) // 12)  # about a dozen rows; --json and -o hold every window
    shown = f"; one in {every} of the {len(mjd)} shown, all in --json and -o" if every > 1 else ""
    lines += [
        "",
        f"  Windows of {a.window_attrs['window_years']:g} yr (centre: Chandler amplitude [mas], period [d]{shown}):",
    ]
    for k in range(len(mjd)):
        if k % every == 0 or k == len(mjd) - 1:
            if not math.isfinite(amp[k]):  # printed "nan +/- nan"; the caveats say why
                lines.append(f"    {iso_date(float(mjd[k]))}  no Chandler term resolved")
                continue
            lines.append(
                f"    {iso_date(float(mjd[k]))}  {amp[k]:6.1f} +/- "
                f"{w['chandler_amplitude_uncertainty'][k]:4.1f}   "
                f"{w['chandler_period'][k]:6.1f} +/- {w['chandler_period_uncertainty'][k]:4.1f}"
            )
    if a.caveats:
        lines += ["", "  Caveats:"] + [f"    - {c}" for c in a.caveats]
    return "\n".join(lines)
