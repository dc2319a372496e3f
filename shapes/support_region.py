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
from scipy import ndimage
from scipy.spatial import ConvexHull, QhullError

from shapes.types import FloatArray

__all__ = ["SupportRegion", "support_region"]


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


def support_region(xy: FloatArray, cell_m: float) -> SupportRegion:
    """The main piece of a support's voxels (``xy``: their coordinates across the support) and
    its convex hull; the piece's bounding box when its points span no area."""
    cells = np.floor((xy - xy.min(axis=0)) / cell_m).astype(np.intp)
    grid = np.zeros(tuple(cells.max(axis=0) + 1), dtype=bool)
    grid[cells[:, 0], cells[:, 1]] = True
    labels, count = ndimage.label(grid, structure=np.ones((3, 3), dtype=bool))
    of_voxel = labels[cells[:, 0], cells[:, 1]]
    main = int(np.argmax(np.bincount(of_voxel, minlength=count + 1)[1:])) + 1
    piece = of_voxel == main
    try:
        halfplanes = np.asarray(ConvexHull(xy[piece]).equations, dtype=np.float64)
    except (QhullError, ValueError):  # fewer than three points, or all on one line
        halfplanes = _box(xy[piece])
    return SupportRegion(piece, halfplanes)
