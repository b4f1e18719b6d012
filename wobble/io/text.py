"""Numbers and JSON for people and scripts: one style in every command, API summary and figure.

* JSON (``dumps``): indented by two spaces, non-finite numbers as ``null``, floats to 15
  significant digits, so that decimal data stay decimal (433.1, not 433.09999999999997: a
  catalogue value converted to seconds and back) while computed values keep every digit a
  double can promise;
* text: a value with its uncertainty to the uncertainty's two significant digits
  (:func:`with_uncertainty`), exact results to seven significant digits (:func:`number`),
  spans in the unit a person would use (:func:`duration`).

It sits in the io layer (text is a representation, like a file) so that the API, the
plots and the command line share it.
"""

from __future__ import annotations

import json
import math

from wobble.numerics.calendar import JULIAN_YEAR

__all__ = [
    "clean",
    "dumps",
    "is_number",
    "number",
    "with_uncertainty",
    "with_uncertainty_g",
    "decimals_for",
    "duration",
    "span_unit",
    "TEXT_DIGITS",
]

JSON_INDENT = 2
_JSON_DIGITS = 15
TEXT_DIGITS = 7


def _round(x: float) -> float | None:
    if not math.isfinite(x):
        return None
    return float(f"{x:.{_JSON_DIGITS}g}")


def clean(obj):
    """A JSON-ready copy of ``obj``: NumPy scalars and arrays as Python numbers and lists,
    floats to 15 significant digits, NaN and infinities as None."""
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, int):
        return obj
    if isinstance(obj, float):
        return _round(obj)
    if isinstance(obj, dict):
        return {str(k): clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    tolist = getattr(obj, "tolist", None)  # NumPy scalars and arrays
    if tolist is not None:
        return clean(tolist())
    return str(obj)


def dumps(obj) -> str:
    """``obj`` as wobble's JSON text (see the module docstring)."""
    return json.dumps(clean(obj), indent=JSON_INDENT, allow_nan=False, ensure_ascii=False)


def is_number(text: str) -> bool:
    """Whether ``text`` reads as a plain number (a float, without a unit)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def number(x, digits: int = TEXT_DIGITS) -> str:
    """A result for a person: ``digits`` significant digits, ``-`` for None, ``inf``/``nan`` as such."""
    if x is None:
        return "-"
    x = float(x)
    if not math.isfinite(x):
        return "inf" if x > 0 else "-inf" if x < 0 else "nan"
    return f"{x:.{digits}g}"


def decimals_for(sigma: float, significant: int = 2, value: float | None = None) -> int:
    """Decimal places that show ``sigma`` to ``significant`` significant digits (>= 0).

    Without a usable ``sigma`` (0: every input exact; nan) the places show ``value``, when given, to
    ``TEXT_DIGITS`` significant digits (a period of 0.02424 d printed as 0.02 with two fixed places); else 2.
    """
    if not (math.isfinite(sigma) and sigma > 0):
        if value is not None and math.isfinite(value) and value != 0:
            return max(0, TEXT_DIGITS - 1 - math.floor(math.log10(abs(value))))
        return 2
    return max(0, significant - 1 - math.floor(math.log10(sigma)))


def with_uncertainty(value: float, sigma: float | None, *, sign: bool = False) -> str:
    """``value +/- sigma`` with both rounded to the uncertainty's two significant digits.

    >>> with_uncertainty(431.4637, 5.5104)
    '431.5 +/- 5.5'
    >>> with_uncertainty(206.9, 0.5)
    '206.90 +/- 0.50'
    """
    if sigma is None or not math.isfinite(value):
        return number(value)
    if sigma == 0:  # exact inputs: the value to TEXT_DIGITS, not to the two places of a zero uncertainty
        return f"{number(value) if not sign else f'{value:+.{TEXT_DIGITS}g}'} +/- 0"
    d = decimals_for(sigma)
    fmt = f"{{:{'+' if sign else ''}.{d}f}}"
    return f"{fmt.format(value)} +/- {sigma:.{d}f}"


def with_uncertainty_g(value: float, sigma: float) -> str:
    """``value +/- sigma`` in significant digits: the value to the place of the uncertainty's second one.

    For values whose size varies over many decades (a rate of 1e-9 rad/s would print as zeros in the
    fixed decimals of :func:`with_uncertainty`). ``sigma`` must be positive and below ``|value|``.

    >>> with_uncertainty_g(1.2345678e-9, 3.1e-12)
    '1.2346e-09 +/- 3.1e-12'
    >>> with_uncertainty_g(-0.754321, 0.02)
    '-0.754 +/- 0.02'
    """
    digits = math.floor(math.log10(abs(value))) - math.floor(math.log10(sigma)) + 2
    return f"{number(value, digits)} +/- {sigma:.2g}"


# (largest span shown in this unit, the unit's length in s, its symbol); beyond: years.
_SPANS = ((120.0, 1.0, "s"), (7200.0, 60.0, "min"), (172800.0, 3600.0, "h"), (2 * JULIAN_YEAR, 86400.0, "d"))


def span_unit(seconds: float) -> tuple[float, str]:
    """(length in s, symbol) of the unit a person would give the span ``seconds`` in."""
    for limit, size, symbol in _SPANS:
        if math.isfinite(seconds) and abs(seconds) < limit:
            return size, symbol
    return (JULIAN_YEAR, "yr") if math.isfinite(seconds) else (1.0, "s")


def duration(seconds: float | None, digits: int = TEXT_DIGITS) -> str:
    """A span in the unit a person would use, with seconds beside it.

    >>> duration(26233000.0)
    '303.6227 d (2.6233e+07 s)'
    >>> duration(51.46003083930758)
    '51.46003 s'
    """
    if seconds is None:
        return "-"
    seconds = float(seconds)
    if not math.isfinite(seconds):
        return number(seconds)
    size, symbol = span_unit(seconds)
    text = f"{number(seconds / size, digits)} {symbol}"
    return text if symbol == "s" else f"{text} ({number(seconds, 5)} s)"
