"""Where a real Kinect frame's CPU goes: the chain's stages timed apart, beside a baseline.

For each of the five Kinect scans of ``tests/data/real_scans`` (those of
``bench/perception.py``'s Kinect figure; no pose: gravity from the scene), the CPU time
(``time.process_time``) of the whole frame and of its stages: the survey (artefacts, stride,
voxel grid, planes; shared by gravity and segmentation), gravity from it, the rest of
segmentation, and the fits (``fit_cluster``, every cluster), each the median over ``--seeds``
seeds of the chain. "before fits" is survey + gravity + segmentation: the CPU a frame costs
before any primitive is fitted. Then the median over the scans, and what one fit costs on a
cluster of 30, 300 and 3,000 points (the fit samples at most 300, so the smallest shows the
fit's fixed cost: its RANSAC batches, refinements and numpy calls).

``--tuned`` measures every real scan tuned on instead (the held-out ones, ``"held_out": true``
in truth.json, are never loaded), with the number of clusters fitted in each frame: the TUM
desks and the cluttered floors show what a frame with many clusters costs, and the median of
the nine Kinect scans (``kinect`` in the name) is the one ``bench/perception.py`` prints.

``--against DIR`` runs the same measurement on another checkout (e.g. the main branch) in a
subprocess right after this one, with the same interpreter, so that the two sets of figures
come from the same minutes; their ratio survives the machine's load, the milliseconds do not.

Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_stages.py --against /path/to/main
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other on a pinned process.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import re  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

SCANS = (
    "bottles_kinect",
    "laptop_box_kinect_0",
    "laptop_box_kinect_1",
    "laptop_box_kinect_2",
    "office_kinect",
)
STAGES = ("survey", "gravity_from_survey", "segment", "fit_cluster")
WIDTHS = (7, 8, 9, 9, 13, 7)
HEADER = f"{'scan':<22}{'frame':>7}{'survey':>8}{'gravity':>9}{'segment':>9}{'before fits':>13}"


def tuned_scans(root: Path) -> tuple[str, ...]:
    """The real scans tuned on, by name: each with its own entry in truth.json or, for a
    later frame of a static scene (``laptop_box_kinect_2``), its first frame's (``_0``), not
    marked held out. A scan with neither is left out, as a held-out one is."""
    truth = json.loads((root / "truth.json").read_text())
    scans = []
    for path in sorted(root.glob("*.npz")):
        key = path.stem if path.stem in truth else re.sub(r"_\d+$", "_0", path.stem)
        if key in truth and not truth[key].get("held_out"):
            scans.append(path.stem)
    return tuple(scans)


def measure(seeds: int, tuned: bool = False) -> None:
    """Print the stage table for the checkout on ``sys.path`` (``tuned``: every scan tuned on,
    with the clusters fitted a frame)."""
    import shapes.pipeline  # noqa: F401  (the module object, not the package's re-exports)
    from shapes import Perception, PerceptionParams, open_source

    pipeline = sys.modules["shapes.pipeline"]
    spent: dict[str, float] = {}
    calls: dict[str, int] = {}

    def timed(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def run(*args: Any, **kwargs: Any) -> Any:
            start = time.process_time()
            try:
                return fn(*args, **kwargs)
            finally:
                spent[name] = spent.get(name, 0.0) + time.process_time() - start
                calls[name] = calls.get(name, 0) + 1

        return run

    for name in STAGES:
        setattr(pipeline, name, timed(name, getattr(pipeline, name)))
    root = Path("tests/data/real_scans")
    params = PerceptionParams(gravity_from_scene=True)
    scans = tuned_scans(root) if tuned else SCANS
    frames = {scan: next(open_source(root / f"{scan}.npz")) for scan in scans}
    Perception(params, seed=0).process(frames[scans[0]])  # warm: lazy imports, caches
    print(f"{Path.cwd()}: CPU ms per frame, median of {seeds} seeds, load {os.getloadavg()[0]:.1f}")
    print(HEADER + f"{'fits':>7}{'primitives':>12}" + (f"{'fitted':>8}" if tuned else ""))
    rows, kinect = [], []
    for scan, frame in frames.items():
        runs = []
        for seed in range(seeds):
            spent.clear()
            calls.clear()
            start = time.process_time()
            result = Perception(params, seed=seed).process(frame)
            total = time.process_time() - start
            before = sum(spent.get(n, 0.0) for n in STAGES[:3])
            runs.append(
                [
                    total,
                    *(spent.get(n, 0.0) for n in STAGES[:3]),
                    before,
                    spent.get("fit_cluster", 0.0),
                ]
            )
        row = 1000 * np.median(np.array(runs), axis=0)
        rows.append(row)
        if "kinect" in scan:
            kinect.append(row[0])
        print(
            f"{scan:<22}"
            + "".join(f"{v:>{w}.0f}" for v, w in zip(row, WIDTHS, strict=True))
            + f"{len(result.primitives):>12}"
            + (f"{calls.get('fit_cluster', 0):>8}" if tuned else "")
        )
    med = np.median(np.array(rows), axis=0)
    print(f"{'median':<22}" + "".join(f"{v:>{w}.0f}" for v, w in zip(med, WIDTHS, strict=True)))
    if tuned:
        print(f"frame, median of the {len(kinect)} Kinect scans: {np.median(kinect):.0f} ms")
    print("one fit (fit_cluster), a standing cylinder of r 4 cm, 1 mm noise, median of 15 seeds:")
    print("  " + ", ".join(f"{n} points {fit_ms(n):.1f} ms" for n in (30, 300, 3000)))


def fit_ms(points: int) -> float:
    """CPU ms of :func:`shapes.fit.fit_cluster` on a cluster of ``points`` points of a standing
    cylinder's visible side (its fixed cost shows on the smallest)."""
    from shapes.fit import fit_cluster
    from shapes.types import SupportPlane

    rng = np.random.default_rng(0)
    angle, height = rng.uniform(-1.2, 1.2, points), rng.uniform(0.0, 0.1, points)
    side = np.column_stack((0.04 * np.sin(angle), -0.04 * np.cos(angle), height))
    side += rng.normal(scale=0.001, size=side.shape)
    support = SupportPlane((0.0, 0.0, 1.0), 0.0)
    spent = []
    for seed in range(15):
        start = time.process_time()
        fit_cluster(side, support=support, rng=np.random.default_rng(seed))
        spent.append(time.process_time() - start)
    return 1000 * float(np.median(spent))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=5, help="seeds of the chain per scan (5)")
    parser.add_argument("--against", type=Path, help="a baseline checkout, measured after this")
    parser.add_argument(
        "--tuned", action="store_true", help="every real scan tuned on, not the five Kinect ones"
    )
    args = parser.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    measure(args.seeds, args.tuned)
    if args.against is not None:
        env = {**os.environ, "PYTHONPATH": str(args.against.resolve())}
        script = Path(__file__).resolve()
        subprocess.run(
            [sys.executable, str(script), "--seeds", str(args.seeds)]
            + (["--tuned"] if args.tuned else []),
            cwd=args.against,
            env=env,
            check=True,
        )


if __name__ == "__main__":
    main()
