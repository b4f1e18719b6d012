"""The heavy-top cases of issue 8 and the SciPy baselines on the same equations.

Shared by scripts/bench_top.py and the work-precision harness. The top of issue 8:
I1 = 1 kg m2, I3 = 0.5 kg m2, M g l = 1 J, omega3 = 10 rad/s, theta0 = 60 deg,
released with phidot0 = +0.3 rad/s (undulating), 0 (cusps), -0.3 rad/s (loops); and a
nearly sleeping top, theta0 = 1e-4 rad. References: tests/references/heavy_top.json
(mpmath, independent of wobble).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from wobble.models.top_ode import top_rhs, vertical_in_body
from wobble.numerics import quaternion as Q

I1, I3, MGL, OMEGA3 = 1.0, 0.5, 1.0, 10.0
RTOL = 1e-12
CASES = [
    ("cusps", "issue8 cusps", dict(theta0=np.pi / 3, phidot0=0.0)),
    ("undulating", "issue8 undulating", dict(theta0=np.pi / 3, phidot0=0.3)),
    ("loops", "issue8 loops", dict(theta0=np.pi / 3, phidot0=-0.3)),
    ("nearly sleeping (theta0 = 1e-4 rad)", "nearly sleeping 1e-4", dict(theta0=1e-4, phidot0=0.0)),
]


def quat_from_euler(phi, theta, psi):
    ch, sh = np.cos(theta / 2), np.sin(theta / 2)
    return np.stack([ch * np.cos((phi + psi) / 2), sh * np.cos((phi - psi) / 2),
                     sh * np.sin((phi - psi) / 2), ch * np.sin((phi + psi) / 2)], axis=-1)


def angle_between(q1, q2):
    d = Q.multiply(q1, Q.conjugate(q2))
    return 2 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def euler_rhs(mdl):
    """The notes' equations (section 5.7): phidot, psidot from the conserved momenta and
    I1 thetaddot = I1 phidot^2 sin cos - I3 omega3 phidot sin + M g l sin."""
    a, b, beta, w3 = mdl.a, mdl.b, mdl.beta, mdl.omega3

    def f(t, y):
        th, thd = y[0], y[1]
        s, c = np.sin(th), np.cos(th)
        phd = (b - a * c) / (s * s)
        return [thd, phd * phd * s * c - a * phd * s + 0.5 * beta * s, phd, w3 - phd * c]

    return f


def turning_event(kind):
    if kind == "euler":
        def ev(t, y):
            return y[1]
    else:
        def ev(t, y):  # d(gamma3)/dt = d(cos theta)/dt = omega x gamma, third component
            w1, w2 = y[0], y[1]
            g = vertical_in_body(y[3:])
            return w1 * g[1] - w2 * g[0]
    return ev


def run_dop853(mdl, t, kind, rtol=RTOL, method="DOP853", extra_t=None, events=True):
    t_eval = t if extra_t is None else np.union1d(t, extra_t)
    ev = turning_event(kind) if events else None
    if kind == "euler":
        y0 = [mdl.theta0, mdl.thetadot0, mdl.phi0, mdl.psi0]
        scale = np.array([1.0, max(abs(mdl.a), 1.0), 1.0, 1.0])
        sol = solve_ivp(euler_rhs(mdl), (0, t_eval[-1]), y0, method=method, t_eval=t_eval, rtol=rtol, atol=rtol * scale,
                        events=ev)
        th, ph, ps = sol.y[0], sol.y[2], sol.y[3]
        q = quat_from_euler(ph, th, ps)
        turning = sol.y_events[0][:, 0] if events else None
    else:
        w, q0 = mdl.evaluate(np.zeros(1), "direct")
        y0 = np.concatenate([w[0], q0[0]])
        scale = np.array([np.linalg.norm(w[0])] * 3 + [1.0] * 4)
        sol = solve_ivp(top_rhs(mdl.I1, mdl.I3, mdl.mgl), (0, t_eval[-1]), y0, method=method, t_eval=t_eval, rtol=rtol,
                        atol=rtol * scale, events=ev)
        q = sol.y[3:].T / np.linalg.norm(sol.y[3:].T, axis=1, keepdims=True)
        g = vertical_in_body(q)
        th = np.arctan2(np.hypot(g[:, 0], g[:, 1]), g[:, 2])
        turning = None
        if events:
            ge = vertical_in_body(sol.y_events[0][:, 3:])
            turning = np.arctan2(np.hypot(ge[:, 0], ge[:, 1]), ge[:, 2])
    return sol.t, th, q, turning


def turning_error(turning, ref):
    """Largest relative error of the integrator's turning angles against the mpmath ones."""
    lo, hi = float(ref["theta_min"]), float(ref["theta_max"])
    near = np.where(np.abs(turning - lo) < np.abs(turning - hi), lo, hi)
    return float(np.max(np.abs(turning - near) / near))
