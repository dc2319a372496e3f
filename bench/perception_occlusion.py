"""What parting clusters at occlusion edges (or another step) costs a Kinect frame, in one process.

Each tuned-on Kinect scan of ``tests/data/real_scans`` (``kinect`` in the name; the held-out and
reserved ones are never loaded) goes through the pipeline with no pose (gravity from the scene)
on seeds 0-2, with the occlusion step on (the default ``occlusion_slope``) and off
(``occlusion_slope`` 0), alternately, ``--repeats`` times (``--off FIELD``: another step, off
when that field of :class:`shapes.segment.SegmentationParams` is 0, such as
``min_part_colour_difference``, the colour seam of stop 40); each frame keeps its least CPU
(``time.process_time``). Printed: the median over the scans of each scan's median frame, on and
off, and the per-scan difference. The two come from the same minutes, so their difference
survives the machine's load better than either figure alone (docs/perception.md, "A thing lying
across another, and a hand reaching in (stop 39)").

Run from the repository root::

    PYTHONPATH=. nice -n 10 .venv/bin/python bench/perception_occlusion.py
"""

import argparse
import dataclasses
import json
import time

import numpy as np
from perception import REAL_SCANS, REAL_TRUTH

from shapes import Perception, PerceptionParams, open_source
from shapes.segment import SegmentationParams


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each frame and mode (3)")
    parser.add_argument(
        "--off",
        default="occlusion_slope",
        help="the SegmentationParams field set to 0 for the step's off runs (occlusion_slope)",
    )
    args = parser.parse_args()
    if args.off not in {f.name for f in dataclasses.fields(SegmentationParams)}:
        parser.error(f"--off: expected a field of SegmentationParams, got {args.off!r}")
    truth = json.loads((REAL_SCANS / "truth.json").read_text())
    names = [
        scan
        for scan, measured in REAL_TRUTH.items()
        if "kinect" in scan
        and not truth[measured].get("held_out")
        and not truth[measured].get("reserved")
    ]
    on = PerceptionParams(gravity_from_scene=True)
    off = dataclasses.replace(on, segmentation=SegmentationParams(**{args.off: 0.0}))
    least: dict[tuple[str, int, str], float] = {}
    for scan in names:
        frame = next(open_source(REAL_SCANS / f"{scan}.npz"))
        for seed in range(3):
            for _ in range(args.repeats):
                for mode, params in (("on", on), ("off", off)):
                    start = time.process_time()
                    Perception(params, seed=seed).process(frame)
                    ms = 1000 * (time.process_time() - start)
                    key = (scan, seed, mode)
                    least[key] = min(least.get(key, float("inf")), ms)
    per_scan = {
        mode: [float(np.median([least[(s, k, mode)] for k in range(3)])) for s in names]
        for mode in ("on", "off")
    }
    gaps = [a - b for a, b in zip(per_scan["on"], per_scan["off"], strict=True)]
    print(
        f"{len(names)} Kinect scans, seeds 0-2: median frame {np.median(per_scan['on']):.0f} ms "
        f"with the step ({args.off}), {np.median(per_scan['off']):.0f} ms without; per scan "
        f"{np.median(gaps):.1f} ms more (median), {min(gaps):.1f} to {max(gaps):.1f} ms"
    )


if __name__ == "__main__":
    main()
