"""Array reductions that NumPy does slowly on a frame's data, done the fast way, same values.

- ``a.min(axis=0)`` of a C-ordered ``(N, 3)`` array runs N inner loops of length 3, which on
  a frame's points costs 20 to 30 times as much as reducing each column as a strided vector
  (:func:`column_min`, :func:`column_max`, :func:`column_span`; a minimum is exact, NaN
  propagates alike);
- ``np.unique`` of integer keys (NumPy 2.4) hashes them and then sorts, which on 64,000 voxel
  keys costs 10 to 15 times a plain sort: :func:`unique_sorted` and :func:`unique_inverse` sort
  and compare neighbours, and give the same arrays;
- a dot product, norm or cross product of 3-vectors over an axis of length 3 costs several
  times two additions of whole arrays: :func:`dot3`, :func:`norm3` and :func:`cross3` give
  numpy's own bits;
- ``np.percentile`` of a short vector spends most of its time in its generality (axes, methods,
  weights): :func:`percentiles` selects the ranks it needs and interpolates as numpy's linear
  method does, to the bit, at a tenth of the cost.

>>> a = np.array([[1.0, 5.0], [3.0, -2.0], [2.0, 0.0]])
>>> column_min(a).tolist(), column_max(a).tolist(), column_span(a).tolist()
([1.0, -2.0], [3.0, 5.0], [2.0, 7.0])
>>> keys, index, counts = unique_inverse(np.array([7, 3, 7, 9]))
>>> keys.tolist(), index.tolist(), counts.tolist()
([3, 7, 9], [1, 0, 1, 2], [1, 2, 1])
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TypeVar

import numpy as np
import numpy.typing as npt

__all__ = [
    "column_max",
    "column_min",
    "column_span",
    "cross3",
    "dot3",
    "inside_box",
    "norm3",
    "percentiles",
    "unique_inverse",
    "unique_sorted",
]

_T = TypeVar("_T", bound=np.generic)


def column_min(a: npt.NDArray[_T]) -> npt.NDArray[_T]:
    """``a.min(axis=0)`` of a 2-D array. Raises ValueError when ``a`` has no rows."""
    return np.array([a[:, i].min() for i in range(a.shape[1])], dtype=a.dtype)


def column_max(a: npt.NDArray[_T]) -> npt.NDArray[_T]:
    """``a.max(axis=0)`` of a 2-D array. Raises ValueError when ``a`` has no rows."""
    return np.array([a[:, i].max() for i in range(a.shape[1])], dtype=a.dtype)


def column_span(a: npt.NDArray[_T]) -> npt.NDArray[_T]:
    """``np.ptp(a, axis=0)`` of a 2-D array. Raises ValueError when ``a`` has no rows."""
    return np.asarray(np.subtract(column_max(a), column_min(a)), dtype=a.dtype)


def unique_sorted(a: npt.NDArray[_T]) -> npt.NDArray[_T]:
    """``np.unique(a)`` of a 1-D array: its distinct values, ascending."""
    ordered = np.sort(a)
    return ordered[np.concatenate(([True], ordered[1:] != ordered[:-1]))]


def unique_inverse(
    a: npt.NDArray[_T],
) -> tuple[npt.NDArray[_T], npt.NDArray[np.intp], npt.NDArray[np.intp]]:
    """``np.unique(a, return_inverse=True, return_counts=True)`` of a 1-D array: its distinct
    values ascending, the index of each element's value among them, and each value's count."""
    order = np.argsort(a, kind="stable")  # keys from an image come in runs: a merge sort's case
    ordered = a[order]
    first = np.concatenate(([True], ordered[1:] != ordered[:-1]))
    index = np.empty(len(a), dtype=np.intp)
    index[order] = np.cumsum(first) - 1
    starts = np.flatnonzero(first)
    counts = np.diff(np.append(starts, len(a)))
    return ordered[starts], index, counts


def dot3(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The dot products of 3-vectors along the last axis, added in numpy's order (so equal to
    ``(a * b).sum(axis=-1)`` to the bit): a reduction over an axis of length 3 costs numpy
    several times more than two additions of whole arrays."""
    return np.asarray(a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2])


def norm3(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``np.linalg.norm(v, axis=-1)`` for 3-vectors, to the bit (see :func:`dot3`)."""
    return np.asarray(np.sqrt(dot3(v, v)))


def cross3(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """``np.cross(a, b)`` for 3-vectors along the last axis, to the bit, without its axis
    juggling."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=-1)


def inside_box(
    points: npt.NDArray[np.float64], lo: npt.NDArray[np.float64], hi: npt.NDArray[np.float64]
) -> npt.NDArray[np.bool_]:
    """Which of ``points`` lie strictly inside the box from ``lo`` to ``hi`` across their first
    two coordinates (the third, if any, plays no part).

    >>> inside_box(np.array([[0.5, 0.5, 9.0], [1.0, 0.5, 0.0]]), np.zeros(2), np.ones(2)).tolist()
    [True, False]
    """
    x, y = points[:, 0], points[:, 1]
    inside: npt.NDArray[np.bool_] = (x > lo[0]) & (x < hi[0]) & (y > lo[1]) & (y < hi[1])
    return inside


def percentiles(values: npt.NDArray[np.float64], q: Sequence[float]) -> list[float]:
    """``np.percentile(values, q)`` of a 1-D float array, as floats equal to numpy's to the bit
    (its default linear method: the ranks below and above each virtual index, and numpy's
    interpolation, taken from the upper rank from half way up); NaN in ``values`` gives NaN.

    Raises ValueError if ``values`` is empty or not one-dimensional, or a ``q`` is outside
    0 to 100.

    >>> percentiles(np.array([4.0, 1.0, 3.0, 2.0]), [0, 50, 90])
    [1.0, 2.5, 3.7]
    """
    if np.ndim(values) != 1 or len(values) == 0:
        raise ValueError(f"values: expected a non-empty 1-D array, got shape {np.shape(values)}")
    if not all(0.0 <= p <= 100.0 for p in q):
        raise ValueError(f"q: expected percentiles between 0 and 100, got {list(q)}")
    n = len(values)
    # numpy's steps, value for value (down to the sign of a zero): the virtual index, the ranks
    # either side (both the last one, written -1, from the top rank on), one partition at all
    # of them and at the first and last, then its interpolation.
    virtual = [(n - 1) * (p / 100) for p in q]
    below = [-1 if v >= n - 1 else math.floor(v) for v in virtual]
    above = [-1 if b == -1 else b + 1 for b in below]
    ordered = np.partition(values, np.unique([0, -1, *below, *above]))
    if np.isnan(ordered[-1]):  # NaN sorts last, and numpy's answer is then NaN throughout
        return [math.nan] * len(q)
    out = []
    for v, b, a in zip(virtual, below, above, strict=True):
        lo, hi, t = float(ordered[b]), float(ordered[a]), v - b
        diff = hi - lo
        out.append(hi - diff * (1 - t) if t >= 0.5 else lo + diff * t)
    return out
