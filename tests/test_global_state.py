"""wobble's results do not depend on global state its caller may have changed.

A script may set decimal's precision, rounding or traps (or decimal.DefaultContext), enable astropy
equivalencies for the whole process, make NumPy raise on underflow, pick a matplotlib backend, switch
Numba's compiler off, or keep a file named like a catalogued planet. Each case below was found by an
audit (2026-11-29) to change a result, accept a wrong input, crash or change the caller's state; the
ground truth is the same call under the default state, or the input's refusal.
"""

from __future__ import annotations

import decimal
import json
import os
import subprocess
import sys
import textwrap

import astropy.units as u
import numpy as np
import pytest

import wobble
from wobble.errors import InputError

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s
Q0 = np.array([0.8, 0.3, 0.4, 0.3]) / np.linalg.norm([0.8, 0.3, 0.4, 0.3])


def _tops():
    """A top from a state (phi0 and psi0 not zero: their sum and difference are formed in decimal), a
    nutating top evaluated far out, and an asymmetric free body: attitudes as nested lists."""
    t_state = wobble.HeavyTop.from_state([0.3, 0.2, 10.0] * RAD_S, Q0, I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J)
    top = wobble.HeavyTop(
        I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, phidot0=-0.3 * RAD_S, omega3=10 * RAD_S
    )
    free = wobble.FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    return [
        t_state.to_dataset(t=[0.0, 7.0] * u.s).attitude.values.tolist(),
        top.to_dataset(t=[1e13, 1e14] * u.s).attitude.values.tolist(),
        free.attitude([1.7, 1e9] * u.s).tolist(),
    ]


_SCRIPT = """
import decimal, json, sys
{setup}
sys.path.insert(0, {tests!r})
from test_global_state import _tops
print(json.dumps([_tops(), decimal.getcontext().flags[decimal.Inexact]]))
"""


def _in_fresh_process(setup: str, env=None):
    """_tops() in a new interpreter after ``setup`` (run before wobble is imported: the constants made at
    import see that state), and whether the caller's context was flagged Inexact."""
    code = _SCRIPT.format(setup=textwrap.dedent(setup), tests=os.path.dirname(__file__))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    return json.loads(out.stdout)


@pytest.fixture(scope="module")
def baseline():
    with decimal.localcontext(decimal.Context(prec=28)):
        return _tops()


@pytest.mark.parametrize(
    "setup",
    [
        "decimal.getcontext().prec = 3; decimal.getcontext().rounding = decimal.ROUND_FLOOR; "
        "decimal.getcontext().Emax = 10",
        "decimal.getcontext().traps[decimal.Inexact] = True; decimal.getcontext().traps[decimal.FloatOperation] = True",
        "decimal.DefaultContext.rounding = decimal.ROUND_FLOOR; decimal.DefaultContext.traps[decimal.Inexact] = True",
    ],
    ids=["precision, rounding and exponent", "traps", "DefaultContext"],
)
def test_the_caller_s_decimal_context_changes_nothing(setup, baseline):
    """Bit for bit the default context's results, and the caller's flags left alone. Until 2026-11-29:
    HeavyTop.from_state formed phi0 and psi0 in the caller's context (6 digits: its t = 0 attitude
    1.5e-6 off q0); 2 pi, made when the heavy top's module was first imported (often after the script
    had set its context), held 3 digits under prec = 3 (phi 1.3e-6 rad off at 1e14 s); traps on Inexact
    or FloatOperation, or a changed DefaultContext, crashed every top and free body.

    Related changes share one fresh interpreter (each costs seconds of start-up); each of the three
    groups fails on the code before the fix (876bea7~1: a result differs, or a trap crashes). A failure
    here: try the group's changes one at a time."""
    got, flagged = _in_fresh_process(setup)
    assert got == baseline
    assert flagged is False


def test_the_start_of_a_top_from_a_state_is_that_state_under_any_context():
    """The ground truth of from_state: at t = 0 the attitude is q0 (to rounding)."""
    with decimal.localcontext(decimal.Context(prec=6)):
        top = wobble.HeavyTop.from_state([0.3, 0.2, 10.0] * RAD_S, Q0, I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J)
    q = top.to_dataset(t=[0.0] * u.s).attitude.values[0]
    assert np.max(np.abs(q - Q0)) < 4e-16


@pytest.mark.parametrize(
    "call",
    [
        lambda: wobble.HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * u.Hz),
        lambda: wobble.HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=1.0 * u.one, omega3=10 * RAD_S),
        lambda: wobble.FreeRotation([1, 2, 3] * KGM2, [0.3, 0.1, 1.0] * u.Hz),
        lambda: wobble.Scene({"moments": [1, 2, 3] * KGM2}, [0.3, 0.1, 1.0] / u.s, t_end=1 * u.s, samples=2),
        lambda: wobble.euler_period(dynamical_flattening=3.273795e-3, spin=1.1605e-5 * u.Hz),
        lambda: wobble.euler_period(dynamical_flattening=0.19 * u.deg, spin=1 * u.sday),
    ],
)
def test_equivalencies_the_caller_enabled_let_no_wrong_unit_through(call):
    """A rate needs an angle unit and an angle an angle, whatever the caller has enabled: under
    astropy's dimensionless_angles() for the whole process, 10 Hz was read as 10 rad/s (2 pi off), a
    plain 1.0 as a radian, 0.19 deg as a flattening of 0.0033."""
    with pytest.raises(InputError):
        call()
    with u.set_enabled_equivalencies(u.dimensionless_angles()):
        with pytest.raises(InputError):
            call()


def test_numpy_raising_on_underflow_does_not_stop_a_run():
    """np.seterr(all="raise") at the caller: a harmless underflow (16 eps 1e-300 at t = 0 in the
    integrator's step check, SciPy's truncated normal in a prior) raised FloatingPointError. The
    results are those of the default error handling."""
    scene = wobble.Scene(
        {"moments": [1.0, 2.0, 3.0] * KGM2},
        [1.0, 0.1, 1.0] * RAD_S,
        t_end=10 * u.s,
        samples=11,
        torques=[wobble.Torque.custom(lambda t, w, q: -0.01 * w, name="drag")],
    )
    want = wobble.run(scene)
    with np.errstate(all="raise"):
        got = wobble.run(scene)
        assert wobble.load_inversion_setup("earth") is not None
    np.testing.assert_array_equal(got.omega.values, want.omega.values)


def _run(code: str, **env_extra):
    env = {**os.environ, **env_extra}
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env)


def test_wobble_s_figures_leave_the_caller_s_matplotlib_backend_alone():
    """wobble.plot.top set matplotlib.use("Agg") on import: a caller's TkAgg, svg or pdf backend
    (and plt.show) were switched off."""
    out = _run(
        """
        import matplotlib
        matplotlib.use("svg")
        import wobble.plot.top
        print(matplotlib.get_backend())
        """
    )
    assert out.returncode == 0 and out.stdout.split() == ["svg"], out.stderr


def test_the_command_line_draws_whatever_mplbackend_says(tmp_path):
    """The command line only writes files: Agg, whatever MPLBACKEND names (a nonsense one was a
    traceback and exit 1)."""
    out = subprocess.run(
        [sys.executable, "-m", "wobble", "top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "60"]
        + ["--omega3", "10", "--plot", "t.png"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={**os.environ, "MPLBACKEND": "nonsense"},
    )
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "t.png").stat().st_size > 1000


def test_with_numba_s_compiler_switched_off_the_numpy_paths_run(tmp_path):
    """NUMBA_DISABLE_JIT=1: a top of 10,001 samples raised NotImplementedError (the compiled series'
    intrinsics cannot run as Python); now the NumPy paths do the work, with the same numbers."""
    code = """
        import numpy as np, sys, wobble, astropy.units as u
        top = wobble.HeavyTop(I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=60 * u.deg,
                              omega3=10 * u.rad / u.s)
        np.save(sys.argv[1], top.to_dataset(t_end=100 * u.s, samples=10_001).attitude.values)
        print("numba" in sys.modules)
    """
    out = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code), str(tmp_path / "q.npy")],
        capture_output=True,
        text=True,
        env={**os.environ, "NUMBA_DISABLE_JIT": "1"},
    )
    assert out.returncode == 0 and out.stdout.split() == ["False"], out.stderr
    top = wobble.HeavyTop(I1=1 * KGM2, I3=0.5 * KGM2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * RAD_S)
    want = top.to_dataset(t_end=100 * u.s, samples=10_001).attitude.values
    np.testing.assert_array_equal(np.load(tmp_path / "q.npy"), want)


def test_a_kernel_numba_cannot_cache_is_compiled_in_memory():
    """A read-only installation with no writable cache directory: Numba's cache=True raised "cannot
    cache function ...: no locator available". compiled.njit compiles such a kernel in memory instead.
    (A function made by exec has no file, so no cache locator: the same error.)"""
    from wobble.numerics import compiled

    if not compiled.available():
        pytest.skip("Numba not installed")
    import numba

    namespace: dict = {}
    exec("def twice(x):\n    return 2.0 * x\n", namespace)
    with pytest.raises(RuntimeError, match="cannot cache"):
        numba.njit(cache=True)(namespace["twice"])
    assert compiled.njit(nogil=True)(namespace["twice"])(1.5) == 3.0


def test_a_planet_file_named_like_a_catalogued_planet_is_that_file(tmp_path, monkeypatch, capsys):
    """`wobble chandler --body-file earth` with one's own file named earth ran the catalogued Earth."""
    from cli_run import run_cli

    monkeypatch.chdir(tmp_path)
    assert run_cli(["example", "my_planet.toml"], capsys)[0] == 0
    (tmp_path / "my_planet.toml").rename(tmp_path / "earth")
    status, out, err = run_cli(["chandler", "--body-file", "earth", "--model", "rigid"], capsys)
    assert status == 0 and out.startswith("My planet"), err
    status, out, _ = run_cli(["chandler", "earth", "--model", "rigid"], capsys)  # the name is the catalogue's
    assert status == 0 and out.startswith("Earth:")


def test_a_shipped_scene_runs_by_its_file_name_from_any_folder(tmp_path, monkeypatch):
    """wobble.run("tennis_racket.toml") in a folder without that file said "no such file", where
    `wobble run tennis_racket.toml` ran the shipped scene."""
    monkeypatch.chdir(tmp_path)
    by_file, by_name = wobble.run("tennis_racket.toml"), wobble.run("tennis_racket")
    np.testing.assert_array_equal(by_file.omega.values, by_name.omega.values)
    with pytest.raises(InputError, match="^scene: got nope.toml; allowed: an existing file"):
        wobble.run("nope.toml")
