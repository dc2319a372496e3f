"""What the plane search's single-precision scoring saves a Kinect frame, in one process.

Each tuned-on Kinect scan of ``tests/data/real_scans`` (``kinect`` in the name; held-out and
reserved scans are never loaded) goes through the pipeline with no pose (gravity from the scene)
on seeds 0-2, alternately with this checkout's ``shapes.segment.planes.ransac_plane`` and with
the one of ``--against`` (another checkout, e.g. the branch's start, loaded from its file),
``--repeats`` times; each frame keeps its least CPU (``time.process_time``). Printed: the median
over the scans of each scan's median frame with each, and the per-scan difference. Both come
from the same minutes, so their difference survives the machine's load better than either
figure (docs/perception.md, "The plane search scored in single precision (stop 40, speed)").
Run from the repository root::

    PYTHONPATH=. nice -n 10 .venv/bin/python bench/perception_plane_precision.py \\
        --against /work/wt/base45
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from perception import REAL_SCANS, loadable_scans  # noqa: E402

import shapes.segment.planes as planes  # noqa: E402
from shapes import Perception, PerceptionParams, open_source  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--against", type=Path, required=True, help="the other checkout")
    parser.add_argument("--repeats", type=int, default=2, help="runs of each frame and mode (2)")
    args = parser.parse_args()
    path = args.against / "shapes" / "segment" / "planes.py"
    spec = importlib.util.spec_from_file_location("planes_against", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"--against: no shapes/segment/planes.py under {args.against}")
    other = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = other  # its dataclasses look their module up
    spec.loader.exec_module(other)
    searches = {"this": planes.ransac_plane, "against": other.ransac_plane}
    names = [scan for scan, _ in loadable_scans() if "kinect" in scan]
    params = PerceptionParams(gravity_from_scene=True)
    least: dict[tuple[str, int, str], float] = {}
    for scan in names:
        frame = next(open_source(REAL_SCANS / f"{scan}.npz"))
        for seed in range(3):
            for _ in range(args.repeats):
                for mode, search in searches.items():
                    planes.ransac_plane = search  # find_planes looks it up in its module
                    start = time.process_time()
                    Perception(params, seed=seed).process(frame)
                    ms = 1000 * (time.process_time() - start)
                    key = (scan, seed, mode)
                    least[key] = min(least.get(key, float("inf")), ms)
    planes.ransac_plane = searches["this"]
    per_scan = {
        mode: [float(np.median([least[(s, k, mode)] for k in range(3)])) for s in names]
        for mode in searches
    }
    gaps = [a - b for a, b in zip(per_scan["this"], per_scan["against"], strict=True)]
    print(
        f"{len(names)} Kinect scans, seeds 0-2: median frame {np.median(per_scan['this']):.0f} ms "
        f"with this plane search, {np.median(per_scan['against']):.0f} ms with --against's; per "
        f"scan {np.median(gaps):.1f} ms (median), {min(gaps):.1f} to {max(gaps):.1f} ms"
    )


if __name__ == "__main__":
    main()
