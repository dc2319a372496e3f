"""open3d's outlier removal and DBSCAN against an exact numpy/SciPy copy of both, in one process.

Tried at stop 40 to make a Kinect frame cheaper, and not kept (docs/perception.md, "A Kinect
frame's CPU at stop 40, and open3d's two searches copied to the bit (stop 40, tried)"). The copy
answers both of open3d's searches (``remove_statistical_outlier``'s nearest neighbours and
``cluster_dbscan``'s radius) from one SciPy k-d tree's pairs closer than DBSCAN's radius: a point
with ``neighbours - 1`` others within the radius has its nearest among them, and only the few
that have not are searched again. Its results are open3d's to the bit: distances summed as
nanoflann sums them (``(dx² + dy²) + dz²``, a point's nearest distances from the nearest up), the
statistics accumulated in open3d's order, a pair counted when its squared distance is below the
squared radius, clusters numbered in the order of their first core point, a border point in the
first cluster that reaches it.

The candidate voxels that :func:`shapes.segment.clusters.clusters_on` hands open3d are recorded
on each tuned-on Kinect scan of ``bench/perception_callgrind.py`` (no pose, seeds 0 to
``--seeds`` - 1; held-out scans are never loaded); then each set goes through both, alternately,
``--repeats`` times. Printed per set: whether the inliers and labels are identical, and each
one's least CPU (``time.process_time``); then the totals and their ratio. Run from the repository
root::

    PYTHONPATH=. nice -n 10 .venv/bin/python bench/perception_density.py
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other on a pinned process.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402
import open3d as o3d  # noqa: E402
from perception_callgrind import SCANS  # noqa: E402
from scipy.sparse import coo_matrix  # noqa: E402
from scipy.sparse.csgraph import connected_components  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

FloatArray = npt.NDArray[np.float64]


class Pairs:
    """The pairs of ``points`` closer than ``radius_m`` (squared distance below its square),
    each once (``first < second``), and the k-d tree that found them."""

    def __init__(self, points: FloatArray, radius_m: float) -> None:
        self.points = np.ascontiguousarray(points, dtype=np.float64)
        self.radius_m = radius_m
        self.tree = cKDTree(self.points)
        # SciPy keeps pairs up to the radius by its own arithmetic: a hair wider, then the
        # squared distances as open3d's nanoflann computes them decide.
        found = self.tree.query_pairs(radius_m * (1 + 1e-9), output_type="ndarray")
        first, second = found[:, 0], found[:, 1]
        squared = squared_distances(self.points, first, second)
        near = squared < radius_m * radius_m
        self.first = first[near]
        self.second = second[near]
        self.squared = squared[near]


def squared_distances(
    points: FloatArray, first: npt.NDArray[np.intp], second: npt.NDArray[np.intp]
) -> FloatArray:
    """The squared distances between the rows ``first`` and ``second`` of ``points``, summed as
    nanoflann sums them: ``(dx * dx + dy * dy) + dz * dz``."""
    out = np.zeros(len(first))
    for column in np.ascontiguousarray(points.T):
        d = np.take(column, first)
        d -= np.take(column, second)
        d *= d
        out += d
    return out


def statistical_inliers(pairs: Pairs, neighbours: int, std_ratio: float) -> npt.NDArray[np.intp]:
    """The indices (ascending) of the points whose mean distance to their ``neighbours``
    nearest points (themselves included) is above zero and below the points' mean of it plus
    ``std_ratio`` standard deviations (Bessel's), as open3d's ``remove_statistical_outlier``."""
    n = len(pairs.points)
    if n == 0:
        return np.zeros(0, dtype=np.intp)
    k = min(neighbours, n)
    nearest = _nearest_distances(pairs, k - 1)  # (n, k - 1): the others, nearest first
    total = np.zeros(n)  # the point itself, at distance 0, comes first
    for column in nearest.T:
        total += column
    mean_distance = total / k
    counted = mean_distance > 0
    cloud_mean = float(np.add.accumulate(np.where(counted, mean_distance, 0.0))[-1]) / n
    centred = mean_distance - cloud_mean
    squares = np.add.accumulate(np.where(counted, centred * centred, 0.0))[-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        std_dev = np.sqrt(squares / np.float64(n - 1))
    threshold = cloud_mean + std_ratio * std_dev
    return np.flatnonzero(counted & (mean_distance < threshold))


def _nearest_distances(pairs: Pairs, count: int) -> FloatArray:
    """Each point's distances to its ``count`` nearest other points, ascending."""
    n = len(pairs.points)
    out = np.empty((n, count))
    if count == 0:
        return out
    source = np.concatenate((pairs.first, pairs.second))
    squared = np.concatenate((pairs.squared, pairs.squared))
    # Nearest first within each point's pairs: equal distances may come in any order. A
    # stable sort of 16-bit keys is a radix sort, ten times numpy's stable sort of others.
    by_distance = np.argsort(squared)
    keys = source[by_distance]
    if n <= 1 << 16:
        keys = keys.astype(np.uint16)
    order = by_distance[np.argsort(keys, kind="stable")]
    source, squared = source[order], squared[order]
    found = np.bincount(source, minlength=n)
    start = np.concatenate(([0], np.cumsum(found)[:-1]))
    full = found >= count
    rows = np.flatnonzero(full)
    taken = start[rows, None] + np.arange(count)
    out[rows] = np.sqrt(squared[taken])
    sparse = np.flatnonzero(~full)
    if len(sparse):
        # Fewer than ``count`` others within the radius: their nearest lie farther.
        _, index = pairs.tree.query(pairs.points[sparse], count + 1)
        index = np.reshape(index, (len(sparse), count + 1))
        distances = np.sqrt(
            squared_distances(pairs.points, np.repeat(sparse, count + 1), index.ravel())
        ).reshape(len(sparse), count + 1)
        distances.sort(axis=1)
        out[sparse] = distances[:, 1:]  # the first is the point itself, at 0
    return out


def dbscan(pairs: Pairs, members: npt.NDArray[np.intp], min_points: int) -> npt.NDArray[np.int64]:
    """DBSCAN labels of the points ``members`` (ascending indices into ``pairs.points``) with
    the pairs' radius, as open3d's ``cluster_dbscan``: -1 for noise, clusters numbered in the
    order of their first core point (one with ``min_points`` points within the radius, itself
    included), a border point in the first cluster that has a core point near it."""
    m = len(members)
    labels = np.full(m, -1, dtype=np.int64)
    if m == 0:
        return labels
    position = np.full(len(pairs.points), -1, dtype=np.intp)
    position[members] = np.arange(m)
    a, b = position[pairs.first], position[pairs.second]
    both = (a >= 0) & (b >= 0)
    a, b = a[both], b[both]
    core = np.bincount(a, minlength=m) + np.bincount(b, minlength=m) + 1 >= min_points
    linked = core[a] & core[b]
    graph = coo_matrix((np.ones(int(linked.sum()), dtype=np.int8), (a[linked], b[linked])), (m, m))
    _, component = connected_components(graph, directed=False)
    cores = np.flatnonzero(core)
    if len(cores) == 0:
        return labels
    of_core = component[cores]
    firsts = np.unique(of_core, return_index=True)[1]  # each component's first core point
    number = np.empty(int(component.max()) + 1, dtype=np.int64)
    number[of_core[np.sort(firsts)]] = np.arange(len(firsts))
    labels[cores] = number[of_core]
    to_a = core[b] & ~core[a]
    to_b = core[a] & ~core[b]
    border = np.concatenate((a[to_a], b[to_b]))
    reached_by = np.concatenate((labels[b[to_a]], labels[a[to_b]]))
    first = np.full(m, m, dtype=np.int64)
    np.minimum.at(first, border, reached_by)
    reached = first < m
    labels[reached] = first[reached]
    return labels


def with_open3d(
    voxels: FloatArray, neighbours: int, std_ratio: float, eps_m: float, min_points: int
) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.int64]]:
    """What ``clusters_on`` does: open3d's outlier removal, then its DBSCAN on the inliers."""
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(voxels))
    _, kept = cloud.remove_statistical_outlier(neighbours, std_ratio)
    inliers = np.asarray(kept, dtype=np.intp)
    inlier_cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(voxels[inliers]))
    labels = np.asarray(inlier_cloud.cluster_dbscan(eps_m, min_points), dtype=np.int64)
    return inliers, labels


def with_copy(
    voxels: FloatArray, neighbours: int, std_ratio: float, eps_m: float, min_points: int
) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.int64]]:
    """The same from one k-d tree's pairs."""
    pairs = Pairs(voxels, eps_m)
    inliers = statistical_inliers(pairs, neighbours, std_ratio)
    return inliers, dbscan(pairs, inliers, min_points)


def recorded(seeds: int) -> list[tuple[str, int, FloatArray, tuple[Any, ...]]]:
    """The candidate voxels and parameters of every ``clusters_on`` call on the scans."""
    import shapes.segment.segmentation as segmentation
    from shapes import Perception, PerceptionParams, open_source

    root = Path("tests/data/real_scans")
    truth = json.loads((root / "truth.json").read_text())
    out: list[tuple[str, int, FloatArray, tuple[Any, ...]]] = []
    original = segmentation.clusters_on
    where: list[Any] = []

    def spy(
        candidates: Any, kept: Any, support: Any, margin: Any, params: Any, *a: Any, **k: Any
    ) -> Any:
        settings = (
            params.outlier_neighbours,
            params.outlier_std_ratio,
            params.cluster_eps_m,
            params.cluster_min_points,
        )
        out.append((where[0], where[1], kept.voxels[candidates].copy(), settings))
        return original(candidates, kept, support, margin, params, *a, **k)

    segmentation.clusters_on = spy  # type: ignore[assignment]
    try:
        for scan in SCANS:
            if truth.get(scan, {}).get("held_out"):
                continue
            frame = next(open_source(root / f"{scan}.npz"))
            for seed in range(seeds):
                where[:] = [scan, seed]
                Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    finally:
        segmentation.clusters_on = original
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds of the chain per scan (3)")
    parser.add_argument("--repeats", type=int, default=5, help="runs of each set and way (5)")
    args = parser.parse_args()
    totals = [0.0, 0.0]
    differ = 0
    cases = recorded(args.seeds)
    for scan, seed, voxels, settings in cases:
        a, b = with_open3d(voxels, *settings), with_copy(voxels, *settings)
        same = all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
        differ += not same
        least = [float("inf"), float("inf")]
        for _ in range(args.repeats):
            for k, way in enumerate((with_open3d, with_copy)):
                start = time.process_time()
                way(voxels, *settings)
                least[k] = min(least[k], 1000 * (time.process_time() - start))
        totals[0] += least[0]
        totals[1] += least[1]
        print(
            f"{scan:<26} seed {seed} {len(voxels):>6} voxels  "
            f"{'same' if same else 'DIFFER'}  open3d {least[0]:6.2f} ms  copy {least[1]:6.2f} ms"
        )
    print(
        f"{len(cases)} sets, {differ} differ; open3d {totals[0]:.1f} ms, copy {totals[1]:.1f} ms, "
        f"ratio {totals[1] / totals[0]:.2f}; load {os.getloadavg()[0]:.1f}"
    )


if __name__ == "__main__":
    main()
