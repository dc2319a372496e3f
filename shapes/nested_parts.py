"""Parts of a seam cut that lie along one another are one thing, not two objects.

The splitter (:mod:`shapes.split`) cuts a cluster where its surface folds inwards. Two objects
side by side fold so, and so does one object made of parts: a telephone's handset lies in its
cradle along the base, its cord along the handset, and the crease between them is as concave as
the gap between a can and a box. What tells them apart across the support is the parts'
outline: objects set down beside one another touch over a short stretch of their outline (two
cans at a point, a box against another's side), while a long thin part lying along another
touches it over most of its length. A part *lies along* another when it is at least
``min_elongation`` times as long as it is wide across the support (its footprint's principal
axes) and the other part comes within ``near_m`` of it, across the support, along at least
``min_along_share`` of its length (slices ``slice_m`` long across its long axis).

>>> g = np.arange(0.0, 0.2, 0.01)
>>> base = np.array([(x, y, 0.05) for x in np.arange(0.05, 0.2, 0.01) for y in g])
>>> handset = np.array([(x, y, 0.1) for x in (0.0, 0.01, 0.02, 0.03) for y in g])
>>> voxels = np.vstack((base, handset))
>>> parts = np.repeat([0, 1], [len(base), len(handset)])
>>> int(joined_where_nested(voxels, parts, near_m=0.03, slice_m=0.01).max())
0
>>> can = np.array([(0.23 + 0.03 * np.cos(a), 0.1 + 0.03 * np.sin(a), 0.05) for a in g * 31])
>>> beside = np.vstack((base, can))
>>> int(joined_where_nested(beside, np.repeat([0, 1], [len(base), len(can)]), near_m=0.03,
...                         slice_m=0.01).max())
1
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["joined_where_nested", "lies_along"]


def lies_along(
    part: FloatArray,
    other: FloatArray,
    *,
    near_m: float,
    slice_m: float,
    min_elongation: float = 2.0,
    min_along_share: float = 0.75,
) -> bool:
    """Whether the voxels ``part`` lie along ``other`` across the support (the x-y plane): see
    the module docstring."""
    slices = _slices_when_long(part, slice_m, min_elongation)
    if slices is None:
        return False
    return bool(_along_share(part, slices, cKDTree(other[:, :2]), near_m) >= min_along_share)


def _slices_when_long(
    part: FloatArray, slice_m: float, min_elongation: float
) -> npt.NDArray[np.int64] | None:
    """Each voxel's slice (``slice_m`` long) along the part's long axis across the support, or
    None when the part is less than ``min_elongation`` times as long as it is wide."""
    across = part[:, :2] - part[:, :2].mean(axis=0)
    if len(across) < 2:
        return None
    axes = np.linalg.eigh(across.T @ across)[1]  # columns by rising spread: the long axis last
    along, wide = across @ axes[:, 1], across @ axes[:, 0]
    if float(along.max() - along.min()) < min_elongation * float(wide.max() - wide.min()):
        return None
    return np.asarray(np.floor((along - along.min()) / slice_m), dtype=np.int64)


def _along_share(
    part: FloatArray, slices: npt.NDArray[np.int64], other: cKDTree, near_m: float
) -> float:
    """The share of the part's slices in which a voxel lies within ``near_m`` of ``other`` (a
    k-d tree of its voxels across the support)."""
    near = np.isfinite(other.query(part[:, :2], distance_upper_bound=near_m)[0])
    # Slices are small counts from 0: a bincount's non-zero bins are the slices present.
    touched = np.count_nonzero(np.bincount(slices[near], minlength=1))
    return float(touched / np.count_nonzero(np.bincount(slices)))


def joined_where_nested(
    voxels: FloatArray,
    parts: npt.NDArray[np.int64],
    *,
    near_m: float,
    slice_m: float,
    min_elongation: float = 2.0,
    min_along_share: float = 0.75,
) -> npt.NDArray[np.int64]:
    """The labels 0, 1, ... of a cut's parts once every part that lies along a larger one
    (:func:`lies_along`) is joined with it, in the order of each joined part's lowest label.

    Raises ValueError when ``parts`` does not give one label per voxel.
    """
    if len(parts) != len(voxels):
        raise ValueError(f"parts: expected one label per voxel ({len(voxels)}), got {len(parts)}")
    count = int(parts.max(initial=-1)) + 1
    members = [voxels[parts == k] for k in range(count)]
    trees: dict[int, cKDTree] = {}
    root = list(range(count))

    def find(k: int) -> int:
        while root[k] != k:
            k = root[k]
        return k

    for a in range(count):
        slices = _slices_when_long(members[a], slice_m, min_elongation)
        if slices is None:  # most parts: no longer than twice their width
            continue
        for b in range(count):
            if a == b or (len(members[a]), a) > (len(members[b]), b):
                continue  # only along a larger part (or, as large, a later one)
            if b not in trees:
                trees[b] = cKDTree(members[b][:, :2])
            if _along_share(members[a], slices, trees[b], near_m) >= min_along_share:
                ra, rb = find(a), find(b)
                root[max(ra, rb)] = min(ra, rb)
    roots = np.array([find(k) for k in range(count)], dtype=np.int64)
    compact = np.unique(roots, return_inverse=True)[1].astype(np.int64)
    return compact[parts] if count else parts.copy()
