"""What a step of the chain (occlusion edges, slivers, colour seams, the fit's parameter charge,
fragments joined, the support measured again) costs a Kinect frame, and which primitives it
changes.

Each tuned-on Kinect scan of ``tests/data/real_scans`` (``kinect`` in the name; the held-out and
reserved ones are never loaded) goes through the pipeline with no pose (gravity from the scene)
on seeds 0-2, with the step on (the default parameters) and off, alternately, ``--repeats``
times. The steps (``--step``), each off as ``STEP_OFF`` says: ``occlusion``
(:mod:`shapes.segment.occlusion`), ``slivers`` (:mod:`shapes.segment.slivers`), ``colour_seam``
(:mod:`shapes.colour_seam`), ``parameter_charge`` (:mod:`shapes.fit.information`),
``fragments`` (:mod:`shapes.segment.fragments`) and ``support_fit``
(:mod:`shapes.segment.support_fit`: it changes only the support reported, no primitive of an
object); each frame keeps its least CPU (``time.process_time``). Printed: every primitive whose
kind the step changes (scan, seed, kind off -> on, its centre in the world frame), then the
median over the scans of each scan's median frame, on and off, and the per-scan difference. The
two come from the same minutes, so their difference survives the machine's load better than
either figure alone (docs/perception.md, "A thing lying across another, and a hand reaching in
(stop 39)").

Run from the repository root::

    PYTHONPATH=. nice -n 10 .venv/bin/python bench/perception_step_cost.py
    PYTHONPATH=. nice -n 10 .venv/bin/python bench/perception_step_cost.py --step slivers
"""

import argparse
import dataclasses
import time

import numpy as np
from perception import REAL_SCANS, loadable_scans

from shapes import Perception, PerceptionParams, open_source
from shapes.fit import FitParams
from shapes.segment import SegmentationParams

STEP_OFF = {
    "occlusion": {"segmentation": SegmentationParams(occlusion_slope=0.0)},
    "slivers": {"segmentation": SegmentationParams(max_edge_share=1.0)},
    "colour_seam": {"segmentation": SegmentationParams(min_part_colour_difference=0.0)},
    "parameter_charge": {"fit": FitParams(parameter_charge=0.0)},
    "fragments": {"segmentation": SegmentationParams(fragment_max_voxels=0)},
    "support_fit": {"segmentation": SegmentationParams(measure_support=False)},
}
"""Each step's parameters that turn it off (fields of :class:`shapes.PerceptionParams`)."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each frame and mode (3)")
    parser.add_argument(
        "--step", choices=sorted(STEP_OFF), default="occlusion", help="the step timed (occlusion)"
    )
    args = parser.parse_args()
    names = [scan for scan, _ in loadable_scans() if "kinect" in scan]
    on = PerceptionParams(gravity_from_scene=True)
    off = dataclasses.replace(on, **STEP_OFF[args.step])
    least: dict[tuple[str, int, str], float] = {}
    for scan in names:
        frame = next(open_source(REAL_SCANS / f"{scan}.npz"))
        for seed in range(3):
            kinds: dict[str, list[tuple[str, tuple[float, ...]]]] = {}
            for _ in range(args.repeats):
                for mode, params in (("on", on), ("off", off)):
                    start = time.process_time()
                    result = Perception(params, seed=seed).process(frame)
                    ms = 1000 * (time.process_time() - start)
                    key = (scan, seed, mode)
                    least[key] = min(least.get(key, float("inf")), ms)
                    kinds[mode] = [
                        (p.kind.value, tuple(round(v, 3) for v in p.centre))
                        for p in result.primitives
                    ]
            if len(kinds["off"]) != len(kinds["on"]):
                print(f"  {scan} seed {seed}: {len(kinds['off'])} -> {len(kinds['on'])} primitives")
                continue
            for (was, centre), (now, _) in zip(kinds["off"], kinds["on"], strict=True):
                if was != now:
                    print(f"  {scan} seed {seed}: {was} -> {now} at {centre}")
    per_scan = {
        mode: [float(np.median([least[(s, k, mode)] for k in range(3)])) for s in names]
        for mode in ("on", "off")
    }
    gaps = [a - b for a, b in zip(per_scan["on"], per_scan["off"], strict=True)]
    print(
        f"{len(names)} Kinect scans, seeds 0-2: median frame {np.median(per_scan['on']):.0f} ms "
        f"with the {args.step} step, {np.median(per_scan['off']):.0f} ms without; per scan "
        f"{np.median(gaps):.1f} ms more (median), {min(gaps):.1f} to {max(gaps):.1f} ms"
    )


if __name__ == "__main__":
    main()
