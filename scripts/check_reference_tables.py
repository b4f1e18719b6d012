"""Score wobble's elliptic kernels, beside SciPy's, on Boost.Math's elliptic-function test tables.

Usage::

    python scripts/check_reference_tables.py            # score, print, update docs/accuracy.md
    python scripts/check_reference_tables.py --no-write # score and print only
    python scripts/check_reference_tables.py --data DIR # tables somewhere else

The tables (Boost.Math ``test/*.ipp``, converted to CSV; a peer's reference values, 25
significant digits) are read from ``../shared/reference-data/boost-math/`` relative to the
repository root. When they are not there the script says so and exits with status 0: they
are outside the project and the test suite never reads them (the worst rows found here are
in ``tests/references/build_elliptic_references.py``, with mpmath values).

Every row is evaluated **one call per row** (the per-row comparison), and each table again
in **one vectorised call** (the array path, reported as its largest difference from the
per-row results). Inputs are Boost's doubles, taken exactly: the modulus k becomes
``m = k^2`` and ``m1 = 1 - k^2``, each rounded once from exact rationals (the tables' k carry
24 bits, so m is exact, and m1 too for |k| >= 1/4). Reductions are those wobble documents:

* ``|phi| > pi/2``: ``phi = j pi + r`` (:func:`wobble.numerics.elliptic.reduce_amplitude`),
  F = 2 j K + F(r), E = 2 j E + E(r), Pi = 2 j Pi(n) + Pi(n; r);
* ``k > 1`` (Jacobi functions): the reciprocal modulus (A&S 16.11.1-3),
  ``sn(u | k) = sn(k u | 1/k) / k``, ``cn(u | k) = dn(k u | 1/k)``, ``dn(u | k) = cn(k u | 1/k)``,
  with ``k u`` exact and ``1/k^2``, ``1 - 1/k^2`` rounded once;
* rows outside every kernel's domain (Pi with n >= 1) are counted and skipped.

Errors are relative, in units of eps = 2^-52 = 2.2e-16, against Boost's tabulated value.
SciPy: ``scipy.special.ellipk, ellipe, ellipkinc, ellipeinc, ellipj`` on the same inputs
(the same reciprocal-modulus transformation for k > 1; ``ellipkinc``/``ellipeinc`` take any
phi); SciPy has no Legendre Pi, so its column is Carlson's textbook form
``s R_F(c^2, D^2, 1) + (n/3) s^3 R_J(c^2, D^2, 1, 1 - n s^2)`` (DLMF 19.25.14) from
``scipy.special.elliprf, elliprj``, after the same reduction of phi.

Exit status 1 when a per-row error exceeds the bound the issue sets (16 eps; 3 eps for the
complete integrals).
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from fractions import Fraction
from pathlib import Path

import numpy as np
import scipy.special as sp

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_DATA = ROOT.parent / "shared" / "reference-data" / "boost-math"
DOC = ROOT / "docs" / "accuracy.md"
START, END = "<!-- boost-table:start -->", "<!-- boost-table:end -->"
EPS = 2.0**-52
BOUND = 16.0
COMPLETE_BOUND = 3.0

sys.path.insert(0, str(ROOT))
from wobble.numerics import elliptic as ell  # noqa: E402 - after sys.path.insert(0, ROOT)
from wobble.numerics.phase import reduce_phase  # noqa: E402 - after sys.path.insert(0, ROOT)


# ---------------------------------------------------------------------------
# Inputs
# ---------------------------------------------------------------------------
def read(path: Path):
    with path.open() as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def params(k: float):
    """m = k^2 and m1 = 1 - k^2, each rounded once from the exact rational."""
    q = Fraction(k) ** 2
    return float(q), float(1 - q)


def reciprocal(u: float, k: float):
    """k u, 1/k^2 and 1 - 1/k^2 for |k| > 1 (A&S 16.11), each rounded once."""
    kk = abs(Fraction(k))
    mu = 1 / (kk * kk)
    return float(Fraction(u) * kk), float(mu), float(1 - mu), float(kk)


def rel_err(got, ref):
    got = np.asarray(got, dtype=float)
    ref = np.asarray(ref, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = np.where(ref != 0, np.abs(got - ref) / np.abs(ref), np.abs(got))
    return np.where(np.isfinite(err) | (got == ref), err, np.inf) / EPS


# ---------------------------------------------------------------------------
# wobble, one row at a time (and the same formulas on whole columns)
# ---------------------------------------------------------------------------
def w_f(phi, m, m1):
    r, j = ell.reduce_amplitude(phi)
    return 2.0 * j * ell.ellipk(m, m1) + ell.ellipf_inc(r, m, m1)


def w_e2(phi, m, m1):
    r, j = ell.reduce_amplitude(phi)
    return 2.0 * j * ell.ellipe(m, m1) + ell.ellipe_inc(r, m, m1)


def w_pi3(n, phi, m, m1):
    r, j = ell.reduce_amplitude(phi)
    whole = np.where(j != 0, 2.0 * j * ell.ellippi(n, m, m1), 0.0)
    return whole + ell.ellippi_inc(n, r, m, m1)


def w_pi_scd(n, phi, m, m1):
    """pi_positive_scd (n > 0) or pi_negative_scd (n <= 0) from s, c, d2 of phi (|phi| <= pi/2)."""
    s, c = np.sin(phi), np.cos(phi)
    c = np.where(np.abs(phi) >= 0.5 * np.pi, 0.0, c)
    d2 = c * c + m1 * s * s
    n = float(n)
    if n > 0:
        return ell.pi_positive_scd(n, 1.0 - n, s, c, d2)
    return ell.pi_negative_scd(-n, s, c, d2, m1)


def _jacobi_inputs(u, k):
    if abs(k) <= 1:
        m, m1 = params(k)
        return u, m, m1, 1.0
    return reciprocal(u, k)


def jacobi_in_domain(fn, u, k):
    """sn, cn, dn of (u | k) through fn(u, m, m1), with the reciprocal modulus where |k| > 1."""
    u = np.asarray(u, dtype=float)
    k = np.asarray(k, dtype=float)
    v, m, m1, kk = np.vectorize(_jacobi_inputs)(u, k)
    sn, cn, dn = fn(v, m, m1)
    big = np.abs(k) > 1
    return np.where(big, sn / kk, sn), np.where(big, dn, cn), np.where(big, cn, dn)


def models_path(u, m, m1):
    """The free body's and heavy top's evaluator: reduce_phase modulo 2K (K double-double),
    then jacobi_reduced with the low part of K (wobble.models.free, wobble.models.top)."""
    sn, cn, dn = [], [], []
    for ui, mi, mi1 in np.broadcast(u, m, m1):
        lv = ell.landen_levels(mi, mi1)
        k_hi, k_lo = (float(x) for x in ell.ellipk_dd(mi, mi1))
        lv.K = np.asarray(k_hi)
        r, j = reduce_phase(np.asarray(ui), (1.0, 0.0), (2.0 * k_hi, 2.0 * k_lo))
        s, c, d = ell.jacobi_reduced(r, lv, k_lo)
        odd = np.floor(0.5 * j) != 0.5 * j
        sn.append(-s if odd else s)
        cn.append(-c if odd else c)
        dn.append(d)
    return np.array(sn, dtype=float), np.array(cn, dtype=float), np.array(dn, dtype=float)


def quarter_path(u, m, m1):
    """The flow map's evaluator: u = n K + x (exact), then jacobi_quarter (Landen for every m)."""
    lv = ell.landen_levels(m, m1)
    x, n = ell.reduce_quarter_period(u, *ell.ellipk_dd(m, m1))
    (sn, cn, dn), _ = ell.jacobi_quarter(n, x, lv)
    return sn, cn, dn


# ---------------------------------------------------------------------------
# SciPy
# ---------------------------------------------------------------------------
def s_pi3(n, phi, m):
    """Carlson's textbook Pi (DLMF 19.25.14) with SciPy's R_F, R_J, after the same reduction."""
    r, j = ell.reduce_amplitude(phi)

    def inc(x):
        s, c = np.sin(x), np.cos(x)
        s2, c2 = s * s, c * c
        d2 = 1.0 - m * s2
        return s * sp.elliprf(c2, d2, 1.0) + (n / 3.0) * s * s2 * sp.elliprj(c2, d2, 1.0, 1.0 - n * s2)

    return np.where(j != 0, 2.0 * j * inc(0.5 * np.pi), 0.0) + inc(r)


def s_jacobi(u, m, m1):
    sn, cn, dn, _ = sp.ellipj(u, m)
    return sn, cn, dn


# ---------------------------------------------------------------------------
# Scoring
# ---------------------------------------------------------------------------
class Score:
    def __init__(self, table, function, rows, per_row, ref, vector=None, scipy=None, bound=BOUND, worst_input=None):
        self.table, self.function, self.rows = table, function, rows
        self.err = rel_err(per_row, ref)
        self.vec = None if vector is None else rel_err(vector, per_row)
        self.scipy = None if scipy is None else rel_err(scipy, ref)
        self.bound = bound
        self.inputs = worst_input
        i = int(np.argmax(self.err)) if self.err.size else 0
        self.worst = worst_input[i] if worst_input is not None and self.err.size else None

    def worst_rows(self, count):
        """The ``count`` largest per-row errors with their inputs (for the test references)."""
        order = np.argsort(-self.err, kind="stable")[:count]
        return [(float(self.err[i]), {k: float(v) for k, v in self.inputs[i].items()}) for i in order]

    @property
    def ok(self):
        return self.bound is None or bool(np.all(self.err <= self.bound))


def score_tables(data: Path):
    scores, skipped = [], {}

    # Complete K and E: k
    for name, fn, sfn, label in (
        ("ellint_k.csv", ell.ellipk, lambda m, m1: sp.ellipk(m), "K (ellipk)"),
        ("ellint_e.csv", ell.ellipe, lambda m, m1: sp.ellipe(m), "E (ellipe)"),
    ):
        _, rows = read(data / name)
        k = np.array([float(r[0]) for r in rows])
        ref = np.array([float(r[1]) for r in rows])
        m, m1 = np.vectorize(params)(k)
        per = np.array([fn(a, b) for a, b in zip(m, m1)], dtype=float)
        scores.append(
            Score(name, label, len(rows), per, ref, fn(m, m1), sfn(m, m1), COMPLETE_BOUND, [dict(k=x) for x in k])
        )
        if name == "ellint_k.csv":
            hi = np.array([ell.ellipk_dd(a, b)[0] for a, b in zip(m, m1)], dtype=float)
            scores.append(
                Score(
                    name,
                    "K hi (ellipk_dd)",
                    len(rows),
                    hi,
                    ref,
                    ell.ellipk_dd(m, m1)[0],
                    None,
                    COMPLETE_BOUND,
                    [dict(k=x) for x in k],
                )
            )

    # Incomplete F and E: phi, k
    for name, fn, sfn, label in (
        ("ellint_f.csv", w_f, sp.ellipkinc, "F (ellipf_inc)"),
        ("ellint_e2.csv", w_e2, sp.ellipeinc, "E(phi) (ellipe_inc)"),
    ):
        _, rows = read(data / name)
        phi = np.array([float(r[0]) for r in rows])
        k = np.array([float(r[1]) for r in rows])
        ref = np.array([float(r[2]) for r in rows])
        m, m1 = np.vectorize(params)(k)
        per = np.array([fn(a, b, c) for a, b, c in zip(phi, m, m1)], dtype=float)
        scores.append(
            Score(
                name,
                label,
                len(rows),
                per,
                ref,
                fn(phi, m, m1),
                sfn(phi, m),
                BOUND,
                [dict(phi=a, k=b) for a, b in zip(phi, k)],
            )
        )

    # Complete Pi: n, k
    _, rows = read(data / "ellint_pi2.csv")
    rows_in = [r for r in rows if float(r[0]) < 1]
    skipped["ellint_pi2.csv"] = len(rows) - len(rows_in)
    n = np.array([float(r[0]) for r in rows_in])
    k = np.array([float(r[1]) for r in rows_in])
    ref = np.array([float(r[2]) for r in rows_in])
    m, m1 = np.vectorize(params)(k)
    per = np.array([ell.ellippi(a, b, c) for a, b, c in zip(n, m, m1)], dtype=float)
    scipy_pi = np.array([s_pi3(a, 0.5 * np.pi, b) for a, b in zip(n, m)], dtype=float)
    scores.append(
        Score(
            "ellint_pi2.csv",
            "Pi(n) (ellippi)",
            len(rows_in),
            per,
            ref,
            ell.ellippi(n, m, m1),
            scipy_pi,
            COMPLETE_BOUND,
            [dict(n=a, k=b) for a, b in zip(n, k)],
        )
    )

    # Incomplete Pi: n, phi, k
    for name in ("ellint_pi3.csv", "ellint_pi3_large.csv"):
        _, rows = read(data / name)
        rows_in = [r for r in rows if float(r[0]) < 1]
        skipped[name] = len(rows) - len(rows_in)
        n = np.array([float(r[0]) for r in rows_in])
        phi = np.array([float(r[1]) for r in rows_in])
        k = np.array([float(r[2]) for r in rows_in])
        ref = np.array([float(r[3]) for r in rows_in])
        m, m1 = np.vectorize(params)(k)
        per = np.array([w_pi3(a, b, c, d) for a, b, c, d in zip(n, phi, m, m1)], dtype=float)
        vec = w_pi3(n, phi, m, m1)
        scipy_pi = np.array([s_pi3(a, b, c) for a, b, c in zip(n, phi, m)], dtype=float)
        worst = [dict(n=a, phi=b, k=c) for a, b, c in zip(n, phi, k)]
        scores.append(Score(name, "Pi(n; phi) (ellippi_inc)", len(rows_in), per, ref, vec, scipy_pi, BOUND, worst))
        inside = np.abs(phi) <= 0.5 * np.pi
        if np.any(inside):
            per_scd = np.array(
                [w_pi_scd(a, b, c, d) for a, b, c, d in zip(n[inside], phi[inside], m[inside], m1[inside])], dtype=float
            )
            scores.append(
                Score(
                    name,
                    "Pi (pi_positive_scd / pi_negative_scd)",
                    int(inside.sum()),
                    per_scd,
                    ref[inside],
                    None,
                    None,
                    BOUND,
                    [w for w, i in zip(worst, inside) if i],
                )
            )

    # Jacobi functions: u, k
    for name in ("jacobi_elliptic.csv", "jacobi_elliptic_small.csv", "jacobi_large_phi.csv", "jacobi_near_1.csv"):
        _, rows = read(data / name)
        u = np.array([float(r[0]) for r in rows])
        k = np.array([float(r[1]) for r in rows])
        ref = np.array([[float(x) for x in r[2:5]] for r in rows])
        worst = [dict(u=a, k=b) for a, b in zip(u, k)]
        per = np.array([jacobi_in_domain(ell.jacobi, a, b) for a, b in zip(u, k)], dtype=float)
        vec = np.array(jacobi_in_domain(ell.jacobi, u, k)).T
        sci = np.array(jacobi_in_domain(s_jacobi, u, k)).T
        for i, f in enumerate(("sn", "cn", "dn")):
            scores.append(
                Score(name, f"{f} (jacobi)", len(rows), per[:, i], ref[:, i], vec[:, i], sci[:, i], BOUND, worst)
            )
        # The amplitude: Boost's sn, cn give am = atan2(sn, cn) + 2 pi j (j from u / K).
        inside = np.abs(k) <= 1
        if np.any(inside):
            m, m1 = np.vectorize(params)(k[inside])
            am_ref = np.arctan2(ref[inside, 0], ref[inside, 1])
            turns = np.rint((0.5 * np.pi * u[inside] / ell.ellipk(m, m1) - am_ref) / (2 * np.pi))
            am_ref = am_ref + 2 * np.pi * turns
            am = np.array([ell.jacobi_am(a, b, c) for a, b, c in zip(u[inside], m, m1)], dtype=float)
            sci_am = sp.ellipj(u[inside], m)[3]
            scores.append(
                Score(
                    name,
                    "am (jacobi_am)*",
                    int(inside.sum()),
                    am,
                    am_ref,
                    ell.jacobi_am(u[inside], m, m1),
                    sci_am,
                    BOUND,
                    [w for w, i in zip(worst, inside) if i],
                )
            )
        for label, fn in (("jacobi_reduced after reduce_phase", models_path), ("jacobi_quarter", quarter_path)):
            got = np.array(jacobi_in_domain(fn, u, k)).T
            for i, f in enumerate(("sn", "cn", "dn")):
                scores.append(Score(name, f"{f} ({label})", len(rows), got[:, i], ref[:, i], None, None, None, worst))
    return scores, skipped


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------
def fmt(x):
    if x is None:
        return "-"
    if not np.isfinite(x):
        return "inf"
    return f"{x:.3g}" if x >= 1000 else f"{x:.2f}"


def table(scores, skipped, data: Path, seconds: float) -> str:
    lines = [
        f"Scored by `python scripts/check_reference_tables.py` ({seconds:.0f} s) on the Boost.Math tables "
        f"(commit 99733ebb of boostorg/math); relative error in eps = 2.2e-16. *per row*: one call per row; "
        "*array vs rows*: the largest difference of one vectorised call per table from the per-row results.",
        "",
        "| table | function | rows | wobble max | wobble median | array vs rows (max) | SciPy max | SciPy median |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for s in scores:
        lines.append(
            f"| {s.table} | {s.function} | {s.rows} | {fmt(s.err.max())} | {fmt(float(np.median(s.err)))} | "
            f"{fmt(None if s.vec is None else s.vec.max())} | {fmt(None if s.scipy is None else s.scipy.max())} | "
            f"{fmt(None if s.scipy is None else float(np.median(s.scipy)))} |"
        )
    skip = ", ".join(f"{k}: {v}" for k, v in skipped.items() if v)
    lines += [
        "",
        f"Rows outside wobble's domain (Pi with n >= 1), skipped: {skip or 'none'}. "
        "\\* am: reference atan2(sn, cn) of Boost's values, unwrapped by u/K (k <= 1 rows). "
        "The SciPy column of Pi is Carlson's textbook form with SciPy's R_F, R_J (SciPy has no Legendre Pi); "
        "of am, `scipy.special.ellipj`'s `ph`.",
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="folder of the Boost CSV tables")
    ap.add_argument("--no-write", action="store_true", help="print only; do not update docs/accuracy.md")
    ap.add_argument(
        "--worst",
        type=int,
        default=1,
        metavar="N",
        help="list the N worst rows of every bounded function (inputs for tests/references)",
    )
    args = ap.parse_args(argv)
    if not (args.data / "README.md").exists() or not (args.data / "ellint_k.csv").exists():
        print(
            f"Boost.Math reference tables not found at {args.data}: nothing scored (they live outside "
            "the project; see the docstring)."
        )
        return 0
    t0 = time.perf_counter()
    scores, skipped = score_tables(args.data)
    text = table(scores, skipped, args.data, time.perf_counter() - t0)
    print(text)
    bad = [s for s in scores if not s.ok]
    for s in scores:
        if s.bound is not None:
            for err, inputs in s.worst_rows(args.worst):
                print(f"worst {s.table:26s} {s.function:42s} {err:8.2f} eps at {inputs}")
    if not args.no_write:
        doc = DOC.read_text()
        if START in doc and END in doc:
            head, rest = doc.split(START, 1)
            _, tail = rest.split(END, 1)
            DOC.write_text(f"{head}{START}\n{text}\n{END}{tail}")
            print(f"wrote {DOC.relative_to(ROOT)}")
        else:
            print(f"{DOC.relative_to(ROOT)} has no {START} ... {END} markers: not written")
    for s in bad:
        print(f"BOUND EXCEEDED: {s.table} {s.function}: {s.err.max():.2f} eps > {s.bound} at {s.worst}")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
