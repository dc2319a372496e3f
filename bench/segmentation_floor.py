"""The floor under a Kinect frame's segmentation: its array and library calls alone.

For each of the five Kinect scans of ``bench/perception_stages.py`` (no pose: gravity from the
scene), the CPU time (``time.process_time``, median of ``--repeats``) of the whole chain before
any fit (survey, gravity, segmentation), then of the calls it cannot do without as it stands,
each re-run alone on the inputs it had in the chain:

- ``image``: the depth image, its noise and the flying pixels judged at the chosen stride
  (full-image array passes);
- ``voxels``: the 1 cm voxel grid of the kept points (a sort of their keys, three sums);
- ``ransac``: the plane searches as made (each up to 500 hypotheses scored on up to 4,000
  voxels);
- ``open3d``: the statistical outlier removal and DBSCAN of the voxels above each support;
- ``kd-trees``: the splitter's k-d trees, 10 nearest neighbours and 1.8 cm pairs of each
  cluster.

"floor" is their sum: what the chain would cost if everything else (the masks, gathers,
planes' tests, supports, normals, parts) were free. Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/segmentation_floor.py
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other on a pinned process.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import copy  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import open3d as o3d  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

SCANS = (
    "bottles_kinect",
    "laptop_box_kinect_0",
    "laptop_box_kinect_1",
    "laptop_box_kinect_2",
    "office_kinect",
)
COLUMNS = ("before fits", "image", "voxels", "ransac", "open3d", "kd-trees", "floor")


def cpu_ms(run: Callable[[], Any], repeats: int) -> float:
    """Median CPU milliseconds of ``run()``."""
    spent = []
    for _ in range(repeats):
        start = time.process_time()
        run()
        spent.append(time.process_time() - start)
    return 1000 * float(np.median(spent))


def measure(scan: str, repeats: int) -> list[float]:
    """The row of one scan: before fits, then each floor item and their sum (CPU ms)."""
    import shapes.segment.planes
    import shapes.segment.segmentation
    import shapes.segment.splitting
    import shapes.segment.survey  # noqa: F401  (the module objects, not the package's names)
    from shapes import open_source
    from shapes.artefacts import depth_noise_1m, flying_pixels
    from shapes.gravity import gravity_from_survey

    seg = sys.modules["shapes.segment"]
    # Where each call recorded below is looked up.
    where = {
        "ransac_plane": sys.modules["shapes.segment.planes"],
        "clusters_on": sys.modules["shapes.segment.segmentation"],
        "split_each": sys.modules["shapes.segment.splitting"],
    }
    in_survey = sys.modules["shapes.segment.survey"]
    params = seg.SegmentationParams()
    frame = next(open_source(Path("tests/data/real_scans") / f"{scan}.npz"))

    def before_fits() -> None:
        surveyed = seg.survey(frame, params, 0)
        up = gravity_from_survey(frame, surveyed, params)
        assert up is not None
        seg.segment(frame.with_pose(up.world_from_sensor), params, 0, surveyed=surveyed)

    # One run with the calls' inputs recorded.
    planes: list[tuple[Any, ...]] = []
    above: list[Any] = []
    clusters: list[Any] = []
    originals = {name: getattr(module, name) for name, module in where.items()}

    def ransac(points: Any, threshold: float, iterations: int, rng: Any) -> Any:
        planes.append((points, threshold, iterations, copy.deepcopy(rng)))
        return originals["ransac_plane"](points, threshold, iterations, rng)

    def candidates(found: Any, kept: Any, *args: Any) -> Any:
        above.append(kept.voxels[found])
        return originals["clusters_on"](found, kept, *args)

    def split(each: Any, *args: Any, **kwargs: Any) -> Any:
        clusters.extend(each)
        return originals["split_each"](each, *args, **kwargs)

    for name, fn in (("ransac_plane", ransac), ("clusters_on", candidates), ("split_each", split)):
        setattr(where[name], name, fn)
    try:
        before_fits()
    finally:
        for name, fn in originals.items():
            setattr(where[name], name, fn)
    surveyed = seg.survey(frame, params, 0)
    stride = seg.pixel_stride(
        int((frame.points[:, 2] <= seg.depth_cut_m(surveyed.sigma_1m, params)).sum()), params
    )

    def image() -> None:
        depth = in_survey._depth_image(frame)
        sigma = depth_noise_1m(depth)
        depth[depth > seg.depth_cut_m(sigma, params)] = np.nan
        flying_pixels(depth, sigma, focal_px=in_survey._focal_px(frame), step=stride)

    def ransacs() -> None:
        for points, threshold, iterations, rng in planes:
            seg.ransac_plane(points, threshold, iterations, copy.deepcopy(rng))

    def libraries() -> None:
        for voxels in above:
            cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(voxels))
            _, kept = cloud.remove_statistical_outlier(
                params.outlier_neighbours, params.outlier_std_ratio
            )
            o3d.geometry.PointCloud(
                o3d.utility.Vector3dVector(voxels[np.asarray(kept)])
            ).cluster_dbscan(params.cluster_eps_m, params.cluster_min_points)

    def trees() -> None:
        for voxels in clusters:
            tree = cKDTree(voxels, balanced_tree=False, compact_nodes=False)
            tree.query(voxels, k=10)
            tree.query_pairs(0.018, output_type="ndarray")

    row = [
        cpu_ms(before_fits, repeats),
        cpu_ms(image, repeats),
        cpu_ms(lambda: seg.voxel_grid(surveyed.points, params.voxel_m), repeats),
        cpu_ms(ransacs, repeats),
        cpu_ms(libraries, repeats),
        cpu_ms(trees, repeats),
    ]
    return [*row, sum(row[1:])]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=7, help="runs per figure (7)")
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    print(f"{Path.cwd()}: CPU ms, median of {args.repeats}, load {os.getloadavg()[0]:.1f}")
    print(f"{'scan':<22}" + "".join(f"{c:>12}" for c in COLUMNS))
    rows = []
    for scan in SCANS:
        rows.append(measure(scan, args.repeats))
        print(f"{scan:<22}" + "".join(f"{v:>12.1f}" for v in rows[-1]), flush=True)
    median = np.median(np.array(rows), axis=0)
    print(f"{'median':<22}" + "".join(f"{v:>12.1f}" for v in median))


if __name__ == "__main__":
    main()
