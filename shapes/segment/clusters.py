"""The clusters over one support, with their full-resolution points.

Steps 6 and 7 of :mod:`shapes.segment`: the free voxels a support owns, without statistical
outliers, grouped by DBSCAN (open3d), cut where objects touch (:mod:`shapes.segment.splitting`),
and each given back its points, colours and pixels (:class:`KeptPoints`). Whether a cluster is
an object of the scene is :mod:`shapes.segment.objects`'s to say.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import open3d as o3d

from shapes.artefacts import sparse_points
from shapes.segment.params import SegmentationParams
from shapes.segment.splitting import split_clusters
from shapes.types import FloatArray, SupportPlane


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
) -> tuple[list[Cluster], int]:
    """DBSCAN clusters of the candidate voxels (of ``kept.voxels``) above one support, and how
    many were too small."""
    voxels, voxel_of, points, sigma_1m = kept.voxels, kept.voxel_of, kept.points, kept.sigma_1m
    cloud = _cloud(voxels[candidates])
    _, inliers = cloud.remove_statistical_outlier(
        params.outlier_neighbours, params.outlier_std_ratio
    )
    candidates = candidates[np.asarray(inliers, dtype=np.intp)]
    labels = np.asarray(
        _cloud(voxels[candidates]).cluster_dbscan(params.cluster_eps_m, params.cluster_min_points),
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


def _cloud(points: FloatArray) -> o3d.geometry.PointCloud:
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
