"""Build tests/references/engine_torqued.json: torqued rigid bodies integrated by mpmath at 30 digits.

Independent of wobble: Euler's equations with the torque and the quaternion
kinematics written out here again and integrated with ``mpmath.odefun``
(a Taylor-series method with error control at the working precision), so the
reference has no code in common with the engine it checks.

Cases (no exact solution):

* ``asymmetric top``: I = (1, 1.5, 2) kg m^2 about a pivot, centre of mass at
  (0.1, 0.05, 0.5) m in the body frame, M = 1 kg, g = 9.81 m/s^2 along -z;
  omega0 = (0.5, -0.3, 8) rad/s, attitude tilted 0.5 rad about inertial x.
* ``gravity gradient orbit``: I = (0.9, 1.1, 1.4) kg m^2 in the field of a
  point mass on a circular orbit (GM / d^3 = 0.04 s^-2, mean motion 0.2 rad/s
  about inertial z, phase 0.3 rad), omega0 = (0.1, 0.2, 1.5) rad/s, attitude
  (cos 0.2, sin 0.2 / sqrt 2, 0, sin 0.2 / sqrt 2): a fast time-dependent torque.

Run: ``python tests/references/build_engine_references.py`` (a few minutes).
"""

from __future__ import annotations

import json
from pathlib import Path

import mpmath as mp

mp.mp.dps = 30
OUT = Path(__file__).with_name("engine_torqued.json")


def qmul(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return [
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ]


def to_body(q, v):
    """R(q)^T v by the matrix of q."""
    w, x, y, z = q
    n2 = w * w + x * x + y * y + z * z
    w, x, y, z = (c / mp.sqrt(n2) for c in q)
    r = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    return [sum(r[j][i] * v[j] for j in range(3)) for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rhs_factory(moments, torque):
    def rhs(t, y):
        w = y[:3]
        q = y[3:]
        tau = torque(t, q)
        L = [moments[i] * w[i] for i in range(3)]
        g = cross(L, w)
        dw = [(tau[i] + g[i]) / moments[i] for i in range(3)]
        dq = [c / 2 for c in qmul(q, [0, w[0], w[1], w[2]])]
        return dw + dq

    return rhs


def case_top():
    moments = [mp.mpf(1), mp.mpf("1.5"), mp.mpf(2)]
    r = [mp.mpf("0.1"), mp.mpf("0.05"), mp.mpf("0.5")]
    mg = [mp.mpf(0), mp.mpf(0), -mp.mpf("9.81")]

    def torque(t, q):
        return cross(r, to_body(q, mg))

    w0 = [mp.mpf("0.5"), mp.mpf("-0.3"), mp.mpf(8)]
    q0 = [mp.cos(mp.mpf("0.25")), mp.sin(mp.mpf("0.25")), mp.mpf(0), mp.mpf(0)]
    return {
        "name": "asymmetric top",
        "moments": ["1", "1.5", "2"],
        "center_of_mass": ["0.1", "0.05", "0.5"],
        "mass": "1",
        "gravity": ["0", "0", "-9.81"],
        "omega0": [str(x) for x in w0],
        "attitude0": [mp.nstr(x, 30) for x in q0],
        "rhs": rhs_factory(moments, torque),
        "y0": w0 + q0,
    }


def case_gradient():
    moments = [mp.mpf("0.9"), mp.mpf("1.1"), mp.mpf("1.4")]
    k = 3 * mp.mpf("0.04")
    n = mp.mpf("0.2")
    phase = mp.mpf("0.3")

    def torque(t, q):
        rho = [mp.cos(n * t + phase), mp.sin(n * t + phase), mp.mpf(0)]
        rb = to_body(q, rho)
        irb = [moments[i] * rb[i] for i in range(3)]
        return [k * c for c in cross(rb, irb)]

    w0 = [mp.mpf("0.1"), mp.mpf("0.2"), mp.mpf("1.5")]
    s = mp.sin(mp.mpf("0.2")) / mp.sqrt(2)
    q0 = [mp.cos(mp.mpf("0.2")), s, mp.mpf(0), s]
    return {
        "name": "gravity gradient orbit",
        "moments": ["0.9", "1.1", "1.4"],
        "gm_over_d3": "0.04",
        "mean_motion": "0.2",
        "phase": "0.3",
        "omega0": [str(x) for x in w0],
        "attitude0": [mp.nstr(x, 30) for x in q0],
        "rhs": rhs_factory(moments, torque),
        "y0": w0 + q0,
    }


def main():
    times = [mp.mpf(x) for x in ("0.5", "1", "2", "3", "4", "5")]
    cases = []
    for case in (case_top(), case_gradient()):
        f = mp.odefun(case.pop("rhs"), 0, case.pop("y0"), tol=mp.mpf(10) ** -28, degree=30)
        rows = [f(t) for t in times]
        case["t"] = [str(t) for t in times]
        case["omega"] = [[mp.nstr(v, 25) for v in row[:3]] for row in rows]
        case["attitude"] = [[mp.nstr(v, 25) for v in row[3:]] for row in rows]
        cases.append(case)
        print(case["name"], "done")
    OUT.write_text(
        json.dumps(
            {"generator": "tests/references/build_engine_references.py", "mpmath_dps": 30, "cases": cases}, indent=1
        )
        + "\n"
    )


if __name__ == "__main__":
    main()
