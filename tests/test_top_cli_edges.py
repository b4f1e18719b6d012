"""`wobble top` at the edges of the float range (fuzzing review): messages, figures, -0.

* --t-end too short for its samples to be distinct: refused naming --t-end and the least, (samples - 1)
  times the smallest normal double (it wrote 1001 times with 2 values; CF needs them increasing).
* Rates whose energy overflows: the options given, as typed, and the defaults used, named as such (it named
  --thetadot0, --phidot0, --omega3 over a tuple of converted numbers for --phidot0 '1e300 deg/s' alone).
* --theta0 -0.0 is 0 (it printed "theta min, max -0, -0 deg"); a subnormal tilt is refused, and a subnormal
  moment is blamed on its own option (a subnormal --I1 was blamed on --I3 through I3 <= 2 I1).
* The figure of a top tilted 1e-16 rad (or 1e-300) draws its path (a start dot in a unit frame before).
"""

from __future__ import annotations

import json
import math

import astropy.units as u
import matplotlib
import numpy as np
import pytest
from cli_run import run_cli

from wobble import HeavyTop

matplotlib.use("Agg")

TINY = np.finfo(float).tiny
TOP = ["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--omega3", "10"]


def _one_line(err):
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err and "Warning" not in err, err
    return lines[0]


@pytest.mark.parametrize("samples", [1001, 11])
def test_a_span_too_short_for_distinct_samples_is_refused(samples, capsys, tmp_path):
    path = tmp_path / "t.nc"
    argv = [*TOP, "--theta0", "60", "--t-end", "5e-324", "--samples", str(samples), "-o", str(path)]
    code, out, err = run_cli(argv, capsys)
    line = _one_line(err)
    assert code == 2 and out == "" and not path.exists()
    assert line.startswith("wobble top: error: --t-end: got 5e-324; allowed: an end time of at least ")
    least = float(line.split("at least ")[1].split()[0])
    assert least == pytest.approx((samples - 1) * TINY, rel=1e-3, abs=0)


def test_the_least_span_gives_evenly_spaced_increasing_times():
    top = HeavyTop(
        I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * u.rad / u.s
    )
    ds = top.to_dataset(t_end=1000 * TINY * u.s, samples=1001)
    t = ds["time"].values
    np.testing.assert_array_equal(t, np.arange(1001) * TINY)  # k 2^-1022 s, exactly
    assert np.all(np.diff(t) > 0)


@pytest.mark.parametrize(
    "extra, want",
    [
        (["--phidot0", "1e300 deg/s"], "--phidot0, --omega3: got 1e300 deg/s, 10 (and the default --thetadot0 0);"),
        (["--phidot0", "1", "--thetadot0", "1e300 rad/s"], "--thetadot0, --phidot0, --omega3: got 1e300 rad/s, 1, 10;"),
    ],
)
def test_an_energy_that_overflows_names_what_was_typed(extra, want, capsys):
    code, out, err = run_cli([*TOP, "--theta0", "60", *extra], capsys)
    line = _one_line(err)
    assert code == 2 and out == ""
    assert line.startswith(f"wobble top: error: {want} allowed: rates whose energy fits double precision")


def test_negative_zero_is_zero(capsys):
    argv = [*TOP, "--theta0", "-0.0", "--phidot0", "-0.0", "--thetadot0", "-0.0", "--phi0", "-0.0"]
    code, out, err = run_cli([*argv, "--mgl", "-0.0"], capsys)
    assert code == 0 and err == ""
    assert "theta min, max               0, 0 deg" in out, out
    assert "-0" not in out
    code, out, err = run_cli([*argv, "--json"], capsys)
    doc = json.loads(out)
    assert doc["theta_min_deg"] == 0.0 and math.copysign(1.0, doc["theta_min_deg"]) == 1.0
    assert "-0.0" not in out


def test_a_subnormal_tilt_is_refused(capsys):
    code, out, err = run_cli([*TOP, "--theta0", "1e-320 rad"], capsys)
    line = _one_line(err)
    assert code == 2 and out == ""
    assert line == (
        "wobble top: error: --theta0: got 1e-320 rad; allowed: 0 (upright) or a tilt of at least "
        "2.225e-308 rad (1.275e-306 deg), the smallest normal double"
    )


@pytest.mark.parametrize(
    ("moments", "option", "typed"),
    [(["--I1", "1e-320", "--I3", "0.5"], "--I1", "1e-320"), (["--I1", "1", "--I3", "1e-320"], "--I3", "1e-320")],
)
def test_a_subnormal_moment_is_blamed_on_its_own_option(moments, option, typed, capsys, tmp_path):
    # Was, for --I1 1e-320: "--I3: got 0.5; allowed: I3 <= 2 I1 = 1.99998e-320 kg m2", blaming the sound I3.
    path = tmp_path / "t.nc"
    argv = ["top", *moments, "--mgl", "1", "--omega3", "10", "--theta0", "60", "-o", str(path)]
    code, out, err = run_cli(argv, capsys)
    assert code == 2 and out == "" and not path.exists()
    assert _one_line(err) == (
        f"wobble top: error: {option}: got {typed}; allowed: a moment of at least 2.225e-308 kg m2, the smallest "
        "normal double"
    )


@pytest.mark.parametrize("theta0", [1e-16, 1e-300])
def test_the_figure_of_a_tiny_tilt_draws_its_path(theta0):
    """Released at rest next to the vertical (notes p. 72, small theta): with x = 1 - cos theta,
    g(x) ~ (x - x0)(2 beta x - a^2 (x - x0)), so theta_max = theta0 a / sqrt(a^2 - 2 beta) (a = I3 omega3 / I1 = 5/s,
    beta = 2 M g l / I1 = 2/s^2), exact to O(theta^2). The path must be drawn between those circles, inside the
    axes, in a power of ten of rad."""
    from wobble.plot.top import axis_locus_figure

    top = HeavyTop(
        I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=theta0 * u.rad, omega3=10 * u.rad / u.s
    )
    theta_max = theta0 * 5.0 / math.sqrt(25.0 - 4.0)
    assert top.model.theta_max == pytest.approx(theta_max, rel=1e-12, abs=0)
    fig = axis_locus_figure(top, 3 * top.model.nutation_period * u.s)
    ax = fig.axes[0]
    path = max(ax.get_lines(), key=lambda line: len(line.get_xdata()) if line.get_color() == "C0" else 0)
    exponent = 3 * math.floor(math.log10(theta0) / 3)
    assert f"$10^{{{exponent}}}$ rad" in ax.get_xlabel()
    radius = np.hypot(path.get_xdata(), path.get_ydata()) * 10.0**exponent
    assert np.all(radius >= theta0 * (1 - 1e-9)) and np.all(radius <= theta_max * (1 + 1e-9))
    assert np.max(radius) == pytest.approx(theta_max, rel=1e-3, abs=0)  # the cusps' far circle is reached
    # Drawn: in display coordinates the path is finite and spans much of the axes.
    pixels = ax.transData.transform(np.column_stack([path.get_xdata(), path.get_ydata()]))
    box = ax.get_window_extent()
    assert np.all(np.isfinite(pixels))
    assert np.ptp(pixels[:, 0]) > 0.1 * box.width and np.ptp(pixels[:, 1]) > 0.1 * box.height  # a dot before
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_a_horizontal_top_has_one_steady_precession_rate(capsys):
    """--theta0 90 is horizontal: u2, E' and p_phi print as 0 (not 6.1e-17, the cosine of the float
    nearest pi/2), and the fast steady precession, infinite there, is said to be absent (it printed
    "fast 8.16562e+16 rad/s")."""
    code, out, err = run_cli([*TOP, "--theta0", "90"], capsys)
    assert code == 0, err
    # At rest with u0 = 0: alpha = 2E'/I1 = 0 and b = 0, so f(u) = -beta u (1 - u^2) - a^2 u^2 (notes p. 71)
    # has the roots 0 and (a^2 -+ sqrt(a^4 + 4 beta^2)) / (2 beta), with a = I3 omega3 / I1 = 5, beta = 2.
    a, beta = 5.0, 2.0
    u1, u3 = ((a * a + s * math.sqrt(a**4 + 4 * beta**2)) / (2 * beta) for s in (-1, 1))
    assert f"roots u1, u2, u3             {u1:.7g}, 0, {u3:.7g}" in out
    assert "energy E, E'                 25, 0 J" in out and "p_phi, p_psi                 0, 5 kg m2/s" in out
    assert "slow 0.2 rad/s (no fast one: the axis is horizontal)" in out and "e+16" not in out
    code, out, err = run_cli([*TOP, "--theta0", "90", "--json"], capsys)
    reg = json.loads(out)["regular_precession_at_theta0"]
    assert reg == {"slow_rad_per_s": 0.2, "fast_rad_per_s": None}


@pytest.mark.parametrize("tilt", [1e-90, 1e-100, 1e-300])
def test_an_upright_top_too_near_its_separatrix_names_the_tilt(tilt, capsys):
    """Below the sleeping spin (omega3 = 3 < 2 sqrt(M g l I1)/I3 = 4) and released 1e-100 rad from upright, the
    top lies 1 - m ~ theta0^2 from its separatrix, past what the Carlson integrals resolve. The refusal named
    --thetadot0, which the user had not given, and printed 1 - m = 0 once it underflowed (1e-300 rad)."""
    code, out, err = run_cli(
        ["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", f"{tilt:g} rad", "--omega3", "3"], capsys
    )
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"wobble top: error: --theta0, --omega3: got {tilt:g} rad, 3"), err
    # Released at rest, f(u) = (u0 - u)[beta (1 - u^2) - a^2 (u0 - u)] (notes p. 72; a = 1.5/s, beta = 2/s^2):
    # u1 = (a^2 - beta)/beta = 1/8 and u3 = 1 + a^2/(2 beta - a^2) x0 = 1 + (9/7) x0 to first order in
    # x0 = theta0^2/2, so 1 - m = (u3 - u0)/(u3 - u1) = (16/7)(8/7) x0 = (64/49) theta0^2. In decimal: 1e-600
    # for 1e-300 rad is below the doubles. The message gives three digits.
    from decimal import Decimal

    gap = Decimal(err.split("1 - m = ")[1].split(" ")[0])
    assert float(gap / Decimal(tilt) ** 2) == pytest.approx(64 / 49, rel=5e-3)
