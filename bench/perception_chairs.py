"""The floor under finding the chairs: what their measured centroid rests on, and where their
voxels go.

The three measured chairs of the tuned-on scans (``lab_floor_rtabmap``'s left and right chair,
``chair_boxes_kinect``'s chair) are missed: the seat and back hang over a base that segmentation
drops or keeps apart (docs/perception.md, "The chairs: a seat joined with what stands under it
(stop 41, tried)"). A rule that joins the seat, the back and the base can only put a chair within
3 cm if the voxels it can join weigh as much as the ground truth's points do. For each chair this
prints:

- from the ground truth's own points (``measure.object_mask``, as ``bench/perception_oracle.py``
  takes them): how far the centroid of the points from ``h`` up lies from the measured centroid,
  for each ``h`` of ``FROM_M`` (what is left when the parts under the seat are lost);
- from the chain's survey, for each of ``--seeds`` seeds (``Perception(PerceptionParams(
  gravity_from_scene=True), seed=k)``, the bench's run, steps logged as
  ``bench/perception_missed.py`` logs them): the chair's voxels (a voxel is the chair's when most
  of its kept points are) under ``UNDER_M``, and of those how many are free, held by a plane, or
  dropped as stray returns (neither: ``shapes.artefacts.sparse_voxels``); and its free voxels
  inside the height band but outside the box of the floor's main piece (``over_supports``), which
  no cluster over the floor can hold; and how far from the measured centroid lies the
  centroid of the chair's points in free voxels, all of them and those a cluster over the floor
  can hold (the best a rule that joins free voxels can do).

The held-out scans are never loaded (the three chairs' scans are tuned on).

Run from the repository root (a few seconds of CPU)::

    PYTHONPATH=. .venv/bin/python bench/perception_chairs.py --seeds 3
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from shapes import Frame, open_source  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

missed = load_script(Path(__file__).with_name("perception_missed.py"), "perception_missed_chairs")
oracle = missed.oracle
CHAIRS = {
    "lab_floor_rtabmap": ("left chair", "right chair"),
    "chair_boxes_kinect": ("chair",),
}
FROM_M = (0.0, 0.20, 0.33, 0.40)
"""Heights over the measured floor from which the ground truth's points are kept: 0.33 m is
under the lowest seat voxel the chain sees on the three chairs (0.34-0.37 m)."""
UNDER_M = 0.33
"""The chair's voxels under this height are its base: legs, column, wheels."""


def truth_rows(scan: str, measured: str, truth: dict[str, Any]) -> list[str]:
    """For each chair of ``scan``, the measured centroid's error when only the points from each
    height of ``FROM_M`` up are kept."""
    normal, offset = oracle.measured_support(scan, measured)
    image = oracle.measure.points_of(scan).reshape(-1, 3)
    pixels = oracle.object_pixels(scan, measured)
    rows = []
    for label in CHAIRS[scan]:
        points = image[pixels[label]]
        points = points[np.isfinite(points).all(axis=1)]
        height = points @ np.asarray(normal) + offset
        centre = np.asarray(truth[measured][label]["centre"])
        cells = []
        for h in FROM_M:
            up = points[height >= h]
            off = 100 * float(np.linalg.norm(up.mean(axis=0) - centre))
            cells.append(f"from {100 * h:.0f} cm: {100 * len(up) / len(points):.0f} % {off:.1f} cm")
        rows.append(f"{scan} / {label}: {len(points)} points; " + "; ".join(cells))
    return rows


def voxel_rows(
    scan: str, measured: str, frame: Frame, seed: int, centres: dict[str, list[float]]
) -> list[str]:
    """For each chair of ``scan`` (measured centroid ``centres[label]``, sensor frame), on seed
    ``seed``: where its voxels under ``UNDER_M`` go, how many of its free voxels in the band lie
    outside the floor's box, and how far from its measured centroid lies the centroid of its
    points in free voxels (all of them; those a cluster over the floor can hold)."""
    result, log = missed.run_logged(frame, seed)
    kept = log.first("KeptPoints")[1]
    judged = log.first("judge_planes")[1]
    (_, voxels, _, _, params), free = log.first("free_voxels")
    over = log.first("over_supports")[1]
    floor = over.supports[0]
    in_plane = np.zeros(len(voxels), dtype=bool)
    for plane in judged.planes:
        in_plane[plane.inliers] = True
    total = np.bincount(kept.voxel_of, minlength=len(voxels))
    pixels = oracle.object_pixels(scan, measured)
    back = np.linalg.inv(result.world_from_sensor)  # the chain's world to the sensor's frame
    rows = []
    for label in CHAIRS[scan]:
        own = np.isin(kept.pixels, pixels[label])
        mine = np.bincount(kept.voxel_of[own], minlength=len(voxels))
        vox = np.flatnonzero(2 * mine > total)
        height = floor.signed_distance(voxels[vox])
        low = vox[height < UNDER_M]
        in_band = (height > 0) & (height < params.max_height_m)
        outside = int((free[vox] & (over.owner[vox] < 0) & in_band).sum())
        centre = np.asarray(centres[label])
        reachable = free[vox] & ~((over.owner[vox] < 0) & in_band)
        best = {
            "free": kept.points[np.isin(kept.voxel_of, vox[free[vox]])],
            "free, in the box": kept.points[np.isin(kept.voxel_of, vox[reachable])],
        }
        off = {
            name: 100
            * float(np.linalg.norm(back[:3, :3] @ pts.mean(axis=0) + back[:3, 3] - centre))
            for name, pts in best.items()
        }
        offs = "; ".join(f"{name} {cm:.1f} cm" for name, cm in off.items())
        rows.append(
            f"{scan} / {label} / seed {seed}: {len(vox)} voxels; under {100 * UNDER_M:.0f} cm "
            f"{len(low)}: free {int(free[low].sum())}, in a plane {int(in_plane[low].sum())}, "
            f"stray returns {int((~free[low] & ~in_plane[low]).sum())}; free in the band outside "
            f"the floor's box {outside}; centroid of its points in voxels: {offs}"
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    truth = json.loads((oracle.SCANS / "truth.json").read_text())
    for scan in CHAIRS:
        measured = oracle.bench.REAL_TRUTH[scan]
        if truth[measured].get("held_out"):
            continue
        for row in truth_rows(scan, measured, truth):
            print(row)
        frame = next(open_source(oracle.SCANS / f"{scan}.npz"))
        for seed in range(args.seeds):
            for row in voxel_rows(
                scan, measured, frame, seed, {k: truth[measured][k]["centre"] for k in CHAIRS[scan]}
            ):
                print(row)


if __name__ == "__main__":
    main()
