"""Eigen-decomposition of a real symmetric 3x3 matrix with a canonical, stable frame.

The eigenvalues of an inertia tensor are well conditioned; its eigenvectors are not
when two eigenvalues nearly coincide (Earth's equatorial moments differ by a few
parts in 10^5, a symmetric top's by rounding only). A plain ``numpy.linalg.eigh``
then returns an arbitrary basis of the near-degenerate plane that jumps by O(1)
under a perturbation of one ulp. This module fixes the frame by rules that do not
depend on rounding noise:

* eigenvalues are returned in ascending order, eigenvectors as the **rows** of a
  proper rotation matrix (right-handed, determinant +1);
* axes 1 and 3, when not degenerate, point so that their component of largest
  magnitude is positive (the first such component on a tie); axis 2 completes the
  right-handed frame;
* when two eigenvalues agree to the relative tolerance ``rtol`` (measured against
  the larger of the two), the unique axis is kept and the pair is replaced by a
  canonical basis of its plane: the first member is the projection onto the plane
  of the input axis most nearly perpendicular to the unique axis; the second
  completes the right-handed frame;
* when all three agree, the frame is the input frame (the identity).

Pure float64 NumPy; no units (SI or any consistent unit).
"""

from __future__ import annotations

import numpy as np

__all__ = ["symmetric_eigen3", "canonical_frame", "degenerate_pairs"]


def degenerate_pairs(differences: np.ndarray, values: np.ndarray, rtol: float) -> tuple[bool, bool]:
    """Which neighbouring pairs of ascending eigenvalues coincide within ``rtol``.

    Parameters
    ----------
    differences : ndarray, shape (3, 3)
        Antisymmetric matrix of differences ``D[i, j] = values[i] - values[j]``
        (given directly when known without cancellation).
    values : ndarray, shape (3,)
        Ascending eigenvalues.
    rtol : float
        Relative tolerance against the larger member of each pair.

    Returns
    -------
    (bool, bool)
        Whether (1, 2) and (2, 3) are degenerate.
    """
    d12 = abs(differences[1, 0])
    d23 = abs(differences[2, 1])
    return bool(d12 <= rtol * abs(values[1])), bool(d23 <= rtol * abs(values[2]))


def _signed(v: np.ndarray) -> np.ndarray:
    """``v`` with its largest-magnitude component made positive (first on a tie)."""
    k = int(np.argmax(np.abs(v)))
    return -v if v[k] < 0 else v


def _plane_basis_vector(axis: np.ndarray) -> np.ndarray:
    """Unit vector in the plane perpendicular to ``axis``, from the most perpendicular input axis."""
    k = int(np.argmin(np.abs(axis)))
    e = np.zeros(3)
    e[k] = 1.0
    p = e - axis[k] * axis
    return p / np.linalg.norm(p)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def canonical_frame(values: np.ndarray, vectors: np.ndarray, differences: np.ndarray, rtol: float) -> np.ndarray:
    """Apply the sign, degeneracy and handedness rules to an eigenbasis.

    Parameters
    ----------
    values : ndarray, shape (3,)
        Ascending eigenvalues.
    vectors : ndarray, shape (3, 3)
        Orthonormal eigenvectors as rows, in the order of ``values``.
    differences : ndarray, shape (3, 3)
        ``D[i, j] = values[i] - values[j]`` (see :func:`degenerate_pairs`).
    rtol : float
        Relative tolerance for calling two eigenvalues equal.

    Returns
    -------
    ndarray, shape (3, 3)
        Rows are the canonical axes; a proper rotation matrix.
    """
    deg12, deg23 = degenerate_pairs(differences, values, rtol)
    if deg12 and deg23:
        return np.eye(3)
    if deg12:
        a3 = _signed(_unit(vectors[2]))
        a1 = _plane_basis_vector(a3)
        a2 = np.cross(a3, a1)
    elif deg23:
        a1 = _signed(_unit(vectors[0]))
        a2 = _plane_basis_vector(a1)
        a3 = np.cross(a1, a2)
    else:
        a1 = _signed(_unit(vectors[0]))
        a3 = _signed(_unit(vectors[2]))
        # Re-orthogonalise against rounding, then complete the right-handed frame.
        a3 = _unit(a3 - (a3 @ a1) * a1)
        a2 = np.cross(a3, a1)
    return np.array([a1, a2, a3])


def symmetric_eigen3(matrix, rtol: float) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (ascending) and canonical eigenvector frame of a symmetric 3x3 matrix.

    The matrix is scaled by a power of two before LAPACK's ``eigh`` (no rounding,
    no overflow for entries from 1e-300 to 1e300); a matrix that is already diagonal
    is not decomposed at all, so its eigenvalues are returned exactly.

    Parameters
    ----------
    matrix : array_like, shape (3, 3)
        Real symmetric matrix (only the lower triangle is read by ``eigh``).
    rtol : float
        Relative tolerance for degeneracy, see :func:`canonical_frame`.

    Returns
    -------
    values : ndarray, shape (3,)
        Ascending eigenvalues.
    axes : ndarray, shape (3, 3)
        Rows are unit eigenvectors; right-handed (determinant +1).
    """
    a = np.asarray(matrix, dtype=float)
    scale = float(np.max(np.abs(a)))
    if scale == 0.0:
        return np.zeros(3), np.eye(3)
    off = a[~np.eye(3, dtype=bool)]
    if not np.any(off):
        diag = np.diag(a).copy()
        order = np.argsort(diag, kind="stable")
        values, vectors = diag[order], np.eye(3)[order]
    else:
        exponent = np.frexp(scale)[1]
        w, v = np.linalg.eigh(np.ldexp(a, -exponent))
        values, vectors = np.ldexp(w, exponent), v.T
    differences = values[:, None] - values[None, :]
    return values, canonical_frame(values, vectors, differences, rtol)
