"""Solids whose moments sit at the bottom of the float range (fuzzing review), against exact rationals.

A box of 1e300 kg and 1e-300 m has moments of about 1e-300 kg m2, a normal double; its edges squared are
0 in doubles, so it printed I1 = I2 = I3 = 0 and "asymmetric (... differs by 0 relative)". The same for the
cone and the top. Moments below the normal doubles (an ellipsoid of 1e-300 kg and 1e-300 m, 1e-900 kg m2;
or of 1 kg and 1e-161 m, 1e-322 kg m2, printed as 9.881313e-323 to 7 figures) are refused, naming the
options as typed. The references are the textbook formulas (Goldstein, Poole & Safko 2002, ch. 5 exercises;
the parallel-axis theorem) in exact rational arithmetic, rounded once.
"""

from __future__ import annotations

import json
from fractions import Fraction as F

import astropy.units as u
import numpy as np
import pytest
from cli_run import run_cli

from wobble import InputError, RigidBody

KGM2 = u.kg * u.m**2


def _exact(values):
    return np.array(sorted(float(v) for v in values))


def _moments(body):
    return body.principal_moments.to_value(KGM2)


def test_box_of_huge_mass_and_tiny_edges():
    m, (a, b, c) = F(1e300), (F(1e-300), F(2e-300), F(3e-300))
    want = _exact([m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12])
    body = RigidBody.box(1e300 * u.kg, [1e-300, 2e-300, 3e-300] * u.m)
    np.testing.assert_allclose(_moments(body), want, rtol=4e-16)
    assert body.classify(1e-9).kind == "asymmetric"


def test_cone_cylinder_and_ellipsoid_of_huge_mass_and_tiny_size():
    m, r, h = F(1e300), F(1e-300), F(1e-300)
    cone = RigidBody.cone(1e300 * u.kg, 1e-300 * u.m, 1e-300 * u.m)
    np.testing.assert_allclose(
        _moments(cone), _exact([F(3, 80) * m * (4 * r * r + h * h)] * 2 + [F(3, 10) * m * r * r]), rtol=4e-16
    )
    inner = F(5e-301)
    tube = RigidBody.cylinder(1e300 * u.kg, 1e-300 * u.m, 1e-300 * u.m, 5e-301 * u.m)
    r2 = r * r + inner * inner
    np.testing.assert_allclose(_moments(tube), _exact([m * (3 * r2 + h * h) / 12] * 2 + [m * r2 / 2]), rtol=4e-16)
    q = [F(1e-300), F(2e-300), F(3e-300)]
    ell = RigidBody.ellipsoid(1e300 * u.kg, [1e-300, 2e-300, 3e-300] * u.m)
    want = [m * (q[1] ** 2 + q[2] ** 2) / 5, m * (q[0] ** 2 + q[2] ** 2) / 5, m * (q[0] ** 2 + q[1] ** 2) / 5]
    np.testing.assert_allclose(_moments(ell), _exact(want), rtol=4e-16)


def test_top_of_huge_masses_and_tiny_lengths_about_its_tip():
    """Disc (M_d, R) at height h on a thin axle (M_a, L) from the tip: about the tip, by parallel axes,
    I_xx = M_d R^2/4 + M_d h^2 + M_a L^2/3 and I_zz = M_d R^2/2."""
    md, rd, ma, ell, h = F(1e300), F(1e-300), F(1e300), F(1e-300), F(1e-300)
    top = RigidBody.spinning_top(1e300 * u.kg, 1e-300 * u.m, 1e300 * u.kg, 1e-300 * u.m, 1e-300 * u.m)
    tip = top.shifted_to("origin")
    ixx = md * rd * rd / 4 + md * h * h + ma * ell * ell / 3
    np.testing.assert_allclose(_moments(tip), _exact([md * rd * rd / 2, ixx, ixx]), rtol=1e-15)


@pytest.mark.parametrize(
    "argv, options, typed",
    [
        (["--solid", "ellipsoid", "--mass", "1e-300", "--axes", "1e-300", "2e-300", "3e-300"], "--mass, --axes",
         "1e-300, 1e-300 2e-300 3e-300"),
        # I1 = (2e-161^2 + 1e-161^2)/5 = 1e-322 kg m2: subnormal, printed as 9.881313e-323 to 7 figures.
        (["--solid", "ellipsoid", "--mass", "1", "--axes", "3e-161", "2e-161", "1e-161"], "--mass, --axes",
         "1, 3e-161 2e-161 1e-161"),
        (["--solid", "box", "--mass", "1e-300 g", "--edges", "1e-5", "1e-5", "1e-5"], "--mass, --edges",
         "1e-300 g, 1e-5 1e-5 1e-5"),
        (["--solid", "top", "--disc-mass", "1e-300", "--disc-radius", "1e-300", "--axle-mass", "1e-300",
          "--axle-length", "1e-300", "--disc-height", "1e-300"],
         "--disc-mass, --disc-radius, --axle-mass, --axle-length, --disc-height",
         "1e-300, 1e-300, 1e-300, 1e-300, 1e-300"),
    ],
)  # fmt: skip
def test_moments_below_the_normal_doubles_are_refused_naming_the_options(argv, options, typed, capsys):
    code, out, err = run_cli(["inertia", *argv], capsys)
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"wobble inertia: error: {options}: got {typed}; allowed: sizes whose moments of inertia are normal "
        "doubles (at least 2.225e-308 kg m2: below, a double keeps only a few digits, or none)"
    ]


def test_the_refusal_is_at_the_normal_boundary():
    """A rod of 12 kg and 2^-511 m: M L^2/12 = 2^-1022, the smallest normal double, exactly; half of it is refused."""
    at = RigidBody.thin_rod(12 * u.kg, 2.0**-511 * u.m)
    assert _moments(at)[1:].tolist() == [2.0**-1022] * 2 and _moments(at)[0] == 0.0
    with pytest.raises(InputError, match="normal doubles"):
        RigidBody.thin_rod(6 * u.kg, 2.0**-511 * u.m)


def test_cli_prints_the_tiny_moments_of_the_review(capsys):
    code, out, err = run_cli(
        ["inertia", "--solid", "box", "--mass", "1e300", "--edges", "1e-300", "2e-300", "3e-300", "--json"], capsys
    )
    assert code == 0 and err == ""
    doc = json.loads(out)
    m, (a, b, c) = F(1e300), (F(1e-300), F(2e-300), F(3e-300))
    want = _exact([m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12])
    np.testing.assert_allclose(doc["principal_moments_kg_m2"], want, rtol=1e-14)
    assert doc["classification"] == "asymmetric" and doc["asymmetry"] > 0.2


def test_moments_past_the_largest_double_name_the_options_as_typed(capsys):
    code, out, err = run_cli(
        ["inertia", "--solid", "box", "--mass", "1e300", "--edges", "1e300", "2e300", "3e300"], capsys
    )
    assert code == 2 and out == ""
    assert err.startswith("wobble inertia: error: --mass, --edges: got 1e300, 1e300 2e300 3e300; allowed: sizes whose")
