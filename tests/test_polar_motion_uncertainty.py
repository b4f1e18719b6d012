"""A randomly excited wobble: the Monte-Carlo excitation term makes the period error honest."""

from __future__ import annotations

import numpy as np
from polar_synthetic import REFERENCE_PERIOD, TRUTH, record

from wobble.models import polar_motion as pm


def test_coverage_for_a_randomly_excited_wobble():
    """Damped free mode of Q = 100 (seed 7, six 30-year records): the mode's period within the stated sigma.

    Without the Monte-Carlo excitation term the errors would be several
    times the stated ones (the record's mean frequency wanders about the
    mode's frequency); with it the normalised errors have unit scale.
    """
    rng = np.random.default_rng(7)
    z, z_auto = [], []
    for _ in range(6):
        t, p = record(rng, 30, chandler="damped", q=100.0)
        f = pm.fit_least_squares(t, p, reference_period=REFERENCE_PERIOD, excitation_q=100.0, draws=16)
        err = f.chandler.period - TRUTH["period"]
        z.append(err / f.chandler.period_sigma)
        z_auto.append(err / f.period_uncertainty.autocorrelation)
    z = np.array(z)
    assert np.all(np.abs(z) < 3.0), z
    assert 0.1 < np.mean(z**2) < 3.0, z
    assert np.mean(np.square(z_auto)) > 4 * np.mean(z**2)
