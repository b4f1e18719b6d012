"""Work-precision benchmarks of every solver in wobble (issue 8).

The top layer of the package: only :mod:`wobble.cli` imports it, and it may
import everything below (plots, the public API, models, numerics). It measures,
for fixed named cases, the error of each method against a reference that does
not depend on that method, and the time it takes (one warm-up, then the minimum
and median of several runs, all methods interleaved in one process), and writes
``docs/performance.md``.

Entry points: ``wobble bench`` (:mod:`wobble.cli.bench`) and
``scripts/work_precision.py``, both calling :func:`wobble.bench.harness.main`.
"""

from __future__ import annotations

__all__ = ["harness"]
