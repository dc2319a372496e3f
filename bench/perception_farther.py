"""Why an object found as one primitive lies more than 3 cm off: its cluster's points taken apart.

For every real scan tuned on (the held-out ones, ``"held_out": true`` in truth.json, are never
loaded) and each of ``--seeds`` seeds of the chain (the bench's run), each object the bench
counts "one primitive farther" (``bench/perception.py``'s ``_objects_row``: the primitive's
cluster centroid against the measured visible centroid; a round object's primitive centre
against its measured axis centre) is split into what moves its centre:

- ``err``: the bench's figure (cm);
- ``kept``: how far the centroid of the object's own pixels (``measure.object_mask``, the ground
  truth's attribution) that the survey keeps lies from the measured centre: the survey's stride
  and cuts alone;
- ``own``: how far the centroid of the object's own points *in the cluster* lies from it: what
  the points the cluster lacks do;
- ``all``: the whole cluster's centroid (the bench's reading for an object that is not round):
  ``own`` moved by the points of something else;
- the shares: of the object's kept points in the cluster (``in``), and of the cluster's points
  that are not the object's (``extra``), with whose they are (another measured object, or
  ``unmeasured``) and their median height over the measured support;
- where the object's kept points that the cluster lacks went: into another primitive's cluster
  (the measured object the bench gives it to, or ``stray``), or into no primitive's cluster;
  then ``--trace`` prints ``bench/perception_missed.py``'s account of segmentation's steps.

Run from the repository root (a few minutes of CPU)::

    PYTHONPATH=. .venv/bin/python bench/perception_farther.py --seeds 3
    PYTHONPATH=. .venv/bin/python bench/perception_farther.py --scan desk_tum --trace
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from collections import Counter  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402

import shapes.segment.segmentation as seg_module  # noqa: E402
from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from shapes.segment.survey import survey  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

missed = load_script(Path(__file__).with_name("perception_missed.py"), "perception_missed_")
strays = load_script(Path(__file__).with_name("perception_strays.py"), "perception_strays_")
oracle = missed.oracle
bench = oracle.bench
measure = oracle.measure
SCANS = bench.REAL_SCANS


def run_watched(frame: Any, seed: int) -> tuple[Any, list[Any], Any]:
    """The bench's chain on ``frame`` with seed ``seed``: its result, the cluster of each of its
    primitives (in order), and the log of segmentation's steps (``perception_missed.Log``)."""
    log = missed.Log()
    saved = {name: getattr(seg_module, name) for name in missed.STEPS}
    try:
        for name, fn in saved.items():
            setattr(seg_module, name, log.wrap(name, fn))
        perception = Perception(PerceptionParams(gravity_from_scene=True), seed=seed)
        result, clusters = strays.clustered(perception, frame)
    finally:
        for name, fn in saved.items():
            setattr(seg_module, name, fn)
    return result, clusters, log


def _cm(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> float:
    return 100 * float(np.linalg.norm(a - b))


def taken_apart(
    scan: str,
    measured: str,
    frame: Any,
    seed: int,
    trace: bool,
    only: list[str] | None,
) -> list[str]:
    """Lines for each object of ``scan`` the bench counts "one, off" on ``seed``."""
    gt = json.loads((SCANS / "truth.json").read_text())[measured]
    pixels = oracle.object_pixels(scan, measured)
    normal, offset = oracle.measured_support(scan, measured)
    result, clusters, log = run_watched(frame, seed)
    back = np.linalg.inv(result.world_from_sensor)
    objects = {
        label: np.asarray(item["centre"])
        for label, item in gt.items()
        if label not in bench.NOT_OBJECTS
    }
    seen = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
    owner = bench._nearest_objects(seen, objects)
    keep = survey(frame, PerceptionParams(gravity_from_scene=True).segmentation, 0).keep
    assert frame.pixels is not None and frame.image_shape is not None
    kept_pixels = frame.pixels[keep]
    label_of = np.full(frame.image_shape[0] * frame.image_shape[1], "", dtype=object)
    for label, pix in pixels.items():
        label_of[pix] = label
    cluster_of = np.full(frame.image_shape[0] * frame.image_shape[1], -1)
    for k, cluster in enumerate(clusters):
        cluster_of[cluster.pixels] = k
    out = []
    for label, centre in objects.items():
        if only and label not in only:
            continue
        score = oracle.score_object(result, gt, label)
        if score.outcome != "one, off":
            continue
        near = [k for k, o in enumerate(owner) if o == label]
        best = min(near, key=lambda k: float(np.linalg.norm(seen[k] - centre)))
        cluster = clusters[best]
        points = cluster.points @ back[:3, :3].T + back[:3, 3]
        mine = label_of[cluster.pixels] == label
        own_kept = np.intersect1d(pixels[label], kept_pixels)
        image = measure.points_of(scan).reshape(-1, 3)
        kept_centre = image[own_kept].mean(axis=0)
        own_centre = points[mine].mean(axis=0) if mine.any() else np.full(3, np.nan)
        extra = points[~mine]
        whose = Counter(label_of[cluster.pixels[~mine]])
        whose_text = ", ".join(f"{name or 'unmeasured'} {n}" for name, n in whose.most_common(3))
        heights_text = "-"
        if len(extra):
            low, mid, high = (100 * np.percentile(extra @ normal + offset, q) for q in (5, 50, 95))
            heights_text = f"{whose_text}; heights {mid:.1f} cm (5-95 % {low:.1f}..{high:.1f})"
        lacking = np.setdiff1d(own_kept, cluster.pixels)
        went = Counter(
            "no primitive" if cluster_of[p] < 0 else owner[cluster_of[p]] or "stray"
            for p in lacking
        )
        went_text = ", ".join(f"{name} {n}" for name, n in went.most_common(4))
        prim = result.primitives[best]
        prim_centre = back[:3, :3] @ np.asarray(prim.centre) + back[:3, 3]
        out.append(
            f"{scan} / {label} / seed {seed}: {score.cell}; primitive centre"
            f" {_cm(prim_centre, centre):.1f} cm; kept {_cm(kept_centre, centre):.1f},"
            f" own {_cm(own_centre, centre):.1f}, all {_cm(points.mean(axis=0), centre):.1f} cm"
        )
        out.append(
            f"    in {mine.sum()}/{len(own_kept)} ({100 * mine.sum() / len(own_kept):.0f} %);"
            f" extra {len(extra)}/{len(points)} ({100 * len(extra) / len(points):.0f} %):"
            f" {heights_text}"
        )
        out.append(f"    lacking {len(lacking)}: {went_text or '-'}")
        delta_own = own_centre - centre
        delta_extra = points.mean(axis=0) - own_centre
        out.append(
            "    shift by lack (cm, sensor x y z): "
            + " ".join(f"{100 * v:+.1f}" for v in delta_own)
            + "; by extra: "
            + " ".join(f"{100 * v:+.1f}" for v in delta_extra)
        )
        if trace:
            for line in missed.trace(frame, result, log, pixels[label], centre):
                out.append(f"        {line}")
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--scan", action="append", help="only these scans (repeatable)")
    parser.add_argument("--object", action="append", help="only these objects (repeatable)")
    parser.add_argument("--trace", action="store_true", help="segmentation's steps too")
    args = parser.parse_args()
    for scan, measured in bench.loadable_scans():
        if args.scan and scan not in args.scan:
            continue
        frame = next(open_source(SCANS / f"{scan}.npz"))
        for seed in range(args.seeds):
            for line in taken_apart(scan, measured, frame, seed, args.trace, args.object):
                print(line, flush=True)


if __name__ == "__main__":
    main()
