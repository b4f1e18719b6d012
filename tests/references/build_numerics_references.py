"""Regenerate tests/references/numerics_kernels.json with mpmath only (no wobble, no numpy).

Usage::

    python tests/references/build_numerics_references.py      # a few seconds

References for three kernels of wobble.numerics that had no direct tests
(tests/test_cubic.py, tests/test_symmetric_eigen.py, tests/test_highprec.py):

* ``cubic``: the heavy top's cubic in x = 1 - u, g(x) = x (2 - x)(A + beta x) - (B + a x)^2
  (course notes section 5.7), for coefficient sets given as short decimal strings (so the
  polynomial is exact in both mpmath and :mod:`decimal`): its three roots by
  ``mpmath.polyroots`` at 100 digits, polished by ``mpmath.findroot`` in x and in
  y = 2 - x, and checked against g. The cases are those the module's docstring names: a
  generic top, a start at a turning point, regular precession (a double root), through the
  vertical (B = 0) and through the bottom (C = 0), a planar pendulum (B = C = 0), roots
  crowding at u = 1 (1e-100) and at u = -1, a nearly free top (beta = 1e-170) and beta = 0.
* ``eigen``: real symmetric 3x3 matrices (float entries, taken exactly) and their
  eigenvalues and eigenvectors by ``mpmath.eigsy`` at 50 digits.
* ``highprec``: square roots, K(m) = pi / (2 AGM(1, sqrt(m1))), Bulirsch's cel for K, E
  and Pi, and sin, cos of floats up to pi (next to their zeros included), at 80 digits.
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import mpmath as mp

OUT = Path(__file__).with_name("numerics_kernels.json")


def s(x, digits=60):
    return mp.nstr(x, digits, strip_zeros=False)


def exact(x) -> mp.mpf:
    f = Fraction(x)
    return mp.mpf(f.numerator) / f.denominator


# ---------------------------------------------------------------------------
# The top's cubic
# ---------------------------------------------------------------------------
# name, A, B, a, beta, x0 (decimal strings); C = B + 2 a; g0 = g(x0) (exact, finite decimals).
CUBIC_CASES = [
    ("generic", "1.5", "-0.7", "3", "2", "0.5"),
    ("turning point", None, "-0.7", "3", "2", "0.4"),  # A chosen so that g(0.4) = 0
    ("regular precession", "-0.140625", "-0.2", "1", "0.5078125", "0.4"),  # g = g' = 0 at 0.4
    ("through the vertical", "2", "0", "1.5", "1", "0.3"),
    ("through the bottom", "2", "-3", "1.5", "1", "1.7"),
    ("planar pendulum", "1", "0", "0", "2", "0.5"),
    ("near the vertical", "1", "-1e-100", "1", "1", "1e-100"),
    ("near the bottom", "0.5", "-2." + "0" * 49 + "1", "1", "1", "1." + "9" * 60),  # C = -1e-50, y0 = 1e-60
    ("nearly free", "1.5", "-0.7", "3", "1e-170", "0.5"),
    ("free (beta = 0)", "1.5", "-0.7", "3", "0", "0.5"),
    ("crowded pair", "0.02", "-0.1", "1", "0.01", "0.09"),
]


def _g(A, B, a, beta, x):
    return x * (2 - x) * (A + beta * x) - (B + a * x) ** 2


def cubic_rows():
    rows = []
    with mp.workdps(250):
        for name, A, B, a, beta, x0 in CUBIC_CASES:
            Bm, am, bm, xm = (mp.mpf(v) for v in (B, a, beta, x0))
            if A is None:  # the turning point: g(x0) = 0 with x0 (2 - x0) = 0.64
                A = str(mp.nstr((Bm + am * xm) ** 2 / (xm * (2 - xm)) - bm * xm, 40))
            Am = mp.mpf(A)
            g0 = _g(Am, Bm, am, bm, xm)
            # -beta x^3 + (2 beta - A - a^2) x^2 + 2 (A - a B) x - B^2
            coeffs = [-bm, 2 * bm - Am - am**2, 2 * (Am - am * Bm), -(Bm**2)]
            while coeffs[0] == 0:
                coeffs = coeffs[1:]
            found = sorted(mp.re(r) for r in mp.polyroots(coeffs, maxsteps=3000, extraprec=3000))
            xs, ys = [], []
            for r in found:
                # polish in the coordinate that keeps the root's digits: x next to u = 1, y next to u = -1
                try:
                    if r <= 1:
                        x = mp.findroot(lambda v: _g(Am, Bm, am, bm, v), r, tol=mp.mpf(10) ** -230)
                        y = 2 - x
                    else:
                        y = mp.findroot(lambda v: _g(Am, Bm, am, bm, 2 - v), 2 - r, tol=mp.mpf(10) ** -230)
                        x = 2 - y
                except (ValueError, ZeroDivisionError):  # a double root: polyroots' value stands
                    x, y = r, 2 - r
                scale = (abs(Am) + Bm**2 + am**2 + abs(bm) + 1) * max(abs(x), 1) ** 3
                assert abs(_g(Am, Bm, am, bm, x)) <= mp.mpf(10) ** -80 * scale, (name, x)
                xs.append(x)
                ys.append(y)
            rows.append(
                {
                    "name": name,
                    "A": A,
                    "B": B,
                    "C": s(Bm + 2 * am, 80),
                    "a": a,
                    "beta": beta,
                    "x0": x0,
                    "y0": s(2 - xm, 80),
                    "g0": s(g0, 120),
                    # ascending x (beta > 0: x3 < 0 <= x2 <= x1); y = 2 - x with its own digits
                    "x": [s(v, 70) for v in xs],
                    "y": [s(v, 70) for v in ys],
                }
            )
    return rows


# ---------------------------------------------------------------------------
# Symmetric 3x3 eigenproblems
# ---------------------------------------------------------------------------
EIGEN_CASES = [
    ("generic", [[2.0, 0.3, -0.1], [0.3, 1.0, 0.25], [-0.1, 0.25, 3.5]]),
    ("Earth-like", [[8.0101e37, 1.2e32, -3.0e31], [1.2e32, 8.0103e37, 2.0e31], [-3.0e31, 2.0e31, 8.0365e37]]),
    ("tiny entries", [[2e-300, 3e-301, 0.0], [3e-301, 1e-300, 1e-301], [0.0, 1e-301, 5e-300]]),
    ("huge entries", [[2e300, 3e299, 0.0], [3e299, 1e300, 1e299], [0.0, 1e299, 5e300]]),
    ("negative definite", [[-1.0, 0.5, 0.2], [0.5, -2.0, 0.1], [0.2, 0.1, -3.0]]),
    ("rotated", [[1.5, 0.5, 0.0], [0.5, 1.5, 0.0], [0.0, 0.0, 4.0]]),
]


def eigen_rows():
    rows = []
    with mp.workdps(50):
        for name, m in EIGEN_CASES:
            a = mp.matrix([[exact(v) for v in row] for row in m])
            e, q = mp.eigsy(a)
            order = sorted(range(3), key=lambda i: e[i])
            rows.append(
                {
                    "name": name,
                    "matrix": [[repr(v) for v in row] for row in m],
                    "values": [s(e[i], 40) for i in order],
                    "vectors": [[s(q[j, i], 40) for j in range(3)] for i in order],  # rows: unit eigenvectors
                }
            )
    return rows


# ---------------------------------------------------------------------------
# highprec
# ---------------------------------------------------------------------------
def highprec_rows():
    out = {"sqrt": [], "agm_k": [], "cel": [], "sin_cos": []}
    with mp.workdps(80):
        for x in [2.0, 0.3, 1e-300, 7.0e300, 1 - 2**-53, 5e-324]:
            out["sqrt"].append({"x": repr(x), "value": s(mp.sqrt(exact(x)), 70)})
        for m1 in [1.0, 0.5, 0.3, 1e-12, 1e-100, 1e-300]:
            out["agm_k"].append({"m1": repr(m1), "value": s(mp.pi / (2 * mp.agm(1, mp.sqrt(exact(m1)))), 70)})
        for m1 in [1.0, 0.5, 0.3, 1e-12]:
            m = 1 - exact(m1)
            out["cel"].append({"kind": "K", "m1": repr(m1), "value": s(mp.ellipk(m), 70)})
            out["cel"].append({"kind": "E", "m1": repr(m1), "value": s(mp.ellipe(m), 70)})
            for n in [-50.0, -0.5, 0.3, 0.99, 0.9999999]:
                out["cel"].append({"kind": "Pi", "m1": repr(m1), "n": repr(n), "value": s(mp.ellippi(exact(n), m), 70)})
        for x in [
            0.0,
            1e-17,
            0.5,
            -0.75,
            0.7853981633974483,
            1.5707963267948966,
            -1.5707963267948966,
            2.0,
            3.141592653589793,
            -3.141592653589793,
            1e-300,
        ]:
            out["sin_cos"].append({"x": repr(x), "sin": s(mp.sin(exact(x)), 70), "cos": s(mp.cos(exact(x)), 70)})
    return out


def main():
    out = {
        "generator": f"tests/references/build_numerics_references.py (mpmath {mp.__version__})",
        "cubic": cubic_rows(),
        "eigen": eigen_rows(),
        "highprec": highprec_rows(),
    }
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
