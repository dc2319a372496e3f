"""One hash per frame and seed of what perception gives, to tell whether a change moved any bit.

For every real scan tuned on (never a held-out or reserved one: ``"held_out": true`` in
truth.json) on seeds 0 to 2, and the first simulated scenes of a few of ``bench/perception.py``'s
conditions, it hashes, to the last bit: the survey (points, voxels, each plane's normal, offset
and voxels), the segmentation (its supports, every cluster's points, voxels, colours, noise and
pixels, its reason) and ``shapes.Perception``'s frame result (every primitive's and support's
fields, the centroids, the pose, the reason). A line a case, then one hash of all the lines::

    PYTHONPATH=$PWD .venv/bin/python bench/perception_fingerprint.py > /tmp/ours.txt
    PYTHONPATH=/path/to/base .venv/bin/python bench/perception_fingerprint.py > /tmp/base.txt
    diff /tmp/base.txt /tmp/ours.txt

Run each checkout's copy of the script, or this one against both: it imports only
``shapes``'s public names and ``bench/perception.py``'s scenes.
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import enum  # noqa: E402
import hashlib  # noqa: E402
import json  # noqa: E402
import struct  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))

SEEDS = (0, 1, 2)
CONDITIONS = ("clean", "touching (0-1 cm)", "noise 3 mm", "floor+wall", "3 mm, 1.7 m right")
SCENES_PER_CONDITION = 2


def feed(digest: Any, value: Any) -> None:
    """Feed ``value`` to ``digest`` bit for bit: arrays by dtype, shape and bytes, floats by
    their IEEE bits, dataclasses field by field, containers item by item."""
    if value is None or isinstance(value, bool | int | str):
        digest.update(f"{type(value).__name__}:{value!r};".encode())
    elif isinstance(value, float):
        digest.update(b"f" + struct.pack("<d", value))
    elif isinstance(value, enum.Enum):
        feed(digest, value.value)
    elif isinstance(value, np.ndarray | np.generic):
        array = np.ascontiguousarray(value)
        digest.update(f"{array.dtype}{array.shape}".encode())
        digest.update(array.tobytes())
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        digest.update(type(value).__name__.encode())
        for field in dataclasses.fields(value):
            digest.update(field.name.encode())
            feed(digest, getattr(value, field.name))
    elif isinstance(value, tuple | list):
        digest.update(f"[{len(value)}".encode())
        for item in value:
            feed(digest, item)
        digest.update(b"]")
    elif isinstance(value, dict):
        for key in sorted(value):
            feed(digest, key)
            feed(digest, value[key])
    else:
        raise TypeError(f"cannot hash a {type(value).__name__}")


def hashed(value: Any) -> str:
    digest = hashlib.sha256()
    feed(digest, value)
    return digest.hexdigest()[:16]


def frames() -> list[tuple[str, Any]]:
    """The tuned-on real scans and the simulated scenes, by name."""
    import perception as bench  # bench/perception.py: its scan list and scenes

    from shapes import open_source

    truth = json.loads((bench.REAL_SCANS / "truth.json").read_text())
    out = []
    for scan, measured in bench.REAL_TRUTH.items():
        gt = truth[measured]
        if gt.get("held_out") or gt.get("reserved"):
            continue  # never loaded
        out.append((scan, next(open_source(bench.REAL_SCANS / f"{scan}.npz"))))
    for cond in bench.CONDITIONS:
        if cond.name not in CONDITIONS:
            continue
        for i in range(SCENES_PER_CONDITION):
            rng = np.random.default_rng([20261123, i, len(cond.name)])
            shot = cond.camera.shoot(cond.scene(rng), rng, cond.sensor, cond.room)
            out.append((f"{cond.name} #{i}", shot.frame))
    return out


def fingerprints(name: str, frame: Any, seed: int, real: bool) -> tuple[str, str, str]:
    """The hashes of the survey, the segmentation and the frame result of one case."""
    from shapes import Perception, PerceptionParams
    from shapes.gravity import gravity_from_survey
    from shapes.segment import SegmentationParams, segment, survey

    params = SegmentationParams()
    surveyed = survey(frame, params, seed)
    posed = frame
    if real:
        up = gravity_from_survey(frame, surveyed, params)
        posed = frame.with_pose(np.eye(4) if up is None else up.world_from_sensor)
    found = segment(posed, params, seed, surveyed=surveyed)
    planes = [(p.normal, p.offset, p.inliers) for p in surveyed.planes]
    result = Perception(PerceptionParams(gravity_from_scene=real), seed=seed).process(frame)
    return (
        hashed((surveyed.keep, surveyed.voxels, surveyed.voxel_of, planes)),
        hashed(found),
        hashed(result),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=len(SEEDS), help="seeds 0 .. N-1")
    args = parser.parse_args()
    every = hashlib.sha256()
    for name, frame in frames():
        real = "#" not in name
        for seed in range(args.seeds):
            line = f"{name:<28} seed {seed}  " + "  ".join(fingerprints(name, frame, seed, real))
            print(line, flush=True)
            every.update(line.encode())
    print(f"all: {every.hexdigest()[:16]}")


if __name__ == "__main__":
    main()
