"""The voxels left free of the supports and of the walls, and the support each stands over.

What the planes do not hold is free (a plane judged a face of objects holds nothing; a tilted
plane's pieces that stand on a support stay free: :mod:`shapes.plane_pieces`), but for stray
returns. Each free voxel between ``above_margin`` and ``max_height_m`` over a support, inside
the bounding box of its main piece shrunk by ``edge_margin_m``, goes to the nearest support
below it (steps 4 and 5 of :mod:`shapes.segment`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.arrays import column_max, column_min, column_span, inside_box
from shapes.artefacts import sparse_voxels
from shapes.plane_pieces import Ground, faces_standing_on
from shapes.segment.params import SegmentationParams
from shapes.segment.supports import JudgedPlanes
from shapes.support_region import SupportRegion
from shapes.types import FloatArray, SupportPlane, vec3


def free_voxels(
    judged: JudgedPlanes,
    voxels: FloatArray,
    sensor_voxels: FloatArray,
    tolerance: FloatArray,
    params: SegmentationParams,
) -> npt.NDArray[np.bool_]:
    """Which of ``voxels`` (in the world frame; ``sensor_voxels``, the same in the sensor's)
    belong to no plane but a face of objects, and have two occupied neighbours or more."""
    grounds = [
        Ground(
            p.normal, p.offset, judged.region_of[id(p)], int(judged.region_of[id(p)].piece.sum())
        )
        for p in judged.supports
    ]
    in_plane = np.zeros(len(voxels), dtype=bool)
    for p in judged.planes:
        if id(p) in judged.faces:  # the fronts or tops of objects stay free
            continue
        in_plane[p.inliers] = True
        if not p.horizontal:  # and so do the pieces of a tilted plane that stand on a support
            inliers = np.flatnonzero(p.inliers)
            faces_of_objects = faces_standing_on(
                voxels[inliers],
                tolerance[inliers],
                p.normal,
                grounds,
                cell_m=params.support_cell_m,
                max_height_m=params.max_height_m,
                edge_margin_m=params.edge_margin_m,
                min_voxels=params.min_cluster_voxels,
            )
            in_plane[inliers[faces_of_objects]] = False
    free = ~in_plane
    # Stray returns and outliers: free voxels with fewer than two occupied neighbours.
    free_idx = np.flatnonzero(free)
    stray = sparse_voxels(sensor_voxels[free_idx], params.voxel_m, among=sensor_voxels)
    free[free_idx[stray]] = False
    return free


@dataclass(frozen=True, eq=False)
class OverSupports:
    """The supports as :class:`shapes.types.SupportPlane` values, and which free voxels stand
    over each; lists in the order of :attr:`JudgedPlanes.supports`."""

    supports: list[SupportPlane]
    regions: list[SupportRegion]
    """Each support's main piece."""
    margins: list[float]
    """Each support's noise margin: ``max(above_margin_m, 3 sigma)`` of its main piece's
    voxels within their tolerance of the plane; what lies lower is the support's. The voxels
    of parallel planes folded into it (:mod:`shapes.segment.bands`) lie farther: they are the
    surface's shape, not its noise, and belong to the support whatever their height."""
    boxes: list[tuple[FloatArray, FloatArray]]
    """Each support's main piece's bounding box across it, shrunk by ``edge_margin_m``."""
    owner: npt.NDArray[np.int_]
    """Per voxel, the index of the support it stands over, or -1."""


def over_supports(
    judged: JudgedPlanes,
    voxels: FloatArray,
    free: npt.NDArray[np.bool_],
    tolerance: FloatArray,
    params: SegmentationParams,
) -> OverSupports:
    """Each ``free`` voxel over the nearest support below it that covers it: between the
    support's margin and ``max_height_m`` over it, inside its box (:class:`OverSupports`)."""
    best_height = np.full(len(voxels), np.inf)
    owner = np.full(len(voxels), -1)
    margins, supports, regions, boxes = [], [], [], []
    for k, p in enumerate(judged.supports):
        inliers = np.flatnonzero(p.inliers)[judged.region_of[id(p)].piece]
        table = voxels[inliers]
        regions.append(judged.region_of[id(p)])
        span = column_span(table[:, :2])
        centre = table.mean(axis=0)
        support = SupportPlane(
            vec3(p.normal),
            p.offset,
            vec3(centre - (centre @ p.normal + p.offset) * p.normal),
            (float(span[0]), float(span[1])),
        )
        supports.append(support)
        residuals = support.signed_distance(table)
        sigma_vox = robust_sigma(residuals[np.abs(residuals) <= tolerance[inliers]])
        margin = max(params.above_margin_m, 3 * sigma_vox)
        margins.append(margin)
        height = support.signed_distance(voxels)
        lo = column_min(table[:, :2]) + params.edge_margin_m
        hi = column_max(table[:, :2]) - params.edge_margin_m
        boxes.append((lo, hi))
        over = (
            free
            & (height > margin)
            & (height < params.max_height_m)
            & inside_box(voxels, lo, hi)
            & (height < best_height)
        )
        best_height[over] = height[over]
        owner[over] = k
    return OverSupports(supports, regions, margins, boxes, owner)


def robust_sigma(values: FloatArray) -> float:
    """The spread of ``values`` as a normal sigma, read from their median absolute deviation
    (0 for none): stray values do not widen it."""
    if len(values) == 0:
        return 0.0
    return float(1.4826 * np.median(np.abs(values - np.median(values))))
