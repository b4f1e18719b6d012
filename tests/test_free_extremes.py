"""`wobble free` at the ends of the float range (fuzzing review): closed forms, not the code's own output.

* Rates whose kinetic energy E = 1/2 sum I w^2 is below the smallest normal double (2.2e-308 J) are
  refused, naming --omega and the least |omega| in the given direction: for I = (1, 2, 3) and
  omega = c (1, 1, 1), E = 3 c^2, so the least is c = sqrt(tiny/3), |omega| = sqrt(tiny). They printed
  "kinetic energy 0 J", |L| = 0 in the file with a "drift" of all of |L|, or (for 1e-310 rad/s) "the spin
  is steady" and "time between flips inf".
* Subnormal moments (below 2.2e-308 kg m2) are refused naming --inertia, as the heavy top's are.
* Above that bound E and |L| are exact closed forms at every sample, even where w^2 or (I w)^2 underflow.
* A periodic motion whose period is past the largest double is refused (it printed "omega never repeats").
* A default span (3 periods) past the largest double names --t-end (it warned of an overflow, then
  complained of "--t-end: got inf s" that nobody typed).
"""

from __future__ import annotations

import math
import sys

import astropy.units as u
import mpmath as mp
import numpy as np
import pytest
from cli_run import run_cli

import wobble.errors
from wobble import FreeRotation

KGM2 = u.kg * u.m**2
RAD_S = u.rad / u.s
TINY = sys.float_info.min


def _one_line(err):
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err and "Warning" not in err
    return lines[0]


@pytest.mark.parametrize("w", ["1e-307", "1e-310", "1e-300"])
def test_rates_whose_energy_is_below_the_normal_doubles_are_refused(w, capsys):
    code, out, err = run_cli(["free", "--inertia", "1", "2", "3", "--omega", w, w, w, "-o", "never.nc"], capsys)
    line = _one_line(err)
    assert code == 2 and out == ""
    assert line.startswith(f"wobble free: error: --omega: got {w} {w} {w}; allowed: ")
    # The least |omega| in the direction (1, 1, 1): E = 3 c^2 = tiny, |omega| = sqrt(3) c = sqrt(tiny).
    least = float(line.split("|omega| >= ")[1].split()[0])
    assert math.sqrt(TINY) <= least <= math.sqrt(TINY) * 1.01


@pytest.mark.parametrize(
    ("moments", "omega"),
    [(["1e-320", "2e-320", "3e-320"], ["1e7", "1e6", "1e7"]), (["1", "2", "3e-320"], ["1", "0.1", "1"])],
)
def test_subnormal_moments_are_refused_naming_inertia(moments, omega, capsys, tmp_path):
    # Was accepted: 1e-320 2e-320 3e-320 kg m2 ran, printing |L| = 3.168561e-313 to seven digits that subnormals
    # do not hold. Refused as the heavy top refuses a subnormal I1 or I3.
    path = tmp_path / "never.nc"
    code, out, err = run_cli(["free", "--inertia", *moments, "--omega", *omega, "-o", str(path)], capsys)
    assert code == 2 and out == "" and not path.exists()
    assert _one_line(err) == (
        f"wobble free: error: --inertia: got {' '.join(moments)}; allowed: three principal moments of at least "
        "2.225e-308 kg m2 each, the smallest normal double"
    )
    with pytest.raises(wobble.errors.InputError, match=r"^moments: got .*; allowed: three principal moments of at"):
        FreeRotation([1e-320, 2e-320, 3e-320] * KGM2, [1e7, 1e6, 1e7] * RAD_S)


def test_the_review_input_just_above_the_bound_is_exact(tmp_path):
    c = 1e-154  # E = 3 c^2 = 3e-308 J: normal; w^2 = 1e-308 at the edge, (I w)^2 for |L| underflows
    body = FreeRotation([1, 2, 3] * KGM2, [c, c, c] * RAD_S)
    ds = body.to_dataset(t_end=3 * body.period, samples=101)
    with mp.workdps(40):
        e = float(mp.mpf(c) ** 2 * 3)
        big_l = float(mp.mpf(c) * mp.sqrt(14))
    assert body.energy.to_value(u.J) == pytest.approx(e, rel=4e-16, abs=0)
    assert body.angular_momentum.to_value(KGM2 / u.s) == pytest.approx(big_l, rel=4e-16, abs=0)
    np.testing.assert_allclose(ds["kinetic_energy"].values, e, rtol=1e-13)
    np.testing.assert_allclose(ds["angular_momentum_magnitude"].values, big_l, rtol=1e-13)
    assert np.max(np.abs(ds["angular_momentum_magnitude_drift"].values)) <= 1e-13 * big_l


def test_tiny_rates_of_a_heavy_body_keep_energy_and_angular_momentum():
    """I = 1e300 kg m2, omega = 1e-300 rad/s: E ~ 1e-300 J and |L| ~ 1 are ordinary numbers, though w^2 underflows."""
    moments, omega = [1e300, 2e300, 3e300], [1e-300, 1e-301, 1e-300]
    body = FreeRotation(moments * KGM2, omega * RAD_S)
    ds = body.to_dataset(t_end=body.period, samples=51)
    with mp.workdps(50):
        I = [mp.mpf(x) for x in moments]
        w = [mp.mpf(x) for x in omega]
        e = float(sum(i * x * x for i, x in zip(I, w)) / 2)
        big_l = float(mp.sqrt(sum((i * x) ** 2 for i, x in zip(I, w))))
    np.testing.assert_allclose(ds["kinetic_energy"].values, e, rtol=1e-13)
    np.testing.assert_allclose(ds["angular_momentum_magnitude"].values, big_l, rtol=1e-13)


def test_steady_spin_of_tiny_rate_turns_about_its_own_axis():
    """omega = 1e-200 rad/s about x (I = 1e200 kg m2): after 1e200 s the body has turned 1 rad about x,
    q = (cos 1/2, sin 1/2, 0, 0). |omega|^2 underflowed and the axis fell back to z."""
    body = FreeRotation([1e200, 2e200, 3e200] * KGM2, [1e-200, 0.0, 0.0] * RAD_S)
    assert body.regime == "steady"
    with mp.workdps(30):
        angle = float(mp.mpf(1e-200) * mp.mpf(1e200))
    q = body.attitude([1e200] * u.s)[0]
    np.testing.assert_allclose(q, [math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0], atol=1e-15)


def test_a_period_past_the_largest_double_is_refused(capsys):
    # Symmetric, I1 = I2 = 1, I3 = 2: omega turns at (I3 - I1) w3 / I1 = 1e-310 rad/s, a period of 6.3e310 s.
    code, out, err = run_cli(["free", "--inertia", "1", "1", "2", "--omega", "1", "0", "1e-310"], capsys)
    line = _one_line(err)
    assert code == 2 and out == ""
    assert line.startswith("wobble free: error: --omega: got 1 0 1e-310; allowed: ")
    assert "6.28e+310 s" in line


def _closed_form_period(moments, omega) -> mp.mpf:
    """omega's period 4 K(k^2) / lambda from the moments and omega(0), at 40 digits (Landau & Lifshitz,
    Mechanics, sec. 37): lambda^2 = (I3 - I2)(L^2 - 2T I1) / (I1 I2 I3),
    k^2 = (I2 - I1)(2T I3 - L^2) / ((I3 - I2)(L^2 - 2T I1)) for I1 < I2 < I3 and L^2 > 2T I2
    (I1 and I3 exchanged below it)."""
    with mp.workdps(40):
        inertia = [mp.mpf(x) for x in moments]
        w = [mp.mpf(x) for x in omega]
        two_t = sum(i * x * x for i, x in zip(inertia, w))
        l2 = sum((i * x) ** 2 for i, x in zip(inertia, w))
        i1, i2, i3 = inertia if l2 > two_t * inertia[1] else inertia[::-1]
        lam = mp.sqrt((i3 - i2) * (l2 - two_t * i1) / (i1 * i2 * i3))
        k2 = (i2 - i1) * (two_t * i3 - l2) / ((i3 - i2) * (l2 - two_t * i1))
        return 4 * mp.ellipk(k2) / lam


def test_a_default_span_past_the_largest_double_names_t_end(capsys):
    # Period 4 K(1/2) / lambda = 6.4227e307 s (L^2 = 14, 2T = 6e-307, k^2 = 1/2): 3 periods overflow.
    moments, omega = [1e307, 2e307, 3e307], [1e-307] * 3
    with mp.workdps(40):
        exact = _closed_form_period(moments, omega)
        assert 3 * exact > mp.mpf(sys.float_info.max) > exact  # the closed form says the default overflows
    argv = ["free", "--inertia", "1e307", "2e307", "3e307", "--omega", "1e-307", "1e-307", "1e-307"]
    code, out, err = run_cli([*argv, "--plot", "never.png"], capsys)
    line = _one_line(err)
    assert code == 2 and out == ""
    assert line.startswith("wobble free: error: --t-end: missing; allowed: ")
    assert "past the largest double" in line
    # The period the message names (6 digits) and the one the refusal was decided on are the closed form's.
    assert float(line.split("3 x ")[1].split()[0]) == pytest.approx(float(exact), rel=5e-6)
    period = FreeRotation(moments * KGM2, omega * RAD_S).period.to_value(u.s)
    assert period == pytest.approx(float(exact), rel=1e-13)


@pytest.mark.parametrize("samples", [1001, 3])
def test_a_span_too_short_for_distinct_samples_is_refused(samples, capsys, tmp_path):
    """--t-end 5e-324 wrote 1001 times with 2 distinct values (CF requires them increasing). The least span is
    (samples - 1) times the smallest normal double, the step then being exactly that double."""
    path = tmp_path / "f.nc"
    argv = ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "--t-end", "5e-324"]
    code, out, err = run_cli([*argv, "--samples", str(samples), "-o", str(path)], capsys)
    line = _one_line(err)
    assert code == 2 and out == "" and not path.exists()
    assert line.startswith("wobble free: error: --t-end: got 5e-324; allowed: an end time of at least ")
    assert float(line.split("at least ")[1].split()[0]) == pytest.approx((samples - 1) * TINY, rel=1e-3, abs=0)
    body = FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    t = body.to_dataset(t_end=(samples - 1) * TINY * u.s, samples=samples)["time"].values
    np.testing.assert_array_equal(t, np.arange(samples) * TINY)


def test_the_figure_of_a_span_of_1e_300_s_draws_omega():
    """Over 1e-300 s omega(t) = omega(0) = (1, 0.1, 1) rad/s to rounding (omega changes at about 1 rad/s^2);
    matplotlib drew no curve for spans below about 1e-287 s, in seconds. In units of 1e-300 s it does."""
    import matplotlib.pyplot as plt

    from wobble.plot.free import motion_figure

    body = FreeRotation([1, 2, 3] * KGM2, [1, 0.1, 1] * RAD_S)
    fig = motion_figure(body, 1e-300 * u.s)
    top, bottom = fig.axes[0], fig.axes[1]
    assert bottom.get_xlabel() == "time [$10^{-300}$ s]"
    lines = {line.get_label(): line for line in top.get_lines()}
    x, y = lines["$\\omega_1$"].get_data()
    assert x[0] == 0.0 and x[-1] == pytest.approx(1.0, rel=1e-15)
    np.testing.assert_allclose(y, 1.0, rtol=1e-15)
    np.testing.assert_allclose(lines["$\\omega_2$"].get_ydata(), 0.1, rtol=1e-15)
    pixels = top.transData.transform(np.column_stack([x, y]))
    assert np.all(np.isfinite(pixels)) and np.ptp(pixels[:, 0]) > 0.9 * top.get_window_extent().width
    plt.close(fig)
