"""Which real scans change with the Perception's seed, seed by seed.

For every real scan tuned on (the held-out and reserved ones, ``"held_out": true`` in
truth.json, are never loaded) and each of the seeds 0 to ``--seeds`` - 1, the chain with no
pose (``Perception(PerceptionParams(gravity_from_scene=True), seed=k)``: the seed is the plane
search's, the survey's, and the fits') is run once and each measured object is matched as
``bench/perception.py`` matches it (a primitive whose centroid lies within 8 cm is one of its
parts). A line per scan and seed: each object's parts, centre error and kind, and the stray
primitives ("others"). ``--changing`` prints only the scans whose line differs between seeds.

Run the same script on another checkout by putting it first on ``PYTHONPATH`` (the code is the
checkout's, the data and the matching this script's)::

    PYTHONPATH=. .venv/bin/python bench/perception_seeds.py --seeds 8
    PYTHONPATH=/path/to/main .venv/bin/python bench/perception_seeds.py --seeds 8
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

bench = load_script(Path(__file__).with_name("perception.py"), "perception_bench")


def row(scan: str, truth: dict, seed: int) -> str:
    """The objects and strays of one scan on one seed, as ``bench/perception.py`` counts
    them (kinds abbreviated: Plane P, Cylinder Cy, Cone Co, Sphere S)."""
    frame = next(open_source(bench.REAL_SCANS / f"{scan}.npz"))
    result = Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    back = np.linalg.inv(result.world_from_sensor)
    seen = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
    used: set[int] = set()
    cells = []
    for label, item in truth.items():
        if label in bench.NOT_OBJECTS:
            continue
        centre = np.asarray(item["centre"])
        near = [k for k, c in enumerate(seen) if np.linalg.norm(c - centre) < bench.REAL_NEAR_M]
        used.update(near)
        if not near:
            cells.append(f"{label} -")
            continue
        best = min(near, key=lambda k: float(np.linalg.norm(seen[k] - centre)))
        prim = result.primitives[best]
        kind = {"Plane": "P", "Cylinder": "Cy", "Cone": "Co", "Sphere": "S"}[prim.kind.value]
        point = seen[best]
        if "radius_m" in item:
            point = back[:3, :3] @ np.asarray(prim.centre) + back[:3, 3]
        err = 100 * float(np.linalg.norm(point - centre))
        cells.append(f"{label} {len(near)}/{err:.1f}/{kind}")
    return f"{'; '.join(cells)} | others {len(result.primitives) - len(used)}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8, help="seeds 0 .. N-1 (default 8)")
    parser.add_argument("--only", nargs="*", default=None, help="these scans only")
    parser.add_argument("--changing", action="store_true", help="only scans that change")
    args = parser.parse_args()
    truth = json.loads((bench.REAL_SCANS / "truth.json").read_text())
    for scan, measured in bench.REAL_TRUTH.items():
        if truth[measured].get("held_out") or truth[measured].get("reserved"):
            continue
        if args.only and scan not in args.only:
            continue
        lines = [row(scan, truth[measured], seed) for seed in range(args.seeds)]
        if args.changing and len(set(lines)) == 1:
            print(f"{scan}: the same on every seed: {lines[0]}", flush=True)
            continue
        print(scan, flush=True)
        for seed, line in enumerate(lines):
            print(f"  seed {seed}: {line}", flush=True)


if __name__ == "__main__":
    main()
