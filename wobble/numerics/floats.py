"""The float64 range, named once (plain Python floats).

``TINY`` is the smallest normal double: below it a number keeps only some of its 53 bits, or none,
so the package refuses inputs and results that would live there. ``SQRT_TINY`` and ``SQRT_HUGE``
bound quantities that are squared later (a planet file's scales, whose variances the uncertainty
propagation forms).
"""

from __future__ import annotations

import math
import sys

__all__ = ["EPS", "TINY", "HUGE", "SQRT_TINY", "SQRT_HUGE"]

#: The spacing of doubles at 1, 2^-52.
EPS = sys.float_info.epsilon
#: The smallest normal double, 2^-1022 = 2.225e-308.
TINY = sys.float_info.min
#: The largest double, 1.798e308.
HUGE = sys.float_info.max
#: Their square roots: a quantity between them has a normal, finite square.
SQRT_TINY = math.sqrt(TINY)
SQRT_HUGE = math.sqrt(HUGE)
