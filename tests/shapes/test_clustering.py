"""shapes.clustering gives open3d's outlier removal and DBSCAN, label for label."""

from pathlib import Path

import numpy as np
import open3d as o3d
import pytest

from shapes import SegmentationParams, open_source
from shapes.clustering import outliers_and_clusters
from shapes.segment import survey

SCANS = Path(__file__).parents[1] / "data" / "real_scans"


def _open3d(points: np.ndarray, params: SegmentationParams) -> tuple[np.ndarray, np.ndarray]:
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    _, kept = cloud.remove_statistical_outlier(params.outlier_neighbours, params.outlier_std_ratio)
    kept = np.asarray(kept, dtype=np.intp)
    inliers = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points[kept]))
    labels = inliers.cluster_dbscan(params.cluster_eps_m, params.cluster_min_points)
    return kept, np.asarray(labels, dtype=np.int64)


def _ours(points: np.ndarray, params: SegmentationParams) -> tuple[np.ndarray, np.ndarray]:
    return outliers_and_clusters(
        points,
        neighbours=params.outlier_neighbours,
        std_ratio=params.outlier_std_ratio,
        eps=params.cluster_eps_m,
        min_points=params.cluster_min_points,
    )


@pytest.mark.parametrize("scan", ["bottles_kinect", "laptop_box_kinect_0", "desk_tum"])
def test_a_real_frames_voxels_give_open3ds_labels(scan: str) -> None:
    params = SegmentationParams()
    voxels = survey(next(open_source(SCANS / f"{scan}.npz")), params, 0).voxels
    kept, labels = _ours(voxels, params)
    expected_kept, expected_labels = _open3d(voxels, params)
    np.testing.assert_array_equal(kept, expected_kept)
    np.testing.assert_array_equal(labels, expected_labels)
    assert labels.max() > 1  # several clusters, so their numbering is tested too


def test_sparse_random_points_with_noise_and_duplicates_give_open3ds_labels() -> None:
    rng = np.random.default_rng(3)
    points = rng.random((600, 3)) * 0.3
    points = np.vstack((points, points[:20]))  # duplicates: distance 0 to a neighbour
    params = SegmentationParams()
    kept, labels = _ours(points, params)
    expected_kept, expected_labels = _open3d(points, params)
    np.testing.assert_array_equal(kept, expected_kept)
    np.testing.assert_array_equal(labels, expected_labels)
    assert (labels == -1).any() and labels.max() > 0


@pytest.mark.parametrize("count", [0, 1])
def test_fewer_than_two_points_keep_none(count: int) -> None:
    kept, labels = _ours(np.zeros((count, 3)), SegmentationParams())
    assert kept.tolist() == [] and labels.tolist() == []
