"""A support seen as a band of parallel planes is one support.

A floor or a desk whose depth undulates (smoothed depth, a warped far desk) is a band of voxels
thicker than one plane's tolerance. The plane search covers the rest of that band with more
planes parallel to the first, lying just under or over it and among its voxels. Judged on
their own, one under the support becomes a second support whose margin starts inside the
first's band, and one over it a step that keeps the objects' bottoms. :func:`one_plane_per_band`
folds them into the support before any plane is judged (:mod:`shapes.segment.supports`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from shapes.segment.params import SegmentationParams
from shapes.segment.planes import Plane
from shapes.support_region import largest_piece
from shapes.types import FloatArray


def one_plane_per_band(
    planes: list[Plane], voxels: FloatArray, tolerance: FloatArray, params: SegmentationParams
) -> list[Plane]:
    """``planes`` (in the world frame, their inliers indexing ``voxels``) with each horizontal
    plane that lies in a larger horizontal plane's band folded into it (:func:`in_band_of`),
    largest first: the larger one keeps its plane and takes the smaller one's voxels; the
    smaller one is dropped. The larger one's plane is kept, not refitted through the union: the
    band's far voxels are the surface's undulation or the slice through objects' bottoms, and
    would tilt or lift it.
    Planes that are not horizontal are returned as they are. ``tolerance``: per voxel, how far
    from a plane it may lie and still belong to it.

    >>> import numpy as np
    >>> from shapes.segment.planes import Plane
    >>> xy = np.c_[np.divmod(np.arange(400), 20)] * 0.025  # a 0.5 m square, 2.5 cm apart
    >>> z = np.r_[np.zeros(200), np.full(200, -0.012)]  # a floor and a plane just under it
    >>> voxels = np.c_[np.r_[xy[::2], xy[1::2]], z]  # the two interleaved
    >>> up = np.array([0.0, 0.0, 1.0])
    >>> floor = Plane(up, 0.0, np.arange(400) < 200, True)
    >>> under = Plane(up, 0.012, np.arange(400) >= 200, True)
    >>> [int(p.inliers.sum()) for p in one_plane_per_band([floor, under], voxels,
    ...     np.full(400, 0.01), SegmentationParams())]
    [400]
    """
    order = sorted(
        (k for k, p in enumerate(planes) if p.horizontal),
        key=lambda k: -int(planes[k].inliers.sum()),
    )
    merged: dict[int, Plane] = {}
    folded: set[int] = set()
    for k in order:
        plane = planes[k]
        into = next(
            (h for h in merged if in_band_of(plane, merged[h], voxels, tolerance, params)), None
        )
        if into is None:
            merged[k] = plane
            continue
        merged[into] = replace(merged[into], inliers=merged[into].inliers | plane.inliers)
        folded.add(k)
    return [merged.get(k, p) for k, p in enumerate(planes) if k not in folded]


def in_band_of(
    plane: Plane,
    support: Plane,
    voxels: FloatArray,
    tolerance: FloatArray,
    params: SegmentationParams,
) -> bool:
    """Whether ``plane`` lies in the band of the larger horizontal ``support``:

    - parallel to it within ``max_band_tilt_deg``;
    - beside it: its voxels' heights over it (5th to 95th percentile) lie on one side of it
      (a plane that runs from under it to over it is tilted across it, as
      :func:`shapes.segment.supports._crosses` says) and reach to within their tolerance and
      half a voxel of it, so that the two planes' voxels make one band with no gap;
    - among its voxels: ``min_shared_ground`` of its voxels lie in the cells
      (``support_cell_m`` across) where the support has voxels too (a rug hides the floor
      under it, a box's top the floor under the box);
    - one solid surface, not scattered in pieces (its largest piece,
      :func:`shapes.support_region.largest_piece`, holds ``min_main_piece_share`` of its voxels,
      as :func:`shapes.plane_pieces.is_scattered` asks): a slice through the bottoms of flat
      things on a desk falls apart around them.
    """
    cos = min(1.0, abs(float(plane.normal @ support.normal)))
    if math.degrees(math.acos(cos)) > params.max_band_tilt_deg:
        return False
    mine = voxels[plane.inliers]
    heights = mine @ support.normal + support.offset
    low, high = np.percentile(heights, [5.0, 95.0])
    if low < 0.0 < high:
        return False  # from under it to over it: a plane across the support, not beside it
    gap = max(float(low), -float(high))
    if gap > float(np.median(tolerance[plane.inliers])) + params.voxel_m / 2:
        return False
    cell = params.support_cell_m
    theirs = np.floor(voxels[support.inliers][:, :2] / cell).astype(np.int64)
    cells = np.floor(mine[:, :2] / cell).astype(np.int64)
    lo = np.minimum(theirs.min(axis=0), cells.min(axis=0))
    span = np.maximum(theirs.max(axis=0), cells.max(axis=0)) - lo + 1
    occupied = np.zeros(int(span[0]) * int(span[1]), dtype=bool)
    occupied[(theirs[:, 0] - lo[0]) * span[1] + theirs[:, 1] - lo[1]] = True
    shared = occupied[(cells[:, 0] - lo[0]) * span[1] + cells[:, 1] - lo[1]]
    if shared.mean() < params.min_shared_ground:
        return False
    return float(largest_piece(mine[:, :2], cell).mean()) >= params.min_main_piece_share
