"""The free body's period the figures cut their spans by (wobble.plot._sampling.free_period), read from a run's
record: the same whatever frame the body's inertia tensor is written in."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import wobble
from wobble.plot._sampling import free_period

_MOMENTS = np.array([0.0012, 0.0158, 0.0170])  # the tennis racket's (kg m2)
_OMEGA = np.array([0.01, 12.0, 0.01])  # rad/s, about its intermediate axis


def _scene(body: dict, omega) -> dict:
    return {
        "schema": "wobble-scene/1",
        "name": "racket",
        "body": body,
        "initial": {"omega": {"value": list(map(float, omega)), "unit": "rad/s"}, "attitude": [1.0, 0.0, 0.0, 0.0]},
        "time": {"start": "0 s", "stop": "4 s", "samples": 201},
        "outputs": ["omega"],
    }


def _closed_form_period(moments, omega) -> float:
    """omega's period from the moments and omega(0) written out, at 30 digits: 4 K(k^2) / lambda with
    lambda^2 = (I3 - I2)(L^2 - 2T I1) / (I1 I2 I3), k^2 = (I2 - I1)(2T I3 - L^2) / ((I3 - I2)(L^2 - 2T I1))
    for I1 < I2 < I3 and L^2 > 2T I2 (I1 and I3 exchanged below it; Landau & Lifshitz, Mechanics, sec. 37)."""
    with mpmath.workdps(30):
        inertia = [mpmath.mpf(float(x)) for x in moments]
        w = [mpmath.mpf(float(x)) for x in omega]
        two_t = sum(i * x * x for i, x in zip(inertia, w))
        l2 = sum((i * x) ** 2 for i, x in zip(inertia, w))
        i1, i2, i3 = inertia if l2 > two_t * inertia[1] else inertia[::-1]
        lam = mpmath.sqrt((i3 - i2) * (l2 - two_t * i1) / (i1 * i2 * i3))
        k2 = (i2 - i1) * (two_t * i3 - l2) / ((i3 - i2) * (l2 - two_t * i1))
        return float(4 * mpmath.ellipk(k2) / lam)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_free_period_is_the_same_in_any_frame_of_the_body(seed):
    """A body given by its tensor R diag(I) R^T, spun at R omega, is the body of diag(I) spun at omega: the
    period free_period reads from the record (through the record's principal axes) is the closed form's,
    4 K(k^2) / lambda at 30 digits from the moments and omega(0), to rounding."""
    exact = _closed_form_period(_MOMENTS, _OMEGA)
    assert 3.37 < exact < 3.38  # s: the racket's flip period
    plain = wobble.run(_scene({"moments": {"value": _MOMENTS.tolist(), "unit": "kg m2"}}, _OMEGA))
    assert free_period(plain) == pytest.approx(exact, rel=1e-12)
    r = Rotation.random(random_state=seed).as_matrix()
    tensor = r @ np.diag(_MOMENTS) @ r.T
    tilted = wobble.run(_scene({"tensor": {"value": tensor.tolist(), "unit": "kg m2"}}, r @ _OMEGA))
    assert free_period(tilted) == pytest.approx(exact, rel=1e-9)


def test_no_free_period_for_an_ensemble():
    """Members spun differently have different periods: no one period cuts the figure's span."""
    data = _scene({"moments": {"value": _MOMENTS.tolist(), "unit": "kg m2"}}, _OMEGA)
    data["initial"]["omega"] = {"value": [_OMEGA.tolist(), (1.01 * _OMEGA).tolist()], "unit": "rad/s"}
    assert free_period(wobble.run(data)) is None


def test_a_perturber_s_own_motion_bounds_what_the_figure_claims_to_resolve():
    """The Moon's tide turns the Earth's angular momentum at its fortnightly and faster terms (2L + l at 3 n,
    2L + 2l at 4 n, ...), where the figure axis alone moves at 1.1e-8 rad/s: the bound had the axis alone,
    and called one sample in 10 days resolved. Now the tide's own harmonics are in it: every term the
    precession fit finds runs below it; daily samples resolve them, three-day ones do not (2L + l turns
    2.1 rad in 3 days)."""
    from wobble.io.scene_file import example_scene_path, read_scene
    from wobble.models.torques import ThirdBody
    from wobble.plot._sampling import panel_rates, resolved

    ds = wobble.run("earth_precession")
    scene = read_scene(example_scene_path("earth_precession"))
    moon = next(s for s in scene.torques if isinstance(s, ThirdBody) and s.name == "moon").orbit
    rates = panel_rates(ds)
    assert rates["axis"] < 2e-8 and rates["angular_momentum"] > 5 * moon.mean_motion
    fastest = 2 * (moon.mean_motion + moon.node_rate + moon.periapsis_rate) + moon.mean_motion  # 2L + l
    assert fastest < rates["angular_momentum"]
    assert resolved(rates["angular_momentum"], 86400.0) and not resolved(rates["angular_momentum"], 3 * 86400.0)


def test_a_symmetric_top_with_its_centre_of_mass_off_the_axis_takes_the_general_bound():
    """A symmetric body's torque changes only with its figure axis when it is a tide or a lever along the axis;
    the rule took any symmetric body, and a gyroscope with its centre of mass 1 cm off the axis got 4.9 rad/s
    where its angular momentum carries its 600 rad/s spin (called resolved at 5 ms samples)."""
    import tomllib

    from wobble.io.scene_file import example_scene_path
    from wobble.plot._sampling import panel_rates

    data = tomllib.loads(example_scene_path("gyroscope").read_text())
    data["outputs"] = ["omega", "attitude", "axis_direction", "angular_momentum"]
    data["time"] = {"stop": "1 s", "samples": 201}
    on_axis = panel_rates(wobble.run(data))
    spin = float(np.max(np.linalg.norm(wobble.run(data)["omega"].values, axis=-1)))
    assert on_axis["angular_momentum"] < 0.1 * spin  # the axis's slow precession and nutation
    data["torques"][0]["center_of_mass"] = {"value": [0.01, 0.0, 0.04], "unit": "m"}
    off_axis = panel_rates(wobble.run(data))
    assert off_axis["angular_momentum"] == pytest.approx(2 * spin, rel=1e-3)  # 2 |omega|: the general rule
