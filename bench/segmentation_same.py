"""Whether two checkouts segment alike: every cluster's points, voxels, colours and noise.

Segments the real scans of ``tests/data/real_scans`` tuned on (no pose: gravity from the
scene; the held-out ones, ``"held_out": true`` in truth.json, are never loaded, so that speed
work never sees them) and three frames of each of ``bench/perception.py``'s simulated
conditions, plus one of them as an unorganised cloud, with seeds 0 and 1, in this checkout and
in ``--against``'s (a subprocess with the same interpreter), and prints each case that differs:
the survey's counts (kept points, voxels, planes), the reason, the supports, and every cluster
array, compared exactly (``--tolerance`` allows a difference in the coordinates). For speed work
that must not change the output. Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/segmentation_same.py --against /path/to/main
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

SEEDS = (0, 1)
SIMULATED_PER_CONDITION = 3


def frames() -> list[tuple[str, Any, bool]]:
    """The cases: (name, frame, whether up comes from the scene)."""
    sys.path.insert(0, str(Path("bench").resolve()))
    import perception as bench  # bench/perception.py: its conditions and camera

    from shapes import Frame, open_source

    root = Path("tests/data/real_scans")
    truth = json.loads((root / "truth.json").read_text())
    out = []
    for scan, measured in bench.REAL_TRUTH.items():
        if not truth[measured].get("held_out"):
            out.append((scan, next(open_source(root / f"{scan}.npz")), True))
    for cond in bench.CONDITIONS:
        for i in range(SIMULATED_PER_CONDITION):
            rng = np.random.default_rng([20261123, i, len(cond.name)])
            shot = cond.camera.shoot(cond.scene(rng), rng, cond.sensor, cond.room)
            out.append((f"{cond.name} #{i}", shot.frame, False))
    last = out[-1][1]
    out.append(("unorganised", Frame(last.world_points()), False))
    return out


def segmentations() -> dict[tuple[str, int], dict[str, Any]]:
    """What this checkout's segmentation gives for every case."""
    import shapes.segment  # noqa: F401  (the module object, not the package's re-exports)
    from shapes.gravity import gravity_from_survey

    seg = sys.modules["shapes.segment"]
    params = seg.SegmentationParams()
    out = {}
    for name, frame, from_scene in frames():
        for seed in SEEDS:
            surveyed = seg.survey(frame, params, seed)
            posed = frame
            if from_scene:
                up = gravity_from_survey(frame, surveyed, params)
                posed = frame.with_pose(np.eye(4) if up is None else up.world_from_sensor)
            found = seg.segment(posed, params, seed, surveyed=surveyed)
            out[(name, seed)] = {
                "survey": (
                    len(surveyed.points),
                    len(surveyed.voxels),
                    [int(p.inliers.sum()) for p in surveyed.planes],
                ),
                "reason": found.reason,
                "supports": [(s.normal, s.offset) for s in found.supports],
                "clusters": [(c.points, c.voxels, c.colours, c.noise_m) for c in found.clusters],
            }
    return out


def differences(ours: Any, theirs: Any, tolerance: float) -> list[str]:
    """What differs between two cases' results, one phrase each."""
    found = []
    for key in ("survey", "reason"):
        if ours[key] != theirs[key]:
            found.append(f"{key} {ours[key]} against {theirs[key]}")
    if len(ours["supports"]) != len(theirs["supports"]):
        found.append(f"{len(ours['supports'])} supports against {len(theirs['supports'])}")
    else:
        for (n1, d1), (n2, d2) in zip(ours["supports"], theirs["supports"], strict=True):
            if np.abs(np.subtract(n1, n2)).max() > tolerance or abs(d1 - d2) > tolerance:
                found.append("a support's plane")
    if len(ours["clusters"]) != len(theirs["clusters"]):
        return [*found, f"{len(ours['clusters'])} clusters against {len(theirs['clusters'])}"]
    for k, (a, b) in enumerate(zip(ours["clusters"], theirs["clusters"], strict=True)):
        for what, x, y in zip(("points", "voxels", "colours"), a[:3], b[:3], strict=True):
            if (x is None) != (y is None) or (x is not None and x.shape != y.shape):
                found.append(f"cluster {k}'s {what}: other shapes")
            elif x is not None and x.size and np.abs(x - y).max() > tolerance:
                found.append(f"cluster {k}'s {what} by up to {np.abs(x - y).max():.3g}")
        if abs(a[3] - b[3]) > tolerance:
            found.append(f"cluster {k}'s noise")
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--against", type=Path, help="the other checkout")
    parser.add_argument("--tolerance", type=float, default=0.0, help="metres (0: exact)")
    parser.add_argument("--write", type=Path, help=argparse.SUPPRESS)  # the subprocess's output
    args = parser.parse_args()
    if args.write is not None:
        args.write.write_bytes(pickle.dumps(segmentations()))
        return
    if args.against is None:
        parser.error("--against: expected the other checkout's directory")
    ours = segmentations()
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / "theirs.pickle"
        env = {**os.environ, "PYTHONPATH": str(args.against.resolve())}
        subprocess.run(
            [sys.executable, str(Path(__file__).resolve()), "--write", str(out)],
            cwd=args.against,
            env=env,
            check=True,
        )
        theirs = pickle.loads(out.read_bytes())
    differing = 0
    for case, result in ours.items():
        found = differences(result, theirs[case], args.tolerance)
        if found:
            differing += 1
            print(f"{case[0]} (seed {case[1]}): " + "; ".join(found))
    clusters = sum(len(r["clusters"]) for r in ours.values())
    print(f"{len(ours)} cases, {clusters} clusters: {differing} case(s) differ from {args.against}")
    sys.exit(1 if differing else 0)


if __name__ == "__main__":
    main()
