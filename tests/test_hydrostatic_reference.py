"""The hydrostatic figure against references built without wobble's Radau/DOP853 path.

* A polytrope of index 1, rho = rho_c sin(k r)/(k r): the l = 2 part of its density solves the
  same Helmholtz equation as rho, so the level surfaces have eps(r) proportional to
  j2(k r)/(k r j1(k r)) (spherical Bessel functions; the ratio solves Clairaut's equation at any
  radius, checked here). The surface condition a eps'(a) + 2 eps(a) = 5 q/2 scales it. Cut at
  k a = 3 (the density stays positive), as one polynomial (its Taylor series to x^30, 3e-18)
  in two layers, the inner one a liquid core, so that e_f is a shell integral over a core whose
  density varies: e_f = int rho d(r^5 eps)/(5 int rho r^4 dr), by mpmath quadrature.
* The shipped profiles, PREM and mars_layered, against Clairaut's second-order equation
  integrated by mpmath's Taylor method at 32 digits
  (tests/references/clairaut.json, tests/references/build_clairaut_references.py).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest

from wobble.io.density_profile import load_profile
from wobble.models.hydrostatic import DensityProfile, hydrostatic_figure

REFERENCE = json.loads((Path(__file__).parent / "references" / "clairaut.json").read_text())
G = 6.67430e-11
KA = 3


def _j1(x):
    return mp.sin(x) / x**2 - mp.cos(x) / x


def _j2(x):
    return (3 / x**3 - 1 / x) * mp.sin(x) - 3 * mp.cos(x) / x**2


def _polytrope_shape(x):
    """eps(r)/const of the n = 1 polytrope, x = k r."""
    return _j2(x) / (x * _j1(x))


def test_the_polytrope_shape_solves_clairauts_equation():
    """The closed form is a solution: r^2 eps'' + 6 (rho/rhobar)(r eps' + eps) - 6 eps = 0, x = k r."""
    with mp.workdps(40):
        for x in (mp.mpf("0.2"), mp.mpf(1), mp.mpf(2), mp.mpf(3)):
            e, d1, d2 = _polytrope_shape(x), mp.diff(_polytrope_shape, x), mp.diff(_polytrope_shape, x, 2)
            ratio = (mp.sin(x) / x) / (3 * (mp.sin(x) - x * mp.cos(x)) / x**3)
            assert abs(x**2 * d2 + 6 * ratio * (x * d1 + e) - 6 * e) < mp.mpf("1e-35") * abs(e)


def test_polytrope_n1_against_its_closed_form():
    a, rho_c, spin = 6.4e6, 12000.0, 7.292115e-5
    with mp.workdps(40):
        coeffs = tuple(
            float(rho_c * (-1) ** (j // 2) * mp.mpf(KA) ** j / mp.factorial(j + 1)) if j % 2 == 0 else 0.0
            for j in range(31)
        )
    b = a / 2
    body = DensityProfile("polytrope", (0.0, b, a), (coeffs, coeffs), a, fluid_core=(0.0, b))
    fig = hydrostatic_figure(body, spin, G)
    with mp.workdps(40):
        k = mp.mpf(KA) / a
        mass = 4 * mp.pi * rho_c * mp.quad(lambda r: mp.sin(k * r) / (k * r) * r**2, [0, a])
        q = mp.mpf(spin) ** 2 * mp.mpf(a) ** 3 / (mp.mpf(G) * mass)
        shape = lambda r: _polytrope_shape(k * r)  # noqa: E731
        eta_a = a * mp.diff(shape, mp.mpf(a)) / shape(mp.mpf(a))
        scale = 5 * q / (2 * (eta_a + 2)) / shape(mp.mpf(a))
        eps = [float(scale * shape(mp.mpf(r))) for r in fig.radius[1:]]
        rho = lambda r: rho_c * mp.sin(k * r) / (k * r)  # noqa: E731
        core_shells = mp.quad(lambda r: rho(r) * mp.diff(lambda s: s**5 * scale * shape(s), r), [0, b])
        core_e = core_shells / (5 * mp.quad(lambda r: rho(r) * r**4, [0, b]))
        moment = (
            2 / mp.mpf(3) * mp.quad(lambda r: rho(r) * r**4, [0, a]) / (mp.quad(lambda r: rho(r) * r**2, [0, a]) * a**2)
        )
    assert fig.q == pytest.approx(float(q), rel=1e-14)
    assert np.max(np.abs(fig.flattening[1:] / np.array(eps) - 1)) < 1e-11
    assert fig.surface_flattening == pytest.approx(float(scale * shape(mp.mpf(a))), rel=1e-11)
    assert fig.core_dynamical_ellipticity == pytest.approx(float(core_e), rel=1e-11)
    assert fig.moment_factor == pytest.approx(float(moment), rel=1e-13)
    assert fig.eta[-1] == pytest.approx(float(eta_a), rel=1e-10)
    # Radau-Darwin: eta(a) from C/(Ma^2) by (2/3)(1 - (2/5) sqrt(1 + eta)) (Jeffreys 1976, sec. 4.04),
    # then eps = 5 q/(2 (eta + 2)); an approximation, 2.9e-3 from the exact figure of this cut polytrope.
    eta_rd = (2.5 * (1 - 1.5 * float(moment))) ** 2 - 1
    assert fig.radau_darwin_flattening == pytest.approx(2.5 * float(q) / (eta_rd + 2), rel=1e-13)
    assert fig.radau_darwin_flattening == pytest.approx(fig.surface_flattening, rel=5e-3)


@pytest.mark.parametrize("ref", REFERENCE["figures"], ids=lambda r: r["profile"])
def test_shipped_profiles_against_an_mpmath_clairaut_solution(ref):
    prof, _ = load_profile(ref["profile"])
    fig = hydrostatic_figure(prof, float(ref["spin_rad_per_s"]), float(ref["gravitational_constant"]))
    assert fig.q == pytest.approx(float(ref["q"]), rel=1e-14)
    assert fig.mass == pytest.approx(float(ref["mass_kg"]), rel=1e-14)
    for r, eps in zip(ref["radius_m"], ref["flattening"]):
        i = int(np.argmin(np.abs(fig.radius - float(r))))
        assert fig.radius[i] == pytest.approx(float(r), rel=1e-15)
        assert fig.flattening[i] == pytest.approx(float(eps), rel=1e-11), r
    assert fig.surface_flattening == pytest.approx(float(ref["surface_flattening"]), rel=1e-11)
    assert fig.eta[-1] == pytest.approx(float(ref["radau_eta_surface"]), rel=1e-10)
    assert fig.j2 == pytest.approx(float(ref["j2"]), rel=1e-11)
    assert fig.moment_factor == pytest.approx(float(ref["moment_factor"]), rel=1e-14)
    assert fig.core_dynamical_ellipticity == pytest.approx(float(ref["core_dynamical_ellipticity"]), rel=1e-11)
    assert math.isclose(fig.dynamical_flattening, fig.j2 / fig.moment_factor, rel_tol=1e-14)
