"""What the fits cost on a Kinect frame: each cluster's :func:`shapes.fit_cluster`, timed in
one process against another checkout's (``--against``), with its parts (each model's RANSAC,
the hypotheses it drew, the refinements).

Each tuned-on Kinect scan of ``tests/data/real_scans`` (``kinect`` in the name; the held-out and
reserved ones are never loaded) goes through this checkout's chain (no pose, gravity from the
scene) on seeds 0-2; every call of ``fit_cluster`` is recorded (its points, support, parameters,
generator and viewpoint). The recorded calls are then replayed ``--repeats`` times, this
checkout's ``fit_cluster`` and ``--against``'s alternately, in this process (the other
checkout's ``shapes`` package is imported under another name); each call keeps its least CPU
(``time.process_time``). Printed: the fits' CPU per frame (median over the scans of the sum over
a frame's clusters) for each checkout and their ratio, how many replays differ (a fit's kind,
parameters or costs not bit-identical), and each checkout's breakdown in one more replay: each
model's RANSAC (calls, hypotheses drawn, CPU) and the refinements' CPU, summed over all clusters.
A frame with no cluster (no fit) is not counted.

Run from the repository root::

    PYTHONPATH=. nice -n 10 .venv/bin/python bench/perception_fit_cost.py --against ../base
"""

import os

# One core: BLAS threads would only spin against each other on a loaded machine.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import collections  # noqa: E402
import copy  # noqa: E402
import importlib  # noqa: E402
import pickle  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

Call = dict[str, Any]


def _other_fit_cluster(root: Path) -> Callable[..., Any]:
    """``fit_cluster`` of the checkout at ``root``, imported as ``other_shapes``: its modules
    keep their references to one another, this checkout's ``shapes`` is imported afresh."""
    mine = {k: v for k, v in sys.modules.items() if k == "shapes" or k.startswith("shapes.")}
    for k in mine:
        del sys.modules[k]
    sys.path.insert(0, str(root.resolve()))
    try:
        module = importlib.import_module("shapes.fit.select")
    finally:
        sys.path.pop(0)
    theirs = {k: v for k, v in sys.modules.items() if k == "shapes" or k.startswith("shapes.")}
    for k, v in theirs.items():
        del sys.modules[k]
        sys.modules["other_" + k] = v
    sys.modules.update(mine)
    return module.fit_cluster  # type: ignore[no-any-return]


def _recorded_calls() -> list[Call]:
    """Every ``fit_cluster`` call of this checkout's chain on the Kinect scans, seeds 0-2."""
    sys.path.insert(0, str(Path("bench").resolve()))
    from perception import REAL_SCANS, loadable_scans

    import shapes.pipeline
    from shapes import Perception, PerceptionParams, open_source

    names = [scan for scan, _ in loadable_scans() if "kinect" in scan]
    calls: list[Call] = []
    real = shapes.pipeline.fit_cluster
    frame_key = [""]

    def recording(points: Any, **kw: Any) -> Any:
        # A copy of the whole generator: its seed sequence counts the spawns too.
        rng = copy.deepcopy(kw["rng"])
        calls.append({"frame": frame_key[0], "points": points.copy(), **kw, "rng": rng})
        return real(points, **kw)

    shapes.pipeline.fit_cluster = recording  # type: ignore[assignment]
    try:
        for scan in names:
            frame = next(open_source(REAL_SCANS / f"{scan}.npz"))
            for seed in range(3):
                frame_key[0] = f"{scan} seed {seed}"
                Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    finally:
        shapes.pipeline.fit_cluster = real
    return calls


def _run(fit: Callable[..., Any], call: Call) -> tuple[float, bytes]:
    rng = copy.deepcopy(call["rng"])
    kw = {k: call[k] for k in ("support", "params", "viewpoint")}
    start = time.process_time()
    out = fit(call["points"], rng=rng, **kw)
    ms = 1000 * (time.process_time() - start)
    if out is None:
        return ms, b"none"
    # Plain values: each checkout's ShapeKind is a class of its own.
    fields = {k: getattr(v, "value", v) for k, v in out.primitive.__dict__.items()}
    costs = {k.value: v for k, v in out.costs.items()}
    counts = {k.value: v for k, v in out.pitt_counts.items()}
    return ms, pickle.dumps((fields, costs, counts))


def _breakdown(select: Any, label: str, calls: list[Call]) -> None:
    """Each model's RANSAC and the refinements, summed over every recorded call, in the module
    ``select`` (a checkout's ``shapes.fit.select``)."""

    cpu: dict[str, float] = collections.defaultdict(float)
    runs: dict[str, int] = collections.defaultdict(int)
    drawn: dict[str, int] = collections.defaultdict(int)
    real_ransac, real_refine = select.ransac, select.refine_if_better

    def ransac(model: Any, *a: Any, **kw: Any) -> Any:
        start = time.process_time()
        res = real_ransac(model, *a, **kw)
        cpu[model.name] += time.process_time() - start
        runs[model.name] += 1
        drawn[model.name] += 0 if res is None else res.hypotheses
        return res

    def refine(model: Any, *a: Any, **kw: Any) -> Any:
        start = time.process_time()
        res = real_refine(model, *a, **kw)
        cpu["refine " + model.name] += time.process_time() - start
        runs["refine " + model.name] += 1
        return res

    select.ransac, select.refine_if_better = ransac, refine  # type: ignore[assignment]
    total = 0.0
    try:
        for call in calls:
            total += _run(select.fit_cluster, call)[0]
    finally:
        select.ransac, select.refine_if_better = real_ransac, real_refine
    frames = len({c["frame"] for c in calls})
    print(f"  {label}, one replay: {total / frames:.1f} ms of fits a frame ({frames} frames)")
    for name in sorted(cpu, key=lambda k: -cpu[k]):
        print(
            f"    {name:22s} {runs[name]:5d} calls {drawn[name]:8d} hypotheses "
            f"{1000 * cpu[name] / frames:6.1f} ms a frame ({100000 * cpu[name] / total:4.1f} %)"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--against", type=Path, required=True, help="the other checkout")
    parser.add_argument("--repeats", type=int, default=3, help="replays of each call (3)")
    args = parser.parse_args()
    theirs = _other_fit_cluster(args.against)
    from shapes.fit.select import fit_cluster as ours

    calls = _recorded_calls()
    least = {"ours": [np.inf] * len(calls), "theirs": [np.inf] * len(calls)}
    differ = 0
    for _ in range(args.repeats):
        for i, call in enumerate(calls):
            a_ms, a_out = _run(ours, call)
            b_ms, b_out = _run(theirs, call)
            least["ours"][i] = min(least["ours"][i], a_ms)
            least["theirs"][i] = min(least["theirs"][i], b_ms)
            differ += a_out != b_out
    frames: dict[str, dict[str, float]] = collections.defaultdict(lambda: {"ours": 0, "theirs": 0})
    for i, call in enumerate(calls):
        for side in least:
            frames[call["frame"]][side] += least[side][i]
    ours_ms = float(np.median([f["ours"] for f in frames.values()]))
    theirs_ms = float(np.median([f["theirs"] for f in frames.values()]))
    ratio = float(np.median([f["ours"] / f["theirs"] for f in frames.values()]))
    print(
        f"fit_cluster on {len(frames)} Kinect frames ({len(calls)} clusters), least of "
        f"{args.repeats}: this checkout {ours_ms:.1f} ms a frame, {args.against} {theirs_ms:.1f} "
        f"ms (medians over frames); median per-frame ratio {ratio:.3f}; "
        f"{differ} of {args.repeats * len(calls)} replays differ"
    )
    _breakdown(sys.modules["shapes.fit.select"], "this checkout", calls)
    _breakdown(sys.modules["other_shapes.fit.select"], str(args.against), calls)


if __name__ == "__main__":
    main()
