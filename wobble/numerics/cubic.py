"""Real roots of the heavy top's cubic, robust where the roots crowd (SI-free, Decimal).

The top's cubic (course notes section 5.7, p. 71; u = cos theta)

    f(u) = (1 - u^2)(alpha - beta u) - (b - a u)^2 = beta (u - u1)(u - u2)(u - u3)

has u1 <= u2 <= 1 < u3 for a physical motion. Solving it as a polynomial in u
fails exactly where the physics is interesting:

* next to the vertical (nearly sleeping top, a top passing near the vertical)
  u1, u2 and u3 crowd at u = 1 and the digits of theta = arccos u are the digits
  of 1 - u that a float u does not have (np.roots loses *all* digits of theta at
  theta = 1e-8); next to the bottom the same happens at u = -1;
* for regular precession u1 = u2 is a double root: a perturbation eps of the
  coefficients moves it by sqrt(eps);
* for a nearly free top (beta -> 0) u3 runs to infinity.

Here the cubic is written in x = 1 - u and in y = 1 + u with coefficients formed
from the initial state without cancellation (see :class:`TopCubic`):

    g(x) = x (2 - x) (A + beta x) - (B + a x)^2,        A = alpha - beta, B = b - a,
    G(y) = y (2 - y) (A_y - beta y) - (C - a y)^2,      A_y = alpha + beta, C = b + a,

so a root next to u = +1 (-1) is found as a small x (y) with full *relative*
accuracy. All arithmetic is :mod:`decimal` at ``DIGITS`` digits from the exact
float inputs. The initial point x0 brackets the two physical roots (g(0) = -B^2
<= 0 <= g(x0) = sin^2 theta0 thetadot0^2 >= 0 >= g(2) = -C^2); they are found
by safeguarded Newton (Newton steps kept inside a shrinking bracket, bisection
otherwise) and the root nearer u = -1 is polished in y. When the top starts at a
turning point (thetadot0 = 0) x0 is an exact root and the cubic is *deflated*
by it analytically, leaving a quadratic in d = x - x0 whose roots are taken by
the cancellation-free formula (a double root then splits linearly, not as a
square root, in the rounding of the inputs). The unphysical root x3 = 1 - u3 <= 0
comes from Vieta (product of the roots) and a Newton polish; for beta = 0 it is
at -infinity and is reported as such.

References: W. H. Press et al., Numerical Recipes, 3rd ed., sections 5.6 and 9.4
(stable quadratic, safeguarded Newton); course notes section 5.7.
"""

from __future__ import annotations

import decimal
from dataclasses import dataclass
from decimal import Decimal

__all__ = ["DIGITS", "TopCubic", "TopRoots", "top_roots", "quadratic_roots"]

DIGITS = 60
_MAX_ITER = 400


def _ctx() -> decimal.Context:
    return decimal.Context(prec=DIGITS)


@dataclass(frozen=True)
class TopCubic:
    """The top's cubic in x = 1 - u and y = 1 + u (all Decimal, dimensionless rates in 1/s^2).

    Attributes
    ----------
    A : Decimal
        alpha - beta (1/s^2).
    B : Decimal
        b - a (1/s): b - a u at u = 1.
    C : Decimal
        b + a (1/s): b - a u at u = -1.
    a : Decimal
        p_psi / I1 (1/s).
    beta : Decimal
        2 M g l / I1 (1/s^2), >= 0.
    """

    A: Decimal
    B: Decimal
    C: Decimal
    a: Decimal
    beta: Decimal

    @property
    def A_y(self) -> Decimal:
        """alpha + beta = A + 2 beta."""
        with decimal.localcontext(_ctx()):
            return self.A + 2 * self.beta

    def g(self, x: Decimal) -> Decimal:
        """g(x) = f(1 - x) = x (2 - x)(A + beta x) - (B + a x)^2."""
        with decimal.localcontext(_ctx()):
            n = self.B + self.a * x
            return x * (2 - x) * (self.A + self.beta * x) - n * n

    def dg(self, x: Decimal) -> Decimal:
        """dg/dx."""
        with decimal.localcontext(_ctx()):
            return (2 - 2 * x) * (self.A + self.beta * x) + self.beta * x * (2 - x) - 2 * self.a * (self.B + self.a * x)

    def G(self, y: Decimal) -> Decimal:
        """G(y) = f(y - 1) = y (2 - y)(A_y - beta y) - (C - a y)^2."""
        with decimal.localcontext(_ctx()):
            n = self.C - self.a * y
            return y * (2 - y) * (self.A_y - self.beta * y) - n * n

    def dG(self, y: Decimal) -> Decimal:
        """dG/dy."""
        with decimal.localcontext(_ctx()):
            return (2 - 2 * y) * (self.A_y - self.beta * y) - self.beta * y * (2 - y) + 2 * self.a * (self.C - self.a * y)

    @property
    def c2(self) -> Decimal:
        """Coefficient of x^2 in g: 2 beta - A - a^2 (g = -beta x^3 + c2 x^2 + c1 x - B^2)."""
        with decimal.localcontext(_ctx()):
            return 2 * self.beta - self.A - self.a * self.a

    @property
    def c1(self) -> Decimal:
        """Coefficient of x in g: 2 (A - a B)."""
        with decimal.localcontext(_ctx()):
            return 2 * (self.A - self.a * self.B)


@dataclass(frozen=True)
class TopRoots:
    """Roots of the top's cubic, each in the coordinate that keeps its digits.

    ``x_i = 1 - u_i`` and ``y_i = 1 + u_i`` are both given (Decimal, ``DIGITS``
    digits); x1 >= x2 >= 0 >= x3 (x3 = -inf when beta = 0).
    ``beta_span = beta (x1 - x3) = beta (u3 - u1)`` and
    ``beta_gap = beta (x2 - x3) = beta (u3 - u2)`` are formed without cancellation
    (they stay finite for beta -> 0: beta_span -> A + a^2).
    """

    x1: Decimal
    x2: Decimal
    x3: Decimal
    y1: Decimal
    y2: Decimal
    y3: Decimal
    beta_span: Decimal
    beta_gap: Decimal


def quadratic_roots(p2: Decimal, p1: Decimal, p0: Decimal) -> tuple[Decimal, Decimal]:
    """Real roots of p2 d^2 + p1 d + p0 (p2 may be 0), by the cancellation-free formula.

    Returns ``(r_small, r_other)``; ``r_other`` is ``Decimal('-Infinity')`` or
    ``'Infinity'`` when p2 = 0 (the root that went to infinity, with the sign of -p1 p2 -> 0).
    A negative discriminant within rounding is taken as zero.
    """
    with decimal.localcontext(_ctx()):
        if p2 == 0:
            if p1 == 0:
                raise ValueError("degenerate quadratic")
            return -p0 / p1, Decimal("-Infinity") if p1 > 0 else Decimal("Infinity")
        disc = p1 * p1 - 4 * p2 * p0
        scale = p1 * p1 + abs(4 * p2 * p0)
        if disc < 0:
            if -disc > scale * Decimal(10) ** (-DIGITS + 8):
                raise ValueError("complex roots")
            disc = Decimal(0)
        sq = disc.sqrt()
        q = -(p1 + sq) / 2 if p1 >= 0 else -(p1 - sq) / 2
        if q == 0:
            return Decimal(0), Decimal(0)
        return p0 / q, q / p2


def _safe_newton(fn, dfn, lo: Decimal, hi: Decimal, start: Decimal | None = None) -> Decimal:
    """A root of fn in [lo, hi] where fn(lo) and fn(hi) differ in sign (or one is 0)."""
    with decimal.localcontext(_ctx()):
        f_lo, f_hi = fn(lo), fn(hi)
        if f_lo == 0:
            return lo
        if f_hi == 0:
            return hi
        if (f_lo > 0) == (f_hi > 0):
            raise ValueError("root not bracketed")
        if f_lo > 0:  # orient so that fn(lo) < 0 < fn(hi)
            lo, hi = hi, lo
        x = (lo + hi) / 2 if start is None else start
        tol = Decimal(10) ** (-DIGITS + 3)
        dx_old = abs(hi - lo)
        dx = dx_old
        fx, dfx = fn(x), dfn(x)
        for _ in range(_MAX_ITER):
            out = dfx == 0 or ((x - hi) * dfx - fx) * ((x - lo) * dfx - fx) > 0
            if out or abs(2 * fx) > abs(dx_old * dfx):
                dx_old = dx
                dx = (hi - lo) / 2
                x = lo + dx
            else:
                dx_old = dx
                dx = fx / dfx
                x = x - dx
            if abs(dx) <= tol * max(abs(x), Decimal(10) ** -300):
                return x
            fx, dfx = fn(x), dfn(x)
            if fx == 0:
                return x
            if fx < 0:
                lo = x
            else:
                hi = x
        return x


def _polish(fn, dfn, x: Decimal, steps: int = 3) -> Decimal:
    with decimal.localcontext(_ctx()):
        for _ in range(steps):
            d = dfn(x)
            if d == 0:
                break
            step = fn(x) / d
            x = x - step
            if step == 0:
                break
        return x


def _with_y(cub: TopCubic, x: Decimal) -> tuple[Decimal, Decimal]:
    """(x, y) of a root in [0, 2]: polished in y when it lies in the lower hemisphere."""
    with decimal.localcontext(_ctx()):
        if x <= 1:
            return x, 2 - x
        y = 2 - x
        y = _polish(cub.G, cub.dG, y) if y > 0 and cub.dG(y) != 0 else y
        y = max(y, Decimal(0))
        return 2 - y, y


def _with_x(cub: TopCubic, y: Decimal, x: Decimal) -> tuple[Decimal, Decimal]:
    """(x, y) of a root in [0, 2] given both estimates: polished in x when next to u = +1."""
    with decimal.localcontext(_ctx()):
        if x > 1:
            return _with_y(cub, x)
        x = max(x, Decimal(0))
        x = _polish(cub.g, cub.dg, x) if x > 0 and cub.dg(x) != 0 else x
        x = max(x, Decimal(0))
        return x, 2 - x


def _root_between(cub: TopCubic, lo: Decimal, hi: Decimal) -> tuple[Decimal, Decimal]:
    """The root of g in [lo, hi] (g changes sign there), as (x, y).

    The bracket is split at x = 1 (the horizontal); a root in the upper half is
    found in x, one in the lower half in y, so either keeps its relative digits.
    """
    with decimal.localcontext(_ctx()):
        g_lo = cub.g(lo)
        if g_lo == 0:
            return lo, 2 - lo
        if lo < 1 < hi:
            g_one = cub.g(Decimal(1))
            if g_one == 0:
                return Decimal(1), Decimal(1)
            if (g_one > 0) != (g_lo > 0):
                hi = Decimal(1)
            else:
                lo = Decimal(1)
        if hi <= 1:
            x = _safe_newton(cub.g, cub.dg, lo, hi)
            return x, 2 - x
        y = _safe_newton(cub.G, cub.dG, 2 - hi, 2 - lo)
        return 2 - y, y


def top_roots(cub: TopCubic, x0: Decimal, y0: Decimal, g0: Decimal) -> TopRoots:
    """The three roots of the top's cubic, given the initial point and g there.

    Parameters
    ----------
    cub : TopCubic
        Coefficients.
    x0, y0 : Decimal
        1 - cos theta0 and 1 + cos theta0, each with full relative accuracy.
    g0 : Decimal
        g(x0) = sin^2 theta0 thetadot0^2 >= 0. When it is 0 the top starts at a
        turning point: x0 is an exact root and the cubic is deflated by it,
        g(x0 + d) = d (g'(x0) + (c2 - 3 beta x0) d - beta d^2) (Taylor at x0).

    Returns
    -------
    TopRoots

    Raises
    ------
    ValueError
        If the data admit no motion (g(x0) < 0).
    """
    beta = cub.beta
    with decimal.localcontext(_ctx()):
        if g0 < 0:
            raise ValueError("g(x0) < 0: no physical motion")
        x3 = None
        if g0 == 0:
            e0 = cub.dg(x0)
            e1 = cub.c2 - 3 * beta * x0
            if beta == 0:
                d_phys = -e0 / e1 if e1 != 0 else Decimal(0)
            else:
                d_a, d_b = quadratic_roots(-beta, e1, e0)
                d_phys, d3 = (d_a, d_b) if d_a >= d_b else (d_b, d_a)
                x3 = x0 + d3
            if d_phys == 0:
                x1, y1, x2, y2 = x0, y0, x0, y0
            elif d_phys > 0:  # x0 is the upper turning point (smallest theta)
                x2, y2 = x0, y0
                x1, y1 = _with_y(cub, min(x0 + d_phys, Decimal(2)))
            else:
                x1, y1 = x0, y0
                x2, y2 = _with_x(cub, y0 - d_phys, x0 + d_phys)
        else:
            x2, y2 = _root_between(cub, Decimal(0), x0)
            x1, y1 = _root_between(cub, x0, Decimal(2))
        # The unphysical root and the spans beta (x1 - x3), beta (x2 - x3).
        if beta == 0:
            x3 = Decimal("-Infinity")
            span = 2 * beta * x1 + beta * x2 - cub.c2  # = A + a^2 for beta = 0
            gap = span
        else:
            if x3 is None:
                if x2 > 0 and cub.B != 0:
                    x3 = -(cub.B * cub.B) / (beta * x1 * x2)  # Vieta: beta x1 x2 x3 = -B^2
                else:
                    x3 = cub.c2 / beta - x1 - x2  # Vieta: sum of the roots
                x3 = _polish(cub.g, cub.dg, x3)
            span = beta * (x1 - x3)
            gap = beta * (x2 - x3)
        return TopRoots(x1=x1, x2=x2, x3=x3, y1=y1, y2=y2, y3=2 - x3, beta_span=span, beta_gap=gap)
