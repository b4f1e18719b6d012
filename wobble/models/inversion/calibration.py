"""Injection–recovery: is the inversion honest about its own uncertainty?

Simulation-based calibration (Cook, Gelman & Rubin 2006, J. Comput. Graph. Stat. 15,
675; Talts et al. 2018, arXiv:1804.06788): draw "true" parameters from the prior,
simulate measurements from them with the likelihood's own noise, invert those, and
ask how often the truth lies inside the posterior's central 68 % and 95 % intervals.
If the sampler and the likelihood are right, the coverage equals the nominal level
(averaged over the prior), and the rank of the truth among independent posterior
draws is uniform. Under-coverage means overconfident intervals; over-coverage,
intervals wider than the data warrant.

Each draw is an independent unit (:func:`recover_one`), so the API and
``scripts/calibrate_inversion.py`` can run them on any dask scheduler.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from wobble.errors import InputError
from wobble.models.inversion.likelihood import Posterior
from wobble.models.inversion.sampling import SamplerSettings, run_emcee

__all__ = ["Recovery", "inject", "recover_one", "coverage", "LEVELS", "central_interval"]

LEVELS = (0.68, 0.95)
_TRUTH_ATTEMPTS = 1000


def central_interval(samples: np.ndarray, level: float, axis=0) -> tuple[np.ndarray, np.ndarray]:
    """The central ``level`` interval (equal tails) of ``samples`` along ``axis``."""
    tail = 50.0 * (1.0 - level)
    return np.percentile(samples, tail, axis=axis), np.percentile(samples, 100.0 - tail, axis=axis)


@dataclass(frozen=True)
class Recovery:
    """One injected truth and what the inversion of its synthetic data recovered (SI).

    Attributes
    ----------
    index : int
        The draw's number (its random streams depend only on the seed and this).
    truth, median : numpy.ndarray
        Per parameter.
    lower, upper : dict
        Level -> per-parameter bounds of the central interval.
    rank : numpy.ndarray
        Number of ``rank_draws`` thinned posterior draws below the truth (SBC rank).
    rank_draws : int
    synthetic : dict
        The simulated measurements, observable -> value.
    min_ess : float
        Smallest effective sample size (walkers x draws / autocorrelation time).
    seconds : float
    """

    index: int
    truth: np.ndarray
    median: np.ndarray
    lower: dict
    upper: dict
    rank: np.ndarray
    rank_draws: int
    synthetic: dict
    min_ess: float
    seconds: float

    def covered(self, level: float) -> np.ndarray:
        return (self.lower[level] <= self.truth) & (self.truth <= self.upper[level])


def _rng(seed, index: int, stream: int) -> np.random.Generator:
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=(index, stream))))


def inject(posterior: Posterior, seed, index: int) -> tuple[np.ndarray, dict[str, float]]:
    """A truth drawn from the prior and measurements simulated from it with Gaussian noise.

    Truths at which a forward model has no answer are redrawn (the prior is then
    effectively truncated to the physical region, as the posterior is).
    """
    rng = _rng(seed, index, 0)
    for _ in range(_TRUTH_ATTEMPTS):
        truth = np.array([p.prior.draw(rng, 1)[0] for p in posterior.parameters])
        pred = posterior.predict(truth[None, :], [m.name for m in posterior.measured])
        if all(np.isfinite(v[0]) for v in pred.values()):
            break
    else:
        raise InputError(
            "priors", ", ".join(posterior.names), "priors with physical draws (the forward model failed on every draw)"
        )
    noise = _rng(seed, index, 1).standard_normal(len(posterior.measured))
    synthetic = {m.name: float(pred[m.name][0] + m.sigma * z) for m, z in zip(posterior.measured, noise)}
    return truth, synthetic


def recover_one(posterior: Posterior, settings: SamplerSettings, seed, index: int, rank_draws: int = 99) -> Recovery:
    """Inject truth number ``index``, invert its synthetic data, and compare.

    Parameters
    ----------
    posterior : Posterior
        The setup (its priors generate the truths; its uncertainties the noise).
    settings : SamplerSettings
        Sampler settings for each inversion.
    seed : int
        Base seed; draw ``index`` uses streams derived from (seed, index).
    index : int
        Which draw.
    rank_draws : int
        Thinned posterior draws for the SBC rank.
    """
    if not posterior.measured:
        raise InputError("observables", "none measured", "at least one measured observable to inject")
    truth, synthetic = inject(posterior, seed, index)
    chains = run_emcee(posterior.with_measured_values(synthetic), settings, seed=_seed_words(seed, index))
    flat = chains.samples.reshape(-1, posterior.ndim)
    lower, upper = {}, {}
    for level in LEVELS:
        lower[level], upper[level] = central_interval(flat, level)
    # Thinned draws spread over walkers and time: nearly independent for the rank.
    pick = np.linspace(0, len(flat) - 1, rank_draws).round().astype(int)
    order = np.random.default_rng(_seed_words(seed, index)).permutation(len(flat))[pick]
    rank = np.sum(flat[order] < truth, axis=0)
    tau = np.nanmax(chains.autocorr) if np.any(np.isfinite(chains.autocorr)) else math.nan
    min_ess = flat.shape[0] / tau if tau and math.isfinite(tau) else math.nan
    return Recovery(
        index, truth, np.median(flat, axis=0), lower, upper, rank, rank_draws, synthetic, float(min_ess), chains.seconds
    )


def _seed_words(seed, index: int) -> list[int]:
    base = list(seed) if isinstance(seed, (list, tuple)) else [int(seed)]
    return [*base, 7919, int(index)]


def coverage(recoveries: Sequence[Recovery], names: Sequence[str]) -> dict:
    """Coverage of the central intervals per parameter, with its binomial standard error.

    Returns
    -------
    dict
        parameter -> {"68": fraction, "95": fraction, "n": draws,
        "se_68": sqrt(0.68 x 0.32/n), "se_95": ...}, in fractions (not percent).
    """
    n = len(recoveries)
    if n == 0:
        raise InputError("recoveries", 0, "at least one injection")
    out = {}
    for i, name in enumerate(names):
        row = {"n": n}
        for level in LEVELS:
            hits = sum(bool(r.covered(level)[i]) for r in recoveries)
            key = f"{round(100 * level)}"
            row[key] = hits / n
            row[f"se_{key}"] = math.sqrt(level * (1 - level) / n)
        out[name] = row
    return out
