"""The clusters over one support, with their full-resolution points.

Steps 6 and 7 of :mod:`shapes.segment`: the free voxels a support owns, without statistical
outliers, grouped by DBSCAN (open3d), cut where objects touch (:mod:`shapes.segment.splitting`),
and each given back its points, colours and pixels (:class:`KeptPoints`). Whether a cluster is
an object of the scene is :mod:`shapes.segment.objects`'s to say.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import open3d as o3d

from shapes.artefacts import sparse_points
from shapes.colour_seam import lab, voxel_colours
from shapes.segment.occlusion import parts_in_front, surfaces
from shapes.segment.params import SegmentationParams
from shapes.segment.splitting import split_clusters
from shapes.types import FloatArray, SupportPlane
from shapes.view import ImageView


@dataclass(frozen=True, eq=False)
class Cluster:
    """The full-resolution points of one object, in the world frame, and its support."""

    points: FloatArray
    colours: FloatArray | None
    voxels: FloatArray
    support: SupportPlane | None = None
    noise_m: float = 0.0
    """The depth noise (one sigma) expected at the cluster's range, in metres."""
    pixels: npt.NDArray[np.intp] | None = None
    """The flat row-major image pixel of each point, on an organised frame."""

    @property
    def centroid(self) -> FloatArray:
        """The mean of the points (PITT's visual centroid, without its n+1 bug)."""
        return np.asarray(self.points.mean(axis=0), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class KeptPoints:
    """A frame's kept points and their voxels, in the world frame: what clusters are made of."""

    voxels: FloatArray
    voxel_of: npt.NDArray[np.intp]
    """The voxel of each point."""
    points: FloatArray
    depth: FloatArray
    """Each point's range (1 for every point of a cloud not in a camera's frame)."""
    colours: tuple[FloatArray, npt.NDArray[np.intp]] | None
    """The frame's colours and the index in the frame of each point (None: no colours)."""
    pixels: npt.NDArray[np.intp] | None
    """The image pixel of each point, on an organised frame."""
    sigma_1m: float
    """The depth noise at 1 m."""
    image_width: int | None = None
    """The width in pixels of the image ``pixels`` index (None: not an organised frame)."""

    def noise_m(self, idx: npt.NDArray[np.intp]) -> float:
        """The depth noise (one sigma) at the median range of the points ``idx``."""
        return self.sigma_1m * float(np.median(self.depth[idx])) ** 2


def clusters_on(
    candidates: npt.NDArray[np.intp],
    kept: KeptPoints,
    support: SupportPlane,
    margin: float,
    params: SegmentationParams,
    organised: bool,
    viewpoint: FloatArray | None,
    view: ImageView | None = None,
) -> tuple[list[Cluster], int]:
    """DBSCAN clusters of the candidate voxels (of ``kept.voxels``) above one support, and how
    many were too small. ``view``: the image's valid window, whose closed edges cut what crosses
    them (:mod:`shapes.view`)."""
    voxels, voxel_of, points, sigma_1m = kept.voxels, kept.voxel_of, kept.points, kept.sigma_1m
    # open3d hands back the inliers' own cloud (their points in order): DBSCAN runs on it, not
    # on a second copy of the same points.
    inlier_cloud, inliers = _cloud(voxels[candidates]).remove_statistical_outlier(
        params.outlier_neighbours, params.outlier_std_ratio
    )
    candidates = candidates[np.asarray(inliers, dtype=np.intp)]
    labels = np.asarray(
        inlier_cloud.cluster_dbscan(params.cluster_eps_m, params.cluster_min_points),
        dtype=np.int64,
    )
    if params.split_touching:
        labels = split_clusters(
            labels,
            voxels[candidates],
            viewpoint,
            params,
            sigma_1m,
            support.signed_distance(voxels[candidates]),
            margin,
            _colours_lab(kept, candidates),
        )
    if organised and params.occlusion_slope > 0:
        labels = _parted_at_occlusions(
            labels, candidates, kept, support.signed_distance(voxels[candidates]), params, view
        )
    voxel_label = np.full(len(voxels), -1, dtype=np.int64)
    voxel_label[candidates] = labels
    # Only the points of labelled voxels (a few percent of a frame) from here on.
    member = np.flatnonzero(voxel_label[voxel_of] >= 0)
    cut = np.maximum(params.above_margin_m, 2 * sigma_1m * kept.depth[member] ** 2)
    member = member[support.signed_distance(points[member]) > np.minimum(cut, margin)]
    point_label = voxel_label[voxel_of[member]]
    clusters = []
    small = 0
    order = member[np.argsort(point_label, kind="stable")]
    bounds = np.searchsorted(np.sort(point_label), np.arange(labels.max(initial=-1) + 2))
    for label in range(labels.max(initial=-1) + 1):
        n_vox = int((labels == label).sum())
        idx = order[bounds[label] : bounds[label + 1]]
        if n_vox < params.min_cluster_voxels or len(idx) < params.min_cluster_voxels:
            small += 1
            continue
        if not organised:
            idx = idx[~sparse_points(points[idx])]
        clusters.append(
            Cluster(
                points[idx],
                None if kept.colours is None else kept.colours[0][kept.colours[1][idx]],
                voxels[candidates[labels == label]],
                support,
                kept.noise_m(idx),
                None if kept.pixels is None else kept.pixels[idx],
            )
        )
    return clusters, small


def _parted_at_occlusions(
    labels: npt.NDArray[np.int64],
    candidates: npt.NDArray[np.intp],
    kept: KeptPoints,
    heights: FloatArray,
    params: SegmentationParams,
    view: ImageView | None,
) -> npt.NDArray[np.int64]:
    """``labels`` (of the ``candidates`` voxels) with every cluster of ``3 * min_cluster_voxels``
    voxels or more, or reaching the image's edge, parted where a surface stands in front of the rest
    (:mod:`shapes.segment.occlusion`), and without what hangs in from an edge of the image's
    window (``view``); ``heights``: each candidate's height over the support."""
    if kept.pixels is None or kept.image_width is None:
        return labels
    out = labels.copy()
    next_label = int(labels.max(initial=-1)) + 1
    position = np.full(len(kept.voxels), -1, dtype=np.intp)
    position[candidates] = np.arange(len(candidates))
    at = position[kept.voxel_of]
    member = np.flatnonzero(at >= 0)
    member = member[labels[at[member]] >= 0]
    member = member[np.argsort(labels[at[member]], kind="stable")]
    bounds = np.searchsorted(labels[at[member]], np.arange(next_label + 1))
    for label in range(next_label):
        idx = member[bounds[label] : bounds[label + 1]]
        voxels_of_cluster = np.flatnonzero(labels == label)
        at_edge = (
            None if view is None else view.at_closed_edge(kept.pixels[idx], params.border_band_px)
        )
        # A thing lying across another needs three surfaces of an object's size; what hangs in
        # from the image's edge, a cluster that reaches it.
        reaches_edge = at_edge is not None and int(at_edge.sum()) >= params.min_cut_voxels
        if len(voxels_of_cluster) < 3 * params.min_cluster_voxels and not reaches_edge:
            continue
        surface, front = surfaces(
            kept.points[idx],
            kept.depth[idx],
            kept.pixels[idx],
            kept.image_width,
            params.occlusion_slope,
            params.occlusion_noise_multiple * kept.sigma_1m * kept.depth[idx] ** 2,
        )
        if len(front) == 0 and not reaches_edge:
            continue
        local = np.full(len(candidates), -1, dtype=np.intp)
        local[voxels_of_cluster] = np.arange(len(voxels_of_cluster))
        parts = parts_in_front(
            surface,
            front,
            local[at[idx]],
            heights[voxels_of_cluster],
            np.column_stack(np.divmod(kept.pixels[idx], kept.image_width)).astype(np.float64),
            at_edge,
            points=kept.points[idx],
            min_voxels=params.min_cluster_voxels,
            max_base_height_m=params.max_base_height_m,
            min_reach_m=params.cluster_eps_m,
            min_edge_points=params.min_cut_voxels,
        )
        for part in range(1, int(parts.max()) + 1):
            out[voxels_of_cluster[parts == part]] = next_label
            next_label += 1
    return out


def _colours_lab(
    kept: KeptPoints, candidates: npt.NDArray[np.intp]
) -> Callable[[npt.NDArray[np.intp]], FloatArray] | None:
    """The CIELAB colour of the voxels ``members`` (indices into ``candidates``), each the mean
    of its kept points' colours, worked out only when asked; None when the frame has no
    colours."""
    if kept.colours is None:
        return None
    frame_colours, frame_index = kept.colours

    def of(members: npt.NDArray[np.intp]) -> FloatArray:
        position = np.full(len(kept.voxels), -1, dtype=np.intp)
        position[candidates[members]] = np.arange(len(members))
        at = position[kept.voxel_of]
        own = np.flatnonzero(at >= 0)
        return lab(voxel_colours(at[own], frame_colours[frame_index[own]], len(members)))

    return of


def _cloud(points: FloatArray) -> o3d.geometry.PointCloud:
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
