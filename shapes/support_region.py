"""The region a support covers: the main piece of its plane and that piece's outline.

A plane found by RANSAC holds every voxel within its tolerance, wherever it lies: beside the
desk the seat of a chair at the desk's height, across the room another table. The support is
the *main piece* of the plane, its largest connected part (voxels in neighbouring cells of a
``cell_m`` grid, diagonals included), and it covers the convex hull of that piece: objects
standing on a table hide the table under and behind them, and the hull of what is seen of the
table still covers them (PCL's tabletop segmentation takes the same convex hull,
``ExtractPolygonalPrismData``).

>>> xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [3, 3]], dtype=float)
>>> region = support_region(xy, cell_m=0.6)
>>> region.piece.tolist()  # the far voxel is a piece of its own
[True, True, True, True, True, False]
>>> region.contains(np.array([[0.5, 0.5], [1.04, 0.5], [2.0, 2.0]]), margin_m=0.05).tolist()
[True, True, False]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull, QhullError

from shapes.arrays import column_min, unique_inverse
from shapes.types import FloatArray

__all__ = ["SupportRegion", "pieces", "support_region"]


@dataclass(frozen=True, eq=False)
class SupportRegion:
    """The main piece of a support's voxels and the outline it covers (in the xy plane)."""

    piece: npt.NDArray[np.bool_]
    """Which of the plane's voxels form its main piece."""
    halfplanes: FloatArray
    """The convex hull of the piece as rows ``(a, b, c)``, ``a x + b y + c <= 0`` inside,
    ``(a, b)`` unit."""

    def contains(self, xy: FloatArray, margin_m: float) -> npt.NDArray[np.bool_]:
        """Which points lie inside the outline grown by ``margin_m`` on every side."""
        inside = xy @ self.halfplanes[:, :2].T + self.halfplanes[:, 2] <= margin_m
        return np.asarray(inside.all(axis=1), dtype=np.bool_)


def _box(xy: FloatArray) -> FloatArray:
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    rows = [[-1.0, 0.0, lo[0]], [1.0, 0.0, -hi[0]], [0.0, -1.0, lo[1]], [0.0, 1.0, -hi[1]]]
    return np.array(rows)


def pieces(xy: FloatArray, cell_m: float) -> npt.NDArray[np.intp]:
    """The connected piece of each point: points in occupied cells of a ``cell_m`` grid joined
    side by side or corner to corner are one piece. Pieces are numbered from 0 in no particular
    order. Only the occupied cells are held (a sparse graph, not a dense grid), so a cloud
    kilometres wide costs no more than its points.

    >>> pieces(np.array([[0.0, 0.0], [0.06, 0.06], [0.3, 0.0]]), cell_m=0.05).tolist()
    [0, 0, 1]
    """
    cells = np.floor((xy - column_min(xy)) / cell_m).astype(np.int64) + 1
    span = int(cells[:, 1].max()) + 2  # a neighbour's column never wraps into the next row
    keys, of_point, _ = unique_inverse(cells[:, 0] * span + cells[:, 1])
    rows, cols = [], []
    for step in (1, span - 1, span, span + 1):  # half the neighbourhood: the graph is undirected
        at = np.minimum(np.searchsorted(keys, keys + step), len(keys) - 1)
        found = keys[at] == keys + step
        rows.append(np.flatnonzero(found))
        cols.append(at[found])
    first, second = np.concatenate(rows), np.concatenate(cols)
    graph = coo_matrix((np.ones(len(first)), (first, second)), shape=(len(keys), len(keys)))
    _, label = connected_components(graph, directed=False)
    return np.asarray(label[of_point.ravel()], dtype=np.intp)


def largest_piece(xy: FloatArray, cell_m: float) -> npt.NDArray[np.bool_]:
    """Which points belong to the largest piece (:func:`pieces`)."""
    label = pieces(xy, cell_m)
    return np.asarray(label == np.argmax(np.bincount(label)), dtype=np.bool_)


_DIRECTIONS = np.array(
    [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]], float
)
"""Eight directions, counter-clockwise: the extreme points along them bound an octagon."""


def _hull_candidates(xy: FloatArray) -> npt.NDArray[np.bool_]:
    """Which points may be vertices of the convex hull: all but those strictly inside the
    octagon of the extreme points in eight directions (Akl and Toussaint's filter; the hull of
    what is left is the same, and qhull runs on a few hundred points, not thousands)."""
    corners = xy[np.argmax(xy @ _DIRECTIONS.T, axis=0)]
    inside = np.ones(len(xy), dtype=np.bool_)
    for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        if (a != b).any():  # a point extreme in two directions is one corner, not an edge
            inside &= (b[0] - a[0]) * (xy[:, 1] - a[1]) - (b[1] - a[1]) * (xy[:, 0] - a[0]) > 0
    return ~inside


def support_region(xy: FloatArray, cell_m: float) -> SupportRegion:
    """The main piece of a support's voxels (``xy``: their coordinates across the support) and
    its convex hull; the piece's bounding box when its points span no area."""
    piece = largest_piece(xy, cell_m)
    try:
        outline = xy[piece]
        hull = ConvexHull(outline[_hull_candidates(outline)])
        halfplanes = np.asarray(hull.equations, dtype=np.float64)
    except (QhullError, ValueError):  # fewer than three points, or all on one line
        halfplanes = _box(xy[piece])
    return SupportRegion(piece, halfplanes)
