"""The chain on the nine Kinect scans tuned on, once each (seed 0), for an instruction count.

Instructions do not move with the machine's load the way CPU time does. Run it under
callgrind twice, once as it is and once with ``--load-only`` (the imports, the scans loaded,
one warm-up frame), and divide the difference by nine::

    PYTHONPATH=. valgrind --tool=callgrind --callgrind-out-file=/tmp/all.out \\
        .venv/bin/python bench/perception_callgrind.py
    PYTHONPATH=. valgrind --tool=callgrind --callgrind-out-file=/tmp/none.out \\
        .venv/bin/python bench/perception_callgrind.py --load-only

Held-out scans (``"held_out": true`` in truth.json) are never loaded.
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from pathlib import Path  # noqa: E402

SCANS = (
    "bottles_kinect",
    "laptop_box_kinect_0",
    "laptop_box_kinect_1",
    "laptop_box_kinect_2",
    "office_kinect",
    "bottle_pack_floor_kinect",
    "people_floor_kinect",
    "box_floor_kinect",
    "chair_boxes_kinect",
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--load-only", action="store_true", help="load and warm up, no frame")
    args = parser.parse_args()
    from shapes import Perception, PerceptionParams, open_source

    root = Path("tests/data/real_scans")
    truth = json.loads((root / "truth.json").read_text())
    scans = [s for s in SCANS if not truth.get(s, {}).get("held_out")]
    params = PerceptionParams(gravity_from_scene=True)
    frames = [next(open_source(root / f"{scan}.npz")) for scan in scans]
    Perception(params, seed=0).process(frames[0])  # warm: lazy imports, caches
    if not args.load_only:
        for frame in frames:
            Perception(params, seed=0).process(frame)


if __name__ == "__main__":
    main()
