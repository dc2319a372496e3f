"""Extra pieces of found objects, and the neighbours that must stay apart: every pair of
primitives' clusters that come near each other in 3D, on the tuned-on real scans.

A pair is labelled with the ground truth's own attribution (``measure.object_mask``, through
``bench/perception_oracle.py``): a cluster *belongs* to the measured object that owns at least
``MOSTLY`` of its pixels.

- ``piece``: one cluster is a stray (the bench matches it to no object) and belongs to an
  object that another cluster of the pair is matched to: an extra piece of a found object;
- ``apart``: the two clusters belong to two different measured objects (touching neighbours);
- ``other``: anything else (a stray of an unmeasured thing beside an object, ...).

For each pair it measures what physically joins the two:

- ``gap``: the least 3D distance between their points (cm);
- ``contact``: how many of the smaller cluster's points lie within ``CONTACT_M`` of the larger's,
  and the length of that contact line (the largest side of their box, cm);
- ``angle``: between the two clusters' least-squares plane normals (degrees);
- ``share``: the smaller's points over the larger's;
- ``over``: the share of the smaller's points within ``OVER_M`` of the larger's, seen from above;
- ``image``: the least distance between the two clusters' image pixels (Chebyshev, pixels);
- ``bottom``: the smaller's 5th percentile of height over its support (cm);
- ``rise``: the smaller's median height less the larger's 95th percentile of height (cm);
- ``step``: which step of segmentation parted them: ``dbscan`` (two DBSCAN clusters: a gap of
  more than ``cluster_eps_m``), ``splitter`` (one DBSCAN cluster the splitter cut), ``occlusion``
  (one cluster after the splitter, parted later: at an occlusion edge); read from the labels
  DBSCAN and the splitter gave the two clusters' voxels.

Only the tuned-on scans are loaded (``"held_out": true`` in truth.json are never read).

Run from the repository root (``--near-cm``: the pairs this close, 5 by default)::

    PYTHONPATH=. .venv/bin/python bench/perception_pieces.py            # pieces and apart pairs
    PYTHONPATH=. .venv/bin/python bench/perception_pieces.py --all      # and the other pairs

The pairs are those of the checkout first on ``PYTHONPATH``: on the code with
:mod:`shapes.segment.fragments` the fragments it joins are gone; the figures of
docs/perception.md, "Extra pieces of found objects (stop 41)", are those of the code before it
(10d3fea).
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import shapes.segment.clusters as seg_clusters  # noqa: E402
from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

strays = load_script(Path(__file__).with_name("perception_strays.py"), "perception_strays_")
bench, oracle = strays.bench, strays.oracle
SCANS = bench.REAL_SCANS

MOSTLY = 0.5
"""The share of a cluster's pixels a measured object must own for the cluster to be its."""
NEAR_M = 0.05
"""Pairs whose clusters come closer than this in 3D are listed."""
CONTACT_M = 0.015
"""A point of the smaller cluster this close to the larger one's is on their contact line."""
IMAGE_VOXELS = 120
"""The image distance is measured only when the smaller cluster has fewer voxels (-1 else)."""
OVER_M = 0.02
"""A point of the smaller cluster this close to the larger one's, seen from above (x, y), lies
over or under it."""


def _key(rows: npt.NDArray[np.float64]) -> list[bytes]:
    return [r.tobytes() for r in np.ascontiguousarray(rows)]


class StageLabels:
    """The labels DBSCAN and the splitter gave each candidate voxel, keyed by the voxel's world
    coordinates (recorded by wrapping the splitter in :mod:`shapes.segment.clusters`: its input
    is DBSCAN's labels)."""

    def __init__(self) -> None:
        self.dbscan: dict[bytes, tuple[int, int]] = {}
        self.split: dict[bytes, tuple[int, int]] = {}
        self.calls = 0

    def __enter__(self) -> "StageLabels":
        self._split = seg_clusters.split_clusters
        me = self

        def split(labels: Any, voxels: Any, *args: Any, **kwargs: Any) -> Any:
            me.calls += 1
            out = me._split(labels, voxels, *args, **kwargs)
            for k, lab, new in zip(_key(voxels), labels, out, strict=True):
                me.dbscan[k] = (me.calls, int(lab))
                me.split[k] = (me.calls, int(new))
            return out

        seg_clusters.split_clusters = split
        return self

    def __exit__(self, *exc: object) -> None:
        seg_clusters.split_clusters = self._split

    def of(self, voxels: npt.NDArray[np.float64], table: dict[bytes, tuple[int, int]]) -> Any:
        """The most common label of ``voxels`` in ``table`` (None if none is recorded)."""
        got = [table[k] for k in _key(voxels) if k in table]
        if not got:
            return None
        values, counts = np.unique(np.asarray(got), axis=0, return_counts=True)
        return tuple(values[int(np.argmax(counts))])


def normal_of(points: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The least-squares plane normal of ``points``."""
    centred = points - points.mean(axis=0)
    return np.asarray(np.linalg.svd(centred, full_matrices=False)[2][2])


def image_gap_px(a: Any, b: Any, width: int, reach_px: int = 40) -> int:
    """The least Chebyshev distance in pixels between the image pixels ``a`` and ``b`` (capped
    at ``reach_px``)."""
    ra, ca = np.divmod(a, width)
    rb, cb = np.divmod(b, width)
    box = (
        (rb >= ra.min() - reach_px)
        & (rb <= ra.max() + reach_px)
        & (cb >= ca.min() - reach_px)
        & (cb <= ca.max() + reach_px)
    )
    rb, cb = rb[box], cb[box]
    if len(rb) == 0:
        return reach_px
    best = reach_px
    for start in range(0, len(ra), 256):
        r, c = ra[start : start + 256], ca[start : start + 256]
        gaps = np.maximum(np.abs(r[:, None] - rb[None, :]), np.abs(c[:, None] - cb[None, :]))
        best = min(best, int(gaps.min()))
    return best


def pairs_of(scan: str, measured: str, seed: int, near_m: float = NEAR_M) -> list[dict[str, Any]]:
    """Every pair of ``scan``'s primitives' clusters within ``near_m`` of each other (seed
    ``seed``)."""
    truth = json.loads((SCANS / "truth.json").read_text())[measured]
    frame = next(open_source(SCANS / f"{scan}.npz"))
    owned = oracle.object_pixels(scan, measured)
    objects = {
        label: np.asarray(item["centre"])
        for label, item in truth.items()
        if label not in bench.NOT_OBJECTS
    }
    with StageLabels() as stages:
        result, clusters = strays.clustered(
            Perception(PerceptionParams(gravity_from_scene=True), seed=seed), frame
        )
    back = np.linalg.inv(result.world_from_sensor)
    centres = [back[:3, :3] @ c + back[:3, 3] for c in result.centroids]
    matched = bench._nearest_objects(centres, objects)
    belongs: list[str | None] = []
    for cluster in clusters:
        share = {k: float(np.isin(cluster.pixels, pix).mean()) for k, pix in owned.items()}
        best = max(share, key=share.__getitem__, default=None)
        belongs.append(best if best is not None and share[best] >= MOSTLY else None)
    trees = [cKDTree(c.points) for c in clusters]
    width = frame.image_shape[1]
    out = []
    for i in range(len(clusters)):
        for j in range(i + 1, len(clusters)):
            small, large = (i, j) if len(clusters[i].points) <= len(clusters[j].points) else (j, i)
            d, _ = trees[large].query(clusters[small].points, distance_upper_bound=near_m)
            if not np.isfinite(d).any():
                continue
            if any(
                matched[a] is None and belongs[a] and belongs[a] == matched[b]
                for a, b in ((small, large), (large, small))
            ):
                label = "piece"
            elif belongs[i] and belongs[j] and belongs[i] != belongs[j]:
                label = "apart"
            else:
                label = "other"
            touching = clusters[small].points[d < CONTACT_M]
            length = float(np.ptp(touching, axis=0).max()) if len(touching) > 1 else 0.0
            a, b = (stages.of(clusters[k].voxels, stages.dbscan) for k in (small, large))
            sa, sb = (stages.of(clusters[k].voxels, stages.split) for k in (small, large))
            step = "dbscan" if a != b else "splitter" if sa != sb else "occlusion"
            flat_large = cKDTree(clusters[large].points[:, :2])
            dxy, _ = flat_large.query(clusters[small].points[:, :2], distance_upper_bound=OVER_M)
            over = float(np.isfinite(dxy).mean())
            rise = float(
                np.median(clusters[small].points[:, 2])
                - np.percentile(clusters[large].points[:, 2], 95)
            )
            cos = abs(float(normal_of(clusters[small].points) @ normal_of(clusters[large].points)))
            out.append(
                {
                    "scan": scan,
                    "seed": seed,
                    "label": label,
                    "small": f"{belongs[small] or '-'}{'' if matched[small] else '*'}",
                    "large": f"{belongs[large] or '-'}{'' if matched[large] else '*'}",
                    "kinds": f"{result.primitives[small].kind.value}/"
                    f"{result.primitives[large].kind.value}",
                    "gap": 100 * float(d.min()),
                    "contact": int((d < CONTACT_M).sum()),
                    "length": 100 * length,
                    "angle": float(np.degrees(np.arccos(min(1.0, cos)))),
                    "share": len(clusters[small].points) / len(clusters[large].points),
                    "points": (len(clusters[small].points), len(clusters[large].points)),
                    "voxels": (len(clusters[small].voxels), len(clusters[large].voxels)),
                    "step": step,
                    "over": over,
                    "image_px": image_gap_px(clusters[small].pixels, clusters[large].pixels, width)
                    if len(clusters[small].voxels) < IMAGE_VOXELS
                    else -1,
                    "bottom": 100
                    * float(
                        np.percentile(
                            clusters[small].support.signed_distance(clusters[small].points), 5
                        )
                    ),
                    "rise": 100 * rise,
                }
            )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="the chain's seeds 0..N-1 (3)")
    parser.add_argument("--all", action="store_true", help="also the pairs labelled other")
    parser.add_argument("--only", help="only the scans whose name contains this")
    parser.add_argument("--near-cm", type=float, default=100 * NEAR_M, help="pairs this close")
    args = parser.parse_args()
    for scan, measured in bench.loadable_scans():
        if args.only and args.only not in scan:
            continue
        for seed in range(args.seeds):
            for p in pairs_of(scan, measured, seed, args.near_cm / 100):
                if p["label"] == "other" and not args.all:
                    continue
                print(
                    f"{p['label']:<6} {p['scan']:<28} s{p['seed']} {p['small'][:18]:<18}"
                    f" {p['large'][:18]:<18} {p['kinds']:<17} gap {p['gap']:5.1f} cm"
                    f" contact {p['contact']:5d} pts {p['length']:5.1f} cm"
                    f" angle {p['angle']:4.0f} share {p['share']:.2f}"
                    f" pts {p['points'][0]}/{p['points'][1]} vox {p['voxels'][0]}/{p['voxels'][1]}"
                    f" {p['step']:<9}"
                    f" over {p['over']:.2f} rise {p['rise']:5.1f} cm bottom {p['bottom']:4.1f} cm"
                    f" image {p['image_px']} px",
                    flush=True,
                )


if __name__ == "__main__":
    main()
