"""Build tests/references/engine_chaotic.json: a chaotic heavy body integrated by mpmath at 30 digits.

Independent of wobble: Euler's equations with the gravity torque and the quaternion
kinematics are those of ``build_engine_references.py`` (written out there, sharing no code
with the engine), integrated with ``mpmath.odefun`` (a Taylor-series method with error
control at the working precision).

The case: principal moments (1, 2, 3) kg m^2 about a fixed pivot, 2 kg with its centre of
mass at (0.1, 0.05, 0.2) m in the body frame, standard gravity (9.80665 m/s^2) along the
inertial -z axis; omega0 = (0.3, 0.8, 1.2) rad/s, attitude the identity; outputs at every
second from 1 to 50 s. Its motion is chaotic: a change of 1e-12 in the start grows about
10^5-fold (omega) and 10^6-fold (attitude) in 50 s, so the float64 rounding of a long run is
amplified into its error.

Run: ``python tests/references/build_engine_chaotic_reference.py`` (about 3 minutes; with
``--check`` it is run again at a tighter tolerance and a higher degree, about 7 minutes, and
the two must agree to 20 digits).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import mpmath as mp
from build_engine_references import cross, rhs_factory, to_body

mp.mp.dps = 30
OUT = Path(__file__).with_name("engine_chaotic.json")


def solve(tol_digits, degree):
    moments = [mp.mpf(1), mp.mpf(2), mp.mpf(3)]
    r = [mp.mpf("0.1"), mp.mpf("0.05"), mp.mpf("0.2")]
    weight = [mp.mpf(0), mp.mpf(0), -2 * mp.mpf("9.80665")]  # M g in the inertial frame

    def torque(t, q):
        return cross(r, to_body(q, weight))

    w0 = [mp.mpf("0.3"), mp.mpf("0.8"), mp.mpf("1.2")]
    q0 = [mp.mpf(1), mp.mpf(0), mp.mpf(0), mp.mpf(0)]
    f = mp.odefun(rhs_factory(moments, torque), 0, w0 + q0, tol=mp.mpf(10) ** -tol_digits, degree=degree)
    return [f(mp.mpf(k)) for k in range(1, 51)]


def main():
    rows = solve(25, 20)
    if "--check" in sys.argv:
        tight = solve(28, 30)
        worst = max(abs(a - b) for ra, rb in zip(rows, tight) for a, b in zip(ra, rb))
        print(f"largest difference from the tighter run: {mp.nstr(worst, 3)}")
        assert worst < mp.mpf(10) ** -20
    case = {
        "name": "chaotic heavy body",
        "moments": ["1", "2", "3"],
        "center_of_mass": ["0.1", "0.05", "0.2"],
        "mass": "2",
        "gravity": ["0", "0", "-9.80665"],
        "omega0": ["0.3", "0.8", "1.2"],
        "attitude0": ["1", "0", "0", "0"],
        "t": [str(k) for k in range(1, 51)],
        "omega": [[mp.nstr(v, 25) for v in row[:3]] for row in rows],
        "attitude": [[mp.nstr(v, 25) for v in row[3:]] for row in rows],
    }
    OUT.write_text(
        json.dumps(
            {"generator": "tests/references/build_engine_chaotic_reference.py", "mpmath_dps": 30, "cases": [case]},
            indent=1,
        )
        + "\n"
    )


if __name__ == "__main__":
    main()
