"""The Chandler budget as text: the table ``wobble chandler`` prints and ``ChandlerBudget.summary()`` returns.

Periods to the decimals the model's uncertainty supports (:func:`wobble.io.text.decimals_for`), each step
with its physics and references, the observed period and the residual in sigma, the Monte Carlo's share
of unphysical draws, the steps a planet's parameters leave out, and on request every catalogued number
with its source.
"""

from __future__ import annotations

import math

__all__ = ["budget_text"]


def _days(q, decimals: int, sign: bool = False) -> str:
    from astropy import units as u

    if q is None:
        return "-"
    x = q.to_value(u.day)
    if not math.isfinite(x):
        return "inf"
    return f"{x:+.{decimals}f}" if sign else f"{x:.{decimals}f}"


def _draws() -> int:
    from wobble.models.chandler import MC_DRAWS

    return MC_DRAWS


def _skipped_steps(b) -> list[str]:
    """Steps after the last one run that the model could add, with what they need (ChandlerBudget.not_run)."""
    return [f"{step} needs {', '.join(missing)}" for step, missing in b.not_run.items()]


def _catalogued(p: dict) -> str:
    """A catalogued value as the file gives it: ``0.29525 +/- 0.003``, ``-5038.481507 +/- 0.0008 arcsec / cy``,
    ``200 s (taken as exact)`` for a value catalogued with uncertainty 0 (a conventional constant), ``yes`` for
    a flag."""
    if p["uncertainty"] is None:
        return "yes" if p["value"] else "no"

    def fmt(x, digits: int | None) -> str:
        if isinstance(x, list):
            return "[" + ", ".join(fmt(v, digits) for v in x) + "]"
        if digits is None:
            # The fewest significant digits that read back as the same float, i.e. as the file gives it
            # (10 cut Mars' rotation rate 350.891985307 to 350.8919853); 200, not 200.0.
            digits = next(d for d in range(1, 18) if float(f"{x:.{d}g}") == float(x))
            if 1 <= abs(x) < 1e6:  # whole digits in place up to six of them: 200 and 86400, not 2e+02
                digits = max(digits, len(str(int(abs(x)))))
        return f"{x:.{digits}g}"

    value = fmt(p["value"], None)
    u = p["uncertainty"]
    exact = not any(u) if isinstance(u, list) else u == 0  # a defined constant: "+/- 0" reads as a typo
    text = value if exact else f"{value} +/- {fmt(p['uncertainty'], 3)}"
    text = f"{text} {p['unit_label']}" if p["unit_label"] else text
    return f"{text} (taken as exact)" if exact else text


def budget_text(b, sources: bool = False, hint: str | None = None) -> str:
    """The budget as text: periods to the decimals that the model's uncertainty supports.

    ``sources``: every catalogued parameter with its value, uncertainty, unit and source. ``hint``: the last
    line when the sources are not listed, saying how to list them (the command line names its command).
    """
    from astropy import units as u

    from wobble.io.text import decimals_for, with_uncertainty
    from wobble.models.chandler import STEP_LABELS

    sigma = b.period_uncertainty.to_value(u.day)
    d = decimals_for(sigma, value=b.period.to_value(u.day))
    lines = [f"{b.planet.title}: Chandler wobble budget (model '{b.model}'; days of 86400 s)"]
    lines.append(f"  {'step':<16}{'period [d]':>11}{'change [d]':>12}{'k2':>8}   physics (references)")
    for s in b.steps:
        label, refs = STEP_LABELS[s.name]
        k2 = f"{s.love_number:.4f}" if s.love_number else "-"
        lines.append(
            f"  {s.name:<16}{_days(s.period, d):>11}{_days(s.change, d, sign=True):>12}{k2:>8}   {label} ({refs})"
        )

    def row(name: str, value: float, err: float | None, tail: str = "", sign: bool = False) -> str:
        number, _, plus = with_uncertainty(value, err, sign=sign).partition(" +/- ")
        return f"  {name:<16}{number:>11}" + (f" +/- {plus}" if plus else "") + tail

    sense = " (no free wobble)" if b.sense == "none" else f" ({b.sense} wobble)"  # a sphere: "(none wobble)"
    if math.isnan(sigma) and b.raw.valid_fraction == 0:  # it printed "+/- nan"
        lines.append(row("model", b.period.to_value(u.day), None, sense + "; no +/-: no Monte Carlo draw was physical"))
    else:
        lines.append(row("model", b.period.to_value(u.day), sigma, sense))
    if b.observed is not None:
        obs, osig = b.observed.to_value(u.day), b.observed_uncertainty.to_value(u.day)
        lines.append(row("observed", obs, osig))
        resid, both = b.residual.to_value(u.day), math.hypot(sigma, osig)
        if math.isnan(both):  # the model's +/- unknown (no physical draw): the residual has none either
            both = None
        tail = f" ({100 * b.relative_residual:+.2f} %" + (f"; {resid / both:+.1f} sigma)" if both else ")")
        lines.append(row("residual", resid, both, tail, sign=True))
    else:
        lines.append(f"  {'observed':<16}{'unknown':>11}")
    if math.isfinite(b.raw.valid_fraction):
        dropped = 100 * (1 - b.raw.valid_fraction)
        lines.append(
            f"  (+/- is one sigma over {_draws():,} Monte Carlo draws of the catalogued uncertainties"
            + (f"; {dropped:.1f} % unphysical draws dropped)" if dropped >= 0.05 else ")")
        )
        if dropped >= 10:
            # The +/- then describes a truncated distribution: more often a wrong uncertainty or unit than physics.
            lines.append(
                f"  WARNING: {dropped:.0f} % of the draws were unphysical: an uncertainty reaches far outside its "
                "parameter's range (check the uncertainties and their units; --sources lists them)"
            )
    skipped = _skipped_steps(b)
    if skipped:
        lines.append("  steps not run (parameters missing): " + "; ".join(skipped))
    if b.secular_love_number is not None:
        ks = b.secular_love_number  # four decimals as a Love number reads; a planet file's far scales in powers of ten
        lines.append(
            f"  secular Love number k_s = {ks:.4f}" if abs(ks) < 1e6 else f"  secular Love number k_s = {ks:.4g}"
        )
    if b.quality_factor is not None:
        q = b.quality_factor
        q_text = f"{q:.0f}" if math.isfinite(q) else "infinite (k2 has no out-of-phase part: no dissipation)"
        lines.append(f"  Q implied by the out-of-phase part of k2: {q_text}")
    if sources:
        lines.append("  parameters (value +/- one sigma and unit as catalogued; source [status if not read]):")
        for p in b.planet.parameter_list():
            lines.append(f"    {p['name']}: {_catalogued(p)}; {b.planet.source(p['name'])}")
    else:
        lines.append(f"  ({hint or 'sources of every number: summary(sources=True)'})")
    return "\n".join(lines)
