""":func:`segment`, the steps of :mod:`shapes.segment` in order.

From a surveyed frame to the object clusters on their supports, and the :class:`Segmentation` it
returns.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from shapes.frame import Frame
from shapes.segment.clusters import Cluster, KeptPoints, clusters_on
from shapes.segment.fragments import fragments_joined
from shapes.segment.free_voxels import free_voxels, over_supports, robust_sigma
from shapes.segment.objects import (
    cut_by_limits,
    floats,
    not_under,
    not_under_support_edges,
    stands_within,
)
from shapes.segment.params import SegmentationParams
from shapes.segment.planes import in_world
from shapes.segment.reach import Reach
from shapes.segment.slivers import off_depth_edges
from shapes.segment.support_fit import measured_support
from shapes.segment.supports import judge_planes
from shapes.segment.survey import Survey, depth_cut_m, survey
from shapes.segment.tall import grown_upwards
from shapes.types import SupportPlane
from shapes.view import image_view

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class Segmentation:
    """What :func:`segment` found: the support plane (None if none), the clusters on every
    support, the supports that carry clusters, the depth noise at 1 m, when there is no
    cluster the reason in one line, and each support as found and as measured again."""

    support: SupportPlane | None
    clusters: tuple[Cluster, ...]
    supports: tuple[SupportPlane, ...] = ()
    noise_1m: float = 0.0
    reason: str | None = None
    measured: tuple[tuple[SupportPlane, SupportPlane], ...] = ()
    """Each support that carries clusters as the plane search found it (the plane the clusters
    were cut with and their objects are fitted on, :attr:`Cluster.support`) beside the same
    support measured again over its main piece (:mod:`shapes.segment.support_fit`), which is
    the one reported in :attr:`support` and :attr:`supports`."""

    def reported(self, plane: SupportPlane) -> SupportPlane:
        """The support reported for a cluster's ``plane`` (its measured plane; ``plane``
        itself when it was not measured again)."""
        return next((m for found, m in self.measured if found is plane), plane)


def segment(
    frame: Frame,
    params: SegmentationParams | None = None,
    seed: int = 0,
    *,
    surveyed: Survey | None = None,
) -> Segmentation:
    """Find the supports and the object clusters on them in one frame (:mod:`shapes.segment`).

    ``surveyed``: the frame's :func:`survey` with the same ``params`` and ``seed``, when the
    caller has it already (the pipeline takes up from it first).
    """
    params = params or SegmentationParams()
    scan = surveyed if surveyed is not None else survey(frame, params, seed)
    if scan.reason is not None:
        return Segmentation(None, (), reason=scan.reason)
    keep, depth, sigma_1m, voxel_of = scan.keep, scan.depth, scan.sigma_1m, scan.voxel_of
    pixels = None if frame.pixels is None else frame.pixels[keep]
    reach = Reach(
        frame.world_from_sensor if scan.in_camera_frame else None,
        depth_cut_m(sigma_1m, params),
        max(params.cut_band_m, 3 * sigma_1m * depth_cut_m(sigma_1m, params) ** 2),
        None
        if frame.pixels is None or frame.image_shape is None or not scan.in_camera_frame
        else image_view(frame.image_shape, frame.pixels, frame.world_from_sensor[:3, :3]),
        scan.depth_image,
    )
    points = frame.world_points_of(scan.points)
    voxels = frame.world_points_of(scan.voxels)
    viewpoint = frame.world_from_sensor[:3, 3] if scan.in_camera_frame else None
    # The frame's colours and which point of the frame each kept point is: a cluster's
    # colours are gathered from the frame's (all the kept points' would cost a pass over it).
    colours = None if frame.colours is None else (frame.colours, np.flatnonzero(keep))
    judged = judge_planes(
        [in_world(p, frame.world_from_sensor, params) for p in scan.planes],
        voxels,
        scan.tolerance,
        params,
    )
    horizontal = judged.supports
    if not horizontal:
        seen = "; ".join(p.describe() for p in judged.planes) or "none"
        log.info("no horizontal support plane in %d voxels", len(voxels))
        return Segmentation(
            None,
            (),
            noise_1m=sigma_1m,
            reason=f"no support found: no horizontal plane among the planes seen ({seen})",
        )
    free = free_voxels(judged, voxels, scan.voxels, scan.tolerance, params)
    over = over_supports(judged, voxels, free, scan.tolerance, params)
    supports, regions, margins, owner = over.supports, over.regions, over.margins, over.owner
    largest = max(range(len(horizontal)), key=lambda k: int(horizontal[k].inliers.sum()))
    if sigma_1m == 0.0:
        # Unorganised: the noise from the full-resolution residuals of the biggest support.
        on = np.zeros(len(voxels), dtype=bool)
        on[horizontal[largest].inliers] = True
        sel = on[voxel_of]
        if sel.sum() > 100:
            resid = supports[largest].signed_distance(points[sel])
            sigma_1m = robust_sigma(resid) / float(np.median(depth[sel] ** 2))
    kept_points = KeptPoints(
        voxels,
        voxel_of,
        points,
        depth,
        colours,
        pixels,
        sigma_1m,
        None if frame.image_shape is None else frame.image_shape[1],
    )
    clusters: list[Cluster] = []
    too_small = above = 0
    votes = np.zeros(len(horizontal), dtype=np.int64)
    kept: list[list[Cluster]] = []
    for k, support in enumerate(supports):
        candidates = np.flatnonzero(owner == k)
        above += len(candidates)
        if len(candidates) < params.min_cluster_voxels:
            kept.append([])
            continue
        found, small = clusters_on(
            candidates,
            kept_points,
            support,
            margins[k],
            params,
            frame.pixels is not None and params.filter_artefacts,
            viewpoint,
            reach.view,
        )
        too_small += small
        found = [c for c in found if stands_within(c, regions[k], params)]
        found = grown_upwards(
            found,
            free & (owner < 0),
            over.boxes[k],
            kept_points,
            reach,
            margins[k],
            params,
        )
        found = [c for c in found if stands_within(c, regions[k], params)]
        parts = [
            c
            for c in found
            if cut_by_limits(c, reach, params) or floats(c, reach, margins[k], params)
        ]
        kept.append(not_under(found, parts, support, params))
    kept = not_under_support_edges(kept, supports, regions, frame, reach, params)
    kept = [off_depth_edges(found, reach.depth_image, params) for found in kept]
    kept = [fragments_joined(found, kept_points.image_width, params) for found in kept]
    for k, found in enumerate(kept):
        votes[k] = sum(len(c.voxels) for c in found)
        clusters += found
    order = [int(k) for k in np.argsort(-votes, kind="stable") if votes[k] > 0]
    # The clusters were cut, and their objects are fitted, with the plane search's planes;
    # the support reported is its plane measured again over its main piece (support_fit).
    reported = list(supports)
    for k in (order or [largest]) if params.measure_support else []:
        plane = horizontal[k]
        table = np.flatnonzero(plane.inliers)[judged.region_of[id(plane)].piece]
        reported[k] = measured_support(supports[k], voxels[table], scan.tolerance[table])
    with_objects = [reported[k] for k in order]
    primary = with_objects[0] if with_objects else reported[largest]
    reason = None
    if not clusters:
        if above < params.min_cluster_voxels:
            reason = (
                f"no clusters above the support: {above} voxels above "
                f"{len(horizontal)} horizontal plane(s)"
            )
        elif too_small:
            reason = (
                f"clusters rejected: {too_small} cluster(s) smaller than "
                f"{params.min_cluster_voxels} voxels"
            )
        else:
            reason = (
                f"no clusters above the support: {above} voxels above it, all stray points "
                "or outliers"
            )
    log.debug("segmented %d points into %d clusters", len(points), len(clusters))
    return Segmentation(
        primary,
        tuple(clusters),
        tuple(with_objects),
        sigma_1m,
        reason,
        tuple((supports[k], reported[k]) for k in order),
    )
