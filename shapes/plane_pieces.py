"""A plane is what its connected pieces are, not every voxel its RANSAC took.

RANSAC's planes are unbounded: a plane holds every voxel within its tolerance, wherever it
lies. A box's front face lines up with voxels scattered across the room (the wall behind it,
the edges of furniture); a plane found just under a desk's top runs through the near edge of
the desk, the keys of a keyboard and a strip of paper. Judged whole, the box's face rises to
the height of the furniture and is taken for a wall, and the plane under the desk's top is
taken for a support of its own, which takes the keyboard's lower voxels from the desk. So
segmentation judges a plane by its pieces (its voxels joined on a grid, diagonals included, as
a support's main piece is: :mod:`shapes.support_region`):

- a *tilted* plane whose main piece stands on a larger horizontal plane (its centre inside
  the hull of that plane's main piece, all but a few of its voxels above it and lower than
  ``max_height_m`` over it) is the face of an object standing there, not a wall: that piece,
  and every other piece of the plane that stands so, stays free (:func:`faces_standing_on`);
- a *horizontal* plane whose main piece holds less than ``min_main_share`` of its voxels is
  no surface of its own but scattered pieces of other things: it is reduced to its main piece
  (:func:`is_scattered`).

>>> from shapes.support_region import support_region
>>> ticks = np.arange(-1.0, 1.0, 0.05)
>>> square = np.array([[x, y] for x in ticks for y in ticks])  # a floor 2 m wide
>>> floor = Ground(np.array([0.0, 0.0, 1.0]), 0.0, support_region(square, 0.05), len(square))
>>> grid = lambda ys, zs: np.array([[0.0, y, z] for y in ys for z in zs])  # in the plane x = 0
>>> face = grid(np.arange(0.0, 0.3, 0.01), np.arange(0.0, 0.4, 0.01))  # a box's, 30 x 40 cm
>>> wall = grid(np.arange(0.96, 1.0, 0.01), np.arange(0.0, 1.2, 0.01))  # at the floor's edge
>>> voxels = np.vstack((face, wall))
>>> freed = faces_standing_on(voxels, np.full(len(voxels), 0.01), np.array([1.0, 0.0, 0.0]),
...     [floor], cell_m=0.05, max_height_m=0.6, edge_margin_m=0.02, min_voxels=12)
>>> int(freed[: len(face)].sum()), int(freed[len(face) :].sum())  # the face, not the wall
(1200, 0)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.support_region import SupportRegion, largest_piece, pieces
from shapes.types import FloatArray

__all__ = ["Ground", "faces_standing_on", "is_scattered", "main_piece"]


@dataclass(frozen=True, eq=False)
class Ground:
    """A horizontal plane that objects may stand on: its upward unit ``normal`` and ``offset``
    (a point's height over it is ``p @ normal + offset``), its :class:`SupportRegion` and how
    many voxels its main piece holds."""

    normal: FloatArray
    offset: float
    region: SupportRegion
    size: int


def is_scattered(region: SupportRegion, min_main_share: float) -> bool:
    """Whether a plane's main piece holds less than ``min_main_share`` of its voxels: the
    plane is then no surface of its own but a line-up of pieces of other things.

    >>> from shapes.support_region import support_region
    >>> xy = np.array([[0.0, 0.0], [0.02, 0.0], [1.0, 1.0], [2.0, 2.0]])
    >>> is_scattered(support_region(xy, 0.05), 0.5), is_scattered(support_region(xy, 0.05), 0.6)
    (False, True)
    """
    return float(region.piece.mean()) < min_main_share


def _in_plane_axes(points: FloatArray, normal: FloatArray) -> FloatArray:
    """The points' coordinates along two unit axes of the plane whose normal is ``normal``
    (cross products written out: ``np.cross`` costs more than the rest on three numbers)."""
    a, b, c = (float(v) for v in normal)
    # e1 = normal x (1, 0, 0), or normal x (0, 1, 0) when the normal lies near x.
    e1 = np.array([0.0, c, -b]) if abs(a) < 0.9 else np.array([-c, 0.0, a])
    e1 /= math.sqrt(float(e1 @ e1))
    e2 = np.array([b * e1[2] - c * e1[1], c * e1[0] - a * e1[2], a * e1[1] - b * e1[0]])
    return np.asarray(points @ np.column_stack((e1, e2)), dtype=np.float64)


def main_piece(points: FloatArray, normal: FloatArray, cell_m: float) -> npt.NDArray[np.bool_]:
    """Which of a plane's voxels (``points``, its unit ``normal``) make its main piece: the
    largest of its pieces when they are joined on a ``cell_m`` grid in the plane (side by side
    or corner to corner), whatever the plane's tilt.

    >>> wall = np.array([[0.0, y, z] for y in (0.0, 0.02, 0.04) for z in (0.0, 0.02)])
    >>> stray = np.array([[0.0, 1.0, -0.3]])
    >>> main_piece(np.vstack((wall, stray)), np.array([1.0, 0.0, 0.0]), 0.05).tolist()
    [True, True, True, True, True, True, False]
    """
    if len(points) == 0:
        return np.zeros(0, dtype=np.bool_)
    return largest_piece(_in_plane_axes(points, normal), cell_m)


def faces_standing_on(
    points: FloatArray,
    tolerance: FloatArray,
    normal: FloatArray,
    grounds: Sequence[Ground],
    *,
    cell_m: float,
    max_height_m: float,
    edge_margin_m: float,
    min_voxels: int,
    max_astray_share: float = 0.02,
) -> npt.NDArray[np.bool_]:
    """Which of a tilted plane's voxels (``points``, its unit ``normal``; ``tolerance``: how far
    from a plane each voxel may lie and still belong to it) are faces of objects: when its
    main piece (its voxels joined on a ``cell_m`` grid in the plane) stands on one of the
    ``grounds``, those of its pieces of at least ``min_voxels`` voxels that stand on one of
    them, holding more voxels than the piece; else none (the plane is a wall, and what else
    lines up with it, a strip of clutter along its base, is left to it).

    A piece stands on a ground when its centre lies inside the ground's main piece's hull
    shrunk by ``edge_margin_m``, and at most ``max_astray_share`` of its voxels lie
    ``max_height_m`` or more over the ground or more than twice their tolerance under it (where
    a face meets the ground, the plane takes the ground's own voxels within its tolerance). A
    wall rises past ``max_height_m``, or stands on the ground's outline, where the ground seen
    ends; a box's face stands inside it, lower.
    """
    if len(points) < min_voxels or not grounds:
        return np.zeros(len(points), dtype=np.bool_)
    label = pieces(_in_plane_axes(points, normal), cell_m)
    size = np.bincount(label)
    centres = np.column_stack(
        [np.bincount(label, weights=points[:, axis]) / size for axis in range(2)]
    )
    standing = np.zeros(len(size), dtype=np.bool_)
    for ground in grounds:
        candidate = (size >= min_voxels) & (size < ground.size) & ~standing
        candidate &= ground.region.contains(centres, -edge_margin_m)
        if not candidate.any():
            continue
        height = points @ ground.normal + ground.offset
        astray = (height >= max_height_m) | (height < -2 * tolerance)
        share = np.bincount(label, weights=astray, minlength=len(size)) / size
        standing |= candidate & (share <= max_astray_share)
    if not standing[np.argmax(size)]:  # the plane is a wall's, whatever else lines up with it
        standing[:] = False
    return np.asarray(standing[label], dtype=np.bool_)
