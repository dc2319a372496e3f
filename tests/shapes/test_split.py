"""The touching-objects splitter: a frame's clusters split at once, each as if alone."""

import numpy as np
import pytest

from shapes.segment import voxel_grid
from shapes.split import split_each, split_touching


def _dome(rng: np.random.Generator, cx: float, radius: float) -> np.ndarray:
    """The upper half of a ball, seen from above, as 1 cm voxels."""
    d = rng.normal(size=(3000, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    d[:, 2] = np.abs(d[:, 2])
    return d * radius + (cx, 0.0, 0.0)


@pytest.fixture(scope="module")
def clusters():
    """Six clusters: two touching domes (which split), one dome, a noisy pair, a small one."""
    rng = np.random.default_rng(11)
    clouds = [
        np.vstack((_dome(rng, -0.041, 0.04), _dome(rng, 0.041, 0.04))),
        _dome(rng, 0.0, 0.05),
        np.vstack((_dome(rng, -0.03, 0.03), _dome(rng, 0.03, 0.03))),
        np.vstack((_dome(rng, -0.05, 0.05), _dome(rng, 0.05, 0.05)))
        + rng.normal(scale=0.004, size=(6000, 3)),
        _dome(rng, 0.0, 0.012),
        np.vstack((_dome(rng, -0.045, 0.045), _dome(rng, 0.04, 0.04))),
    ]
    return [voxel_grid(c, 0.01)[0] for c in clouds]


@pytest.mark.parametrize("viewpoint", [None, (0.0, 0.0, 1.0)])
def test_clusters_split_together_are_split_as_each_alone(clusters, viewpoint):
    view = None if viewpoint is None else np.array(viewpoint)
    noise = [0.0, 0.001, 0.003, 0.006, 0.0, 0.0025]
    together = split_each(clusters, view, noise_m=noise)
    alone = [split_touching(c, view, noise_m=n) for c, n in zip(clusters, noise, strict=True)]
    assert sum(int(labels.max()) > 0 for labels in alone) >= 2  # some of them split
    for got, expected in zip(together, alone, strict=True):
        np.testing.assert_array_equal(got, expected)


def test_one_noise_per_cluster_is_required(clusters):
    with pytest.raises(ValueError, match=r"noise_m: expected one noise per cluster \(6\), got 2"):
        split_each(clusters, None, noise_m=[0.0, 0.0])
