"""Real roots of the heavy top's cubic, robust where the roots crowd (SI-free, Decimal).

The top's cubic (course notes section 5.7, p. 71; u = cos theta)

    f(u) = (1 - u^2)(alpha - beta u) - (b - a u)^2 = beta (u - u1)(u - u2)(u - u3)

has u1 <= u2 <= 1 < u3 for a physical motion. Solving it as a polynomial in u
fails exactly where the physics is interesting:

* next to the vertical (nearly sleeping top, a top passing near the vertical)
  u1, u2 and u3 crowd at u = 1 and the digits of theta = arccos u are the digits
  of 1 - u that a float u does not have (np.roots on the cubic in u returns
  theta_min = 0 and theta_max 2.4 times too large for a top released at
  theta0 = 1e-4 rad, see docs/heavy-top.md); next to the bottom the same
  happens at u = -1;
* for regular precession u1 = u2 is a double root: a perturbation eps of the
  coefficients moves it by sqrt(eps);
* for a nearly free top (beta -> 0) u3 runs to infinity.

Here the cubic is written in x = 1 - u and in y = 1 + u with coefficients formed
from the initial state without cancellation (see :class:`TopCubic`):

    g(x) = x (2 - x) (A + beta x) - (B + a x)^2,        A = alpha - beta, B = b - a,
    G(y) = y (2 - y) (A_y - beta y) - (C - a y)^2,      A_y = alpha + beta, C = b + a,

so a root next to u = +1 (-1) is found as a small x (y) with full *relative*
accuracy. All arithmetic is :mod:`decimal` at ``DIGITS`` digits from the exact
float inputs (:func:`top_roots`):

* roots known exactly are divided out first -- x0 when the top starts at a turning
  point (thetadot0 = 0; a double root, regular precession, then splits linearly
  in the rounding of the inputs, not as a square root), x = 0 when b = a (through
  the vertical), x = 2 when b = -a (through the bottom) -- and the quadratic left
  is solved by the cancellation-free formula, a root much nearer a pole than the
  divided-out one being recomputed from Vieta's product;
* otherwise the initial point brackets the two physical roots (g(0) = -B^2 < 0 <
  g(x0) = sin^2 theta0 thetadot0^2 > 0 > g(2) = -C^2, the middle value known
  exactly rather than evaluated); each is found by safeguarded Newton (an iterate
  is kept only strictly inside the shrinking bracket; bisection otherwise,
  geometric across decades, so a root of 1e-400 is reached in a few dozen steps),
  in x or in y by its hemisphere; the unphysical root x3 = 1 - u3 <= 0 follows from
  Vieta (x1 x2 x3 = -B^2 / beta) and a polish; for beta = 0 it is at -infinity.

Found the hard way (fuzzing): non-spinning pendulums (b = a = 0), tops 1e-200 rad
from the vertical, beta of 1e-170, roots that coincide to working precision; each
has a test or a guard here.

References: W. H. Press et al., Numerical Recipes, 3rd ed., sections 5.6 and 9.4
(stable quadratic, safeguarded Newton); course notes section 5.7.
"""

from __future__ import annotations

import decimal
from dataclasses import dataclass
from decimal import Decimal

from wobble.numerics import highprec as hp

__all__ = ["DIGITS", "TopCubic", "TopRoots", "top_roots", "quadratic_roots"]

DIGITS = 60
_MAX_ITER = 600


# One template: decimal.localcontext works on a copy of it (creating a Context costs about a
# microsecond, and the roots take dozens of contexts).
_CONTEXT = hp.make_context(DIGITS)  # every setting given: none from decimal.DefaultContext


def _ctx() -> decimal.Context:
    return _CONTEXT


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
            return (
                (2 - 2 * y) * (self.A_y - self.beta * y) - self.beta * y * (2 - y) + 2 * self.a * (self.C - self.a * y)
            )

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
    ``d_low = x0 - x2 >= 0`` and ``d_high = x1 - x0 >= 0`` are the turning points' offsets from the
    initial point, each with its own relative digits: a nutation 1e-61 of x wide (a heavy top of
    M g l = 1e-60 J) is below the digits of x1 and x2, so x1 - x2 is zero there but
    :attr:`width` = d_low + d_high is not.
    """

    x1: Decimal
    x2: Decimal
    x3: Decimal
    y1: Decimal
    y2: Decimal
    y3: Decimal
    beta_span: Decimal
    beta_gap: Decimal
    d_low: Decimal
    d_high: Decimal

    @property
    def width(self) -> Decimal:
        """x1 - x2 = u2 - u1 >= 0 with full relative accuracy (the sum of the offsets, no cancellation)."""
        with decimal.localcontext(_ctx()):
            return self.d_low + self.d_high


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


def _middle(lo: Decimal, hi: Decimal) -> Decimal:
    """Bisection point: geometric when the bracket spans many decades (a root of 1e-400
    next to the vertical is then reached in a few dozen steps, not a thousand)."""
    a, b = (lo, hi) if lo <= hi else (hi, lo)
    if a > 0 and b > 1000 * a:
        return (a * b).sqrt()
    if a == 0 and b > 0:
        return b * Decimal("1e-12")
    if b < 0 and a < 1000 * b:
        return -(a * b).sqrt()
    return (a + b) / 2


def _safe_newton(fn, dfn, lo: Decimal, hi: Decimal, f_lo=None, f_hi=None) -> Decimal:
    """A root of fn in [lo, hi] where fn(lo) and fn(hi) differ in sign (or one is 0).

    ``f_lo``, ``f_hi``: the endpoint values when known exactly (g(x0) = sin^2 theta0
    thetadot0^2 can be far below the rounding of the polynomial's terms).
    """
    with decimal.localcontext(_ctx()):
        f_lo = fn(lo) if f_lo is None else f_lo
        f_hi = fn(hi) if f_hi is None else f_hi
        if f_lo == 0:
            return lo
        if f_hi == 0:
            return hi
        if (f_lo > 0) == (f_hi > 0):
            raise ValueError("root not bracketed")
        if f_lo > 0:  # orient so that fn(lo) < 0 < fn(hi)
            lo, hi = hi, lo
        x = _middle(lo, hi)
        tol = Decimal(10) ** (-DIGITS + 3)
        fx, dfx = fn(x), dfn(x)
        width_old = abs(hi - lo)
        for _ in range(_MAX_ITER):
            left, right = (lo, hi) if lo <= hi else (hi, lo)
            x_new = x - fx / dfx if dfx != 0 else None
            # Newton only while it stays strictly inside the bracket and shrinks it fast
            # enough; otherwise bisect (geometrically across decades).
            newton = x_new is not None and left < x_new < right and abs(right - left) <= width_old / 2
            if not newton:
                x_new = _middle(lo, hi)
            width_old = abs(right - left)
            # Converged: a Newton step below tol, or a bracket narrower than tol.
            size = abs(x_new - x) if newton else abs(right - left)
            x = x_new
            if size <= tol * abs(x) or size == 0:
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
    """Newton steps that only refine the last digits of an already accurate root.

    A step larger than 1e-20 |x| is refused: next to a (nearly) double root g' is
    small and Newton would jump to the other root.
    """
    with decimal.localcontext(_ctx()):
        limit = Decimal(10) ** -20 * abs(x)
        for _ in range(steps):
            d = dfn(x)
            if d == 0:
                break
            step = fn(x) / d
            if step == 0 or abs(step) > limit:
                break
            x = x - step
        return x


def _root_between(cub: TopCubic, x0: Decimal, y0: Decimal, g0: Decimal, towards_top: bool) -> tuple[Decimal, Decimal]:
    """The root of g between the initial point and the vertical (``towards_top``: x in [0, x0]) or the bottom
    (x in [x0, 2], y in [0, y0]), where g(x0) = g0 > 0, as (x, y).

    The bracket is split at x = 1 (the horizontal); a root in the upper half is found in x, one in the lower
    half in y, so either keeps its relative digits. The initial point's end is x0 in x and y0 in y, each with
    its own digits: 2 - x0 is 0 at 60 digits for a start within 1e-30 rad of the bottom, where the bracket
    [2 - x0, 0] held no root. g(0) = -B^2 < 0 and g(2) = -C^2 < 0 here (B, C != 0).
    """
    with decimal.localcontext(_ctx()):
        one = Decimal(1)
        start, start_other, fn, dfn, fn_other, dfn_other = (
            (x0, y0, cub.g, cub.dg, cub.G, cub.dG) if towards_top else (y0, x0, cub.G, cub.dG, cub.g, cub.dg)
        )

        def pair(value, in_x):
            return (value, 2 - value) if in_x else (2 - value, value)

        # In the coordinate that is 0 at the pole it moves towards (x at the vertical, y at the bottom):
        # from the pole (-B^2 or -C^2) to the start (g0), unless the start lies past the horizontal.
        if start <= 1:
            return pair(_safe_newton(fn, dfn, Decimal(0), start, None, g0), towards_top)
        g_one = cub.g(one)
        if g_one == 0:
            return one, one
        if g_one > 0:  # between the pole and the horizontal
            return pair(_safe_newton(fn, dfn, Decimal(0), one, None, g_one), towards_top)
        # Between the horizontal and the start, in the start's own coordinate.
        return pair(_safe_newton(fn_other, dfn_other, start_other, one, g0, g_one), not towards_top)


def _deflated(cub: TopCubic, xr: Decimal, yr: Decimal, dg_r: Decimal | None = None) -> list[tuple[Decimal, Decimal]]:
    """The other roots, as (x, y), once the exact root (xr, yr) is divided out.

    Taylor at the root: g(xr + d) = d (g'(xr) + (c2 - 3 beta xr) d - beta d^2), solved by
    the cancellation-free quadratic formula. x = xr + d (y = yr - d) cancels when the
    new root lies much nearer the pole than xr; such a root is recomputed from Vieta,
    x1 x2 x3 = -B^2 / beta (y1 y2 y3 = C^2 / beta), which has no cancellation, then
    polished by Newton in the coordinate of its hemisphere (x3 < 0 is left negative).
    For beta = 0 the cubic is a quadratic: one finite root. ``dg_r``: g'(xr) when the caller has it
    without cancellation (:func:`top_roots`'s ``dg0``).
    """
    beta = cub.beta
    with decimal.localcontext(_ctx()):
        p2, p1, p0 = -beta, cub.c2 - 3 * beta * xr, cub.dg(xr) if dg_r is None else dg_r
        if p2 == 0:
            ds = [-p0 / p1] if p1 != 0 else [Decimal(0)]
        else:
            ds = list(quadratic_roots(p2, p1, p0))
        roots = [[xr + d, yr - d] for d in ds]
        if beta == 0 and len(roots) == 1:
            # The cubic is the quadratic -(A + a^2) x^2 + 2 (A - a B) x - B^2: Vieta on the
            # two finite roots, x xr = B^2 / (A + a^2), y yr = C^2 / (A + a^2).
            lead = cub.A + cub.a * cub.a
            if xr != 0 and roots[0][0] <= 1:
                roots[0][0] = cub.B * cub.B / (lead * xr)
                roots[0][1] = 2 - roots[0][0]
            elif yr != 0 and roots[0][0] > 1:
                roots[0][1] = cub.C * cub.C / (lead * yr)
                roots[0][0] = 2 - roots[0][1]
        if beta != 0 and len(roots) == 2:
            if xr != 0:
                i = 0 if abs(roots[0][0]) <= abs(roots[1][0]) else 1
                other = roots[1 - i][0]
                if abs(roots[i][0]) < abs(xr) and other != 0:
                    roots[i][0] = -(cub.B * cub.B) / (beta * xr * other)
                    roots[i][1] = 2 - roots[i][0]
            if yr != 0:
                i = 0 if abs(roots[0][1]) <= abs(roots[1][1]) else 1
                other = roots[1 - i][1]
                if abs(roots[i][1]) < abs(yr) and other != 0:
                    roots[i][1] = (cub.C * cub.C) / (beta * yr * other)
                    roots[i][0] = 2 - roots[i][1]
        out = []
        for x, y in roots:
            if x <= 1:
                if x != 0 and cub.dg(x) != 0:
                    x = _polish(cub.g, cub.dg, x, steps=2)
                out.append((x, 2 - x))
            else:
                if y != 0 and cub.dG(y) != 0:
                    y = _polish(cub.G, cub.dG, y, steps=2)
                out.append((2 - y, y))
        return out


def _offsets(
    cub: TopCubic, x0: Decimal, g0: Decimal, dg0: Decimal, x1: Decimal, x2: Decimal
) -> tuple[Decimal, Decimal]:
    """x0 - x2 >= 0 and x1 - x0 >= 0 for the turning points x2 <= x0 <= x1, each with full relative accuracy.

    The difference of two 60-digit roots keeps its digits unless they lie within 1e-20 of each other
    (relative); then the offset is solved for itself, from g's Taylor form about the initial point,
    h(d) = g(x0 + d) = g0 + g'(x0) d + (c2 - 3 beta x0) d^2 - beta d^3 (coefficients without
    cancellation, g0 and g'(x0) from the caller): as a root of the quadratic h(d)/d when x0 is itself
    a turning point (g0 = 0), by safeguarded Newton on h otherwise.
    """
    with decimal.localcontext(_ctx()):
        tiny = Decimal(10) ** -20
        d_low, d_high = x0 - x2, x1 - x0
        near_low = d_low <= tiny * max(abs(x0), abs(x2))
        near_high = d_high <= tiny * max(abs(x0), abs(x1))
        if not (near_low or near_high):
            return d_low, d_high
        p2, p1 = -cub.beta, cub.c2 - 3 * cub.beta * x0
        if g0 == 0:
            # x0 is a turning point; the other is the root of p2 d^2 + p1 d + g'(x0) on its side of 0: x1 is the
            # only root above x0 when x0 = x2 (x3 < x2), x2 the larger of the two below when x0 = x1.
            ds = [d for d in quadratic_roots(p2, p1, dg0) if d.is_finite()] if (p2, p1) != (0, 0) else []
            above = [d for d in ds if d > 0]
            if above:
                return Decimal(0), (min(above) if near_high else d_high)
            below = [d for d in ds if d <= 0]
            return (-max(below) if below and near_low else d_low), Decimal(0)

        def solve(sign: int, diff: Decimal, scale: Decimal) -> Decimal:
            def h(e):  # h(sign e), e >= 0
                d = sign * e
                return g0 + d * (dg0 + d * (p1 + d * p2))

            def dh(e):
                d = sign * e
                return sign * (dg0 + d * (2 * p1 + 3 * p2 * d))

            hi = Decimal(10) ** -19 * scale  # h(0) = g0 > 0 > h(hi): the root lies within 1e-20 scale of x0
            h_hi = h(hi)
            if h_hi >= 0:
                return diff
            return _safe_newton(h, dh, Decimal(0), hi, g0, h_hi)

        if near_low:
            d_low = solve(-1, d_low, max(abs(x0), abs(x2)))
        if near_high:
            d_high = solve(1, d_high, max(abs(x0), abs(x1)))
        return d_low, d_high


def top_roots(cub: TopCubic, x0: Decimal, y0: Decimal, g0: Decimal, dg0: Decimal | None = None) -> TopRoots:
    """The three roots of the top's cubic, given the initial point and g there.

    Parameters
    ----------
    cub : TopCubic
        Coefficients.
    x0, y0 : Decimal
        1 - cos theta0 and 1 + cos theta0, each with full relative accuracy.
    g0 : Decimal
        g(x0) = sin^2 theta0 thetadot0^2 >= 0, known exactly (evaluating the
        polynomial there would cancel).
    dg0 : Decimal, optional
        g'(x0) = 2 u0 kin + beta x0 y0 - 2 a phidot0 sin^2 theta0 (kin = thetadot0^2 + phidot0^2
        sin^2 theta0), formed without cancellation; evaluated from the polynomial when not given.
        With it the turning points' offsets from x0 (``d_low``, ``d_high``) keep their digits
        however narrow the nutation.

    Returns
    -------
    TopRoots
        With beta > 0 the roots sorted x3 <= x2 <= x1: g >= 0 only between x2 and x1
        (g -> +inf as x -> -inf), so that interval is the motion's.

    Notes
    -----
    Roots known exactly are divided out first: x0 when the top starts at a turning
    point (g0 = 0), x = 0 when b = a (the axis passes through the vertical, or a
    planar pendulum), x = 2 when b = -a (through the bottom). Otherwise the two
    physical roots are bracketed by [0, x0] and [x0, 2] (g(0) = -B^2 < 0 < g(x0) >
    g(2) = -C^2) and x3 follows from Vieta and a Newton polish.
    """
    beta = cub.beta
    with decimal.localcontext(_ctx()):
        if g0 < 0:
            raise ValueError("g(x0) < 0: no physical motion")
        if cub.B == 0 and cub.C == 0:
            # b = a = 0 (no spin, no vertical momentum: a planar pendulum or a tumbling
            # free body): g = x (2 - x)(A + beta x), roots 0, 2 and -A/beta = 2 - A_y/beta.
            if beta == 0:
                x3, y3 = Decimal("-Infinity"), Decimal("Infinity")
                span = gap = cub.A
            else:
                x3, y3 = -cub.A / beta, cub.A_y / beta
            found = sorted(
                [(Decimal(0), Decimal(2)), (Decimal(2), Decimal(0))] + ([] if beta == 0 else [(x3, y3)]),
                key=lambda r: r[0],
            )
            if beta == 0:
                (x2, y2), (x1, y1) = found
            else:
                (x3, y3), (x2, y2), (x1, y1) = found
                span, gap = beta * (x1 - x3), beta * (x2 - x3)
            return TopRoots(
                x1=x1, x2=x2, x3=x3, y1=y1, y2=y2, y3=y3, beta_span=span, beta_gap=gap, d_low=x0 - x2, d_high=x1 - x0
            )
        if dg0 is None:
            dg0 = cub.dg(x0)
        exact: list[tuple[Decimal, Decimal]] = []
        if g0 == 0:
            exact.append((x0, y0))
        if cub.B == 0 and all(x != 0 for x, _ in exact):
            exact.append((Decimal(0), Decimal(2)))
        if cub.C == 0 and all(y != 0 for _, y in exact):
            exact.append((Decimal(2), Decimal(0)))
        if exact:
            found = [exact[0]] + _deflated(cub, *exact[0], dg0 if exact[0][0] == x0 else None)
            # Snap the computed roots to the other exact ones.
            for xe, ye in exact[1:]:
                i = min(range(1, len(found)), key=lambda k: abs(found[k][0] - xe))
                found[i] = (xe, ye)
        else:
            found = [_root_between(cub, x0, y0, g0, True), _root_between(cub, x0, y0, g0, False)]
            if beta != 0:
                x1, x2 = max(found[0][0], found[1][0]), min(found[0][0], found[1][0])
                x3 = -(cub.B * cub.B) / (beta * x1 * x2)  # Vieta: beta x1 x2 x3 = -B^2
                x3 = _polish(cub.g, cub.dg, x3)
                found.append((x3, 2 - x3))
        # By x, ties by y: next to the bottom two roots 1e-90 apart share their 60-digit x, not their y.
        found.sort(key=lambda r: (r[0], -r[1]))
        lo_x, hi_x = (found[0][0], found[-1][0]) if beta == 0 else (found[1][0], found[2][0])
        slack = Decimal(10) ** (-DIGITS + 10)
        if not (lo_x - slack * abs(x0) <= x0 <= hi_x + slack * abs(x0) + slack):
            raise ValueError("internal: the motion's interval does not contain the initial point")
        if beta == 0:
            (x2, y2), (x1, y1) = found[0], found[-1]
            x3 = Decimal("-Infinity")
            span = cub.A + cub.a * cub.a  # beta (x1 - x3) -> A + a^2 as beta -> 0
            gap = span
            y3 = Decimal("Infinity")
        else:
            (x3, y3), (x2, y2), (x1, y1) = found
            span = beta * (x1 - x3)
            gap = beta * (x2 - x3)
        d_low, d_high = _offsets(cub, x0, g0, dg0, x1, x2)
        return TopRoots(
            x1=x1, x2=x2, x3=x3, y1=y1, y2=y2, y3=y3, beta_span=span, beta_gap=gap, d_low=d_low, d_high=d_high
        )
