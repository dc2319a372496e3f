"""Segmentation: from a raw frame to the object clusters standing on the support (table).

Steps (PITT's, with its quirks fixed; see ``shared/reference/pitt-perception.md`` §4):

1. depth cut in the sensor frame (``z <= max_depth_m``), then transform to the world frame;
2. voxel grid (``voxel_m``): each occupied voxel becomes the mean of its points. It is computed in
   numpy so that every full-resolution point keeps the index of its voxel;
3. support plane: RANSAC (numpy, seeded) on the voxels, repeated until a horizontal plane
   (normal within ``max_support_tilt_deg`` of world z) holding at least
   ``min_support_fraction`` of the voxels is found; its normal is turned to point up. The
   threshold is 1 cm, not PITT's 2 cm, which ate the bottom of every object;
4. points above the support: more than ``above_margin_m`` and less than ``max_height_m`` above
   the plane, inside the support's xy bounding box shrunk by ``edge_margin_m``;
5. statistical outlier removal and DBSCAN (open3d) on those voxels; clusters with fewer than
   ``min_cluster_voxels`` voxels are dropped;
6. each cluster gets its full-resolution points (and colours) back through the voxel index.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import open3d as o3d

from shapes.frame import Frame
from shapes.types import FloatArray, SupportPlane, vec3

__all__ = ["Cluster", "Segmentation", "SegmentationParams", "segment"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SegmentationParams:
    """Parameters of :func:`segment`; lengths in metres."""

    voxel_m: float = 0.01
    max_depth_m: float = 3.0
    support_threshold_m: float = 0.01
    support_iterations: int = 500
    max_support_tilt_deg: float = 10.0
    min_support_fraction: float = 0.03
    max_support_attempts: int = 4
    above_margin_m: float = 0.008
    max_height_m: float = 1.0
    edge_margin_m: float = 0.02
    outlier_neighbours: int = 10
    outlier_std_ratio: float = 3.0
    cluster_eps_m: float = 0.03
    cluster_min_points: int = 3
    min_cluster_voxels: int = 12


@dataclass(frozen=True, eq=False)
class Cluster:
    """The full-resolution points of one object, in the world frame."""

    points: FloatArray
    colours: FloatArray | None
    voxels: FloatArray

    @property
    def centroid(self) -> FloatArray:
        """The mean of the points (PITT's visual centroid, without its n+1 bug)."""
        return np.asarray(self.points.mean(axis=0), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class Segmentation:
    """What :func:`segment` found: the support plane (None if none) and the clusters on it."""

    support: SupportPlane | None
    clusters: tuple[Cluster, ...]


def voxel_grid(points: FloatArray, voxel_m: float) -> tuple[FloatArray, npt.NDArray[np.intp]]:
    """Voxel means and, for each input point, the index of its voxel.

    >>> means, index = voxel_grid(np.array([[0.001, 0, 0], [0.003, 0, 0], [0.5, 0, 0]]), 0.01)
    >>> means.round(3).tolist(), index.tolist()
    ([[0.002, 0.0, 0.0], [0.5, 0.0, 0.0]], [0, 0, 1])
    """
    keys = np.floor(points / voxel_m).astype(np.int64)
    keys -= keys.min(axis=0)
    span = keys.max(axis=0) + 1
    flat = (keys[:, 0] * span[1] + keys[:, 1]) * span[2] + keys[:, 2]
    _, index, counts = np.unique(flat, return_inverse=True, return_counts=True)
    means = np.empty((len(counts), 3))
    for axis in range(3):
        means[:, axis] = np.bincount(index, weights=points[:, axis]) / counts
    return means, index.astype(np.intp)


def _cloud(points: FloatArray) -> o3d.geometry.PointCloud:
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))


_HYPOTHESES_PER_PASS = 32
"""Plane hypotheses scored against every point at once (bounds the distance matrix)."""
_CONFIDENCE = 1 - 1e-7
"""RANSAC stops once a better plane is this unlikely to be left among the unscored samples."""


def ransac_plane(
    points: FloatArray, threshold: float, iterations: int, rng: np.random.Generator
) -> tuple[FloatArray, npt.NDArray[np.intp]] | None:
    """RANSAC: of up to ``iterations`` planes through three random points, the one with the
    most points within ``threshold`` (the first on a tie). It stops early, as usual, once the
    samples scored make a better plane unlikely (``_CONFIDENCE``, from the best inlier ratio so
    far). Returns the unit normal and the indices of its points, or None if no sample spans a
    plane.

    In numpy with the caller's generator, so that a seed fixes the result: open3d's
    ``segment_plane`` runs its iterations on parallel threads and, even seeded, its result
    varies with their scheduling (seen as a flaky determinism test on a loaded machine).
    """
    if len(points) < 3:
        return None
    samples = rng.integers(0, len(points), size=(iterations, 3))
    a, b, c = points[samples[:, 0]], points[samples[:, 1]], points[samples[:, 2]]
    normals = np.cross(b - a, c - a)
    lengths = np.linalg.norm(normals, axis=1)
    spanning = lengths > 1e-12
    if not spanning.any():
        return None
    normals = normals[spanning] / lengths[spanning, None]
    offsets = -np.einsum("ij,ij->i", normals, a[spanning])
    best, best_count = 0, -1
    for start in range(0, len(normals), _HYPOTHESES_PER_PASS):
        stop = start + _HYPOTHESES_PER_PASS
        distances = np.abs(points @ normals[start:stop].T + offsets[start:stop])
        counts = np.count_nonzero(distances <= threshold, axis=0)
        k = int(np.argmax(counts))
        if counts[k] > best_count:
            best, best_count = start + k, int(counts[k])
        p_good = (best_count / len(points)) ** 3  # that a sample's three points are all inliers
        if p_good >= 1 or (p_good > 0 and stop >= math.log(1 - _CONFIDENCE) / math.log1p(-p_good)):
            break
    inliers = np.flatnonzero(np.abs(points @ normals[best] + offsets[best]) <= threshold)
    return normals[best], inliers


def find_support(
    voxels: FloatArray, params: SegmentationParams, seed: int
) -> tuple[SupportPlane, npt.NDArray[np.bool_]] | None:
    """The first horizontal plane RANSAC finds, and the mask of its inlier voxels."""
    cos_tilt = math.cos(math.radians(params.max_support_tilt_deg))
    remaining = np.arange(len(voxels))
    min_inliers = max(3, int(params.min_support_fraction * len(voxels)))
    rng = np.random.default_rng(seed)
    for _ in range(params.max_support_attempts):
        if len(remaining) < min_inliers:
            return None
        found = ransac_plane(
            voxels[remaining], params.support_threshold_m, params.support_iterations, rng
        )
        if found is None or len(found[1]) < min_inliers:
            return None
        n, inl = found
        if abs(n[2]) >= cos_tilt:
            sign = 1.0 if n[2] > 0 else -1.0
            # Refit by least squares on the inliers for a plane free of sampling noise.
            pts = voxels[remaining[inl]]
            centre = pts.mean(axis=0)
            normal = np.linalg.svd(pts - centre, full_matrices=False)[2][2]
            normal *= 1.0 if normal @ (sign * n) > 0 else -1.0
            mask = np.zeros(len(voxels), dtype=bool)
            mask[remaining[inl]] = True
            return SupportPlane(vec3(normal), float(-normal @ centre)), mask
        remaining = np.delete(remaining, inl)
    return None


def segment(frame: Frame, params: SegmentationParams | None = None, seed: int = 0) -> Segmentation:
    """Find the support plane and the object clusters above it in one frame."""
    params = params or SegmentationParams()
    keep = frame.points[:, 2] <= params.max_depth_m
    if not keep.any():
        return Segmentation(None, ())
    points = frame.world_points(keep)
    colours = None if frame.colours is None else frame.colours[keep]
    voxels, voxel_of = voxel_grid(points, params.voxel_m)
    found = find_support(voxels, params, seed)
    if found is None:
        log.info("no horizontal support plane in %d voxels", len(voxels))
        return Segmentation(None, ())
    support, support_mask = found
    height = support.signed_distance(voxels)
    table = voxels[support_mask]
    lo = table[:, :2].min(axis=0) + params.edge_margin_m
    hi = table[:, :2].max(axis=0) - params.edge_margin_m
    above = (
        (height > params.above_margin_m)
        & (height < params.max_height_m)
        & np.all((voxels[:, :2] > lo) & (voxels[:, :2] < hi), axis=1)
    )
    candidates = np.flatnonzero(above)
    if len(candidates) < params.min_cluster_voxels:
        return Segmentation(support, ())
    cloud = _cloud(voxels[candidates])
    _, kept = cloud.remove_statistical_outlier(params.outlier_neighbours, params.outlier_std_ratio)
    candidates = candidates[np.asarray(kept, dtype=np.intp)]
    labels = np.asarray(
        _cloud(voxels[candidates]).cluster_dbscan(params.cluster_eps_m, params.cluster_min_points),
        dtype=np.int64,
    )
    voxel_label = np.full(len(voxels), -1, dtype=np.int64)
    voxel_label[candidates] = labels
    point_label = voxel_label[voxel_of]
    point_label[support.signed_distance(points) <= params.above_margin_m] = -1
    clusters = []
    order = np.argsort(point_label, kind="stable")
    bounds = np.searchsorted(point_label[order], np.arange(labels.max(initial=-1) + 2))
    for label in range(labels.max(initial=-1) + 1):
        n_vox = int((labels == label).sum())
        idx = order[bounds[label] : bounds[label + 1]]
        if n_vox < params.min_cluster_voxels or len(idx) < params.min_cluster_voxels:
            continue
        clusters.append(
            Cluster(
                points[idx],
                None if colours is None else colours[idx],
                voxels[candidates[labels == label]],
            )
        )
    log.debug("segmented %d points into %d clusters", len(points), len(clusters))
    return Segmentation(support, tuple(clusters))
