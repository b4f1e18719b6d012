"""Regenerate tests/references/clairaut.json with mpmath only (no wobble, no numpy).

Usage::

    python tests/references/build_clairaut_references.py      # about three minutes

The hydrostatic figure of the shipped density profiles (``data/profiles/prem.toml``,
``data/profiles/mars_layered.toml``, read as TOML here), for tests/test_hydrostatic_reference.py.
Independent of wobble's Radau/DOP853 path (:mod:`wobble.numerics.clairaut`): Clairaut's
equation itself, second order and linear in eps (Jeffreys 1976, *The Earth*, ch. 4),

    r^2 eps'' + 6 (rho/rhobar)(r eps' + eps) - 6 eps = 0,

written in t = ln r (eps_tt = eps_t - 6 (rho/rhobar)(eps_t + eps) + 6 eps) and integrated layer
by layer with ``mpmath.odefun`` (Taylor series) at 32 digits, the mass inside r from the exact
polynomial integrals. It starts at r0 = 1e-6 a with eps = 1 and the two-term series
r eps'/eps = -d1 x - (6/7) d2 x^2 of rho/rhobar - 1 = d1 x + d2 x^2: the start's error (the
next term, ~1e-18) excites the solution r^-5, whose share falls as (r0/r)^5, below 1e-30 by
r = 1e-3 a. The surface condition
a eps'(a) + 2 eps(a) = 5 q/2, q = Omega^2 a^3/(G M) scales it; C - A = (8 pi/15) int rho d(r^5 eps)
is a third component of the same integration, and e_f = (C_f - A_f)/A_f its difference over
the liquid core, A_f = (8 pi/3) int rho r^4 dr.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import mpmath as mp

OUT = Path(__file__).with_name("clairaut.json")
PROFILES = Path(__file__).resolve().parents[2] / "data" / "profiles"
DPS = 32
G = "6.67430e-11"  # CODATA 2018, astropy's constants.G (the default of wobble.hydrostatic_figure)
SPIN = {
    "prem": lambda: mp.mpf("7.292115e-5"),  # rad/s, IERS Conventions (2010), as data/bodies/earth.toml
    # 350.891985307 deg/d (Konopliv et al. 2016, as data/bodies/mars.toml) in rad/s.
    "mars_layered": lambda: mp.mpf("350.891985307") * mp.pi / 180 / 86400,
}
UNITS = {"km": 1000, "g cm-3": 1000}


def s(x, digits=30):
    return mp.nstr(x, digits, strip_zeros=False)


def read(name):
    """Layer tops (m), density coefficients (kg/m^3 per power of r/scale), scale (m), liquid core (m)."""
    par = tomllib.loads((PROFILES / f"{name}.toml").read_text())["parameters"]

    def si(key):
        p = par[key]
        factor = UNITS[p["unit"]]
        if isinstance(p["value"][0], list):
            return [[mp.mpf(str(c)) * factor for c in row] for row in p["value"]]
        return [mp.mpf(str(c)) * factor for c in p["value"]]

    def one(key):
        p = par[key]
        return mp.mpf(str(p["value"])) * UNITS[p["unit"]]

    core = (one("fluid_core_inner_radius"), one("fluid_core_outer_radius"))
    return si("layer_top_radius"), si("density_coefficients"), one("normalising_radius"), core


def figure(name):
    tops, coeffs, scale, (core_lo, core_hi) = read(name)
    a = tops[-1]
    edges = [mp.mpf(0)] + list(tops)

    def rho(i, r):
        return sum(c * (r / scale) ** j for j, c in enumerate(coeffs[i]))

    def integral(i, lo, hi, n):  # int rho r^n dr over part of layer i, exactly
        return sum(
            c / scale**j * (hi ** (j + n + 1) - lo ** (j + n + 1)) / (j + n + 1) for j, c in enumerate(coeffs[i])
        )

    below = [mp.mpf(0)]
    for i in range(len(coeffs)):
        below.append(below[-1] + integral(i, edges[i], edges[i + 1], 2))
    mass = 4 * mp.pi * below[-1]
    spin = SPIN[name]()
    q = spin**2 * a**3 / (mp.mpf(G) * mass)

    # Start: rho/rhobar - 1 = d1 x + d2 x^2 near the centre (x = r/scale), eta = -d1 x - (6/7) d2 x^2.
    c = coeffs[0] + [mp.mpf(0)] * 3
    d1 = c[1] / (4 * c[0])
    d2 = 2 * c[2] / (5 * c[0]) - d1 * 3 * c[1] / (4 * c[0])
    r0 = mp.mpf("1e-6") * a
    x0 = r0 / scale
    state = [mp.mpf(1), -d1 * x0 - 6 * d2 * x0**2 / 7, c[0] * r0**5]  # eps, eps_t, int rho d(r^5 eps)
    t0 = mp.log(r0)
    at_edges = []
    for i in range(len(coeffs)):

        def rhs(t, y, i=i):
            r = mp.exp(t)
            ratio = rho(i, r) * r**3 / (3 * (below[i] + integral(i, edges[i], r, 2)))
            eps, eps_t, _ = y
            return [eps_t, eps_t - 6 * ratio * (eps_t + eps) + 6 * eps, rho(i, r) * r**5 * (5 * eps + eps_t)]

        t1 = mp.log(edges[i + 1])
        state = list(mp.odefun(rhs, t0, state)(t1))
        at_edges.append(state)
        t0 = t1
    eps_a, eps_t_a, shells = state
    norm = 5 * q / (2 * (eps_t_a + 2 * eps_a))
    moment = 8 * mp.pi / 3 * sum(integral(i, edges[i], edges[i + 1], 4) for i in range(len(coeffs)))
    i_lo = [k for k, e in enumerate(edges) if e == core_lo][0]
    i_hi = [k for k, e in enumerate(edges) if e == core_hi][0]
    shells_at = [mp.mpf(0)] + [e[2] for e in at_edges]
    core_moment = 8 * mp.pi / 3 * sum(integral(i, edges[i], edges[i + 1], 4) for i in range(i_lo, i_hi))
    core_e = 8 * mp.pi / 15 * norm * (shells_at[i_hi] - shells_at[i_lo]) / core_moment
    return {
        "profile": name,
        "spin_rad_per_s": s(spin),
        "gravitational_constant": G,
        "q": s(q),
        "mass_kg": s(mass),
        "radius_m": [s(e) for e in edges[1:]],
        "flattening": [s(norm * e[0]) for e in at_edges],
        "surface_flattening": s(norm * eps_a),
        "radau_eta_surface": s(eps_t_a / eps_a),
        "j2": s(8 * mp.pi / 15 * norm * shells / (mass * a**2)),
        "moment_factor": s(moment / (mass * a**2)),
        "core_dynamical_ellipticity": s(core_e),
    }


def main():
    mp.mp.dps = DPS
    out = {
        "generator": f"tests/references/build_clairaut_references.py (mpmath {mp.__version__}, {DPS} digits)",
        "figures": [figure(name) for name in SPIN],
    }
    OUT.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
