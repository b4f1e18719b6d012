"""Euclidean lengths without underflow or overflow (plain float64 NumPy)."""

from __future__ import annotations

import numpy as np

__all__ = ["norm"]


def norm(vectors, axis: int = -1, keepdims: bool = False) -> np.ndarray:
    """Euclidean length along ``axis`` without underflow or overflow: each vector is scaled by its largest
    component first. ``np.linalg.norm`` squares before it sums, so a spin of 1e-170 rad/s came out 0 (and
    1e-160 as 9.99994e-161): the free figure divided by it and drew nothing.

    >>> float(norm([1e-170, 0.0, 1e-175])), float(norm([3e200, 4e200, 0.0])) / 1e200
    (1.00000000005e-170, 5.0)
    """
    v = np.asarray(vectors, dtype=float)
    scale = np.max(np.abs(v), axis=axis, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):  # a zero vector is 0, a NaN one NaN
        unit = np.where(scale > 0, v / np.where(scale > 0, scale, 1.0), 0.0)
    out = np.linalg.norm(unit, axis=axis, keepdims=True) * scale
    return out if keepdims else np.squeeze(out, axis=axis)
