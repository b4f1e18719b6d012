"""Bayesian inversion of a planet's parameters from its observed wobble, tides and rotation.

One idea per module:

* :mod:`~wobble.models.inversion.priors`: proper priors (uniform, log-uniform,
  truncated normal) on SI floats;
* :mod:`~wobble.models.inversion.observables`: the forward-model registry (an
  observable is one registered function of the parameter arrays);
* :mod:`~wobble.models.inversion.likelihood`: the vectorised posterior
  (priors times a Gaussian likelihood);
* :mod:`~wobble.models.inversion.sampling`: the emcee ensemble sampler driver;
* :mod:`~wobble.models.inversion.calibration`: injection–recovery (simulation-based
  calibration) of the whole chain.

Everything here is SI float64 and NumPy (emcee is NumPy-only); units, xarray and
ArviZ live in :mod:`wobble.api.inversion`.
"""
