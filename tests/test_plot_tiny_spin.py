"""Figures of spins so slow that squaring their components underflows (wobble.numerics.scaled_norm.norm).

np.linalg.norm squares before it sums: |omega| of 1e-170 rad/s came out 0 (1e-160 as 9.99994e-161). The free
figure divided by it (NumPy's divide-by-zero warnings on stderr), drew no curves, and read |omega(0)| = 0; the
polhode of 1e-170 rad/s about e1 was drawn as a body at rest (found by the command-line fuzzer, seed 401).
"""

from __future__ import annotations

import math
import re

import mpmath
import numpy as np
import pytest
from astropy import units as u
from hypothesis import given
from hypothesis import strategies as st

import wobble
from wobble.numerics.scaled_norm import norm


@given(st.lists(st.floats(-1e300, 1e300, allow_nan=False), min_size=3, max_size=3))
def test_norm_is_the_euclidean_length_at_any_scale(v):
    """Against mpmath at 40 digits, to a few ulps, from subnormal components to 1e300."""
    with mpmath.workdps(40):  # not mp.dps = 40: that leaked into every later test of the worker
        exact = mpmath.sqrt(sum(mpmath.mpf(float(x)) ** 2 for x in v))
    if exact == 0:
        assert float(norm(v)) == 0.0
        return
    assert float(norm(v)) == pytest.approx(float(exact), rel=4e-16, abs=0)


def test_norm_keeps_axes_and_zero_and_nan_vectors():
    v = np.array([[[1e-170, 0.0, 1e-175], [0.0, 0.0, 0.0], [np.nan, 1.0, 0.0]]])
    assert norm(v).shape == (1, 3) and norm(v, keepdims=True).shape == (1, 3, 1)
    assert norm(v)[0, 0] == pytest.approx(math.hypot(1e-170, 1e-175), rel=1e-15, abs=0)
    assert norm(v)[0, 1] == 0.0 and np.isnan(norm(v)[0, 2])
    assert norm(v, axis=0).shape == (3, 3)


@pytest.mark.parametrize("omega", [[1e-170, 0.0, 1e-175], [1e-170, 1e-180, 0.0]])
def test_the_free_figure_of_a_tiny_spin_draws_it_as_any_other(omega, recwarn):
    """Drawn as the same body at 1 rad/s: the same curves in units of |omega(0)|, and the polhode seen down e1.
    The moments are 1e40 kg m2 and up: a body of 1 kg m2 at 1e-170 rad/s has a kinetic energy of 1e-340 J, below
    the normal doubles, and is refused (tests/test_free_extremes.py); here E = 1e-300 J while omega^2 underflows."""
    from wobble.plot.free import motion_figure

    moments = [1e40, 2e40, (2.0 + omega[1] * 1e170) * 1e40] * u.kg * u.m**2
    tiny = motion_figure(wobble.FreeRotation(moments, omega * u.rad / u.s), 10 * u.s)
    spin = math.hypot(*omega)
    legends = [ax.get_legend() for ax in tiny.axes if ax.get_legend() is not None]
    titles = [legend.get_title().get_text() for legend in legends]
    assert any(f"= {spin:.4g} rad" in title for title in titles), titles  # it read |omega(0)| = 0
    for ax in tiny.axes[:2]:
        for line in ax.get_lines():
            assert np.all(np.isfinite(line.get_ydata())), "a curve of NaN (divided by an underflowed |omega|)"
    # The values drawn: over 10 s omega does not move (its polhode takes 1e170 s), so the two small components
    # are omega_k(0) / |omega(0)|, here from mpmath at 30 digits, in the power of ten the axis names.
    top = tiny.axes[0]
    power = re.search(r"10\^\{(-?\d+)\}", top.get_ylabel())
    scale = 10.0 ** int(power.group(1)) if power else 1.0
    with mpmath.workdps(30):
        norm_exact = mpmath.sqrt(sum(mpmath.mpf(w) ** 2 for w in omega))
        want = sorted(float(mpmath.mpf(omega[k]) / norm_exact) for k in (1, 2))
    drawn = sorted(float(np.mean(line.get_ydata())) * scale for line in top.get_lines()[:2])
    np.testing.assert_allclose(drawn, want, rtol=1e-14, atol=1e-15)  # atol: rounding, in units of |omega(0)|
    assert tiny.axes[2].name != "3d" and "seen down $e_1$" in tiny.axes[2].get_title()
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]
