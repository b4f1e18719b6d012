"""Small conventions shared by wobble's figures."""

from __future__ import annotations

import math
import re

import numpy as np

from wobble.io.text import span_unit
from wobble.numerics.calendar import DAY, JULIAN_YEAR, MJD_J2000

__all__ = [
    "time_axis",
    "ANGLE_UNITS",
    "angle_unit",
    "power_of_ten",
    "power_label",
    "power_axis",
    "largest",
    "pm",
    "SMALL_CHANGE",
    "ROUNDING_CHANGE",
    "finite_range",
    "constancy",
    "start_text",
    "legend_beside",
    "unit_label",
    "decimal_year",
]

#: A quantity whose samples move by less than this share of its size is drawn as its change from the start,
#: its start named (on an axis spanning the quantity, 5 % is a few pixels: flat lines).
SMALL_CHANGE = 0.05
#: A quantity whose samples move by less than this share of its size is constant to rounding: drawn flat, or
#: named, with its measured spread (:func:`constancy`), never as its last bits (a staircase of float steps).
ROUNDING_CHANGE = 1e-12
_ARCSEC = math.pi / (180.0 * 3600.0)
#: The angle units of the figures, largest first: (name, radians per unit).
ANGLE_UNITS = (("deg", math.radians(1.0)), ("arcsec", _ARCSEC), ("mas", 1e-3 * _ARCSEC), ("µas", 1e-6 * _ARCSEC))


def time_axis(span_s: float, unit: tuple[float, str] | None = None) -> tuple[float, str]:
    """(seconds per unit, unit name) for a time axis spanning ``span_s`` seconds: the unit the text gives
    that span in (:func:`wobble.io.text.span_unit`: the largest the span reaches twice), so a figure and
    the summary beside it speak of a run in the same unit (the figures had a table of their own, with
    other limits: a 2.5-day run was 60 h on the axis and 2.5 d in the text).

    A span that would read below 1e-3 or from 1e4 of that unit (1e-300 s, 1e300 yr) is in a power of ten
    of it, named in the label, as the value axes are (:func:`power_of_ten`): matplotlib drew no curve at all
    over a span of 1e-290 s, and a multiplier such as '1e300' under the axis otherwise.

    ``unit``, (seconds per unit, its name), is the unit the user gave the span in (``--t-end 200`` is in
    seconds, so its figure too: the text said 200 s and the axis 3.3 min); the power of ten still applies.

    >>> time_axis(200.0), time_axis(200.0, (1.0, 's')), time_axis(3e7), time_axis(1e-300)
    ((60.0, 'min'), (1.0, 's'), (86400.0, 'd'), (1e-300, '$10^{-300}$ s'))
    """
    size, name = span_unit(span_s) if unit is None else unit
    exponent = power_of_ten(span_s / size) if math.isfinite(span_s) and span_s > 0 else 0
    if exponent == 0:
        return size, name
    return size * 10.0**exponent, power_label(exponent, name)


def angle_unit(extent_rad: float) -> tuple[float, str]:
    """(radians per unit, unit name) for angles up to ``extent_rad``: the largest of deg, arcsec, mas
    and µas that the extent reaches once, so tick labels read 1 to a few thousand (a 2.9 deg circle in
    deg, not as 10,000 arcsec; a 0.2 arcsec one in mas).

    >>> angle_unit(math.radians(2.9))[1], angle_unit(math.radians(0.5))[1], angle_unit(1e-6)[1]
    ('deg', 'arcsec', 'mas')
    """
    for name, size in ANGLE_UNITS[:-1]:
        if extent_rad >= size:
            return size, name
    return ANGLE_UNITS[-1][1], ANGLE_UNITS[-1][0]


def power_of_ten(largest: float) -> int:
    """The power of ten (a multiple of 3) to divide values up to ``abs(largest)`` by, so that they read
    as plain numbers without matplotlib's offset or '1e-11' multiplier: 0 when they already do
    (1e-3 <= |largest| < 1e4), or for zero and non-finite values.

    >>> power_of_ten(7.3e-11), power_of_ten(-2.7e-19), power_of_ten(0.1), power_of_ten(0.0)
    (-12, -21, 0, 0)
    """
    largest = abs(float(largest))
    if not math.isfinite(largest) or largest == 0.0 or 1e-3 <= largest < 1e4:
        return 0
    return 3 * math.floor(math.log10(largest) / 3)


def power_label(exponent: int, unit: str = "") -> str:
    """An axis unit with its power of ten in front, as mathtext: ``$10^{-6}$ rad s$^{-1}$``; the unit
    alone for exponent 0. ``unit`` is spelled as :func:`unit_label` spells it."""
    if exponent == 0:
        return unit
    return f"$10^{{{exponent}}}$ {unit}".rstrip()


def largest(values) -> float:
    """The largest finite |value| (0 for none): a NaN sample must not set an axis's scale."""
    values = np.asarray(values, dtype=float)
    return float(np.max(np.abs(values[np.isfinite(values)]), initial=0.0))


def power_axis(ax, biggest: float, unit: str = "", name: str | None = None) -> float:
    """Label ``ax``'s y axis with ``unit`` in the power of ten of ``biggest`` (:func:`power_of_ten`),
    after ``name`` in brackets when given (``relative change [$10^{-9}$]``), with plain tick labels and
    no offset text; returns the divisor ``10**exponent`` for the values drawn."""
    exponent = power_of_ten(biggest)
    unit_text = power_label(exponent, unit)
    ax.set_ylabel(unit_text if name is None else (f"{name} [{unit_text}]" if unit_text else name))
    ax.ticklabel_format(axis="y", style="plain", useOffset=False)
    return 10.0**exponent


def legend_beside(ax, fontsize: float = 8, **kwargs):
    """``ax``'s legend outside the axes, on the right, its top at the axes' top, unframed: inside, any
    corner covered some figure's curves or bands (the free figure's peaks, the modes figure's +-1 sigma
    bands and full-height lines). ``kwargs`` go to :meth:`matplotlib.axes.Axes.legend`."""
    return ax.legend(
        loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=fontsize, frameon=False, **kwargs
    )


_UNIT_TOKEN = re.compile(r"([^\W\d_]+)(-?\d+)?")


def unit_label(unit: str) -> str:
    """A unit as every figure spells it: powers as mathtext superscripts, ``rad s$^{-1}$`` (drawn rad s⁻¹),
    ``kg m$^{2}$``, from the CF and astropy spelling the files carry (``rad s-1``, ``kg m2 s-1``) or a
    slash (``rad/s``, ``arcsec/yr``: what follows it is in the denominator). Text that is not a product of
    named units (mathtext already, ``1``, ``%``) comes back as it is.

    >>> unit_label("kg m2 s-1"), unit_label("arcsec/yr"), unit_label("J"), unit_label("1")
    ('kg m$^{2}$ s$^{-1}$', 'arcsec yr$^{-1}$', 'J', '1')
    """
    if "$" in unit or unit.count("/") > 1:
        return unit
    numerator, _, denominator = unit.partition("/")
    parts = []
    for tokens, sign in ((numerator.split(), 1), (denominator.split(), -1)):
        for token in tokens:
            match = _UNIT_TOKEN.fullmatch(token)
            if match is None:
                return unit
            power = sign * int(match.group(2) or 1)
            parts.append(match.group(1) + ("" if power == 1 else f"$^{{{power}}}$"))
    return " ".join(parts) if parts else unit


def pm(value: float, sigma: float) -> str:
    """``value ± sigma`` to the uncertainty's two significant digits, as the text output prints it
    (:func:`wobble.io.text.with_uncertainty`, with a plus-minus sign).

    >>> pm(206.9, 0.5), pm(430.6, 19.6)
    ('206.90 ± 0.50', '431 ± 20')
    """
    from wobble.io.text import with_uncertainty

    return with_uncertainty(value, sigma).replace("+/-", "±")


def finite_range(values) -> float:
    """max - min of the finite values (0 for none): a NaN sample must not hide a constant.

    >>> finite_range([1.0, float("nan"), 3.0]), finite_range([])
    (2.0, 0.0)
    """
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    return float(np.ptp(finite)) if finite.size else 0.0


def constancy(spread: float, size: float) -> str:
    """How constant a quantity of ``size`` whose samples span ``spread`` is, as measured: 'constant' (no
    spread at all) or 'constant to 2e-15' (the spread relative to the size).

    >>> constancy(0.0, 7.3e-5), constancy(2.7e-19, 7.3e-5)
    ('constant', 'constant to 4e-15')
    """
    return "constant" if spread == 0 else f"constant to {spread / size:.1g}"


def start_text(start, unit: str) -> str:
    """A vector's start for a title, to six digits of its largest component in one power of ten:
    ``(0.00000, 2.33047, 5.37529) $10^{33}$ kg m$^{2}$ s$^{-1}$``; a scalar's without the brackets. The power is
    chosen after rounding to six digits, so that -9.9999996e32 reads -1.00000 in 10^33, not -1000.000
    in 10^30.

    >>> start_text([0.0, -9.9999996e32, 5e32], "J"), start_text(7.292115e-5, "rad")
    ('(0.00000, -1.00000, 0.50000) $10^{33}$ J', '72.9212 $10^{-6}$ rad')
    """
    from wobble.io.text import decimals_for

    start = np.asarray(start, dtype=float)
    exponent = power_of_ten(float(f"{largest(start):.6g}"))
    scaled = start / 10.0**exponent
    rounded = float(f"{largest(scaled):.6g}")
    decimals = decimals_for(rounded, 6) if rounded > 0 else 0
    parts = ", ".join(f"{round(v, decimals) + 0.0:.{decimals}f}" for v in scaled.ravel())  # + 0.0: no "-0.00000"
    return f"{parts if scaled.ndim == 0 else f'({parts})'} {power_label(exponent, unit)}".rstrip()


def decimal_year(mjd) -> np.ndarray:
    """Modified Julian Dates as decimal years for a time axis: 2000.0 at J2000.0, Julian years of 365.25 d.

    >>> float(decimal_year(51544.5)), float(decimal_year(51544.5 + 365.25))
    (2000.0, 2001.0)
    """
    return 2000.0 + (np.asarray(mjd, dtype=float) - MJD_J2000) / (JULIAN_YEAR / DAY)
