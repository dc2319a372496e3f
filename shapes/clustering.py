"""Statistical outlier removal and DBSCAN on one k-d tree (scipy), as open3d's
``remove_statistical_outlier`` and ``cluster_dbscan`` compute them.

Segmentation runs the two one after the other on the voxels above a support. open3d builds a
tree for each and searches every point's neighbourhood twice; here one tree answers both: the
k nearest neighbours for the outlier test, then the pairs within the DBSCAN radius, of which
those between kept points are DBSCAN's neighbourhoods. The results are open3d's, label for
label (``tests/shapes/test_clustering.py`` compares them on real and simulated voxels):

- a point is an outlier when the mean distance to its ``neighbours`` nearest points (itself
  included, at distance 0) is not below ``mean + std_ratio * std`` of those means over the
  cloud (a sample standard deviation); a cloud of fewer than two points keeps none;
- DBSCAN: a *core* point has at least ``min_points`` points (itself included) closer than
  ``eps``; clusters are the connected groups of core points, numbered in the order of their
  first point; a point that is not core takes the label of the first cluster with a core point
  closer than ``eps``, else -1 (noise).

>>> points = np.array([[0.0, 0, 0], [0.01, 0, 0], [0.02, 0, 0], [0.5, 0, 0], [0.51, 0, 0],
...                    [0.52, 0, 0], [0.53, 0, 0], [2.0, 0, 0]])
>>> kept, labels = outliers_and_clusters(points, neighbours=3, std_ratio=1.0, eps=0.015,
...                                      min_points=3)
>>> kept.tolist(), labels.tolist()
([0, 1, 2, 3, 4, 5, 6], [0, 0, 0, 1, 1, 1, 1])
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["outliers_and_clusters"]

Index = npt.NDArray[np.intp]


def outliers_and_clusters(
    points: FloatArray, *, neighbours: int, std_ratio: float, eps: float, min_points: int
) -> tuple[Index, npt.NDArray[np.int64]]:
    """The indices of the points kept by the outlier test, and the DBSCAN label (-1: noise) of
    each kept point (see the module docstring)."""
    n = len(points)
    if n == 0:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.int64)
    tree = cKDTree(points, balanced_tree=False, compact_nodes=False)
    if n < 2:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.int64)
    distances = tree.query(points, k=min(neighbours, n))[0].reshape(n, -1)
    mean = distances.mean(axis=1)
    # As open3d: a point at distance 0 from all its neighbours (duplicates) is dropped and
    # adds nothing to the sums, but counts in the number of points they are divided by.
    valid = mean > 0
    cloud_mean = float(mean[valid].sum()) / n
    std = float(np.sqrt(((mean[valid] - cloud_mean) ** 2).sum() / (n - 1)))
    kept = np.flatnonzero(valid & (mean < cloud_mean + std_ratio * std))
    # open3d's radius search keeps the points strictly closer than eps.
    pairs = tree.query_pairs(np.nextafter(eps, 0.0), output_type="ndarray")
    position = np.full(n, -1, dtype=np.intp)
    position[kept] = np.arange(len(kept))
    i, j = position[pairs[:, 0]], position[pairs[:, 1]]
    both = (i >= 0) & (j >= 0)
    return kept, _dbscan(len(kept), i[both], j[both], min_points)


def _dbscan(
    n: int, i: npt.NDArray[np.intp], j: npt.NDArray[np.intp], min_points: int
) -> npt.NDArray[np.int64]:
    """DBSCAN labels of n points from the pairs (i, j) closer than its radius."""
    core = np.bincount(i, minlength=n) + np.bincount(j, minlength=n) + 1 >= min_points
    linked = core[i] & core[j]
    graph = coo_matrix((np.ones(int(linked.sum())), (i[linked], j[linked])), shape=(n, n))
    _, component = connected_components(graph, directed=False)
    # Clusters numbered in the order of their first core point, as open3d's scan finds them.
    first = np.unique(component[core], return_index=True)[1]
    number = np.full(int(component.max(initial=-1)) + 1, -1, dtype=np.int64)
    number[component[core][np.sort(first)]] = np.arange(len(first))
    labels = np.full(n, -1, dtype=np.int64)
    labels[core] = number[component[core]]
    # A border point joins the first cluster (lowest label) among its core neighbours.
    to_i, to_j = core[j] & ~core[i], core[i] & ~core[j]
    border = np.concatenate((i[to_i], j[to_j]))
    label = np.concatenate((labels[j[to_i]], labels[i[to_j]]))
    lowest = np.full(n, np.iinfo(np.int64).max)
    np.minimum.at(lowest, border, label)
    joined = lowest < np.iinfo(np.int64).max
    labels[joined] = lowest[joined]
    return labels
