"""Principal axes in any order mapped to ascending ones by a proper signed permutation.

The exact solutions and the flow map work in a right-handed frame whose axes carry the
principal moments in increasing order. A user's axes (any order of the moments) are mapped
to it by a signed permutation of determinant +1: a plain permutation when it is even; an
odd one (a swap, a mirror image: P(a x b) = -Pa x Pb) has its last axis reversed. Vectors
go in with :func:`to_sorted` and come back with :func:`to_user`; quaternions map their
vector part the same way.
"""

from __future__ import annotations

import numpy as np

__all__ = ["proper_signs", "proper_sort", "to_sorted", "to_user"]


def proper_signs(order) -> np.ndarray:
    """Signs making the permutation ``order`` proper: (1, 1, 1), or (1, 1, -1) when it is odd.

    ``order`` has shape (..., 3): model axis k is user axis ``order[..., k]``.
    """
    order = np.asarray(order)
    inversions = (
        (order[..., 0] > order[..., 1]).astype(int) + (order[..., 0] > order[..., 2]) + (order[..., 1] > order[..., 2])
    )
    signs = np.ones(order.shape)
    signs[..., 2] = np.where(inversions % 2 == 1, -1.0, 1.0)
    return signs


def proper_sort(moments):
    """Per body, the signed permutation (det +1) taking user axes to ascending moments.

    Parameters
    ----------
    moments : array_like, shape (..., 3)
        Principal moments (kg m^2) in the user's axis order.

    Returns
    -------
    order : numpy.ndarray of int, shape (..., 3)
        Model axis k is user axis ``order[..., k]``.
    signs : numpy.ndarray, shape (..., 3)
        ... times ``signs[..., k]`` (the last sign is -1 for odd permutations).
    """
    order = np.argsort(np.asarray(moments, dtype=float), axis=-1, kind="stable")
    return order, proper_signs(order)


def _shared(order) -> bool:
    # One order for every vector (a single body): plain column copies, no index arrays.
    return np.ndim(order) == 1


def to_sorted(v, order, signs) -> np.ndarray:
    """User-frame vectors ``v`` (..., 3) in the sorted (model) frame."""
    v = np.asarray(v, dtype=float)
    if _shared(order):
        return np.stack([signs[k] * v[..., order[k]] for k in range(3)], axis=-1)
    return np.asarray(signs) * np.take_along_axis(v, np.broadcast_to(np.asarray(order), v.shape), axis=-1)


def to_user(v, order, signs) -> np.ndarray:
    """Sorted-frame vectors ``v`` (..., 3) back in the user's frame (C-ordered output)."""
    v = np.asarray(v, dtype=float)
    out = np.empty(v.shape)
    if _shared(order):
        for k in range(3):
            out[..., order[k]] = signs[k] * v[..., k]
        return out
    np.put_along_axis(out, np.broadcast_to(np.asarray(order), v.shape), np.asarray(signs) * v, axis=-1)
    return out
