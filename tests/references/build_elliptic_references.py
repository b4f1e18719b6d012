"""Regenerate tests/references/elliptic_kernels.json with mpmath only (no wobble, no numpy).

Usage::

    python tests/references/build_elliptic_references.py      # ~1 minute

The reference values behind the accuracy bounds documented in
:mod:`wobble.numerics.elliptic` and :mod:`wobble.numerics.double_double`
(tests/test_elliptic_bounds.py checks one bound per test). Inputs are float64
values taken *exactly* (``mpmath.mpf(float)``); the parameter is given by its exact
complement ``m1`` (``m = 1 - m1`` in mpmath arithmetic), as the kernels take it.
Values at 40 digits (more where ``m1`` is tiny: ``1 - m1`` must be exact), each
checked against a second evaluation at 20 more digits before it is stored.

Two sources of inputs:

* **the worst rows of Boost.Math's tables** for wobble's kernels, as found by
  ``python scripts/check_reference_tables.py --worst 3`` (Boost.Math ``test/*.ipp``,
  the inputs only: the values here are mpmath's). Boost's modulus k becomes
  ``m1 = 1 - k^2`` rounded once; k > 1 rows of the Jacobi tables enter through the
  reciprocal modulus (A&S 16.11: argument ``k u``, ``m1 = 1 - 1/k^2`` rounded once),
  so every row here is inside the kernels' domain, at the floats they receive;
* **grids** over the parameter (m1 from 2.3e-308 to 1), the amplitude, the
  characteristic (n from -1e4 to 1 - 1e-9) and the argument (u up to 2^25 K and
  1e6 K), including the row of Pi(n; phi | m) next to its pole that lost 84 eps.
"""

from __future__ import annotations

import json
import math
import random
from fractions import Fraction
from pathlib import Path

import mpmath as mp

OUT = Path(__file__).with_name("elliptic_kernels.json")
DPS = 40


def s(x, digits=34):
    return mp.nstr(x, digits, strip_zeros=False)


def exact(x) -> mp.mpf:
    f = Fraction(x)
    return mp.mpf(f.numerator) / f.denominator


def dps_for(m1: float) -> int:
    """40 digits beyond those of m1 in m = 1 - m1 (mpmath recovers m1 from m; m1 down to 2.3e-308)."""
    return DPS + (0 if m1 == 0 or m1 >= 0.5 else int(-math.log10(m1)) + 5)


def checked(fn, m1, extra=0):
    """fn() at dps_for(m1) + extra digits, checked against 20 more."""
    with mp.workdps(dps_for(m1) + extra):
        a = fn()
    with mp.workdps(dps_for(m1) + extra + 20):
        b = fn()
    a = a if isinstance(a, (list, tuple)) else [a]
    b = b if isinstance(b, (list, tuple)) else [b]
    for x, y in zip(a, b):
        assert abs(x - y) <= mp.mpf(10) ** -36 * max(abs(y), mp.mpf(10) ** -300), (x, y)
    return a


def m1_of_k(k: float) -> float:
    return float(1 - Fraction(k) ** 2)


# ---------------------------------------------------------------------------
# Boost.Math's worst rows for wobble (inputs; scripts/check_reference_tables.py --worst 3)
# ---------------------------------------------------------------------------
BOOST_K = [0.8417503237724304, 0.9004446268081665, 0.09376753121614456, -0.9904230833053589]
BOOST_E = [0.9004441499710083, 0.5093733072280884, -0.9904330372810364]
BOOST_PI = [
    (0.9928812980651855, 0.09754040092229843),
    (0.6323592662811279, 0.09754040092229843),
    (0.9964613318443298, 0.9171178936958313),
    (-87.17433166503906, 0.1269868165254593),
    (-15.664134979248047, 0.9057919383049011),
    (0.9688677787780762, 0.8147236704826355),
]
BOOST_F = [(19.150136947631836, 0.9676949381828308), (9.507055282592773, 0.9688677787780762)]
BOOST_E2 = [(2.539736270904541, 0.9377356171607971), (0.15262925624847412, -0.6232360601425171)]
BOOST_PI3 = [  # n, phi, k
    (0.9964613318443298, 1.5652378797531128, 0.9171178936958313),  # 84 eps before 1 - n s^2 was rewritten
    (0.9648885130882263, 1.504048228263855, 0.900053858757019),
    (0.9928812980651855, 1.5200517177581787, 0.7802274227142334),
    (-77.3941650390625, 2.6471853256225586, 0.45603281259536743),
    (-34.33353042602539, 2.6471853256225586, 0.36318644881248474),
    (-84.76158142089844, 0.9376299381256104, 0.6813595294952393),
    (-88.29515075683594, -8.049192428588867, 0.8147236704826355),
]
BOOST_JACOBI = [  # u, k (k > 1: reciprocal modulus)
    (0.9676947593688965, 0.9057917594909668),
    (0.5468814373016357, 0.09754037857055664),
    (0.6323592662811279, 0.9928812980651855),
    (0.5468814373016357, 0.9964611530303955),
    (0.1269868016242981, 0.9057917594909668),
    (0.001962467096745968, 0.7518312931060791),
    (3.387028118595481e-05, 0.4898730516433716),
    (1.655740737915039, 3.387028118595481e-05),
    (1.655740737915039, 0.23480379581451416),
    (0.7518312931060791, 0.7518312931060791),
    (-124.647216796875, 0.8350083827972412),
    (188.23712158203125, 0.9057917594909668),
    (-111.58639526367188, 0.6323592662811279),
    (18.752593994140625, 0.8147234916687012),
    (185.95538330078125, 0.9057917594909668),
    (-88.6007080078125, 0.8350083827972412),
    (134.00341796875, 0.3081669807434082),
    (192.44384765625, 0.22103404998779297),
    (-145.8092041015625, 0.8147234916687012),
    (197.15252685546875, 0.1269868016242981),
    (4.688676834106445, 1.0623893737792969),
    (0.4688149690628052, 1.0023207664489746),
    (3.1472368240356445, 1.0000371932983398),
    (4.648883819580078, 1.0007553100585938),
    (4.057918548583984, 1.0023207664489746),
    (-3.645230293273926, 1.0000033378601074),
    (-3.116180419921875, 1.0155692100524902),
]


def jacobi_inputs(u: float, k: float):
    """(u, m1) at the kernel: the reciprocal modulus for |k| > 1 (A&S 16.11.1-3)."""
    if abs(k) <= 1:
        return u, m1_of_k(k)
    kk = abs(Fraction(k))
    v = Fraction(u) * kk
    assert float(v) == v  # 24-bit u and k: k u is exact
    return float(v), float(1 - 1 / (kk * kk))


# ---------------------------------------------------------------------------
# Complete and incomplete integrals
# ---------------------------------------------------------------------------
M1_GRID = [
    2.2250738585072014e-308,
    1e-300,
    1e-100,
    1e-30,
    1e-16,
    1e-12,
    1e-8,
    1e-4,
    7e-6,
    0.01,
    0.2,
    0.5,
    0.7,
    0.9,
    1 - 1e-9,
    1 - 1e-12,
    1.0,
]
N_GRID = [
    -1e4,
    -87.17433166503906,
    -15.664134979248047,
    -1.0,
    -1e-8,
    0.0,
    0.3,
    0.9,
    0.99,
    0.9964613318443298,
    0.999999,
    1 - 1e-9,
]
PHI_GRID = [1e-8, 0.3, -0.7, 1.2, 1.5652378797531128, 1.5707963267948966]


def integral_rows():
    rows = []
    for m1 in sorted({*M1_GRID, *(m1_of_k(k) for k in BOOST_K + BOOST_E)}):
        if m1 == 0:
            continue
        k_val, e_val = checked(lambda: [mp.ellipk(1 - exact(m1)), mp.ellipe(1 - exact(m1))], m1)
        rows.append({"kind": "K", "m1": repr(m1), "value": s(k_val)})
        rows.append({"kind": "E", "m1": repr(m1), "value": s(e_val)})
    pi_inputs = {(n, m1) for n in N_GRID for m1 in (1e-16, 1e-8, 0.01, 0.5, 0.9, 1.0)}
    pi_inputs |= {(n, m1_of_k(k)) for n, k in BOOST_PI}
    for n, m1 in sorted(pi_inputs):
        (v,) = checked(lambda: mp.ellippi(exact(n), 1 - exact(m1)), m1)
        rows.append({"kind": "Pi", "n": repr(n), "m1": repr(m1), "value": s(v)})
    # Incomplete: F, E(phi) over phi (any phi: mpmath continues them), Pi(n; phi).
    f_inputs = {
        (phi, m1) for phi in PHI_GRID + [19.150136947631836, -1185.395751953125] for m1 in (1e-16, 0.01, 0.5, 1.0)
    }
    f_inputs |= {(phi, m1_of_k(k)) for phi, k in BOOST_F + BOOST_E2}
    for phi, m1 in sorted(f_inputs):
        f_val, e_val = checked(lambda: [mp.ellipf(exact(phi), 1 - exact(m1)), mp.ellipe(exact(phi), 1 - exact(m1))], m1)
        rows.append({"kind": "F", "phi": repr(phi), "m1": repr(m1), "value": s(f_val)})
        rows.append({"kind": "Einc", "phi": repr(phi), "m1": repr(m1), "value": s(e_val)})
    p_inputs = {(n, phi, m1) for n in N_GRID for phi in PHI_GRID for m1 in (1e-16, 0.01, 0.5, 1.0)}
    p_inputs |= {(n, phi, m1_of_k(k)) for n, phi, k in BOOST_PI3}
    for n, phi, m1 in sorted(p_inputs):
        (v,) = checked(lambda: mp.ellippi(exact(n), exact(phi), 1 - exact(m1)), m1)
        rows.append({"kind": "Pi_inc", "n": repr(n), "phi": repr(phi), "m1": repr(m1), "value": s(v)})
    return rows


# ---------------------------------------------------------------------------
# Jacobi functions and the amplitude
# ---------------------------------------------------------------------------
FRACTIONS = [
    1e-9,
    0.013,
    0.25,
    0.49,
    0.5,
    0.51,
    0.99,
    1.0,
    1.3,
    -2.7,
    3.9,
    77.3,
    -1000.37,
    123456.2,
    1e6 + 0.77,
    2.0**25 + 0.3,
]


def jacobi_row(u: float, m1: float, source: str):
    def values():
        m = 1 - exact(m1)
        uu = exact(u)
        sn, cn, dn = (mp.ellipfun(f, uu, m=m) for f in ("sn", "cn", "dn"))
        if m1 == 0:
            return [sn, cn, dn, 2 * mp.atan(mp.tanh(uu / 2)), mp.mpf(0)]
        kk = mp.ellipk(m)
        a0 = mp.atan2(sn, cn)
        am = a0 + 2 * mp.pi * mp.nint((mp.pi * uu / (2 * kk) - a0) / (2 * mp.pi))
        q = mp.nint(uu / kk)
        return [sn, cn, dn, am, abs(uu - q * kk) / (max(abs(q), 1) * kk)]

    # a large u loses log10|u| digits to the reduction inside mpmath, and a value next to a
    # zero (u = float(q K)) up to 18 more
    sn, cn, dn, am, dist = checked(values, m1, extra=int(math.log10(max(abs(u), 1.0))) + 25)
    return {
        "source": source,
        "u": repr(u),
        "m1": repr(m1),
        "sn": s(sn),
        "cn": s(cn),
        "dn": s(dn),
        "am": s(am),
        # u within 1e-15 |q| K of a multiple of K: the double-double K's floor, an absolute bound there
        "near_zero": bool(dist < mp.mpf("1e-15")),
    }


def jacobi_rows():
    rows = []
    for u, k in BOOST_JACOBI:
        v, m1 = jacobi_inputs(u, k)
        rows.append(jacobi_row(v, m1, f"boost u={u!r} k={k!r}"))
    rng = random.Random(21)
    for m1 in M1_GRID + [0.0]:
        with mp.workdps(dps_for(m1)):
            kk = mp.ellipk(1 - exact(m1)) if m1 > 0 else None
        us = [rng.uniform(-200, 200) for _ in range(3)]
        if kk is not None:
            us += [float(fr * kk) for fr in FRACTIONS]
        for u in us:
            rows.append(jacobi_row(u, m1, "grid"))
    return rows


# ---------------------------------------------------------------------------
# Reductions and double-double pieces
# ---------------------------------------------------------------------------
def reduce_rows():
    rows = []
    with mp.workdps(60):
        for phi in [
            1185.395751953125,
            -8.049192428588867,
            19.150136947631836,
            1e6 + 0.3,
            2.0**25,
            4.71238898038469,
            1.5707963267948966,
            -1.5707963267948968,
            1e-300,
            0.0,
        ]:
            j = mp.nint(exact(phi) / mp.pi)
            r = exact(phi) - j * mp.pi
            if r > mp.pi / 2:
                j, r = j + 1, r - mp.pi
            elif r < -mp.pi / 2:
                j, r = j - 1, r + mp.pi
            rows.append({"phi": repr(phi), "j": int(j), "r": s(r)})
    return rows


def agm_rows():
    rows = []
    with mp.workdps(60):
        for m1 in M1_GRID + [2.0**-52, 0.3, 5e-324]:
            b = mp.sqrt(exact(m1))
            rows.append({"m1": repr(m1), "K": s(mp.pi / (2 * mp.agm(1, b)), 45), "sqrt": s(b, 45)})
    return rows


def main():
    mp.mp.dps = DPS
    out = {
        "generator": f"tests/references/build_elliptic_references.py (mpmath {mp.__version__})",
        "integrals": integral_rows(),
        "jacobi": jacobi_rows(),
        "reduce_amplitude": reduce_rows(),
        "agm": agm_rows(),
    }
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT} ({sum(len(v) for v in out.values() if isinstance(v, list))} rows)")


if __name__ == "__main__":
    main()
