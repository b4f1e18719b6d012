"""Prior distributions of the inverted parameters (SI floats, vectorised).

Three families, each proper (it integrates to one) and optionally truncated:

* ``uniform(low, high)``: density 1/(high - low) on [low, high];
* ``log_uniform(low, high)``: density 1/(x ln(high/low)) on [low, high], 0 < low;
  for a scale parameter known only to an order of magnitude;
* ``normal(mean, sd)``: the Gaussian, truncated to [low, high] where physics
  requires (a radius is positive, the anelastic exponent lies in (0, 1)) and
  renormalised there.

A parameter without a user-given prior gets ``normal(value, uncertainty)`` from
the catalogue, truncated to its physical range (:data:`PHYSICAL_RANGE`).
Every prior exposes ``logpdf`` (on arrays, -inf outside the support), ``ppf``
(the inverse CDF, used for draws and for starting points) and ``median``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special, stats

from wobble.models.planet import POSITIVE_KEYS

__all__ = ["Prior", "Uniform", "LogUniform", "Normal", "PHYSICAL_RANGE", "physical_range", "KINDS"]

KINDS = ("uniform", "log_uniform", "normal")

# Where each Chandler-model parameter is physical (open or closed bounds alike: the
# prior's support must lie inside, a normal prior is truncated to it).
PHYSICAL_RANGE: dict[str, tuple[float, float]] = {
    **{key: (0.0, math.inf) for key in POSITIVE_KEYS},
    "love_number_k2": (0.0, math.inf),
    "love_number_k2_imaginary": (0.0, math.inf),
    "ocean_pole_tide_love_number": (0.0, math.inf),
    "anelastic_exponent": (0.0, 1.0),
    # The core yields in the sense of the forcing (Sasao, Okubo & Saito 1980).
    "core_compliance_beta": (0.0, math.inf),
    "core_compliance_gamma": (0.0, math.inf),
    # e_f = e_hyd (1 + excess) must stay positive: a core flattened, not prolate.
    "core_flattening_excess": (-1.0, math.inf),
}


def physical_range(name: str) -> tuple[float, float]:
    """(low, high) of parameter ``name``; the whole real line when physics sets no bound."""
    return PHYSICAL_RANGE.get(name, (-math.inf, math.inf))


class Prior:
    """Base class: a proper one-dimensional prior on [low, high]."""

    kind = ""
    low: float
    high: float

    def logpdf(self, x) -> np.ndarray:
        raise NotImplementedError

    def ppf(self, q) -> np.ndarray:
        raise NotImplementedError

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` independent draws (inverse-CDF sampling with ``rng``)."""
        return self.ppf(rng.random(n))

    @property
    def median(self) -> float:
        return float(self.ppf(0.5))

    def problems(self) -> list[str]:
        """Why this prior is improper or contradictory (empty when it is fine)."""
        return []

    def describe(self, scale: float = 1.0, unit: str = "") -> str:
        """The prior in words, its numbers divided by ``scale`` (for display units)."""
        raise NotImplementedError

    def as_dict(self) -> dict:
        """The prior's kind and numbers (SI)."""
        return {"kind": self.kind, **{k: v for k, v in self.__dict__.items()}}


def _support(x, low, high):
    x = np.asarray(x, dtype=float)
    return x, (x >= low) & (x <= high)


def _fmt(x: float, scale: float) -> str:
    return f"{x / scale:.6g}"


@dataclass(frozen=True)
class Uniform(Prior):
    """Uniform on [low, high]."""

    low: float
    high: float
    kind = "uniform"

    def problems(self) -> list[str]:
        if not (math.isfinite(self.low) and math.isfinite(self.high)):
            return ["finite bounds (an unbounded uniform prior is improper)"]
        if not self.low < self.high:
            return ["low < high"]
        return []

    def logpdf(self, x) -> np.ndarray:
        x, inside = _support(x, self.low, self.high)
        return np.where(inside, -math.log(self.high - self.low), -np.inf)

    def ppf(self, q) -> np.ndarray:
        return self.low + (self.high - self.low) * np.asarray(q, dtype=float)

    def describe(self, scale: float = 1.0, unit: str = "") -> str:
        return f"uniform({_fmt(self.low, scale)}, {_fmt(self.high, scale)}){' ' + unit if unit else ''}"


@dataclass(frozen=True)
class LogUniform(Prior):
    """Log-uniform (density proportional to 1/x) on [low, high], 0 < low < high."""

    low: float
    high: float
    kind = "log_uniform"

    def problems(self) -> list[str]:
        if not (math.isfinite(self.low) and math.isfinite(self.high)):
            return ["finite bounds (an unbounded log-uniform prior is improper)"]
        if not self.low > 0:
            return ["0 < low (a log-uniform prior needs positive bounds)"]
        if not self.low < self.high:
            return ["low < high"]
        return []

    def logpdf(self, x) -> np.ndarray:
        x, inside = _support(x, self.low, self.high)
        with np.errstate(divide="ignore", invalid="ignore"):
            value = -np.log(x) - math.log(math.log(self.high / self.low))
        return np.where(inside, value, -np.inf)

    def ppf(self, q) -> np.ndarray:
        return self.low * (self.high / self.low) ** np.asarray(q, dtype=float)

    def describe(self, scale: float = 1.0, unit: str = "") -> str:
        return f"log_uniform({_fmt(self.low, scale)}, {_fmt(self.high, scale)}){' ' + unit if unit else ''}"


@dataclass(frozen=True)
class Normal(Prior):
    """Normal(mean, sd), truncated to [low, high] and renormalised there."""

    mean: float
    sd: float
    low: float = -math.inf
    high: float = math.inf
    kind = "normal"

    def problems(self) -> list[str]:
        if not (math.isfinite(self.mean) and math.isfinite(self.sd)):
            return ["a finite mean and standard deviation"]
        if not self.sd > 0:
            return ["a positive standard deviation (sd > 0; a fixed parameter is not inverted)"]
        if not self.low < self.high:
            return ["truncation bounds with low < high"]
        if not self._log_mass() > math.log(1e-12):
            return [
                f"a normal prior with probability inside the range [{self.low:.6g}, {self.high:.6g}] it is truncated to"
            ]
        return []

    def _a(self) -> float:
        return (self.low - self.mean) / self.sd

    def _b(self) -> float:
        return (self.high - self.mean) / self.sd

    def _log_mass(self) -> float:
        a, b = self._a(), self._b()
        if b <= 0:  # the mass lies in the left tail: compute it there without cancellation
            return float(special.log_ndtr(b) + np.log1p(-np.exp(special.log_ndtr(a) - special.log_ndtr(b))))
        if a >= 0:
            return float(special.log_ndtr(-a) + np.log1p(-np.exp(special.log_ndtr(-b) - special.log_ndtr(-a))))
        return float(np.log(special.ndtr(b) - special.ndtr(a)))

    def logpdf(self, x) -> np.ndarray:
        x, inside = _support(x, self.low, self.high)
        z = (x - self.mean) / self.sd
        value = -0.5 * z * z - math.log(self.sd * math.sqrt(2.0 * math.pi)) - self._log_mass()
        return np.where(inside, value, -np.inf)

    def ppf(self, q) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        if math.isinf(self.low) and math.isinf(self.high):
            return self.mean + self.sd * special.ndtri(q)
        with np.errstate(under="ignore"):  # SciPy's ppf underflows harmlessly in its tails (a caller may raise on it)
            return stats.truncnorm.ppf(q, self._a(), self._b(), loc=self.mean, scale=self.sd)

    def describe(self, scale: float = 1.0, unit: str = "") -> str:
        text = f"normal({_fmt(self.mean, scale)}, {_fmt(self.sd, scale)})"
        bounds = [b for b in (self.low, self.high) if math.isfinite(b)]
        if bounds:
            lo = "-inf" if math.isinf(self.low) else _fmt(self.low, scale)
            hi = "inf" if math.isinf(self.high) else _fmt(self.high, scale)
            text += f" truncated to [{lo}, {hi}]"
        return text + (f" {unit}" if unit else "")
