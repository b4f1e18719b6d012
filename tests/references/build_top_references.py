"""Regenerate tests/references/heavy_top.json with mpmath only (no wobble, no numpy).

Usage::

    python tests/references/build_top_references.py      # a few minutes

Inputs are float64 values (moments, M g l, theta0, rates), taken *exactly* as
``mpmath.mpf(float)``, so the tests measure wobble's algorithm and not the rounding
of its inputs. Everything follows the course notes, section 5.7 (z-x-z Euler
angles, omega_j(phi, theta, psi) of p. 70, f(u) of p. 71), at 60 digits:

* ``analysis``: a, b, alpha, beta, E, E', p_phi, p_psi; the roots of the cubic
  f(u) = beta u^3 - (alpha + a^2) u^2 + (2ab - beta) u + (alpha - b^2) by
  ``mpmath.polyroots`` (60 digits, extra precision) polished with ``findroot`` in
  x = 1 - u; the turning angles; the nutation period T = 2 int_{u1}^{u2} du/sqrt(f)
  and the advances of phi and psi over one period by ``mpmath.quad`` (with
  u = u1 + (u2 - u1) sin^2 s, which removes the endpoint singularities; no elliptic
  function enters), checked against 4 K(m)/sqrt(beta (u3 - u1)) with ``mpmath.ellipk``;
  the steady-precession rates from f = df/du = 0; sleeping-top stability.
* ``ode``: the top as omega (body) and a unit quaternion (body -> space), Euler's
  equations with the gravity torque and q' = q (0, omega)/2, integrated by
  ``mpmath.odefun`` (Taylor series, 30 digits) over a few nutation periods: no
  Euler angle and no elliptic function enters, and it is regular at theta = 0.
* ``long``: over 1000 nutation periods, where a Taylor integration would take
  hours: u(t) = u1 + (u2 - u1) sn^2(lambda t + w0 | m) with ``mpmath.ellipfun``
  (its conventions checked here against the ODE on the short span), phi(t) and
  psi(t) by ``mpmath.quad`` of the notes' phidot(u), psidot(u) over whole periods
  (counted) plus the remainder, and the quaternion from (phi, theta, psi).

``python tests/references/build_top_references.py --very-long`` writes
tests/references/heavy_top_very_long.json instead (under a minute): the same closed form at
times from 2^26 to 2^49.9 nutation periods, for a few cases, at 60 digits and again at 80 (the
two must agree to 1e-30 rad, or the script stops): the reach of the model's secular phases.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import mpmath as mp

OUT = Path(__file__).with_name("heavy_top.json")
OUT_VERY_LONG = Path(__file__).with_name("heavy_top_very_long.json")
DPS = 60


def s(x, digits=34):
    return mp.nstr(mp.mpf(x), digits, strip_zeros=False)


# ---------------------------------------------------------------------------
# Cases: float inputs (I1, I3, M g l about the tip; theta0, rates).
# ---------------------------------------------------------------------------
DEG60 = math.pi / 3


def _slow_fast(I1, I3, mgl, omega3, theta):
    with mp.workdps(DPS):
        I1, I3, mgl, w3, th = (mp.mpf(v) for v in (I1, I3, mgl, omega3, theta))
        c = mp.cos(th)
        disc = (I3 * w3) ** 2 - 4 * I1 * mgl * c
        r1 = (I3 * w3 + mp.sqrt(disc)) / (2 * I1 * c)
        r2 = (I3 * w3 - mp.sqrt(disc)) / (2 * I1 * c)
        return sorted([r1, r2], key=abs)


_slow, _fast = _slow_fast(1.0, 0.5, 1.0, 10.0, DEG60)

CASES = [
    # name, I1, I3, mgl, theta0, thetadot0, phidot0, omega3, phi0, psi0, long span?
    ("benchmark cusps", 1.0, 0.5, 1.0, DEG60, 0.0, 0.0, 10.0, 0.0, 0.0, True),
    ("benchmark undulating", 1.0, 0.5, 1.0, DEG60, 0.0, 0.3, 10.0, 0.0, 0.0, True),
    ("benchmark loops", 1.0, 0.5, 1.0, DEG60, 0.0, -0.3, 10.0, 0.0, 0.0, True),
    ("generic offsets", 1.0, 0.5, 1.0, DEG60, 0.1, 0.2, 10.0, 1.0, 0.3, True),
    ("nearly sleeping 1e-6", 1.0, 0.5, 1.0, 1e-6, 0.0, 0.0, 10.0, 0.0, 0.0, True),
    ("nearly sleeping 1e-4", 1.0, 0.5, 1.0, 1e-4, 0.0, 0.0, 10.0, 0.0, 0.0, True),
    ("near vertical moving", 1.0, 0.5, 1.0, 1e-6, 2e-6, 3.0, 10.0, 0.0, 0.0, True),
    ("sleeping stable", 1.0, 0.5, 1.0, 0.0, 0.0, 0.0, 10.0, 0.0, 0.0, False),
    ("sleeping unstable", 1.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, False),
    ("through the vertical", 1.0, 0.5, 1.0, 0.0, 0.5, 0.0, 10.0, 0.0, 0.0, False),
    ("regular slow", 1.0, 0.5, 1.0, DEG60, 0.0, float(_slow), 10.0, 0.0, 0.0, True),
    ("regular fast", 1.0, 0.5, 1.0, DEG60, 0.0, float(_fast), 10.0, 0.0, 0.0, True),
    ("near separatrix 1e-4", 1.0, 0.5, 1.0, 1e-4, 0.0, 0.0, 1.0, 0.0, 0.0, True),
    ("near separatrix 1e-7", 1.0, 0.5, 1.0, 1e-7, 0.0, 0.0, 1.0, 0.0, 0.0, True),
    ("fast spin 1e4", 1.0, 0.5, 1.0, DEG60, 0.0, 0.015, 141.4, 0.0, 0.0, True),
    ("slow spin below threshold", 1.0, 0.5, 1.0, math.pi / 6, 0.5, 0.2, 1.5, 0.0, 0.0, True),
    ("hanging", 1.0, 0.5, 1.0, 2.5, -0.2, 0.7, 3.0, 0.0, 0.0, True),
    ("nearly free", 1.0, 0.5, 1e-12, DEG60, 0.0, 0.3, 10.0, 0.0, 0.0, True),
    ("tall top", 2.0, 0.3, 5.0, 0.4, -0.3, 1.2, 25.0, 0.5, -1.0, True),
]


class Top:
    """The notes' analysis of one case, at DPS digits."""

    def __init__(self, name, I1, I3, mgl, theta0, thetadot0, phidot0, omega3, phi0, psi0):
        self.name = name
        self.inputs = dict(
            I1=I1,
            I3=I3,
            mgl=mgl,
            theta0=theta0,
            thetadot0=thetadot0,
            phidot0=phidot0,
            omega3=omega3,
            phi0=phi0,
            psi0=psi0,
        )
        I1, I3, mgl = mp.mpf(I1), mp.mpf(I3), mp.mpf(mgl)
        th, thd, phd, w3 = mp.mpf(theta0), mp.mpf(thetadot0), mp.mpf(phidot0), mp.mpf(omega3)
        self.I1, self.I3, self.mgl = I1, I3, mgl
        self.th0, self.thd0, self.phd0, self.w3 = th, thd, phd, w3
        self.phi0, self.psi0 = mp.mpf(phi0), mp.mpf(psi0)
        s0, u0 = mp.sin(th), mp.cos(th)
        self.u0 = u0
        self.psd0 = w3 - phd * u0
        self.a = I3 * w3 / I1
        self.b = phd * s0**2 + self.a * u0
        self.beta = 2 * mgl / I1
        self.alpha = thd**2 + phd**2 * s0**2 + self.beta * u0
        self.E = I1 / 2 * (thd**2 + phd**2 * s0**2) + I3 / 2 * w3**2 + mgl * u0
        self.Ep = self.E - I3 / 2 * w3**2
        self.p_psi = I3 * w3
        self.p_phi = I1 * self.b

    def f(self, u):
        return (1 - u * u) * (self.alpha - self.beta * u) - (self.b - self.a * u) ** 2

    def roots(self):
        a, b, al, be = self.a, self.b, self.alpha, self.beta
        if self.th0 == 0 and self.thd0 == 0:  # sleeping: f = beta x^2 (c2/beta - x), x = 1 - u
            c2 = 2 * be - al + be - a * a  # 2 beta - (alpha - beta) - a^2 with alpha = beta
            xs = sorted([mp.mpf(0), mp.mpf(0), c2 / be], reverse=True)
            return xs
        coeffs = [be, -(al + a * a), 2 * a * b - be, al - b * b]
        rts = mp.polyroots(coeffs, maxsteps=400, extraprec=4 * DPS)
        rts = sorted(mp.re(r) for r in rts)

        def gx(x):
            return self.f(1 - x)

        xs = []
        for r in rts:
            x = 1 - r
            if x != 0 and abs(x) > mp.mpf(10) ** (-DPS + 5):
                try:
                    x = mp.findroot(gx, x, tol=mp.mpf(10) ** (-2 * DPS + 10))
                except (ValueError, ZeroDivisionError):
                    pass
            xs.append(x)
        xs = sorted(xs, reverse=True)  # x1 >= x2 >= x3 (u1 <= u2 <= u3)
        return xs

    def sample_u(self, s_, x1, x2):
        return 1 - (x1 - (x1 - x2) * mp.sin(s_) ** 2)


def analysis(top: Top):
    out = {}
    x1, x2, x3 = top.roots()
    u1, u2, u3 = 1 - x1, 1 - x2, 1 - x3
    sleeping = top.th0 == 0 and top.thd0 == 0
    out.update(
        a=s(top.a),
        b=s(top.b),
        alpha=s(top.alpha),
        beta=s(top.beta),
        energy=s(top.E),
        energy_prime=s(top.Ep),
        p_phi=s(top.p_phi),
        p_psi=s(top.p_psi),
        psidot0=s(top.psd0),
        u1=s(u1),
        u2=s(u2),
        u3=s(u3),
        x1=s(x1),
        x2=s(x2),
        x3=s(x3),
        theta_max=s(0 if sleeping else 2 * mp.asin(mp.sqrt(x1 / 2))),
        theta_min=s(0 if sleeping else 2 * mp.asin(mp.sqrt(max(x2, 0) / 2))),
        sleeping_stable=bool(top.I3**2 * top.w3**2 > 4 * top.mgl * top.I1),
        f_at_u0=s(top.f(top.u0)),
    )
    try:
        slow, fast = _slow_fast(*(float(v) for v in (top.I1, top.I3, top.mgl, top.w3, top.th0)))
        out.update(regular_slow=s(slow), regular_fast=s(fast))
    except (ValueError, ZeroDivisionError, TypeError):
        pass
    if not sleeping and x1 - x2 > mp.mpf(10) ** (-DPS + 20) * max(x1, mp.mpf(10) ** -300) and x2 - x3 > 0:
        m = (x1 - x2) / (x1 - x3)
        m1 = (x2 - x3) / (x1 - x3)
        out.update(m=s(m), m1=s(m1))
        # Period and advances by quadrature in s (u = u1 + (u2 - u1) sin^2 s).
        be = top.beta

        def w(s_):
            x = x1 - (x1 - x2) * mp.sin(s_) ** 2
            return 1 / mp.sqrt(be * (x - x3))

        big_b = top.b - top.a  # b - a u = (b - a) + a x, no cancellation next to u = 1

        def phidot(s_):
            x = x1 - (x1 - x2) * mp.sin(s_) ** 2
            if big_b == 0:  # through the vertical: (b - a u)/(1 - u^2) = a/(1 + u)
                return top.a / (2 - x)
            return (big_b + top.a * x) / (x * (2 - x))

        def psidot(s_):
            x = x1 - (x1 - x2) * mp.sin(s_) ** 2
            return top.I1 * top.a / top.I3 - (1 - x) * phidot(s_)

        # Points cluster at s = pi/2 (u = u2), where phidot peaks for a top near the vertical.
        pts = [mp.mpf(0)] + [mp.pi / 2 * (1 - mp.mpf(2) ** -k) for k in range(1, 60)] + [mp.pi / 2]
        period = 4 * mp.quad(w, pts)
        dphi = 4 * mp.quad(lambda q: phidot(q) * w(q), pts)
        dpsi = 4 * mp.quad(lambda q: psidot(q) * w(q), pts)
        period_k = 4 * mp.ellipk(m) / mp.sqrt(be * (x1 - x3))
        assert abs(period / period_k - 1) < mp.mpf(10) ** -30, (top.name, period, period_k)
        out.update(
            period=s(period),
            mean_precession_rate=s(dphi / period),
            mean_spin_rate=s(dpsi / period),
            dphi_per_period=s(dphi),
            dpsi_per_period=s(dpsi),
        )
    return out, (x1, x2, x3)


# ---------------------------------------------------------------------------
# Quaternions and the ODE
# ---------------------------------------------------------------------------
def quat_from_euler(phi, theta, psi):
    ch, sh = mp.cos(theta / 2), mp.sin(theta / 2)
    return [
        ch * mp.cos((phi + psi) / 2),
        sh * mp.cos((phi - psi) / 2),
        sh * mp.sin((phi - psi) / 2),
        ch * mp.sin((phi + psi) / 2),
    ]


def omega_from_euler(theta, psi, thd, phd, psd):
    return [
        phd * mp.sin(theta) * mp.sin(psi) + thd * mp.cos(psi),
        phd * mp.sin(theta) * mp.cos(psi) - thd * mp.sin(psi),
        phd * mp.cos(theta) + psd,
    ]


def ode_case(top: Top, times):
    I1, I3, mgl = top.I1, top.I3, top.mgl

    def rhs(t, y):
        w1, w2, w3, q0, q1, q2, q3 = y
        g1 = 2 * (q1 * q3 - q0 * q2)
        g2 = 2 * (q2 * q3 + q0 * q1)
        return [
            ((I1 - I3) * w2 * w3 + mgl * g2) / I1,
            ((I3 - I1) * w3 * w1 - mgl * g1) / I1,
            mp.mpf(0),
            -(q1 * w1 + q2 * w2 + q3 * w3) / 2,
            (q0 * w1 + q2 * w3 - q3 * w2) / 2,
            (q0 * w2 - q1 * w3 + q3 * w1) / 2,
            (q0 * w3 + q1 * w2 - q2 * w1) / 2,
        ]

    with mp.workdps(30):
        q0 = quat_from_euler(top.phi0, top.th0, top.psi0)
        w0 = omega_from_euler(top.th0, top.psi0, top.thd0, top.phd0, top.psd0)
        sol = mp.odefun(rhs, 0, w0 + q0)
        ys = [sol(mp.mpf(t)) for t in times]
    return {
        "t": [repr(float(t)) for t in times],
        "omega0": [s(v, 25) for v in w0],
        "q0": [s(v, 25) for v in q0],
        "omega": [[s(v, 25) for v in y[:3]] for y in ys],
        "quaternion": [[s(v, 25) for v in y[3:]] for y in ys],
        "theta": [s(2 * mp.atan2(mp.sqrt(y[4] ** 2 + y[5] ** 2), mp.sqrt(y[3] ** 2 + y[6] ** 2)), 25) for y in ys],
    }


# ---------------------------------------------------------------------------
# The closed form over long spans (notes' formulas, mpmath functions)
# ---------------------------------------------------------------------------
class Closed:
    def __init__(self, top: Top, xs):
        x1, x2, x3 = xs
        self.top, self.x1, self.x2, self.x3 = top, x1, x2, x3
        be = top.beta
        self.m = (x1 - x2) / (x1 - x3)
        self.lam = mp.sqrt(be * (x1 - x3)) / 2
        self.K = mp.ellipk(self.m)
        x0 = 1 - top.u0
        sn0 = mp.sqrt((x1 - x0) / (x1 - x2))
        sn0 = min(sn0, mp.mpf(1))
        w0 = mp.ellipf(mp.asin(sn0), self.m)
        self.w0 = -w0 if top.thd0 > 0 else w0

    def x_of_w(self, w):
        sn = mp.ellipfun("sn", w, m=self.m)
        return self.x1 - (self.x1 - self.x2) * sn**2

    def rates(self, w):
        x = self.x_of_w(w)
        top = self.top
        big_b = top.b - top.a
        phd = top.a / (2 - x) if big_b == 0 else (big_b + top.a * x) / (x * (2 - x))
        return phd, top.I1 * top.a / top.I3 - (1 - x) * phd

    def integral(self, w_a, w_b, which):
        k = self.K
        pts = [w_a]
        j = mp.ceil(w_a / k)
        while j * k < w_b:
            if j * k > w_a:
                pts.append(j * k)
            j += 1
        pts.append(w_b)
        return mp.quad(lambda w: self.rates(w)[which], pts)

    def state(self, times):
        top = self.top
        full = [self.integral(-self.K, self.K, i) for i in (0, 1)]
        out = []
        for t in times:
            t = mp.mpf(t)
            w = self.lam * t + self.w0
            n = mp.floor((w - self.w0) / (2 * self.K))
            w_rem = w - 2 * self.K * n
            ang = [n * full[i] + self.integral(self.w0, w_rem, i) for i in (0, 1)]
            phi = top.phi0 + ang[0] / self.lam
            psi = top.psi0 + ang[1] / self.lam
            x = self.x_of_w(w)
            theta = 2 * mp.asin(mp.sqrt(x / 2))
            out.append((theta, phi, psi))
        return out


def long_case(top: Top, xs, an, times):
    cl = Closed(top, xs)
    states = cl.state(times)
    return {
        "t": [repr(float(t)) for t in times],
        "theta": [s(th, 25) for th, _, _ in states],
        "phi": [s(ph, 30) for _, ph, _ in states],
        "psi": [s(ps, 30) for _, _, ps in states],
        "quaternion": [[s(v, 25) for v in quat_from_euler(ph, th, ps)] for th, ph, ps in states],
    }


def check_closed_against_ode(top: Top, xs, ode):
    """The closed form's conventions (w0 sign, phi/psi integrals) agree with the ODE."""
    cl = Closed(top, xs)
    times = [mp.mpf(t) for t in ode["t"]]
    for (th, ph, ps), q_ode in zip(cl.state(times), ode["quaternion"]):
        q = quat_from_euler(ph, th, ps)
        q_ode = [mp.mpf(v) for v in q_ode]
        dot = abs(sum(a * b for a, b in zip(q, q_ode)))
        assert abs(dot - 1) < mp.mpf(10) ** -20, (top.name, dot)


def main():
    mp.mp.dps = DPS
    data = {
        "generator": f"tests/references/build_top_references.py (mpmath {mp.__version__}, {DPS} digits)",
        "cases": [],
    }
    for name, I1, I3, mgl, th, thd, phd, w3, phi0, psi0, long_span in CASES:
        top = Top(name, I1, I3, mgl, th, thd, phd, w3, phi0, psi0)
        an, xs = analysis(top)
        case = {"name": name, "inputs": {k: repr(float(v)) for k, v in top.inputs.items()}, "analysis": an}
        if "period" in an:
            period = mp.mpf(an["period"])
        else:  # sleeping or regular: the period of small nutations about it
            period = 2 * mp.pi / mp.sqrt(abs(top.a**2 - 2 * top.beta * top.u0) if top.a**2 != 2 * top.beta else 1)
        short = [float(period * f) for f in (0.1, 0.37, 0.5, 0.93, 1.0, 1.61, 2.2, 2.99)]
        if name not in ("sleeping unstable",):
            case["ode"] = ode_case(top, short)
        if long_span and "m" in an:
            check_closed_against_ode(top, xs, case["ode"])
            long_t = [float(period * f) for f in (0.37, 1.9, 10.3, 99.7, 500.1, 999.6, 1000.25)]
            case["long"] = long_case(top, xs, an, long_t)
        data["cases"].append(case)
        print(f"{name}: done", flush=True)
    OUT.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {OUT}")


# Times in nutation periods from just past 2^26 (where the secular phases' three-piece products stop
# being exact) to 2^49.9; each time is the float64 nearest to the period times the factor.
VERY_LONG_PERIODS = (2.0**26 + 0.37, 3.7e8 + 0.61, 1.1e11 + 0.2, 1.7 * 2.0**40, 1.9 * 2.0**49)
VERY_LONG_CASES = ("benchmark cusps", "benchmark loops", "generic offsets", "fast spin 1e4", "tall top")


def wrapped(x):
    """x modulo 2 pi, in (-pi, pi]."""
    return x - 2 * mp.pi * mp.ceil((x - mp.pi) / (2 * mp.pi))


def very_long_main():
    data = {
        "generator": (
            f"tests/references/build_top_references.py --very-long (mpmath {mp.__version__}, {DPS} digits,"
            " checked at 80)"
        ),
        "cases": [],
    }
    for name, I1, I3, mgl, th, thd, phd, w3, phi0, psi0, _ in CASES:
        if name not in VERY_LONG_CASES:
            continue
        top = Top(name, I1, I3, mgl, th, thd, phd, w3, phi0, psi0)
        an, xs = analysis(top)
        times = [float(mp.mpf(an["period"]) * f) for f in VERY_LONG_PERIODS]
        states = Closed(top, xs).state(times)
        # The same numbers (inputs and roots) evaluated at 80 digits: the quadratures and the count of
        # whole periods (up to 1e15 of them) keep 30 digits of the phases at 60.
        with mp.workdps(80):
            check = Closed(top, xs).state(times)
        for a, b in zip(states, check):
            assert all(abs(x - y) < mp.mpf(10) ** -30 for x, y in zip(a, b)), (name, a, b)
        data["cases"].append(
            {
                "name": name,
                "inputs": {k: repr(float(v)) for k, v in top.inputs.items()},
                "period": an["period"],
                "periods": [repr(f) for f in VERY_LONG_PERIODS],
                "t": [repr(t) for t in times],
                "theta": [s(th, 25) for th, _, _ in states],
                # phi and psi reach 1e16 rad: given modulo 2 pi, in (-pi, pi], so that 30 digits stay 30 decimals.
                "phi": [s(wrapped(ph), 30) for _, ph, _ in states],
                "psi": [s(wrapped(ps), 30) for _, _, ps in states],
                "quaternion": [[s(v, 25) for v in quat_from_euler(ph, th, ps)] for th, ph, ps in states],
            }
        )
        print(f"{name}: done", flush=True)
    OUT_VERY_LONG.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {OUT_VERY_LONG}")


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--very-long"]:
        mp.mp.dps = DPS
        very_long_main()
    else:
        main()
