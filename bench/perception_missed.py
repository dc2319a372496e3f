"""Where a missed object's points go: each step of segmentation that drops or absorbs them.

For every real scan tuned on (the held-out ones, ``"held_out": true`` in truth.json, are never
loaded unless named by ``--held-out-too``, which is for after the lead's one run of them) and
each of ``--seeds`` seeds of the chain (``Perception(PerceptionParams(gravity_from_scene=True),
seed=k)``, the bench's run), the objects the bench counts missed are
followed through :func:`shapes.segment.segment`, whose steps are wrapped for this run only:

- the object's points: its pixels as ``bench/perception_oracle.py``'s ``object_pixels`` takes
  them (``measure.object_mask``: the ground truth's own attribution), those the survey keeps,
  and its voxels (a voxel is the object's when most of its kept points are);
- the planes: how many of its voxels are inliers of a support, of another plane that holds them
  (a wall, a tilted plane) or of a plane judged a face of objects (those stay free); and of a
  support's, how many a horizontal plane folded into its band brought (how high that plane lies);
- the free voxels: how many are free, how many stand over a support (``over_supports``), and of
  those that do not, how many lie under the support's margin, over ``max_height_m``, outside the
  support's box, or over no support at all;
- the clusters: those of ``clusters_on`` holding the object's points (object points / all
  points, height range over the support), and each one's fate, in order: ``stands_within``,
  ``grown_upwards``, ``cut_by_limits`` (which limit), ``floats``, ``not_under``,
  ``not_under_support_edges``; then, for what is kept, where its centroid lies from the object's
  measured centre, and which measured object the bench gives it to.

Run from the repository root (a few minutes of CPU)::

    PYTHONPATH=. .venv/bin/python bench/perception_missed.py --seeds 3
    PYTHONPATH=. .venv/bin/python bench/perception_missed.py --scan office_kinect --all
    PYTHONPATH=. .venv/bin/python bench/perception_missed.py \
        --held-out-too tote_whisk_sr300_0 --scan tote_whisk_sr300_0 --all
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402

import shapes.segment.segmentation as seg_module  # noqa: E402
from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from shapes.segment.reach import reaching  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

oracle = load_script(
    Path(__file__).with_name("perception_oracle.py"), "perception_oracle_for_missed"
)
bench = oracle.bench
SCANS = bench.REAL_SCANS
STEPS = (
    "judge_planes",
    "free_voxels",
    "over_supports",
    "KeptPoints",
    "clusters_on",
    "stands_within",
    "grown_upwards",
    "cut_by_limits",
    "floats",
    "not_under",
    "not_under_support_edges",
)


class Log:
    """What the wrapped steps saw in one run of the chain."""

    def __init__(self) -> None:
        self.calls: list[tuple[str, tuple[Any, ...], Any]] = []

    def wrap(self, name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        def wrapped(*args: Any, **kwargs: Any) -> Any:
            out = fn(*args, **kwargs)
            self.calls.append((name, args, out))
            return out

        return wrapped

    def first(self, name: str) -> tuple[tuple[Any, ...], Any]:
        return next((a, o) for n, a, o in self.calls if n == name)


def run_logged(frame: Any, seed: int) -> tuple[Any, Log]:
    """The chain on ``frame`` with seed ``seed``, its segmentation steps logged."""
    log = Log()
    saved = {name: getattr(seg_module, name) for name in STEPS}
    try:
        for name, fn in saved.items():
            setattr(seg_module, name, log.wrap(name, fn))
        result = Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    finally:
        for name, fn in saved.items():
            setattr(seg_module, name, fn)
    return result, log


def _heights(cluster: Any) -> tuple[float, float]:
    h = cluster.support.signed_distance(cluster.voxels)
    return float(h.min()), float(h.max())


def trace(
    frame: Any, result: Any, log: Log, pix: npt.NDArray[np.intp], centre: np.ndarray
) -> list[str]:
    """Lines saying where the object's points (``pix``, flat pixels) went in this run."""
    out: list[str] = []
    kept = log.first("KeptPoints")[1]
    judged = log.first("judge_planes")[1]
    (_, voxels, _, _, params), free = log.first("free_voxels")
    over = log.first("over_supports")[1]
    own_point = np.isin(kept.pixels, pix)
    n_kept = int(own_point.sum())
    if n_kept == 0:
        return [f"{len(pix)} pixels, none kept by the survey"]
    total = np.bincount(kept.voxel_of, minlength=len(voxels))
    mine = np.bincount(kept.voxel_of[own_point], minlength=len(voxels))
    vox = np.flatnonzero(2 * mine > total)
    out.append(f"{len(pix)} pixels, {n_kept} kept, {len(vox)} voxels (most points the object's)")
    support_ids = {id(p): k for k, p in enumerate(judged.supports)}
    planes = []
    for j, p in enumerate(judged.planes):
        n = int(p.inliers[vox].sum())
        if n == 0:
            continue
        what = (
            f"support {support_ids[id(p)]}"
            if id(p) in support_ids
            else "face (free)"
            if id(p) in judged.faces
            else "horizontal plane"
            if p.horizontal
            else "tilted/wall plane"
        )
        normal = np.round(np.asarray(p.normal), 2)
        planes.append(f"plane {j} ({what}, n {normal.tolist()}, off {p.offset:.2f}): {n}")
    if planes:
        out.append("in planes: " + "; ".join(planes))
    folded = _folded_into_supports(log, judged, vox)
    if folded:
        out.append("of which folded into a support's band: " + "; ".join(folded))
    is_free = free[vox]
    owned = over.owner[vox]
    out.append(
        f"free {int(is_free.sum())} of {len(vox)}; over a support {int((owned >= 0).sum())}"
        + "".join(
            f" (support {k}: {int((owned == k).sum())})" for k in np.unique(owned[owned >= 0])
        )
    )
    unowned = vox[is_free & (owned < 0)]
    if len(unowned):
        reasons = []
        for k, support in enumerate(over.supports):
            h = support.signed_distance(voxels[unowned])
            lo, hi = over.boxes[k]
            inside = np.all((voxels[unowned, :2] >= lo) & (voxels[unowned, :2] <= hi), axis=1)
            reasons.append(
                f"support {k} (z {support.offset:+.2f}): under margin"
                f" {over.margins[k] * 100:.1f} cm"
                f" {int((h <= over.margins[k]).sum())}, over {params.max_height_m} m"
                f" {int((h >= params.max_height_m).sum())}, in band but outside box"
                f" {int(((h > over.margins[k]) & (h < params.max_height_m) & ~inside).sum())}"
                f" (heights {100 * h.min():.0f}..{100 * h.max():.0f} cm)"
            )
        out.append(f"free, over no support: {len(unowned)}: " + "; ".join(reasons))
    # The clusters holding the object's points, and each one's fate.
    fate: dict[int, list[str]] = {}
    made: list[Any] = []
    for name, args, res in log.calls:
        if name == "clusters_on":
            made += res[0]
        elif name in ("stands_within", "cut_by_limits", "floats"):
            fate.setdefault(id(args[0]), []).append(f"{name}={res}")
        elif name == "grown_upwards":
            before = {id(c) for c in args[0]}
            for c in res:
                if id(c) not in before:
                    made.append(c)
                    fate.setdefault(id(c), []).append("grown upwards (new)")
        elif name == "not_under":
            found, parts = args[0], args[1]
            kept_ids = {id(c) for c in res}
            for c in found:
                if id(c) not in kept_ids and not any(c is p for p in parts):
                    fate.setdefault(id(c), []).append("under a dropped part")
        elif name == "not_under_support_edges":
            before_ids = {id(c) for group in args[0] for c in group}
            after_ids = {id(c) for group in res for c in group}
            for i in before_ids - after_ids:
                fate.setdefault(i, []).append("under a support's edge")
    final_ids = {id(c) for group in log.first("not_under_support_edges")[1] for c in group}
    in_clusters = 0
    back = np.linalg.inv(result.world_from_sensor)
    for c in made:
        n = int(np.isin(c.pixels, pix).sum()) if c.pixels is not None else 0
        if n < max(3, 0.05 * n_kept):
            continue
        in_clusters = max(in_clusters, n)
        lo, hi = _heights(c)
        steps = fate.get(id(c), [])
        cut = ""
        if "cut_by_limits=True" in steps:
            cut = " [" + _which_limit(c, params) + "]"
        seen = back[:3, :3] @ c.centroid + back[:3, 3]
        off_cm = 100 * float(np.linalg.norm(seen - centre))
        where = "KEPT" if id(c) in final_ids else "dropped"
        out.append(
            f"cluster: {n} of its {len(c.points)} points the object's, {len(c.voxels)} voxels,"
            f" heights {100 * lo:.1f}..{100 * hi:.1f} cm, centroid {off_cm:.1f} cm off;"
            f" {', '.join(steps) or '-'}{cut}; {where}"
        )
    if not in_clusters:
        out.append("in no cluster of 5 % of its kept points")
    return out


def _folded_into_supports(log: Log, judged: Any, vox: npt.NDArray[np.intp]) -> list[str]:
    """For each horizontal plane that ``judge_planes`` folded into a support's band
    (:func:`shapes.segment.bands.one_plane_per_band`) and that holds some of ``vox``: how far
    over the support it lies (the median of its voxels' heights) and how many of ``vox`` it
    holds. Those voxels count as the support's, not free."""
    found, voxels = log.first("judge_planes")[0][:2]
    kept_ids = {id(p) for p in judged.planes}
    out = []
    for q in found:
        n = int(q.inliers[vox].sum())
        if not q.horizontal or id(q) in kept_ids or n == 0:
            continue
        for k, support in enumerate(judged.supports):
            same = q.offset == support.offset and np.array_equal(q.normal, support.normal)
            if same or not support.inliers[q.inliers].all():
                continue  # the support's own plane (a copy that took the folded voxels)
            h = voxels[q.inliers] @ support.normal + support.offset
            low, mid, high = (100 * float(v) for v in np.percentile(h, [5, 50, 95]))
            out.append(
                f"a plane of {int(q.inliers.sum())} voxels {low:.1f}..{high:.1f} cm"
                f" (median {mid:.1f}) over support {k}: {n}"
            )
    return out


def _which_limit(cluster: Any, params: Any) -> str:
    h = cluster.support.signed_distance(cluster.voxels)
    limit = params.max_tall_height_m if h.max() >= params.max_height_m else params.max_height_m
    if reaching(h >= limit - params.cut_band_m, params):
        return f"band top {limit} m"
    return "image edge or depth cut"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--scan", action="append", help="only these scans (repeatable)")
    parser.add_argument("--object", action="append", help="only these objects (repeatable)")
    parser.add_argument("--all", action="store_true", help="trace found objects too")
    oracle.bench.add_held_out_too(parser)
    args = parser.parse_args()
    truth = json.loads((SCANS / "truth.json").read_text())
    for scan, measured in oracle.bench.loadable_scans(args.held_out_too):
        gt = truth[measured]
        if args.scan and scan not in args.scan:
            continue
        frame = next(open_source(SCANS / f"{scan}.npz"))
        pixels = oracle.object_pixels(scan, measured)
        for seed in range(args.seeds):
            result, log = run_logged(frame, seed)
            for label, pix in pixels.items():
                if args.object and label not in args.object:
                    continue
                score = oracle.score_object(result, gt, label)
                if score.outcome != "missed" and not args.all:
                    continue
                centre = np.asarray(gt[label]["centre"])
                print(f"{scan} / {label} / seed {seed}: {score.outcome}")
                for line in trace(frame, result, log, pix, centre):
                    print(f"    {line}")


if __name__ == "__main__":
    main()
