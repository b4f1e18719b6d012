"""Periodic series from a table of Taylor expansions, compiled (Numba; float64).

The heavy top's periodic parts (theta and the two phase corrections, docs/heavy-top.md)
are tabulated at S nodes over one nutation period as Taylor coefficients
``f^(j)(node) / j!``; a sample at reduced phase r takes the nearest node and sums the
polynomial in ``d = r - node`` by Horner. :meth:`wobble.models.top_series.Fourier.series` does it
in NumPy with one gather per coefficient (``np.take``: 3 series x 6 coefficients over the
samples); here one pass over the samples computes every series, the table staying in
cache. The operations are NumPy's, in the same order and without fused multiply-adds,
so the two agree bit for bit.

Numba is imported by this module only (~0.4 s once per process).
"""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["series"]


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _series(r, k0, inv_h, h, table, rows, out):
    nodes = table.shape[2]
    order = table.shape[1] - 1
    for i in range(r.shape[0]):
        u = (r[i] + k0) * inv_h
        idx = np.rint(u)
        d = (u - idx) * h
        ii = int(idx)
        if ii >= nodes:  # r = +K is the node of r = -K
            ii -= nodes
        for k in range(rows.shape[0]):
            row = rows[k]
            acc = table[row, order, ii]
            for j in range(order - 1, -1, -1):
                acc *= d
                acc += table[row, j, ii]
            out[k, i] = acc


def series(r, k0: float, h: float, table, rows):
    """The series ``rows`` of ``table`` (kinds, order + 1, nodes) at reduced phases ``r`` (1-D).

    Parameters
    ----------
    r : numpy.ndarray
        Reduced phases, ``|r| <= K`` (the table spans ``[-K, K]`` with node spacing ``h``).
    k0 : float
        K, the offset of the first node.
    h : float
        Node spacing.
    table : numpy.ndarray
        ``f^(j)(node) / j!`` for each series, coefficient order and node.
    rows : sequence of int
        The series wanted.

    Returns
    -------
    list of numpy.ndarray
        One array like ``r`` per row.
    """
    r = np.ascontiguousarray(r, dtype=float)
    out = np.empty((len(rows), r.size))
    _series(r.reshape(-1), float(k0), 1.0 / h, float(h), np.ascontiguousarray(table, dtype=float),
            np.asarray(rows, dtype=np.int64), out)
    return [o.reshape(r.shape) for o in out]
