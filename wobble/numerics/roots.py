"""A bracketed scalar root: the Anderson-Bjorck variant of regula falsi (float64).

For a continuous f with f(lo) f(hi) < 0 the bracket always holds a root, and
the Anderson-Bjorck weighting (Anderson & Bjorck 1973, BIT 13, 253; Galdino
2011 compares it with Illinois and Pegasus) keeps the convergence superlinear
where plain regula falsi stalls on one end. Used where ``scipy.optimize.brentq``
would do the same job, because importing ``scipy.optimize`` costs the command
line more than the whole computation (``wobble modes``).
"""

from __future__ import annotations

import math

from wobble.numerics.floats import EPS

__all__ = ["bracketed_root"]


def bracketed_root(
    f,
    lo: float,
    hi: float,
    *,
    f_lo: float | None = None,
    f_hi: float | None = None,
    xtol: float = 0.0,
    maxiter: int = 200,
) -> float:
    """A root of ``f`` in [lo, hi], to the last bits.

    Parameters
    ----------
    f : callable
        float -> float, continuous on [lo, hi].
    lo, hi : float
        The bracket; f(lo) and f(hi) must differ in sign (or one be zero).
    f_lo, f_hi : float, optional
        f at the ends, when already known.
    xtol : float
        Absolute tolerance added to the 4 eps |x| relative one.
    maxiter : int
        Evaluation budget.

    Raises
    ------
    ValueError
        The ends do not bracket a root, or the budget ran out.
    """
    a, b = float(lo), float(hi)
    fa = f(a) if f_lo is None else float(f_lo)
    fb = f(b) if f_hi is None else float(f_hi)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if math.copysign(1.0, fa) == math.copysign(1.0, fb):
        raise ValueError("the interval does not bracket a root")
    width = abs(b - a)
    for it in range(maxiter):
        # A bisection whenever two secant steps did not halve the bracket:
        # the convergence is then at least linear, whatever f looks like.
        if it % 3 == 2 and abs(b - a) > 0.5 * width:
            c = 0.5 * (a + b)
        else:
            c = (a * fb - b * fa) / (fb - fa)
            if not (min(a, b) < c < max(a, b)):
                c = 0.5 * (a + b)  # rounding pushed the secant out
        if it % 3 == 2:
            width = abs(b - a)
        fc = f(c)
        if fc == 0.0:
            return c
        if math.copysign(1.0, fc) == math.copysign(1.0, fb):
            # c replaces b; the retained end a gets the Anderson-Bjorck weight.
            m = 1.0 - fc / fb
            fa = fa * (m if m > 0 else 0.5)
            b, fb = c, fc
        else:
            m = 1.0 - fc / fa
            fb = fb * (m if m > 0 else 0.5)
            a, fa = c, fc
        if abs(b - a) <= xtol + 4 * EPS * abs(c):
            return c
    raise ValueError("no convergence within the evaluation budget")
