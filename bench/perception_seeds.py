"""Which real scans change with the Perception's seed, seed by seed.

For every real scan tuned on (the held-out and reserved ones, ``"held_out": true`` in
truth.json, are never loaded) and each of the seeds 0 to ``--seeds`` - 1, the chain with no
pose (``Perception(PerceptionParams(gravity_from_scene=True), seed=k)``: the seed is the plane
search's, the survey's, and the fits') is run once and each measured object is matched by
``bench/perception.py``'s own matching (each primitive a part of the object whose centroid is
nearest, within 8 cm, or a stray). A line per scan and seed: each object's parts, centre error
and kind, and the stray primitives ("others"). ``--changing`` prints only the scans whose line
differs between seeds.

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

from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

bench = load_script(Path(__file__).with_name("perception.py"), "perception_bench")


def row(scan: str, truth: dict, seed: int) -> str:
    """The objects and strays of one scan on one seed, matched and written as
    ``bench/perception.py`` writes a scan's row (its ``_objects_row``)."""
    frame = next(open_source(bench.REAL_SCANS / f"{scan}.npz"))
    result = Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    cells, tally = bench._objects_row(result, truth)
    return f"{'; '.join(cells)} | others {tally['strays']}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8, help="seeds 0 .. N-1 (default 8)")
    parser.add_argument("--only", nargs="*", default=None, help="these scans only")
    parser.add_argument("--changing", action="store_true", help="only scans that change")
    args = parser.parse_args()
    truth = json.loads((bench.REAL_SCANS / "truth.json").read_text())
    for scan, measured in bench.loadable_scans():
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
