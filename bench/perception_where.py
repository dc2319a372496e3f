"""Where a Kinect frame's CPU goes, function by function, on the nine Kinect scans tuned on.

Each function below is wrapped, for this run only, in a timer of CPU time
(``time.process_time``; outermost call only when it recurses), and the chain runs on each
Kinect scan of ``bench/perception_callgrind.py`` (no pose: gravity from the scene) on
``--seeds`` seeds. Printed per frame, in ms: each function's CPU (its callees included) for
the laptop and bottle frames (the frames of the median, which ``bench/perception.py``'s
"CPU per 640x480 frame" reads) and for all nine, and how many calls a frame makes. Nested rows
(indented) are part of the row above them; a k-d tree's row holds its build and its queries
(the calls counted are both), and ``_cloud``'s the open3d clouds' building, outlier removal
and DBSCAN. The splitter's ``cKDTree`` row includes the trees of its ``_parts``.

The wrappers add a few microseconds a call, so the figures are for comparing the parts of a
frame, not for comparing checkouts (``bench/perception_stages.py --against`` and
``bench/perception_callgrind.py`` do that). Held-out scans are never loaded. Run from the
repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_where.py --seeds 3
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other on a pinned process.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import importlib  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
from collections import defaultdict  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

from perception_callgrind import SCANS  # noqa: E402

MEDIAN_FRAMES = (
    "bottles_kinect",
    "laptop_box_kinect_0",
    "laptop_box_kinect_1",
    "laptop_box_kinect_2",
)
TIMED = (  # (depth, module, name): the name as the calling module looks it up
    (0, "shapes.pipeline", "survey"),
    (1, "shapes.segment.survey", "depth_noise_1m"),
    (1, "shapes.segment.survey", "flying_pixels"),
    (1, "shapes.segment.survey", "voxel_grid"),
    (1, "shapes.segment.survey", "find_planes"),
    (2, "shapes.segment.planes", "ransac_plane"),
    (0, "shapes.pipeline", "gravity_from_survey"),
    (0, "shapes.pipeline", "segment"),
    (1, "shapes.segment.segmentation", "image_view"),
    (1, "shapes.segment.segmentation", "judge_planes"),
    (2, "shapes.segment.supports", "support_region"),
    (1, "shapes.segment.segmentation", "free_voxels"),
    (1, "shapes.segment.segmentation", "over_supports"),
    (1, "shapes.segment.segmentation", "clusters_on"),
    (2, "shapes.segment.clusters", "_cloud"),
    (2, "shapes.segment.clusters", "split_clusters"),
    (3, "shapes.segment.splitting", "split_each"),
    (4, "shapes.split", "cKDTree"),
    (4, "shapes.split", "patch_normals"),
    (4, "shapes.split", "connected_components"),
    (4, "shapes.split", "_parts"),
    (2, "shapes.segment.clusters", "_parted_at_occlusions"),
    (0, "shapes.pipeline", "fit_cluster"),
    (1, "shapes.fit.select", "normals_at"),
    (2, "shapes.fit.select", "cKDTree"),
    (1, "shapes.fit.select", "ransac"),
    (1, "shapes.fit.select", "refine_if_better"),
    (1, "shapes.fit.select", "_sphere_on_rays"),
)


class _Timed:
    """A stand-in for a function that adds its CPU time and calls to ``totals[key]``. With
    ``methods``, what it returns stands in for the returned object, and the methods called
    on that are timed under the same key (a k-d tree's build and queries; an open3d cloud's
    outlier removal and DBSCAN)."""

    def __init__(
        self,
        key: str,
        target: Callable[..., Any],
        totals: dict[str, list[float]],
        methods: bool = False,
    ) -> None:
        self.key, self.target, self.totals, self.methods, self.depth = (
            key,
            target,
            totals,
            methods,
            0,
        )

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        if self.depth:
            return self.target(*args, **kwargs)
        self.depth += 1
        start = time.process_time()
        try:
            out = self.target(*args, **kwargs)
        finally:
            entry = self.totals[self.key]
            entry[0] += time.process_time() - start
            entry[1] += 1
            self.depth -= 1
        return _Methods(self.key, out, self.totals) if self.methods else out


class _Methods:
    """An object whose methods are each timed under ``key``."""

    def __init__(self, key: str, target: Any, totals: dict[str, list[float]]) -> None:
        self.key, self.target, self.totals = key, target, totals

    def __getattr__(self, name: str) -> Any:
        return _Timed(self.key, getattr(self.target, name), self.totals)


def _wrapped(totals: dict[str, list[float]]) -> dict[tuple[str, str], Any]:
    """Puts a timed stand-in in place of each function of ``TIMED``; returns the originals."""
    originals = {}
    for depth, module_name, name in TIMED:
        module = importlib.import_module(module_name)
        key = f"{'  ' * depth}{name} ({module_name.split('.')[-1]})"
        originals[module_name, name] = getattr(module, name)
        methods = name in ("cKDTree", "_cloud")
        setattr(module, name, _Timed(key, originals[module_name, name], totals, methods))
    return originals


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds of the chain per scan (3)")
    args = parser.parse_args()
    if args.seeds < 1:
        parser.error(f"--seeds: expected a positive count, got {args.seeds}")
    from shapes import Perception, PerceptionParams, open_source

    root = Path("tests/data/real_scans")
    truth = json.loads((root / "truth.json").read_text())
    scans = [s for s in SCANS if not truth.get(s, {}).get("held_out")]
    frames = {scan: next(open_source(root / f"{scan}.npz")) for scan in scans}
    params = PerceptionParams(gravity_from_scene=True)
    Perception(params, seed=0).process(frames[scans[0]])  # warm: lazy imports, caches
    per_scan: dict[str, dict[str, list[float]]] = {}
    for scan, frame in frames.items():
        totals: dict[str, list[float]] = defaultdict(lambda: [0.0, 0])
        originals = _wrapped(totals)
        try:
            for seed in range(args.seeds):
                start = time.process_time()
                Perception(params, seed=seed).process(frame)
                totals["frame"][0] += time.process_time() - start
                totals["frame"][1] += 1
        finally:
            for (module_name, name), original in originals.items():
                setattr(importlib.import_module(module_name), name, original)
        per_scan[scan] = dict(totals)
    _print(per_scan, args.seeds)


def _print(per_scan: dict[str, dict[str, list[float]]], seeds: int) -> None:
    groups = {
        "median frames": [s for s in per_scan if s in MEDIAN_FRAMES],
        "all nine": list(per_scan),
    }
    print(f"CPU ms per frame (calls per frame), {seeds} seeds each; median frames:")
    print(f"  {', '.join(groups['median frames'])}")
    print(f"{'':<34}" + "".join(f"{g:>22}" for g in groups))
    keys = ["frame"] + [f"{'  ' * d}{n} ({m.split('.')[-1]})" for d, m, n in TIMED]
    for key in keys:
        cells = []
        for scans in groups.values():
            count = seeds * len(scans)
            ms = sum(per_scan[s].get(key, [0.0, 0])[0] for s in scans) * 1000 / count
            calls = sum(per_scan[s].get(key, [0.0, 0])[1] for s in scans) / count
            cells.append(f"{ms:>13.1f} ({calls:>5.1f})")
        print(f"{key:<34}" + "".join(f"{c:>22}" for c in cells))


if __name__ == "__main__":
    main()
