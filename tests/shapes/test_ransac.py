"""The support plane's RANSAC: it finds a planted plane among clutter, and a seed fixes it."""

import numpy as np

from shapes.segment import ransac_plane


def cloud(rng: np.random.Generator) -> tuple[np.ndarray, int]:
    """A tilted plane of 3,000 noisy points (normal ∝ (0.1, -0.2, 1), through (0, 0, 0.7)) and
    1,000 uniform points of clutter; returns the cloud and the number of plane points."""
    normal = np.array([0.1, -0.2, 1.0]) / np.linalg.norm([0.1, -0.2, 1.0])
    xy = rng.uniform(-0.5, 0.5, size=(3000, 2))
    z = 0.7 - (normal[0] * xy[:, 0] + normal[1] * xy[:, 1]) / normal[2]
    plane = np.column_stack((xy, z)) + rng.normal(0, 0.002, size=(3000, 3))
    clutter = rng.uniform([-0.5, -0.5, 0.0], [0.5, 0.5, 1.5], size=(1000, 3))
    return np.vstack((plane, clutter)), len(plane)


def test_the_planted_plane_is_found_with_its_points() -> None:
    points, on_plane = cloud(np.random.default_rng(4))
    found = ransac_plane(points, 0.01, 500, np.random.default_rng(0))
    assert found is not None
    normal, inliers = found
    truth = np.array([0.1, -0.2, 1.0]) / np.linalg.norm([0.1, -0.2, 1.0])
    assert abs(abs(normal @ truth) - 1) < 1e-3
    assert np.isclose(np.linalg.norm(normal), 1.0)
    planted = np.count_nonzero(inliers < on_plane)
    assert planted >= 0.99 * on_plane  # nearly every plane point (noise 2 mm, threshold 1 cm)
    assert len(inliers) - planted < 0.05 * len(points)  # and little of the clutter


def test_a_seed_gives_the_same_plane_every_time() -> None:
    points, _ = cloud(np.random.default_rng(5))
    first = ransac_plane(points, 0.01, 500, np.random.default_rng(3))
    second = ransac_plane(points, 0.01, 500, np.random.default_rng(3))
    assert first is not None and second is not None
    assert np.array_equal(first[0], second[0]) and np.array_equal(first[1], second[1])


def test_no_plane_from_too_few_or_collinear_points() -> None:
    rng = np.random.default_rng(0)
    assert ransac_plane(np.zeros((2, 3)), 0.01, 100, rng) is None
    line = np.outer(np.linspace(0, 1, 50), [1.0, 2.0, 3.0])
    assert ransac_plane(line, 0.01, 100, rng) is None
