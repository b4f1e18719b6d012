"""Regenerate tests/references/free_rotation.json with mpmath only (no wobble import).

Usage::

    python tests/references/build_free_references.py      # ~3 minutes

Inputs are float64 values (moments, omega0, times), taken *exactly* as
``mpmath.mpf(float)`` (a decimal such as 0.1 means its binary double), so the
tests measure wobble's algorithm, not the rounding of its inputs. Three
independent references:

* ``elliptic``: Jacobi sn, cn, dn from ``mpmath.ellipfun`` and K, E, F, E(phi),
  Pi(n; phi) from ``mpmath.ellipk`` etc. at 40 digits (checked against 60 digits
  before they are stored), with the parameter given by its exact complement
  m1 (m = 1 - m1 in mpmath arithmetic);
* ``ode``: Euler's equations plus the quaternion kinematics q' = q (0, omega) / 2
  integrated by ``mpmath.odefun`` (Taylor series, 30 digits): no elliptic
  function and no formula of the solution enters;
* ``closed``: for long spans, where the Taylor integration would take hours,
  Landau & Lifshitz section 37 evaluated with ``mpmath.ellipfun`` at 40 digits
  (its sign conventions checked against the ODE on the short spans), and the
  attitude's twist angle psi(t) = int_0^t [L/I_c + (D_c/I_c)/(L + I_c |omega_c|)] dt
  integrated by ``mpmath.quad`` over one period and the remainder.

``python tests/references/build_free_references.py --very-long`` writes
tests/references/free_rotation_very_long.json instead: the closed form at times from 2^26 to
1.9 x 2^48 periods of omega, at 60 digits, checked at 80.
"""

from __future__ import annotations

import json
from pathlib import Path

import mpmath as mp

OUT = Path(__file__).with_name("free_rotation.json")
DPS = 40


def s(x, digits=30):
    return mp.nstr(x, digits, strip_zeros=False)


# ---------------------------------------------------------------------------
# Elliptic functions and integrals
# ---------------------------------------------------------------------------
def elliptic_cases():
    rows = []
    m1_values = [1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-10, 1e-6, 1e-3, 0.25, 0.5, 0.75, 0.9, 1 - 1e-6, 1 - 1e-12, 1.0]
    fracs = [0.0137, 0.3, 0.49, 0.51, 0.77, 0.999999, 1.3, 1.999, 2.7, 3.9, 1000.37, 123456.2, 1e6 + 0.77]
    for m1f in m1_values:
        m1 = mp.mpf(m1f)
        m = 1 - m1
        K = mp.ellipk(m)
        for fr in fracs:
            u = float(mp.mpf(fr) * K)
            uu = mp.mpf(u)
            vals = [mp.ellipfun(k, uu, m=m) for k in ("sn", "cn", "dn")]
            with mp.workdps(60):
                check = [mp.ellipfun(k, uu, m=1 - mp.mpf(m1f)) for k in ("sn", "cn", "dn")]
            assert all(abs(a - b) < mp.mpf(10) ** -32 for a, b in zip(vals, check))
            rows.append({"m1": repr(m1f), "u": repr(u), "sn": s(vals[0]), "cn": s(vals[1]), "dn": s(vals[2])})
    return rows


def integral_cases():
    rows = []
    for m1f in [1e-16, 1e-12, 1e-6, 0.1, 0.5, 0.9, 1.0]:
        m1 = mp.mpf(m1f)
        m = 1 - m1
        rows.append({"kind": "K", "m1": repr(m1f), "value": s(mp.ellipk(m))})
        rows.append({"kind": "E", "m1": repr(m1f), "value": s(mp.ellipe(m))})
        for phi in [0.3, 1.0, 1.5, 1.5707963]:
            p = mp.mpf(phi)
            rows.append({"kind": "F", "m1": repr(m1f), "phi": repr(phi), "value": s(mp.ellipf(p, m))})
            rows.append({"kind": "Einc", "m1": repr(m1f), "phi": repr(phi), "value": s(mp.ellipe(p, m))})
            for n in [-1e6, -3.0, -0.01, 0.0, 0.5]:
                rows.append(
                    {
                        "kind": "Pi",
                        "m1": repr(m1f),
                        "phi": repr(phi),
                        "n": repr(n),
                        "value": s(mp.ellippi(mp.mpf(n), p, m)),
                    }
                )
    return rows


# ---------------------------------------------------------------------------
# The free body
# ---------------------------------------------------------------------------
def ode_case(name, moments, omega0, times):
    I = [mp.mpf(x) for x in moments]

    def f(t, y):
        w1, w2, w3, q0, q1, q2, q3 = y
        return [
            (I[1] - I[2]) * w2 * w3 / I[0],
            (I[2] - I[0]) * w3 * w1 / I[1],
            (I[0] - I[1]) * w1 * w2 / I[2],
            -(q1 * w1 + q2 * w2 + q3 * w3) / 2,
            (q0 * w1 + q2 * w3 - q3 * w2) / 2,
            (q0 * w2 - q1 * w3 + q3 * w1) / 2,
            (q0 * w3 + q1 * w2 - q2 * w1) / 2,
        ]

    with mp.workdps(30):
        sol = mp.odefun(f, 0, [mp.mpf(x) for x in omega0] + [1, 0, 0, 0])
        ys = [sol(mp.mpf(t)) for t in times]
    return {
        "name": name,
        "moments": [repr(float(x)) for x in moments],
        "omega0": [repr(float(x)) for x in omega0],
        "t": [repr(float(t)) for t in times],
        "omega": [[s(v, 25) for v in y[:3]] for y in ys],
        "attitude": [[s(v, 25) for v in y[3:]] for y in ys],
    }


class Closed:
    """Landau & Lifshitz section 37 in mpmath, in the user's axis order."""

    def __init__(self, moments, omega0):
        self.user = [mp.mpf(x) for x in moments]
        w = [mp.mpf(x) for x in omega0]
        order = sorted(range(3), key=lambda i: float(moments[i]))
        parity = 1 if order in ([0, 1, 2], [1, 2, 0], [2, 0, 1]) else -1
        self.order, self.sgn = order, [1, 1, parity]
        I = [self.user[order[k]] for k in range(3)]
        w = [self.sgn[k] * w[order[k]] for k in range(3)]
        self.I = I
        two_e = sum(I[i] * w[i] ** 2 for i in range(3))
        l2 = sum((I[i] * w[i]) ** 2 for i in range(3))
        D = [two_e * I[j] - l2 for j in range(3)]
        a, b, c = (0, 1, 2) if D[1] <= 0 else (2, 1, 0)
        self.abc = a, b, c
        self.A = [
            mp.sqrt(D[c] / (I[a] * (I[c] - I[a]))),
            mp.sqrt(D[c] / (I[b] * (I[c] - I[b]))),
            mp.sqrt(-D[a] / (I[c] * (I[c] - I[a]))),
        ]
        self.lam = mp.sqrt((I[c] - I[b]) * (-D[a]) / (I[0] * I[1] * I[2]))
        self.m = (I[b] - I[a]) * D[c] / ((I[c] - I[b]) * (-D[a]))
        self.m1 = (I[c] - I[a]) * (-D[b]) / ((I[c] - I[b]) * (-D[a]))
        self.sig = 1 if w[c] > 0 else -1
        cn0, sn0 = w[a] / self.A[0], self.sig * w[b] / self.A[1]
        self.u0 = mp.ellipf(mp.atan2(sn0, cn0), self.m)
        self.K = mp.ellipk(self.m)
        self.L = mp.sqrt(l2)
        self.Dc = D[c]
        self.w0 = w

    def omega_model(self, t):
        a, b, c = self.abc
        u = self.lam * t + self.u0
        sn, cn, dn = (mp.ellipfun(k, u, m=self.m) for k in ("sn", "cn", "dn"))
        out = [0, 0, 0]
        out[a] = self.A[0] * cn
        out[b] = self.sig * self.A[1] * sn
        out[c] = self.sig * self.A[2] * dn
        return out

    def to_user(self, v):
        out = [0, 0, 0]
        for k in range(3):
            out[self.order[k]] = self.sgn[k] * v[k]
        return out

    def omega(self, t):
        return self.to_user(self.omega_model(mp.mpf(t)))

    def psi(self, t):
        """Twist angle about L: quadrature of psi' over whole periods of dn plus the rest."""
        c = self.abc[2]
        Ic, L, q = self.I[c], self.L, self.I[c] * self.A[2]

        def rate(tt):
            dn = mp.ellipfun("dn", self.lam * tt + self.u0, m=self.m)
            return L / Ic + (self.Dc / Ic) / (L + q * dn)

        period = 2 * self.K / self.lam
        n = mp.floor(t / period)
        per = mp.quad(rate, mp.linspace(0, period, 9))
        rest = mp.quad(rate, [n * period, (n * period + t) / 2, t]) if t > n * period else 0
        return n * per + rest

    def attitude(self, t):
        t = mp.mpf(t)
        c = self.abc[2]
        z = [0, 0, 0]
        z[c] = self.sig

        def arc(w):
            lv = [self.I[k] * w[k] / self.L for k in range(3)]
            cr = [lv[1] * z[2] - lv[2] * z[1], lv[2] * z[0] - lv[0] * z[2], lv[0] * z[1] - lv[1] * z[0]]
            q = [1 + sum(lv[k] * z[k] for k in range(3))] + cr
            nrm = mp.sqrt(sum(x * x for x in q))
            return [x / nrm for x in q]

        def mul(p, q):
            return [
                p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
                p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
                p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
                p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
            ]

        s0 = arc(self.w0)
        s0c = [s0[0], -s0[1], -s0[2], -s0[3]]
        half = self.psi(t) / 2
        twist = [mp.cos(half)] + [mp.sin(half) * zk for zk in z]
        q = mul(s0c, mul(twist, arc(self.omega_model(t))))
        return [q[0]] + self.to_user(q[1:])


def closed_case(name, moments, omega0, times, attitude_times=(), flips=None):
    cl = Closed(moments, omega0)
    row = {
        "name": name,
        "moments": [repr(float(x)) for x in moments],
        "omega0": [repr(float(x)) for x in omega0],
        "m1": s(cl.m1),
        "period": s(4 * cl.K / cl.lam),
        "t": [repr(float(t)) for t in times],
        "omega": [[s(v, 25) for v in cl.omega(t)] for t in times],
        "attitude_t": [repr(float(t)) for t in attitude_times],
        "attitude": [[s(v, 25) for v in cl.attitude(t)] for t in attitude_times],
    }
    if flips:
        half = 2 * cl.K / cl.lam
        j0 = mp.ceil((flips[0] + cl.u0 / cl.lam) / half)
        ts = []
        j = j0
        while True:
            tj = j * half - cl.u0 / cl.lam
            if tj > flips[1]:
                break
            ts.append(s(tj, 25))
            j += 1
        row["flip_times"] = ts
        row["time_between_flips"] = s(half, 25)
    return row


def main():
    mp.mp.dps = DPS
    data = {"generator": f"tests/references/build_free_references.py (mpmath {mp.__version__}, {DPS:d} digits)"}
    data["elliptic"] = elliptic_cases()
    data["integrals"] = integral_cases()
    short = [0.5, 1.0, 2.5, 4.0, 7.0, 10.0]
    data["ode"] = [
        ode_case("generic", (1.0, 2.0, 3.0), (1.0, 0.1, 1.0), short),
        ode_case("minor-axis, permuted", (2.0, 3.0, 1.0), (1.0, 0.1, -1.0), short),
        ode_case("near separatrix", (1.0, 2.0, 3.0), (1e-6, 1.0, 1e-6), short),
        ode_case("symmetric", (2.0, 2.0, 3.0), (0.3, 0.1, 1.0), short),
        ode_case("nearly symmetric 1e-12", (1.0, 1.000000000001, 1.5), (0.1, 0.05, 1.0), short),
    ]
    mp.mp.dps = DPS
    gen = Closed((1.0, 2.0, 3.0), (1.0, 0.1, 1.0))
    period = float(4 * gen.K / gen.lam)
    long_t = [0.0, 13.7, period * 1000 + 1.3, period * 1e5 + 2.2, period * 1e6 + 0.7, period * 1e6 + 5.1]
    generic_t = [x * 10.0 for x in range(0, 101, 5)]
    day = 86400.0
    earth_t = [day * k for k in (0, 1, 100, 1000, 10000, 20000, 30000, 36000, 36525)]
    earth_moments = (8.01012e37, 8.01032e37, 8.03652e37)
    earth_omega = (7.292115e-11, 0.0, 7.292115e-05)
    sep_t = [x * 5.0 for x in range(0, 41)]
    data["closed"] = [
        closed_case(
            "generic 1000 s", (1.0, 2.0, 3.0), (1.0, 0.1, 1.0), generic_t, [100.0, 1000.0], flips=(0.0, 1000.0)
        ),
        closed_case("generic 1e6 periods", (1.0, 2.0, 3.0), (1.0, 0.1, 1.0), long_t, long_t[2:4]),
        # The attitude at every reference time (it was at 50 and 200 s only: an independent check found
        # 2e-14 rad between them, against the 6.3e-15 the two times showed).
        closed_case("separatrix 2e-12", (1.0, 2.0, 3.0), (1e-6, 1.0, 1e-6), sep_t, sep_t, flips=(0.0, 200.0)),
        closed_case("separatrix 5e-13", (1.0, 2.0, 3.0), (5e-7, 1.0, 5e-7), sep_t, [], flips=(0.0, 200.0)),
        closed_case("separatrix minor side", (1.0, 2.0, 3.0), (3e-6, -1.0, -1e-6), sep_t, [], flips=(0.0, 200.0)),
        closed_case("minor-axis permuted", (3.0, 1.0, 2.0), (-0.2, 1.3, 0.4), generic_t, [1000.0]),
        closed_case("nearly symmetric 1e-12", (1.0, 1.000000000001, 1.5), (0.1, 0.05, 1.0), generic_t, [1000.0]),
        closed_case("Earth 100 years", earth_moments, earth_omega, earth_t, [earth_t[-1]]),
    ]
    OUT.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {OUT}")


# ``--very-long``: times from just past 2^26 to 1.9 x 2^48 periods of omega (2^49.9 half-periods, the
# whole 2K steps of the phase reduction), at 60 digits and again at 80 (the two must agree to 1e-30).
OUT_VERY_LONG = OUT.with_name("free_rotation_very_long.json")
VERY_LONG_PERIODS = (2.0**26 + 0.37, 3.7e8 + 0.61, 1.1e11 + 0.2, 1.7 * 2.0**40, 1.9 * 2.0**48)
VERY_LONG_CASES = (
    ("generic", (1.0, 2.0, 3.0), (1.0, 0.1, 1.0)),
    ("minor-axis permuted", (3.0, 1.0, 2.0), (-0.2, 1.3, 0.4)),
    ("near separatrix 1e-3", (1.0, 2.0, 3.0), (1e-3, 1.0, 1e-3)),
)


def very_long_main():
    mp.mp.dps = 60
    data = {
        "generator": (
            f"tests/references/build_free_references.py --very-long (mpmath {mp.__version__}, 60 digits, checked at 80)"
        ),
        "closed": [],
    }
    for name, moments, omega0 in VERY_LONG_CASES:
        cl = Closed(moments, omega0)
        period = 4 * cl.K / cl.lam
        times = [float(period * f) for f in VERY_LONG_PERIODS]
        row = closed_case(name, moments, omega0, times, times)
        with mp.workdps(80):
            check = Closed(moments, omega0)
            for t, want in zip(times, row["attitude"]):
                got = check.attitude(t)
                assert all(abs(mp.mpf(w) - g) < mp.mpf(10) ** -24 for w, g in zip(want, got)), (name, t)
        row["periods"] = [repr(f) for f in VERY_LONG_PERIODS]
        data["closed"].append(row)
        print(f"{name}: done", flush=True)
    OUT_VERY_LONG.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {OUT_VERY_LONG}")


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--very-long"]:
        very_long_main()
    else:
        main()
