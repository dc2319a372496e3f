"""Surface normals of point neighbourhoods, in closed form.

A normal is the smallest principal axis of a neighbourhood's covariance. For many small
neighbourhoods at once, the eigenvalue of a 3 x 3 symmetric matrix in closed form (the
trigonometric solution of its characteristic cubic) and the eigenvector as the longest cross
product of two rows of ``C - lambda I`` cost a few array operations, where a batched LAPACK
``eigh`` pays a call per matrix.

>>> flat = np.column_stack((np.random.default_rng(0).random((50, 2)), np.zeros(50)))
>>> np.abs(patch_normals(flat, np.arange(50)[None, :10].repeat(2, axis=0))).round(6).tolist()
[[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shapes.types import FloatArray

__all__ = ["patch_normals", "smallest_axes"]


def smallest_axes(cov: FloatArray) -> FloatArray:
    """Unit eigenvectors of the smallest eigenvalue of ``(N, 3, 3)`` symmetric matrices.

    A matrix with a repeated smallest eigenvalue (a line, a point) gets one of its axes.

    >>> np.abs(smallest_axes(np.diag([3.0, 1.0, 2.0])[None])).round(6).tolist()
    [[0.0, 1.0, 0.0]]
    """
    n = len(cov)
    # The nine entries as contiguous rows (``e[3 * i + j]`` is ``cov[:, i, j]``): the same
    # arithmetic as on the strided columns of ``cov``, at half the cost.
    e = np.ascontiguousarray(np.reshape(cov, (n, 9)).T)
    return _smallest_axes_of_entries(list(e))


def _smallest_axes_of_entries(e: list[FloatArray]) -> FloatArray:
    """:func:`smallest_axes` of the matrices whose entries ``(i, j)`` are the arrays
    ``e[3 * i + j]`` (nine of length N), to the bit."""
    n = len(e[0])
    a00, a11, a22 = e[0], e[4], e[8]
    a01, a02, a12 = e[1], e[2], e[5]
    q = (a00 + a11 + a22) / 3.0
    off = a01 * a01 + a02 * a02 + a12 * a12
    p = np.sqrt(((a00 - q) ** 2 + (a11 - q) ** 2 + (a22 - q) ** 2 + 2.0 * off) / 6.0)
    safe = np.where(p > 0, p, 1.0)
    b00, b11, b22 = (a00 - q) / safe, (a11 - q) / safe, (a22 - q) / safe
    b01, b02, b12 = a01 / safe, a02 / safe, a12 / safe
    half_det = (
        b00 * (b11 * b22 - b12 * b12)
        - b01 * (b01 * b22 - b12 * b02)
        + b02 * (b01 * b12 - b11 * b02)
    ) / 2.0
    phi = np.arccos(np.clip(half_det, -1.0, 1.0)) / 3.0
    smallest = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
    # The rows of ``C - smallest I`` entry by entry, each as ``cov - smallest * np.eye(3)``
    # gives it (the off-diagonal ones minus ``smallest * 0.0``, which keeps the sign of a zero).
    r = [e[k] - smallest * (1.0 if k in (0, 4, 8) else 0.0) for k in range(9)]
    rows = (r[0:3], r[3:6], r[6:9])
    # The cross products of two rows (np.cross's products and differences, in its order),
    # stacked as ``candidates[:, k]``.
    candidates = np.empty((n, 3, 3))
    for k, (u, v) in enumerate(((0, 1), (0, 2), (1, 2))):
        (u0, u1, u2), (v0, v1, v2) = rows[u], rows[v]
        candidates[:, k, 0] = u1 * v2 - u2 * v1
        candidates[:, k, 1] = u2 * v0 - u0 * v2
        candidates[:, k, 2] = u0 * v1 - u1 * v0
    lengths = np.einsum("nki,nki->nk", candidates, candidates)
    best = lengths.argmax(axis=1)
    axis = candidates[np.arange(n), best]
    norm = np.sqrt(lengths[np.arange(n), best])
    # Two equal smallest eigenvalues leave no cross product: any axis normal to the largest.
    flat = norm <= 1e-30 * np.maximum(1.0, q * q)
    if flat.any():
        cov = np.stack(e, axis=1).reshape(n, 3, 3)
        axis[flat] = np.linalg.eigh(cov[flat])[1][:, :, 0]
        norm[flat] = 1.0
    return np.asarray(axis / norm[:, None], dtype=np.float64)


def patch_normals(points: FloatArray, neighbours: npt.NDArray[np.intp]) -> FloatArray:
    """Unoriented unit normals, one per row of ``neighbours`` (``(N, k)`` indices into
    ``points``): the smallest principal axis of those points.

    Raises ValueError when ``neighbours`` is not two-dimensional.
    """
    if np.ndim(neighbours) != 2:
        raise ValueError(
            f"neighbours: expected an (N, k) array of indices, got shape {np.shape(neighbours)}"
        )
    # Each coordinate gathered as (k, N): the sums over the k neighbours then run over whole
    # rows, one neighbour after another, the order (and so the values) of the sums over the
    # middle axis of (N, k, 3) and of einsum's, at a fraction of the cost; the covariance's six
    # distinct entries are summed the same way, and handed on as rows, not as (N, 3, 3).
    columns = np.ascontiguousarray(np.transpose(points))
    rows = np.ascontiguousarray(np.transpose(neighbours))  # taken from three times
    centred = []
    for column in columns:
        patch = np.take(column, rows)  # column[rows]: several times the cost
        centred.append(patch - patch.mean(axis=0))
    entries: list[FloatArray | None] = [None] * 9
    for i in range(3):
        for j in range(i, 3):
            entries[3 * i + j] = entries[3 * j + i] = (centred[i] * centred[j]).sum(axis=0)
    return _smallest_axes_of_entries([x for x in entries if x is not None])
