"""Free bodies started exactly on the separatrix (L^2 = 2 E I2) with every sign of omega, against an independent
integration of Euler's equations and the quaternion kinematics (SciPy's DOP853).

On the separatrix omega_a = A_a sech u never changes sign, so the closed form's start phase u0 = 2K - f, which reaches
omega_a < 0 everywhere else, was inf - f with K = inf: ``FreeRotation([3, 4, 6], [-1, 0.4, 0.5])`` raised
``OverflowError``, and ``wobble free`` printed a traceback; ``wobble free`` on any separatrix with ``--t-end`` failed
too (no time between flips), and so did its netCDF output (a None attribute).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from astropy import units as u
from scipy.integrate import solve_ivp

from cli_run import run_cli
from reference_odes import euler_quaternion_rhs
from wobble import FreeRotation

# Exactly on the separatrix in floats: D_1 = I0 (I1 - I0) w0^2 - I2 (I2 - I1) w2^2 = 0 holds for w0 = +-2 w2 with
# moments (3, 4, 6), w0 = +-w2 with (3, 5, 6), whatever w1; and in a user order whose sorting is an odd permutation.
CASES = [
    ((3.0, 4.0, 6.0), (-1.0, 0.4, 0.5)),  # the audit's case
    ((3.0, 4.0, 6.0), (-1.0, 0.4, -0.5)),
    ((3.0, 4.0, 6.0), (-1.0, -0.4, -0.5)),
    ((3.0, 4.0, 6.0), (1.0, 0.4, -0.5)),
    ((3.0, 4.0, 6.0), (1.0, 0.4, 0.5)),
    ((3.0, 4.0, 6.0), (-1.0, 0.0, 0.5)),  # omega_b = 0: mid-flip at t = 0
    ((3.0, 4.0, 6.0), (-1.0, 0.0, -0.5)),
    ((3.0, 4.0, 6.0), (1.0, 0.0, -0.5)),
    ((3.0, 5.0, 6.0), (-0.3, 0.7, 0.3)),
    ((3.0, 5.0, 6.0), (-0.3, -0.2, -0.3)),
    ((4.0, 3.0, 6.0), (0.4, -1.0, 0.5)),  # intermediate moment first, smallest second
    ((4.0, 3.0, 6.0), (-0.4, -1.0, -0.5)),
]
TIMES = np.linspace(-2.0, 3.0, 26)


def _rhs(t, y, moments):
    return euler_quaternion_rhs(moments)(t, y)


def _reference(moments, omega0, times):
    """omega and the attitude quaternion at ``times`` (either side of 0) by DOP853 from q = identity."""
    y0 = np.concatenate([omega0, [1.0, 0.0, 0.0, 0.0]])
    out = np.empty((times.size, 7))
    for side in (times < 0, times >= 0):
        ts = np.sort(times[side])[:: -1 if times[side][0] < 0 else 1]  # outwards from 0
        sol = solve_ivp(
            _rhs, (0.0, ts[-1]), y0, method="DOP853", t_eval=ts, rtol=1e-12, atol=1e-14, args=(np.asarray(moments),)
        )
        assert sol.success
        out[side] = sol.y.T[np.argsort(ts)]
    return out[:, :3], out[:, 3:]


@pytest.mark.parametrize(("moments", "omega0"), CASES)
def test_every_sign_on_the_separatrix_follows_eulers_equations(moments, omega0):
    body = FreeRotation(moments * u.kg * u.m**2, omega0 * u.rad / u.s)
    assert body.regime == "separatrix"
    w_ref, q_ref = _reference(moments, np.asarray(omega0), TIMES)
    w = body.omega(TIMES * u.s).to_value(u.rad / u.s)
    q = body.attitude(TIMES * u.s)
    np.testing.assert_allclose(w, w_ref, rtol=0, atol=1e-8)
    np.testing.assert_allclose(q, q_ref, rtol=0, atol=1e-8)  # both continuous from the identity: same sign
    # The one flip: where the reference's intermediate component is 0 (an event of the same integration, +-10 s).
    inter = int(np.argsort(moments, kind="stable")[1])
    flips = body.flip_times(10 * u.s, t_start=-10 * u.s).to_value(u.s)
    if omega0[inter] == 0:
        assert flips.tolist() == [0.0]
        return
    events = [_flip_times(moments, omega0, inter, end) for end in (-10.0, 10.0)]
    np.testing.assert_allclose(flips, np.concatenate(events), rtol=0, atol=1e-9)
    assert flips.size == 1


def _flip_times(moments, omega0, inter, end):
    sol = solve_ivp(
        _rhs,
        (0.0, end),
        np.concatenate([omega0, [1.0, 0.0, 0.0, 0.0]]),
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        args=(np.asarray(moments),),
        events=lambda _t, y, _m: y[inter],
    )
    assert sol.success
    return sol.t_events[0]


def test_the_command_line_runs_the_audits_case(capsys, tmp_path):
    argv = ["free", "--inertia", "3", "4", "6", "--omega", "-1", "0.4", "0.5", "--t-end", "2", "--json"]
    out = tmp_path / "sep.nc"
    code, stdout, stderr = run_cli([*argv, "-o", str(out)], capsys)
    assert code == 0, stderr
    doc = json.loads(stdout)
    assert doc["regime"] == "separatrix" and doc["flips_in_span"] == 1 and doc["time_between_flips_s"] is None
    # The flip: the reference's omega_b = 0, found by an event of the same integration.
    np.testing.assert_allclose(
        doc["flip_times_s"], _flip_times((3.0, 4.0, 6.0), (-1.0, 0.4, 0.5), 1, 2.0), rtol=0, atol=1e-9
    )
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert ds.attrs["regime"] == "separatrix" and "time_between_flips_s" not in ds.attrs
        assert ds.omega.shape == (1001, 3) and np.all(np.isfinite(ds.omega.values))
        np.testing.assert_allclose(ds.omega.values[0], [-1.0, 0.4, 0.5], rtol=0, atol=1e-15)
    code, stdout, stderr = run_cli(argv[:-1], capsys)
    assert code == 0 and "separatrix" in stdout and "Traceback" not in stderr


@pytest.mark.parametrize(("moments", "omega"), CASES[:3])
def test_the_engine_runs_the_exact_separatrix_for_every_sign(moments, omega):
    """An accuracy guard: the engine on the separatrix, every sign of omega_a, against DOP853 from the same state
    (the flow map it used for omega_a < 0 and the exact solution it uses now agree to 2e-13, so this does not tell
    which path ran)."""
    import wobble

    scene = wobble.Scene(
        body=np.array(moments) * u.kg * u.m**2,
        omega0=np.array(omega) * u.rad / u.s,
        t_end=3 * u.s,
        samples=31,
        accuracy=1e-9,
        outputs=["omega"],
    )
    ds = wobble.run(scene)
    t = ds["time"].values
    y0 = np.concatenate([omega, [1.0, 0.0, 0.0, 0.0]])
    sol = solve_ivp(_rhs, (0.0, 3.0), y0, "DOP853", t_eval=t, rtol=1e-12, atol=1e-14, args=(np.asarray(moments),))
    w = sol.y[:3].T
    assert np.max(np.abs(ds["omega"].values.reshape(-1, 3) - w)) < 1e-11
