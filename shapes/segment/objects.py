"""What is an object of the scene: the rules that keep or drop a cluster over a support.

A cluster is kept when, in the order :func:`shapes.segment.segment` asks (docs/perception.md,
"What is an object of the scene"):

1. it stands within its support's outline (:func:`stands_within`), before and after a cluster
   cut at the height band's top grows upwards (:mod:`shapes.segment.tall`);
2. it is not cut by the scene's limits: the band's top, the depth cut, an edge of the image's
   valid window with nothing behind it (:func:`cut_by_limits`);
3. its bottom does not hang over the support (:func:`floats`; :func:`seen_standing`);
4. it stands under no part dropped by 2 or 3 (:func:`not_under`);
5. it does not stand under a higher support's edge, which hides its top
   (:func:`not_under_support_edges`, :mod:`shapes.support_edge`).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shapes.arrays import column_max, column_min
from shapes.frame import Frame
from shapes.segment.clusters import Cluster
from shapes.segment.params import SegmentationParams
from shapes.segment.reach import Reach, reaching
from shapes.support_edge import hidden_by_edge, occluders_above, reaches_under
from shapes.support_region import SupportRegion
from shapes.types import FloatArray, SupportPlane


def stands_within(cluster: Cluster, region: SupportRegion, params: SegmentationParams) -> bool:
    """Whether a cluster stands within its support's outline (its voxels' centre across the
    support inside the main piece's hull grown by ``extent_margin_m``): the back of a chair
    rising over the edge of a desk, or a wall behind it, does not."""
    centre = cluster.voxels[:, :2].mean(axis=0)
    return bool(region.contains(centre[None, :], params.extent_margin_m)[0])


def cut_by_limits(cluster: Cluster, reach: Reach, params: SegmentationParams) -> bool:
    """Whether a cluster is cut by the scene's limits, and so is a part of something larger
    (a wall, a door, a chair's back, a person's legs), not an object: at least
    ``min_cut_share`` of its voxels (and ``min_cut_voxels``) lie within ``cut_band_m`` of
    ``max_height_m`` over its support (``max_tall_height_m`` for a cluster grown over the band,
    :func:`grown_upwards`), or as large a share of its points within
    ``reach.band_m`` of the depth cut, or within ``border_band_px`` of an edge of the image's
    valid window other than the one the camera looks down through, on a line where nothing
    behind it (:func:`_behind_m`) shows between it and that edge
    (:meth:`shapes.view.ImageView.cut_at_closed_edge`)."""
    assert cluster.support is not None
    height = cluster.support.signed_distance(cluster.voxels)
    # Only a cluster grown upwards (:func:`grown_upwards`) rises over the band: its limit is
    # the higher one.
    limit = params.max_tall_height_m if height.max() >= params.max_height_m else params.max_height_m
    if reaching(height >= limit - params.cut_band_m, params):
        return True
    if (
        reach.view is not None
        and cluster.pixels is not None
        and reaching(reach.view.at_closed_edge(cluster.pixels, params.border_band_px), params)
        and (
            reach.depth_image is None
            or reaching(
                reach.view.cut_at_closed_edge(
                    cluster.pixels,
                    params.border_band_px,
                    reach.depth_image,
                    _behind_m(cluster, reach.depth_image, params),
                ),
                params,
            )
        )
    ):
        return True
    if reach.world_from_sensor is None:
        return False
    depth = reach.depth_of(cluster.points)
    return reaching(depth >= reach.depth_cut_m - reach.band_m, params)


def _behind_m(cluster: Cluster, depth_image: FloatArray, params: SegmentationParams) -> float:
    """How much farther than a cluster's outline a depth must lie to be something seen behind
    it: ``cut_band_m`` (or three times its noise), and no less than the cluster's own depth
    extent, so that a surface receding towards the image's edge (a chair's leg, the floor
    round a wheel) does not pass for a background behind the cluster."""
    assert cluster.pixels is not None
    extent_m = float(np.ptp(depth_image.ravel()[cluster.pixels]))
    return max(nearer_m(cluster, params), extent_m)


def seen_standing(cluster: Cluster, margin_m: float, params: SegmentationParams) -> bool:
    """Whether a cluster's lowest voxel lies on its support: less than ``max_base_height_m``
    over the lowest an object's voxel can lie (``margin_m``). Unlike :func:`floats`, a bottom
    hidden behind something nearer does not count: it may be anything's upper part."""
    assert cluster.support is not None
    lowest = float(cluster.support.signed_distance(cluster.voxels).min())
    return lowest < margin_m + params.max_base_height_m


def floats(cluster: Cluster, reach: Reach, margin_m: float, params: SegmentationParams) -> bool:
    """Whether a cluster hangs over its support, and so is a part of something standing on it
    elsewhere (a chair's seat or armrest over its post, a shelf's edge, what stands on a
    shelf), not an object: its lowest voxel lies ``max_base_height_m`` or more above the
    lowest an object's voxel can lie (``margin_m``, the support's noise margin), and its
    lower outline in the image is its own (less than ``min_hidden_share`` of
    it has something nearer just past it, towards the image's open edge). An object whose
    base is hidden behind another stands on the support unseen, and is kept."""
    assert cluster.support is not None
    seen = reach.image()
    if seen is None or cluster.pixels is None:
        return False
    if seen_standing(cluster, margin_m, params):
        return False
    view, image = seen
    depth = reach.depth_of(cluster.points)
    hidden = view.hidden_below(
        cluster.pixels,
        depth,
        image,
        params.floating_probe_px,
        nearer_m(cluster, params),
    )
    return hidden < params.min_hidden_share


def not_under(
    found: list[Cluster], parts: list[Cluster], support: SupportPlane, params: SegmentationParams
) -> list[Cluster]:
    """The clusters of ``found`` (all on ``support``) that are not one of ``parts`` and do not
    stand under one, in their order. A cluster stands under a part of something larger when its
    voxels' centre across the support lies within the part's extent, grown by
    ``cluster_eps_m``, and its top lies below the part's bottom: a chair's base under its
    seat, a table's legs under its top. Both are parts of one thing.

    Each cluster's centre and top and each part's extent and bottom are computed once (a
    cluttered frame has hundreds of pairs)."""
    if not parts:
        return list(found)
    lo = np.array([column_min(p.voxels[:, :2]) for p in parts]) - params.cluster_eps_m
    hi = np.array([column_max(p.voxels[:, :2]) for p in parts]) + params.cluster_eps_m
    bottom = np.array([float(support.signed_distance(p.voxels).min()) for p in parts])
    kept = []
    for cluster in found:
        if any(cluster is p for p in parts):
            continue
        centre = cluster.voxels[:, :2].mean(axis=0)
        over = (centre >= lo).all(axis=1) & (centre <= hi).all(axis=1)
        if over.any() and float(support.signed_distance(cluster.voxels).max()) < bottom[over].max():
            continue
        kept.append(cluster)
    return kept


def not_under_support_edges(
    kept: list[list[Cluster]],
    supports: list[SupportPlane],
    regions: list[SupportRegion],
    frame: Frame,
    reach: Reach,
    params: SegmentationParams,
) -> list[list[Cluster]]:
    """The clusters kept on each support (``kept[k]`` on ``supports[k]``, whose main piece
    covers ``regions[k]``) without those that stand under another support's edge: every voxel
    under that support's plane, its footprint reaching under it and its top hidden by that
    support's edge (:mod:`shapes.support_edge`): a desk's legs and panel seen on the
    floor through the gap under its front edge are parts of the desk."""
    seen = reach.image()
    if len(supports) < 2 or seen is None or frame.pixels is None:
        return kept
    view, image = seen
    point_of: npt.NDArray[np.intp] | None = None  # the frame's point at each pixel, if needed
    out = []
    for k, found in enumerate(kept):
        stays = []
        for cluster in found:
            above = [
                j
                for j, higher in enumerate(supports)
                if j != k
                and float(higher.signed_distance(cluster.voxels).max()) < 0.0
                and reaches_under(cluster.voxels, regions[j], params.extent_margin_m)
            ]
            if not above or cluster.pixels is None:
                stays.append(cluster)
                continue
            nearer = nearer_m(cluster, params)
            lines, hiding = occluders_above(
                view,
                cluster.pixels,
                reach.depth_of(cluster.points),
                image,
                params.floating_probe_px,
                nearer,
            )
            if point_of is None:
                point_of = np.full(image.size, -1, dtype=np.intp)
                point_of[frame.pixels] = np.arange(len(frame.pixels))
            at = point_of[hiding]
            hiders = frame.world_points_of(frame.points[at[at >= 0]])
            if any(
                hidden_by_edge(
                    supports[j].signed_distance(hiders),
                    lines,
                    edge_depth_m=params.support_edge_depth_m,
                    nearer_m=nearer,
                    min_hidden_share=params.min_edge_hidden_share,
                )
                for j in above
            ):
                continue
            stays.append(cluster)
        out.append(stays)
    return out


def nearer_m(cluster: Cluster, params: SegmentationParams) -> float:
    """How much nearer (or farther) than a cluster's points a depth must lie to be something
    else in front of (or behind) it: ``cut_band_m``, or three times the cluster's noise."""
    return max(params.cut_band_m, 3 * cluster.noise_m)
