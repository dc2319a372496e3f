"""What the strays are: each primitive the bench matches to no measured object, described by its
points, on the tuned-on real scans and the chain's three seeds.

A stray, as ``bench/perception.py`` counts it, is a primitive whose cluster's centroid lies
``REAL_NEAR_M`` (8 cm) or farther from every measured object's centroid. For each one this
script reads the cluster's own image pixels (``Cluster.pixels``) and measures, with the ground
truth's own attribution (``measure.object_mask`` on the support ``measure.py`` fits):

- ``own``: the share of its pixels that are a measured object's own pixels (and whose);
- ``near``: the share within ``NEAR_OBJECT_M`` (3D) of a measured object's own points, not
  counting those of ``own``: the object's bottom under 1.5 cm, a face its boxes leave out;
- the height of its points over the measured support (5th, 50th, 95th percentiles);
- ``edge``: the share of its pixels at a depth discontinuity (``EDGE_JUMP`` of the depth
  within ``EDGE_WINDOW`` pixels): the mixed pixels between a near and a far surface;
- its pixel box (rows, columns), its mean colour, its primitive's kind and size.

and puts it in one category, by the first test it passes:

1. ``measured object found, its own pixels``: ``own`` >= ``MOSTLY``, and the object is also
   given a primitive the bench matches to it: an extra piece (a face split off, a rim);
2. ``measured object missed, its own pixels``: the same of an object the bench calls missed
   (a piece of a large one, its centroid 8 cm or more from the whole object's);
3. ``measured object, beyond its boxes``: ``own + near`` >= ``MOSTLY``;
4. ``support``: the median height within ``SUPPORT_M`` of the support (its own surface);
5. ``below the support``: a median height lower still (the floor under a desk, what stands on
   it);
6. ``depth-edge pixels``: ``edge`` >= ``MOSTLY``;
7. ``above the scan's height limit``: the median height over the scan's ``MAX_HEIGHT_M``
   (a wall, furniture, a person: what the ground truth does not measure);
8. ``unmeasured, on the support``: the rest (what it is comes from the colour image: see
   ``docs/perception.md``, "What the strays are (stop 40)").

Only the tuned-on scans are loaded (``"held_out": true`` in truth.json are never read), and the
held-out scans named by ``--held-out-too``, which is for after the lead's one run of them.

Run from the repository root::

    PYTHONPATH=. .venv/bin/python bench/perception_strays.py            # the table
    PYTHONPATH=. .venv/bin/python bench/perception_strays.py --each     # and every stray
    PYTHONPATH=. .venv/bin/python bench/perception_strays.py --each \
        --held-out-too tote_whisk_sr300_0 --only tote_whisk_sr300_0

``--without-slivers`` runs the chain without its last step (:mod:`shapes.segment.slivers`, stop
40), as the stop began: the table of ``docs/perception.md`` comes from that code.
"""

import os

# One core: BLAS and OpenMP threads would only spin against each other on a pinned process.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from collections import Counter  # noqa: E402
from dataclasses import dataclass, replace  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402
from scipy.ndimage import maximum_filter, minimum_filter  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import shapes.pipeline  # noqa: E402
from shapes import Perception, PerceptionParams, ShapeKind, open_source  # noqa: E402
from shapes.segment import Cluster, SegmentationParams  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

bench = load_script(Path(__file__).with_name("perception.py"), "perception_bench")
oracle = load_script(Path(__file__).with_name("perception_oracle.py"), "perception_oracle_")
SCANS = bench.REAL_SCANS
measure = oracle.measure

NEAR_OBJECT_M = 0.03
"""A stray's point this close to a measured object's own points counts as that object's."""
MOSTLY = 0.5
"""The share of a stray's pixels that puts it in a category."""
SUPPORT_M = 0.02
"""A stray whose median height over the measured support is under this is the support's."""
EDGE_WINDOW = 5
"""The side, in pixels, of the window in which a depth discontinuity is looked for."""
EDGE_JUMP = 0.05
"""A depth range within the window larger than this share of the pixel's depth is an edge
(5 cm at 1 m: ten times the Kinect's noise there, three disparity steps at 2 m)."""
TOUCH_PX = 4
"""Two clusters' pixels this close in the image (two strides of a 640 x 480 frame) touch."""
CATEGORIES = (
    "measured object found, its own pixels",
    "measured object missed, its own pixels",
    "measured object, beyond its boxes",
    "support",
    "below the support",
    "depth-edge pixels",
    "above the scan's height limit",
    "unmeasured, on the support",
)


@dataclass(frozen=True)
class Stray:
    """One stray primitive and what its points are."""

    scan: str
    seed: int
    category: str
    kind: str
    size_cm: float
    """A round primitive's radius; a plane's largest side of its points' box (cm)."""
    points: int
    heights_cm: tuple[float, float, float]
    own: float
    near: float
    edge: float
    whose: str
    rows: tuple[int, int]
    cols: tuple[int, int]
    colour: tuple[int, int, int]
    also_found: bool
    """``whose`` object is also given a primitive the bench matches to it."""
    lines: int
    """How many image rows or columns the stray spans, whichever are fewer (at the pixels it
    has: a one-line sliver spans 1)."""
    touches: float
    """The share of its pixels within ``TOUCH_PX`` of another primitive's cluster's pixels."""


def clustered(perception: Perception, frame: Any) -> tuple[Any, list[Cluster]]:
    """The frame's result and, for each of its primitives in order, the cluster it was fitted
    to (the pipeline's own ``segment`` and ``fit_cluster``, watched, not changed)."""
    seen: list[Cluster] = []
    fitted: list[bool] = []
    segment, fit = shapes.pipeline.segment, shapes.pipeline.fit_cluster

    def watched_segment(*args: Any, **kwargs: Any) -> Any:
        seg = segment(*args, **kwargs)
        seen.extend(seg.clusters)
        return seg

    def watched_fit(*args: Any, **kwargs: Any) -> Any:
        out = fit(*args, **kwargs)
        fitted.append(out is not None)
        return out

    shapes.pipeline.segment, shapes.pipeline.fit_cluster = watched_segment, watched_fit
    try:
        result = perception.process(frame)
    finally:
        shapes.pipeline.segment, shapes.pipeline.fit_cluster = segment, fit
    return result, [c for c, ok in zip(seen, fitted, strict=True) if ok]


def depth_edges(image: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
    """The pixels within ``EDGE_WINDOW`` of a depth discontinuity between pixels with a depth
    (a pixel with none is left out of the window)."""
    z = image[..., 2]
    valid = np.isfinite(z)
    top = maximum_filter(np.where(valid, z, 0.0), EDGE_WINDOW)
    bottom = minimum_filter(np.where(valid, z, np.inf), EDGE_WINDOW)
    return np.asarray(valid & (top - bottom > EDGE_JUMP * np.where(valid, z, 1.0)))


def strays_of(scan: str, measured: str, seeds: int, params: PerceptionParams) -> list[Stray]:
    """Every stray of ``scan`` on seeds 0 .. ``seeds`` - 1, the chain run with ``params``."""
    truth = json.loads((SCANS / "truth.json").read_text())[measured]
    frame = next(open_source(SCANS / f"{scan}.npz"))
    image = measure.points_of(scan)
    flat = image.reshape(-1, 3)
    with np.load(SCANS / f"{scan}.npz") as data:
        # A PCL capture without colour stores no image (its strays' colour reads 0, 0, 0).
        rgb = data["rgb"].reshape(-1, 3) if "rgb" in data.files else np.zeros_like(flat)
    normal, offset = oracle.measured_support(scan, measured)
    height = flat @ normal + offset
    owned = oracle.object_pixels(scan, measured)
    label_of = np.full(len(flat), -1)
    labels = list(owned)
    for k, label in enumerate(labels):
        label_of[owned[label]] = k
    trees = {label: cKDTree(flat[pix]) for label, pix in owned.items() if len(pix)}
    edges = depth_edges(image).ravel()
    limit = measure.MAX_HEIGHT_M.get(measured, 0.40)
    objects = {
        label: np.asarray(item["centre"])
        for label, item in truth.items()
        if label not in bench.NOT_OBJECTS
    }
    out = []
    for seed in range(seeds):
        perception = Perception(params, seed=seed)
        result, clusters = clustered(perception, frame)
        back = np.linalg.inv(result.world_from_sensor)
        centres = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
        owner = bench._nearest_objects(centres, objects)
        taken = np.zeros(image.shape[:2], dtype=np.int32)
        for k, cluster in enumerate(clusters):
            assert cluster.pixels is not None
            taken.ravel()[cluster.pixels] = k + 1
        near_other = maximum_filter(taken, 2 * TOUCH_PX + 1)
        near_other_low = -maximum_filter(-np.where(taken > 0, taken, 10**6), 2 * TOUCH_PX + 1)
        for index, (prim, cluster, who) in enumerate(
            zip(result.primitives, clusters, owner, strict=True)
        ):
            if who is not None:
                continue
            assert cluster.pixels is not None
            pix = cluster.pixels
            pts = flat[pix]
            mine = label_of[pix]
            own = float(np.mean(mine >= 0))
            close = np.zeros(len(pix), dtype=bool)
            dist_to: dict[str, float] = {}
            for label, tree in trees.items():
                d, _ = tree.query(pts, distance_upper_bound=NEAR_OBJECT_M)
                hit = np.isfinite(d)
                close |= hit
                dist_to[label] = float(np.mean(hit | (mine == labels.index(label))))
            near = float(np.mean(close & (mine < 0)))
            whose = max(dist_to, key=dist_to.__getitem__, default="")
            whose = whose if dist_to.get(whose, 0) > 0 else ""
            h = height[pix]
            med = float(np.median(h))
            edge = float(np.mean(edges[pix]))
            if own >= MOSTLY:
                category = CATEGORIES[0 if whose in owner else 1]
            elif own + near >= MOSTLY:
                category = CATEGORIES[2]
            elif abs(med) < SUPPORT_M:
                category = CATEGORIES[3]
            elif med < 0:
                category = CATEGORIES[4]
            elif edge >= MOSTLY:
                category = CATEGORIES[5]
            elif med > limit:
                category = CATEGORIES[6]
            else:
                category = CATEGORIES[7]
            if prim.kind is ShapeKind.PLANE:
                size = 100 * float(np.ptp(cluster.points[:, :2], axis=0).max())
            else:
                size = 100 * float(prim.radius or 0.0)
            r, c = np.divmod(pix, image.shape[1])
            hi, lo = near_other.ravel()[pix], near_other_low.ravel()[pix]
            touches = float(np.mean((hi != index + 1) | (lo != index + 1)))
            out.append(
                Stray(
                    scan,
                    seed,
                    category,
                    prim.kind.value,
                    size,
                    len(pix),
                    tuple(100 * float(q) for q in np.percentile(h, [5, 50, 95])),  # type: ignore[arg-type]
                    own,
                    near,
                    edge,
                    whose,
                    (int(r.min()), int(r.max())),
                    (int(c.min()), int(c.max())),
                    tuple(int(v) for v in rgb[pix].mean(axis=0)),  # type: ignore[arg-type]
                    whose in owner,
                    min(len(np.unique(r)), len(np.unique(c))),
                    touches,
                )
            )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="the chain's seeds 0..N-1 (3)")
    parser.add_argument("--each", action="store_true", help="print every stray")
    parser.add_argument("--only", help="only the scans whose name contains this")
    parser.add_argument(
        "--without-slivers",
        action="store_true",
        help="the chain without its last step (shapes.segment.slivers): the strays before it",
    )
    bench.add_held_out_too(parser)
    args = parser.parse_args()
    params = PerceptionParams(gravity_from_scene=True)
    if args.without_slivers:
        params = replace(params, segmentation=SegmentationParams(max_edge_share=1.0))
    strays: list[Stray] = []
    for scan, measured in bench.loadable_scans(args.held_out_too):
        if args.only and args.only not in scan:
            continue
        found = strays_of(scan, measured, args.seeds, params)
        strays += found
        if args.each:
            for s in found:
                print(
                    f"{s.scan:<28} seed {s.seed} {s.category:<34} {s.kind:<8} {s.size_cm:5.1f} cm"
                    f" {s.points:6d} pts  h {s.heights_cm[0]:6.1f} {s.heights_cm[1]:6.1f}"
                    f" {s.heights_cm[2]:6.1f} cm  own {s.own:.2f} near {s.near:.2f}"
                    f" edge {s.edge:.2f} {s.whose or '-':<20} rows {s.rows} cols {s.cols}"
                    f" rgb {s.colour} lines {s.lines} touches {s.touches:.2f}"
                    f" {'also found' if s.also_found else ''}",
                    flush=True,
                )
    print(f"strays by category and scan, seeds 0-{args.seeds - 1} (counts per seed):")
    scans = list(dict.fromkeys(s.scan for s in strays))
    for category in CATEGORIES:
        mine = [s for s in strays if s.category == category]
        per_seed = Counter(s.seed for s in mine)
        seeds = "/".join(str(per_seed[k]) for k in range(args.seeds))
        print(f"  {category}: {seeds}")
        for scan in scans:
            here = [s for s in mine if s.scan == scan]
            if not here:
                continue
            counts = Counter(s.seed for s in here)
            kinds = Counter(s.kind for s in here)
            sizes = sorted(s.size_cm for s in here)
            print(
                f"    {scan:<28} {'/'.join(str(counts[k]) for k in range(args.seeds)):<9}"
                f" {', '.join(f'{n} {k}' for k, n in kinds.most_common())};"
                f" size {sizes[0]:.0f}-{sizes[-1]:.0f} cm"
            )
    total = Counter(s.seed for s in strays)
    print(f"  all: {'/'.join(str(total[k]) for k in range(args.seeds))}")


if __name__ == "__main__":
    main()
