"""Work-precision benchmarks of every solver in wobble and of its public API, from a source checkout.

Not part of the installed package: the benchmark reads the committed mpmath references
(tests/references/) and its own Radau reference (benchmarks/engine_reference.json), and
writes docs/performance.md and docs/figures/, all files of the source tree. It may import
everything in wobble (the public API, models, numerics, plots); nothing in wobble imports
it (import-linter: the top layer). For each fixed named case it measures the error of each
method against a reference that does not depend on that method, and the time it takes
(one warm-up, then the minimum and median of several runs, all methods interleaved in
one process).

Entry points: ``wobble bench`` (:mod:`wobble.cli.bench`, which finds this folder next to
the imported wobble package) and ``python scripts/work_precision.py``, both through
:mod:`benchmarks.harness`.
"""

from __future__ import annotations

__all__ = ["harness"]
