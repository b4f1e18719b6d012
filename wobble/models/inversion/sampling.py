"""Sampling the posterior with emcee, the affine-invariant ensemble sampler.

emcee (Foreman-Mackey et al. 2013, PASP 125, 306) moves an ensemble of walkers, half
of them at a time, each half with proposals built from the other half. The moves are a
mixture (:data:`MOVES` by default; a setup may choose its own): 80 % an *independence* move
(:func:`_independence_move`: a Student t proposal with the mean and covariance of the other half), 15 % differential
evolution (ter Braak 2006, Stat. Comput. 16, 239; Nelson, Ford & Payne 2014, ApJS 210,
11) and 5 % its snooker variant (ter Braak & Vrugt 2008, Stat. Comput. 18, 435). All
are invariant under linear maps of the parameters, so correlated and badly scaled
parameters (a core radius in metres beside a Love number, a core moment of 1e36 kg m2
beside a compliance of 1e-4) cost nothing extra. The wobble posteriors are nearly
Gaussian, and there a proposal from the ensemble's own mean and covariance makes
successive draws nearly independent: with 64 walkers the autocorrelation time is about
10 steps for the eight-parameter Mars and Earth setups, against about 40 for the
stretch move of Goodman & Weare (2010) mixed with differential evolution and 50 for
the earlier mixture (half stretch), measured on the same setups. The
differential-evolution part explores along ridges, where an independence proposal is
poor; on the long curved ridge of the Chandler period alone (core radius against k2)
a setup mixes in the stretch move of Goodman & Weare (2010, Comm. App. Math. Comp.
Sci. 5, 65) instead, which is accepted more often there. The
ensemble's half-steps evaluate the posterior for half the walkers at once
(``vectorize=True``): one call of the vectorised forward model per half-step.

Walkers start from independent draws of the prior (only where the posterior is
positive), so a run never starts at the answer it is meant to find; the first
``burn`` steps are discarded. Same seed, same numbers: the starting draws and emcee's
own random state come from one ``numpy.random.SeedSequence``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from wobble.errors import InputError
from wobble.models.inversion.likelihood import Posterior

__all__ = ["SamplerSettings", "Chains", "run_emcee", "draw_prior", "start_positions", "MOVES", "MOVE_NAMES"]

# (move, weight): see the module docstring.
MOVES = (("independence", 0.8), ("de", 0.15), ("de_snooker", 0.05))
#: The moves a setup may mix (``[sampler] moves``).
MOVE_NAMES = ("independence", "stretch", "de", "de_snooker")
#: Degrees of freedom of the independence move's Student t proposal, and the widening of its scale.
T_DOF = 5.0
WIDEN = 1.2

_START_ATTEMPTS = 100


@dataclass(frozen=True)
class SamplerSettings:
    """How long and how wide to sample.

    Attributes
    ----------
    walkers : int
        Walkers per ensemble (even, at least twice the number of parameters).
    steps : int
        Steps kept per walker after the burn-in.
    burn : int
        Steps discarded at the start.
    thin : int
        Keep every ``thin``-th step.
    ensembles : int
        Independent ensembles (run in parallel on dask when a scheduler is given);
        their walkers are pooled as chains.
    prior_draws : int
        Independent prior draws stored beside the posterior.
    moves : tuple of (name, weight)
        The mixture of moves (:data:`MOVE_NAMES`; weights are normalised); default
        :data:`MOVES`.
    """

    walkers: int = 32
    steps: int = 6000
    burn: int = 1000
    thin: int = 1
    ensembles: int = 1
    prior_draws: int = 4000
    moves: tuple = MOVES

    def check(self, ndim: int) -> None:
        for name in ("walkers", "steps", "thin", "ensembles", "prior_draws"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise InputError(name, value, "a positive whole number")
        if isinstance(self.burn, bool) or not isinstance(self.burn, (int, np.integer)) or self.burn < 0:
            raise InputError("burn", self.burn, "a whole number >= 0")
        if self.walkers < 2 * ndim or self.walkers % 2:
            raise InputError("walkers", self.walkers, f"an even number >= {2 * ndim} (twice the {ndim} parameters)")
        if self.steps // self.thin < 2:
            raise InputError("steps", self.steps, f"at least {2 * self.thin} (two kept draws at thin = {self.thin})")
        names = [m[0] for m in self.moves]
        if not names or len(set(names)) != len(names) or any(n not in MOVE_NAMES for n in names):
            raise InputError(
                "moves", ", ".join(map(str, names)) or "none", f"each of {', '.join(MOVE_NAMES)} at most once"
            )
        for name, weight in self.moves:
            if isinstance(weight, bool) or not (
                isinstance(weight, (int, float)) and math.isfinite(weight) and weight > 0
            ):
                raise InputError(f"moves.{name}", weight, "a positive weight")

    def as_dict(self) -> dict:
        out = dict(self.__dict__)
        out["moves"] = {name: float(weight) for name, weight in self.moves}
        return out


@dataclass(frozen=True)
class Chains:
    """One ensemble's kept draws.

    Attributes
    ----------
    samples : numpy.ndarray
        Shape (walkers, draws, ndim), SI.
    log_posterior : numpy.ndarray
        Shape (walkers, draws).
    acceptance : numpy.ndarray
        Acceptance fraction of each walker over the whole run.
    autocorr : numpy.ndarray
        emcee's integrated autocorrelation time per parameter, in steps (after thinning).
    seconds : float
        Wall-clock time of the run.
    """

    samples: np.ndarray
    log_posterior: np.ndarray
    acceptance: np.ndarray
    autocorr: np.ndarray
    seconds: float


def _independence_move():
    """emcee's red-blue move with an independence proposal fitted to the complementary half
    (see :class:`IndependenceMove`); built on first use, as emcee is imported lazily."""
    from emcee.moves import RedBlueMove

    class IndependenceMove(RedBlueMove):
        """Independence Metropolis-Hastings from the other half of the ensemble.

        Each walker of the half being moved proposes a point drawn from a
        multivariate Student t (nu = :data:`T_DOF` degrees of freedom) whose centre
        and scale matrix are the mean and covariance of the *other* half, widened by
        :data:`WIDEN`; the Hastings factor is the ratio of that density at the
        current and the proposed point. The proposal depends only on the other half,
        which stays fixed while this half moves, so each update leaves the posterior
        invariant (the argument of Goodman & Weare 2010 for the stretch move, and of
        emcee's KDEMove, whose kernel estimate this replaces by one t density).
        Heavy tails keep the independence sampler honest where the posterior's
        tails are heavier than a Gaussian's (Tierney 1994, Ann. Stat. 22, 1701,
        sec. 2.3.3); on a nearly Gaussian posterior it proposes from almost the
        right distribution, so successive draws are nearly independent.
        """

        def get_proposal(self, s, c, random):
            c = np.concatenate(c, axis=0)
            n, ndim = s.shape
            # Standardised coordinates (a core moment of 1e36 beside a compliance of 1e-4).
            mean = c.mean(axis=0)
            scale = c.std(axis=0)
            if len(c) < 3 or not np.all(scale > 0):  # no spread to learn from: no move
                return s.copy(), np.full(n, -np.inf)
            if len(c) < 2 * ndim:  # too few walkers for a covariance: scales only
                corr = np.eye(ndim) * WIDEN**2
            else:
                corr = np.cov((c - mean) / scale, rowvar=False).reshape(ndim, ndim) * WIDEN**2
            try:
                chol = np.linalg.cholesky(corr)
            except np.linalg.LinAlgError:  # the other half is degenerate (on a plane): no move
                return s.copy(), np.full(n, -np.inf)
            w = random.chisquare(T_DOF, size=n) / T_DOF
            q = mean + scale * ((random.standard_normal((n, ndim)) @ chol.T) / np.sqrt(w)[:, None])

            def log_t(x):
                z = np.linalg.solve(chol, ((x - mean) / scale).T)
                return -0.5 * (T_DOF + ndim) * np.log1p(np.sum(z * z, axis=0) / T_DOF)

            return q, log_t(s) - log_t(q)

    return IndependenceMove()


def _rng(seed) -> np.random.Generator:
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed)))


def draw_prior(posterior: Posterior, n: int, seed) -> np.ndarray:
    """``n`` independent draws of the joint prior, shape (n, ndim), SI."""
    rng = _rng(seed)
    return np.stack([p.prior.draw(rng, n) for p in posterior.parameters], axis=-1)


def start_positions(posterior: Posterior, walkers: int, rng: np.random.Generator) -> np.ndarray:
    """Prior draws at which the posterior is positive, one per walker."""
    found = np.empty((0, posterior.ndim))
    for _ in range(_START_ATTEMPTS):
        need = walkers - len(found)
        batch = np.stack([p.prior.draw(rng, 4 * need) for p in posterior.parameters], axis=-1)
        ok = np.isfinite(posterior(batch))
        found = np.concatenate([found, batch[ok][:need]])
        if len(found) == walkers:
            return found
    raise InputError(
        "priors",
        ", ".join(posterior.names),
        f"priors under which the posterior is positive somewhere: {len(found)} of {_START_ATTEMPTS * 4 * walkers} "
        "prior draws had a finite likelihood (the data may contradict the priors, or the model fails there)",
    )


def run_emcee(
    posterior: Posterior,
    settings: SamplerSettings,
    seed,
    progress: Callable[[int, int], None] | None = None,
) -> Chains:
    """Run one emcee ensemble on ``posterior``.

    Parameters
    ----------
    posterior : Posterior
        The target (vectorised over walkers).
    settings : SamplerSettings
        Walkers, steps, burn-in and thinning.
    seed : int or sequence of int
        Seeds the starting points and emcee's random state.
    progress : callable, optional
        ``progress(done, total)`` after every step.
    """
    import emcee

    settings.check(posterior.ndim)
    rng = _rng(seed)
    start = start_positions(posterior, settings.walkers, rng)
    moves = {
        "stretch": emcee.moves.StretchMove,
        "de": emcee.moves.DEMove,
        "de_snooker": emcee.moves.DESnookerMove,
        "independence": _independence_move,
    }
    sampler = emcee.EnsembleSampler(
        settings.walkers, posterior.ndim, posterior, vectorize=True, moves=[(moves[m](), w) for m, w in settings.moves]
    )
    sampler.random_state = np.random.RandomState(int(rng.integers(2**32))).get_state()
    total = settings.burn + settings.steps
    t0 = time.perf_counter()
    for i, _ in enumerate(sampler.sample(start, iterations=total), start=1):
        if progress is not None:
            progress(i, total)
    seconds = time.perf_counter() - t0
    chain = sampler.get_chain(discard=settings.burn, thin=settings.thin)  # (draws, walkers, ndim)
    logp = sampler.get_log_prob(discard=settings.burn, thin=settings.thin)
    return Chains(
        samples=np.ascontiguousarray(np.swapaxes(chain, 0, 1)),
        log_posterior=np.ascontiguousarray(logp.T),
        acceptance=np.asarray(sampler.acceptance_fraction, dtype=float),
        autocorr=_autocorr(chain),
        seconds=seconds,
    )


def _autocorr(chain: np.ndarray) -> np.ndarray:
    """emcee's integrated autocorrelation time per parameter (no reliability check: ours is ESS)."""
    import emcee

    if chain.shape[0] < 4:
        return np.full(chain.shape[-1], math.nan)
    # A walker that never moved (a short run) has no autocorrelation: NaN there, not a warning.
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.asarray(emcee.autocorr.integrated_time(chain, tol=0), dtype=float)
