"""Perception accuracy and speed on seeded single-view synthetic tabletop scenes.

Each scene has 2-6 random objects (spheres, upright cylinders, upright cones, boxes) on a table,
ray-cast by a 320x240 depth camera from about 1 m with Kinect-like noise (sigma 1.2-3 mm, dropouts,
flying pixels), about 50k points per frame. Every frame goes through the chain the pipeline
runs (depth cut, voxel grid, support plane, clustering, per-cluster fitting, shape choice).

Printed:

- shape accuracy over the visible objects (≥ 50 points in the frame), with the confusion table;
  a box counts as right when reported as a Plane; a missed object counts as wrong;
- the same clusters classified by PITT's raw-inlier rule, for comparison (inlier counts at
  PITT's thresholds of the same RANSAC models, before refinement; lateral surface only for the
  cylinder, as in PITT);
- median and 95th-percentile errors: radius (spheres, cylinders, cones), height (cylinders,
  cones), centre (3-D, spheres, cylinders, cones), on objects whose shape was right;
- milliseconds per frame (median and p95) of segmentation + fitting, as wall time and as the
  process's CPU time (all threads; less sensitive to other work on a shared machine), and the
  points per frame.

Run from the repository root::

    .venv/bin/python bench/perception.py                 # 200 scenes
    .venv/bin/python bench/perception.py --scenes 20     # a quick look
"""

import argparse
import math
import os
import platform
import time
from collections import Counter

import numpy as np

from shapes.fit import fit_cluster, pitt_choice
from shapes.segment import segment
from shapes.synthetic import random_scene

VISIBLE_POINTS = 50
MATCH_GATE_M = 0.10


def percentiles(values: list[float]) -> str:
    if not values:
        return "n/a"
    a = np.abs(np.asarray(values)) * 1000
    return f"median {np.median(a):6.2f} mm   p95 {np.percentile(a, 95):6.2f} mm   (n={len(a)})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scenes", type=int, default=200, help="number of scenes (default 200)")
    parser.add_argument("--seed", type=int, default=20240611, help="seed of the scene generator")
    args = parser.parse_args()

    rng = np.random.default_rng(args.seed)
    # Warm-up: the first open3d calls and numpy paths are slower.
    warm = random_scene(rng, 3).render(rng)
    segment(warm.frame)

    confusion: Counter[tuple[str, str]] = Counter()
    pitt_right = total = occluded = extra = 0
    radius_err: list[float] = []
    height_err: list[float] = []
    centre_err: list[float] = []
    frame_ms: list[float] = []
    frame_cpu_ms: list[float] = []
    n_points: list[int] = []
    for i in range(args.scenes):
        scene = random_scene(rng, int(rng.integers(2, 7)))
        shot = scene.render(rng)
        n_points.append(len(shot.frame.points))
        fit_rng = np.random.default_rng([args.seed, i])
        start, start_cpu = time.perf_counter(), time.process_time()
        seg = segment(shot.frame, seed=i)
        fits = [fit_cluster(c.points, support=seg.support, rng=fit_rng) for c in seg.clusters]
        frame_ms.append((time.perf_counter() - start) * 1000)
        frame_cpu_ms.append((time.process_time() - start_cpu) * 1000)
        found = [(c, f) for c, f in zip(seg.clusters, fits, strict=True) if f is not None]
        used: set[int] = set()
        visible = np.bincount(shot.labels + 1, minlength=len(scene.objects) + 1)[1:]
        for k, obj in enumerate(scene.objects):
            if visible[k] < VISIBLE_POINTS:
                occluded += 1
                continue
            total += 1
            best, best_d = None, MATCH_GATE_M
            for j, (cluster, _fit) in enumerate(found):
                d = math.dist(cluster.centroid[:2], obj.position[:2])
                if j not in used and d < best_d:
                    best, best_d = j, d
            if best is None:
                confusion[(obj.expected_kind.value, "missed")] += 1
                continue
            used.add(best)
            fit = found[best][1]
            p = fit.primitive
            confusion[(obj.expected_kind.value, p.kind.value)] += 1
            pitt_right += pitt_choice(fit.pitt_counts) is obj.expected_kind
            if p.kind is not obj.expected_kind or obj.kind == "Box":
                continue
            assert p.radius is not None
            radius_err.append(p.radius - obj.radius)
            centre_err.append(math.dist(p.centre, obj.centre))
            if p.height is not None:
                height_err.append(p.height - obj.height)
        extra += len(found) - len(used)

    right = sum(n for (t, p), n in confusion.items() if t == p)
    kinds = ["Sphere", "Cylinder", "Cone", "Plane"]
    print(f"perception bench: {args.scenes} scenes, seed {args.seed}")
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, load average "
        f"{os.getloadavg()[0]:.2f}; python {platform.python_version()}"
    )
    print(f"points per frame: median {int(np.median(n_points))}, min {min(n_points)}")
    print(
        f"objects: {total} visible, {occluded} hidden (< {VISIBLE_POINTS} points), "
        f"{extra} extra detections"
    )
    print(f"shape accuracy: {100 * right / max(total, 1):.2f} % ({right}/{total})")
    print(f"PITT's rule on the same fits: {100 * pitt_right / max(total, 1):.2f} %")
    print("confusion (rows truth, columns reported):")
    print("            " + "".join(f"{k:>9}" for k in [*kinds, "missed"]))
    for t in kinds:
        print(f"  {t:<10}" + "".join(f"{confusion[(t, k)]:>9}" for k in [*kinds, "missed"]))
    print(f"radius error: {percentiles(radius_err)}")
    print(f"height error: {percentiles(height_err)}")
    print(f"centre error: {percentiles(centre_err)}")
    ms, cpu = np.asarray(frame_ms), np.asarray(frame_cpu_ms)
    print(
        f"time per frame (wall): median {np.median(ms):.1f} ms, p95 {np.percentile(ms, 95):.1f} "
        f"ms, mean {ms.mean():.1f} ms"
    )
    print(
        f"CPU time per frame (all threads of this process): median {np.median(cpu):.1f} ms, "
        f"p95 {np.percentile(cpu, 95):.1f} ms"
    )
    print(f"load average after the run: {os.getloadavg()[0]:.2f} (other work slows the wall time)")


if __name__ == "__main__":
    main()
