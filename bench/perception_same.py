"""Whether two checkouts perceive alike: every frame's primitives, supports, ids and events.

Runs the whole chain (:class:`shapes.Perception`) on the real scans tuned on (the held-out
ones, ``"held_out": true`` in truth.json, are never loaded) with no pose, seeds 0 and 1 (or
``--seeds``), and on
three frames of each of ``bench/perception.py``'s simulated conditions, each condition's
frames through one tracker (so ids and events are compared too), in this checkout and in
``--against``'s (a subprocess with the same interpreter), and prints each case that differs.
Everything is compared exactly (pickled bytes): for speed work that must not change the
output. Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_same.py --against /path/to/main
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other on a pinned process.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import pickle  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

SEEDS = 2
SIMULATED_PER_CONDITION = 3
FIELDS = ("support", "primitives", "events", "centroids", "reason", "gravity", "supports")


def _outcome(result: Any) -> dict[str, bytes]:
    """One frame's result, field by field, as bytes that are equal only if the values are."""
    out = {name: pickle.dumps(getattr(result, name)) for name in FIELDS}
    out["world_from_sensor"] = np.asarray(result.world_from_sensor).tobytes()
    return out


def perceptions(seeds: int = SEEDS) -> dict[str, dict[str, bytes]]:
    """What this checkout's chain gives for every case, on seeds ``0 .. seeds - 1``."""
    sys.path.insert(0, str(Path("bench").resolve()))
    import perception as bench  # bench/perception.py: its scans, conditions and camera

    from shapes import Perception, PerceptionParams, open_source

    root = Path("tests/data/real_scans")
    truth = json.loads((root / "truth.json").read_text())
    out = {}
    for scan, measured in bench.REAL_TRUTH.items():
        if truth[measured].get("held_out"):
            continue
        frame = next(open_source(root / f"{scan}.npz"))
        for seed in range(seeds):
            result = Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
            out[f"{scan} seed {seed}"] = _outcome(result)
    for cond in bench.CONDITIONS:
        for seed in range(seeds):
            tracker = Perception(seed=seed)
            for i in range(SIMULATED_PER_CONDITION):
                rng = np.random.default_rng([20261123, i, len(cond.name)])
                shot = cond.camera.shoot(cond.scene(rng), rng, cond.sensor, cond.room)
                out[f"{cond.name} #{i} seed {seed}"] = _outcome(tracker.process(shot.frame))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--against", type=Path, required=True, help="the other checkout")
    parser.add_argument(
        "--seeds", type=int, default=SEEDS, help=f"seeds 0 .. SEEDS - 1 of each case ({SEEDS})"
    )
    parser.add_argument("--dump", type=Path, help=argparse.SUPPRESS)  # the subprocess's output
    args = parser.parse_args()
    if args.seeds < 1:
        parser.error(f"--seeds: expected a positive count, got {args.seeds}")
    if args.dump is not None:
        args.dump.write_bytes(pickle.dumps(perceptions(args.seeds)))
        return
    ours = perceptions(args.seeds)
    with tempfile.TemporaryDirectory() as tmp:
        dump = Path(tmp) / "theirs.pickle"
        env = {**os.environ, "PYTHONPATH": str(args.against.resolve())}
        script = Path(__file__).resolve()
        subprocess.run(
            [
                sys.executable,
                str(script),
                "--against",
                ".",
                "--seeds",
                str(args.seeds),
                "--dump",
                str(dump),
            ],
            cwd=args.against,
            env=env,
            check=True,
        )
        theirs = pickle.loads(dump.read_bytes())
    differ = 0
    for case in sorted(set(ours) | set(theirs)):
        a, b = ours.get(case), theirs.get(case)
        if a is None or b is None:
            print(f"{case}: only in {'theirs' if a is None else 'ours'}")
            differ += 1
            continue
        fields = [name for name in a if a[name] != b.get(name)]
        if fields:
            print(f"{case}: differs in {', '.join(fields)}")
            differ += 1
    print(f"{len(ours)} cases here, {len(theirs)} there; {differ} differ")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
