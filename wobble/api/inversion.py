"""Bayesian inversion of a planet's interior from its wobble: the public API.

>>> import wobble
>>> result = wobble.invert("mars", steps=300, burn=300, seed=1)   # doctest: +SKIP
>>> print(result.summary())                                        # doctest: +SKIP

:func:`invert` reads a setup (a shipped name such as ``"mars"``/``"earth"``, a
``wobble-inversion/1`` TOML file or a dict of the same structure; see
:mod:`wobble.io.inversion_file`), samples the posterior with emcee, and returns an
:class:`Inversion`: a summary table (median, central 68 % and 95 % intervals, R-hat
and effective sample size per parameter, computed with ArviZ), the posterior
predictive of every observable beside its measured value, an ArviZ
``InferenceData`` (:meth:`Inversion.to_inference_data`, :meth:`Inversion.write`)
and a corner plot (:meth:`Inversion.plot`). Convergence problems are warnings in
the result (``warnings``), never silently dropped.

:func:`injection_recovery` checks the whole chain by simulation-based calibration.
Both run their independent units (ensembles, injections) on a dask scheduler when
one is given, as :func:`wobble.run_sweep` does.
"""

from __future__ import annotations

import math
import os
import re
import sys
import time
import warnings
from collections.abc import Mapping
from pathlib import Path
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from wobble.api._progress import ProgressBar
from wobble.api._scheduler import LOCAL, check_scheduler, connected
from wobble.errors import FileFormatError, InputError
from wobble.io.cf import INT64_ALLOWED, INT64_MAX
from wobble.io.catalog import catalogue_names
from wobble.io.json_keys import deprecate
from wobble.io.inversion_file import InversionSetup, read_setup, resolve_setup, setup_from_dict, setup_names
from wobble.io.parameter_file import read_toml
from wobble.models.inversion.calibration import Recovery, central_interval, coverage, recover_one
from wobble.models.inversion.likelihood import Posterior
from wobble.models.inversion.sampling import Chains, SamplerSettings, draw_prior, run_emcee

if TYPE_CHECKING:
    import arviz

__all__ = [
    "Inversion",
    "Calibration",
    "invert",
    "load_inversion_setup",
    "inversion_setups",
    "injection_recovery",
    "RHAT_MAX",
    "ESS_MIN",
]

# Convergence thresholds (Vehtari et al. 2021, Bayesian Analysis 16, 667: rank-normalised
# split R-hat below 1.01 and a bulk and tail ESS above 400 for reliable quantiles).
RHAT_MAX = 1.01
ESS_MIN = 400
ACCEPTANCE_RANGE = (0.15, 0.7)
#: ``diagnostics`` keys of the JSON kept under their old names for one release: the thresholds were "r_hat_max"
#: and "ess_min", read as measurements beside min_ess and max_r_hat.
DIAGNOSTICS_RENAMES = {"r_hat_max": "r_hat_threshold", "ess_min": "ess_threshold"}
_REFERENCES = (
    "Foreman-Mackey et al. 2013 (emcee, PASP 125, 306); Goodman & Weare 2010 (stretch move); "
    "ter Braak 2006 and ter Braak & Vrugt 2008 (differential-evolution moves); "
    "Vehtari et al. 2021 (rank-normalised R-hat and ESS, Bayesian Analysis 16, 667); "
    "Kumar et al. 2019 (ArviZ, JOSS 4, 1143)"
)


def arviz():
    """ArviZ, imported on first use.

    ArviZ 0.x announces its coming 1.0 refactor with a FutureWarning once a day on
    import; that notice is about ArviZ's future API, not about anything wobble calls,
    so exactly that message is ignored here (any other warning still is an error in
    the tests).
    """
    if "arviz" not in sys.modules:
        with warnings.catch_warnings():
            warnings.filterwarnings(
                "ignore", message=r"\s*ArviZ is undergoing a major refactor", category=FutureWarning
            )
            import arviz
        return arviz
    return sys.modules["arviz"]


def inversion_setups() -> list[str]:
    """Names of the shipped setups (``data/inversions/*.toml``)."""
    return setup_names()


def load_inversion_setup(setup) -> InversionSetup:
    """A setup from a shipped name, a TOML path, a dict (TOML structure) or an InversionSetup."""
    if isinstance(setup, InversionSetup):
        return setup
    if isinstance(setup, Mapping):
        return setup_from_dict(dict(setup))
    if isinstance(setup, (str, os.PathLike)):
        return read_setup(setup)
    raise InputError("setup", setup, f"a setup name ({', '.join(setup_names())}), a TOML file, or a dict")


# ---------------------------------------------------------------------------
# Running ensembles and injections, locally or on dask
# ---------------------------------------------------------------------------


def _map(function, items: list, scheduler, progress: ProgressBar | None):
    """``[function(*item) for item in items]``, in this process or on a dask scheduler."""
    if scheduler is None:
        out = []
        for item in items:
            out.append(function(*item))
            if progress is not None and len(items) > 1:
                progress(len(out))
        return out
    if isinstance(scheduler, str) and scheduler in LOCAL:
        import dask

        results = dask.compute(*[dask.delayed(function, pure=True)(*item) for item in items], scheduler=scheduler)
        if progress is not None:
            progress(len(items))
        return list(results)
    from distributed import as_completed

    with connected(scheduler) as client:
        futures = [client.submit(function, *item, pure=True) for item in items]
        done = 0
        for _ in as_completed(futures):
            done += 1
            if progress is not None:
                progress(done)
        return [f.result() for f in futures]


def _ensemble_seed(seed: int, index: int) -> list[int]:
    return [int(seed), 1, int(index)]


def _run_ensemble(posterior: Posterior, settings: SamplerSettings, seed, progress=None) -> Chains:
    return run_emcee(posterior, settings, seed, progress)


# ---------------------------------------------------------------------------
# The result
# ---------------------------------------------------------------------------


# Keys of an observable's row that only a measured quantity fills (null in the others).
_MEASURED_KEYS = (
    "observed",
    "observed_uncertainty",
    "source",
    "predictive_median",
    "predictive_lower_68",
    "predictive_upper_68",
    "predictive_lower_95",
    "predictive_upper_95",
    "predictive_p_value",
)


@dataclass(frozen=True)
class _Row:
    name: str
    unit: str
    median: float
    lower_68: float
    upper_68: float
    lower_95: float
    upper_95: float
    r_hat: float
    ess: float
    ess_tail: float
    prior: str
    prior_68: tuple[float, float]


class Inversion:
    """The posterior of one setup, with diagnostics and the posterior predictive.

    Build with :func:`invert`. Values in tables and files are in each parameter's
    display unit (``unit``); :attr:`samples` holds them in SI.

    Attributes
    ----------
    setup : InversionSetup
    samples : numpy.ndarray
        Posterior draws, shape (chains, draws, parameters), SI.
    log_posterior : numpy.ndarray
        ln p of each draw, shape (chains, draws).
    prior_samples : numpy.ndarray
        Independent prior draws, shape (draws, parameters), SI.
    settings : SamplerSettings
    seed : int
    seconds : float
        Wall-clock sampling time (all ensembles).
    prior_only : bool
        Whether the likelihood was dropped.
    warnings : list of str
        Convergence and sampler warnings (also in :meth:`to_dict` and the netCDF file).
    """

    def __init__(
        self,
        setup: InversionSetup,
        chains: list[Chains],
        prior_samples: np.ndarray,
        settings: SamplerSettings,
        seed: int,
        seconds: float,
        prior_only: bool,
        scheduler: str | None,
    ):
        self.setup = setup
        self.posterior = setup.posterior(prior_only=prior_only)
        self.samples = np.concatenate([c.samples for c in chains], axis=0)
        self.log_posterior = np.concatenate([c.log_posterior for c in chains], axis=0)
        self.acceptance = np.concatenate([c.acceptance for c in chains])
        self.autocorr = _nanmax(np.stack([c.autocorr for c in chains]), axis=0)
        self.prior_samples = prior_samples
        self.settings = settings
        self.seed = seed
        self.seconds = seconds
        self.prior_only = prior_only
        self.scheduler = scheduler
        self._idata = None
        self._predictions = None
        self._rows = None
        self.warnings: list[str] = []
        self._diagnose()

    # -- helpers ----------------------------------------------------------------

    @property
    def names(self) -> tuple[str, ...]:
        return self.posterior.names

    def _flat(self) -> np.ndarray:
        return self.samples.reshape(-1, self.posterior.ndim)

    def predictions(self) -> dict[str, np.ndarray]:
        """Forward predictions of every observable and derived quantity for every draw, SI,
        shape (chains, draws)."""
        if self._predictions is None:
            pred = self.posterior.predict(self._flat())
            self._predictions = {k: v.reshape(self.samples.shape[:2]) for k, v in pred.items()}
        return self._predictions

    def _replicated(self) -> dict[str, np.ndarray]:
        """Posterior predictive draws y_rep = f(theta) + noise (SI), shape (chains, draws)."""
        rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(self.seed), 2])))
        pred = self.predictions()
        return {
            m.name: pred[m.name] + m.sigma * rng.standard_normal(pred[m.name].shape) for m in self.posterior.measured
        }

    def _independence_moves(self) -> bool:
        """Whether the mixture proposes from the ensemble's fitted density (the independence move).

        Such a proposal is accepted more often the closer it is to the posterior: near 1 on a Gaussian
        posterior, the best case, so a high acceptance is no warning then (it is for the random-walk-like
        stretch and differential-evolution moves, whose [0.15, 0.7] band is the emcee guidance).
        """
        return any(name == "independence" and weight > 0 for name, weight in self.settings.moves)

    def _diagnose(self):
        rows = self.rows()
        bad_rhat = [r.name for r in rows if not (r.r_hat <= RHAT_MAX)]
        small = [r.name for r in rows if not (min(r.ess, r.ess_tail) >= ESS_MIN)]
        if bad_rhat:
            worst = max(
                (r for r in rows if r.name in bad_rhat), key=lambda r: r.r_hat if math.isfinite(r.r_hat) else math.inf
            )
            self.warnings.append(
                f"R-hat above {RHAT_MAX} for {', '.join(bad_rhat)} (worst {worst.r_hat:.3f}, {worst.name}): "
                "the chains have not converged; run longer (--steps) or with more burn-in"
            )
        if small:
            worst = min((r for r in rows if r.name in small), key=lambda r: min(r.ess, r.ess_tail))
            self.warnings.append(
                f"effective sample size below {ESS_MIN} for {', '.join(small)} "
                f"(smallest {min(worst.ess, worst.ess_tail):.0f}, {worst.name}): intervals are unreliable; run "
                "longer (--steps)"
            )
        acc = float(np.mean(self.acceptance))
        lo, hi = ACCEPTANCE_RANGE
        if acc < lo or (acc > hi and not self._independence_moves()):
            self.warnings.append(f"mean acceptance fraction {acc:.2f} outside [{lo}, {hi}]: the ensemble moves poorly")
        draws = self.samples.shape[1] * self.settings.thin
        tau = float(_nanmax(self.autocorr)) * self.settings.thin
        if math.isfinite(tau) and draws < 50 * tau:
            self.warnings.append(
                f"{draws} steps per walker are fewer than 50 autocorrelation times ({tau:.0f} steps): "
                "emcee's estimate of the autocorrelation time itself is unreliable"
            )
        for m in self.posterior.measurements:
            pred = self.predictions()[m.name]
            bad = float(np.mean(~np.isfinite(pred)))
            if m.measured and bad > 0:
                self.warnings.append(f"{bad:.1%} of the draws have no prediction of {m.name}")

    def rows(self) -> list[_Row]:
        """The summary table: one row per sampled parameter (display units)."""
        if self._rows is not None:
            return self._rows
        az = arviz()
        post = {p.name: self.samples[..., i] / p.scale for i, p in enumerate(self.posterior.parameters)}
        ds = _dataset(post)
        with np.errstate(invalid="ignore", divide="ignore"):
            rhat = az.rhat(ds, method="rank")
            ess_bulk = az.ess(ds, method="bulk")
            ess_tail = az.ess(ds, method="tail")
        rows = []
        for i, p in enumerate(self.posterior.parameters):
            x = post[p.name].ravel()
            lo68, hi68 = central_interval(x, 0.68)
            lo95, hi95 = central_interval(x, 0.95)
            plo, phi = central_interval(self.prior_samples[:, i] / p.scale, 0.68)
            rows.append(
                _Row(
                    p.name,
                    p.unit,
                    float(np.median(x)),
                    float(lo68),
                    float(hi68),
                    float(lo95),
                    float(hi95),
                    float(rhat[p.name]),
                    float(ess_bulk[p.name]),
                    float(ess_tail[p.name]),
                    p.prior.describe(p.scale, p.unit),
                    (float(plo), float(phi)),
                )
            )
        self._rows = rows
        return rows

    def quantity_rows(self) -> list[dict]:
        """Derived quantities and observables: posterior (noise-free model) and, for the
        measured ones, the posterior predictive beside the measured value (display units)."""
        out = []
        pred = self.predictions()
        rep = self._replicated()
        prior_pred = self.posterior.predict(self.prior_samples)
        for m in self.posterior.measurements:
            x = pred[m.name].ravel() / m.scale
            x = x[np.isfinite(x)]
            row = {"name": m.name, "unit": m.unit, "description": m.model.description, "measured": m.measured}
            row.update(_interval_dict(x))
            px = prior_pred[m.name] / m.scale
            px = px[np.isfinite(px)]
            row["prior_lower_68"], row["prior_upper_68"] = (
                (float(v) for v in central_interval(px, 0.68)) if px.size else (math.nan, math.nan)
            )
            # The same keys in every row (README, "Commands"): null where the quantity has no measurement.
            row.update(dict.fromkeys(_MEASURED_KEYS))
            if m.measured:
                y = rep[m.name].ravel() / m.scale
                y = y[np.isfinite(y)]
                lo, hi = central_interval(y, 0.68)
                lo95, hi95 = central_interval(y, 0.95)
                row.update(
                    {
                        "observed": m.value / m.scale,
                        "observed_uncertainty": m.sigma / m.scale,
                        "source": m.source,
                        "predictive_median": float(np.median(y)),
                        "predictive_lower_68": float(lo),
                        "predictive_upper_68": float(hi),
                        "predictive_lower_95": float(lo95),
                        "predictive_upper_95": float(hi95),
                        "predictive_p_value": float(np.mean(y > m.value / m.scale)),
                    }
                )
            out.append(row)
        return out

    @property
    def min_ess(self) -> float:
        return min(min(r.ess, r.ess_tail) for r in self.rows())

    @property
    def max_r_hat(self) -> float:
        """The worst (largest) rank-normalised split R-hat over the sampled parameters."""
        return max(r.r_hat for r in self.rows())

    @property
    def seconds_per_effective_sample(self) -> float:
        return self.seconds / self.min_ess if self.min_ess > 0 else math.inf

    # -- the vocabulary ------------------------------------------------------------

    def to_dict(self) -> dict:
        """JSON-ready: parameters, observables, sampler, settings, diagnostics, warnings."""
        comparisons = {}
        for c in self.setup.comparisons:
            scale = self._scale(c.name)
            comparisons.setdefault(c.name, []).append(
                {
                    "value": None if c.value is None else c.value / scale,
                    "uncertainty": None if c.uncertainty is None else c.uncertainty / scale,
                    "low": None if c.low is None else c.low / scale,
                    "high": None if c.high is None else c.high / scale,
                    "source": c.source,
                }
            )
        out = {
            "setup": self.setup.name,
            "title": self.setup.title,
            "body": self.setup.planet.name,
            "model": self.setup.model,
            "prior_only": self.prior_only,
            "parameters": [
                {
                    "name": r.name,
                    "unit": r.unit,
                    "median": r.median,
                    "lower_68": r.lower_68,
                    "upper_68": r.upper_68,
                    "lower_95": r.lower_95,
                    "upper_95": r.upper_95,
                    "r_hat": r.r_hat,
                    "ess": r.ess,
                    "ess_tail": r.ess_tail,
                    "prior": r.prior,
                    "prior_lower_68": r.prior_68[0],
                    "prior_upper_68": r.prior_68[1],
                    "published": comparisons.get(r.name, []),
                }
                for r in self.rows()
            ],
            "observables": [{**row, "published": comparisons.get(row["name"], [])} for row in self.quantity_rows()],
            "sampler": "emcee",
            "sampler_version": _version("emcee"),
            "settings": {**self.settings.as_dict(), "seed": self.seed, "vectorize": True},
            "scheduler": self.scheduler,
            "diagnostics": deprecate(
                {
                    "draws": int(self.samples.shape[0] * self.samples.shape[1]),
                    "chains": int(self.samples.shape[0]),
                    "mean_acceptance_fraction": float(np.mean(self.acceptance)),
                    "autocorrelation_time_steps": {
                        n: float(t) * self.settings.thin for n, t in zip(self.names, self.autocorr)
                    },
                    "min_ess": self.min_ess,
                    "max_r_hat": self.max_r_hat,
                    "seconds": self.seconds,
                    "seconds_per_effective_sample": self.seconds_per_effective_sample,
                    # The thresholds the warnings apply (measured values above: min_ess, max_r_hat); their old
                    # names are kept one release (DIAGNOSTICS_RENAMES).
                    "r_hat_threshold": RHAT_MAX,
                    "ess_threshold": ESS_MIN,
                },
                DIAGNOSTICS_RENAMES,
            ),
            "warnings": list(self.warnings),
            "notes": list(self.setup.notes),
            "references": _REFERENCES,
        }
        # The root lists the renames of the object it holds too (as every command's root does, README "Commands").
        return deprecate(out, {f"diagnostics.{old}": f"diagnostics.{new}" for old, new in DIAGNOSTICS_RENAMES.items()})

    def _scale(self, name: str) -> float:
        for p in self.posterior.parameters:
            if p.name == name:
                return p.scale
        for m in self.posterior.measurements:
            if m.name == name:
                return m.scale
        return 1.0

    def summary(self) -> str:
        """The table a person reads: parameters, observables, diagnostics, warnings."""
        lines = [
            f"{self.setup.title} ({'PRIOR ONLY: no data' if self.prior_only else 'posterior'}; "
            f"body {self.setup.planet.name}, model '{self.setup.model}')"
        ]
        lines.append(
            f"  {'parameter':<28} {'median':>11} {'68 % interval':>25} {'95 % interval':>25} {'R-hat':>6} "
            f"{'ESS':>6}  unit   prior"
        )
        for r in self.rows():
            med, lo68, hi68, lo95, hi95 = _same_decimals(
                (r.median, r.lower_68, r.upper_68, r.lower_95, r.upper_95), (r.upper_68 - r.lower_68) / 2
            )
            lines.append(
                f"  {r.name:<28} {med:>11} {f'[{lo68}, {hi68}]':>25} {f'[{lo95}, {hi95}]':>25} "
                f"{r.r_hat:6.3f} {min(r.ess, r.ess_tail):6.0f}  {r.unit or '-':<6} {r.prior}"
            )
        published = [c for c in self.setup.comparisons]
        if published:
            lines.append("  published:")
            for c in published:
                s = self._scale(c.name)
                if c.value is not None:
                    val = (
                        _g(c.value / s)
                        if c.uncertainty is None
                        else " +/- ".join(_same_decimals((c.value / s, c.uncertainty / s), c.uncertainty / s))
                    )
                else:
                    val = f"{_g(c.low / s)} to {_g(c.high / s)}"
                lines.append(f"    {c.name:<26} {val:<22} {c.source}")
        # A prior-only run has no posterior: its column is the prior predictive.
        predictive = "prior predictive (68 %)" if self.prior_only else "posterior predictive (68 %)"
        lines.append(f"  {'observable':<28} {'measured':>22} {predictive:>36} {'model median':>13}  unit")
        for row in self.quantity_rows():
            # One row, one number of decimals: two significant digits of the finer of the measurement's
            # uncertainty and the half-width of the 68 % interval shown (an FCN of -430.00 +/- 0.10 d).
            if row["measured"]:
                spread = min(row["observed_uncertainty"], (row["predictive_upper_68"] - row["predictive_lower_68"]) / 2)
                obs, osig, pmed, plo, phi, med = _same_decimals(
                    (
                        row["observed"],
                        row["observed_uncertainty"],
                        row["predictive_median"],
                        row["predictive_lower_68"],
                        row["predictive_upper_68"],
                        row["median"],
                    ),
                    spread,
                )
                meas, pp = f"{obs} +/- {osig}", f"{pmed} [{plo}, {phi}]"
            else:
                med, lo, hi = _same_decimals(
                    (row["median"], row["lower_68"], row["upper_68"]), (row["upper_68"] - row["lower_68"]) / 2
                )
                meas, pp = "(derived)", f"{med} [{lo}, {hi}]"
            unit = (row["unit"] or "-").replace(" / ", "/")  # mas/yr, as the precession budget writes it
            lines.append(f"  {row['name']:<28} {meas:>22} {pp:>36} {med:>13}  {unit}")
        d = self.to_dict()["diagnostics"]
        lines.append(
            f"  sampler: emcee, {self.settings.walkers} walkers x {self.settings.ensembles} ensemble(s), "
            f"{self.settings.steps} steps after {self.settings.burn} burn-in, seed {self.seed}; "
            f"acceptance {d['mean_acceptance_fraction']:.2f}; {_g(self.seconds, 3)} s, "
            f"{_g(1e3 * self.seconds_per_effective_sample, 3)} ms per effective sample"
        )
        for w in self.warnings:
            lines.append(f"  WARNING: {w}")
        for note in self.setup.notes:
            lines.append(f"  note: {note}")
        return "\n".join(lines)

    def to_inference_data(self) -> arviz.InferenceData:
        """The run as ArviZ InferenceData: posterior (parameters, model predictions and derived
        quantities), prior, posterior_predictive and prior_predictive (replicated measurements),
        log_likelihood (per observable), observed_data, constant_data (uncertainties),
        sample_stats (ln p). Display units in each variable's ``units`` attribute."""
        if self._idata is not None:
            return self._idata
        az = arviz()
        chains, draws = self.samples.shape[:2]
        post = {p.name: self.samples[..., i] / p.scale for i, p in enumerate(self.posterior.parameters)}
        pred = self.predictions()
        for m in self.posterior.measurements:
            post[_model_name(m)] = pred[m.name] / m.scale
        prior = {p.name: self.prior_samples[None, :, i] / p.scale for i, p in enumerate(self.posterior.parameters)}
        prior_pred = self.posterior.predict(self.prior_samples)
        for m in self.posterior.measurements:
            prior[_model_name(m)] = prior_pred[m.name][None, :] / m.scale
        rep = self._replicated()
        rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(self.seed), 3])))
        measured = self.posterior.measured
        groups = dict(
            posterior=post,
            prior=prior,
            sample_stats={"lp": self.log_posterior},
            observed_data={m.name: np.array([m.value / m.scale]) for m in measured},
            constant_data={f"{m.name}_uncertainty": np.array([m.sigma / m.scale]) for m in measured},
        )
        if measured:
            # One observation each, shaped like observed_data (dimension <name>_dim_0), as ArviZ's
            # posterior-predictive checks (az.plot_ppc) expect.
            groups["posterior_predictive"] = {m.name: rep[m.name][..., None] / m.scale for m in measured}
            groups["prior_predictive"] = {
                m.name: (prior_pred[m.name] + m.sigma * rng.standard_normal(prior_pred[m.name].shape))[None, :, None]
                / m.scale
                for m in measured
            }
            z = {m.name: (pred[m.name] - m.value) / m.sigma for m in measured}
            groups["log_likelihood"] = {
                m.name: (-0.5 * z[m.name] ** 2 - math.log(m.sigma / m.scale * math.sqrt(2 * math.pi)))[..., None]
                for m in measured
            }
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            # ArviZ guesses the layout when there are more walkers (chains) than steps (draws); ours is
            # (chain, draw) by construction, so its "More chains than draws" warning is noise on stderr.
            warnings.filterwarnings("ignore", message="More chains", category=UserWarning)
            idata = az.from_dict(**groups)
        self._annotate(idata)
        self._idata = idata
        return idata

    def _annotate(self, idata):
        from wobble.io.cf import udunits

        # UDUNITS strings, as every other file writes them ("mas / yr" is not one: milliarcsecond Julian_year-1).
        units = {
            p.name: (udunits(p.unit), f"{p.name} ({p.prior.describe(p.scale, p.unit)} prior)")
            for p in self.posterior.parameters
        }
        for m in self.posterior.measurements:
            units[_model_name(m)] = (udunits(m.unit), f"modelled {m.model.description}")
            units[m.name] = (udunits(m.unit), m.model.description)
            units[f"{m.name}_uncertainty"] = (udunits(m.unit), f"one-sigma uncertainty of the measured {m.name}")
        units["lp"] = ("1", "log posterior density (up to the evidence)")
        for group in idata.groups():
            ds = getattr(idata, group)
            for name in ds.data_vars:
                key = name if name in units else None
                if key is not None:
                    ds[name].attrs.update({"units": units[key][0], "long_name": units[key][1]})
            if group == "observed_data":
                for m in self.posterior.measured:
                    ds[m.name].attrs["source"] = m.source
            if group == "log_likelihood":
                for name in ds.data_vars:
                    ds[name].attrs.update({"units": "1", "long_name": f"pointwise Gaussian log-likelihood of {name}"})
            # ArviZ's index coordinates had neither units nor long_name (docs/netcdf.md: every numeric variable
            # has both): the chain, the draw, and the position in a quantity's array (<name>_dim_0).
            for name in ds.coords:
                label = _INDEX_NAMES.get(name) or (
                    f"index in {name.rsplit('_dim_', 1)[0]}" if re.fullmatch(r".+_dim_\d+", name) else None
                )
                if label is not None and "long_name" not in ds[name].attrs:
                    ds[name].attrs.update({"units": "1", "long_name": label})
        attrs = {
            "title": self.setup.title,
            "wobble_setup": self.setup.name,
            "body": self.setup.planet.name,
            "chandler_model": self.setup.model,
            "inference_library": "emcee",
            "inference_library_version": _version("emcee"),
            "sampler_settings": "; ".join(f"{k} = {v}" for k, v in self.settings.as_dict().items()),
            "seed": int(self.seed),
            "prior_only": int(self.prior_only),
            "warnings": " | ".join(self.warnings) if self.warnings else "none",
            "notes": " | ".join(self.setup.notes) if self.setup.notes else "none",
            "references": _REFERENCES,
            "source": f"wobble {_version('wobble')}",
        }
        for group in idata.groups():
            getattr(idata, group).attrs.update(attrs)

    def write(self, path, *, overwrite: bool = False, command: str | None = None):
        """Save :meth:`to_inference_data` as netCDF (ArviZ's groups), atomically.

        Written under a temporary name in the target folder and renamed; an existing
        file is replaced only with ``overwrite=True``. The root group, which ArviZ leaves
        empty, carries the global attributes of every wobble file (``Conventions``,
        ``title``, ``source``, ``history``, naming ``command``). Reopen with
        ``arviz.from_netcdf(path)`` (or ``xarray.open_dataset(path, group="posterior")``).
        """
        from wobble.io.atomic import atomic_target, interrupts_held
        from wobble.io.netcdf import mark_inference_data

        idata = self.to_inference_data()
        with atomic_target(path, overwrite) as tmp:
            # netCDF4, as every wobble file: h5netcdf (ArviZ's default) leaves HDF5 objects open
            # after a failed write (a full disk), and the interpreter then crashes closing them.
            with interrupts_held():  # Ctrl-C inside xarray's locked writer can deadlock it
                idata.to_netcdf(tmp, engine="netcdf4")
                mark_inference_data(
                    tmp,
                    f"wobble inversion: {self.setup.title}",
                    idata.groups(),
                    command=command,
                    references=_REFERENCES,  # the groups' own, where a reader of the root looks first
                )
        from pathlib import Path

        return Path(path)

    def plot(self, path, *, overwrite: bool = False):
        """Corner plot of the posterior (priors dashed, published values as bands) to ``path``,
        atomically (PNG, PDF or SVG; an existing file is replaced only with ``overwrite=True``)."""
        from wobble.plot.inversion import corner_plot

        return corner_plot(self, path, overwrite=overwrite)

    def __repr__(self) -> str:
        return f"Inversion({self.setup.name!r}, {self.samples.shape[0]} chains x {self.samples.shape[1]} draws)"


#: long_name of ArviZ's index coordinates.
_INDEX_NAMES = {"chain": "chain (walker) index", "draw": "draw index along the chain (after burn-in and thinning)"}


def _median_finite(values) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return float(np.median(finite)) if finite else math.nan


def _nanmax(a, axis=None):
    """Largest finite-or-inf value, NaN where every entry is NaN (without NumPy's warning)."""
    a = np.asarray(a, dtype=float)
    top = np.max(np.where(np.isnan(a), -np.inf, a), axis=axis)
    return np.where(np.isneginf(top) & np.all(np.isnan(a), axis=axis), np.nan, top)


def _model_name(m) -> str:
    """Name of a quantity's model prediction in the posterior group (derived: its own name)."""
    return f"{m.name}_model" if m.measured else m.name


def _dataset(post: dict):
    from wobble.api.dataset import xarray

    xr = xarray()
    return xr.Dataset({k: (("chain", "draw"), v) for k, v in post.items()})


def _interval_dict(x: np.ndarray) -> dict:
    if x.size == 0:
        return {k: math.nan for k in ("median", "lower_68", "upper_68", "lower_95", "upper_95")}
    lo68, hi68 = central_interval(x, 0.68)
    lo95, hi95 = central_interval(x, 0.95)
    return {
        "median": float(np.median(x)),
        "lower_68": float(lo68),
        "upper_68": float(hi68),
        "lower_95": float(lo95),
        "upper_95": float(hi95),
    }


def _g(x: float, digits: int = 5) -> str:
    x = float(x)
    if not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return f"{x:.{digits}g}"


#: Beyond this many decimals a row is written with one shared power of ten (3.1e-07, not 0.00000031).
_MAX_DECIMALS = 6


def _same_decimals(values, spread: float) -> list[str]:
    """``values`` (one row of the summary: a median and its intervals, a measurement and its
    uncertainty) all to the same decimal place, two significant digits of ``spread`` (the half-width
    of the row's 68 % interval, or an uncertainty): ``1799 [1757, 1840]``, ``0.001813 [0.001730, 0.001898]``.

    Very small or very large numbers share one power of ten (``4.2e-08 [3.1e-08, 5.3e-08]``); without
    a usable spread each value gets five significant digits.
    """
    from wobble.io.text import decimals_for

    values = [float(v) for v in values]
    finite = [abs(v) for v in values if math.isfinite(v)]
    if not (math.isfinite(spread) and spread > 0) or not finite:
        return [_g(v) for v in values]
    d = decimals_for(spread)
    top = max(max(finite), spread)
    if d <= _MAX_DECIMALS and top < 1e7:
        return [f"{v:.{d}f}" if math.isfinite(v) else _g(v) for v in values]
    exponent = math.floor(math.log10(top))
    m = max(0, exponent - math.floor(math.log10(spread)) + 1)
    return [f"{v / 10.0**exponent:.{m}f}e{exponent:+03d}" if math.isfinite(v) else _g(v) for v in values]


def _version(package: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(package)
    except PackageNotFoundError:
        return "unknown"


def _settings(setup: InversionSetup, **overrides) -> SamplerSettings:
    given = {k: v for k, v in overrides.items() if v is not None}
    return replace(setup.settings, **given)


#: The parameter an InputError names when the chains would not fit in memory: a product of four settings.
SIZE = "walkers x (burn + steps) x ensembles"


def _check_size(settings: SamplerSettings, ndim: int) -> None:
    """Refuse, before any work, a run whose chains cannot fit in half the free memory: every walker's
    position and log-probability at every step of every ensemble (``--walkers 1e10`` asked numpy for
    298 GiB and failed with a traceback; ``--ensembles 1e20`` ran without end)."""
    from wobble.io.memory import available_memory, human_bytes

    per_draw = 8 * (ndim + 1)
    draws = settings.ensembles * settings.walkers * (settings.burn + settings.steps)
    have = available_memory() // 2
    if draws * per_draw > have:
        # The product's factors are shown with the total, so that the message says which numbers made it.
        s = settings
        raise InputError(
            SIZE,
            f"{s.walkers} x ({s.burn} + {s.steps}) x {s.ensembles} = {draws:,} walker-steps",
            f"at most {have // per_draw:,} walker-steps here: {draws:,} need about {human_bytes(draws * per_draw)} "
            f"of memory and {human_bytes(have)} is usable (ask for fewer walkers, steps or ensembles)",
        )


def _with_body(setup, body) -> InversionSetup:
    """The setup with its ``body`` replaced: a catalogue name or a planet file (a path relative to the caller's
    folder, not the setup's, as ``wobble chandler --body-file`` reads it)."""
    typed = os.fspath(body)
    text = typed
    if Path(text).is_file():
        text = str(Path(text).resolve())
    elif text.strip().lower() not in catalogue_names():
        from wobble.io.shipped import resolve

        # As wobble chandler --body-file reads it: a shipped planet file by name (my_planet.toml), and a
        # missing one said to be missing (it was told "a planet file, or a catalogued planet").
        text = str(Path(resolve(text, ("examples", "bodies"), "body", (".toml",))).resolve())
    try:
        if isinstance(setup, Mapping):
            return setup_from_dict({**setup, "body": text})
        if isinstance(setup, (str, os.PathLike)):
            path = resolve_setup(setup)
            return setup_from_dict({**read_toml(path), "body": text}, path)
    except FileFormatError as exc:
        if exc.path != text:
            raise
        # The planet file named as the caller typed it (wobble chandler's way), not as made absolute above so
        # that the setup's folder does not change what a relative path means.
        raise FileFormatError(typed, exc.where, exc.problem) from None
    raise InputError(
        "body", body, "none with an InversionSetup, whose body is built in (give the setup by name, file or dict)"
    )


def invert(
    setup="mars",
    *,
    body=None,
    seed: int | None = None,
    walkers: int | None = None,
    steps: int | None = None,
    burn: int | None = None,
    thin: int | None = None,
    ensembles: int | None = None,
    prior_only: bool = False,
    scheduler=None,
    progress: bool = False,
) -> Inversion:
    """Sample the posterior of a setup's parameters given its observables.

    Parameters
    ----------
    setup : str, path, dict or InversionSetup
        ``"mars"``, ``"earth"``, ``"mars_chandler_only"`` (:func:`inversion_setups`), a
        ``wobble-inversion/1`` TOML file, or a dict of the same structure.
    body : str or path, optional
        Replaces the setup's body: a catalogued planet's name or a planet file of your own
        (``wobble invert --body-file``); its catalogue gives the observables the setup does not.
    seed : int, optional
        Overrides the setup's seed: the same seed gives the same numbers.
    walkers, steps, burn, thin, ensembles : int, optional
        Override the setup's sampler settings.
    prior_only : bool
        Drop the likelihood: the prior (pushed through the forward models), to see
        what the data add.
    scheduler : str or distributed.Client, optional
        Where independent ensembles run: ``None`` (this process), ``"threads"``,
        ``"processes"``, ``"synchronous"`` or a dask.distributed address.
    progress : bool
        A progress bar on stderr.

    Returns
    -------
    Inversion
    """
    s = load_inversion_setup(setup) if body is None else _with_body(setup, body)
    if seed is not None and (
        isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed <= INT64_MAX
    ):
        raise InputError("seed", seed, f"a non-negative integer {INT64_ALLOWED}")
    check_scheduler(scheduler)
    settings = _settings(s, walkers=walkers, steps=steps, burn=burn, thin=thin, ensembles=ensembles)
    posterior = s.posterior(prior_only=prior_only)
    settings.check(posterior.ndim)
    _check_size(settings, posterior.ndim)
    seed = s.seed if seed is None else int(seed)
    total = settings.ensembles * (settings.burn + settings.steps)
    bar = ProgressBar(
        total if scheduler is None else settings.ensembles, "steps" if scheduler is None else "ensembles", progress
    )
    t0 = time.perf_counter()
    try:
        if scheduler is None:
            chains = []
            for e in range(settings.ensembles):
                offset = e * (settings.burn + settings.steps)
                chains.append(
                    run_emcee(posterior, settings, _ensemble_seed(seed, e), (lambda d, t, o=offset: bar(o + d)))
                )
        else:
            items = [(posterior, settings, _ensemble_seed(seed, e)) for e in range(settings.ensembles)]
            chains = _map(_run_ensemble, items, scheduler, bar)
    finally:
        bar.close()
    seconds = time.perf_counter() - t0
    prior_samples = draw_prior(posterior, settings.prior_draws, [seed, 4])
    return Inversion(
        s, chains, prior_samples, settings, seed, seconds, prior_only, None if scheduler is None else str(scheduler)
    )


# ---------------------------------------------------------------------------
# Injection–recovery
# ---------------------------------------------------------------------------


class Calibration:
    """Coverage of the posterior intervals over injected truths (simulation-based calibration).

    Attributes
    ----------
    setup : InversionSetup
    recoveries : list of Recovery
    coverage : dict
        Parameter -> {"68": fraction, "95": fraction, "se_68", "se_95", "n"}.
    seconds : float
    """

    def __init__(
        self, setup: InversionSetup, recoveries: list[Recovery], settings: SamplerSettings, seed: int, seconds: float
    ):
        self.setup = setup
        self.recoveries = recoveries
        self.settings = settings
        self.seed = seed
        self.seconds = seconds
        self.names = setup.posterior().names
        self.coverage = coverage(recoveries, self.names)

    def rank_histogram(self, bins: int = 10) -> dict[str, list[int]]:
        """SBC ranks per parameter, counted in ``bins`` equal bins (uniform if calibrated)."""
        out = {}
        draws = self.recoveries[0].rank_draws
        for i, name in enumerate(self.names):
            ranks = np.array([r.rank[i] for r in self.recoveries])
            out[name] = np.histogram(ranks, bins=bins, range=(0, draws + 1))[0].tolist()
        return out

    def to_dict(self) -> dict:
        return {
            "setup": self.setup.name,
            "draws": len(self.recoveries),
            "seed": self.seed,
            "settings": self.settings.as_dict(),
            "coverage": self.coverage,
            "rank_histogram": self.rank_histogram(),
            "seconds": self.seconds,
            "min_ess_median": _median_finite([r.min_ess for r in self.recoveries]),
        }

    def summary(self) -> str:
        lines = [f"Injection-recovery of '{self.setup.name}': {len(self.recoveries)} truths drawn from the prior"]
        lines.append(f"  {'parameter':<28} {'68 % coverage':>16} {'95 % coverage':>16}")
        for name, c in self.coverage.items():
            lines.append(
                f"  {name:<28} {100 * c['68']:8.1f} +/- {100 * c['se_68']:.1f} {100 * c['95']:8.1f} +/- "
                f"{100 * c['se_95']:.1f}"
            )
        return "\n".join(lines)


def injection_recovery(
    setup="mars",
    draws: int = 100,
    *,
    seed: int = 0,
    walkers=None,
    steps=None,
    burn=None,
    thin=None,
    scheduler=None,
    progress: bool = False,
) -> Calibration:
    """Injection–recovery of a setup: invert ``draws`` synthetic data sets from prior truths.

    Each truth is drawn from the setup's priors, its measurements are simulated with
    the setup's uncertainties, and the inversion is rerun; the result reports how
    often the truth lies in the central 68 % and 95 % intervals (nominal: 68 % and
    95 %). Draws run on ``scheduler`` (as in :func:`invert`).
    """
    s = load_inversion_setup(setup)
    if isinstance(draws, bool) or not isinstance(draws, (int, np.integer)) or draws < 1:
        raise InputError("draws", draws, "a positive whole number")
    check_scheduler(scheduler)
    settings = _settings(s, walkers=walkers, steps=steps, burn=burn, thin=thin)
    posterior = s.posterior()
    settings.check(posterior.ndim)
    _check_size(settings, posterior.ndim)
    bar = ProgressBar(draws, "injections", progress)
    t0 = time.perf_counter()
    try:
        recoveries = _map(recover_one, [(posterior, settings, seed, i) for i in range(draws)], scheduler, bar)
    finally:
        bar.close()
    return Calibration(s, recoveries, settings, seed, time.perf_counter() - t0)
