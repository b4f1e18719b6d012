"""Compile (or load) wobble's Numba kernels once, in a process of their own (tests/conftest.py).

On a fresh checkout Numba's disk cache is empty, and every test process that reaches a compiled
kernel before the cache is written compiles it again: about 30 s for the compiled DOP853 and the heavy
top's Taylor tables on 2 cores, in both pytest-xdist workers at once (and in the processes some tests
start). Started by the controlling process while the workers collect, this run writes the cache
first; a warm checkout only loads it (about a second). Not a test: nothing here is checked.
"""

from __future__ import annotations

import astropy.units as u
import numpy as np

import wobble


def main() -> None:
    kgm2, rad_s = u.kg * u.m**2, u.rad / u.s
    scene = wobble.Scene(
        body=[1.0, 1.0, 0.5] * kgm2,
        omega0=[0.3, 0.2, 10.0] * rad_s,
        torques=[wobble.Torque.gravity(1 * u.kg, [0, 0, 0.1] * u.m, g=9.80665 * u.m / u.s**2)],
        t_end=1 * u.s,
        samples=11,
        accuracy=1e-8,
        outputs=["omega", "attitude"],
    )
    wobble.run(scene, model="dop853")  # the compiled DOP853
    top = wobble.HeavyTop(I1=1 * kgm2, I3=0.5 * kgm2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * rad_s)
    top.to_dataset(t=np.linspace(0.0, 100.0, 20000) * u.s)  # the heavy top's compiled Taylor tables


if __name__ == "__main__":
    main()
