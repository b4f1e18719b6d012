"""The free body's period the figures cut their spans by (wobble.plot._sampling.free_period), read from a run's
record: the same whatever frame the body's inertia tensor is written in."""

from __future__ import annotations

import math

import astropy.units as u
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


def _gyroscope_inputs(data: dict) -> dict:
    """The heavy top a gyroscope scene describes, in SI from its own entries (astropy for the units)."""
    body, lever, start = data["body"], data["torques"][0], data["initial"]
    return {
        "moments": u.Quantity(body["moments"]["value"], body["moments"]["unit"]).to_value(u.kg * u.m**2),
        "weight": u.Quantity(body["mass"]).to_value(u.kg) * u.Quantity(lever["g"]).to_value(u.m / u.s**2),
        "lever": u.Quantity(lever["center_of_mass"]["value"], lever["center_of_mass"]["unit"]).to_value(u.m),
        "angles": u.Quantity(start["euler_angles"]["value"], start["euler_angles"]["unit"]).to_value(u.rad),
        "rates": u.Quantity(start["euler_rates"]["value"], start["euler_rates"]["unit"]).to_value(u.rad / u.s),
    }


def _heavy_top_omega(data: dict, times) -> np.ndarray:
    """omega(t) in the body (rad/s) of a scene's top under uniform gravity, from its inputs alone: the
    Euler-Poisson equations I w' = I w x w + M g n x r, n' = n x w (n the upward vertical in the body, r the
    centre of mass), from omega(0) and n(0) of the z-x-z Euler angles and rates (omega_1 = phi_dot sin theta
    sin psi + theta_dot cos psi, ...: the notes, sec. 5.7), integrated by SciPy's DOP853 at rtol 1e-11: no wobble
    code (it agrees with wobble's run to 1e-12)."""
    from scipy.integrate import solve_ivp

    top = _gyroscope_inputs(data)
    i1, i2, i3 = top["moments"]
    mg = top["weight"]
    x, y, z = top["lever"]
    _, theta, psi = top["angles"]
    dphi, dtheta, dpsi = top["rates"]
    w0 = [
        dphi * math.sin(theta) * math.sin(psi) + dtheta * math.cos(psi),
        dphi * math.sin(theta) * math.cos(psi) - dtheta * math.sin(psi),
        dphi * math.cos(theta) + dpsi,
    ]
    n0 = [math.sin(theta) * math.sin(psi), math.sin(theta) * math.cos(psi), math.cos(theta)]

    def rhs(_, s):
        w1, w2, w3, n1, n2, n3 = s
        return [
            (mg * (n2 * z - n3 * y) + (i2 - i3) * w2 * w3) / i1,
            (mg * (n3 * x - n1 * z) + (i3 - i1) * w3 * w1) / i2,
            (mg * (n1 * y - n2 * x) + (i1 - i2) * w1 * w2) / i3,
            n2 * w3 - n3 * w2,
            n3 * w1 - n1 * w3,
            n1 * w2 - n2 * w1,
        ]

    sol = solve_ivp(rhs, (0.0, times[-1]), w0 + n0, method="DOP853", t_eval=times, rtol=1e-11, atol=1e-14)
    assert sol.success
    return sol.y[:3].T


def test_a_symmetric_top_with_its_centre_of_mass_off_the_axis_takes_the_general_bound():
    """A symmetric body's torque changes only with its figure axis when it is a tide or a lever along the axis;
    the rule took any symmetric body, and a gyroscope with its centre of mass 1 cm off the axis got 4.9 rad/s
    where its angular momentum carries its 600 rad/s spin (called resolved at 5 ms samples).

    Both bounds from the top's inputs, not from the run: on the axis, twice the figure axis's rate (its speed
    over its excursion) on the closed-form steady precession; off it, 2 |omega| with omega from the
    Euler-Poisson equations integrated here, and above the spin line the offset puts in the angular momentum."""
    import tomllib

    from wobble.io.scene_file import example_scene_path
    from wobble.plot._sampling import panel_rates

    data = tomllib.loads(example_scene_path("gyroscope").read_text())
    data["outputs"] = ["omega", "attitude", "axis_direction", "angular_momentum"]
    data["time"] = {"stop": "1 s", "samples": 201}
    top = _gyroscope_inputs(data)
    i1, _, i3 = top["moments"]
    phi_dot, _, psi_dot = top["rates"]
    theta = top["angles"][1]
    w3 = psi_dot + phi_dot * math.cos(theta)
    c, mgl = math.cos(theta), top["weight"] * top["lever"][2]
    # The shipped start is the slow steady precession (Goldstein, Poole & Safko 2002, eq. 5.73 with theta_dot = 0).
    assert phi_dot == pytest.approx((i3 * w3 - math.sqrt((i3 * w3) ** 2 - 4 * i1 * mgl * c)) / (2 * i1 * c), rel=1e-9)

    ds = wobble.run(data)
    t = ds["time"].values
    # On the axis: the figure axis e3 = (sin theta sin phi, -sin theta cos phi, cos theta), phi = phi_dot t, moves
    # at phi_dot sin theta; its rate is that over its largest excursion about its mean, and the torque, M g l
    # z x e3, is at most quadratic in e3 (here linear; the field is fixed: no rate of its own): twice that.
    e3 = np.stack([np.sin(theta) * np.sin(phi_dot * t), -np.sin(theta) * np.cos(phi_dot * t), np.full_like(t, c)], -1)
    excursion = np.max(np.abs(e3 - e3.mean(axis=0)))
    on_axis = panel_rates(ds)["angular_momentum"]
    assert on_axis == pytest.approx(2 * phi_dot * math.sin(theta) / excursion, rel=1e-7)
    assert phi_dot < on_axis < 0.1 * w3  # above L's own turn about the vertical (phi_dot), far below the spin

    data["torques"][0]["center_of_mass"] = {"value": [0.01, 0.0, 0.04], "unit": "m"}
    ds = wobble.run(data)
    off_axis = panel_rates(ds)["angular_momentum"]
    # The general rule: 2 |omega|, its largest at the samples, omega from the equations of motion written out.
    spin = np.max(np.linalg.norm(_heavy_top_omega(data, ds["time"].values), axis=-1))
    assert off_axis == pytest.approx(2 * spin, rel=1e-9)
    # The offset across the axis turns with the body, so the torque's part M g (R r_perp) x (-z) runs at
    # psi_dot +- phi_dot in space (598.3 and 601.2 rad/s, to first order in the offset): the bound covers both.
    assert off_axis > psi_dot + phi_dot
