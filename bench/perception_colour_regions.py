"""Whether colour regions could part a cluster where the geometry gives no seam: the measure.

For every real scan tuned on that has colours (the held-out ones, ``"held_out": true`` in
truth.json, are never loaded) and each of ``--seeds`` seeds of the chain (the bench's run), the
clusters as the splitter leaves them (:func:`shapes.segment.splitting.split_clusters`, wrapped
for this run only; the chain's output does not change) are each parted in two by colour: a
2-means in CIELAB over the voxels' colours, started from the two ends of the colours' main axis.
For each cluster of ``MIN_VOXELS`` coloured voxels or more it prints:

- the two regions' sizes and the distance between their median colours (CIE76 delta E);
- how compact each region is (the share of its voxels in its largest piece, voxels linked within
  ``LINK_M``), how far apart their median heights over the support lie, and the plane fit's rms
  of the union against the worse of the two regions alone;
- which measured object holds most of each region's voxels (``measure.object_mask``, the ground
  truth's own attribution; ``-``: no measured object), with its share.

Then, for each candidate guard of "flat things side by side, parted by colour" (docs/perception.md,
"Flat things side by side, parted by colour regions (stop 40, tried)"), how many clusters it
would part, by what the ground truth says they are; with ``--short-contact``, the colour
regions that meet the rest of their cluster at a point (:func:`short_contacts`); and, with
``--pairs``, the ground truth's own
partition of the fr1 power adapter and the fr2 papers from the cluster that holds them.

Run from the repository root (about a minute of CPU a seed)::

    PYTHONPATH=. .venv/bin/python bench/perception_colour_regions.py --seeds 3
    PYTHONPATH=. .venv/bin/python bench/perception_colour_regions.py --pairs
    PYTHONPATH=. .venv/bin/python bench/perception_colour_regions.py --short-contact --seeds 3
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
from collections import Counter  # noqa: E402
from collections.abc import Callable, Iterator  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402
from scipy.sparse import coo_matrix  # noqa: E402
from scipy.sparse.csgraph import connected_components  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402

import shapes.segment.clusters as clusters_module  # noqa: E402
import shapes.segment.segmentation as seg_module  # noqa: E402
from shapes import Perception, PerceptionParams, open_source  # noqa: E402
from tests.shapes.real_scans import load_script  # noqa: E402

oracle = load_script(
    Path(__file__).with_name("perception_oracle.py"), "perception_oracle_for_colour_regions"
)
bench = oracle.bench
SCANS = bench.REAL_SCANS
MIN_VOXELS = 24
"""Clusters with fewer coloured voxels are left out (two regions of 12, the least cluster)."""
LINK_M = 0.015
"""Voxels (1 cm) closer than this are one piece: the 6 face neighbours, not the diagonals."""
EDGE_DELTA_E = 30.0
"""``--short-contact``: neighbouring voxels closer in colour than this are one colour region."""
MAX_CONTACT = 6
"""``--short-contact``: a region touching the rest of its cluster with this many voxels or fewer
meets it at a point, not along a line (the adapter meets the dispenser with 1-4)."""
PAIRS = {
    "desk_fr1_tum_0": ("power adapter", "tape dispenser"),
    "desk_fr1_tum_1": ("power adapter", "tape dispenser"),
    "desk_fr2_tum_0": ("papers", ""),
    "desk_fr2_tum_1": ("papers", ""),
}
"""The merged flat things of "Why the missed objects are missed (stop 40)", each with the thing
whose cluster holds it ("": the unmeasured booklets and white box)."""


@dataclass(frozen=True)
class Parted:
    """One cluster as the splitter left it, parted in two by colour."""

    scan: str
    seed: int
    sizes: tuple[int, int]
    delta_e: float
    compact: tuple[float, float]
    height_apart_m: float
    rms_union_m: float
    rms_worse_part_m: float
    touching: int
    """The smaller region's voxels within ``LINK_M`` of the other region: how long they meet."""
    owners: tuple[tuple[str, int, int], tuple[str, int, int]]
    """Each region's main measured object ("" for none), its voxels, and the region's."""

    @property
    def one_object(self) -> bool:
        return self.owners[0][0] == self.owners[1][0]

    def line(self) -> str:
        owners = " ; ".join(f"{o or '-'}:{n}/{m}" for o, n, m in self.owners)
        return (
            f"{self.scan} s{self.seed} sizes {list(self.sizes)} dE {self.delta_e:.1f}"
            f" compact {self.compact[0]:.2f},{self.compact[1]:.2f}"
            f" heights {100 * self.height_apart_m:.1f} cm apart"
            f" plane rms {100 * self.rms_union_m:.2f} (union) {100 * self.rms_worse_part_m:.2f}"
            f" (worse part) cm, {self.touching} touching | {owners}"
        )


GUARDS: dict[str, Callable[[Parted], bool]] = {
    "dE > 40, both regions >= 20 voxels, each compact (>= 0.8)": lambda p: (
        p.delta_e > 40 and min(p.sizes) >= 20 and min(p.compact) >= 0.8
    ),
    "the same, and each region alone a better plane": lambda p: (
        p.delta_e > 40
        and min(p.sizes) >= 20
        and min(p.compact) >= 0.8
        and p.rms_worse_part_m < p.rms_union_m
    ),
    "the same as the first, and heights >= 1 cm apart": lambda p: (
        p.delta_e > 40 and min(p.sizes) >= 20 and min(p.compact) >= 0.8 and p.height_apart_m >= 0.01
    ),
}


def split_clusters_logged(seen: list[dict[str, Any]]) -> Callable[..., Any]:
    """``split_clusters`` that also appends its voxels, heights, colours and labels to ``seen``."""
    split = clusters_module.split_clusters

    def logged(*args: Any) -> Any:
        out = split(*args)
        seen.append({"voxels": args[1], "heights": args[5], "colours": args[7], "labels": out})
        return out

    return logged


def run_logged(frame: Any, seed: int) -> list[dict[str, Any]]:
    """The chain on ``frame`` with seed ``seed``; each ``split_clusters`` call with its
    ``KeptPoints`` (``clusters_on``'s, logged beside it)."""
    seen: list[dict[str, Any]] = []
    kept: list[Any] = []
    clusters_on = seg_module.clusters_on

    def on(candidates: Any, kept_points: Any, *args: Any, **kwargs: Any) -> Any:
        kept.append(kept_points)
        return clusters_on(candidates, kept_points, *args, **kwargs)

    saved = clusters_module.split_clusters
    try:
        clusters_module.split_clusters = split_clusters_logged(seen)
        seg_module.clusters_on = on
        Perception(PerceptionParams(gravity_from_scene=True), seed=seed).process(frame)
    finally:
        clusters_module.split_clusters = saved
        seg_module.clusters_on = clusters_on
    for call, kept_points in zip(seen, kept, strict=True):
        call["kept"] = kept_points
    return seen


def owners_of(call: dict[str, Any], pixels: dict[str, npt.NDArray[np.intp]]) -> npt.NDArray[Any]:
    """The measured object holding most of each split voxel's kept points ("" for none)."""
    kept = call["kept"]
    total = np.bincount(kept.voxel_of, minlength=len(kept.voxels))
    owner = np.full(len(kept.voxels), "", dtype=object)
    for label, pix in pixels.items():
        mine = np.bincount(kept.voxel_of[np.isin(kept.pixels, pix)], minlength=len(kept.voxels))
        owner[2 * mine > total] = label
    index = {tuple(v): i for i, v in enumerate(np.round(kept.voxels, 6))}
    at = np.array([index[tuple(v)] for v in np.round(call["voxels"], 6)], dtype=np.intp)
    return np.asarray(owner[at])


def two_means(colours: npt.NDArray[np.float64]) -> npt.NDArray[np.int64]:
    """Two groups (0, 1) of ``colours`` by 2-means, started from their main axis's two ends."""
    centred = colours - colours.mean(axis=0)
    along = centred @ np.linalg.svd(centred, full_matrices=False)[2][0]
    centres = colours[[along.argmin(), along.argmax()]]
    group = np.zeros(len(colours), dtype=np.int64)
    for _ in range(50):
        near = np.linalg.norm(colours[:, None, :] - centres[None, :, :], axis=2)
        group = near.argmin(axis=1).astype(np.int64)
        if group.min() == group.max():
            break
        moved = np.array([colours[group == k].mean(axis=0) for k in (0, 1)])
        if np.allclose(moved, centres):
            break
        centres = moved
    return group


def largest_piece_share(voxels: npt.NDArray[np.float64]) -> float:
    """The share of ``voxels`` in their largest piece (linked within ``LINK_M``)."""
    pairs = cKDTree(voxels).query_pairs(LINK_M, output_type="ndarray")
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(voxels), len(voxels))
    )
    return float(np.bincount(connected_components(graph, directed=False)[1]).max() / len(voxels))


def touching_voxels(
    voxels: npt.NDArray[np.float64], part: npt.NDArray[np.intp], other: npt.NDArray[np.intp]
) -> int:
    """How many voxels of ``part`` lie within ``LINK_M`` of a voxel of ``other``."""
    gaps = cKDTree(voxels[other]).query(voxels[part], distance_upper_bound=LINK_M)[0]
    return int(np.isfinite(gaps).sum())


def plane_rms(voxels: npt.NDArray[np.float64]) -> float:
    """The rms distance of ``voxels`` from their least-squares plane."""
    smallest = np.linalg.svd(voxels - voxels.mean(axis=0), compute_uv=False)[-1]
    return float(smallest / np.sqrt(len(voxels)))


def parted(scan: str, seed: int, call: dict[str, Any], owner: npt.NDArray[Any]) -> Iterator[Parted]:
    """Every cluster of one ``split_clusters`` call, parted in two by colour."""
    labels, voxels, heights = call["labels"], call["voxels"], call["heights"]
    for label in range(int(labels.max(initial=-1)) + 1):
        members = np.flatnonzero(labels == label)
        colours = call["colours"](members)
        coloured = np.isfinite(colours).all(axis=1)
        members, colours = members[coloured], colours[coloured]
        if len(members) < MIN_VOXELS:
            continue
        group = two_means(colours)
        if group.min() == group.max():
            continue
        region = [members[group == k] for k in (0, 1)]
        medians = [np.median(colours[group == k], axis=0) for k in (0, 1)]
        main = []
        for r in region:
            names, counts = np.unique(owner[r], return_counts=True)
            main.append((str(names[counts.argmax()]), int(counts.max()), len(r)))
        yield Parted(
            scan,
            seed,
            (len(region[0]), len(region[1])),
            float(np.linalg.norm(medians[0] - medians[1])),
            (largest_piece_share(voxels[region[0]]), largest_piece_share(voxels[region[1]])),
            abs(float(np.median(heights[region[0]]) - np.median(heights[region[1]]))),
            plane_rms(voxels[members]),
            max(plane_rms(voxels[r]) for r in region),
            touching_voxels(voxels, *sorted(region, key=len)),
            (main[0], main[1]),
        )


def short_contacts(
    scan: str, seed: int, call: dict[str, Any], owner: npt.NDArray[Any]
) -> Iterator[tuple[str, str]]:
    """Colour regions cut off where they meet the rest of their cluster at a point: the voxel
    graph (links within ``LINK_M``) keeps only links between voxels less than ``EDGE_DELTA_E``
    apart in colour; each piece of 20 voxels or more touching the rest with at most
    ``MAX_CONTACT`` voxels, and more than 40 apart from every region it touches. Yields a line
    and what the ground truth says the cut parts."""
    labels, voxels = call["labels"], call["voxels"]
    for label in range(int(labels.max(initial=-1)) + 1):
        members = np.flatnonzero(labels == label)
        if len(members) < 40:
            continue
        colours = call["colours"](members)
        at = voxels[members]
        pairs = cKDTree(at).query_pairs(LINK_M, output_type="ndarray")
        seen = np.isfinite(colours).all(axis=1)
        alike = (
            seen[pairs[:, 0]]
            & seen[pairs[:, 1]]
            & (np.linalg.norm(colours[pairs[:, 0]] - colours[pairs[:, 1]], axis=1) < EDGE_DELTA_E)
        )
        linked = pairs[alike]
        graph = coo_matrix(
            (np.ones(len(linked)), (linked[:, 0], linked[:, 1])), shape=(len(at), len(at))
        )
        region = connected_components(graph, directed=False)[1]
        sizes = np.bincount(region)
        for k in np.flatnonzero(sizes >= 20):
            part, rest = np.flatnonzero(region == k), np.flatnonzero(region != k)
            if len(rest) < 20:
                continue
            gaps, nearest = cKDTree(at[rest]).query(at[part], distance_upper_bound=LINK_M)
            contact = int(np.isfinite(gaps).sum())
            if not 0 < contact <= MAX_CONTACT:
                continue
            median = np.nanmedian(colours[part], axis=0)
            apart = min(
                float(np.linalg.norm(median - np.nanmedian(colours[region == n], axis=0)))
                for n in np.unique(region[rest[nearest[np.isfinite(gaps)]]])
            )
            if apart <= 40:
                continue
            mains = []
            for side in (part, rest):
                names, counts = np.unique(owner[members[side]], return_counts=True)
                mains.append(str(names[counts.argmax()]))
            kind = (
                "two things"
                if mains[0] != mains[1]
                else "one measured object"
                if mains[0]
                else "unmeasured"
            )
            yield (
                f"{scan} s{seed}: region {len(part)} of {len(members)} voxels, {contact} touching,"
                f" dE {apart:.1f}: {mains[0] or '-'} from {mains[1] or '-'}",
                kind,
            )


def pair_lines(scan: str, seed: int, call: dict[str, Any], owner: npt.NDArray[Any]) -> list[str]:
    """The ground truth's partition of ``PAIRS[scan]`` within the cluster holding the object."""
    target, other = PAIRS[scan]
    labels, voxels, heights = call["labels"], call["voxels"], call["heights"]
    out = []
    for label in np.unique(labels[(owner == target) & (labels >= 0)]):
        members = np.flatnonzero(labels == label)
        mine = members[owner[members] == target]
        theirs = members[owner[members] == other]
        if len(mine) < 3 or len(theirs) < 3:
            continue
        colours = call["colours"](members)
        medians = []
        for part in (mine, theirs):
            values = colours[np.isin(members, part)]
            medians.append(np.median(values[np.isfinite(values).all(axis=1)], axis=0))
        delta_e = float(np.linalg.norm(medians[0] - medians[1]))
        # The other thing's own colour regions: how far the object's colour lies from each,
        # their median heights, and how many of their voxels lie within LINK_M of the object.
        values = colours[np.isin(members, theirs)]
        seen = np.isfinite(values).all(axis=1)
        group = two_means(values[seen])
        near_object = np.isfinite(
            cKDTree(voxels[mine]).query(voxels[theirs[seen]], distance_upper_bound=LINK_M)[0]
        )
        own = [np.median(values[seen][group == k], axis=0) for k in (0, 1) if (group == k).any()]
        regions = ", ".join(
            f"{(group == k).sum()} voxels at dE {np.linalg.norm(medians[0] - m):.1f},"
            f" {100 * np.median(heights[theirs[seen][group == k]]):.1f} cm high,"
            f" {(near_object & (group == k)).sum()} touching"
            for k, m in enumerate(own)
        )
        inner = float(np.linalg.norm(own[0] - own[-1]))
        normals = [
            np.linalg.svd(voxels[p] - voxels[p].mean(axis=0), full_matrices=False)[2][-1]
            for p in (mine, theirs)
        ]
        angle = np.degrees(np.arccos(min(1.0, abs(float(normals[0] @ normals[1])))))
        out.append(
            f"{scan} s{seed}: cluster of {len(members)} voxels: {target} {len(mine)},"
            f" {other or 'unmeasured'} {len(theirs)}; dE {delta_e:.1f};"
            f" the other's own two colour regions {inner:.1f} apart ({regions});"
            f" median heights {100 * np.median(heights[mine]):.1f} and"
            f" {100 * np.median(heights[theirs]):.1f} cm; normals {angle:.1f} deg apart;"
            f" plane rms union {100 * plane_rms(voxels[np.r_[mine, theirs]]):.2f} cm,"
            f" parts {100 * plane_rms(voxels[mine]):.2f} and {100 * plane_rms(voxels[theirs]):.2f}"
        )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--scan", action="append", help="only these scans (repeatable)")
    parser.add_argument("--pairs", action="store_true", help="only the merged flat things")
    parser.add_argument(
        "--short-contact", action="store_true", help="colour regions that meet at a point"
    )
    args = parser.parse_args()
    rows: list[Parted] = []
    contacts: Counter[str] = Counter()
    for scan, measured in bench.loadable_scans():
        if (args.scan and scan not in args.scan) or (args.pairs and scan not in PAIRS):
            continue
        frame = next(open_source(SCANS / f"{scan}.npz"))
        if frame.colours is None:
            continue
        pixels = oracle.object_pixels(scan, measured)
        for seed in range(args.seeds):
            for call in run_logged(frame, seed):
                if call["colours"] is None:
                    continue
                owner = owners_of(call, pixels)
                if args.pairs:
                    for line in pair_lines(scan, seed, call, owner):
                        print(line)
                    continue
                if args.short_contact:
                    for line, kind in short_contacts(scan, seed, call, owner):
                        contacts[kind] += 1
                        print(line)
                    continue
                for row in parted(scan, seed, call, owner):
                    rows.append(row)
                    print(row.line())
    if args.pairs:
        return
    if args.short_contact:
        print(f"cut at a point: {sum(contacts.values())}: {dict(sorted(contacts.items()))}")
        return
    print(f"\n{len(rows)} clusters of {MIN_VOXELS} coloured voxels or more")
    for name, guard in GUARDS.items():
        taken = Counter(
            "one measured object"
            if p.one_object and p.owners[0][0]
            else "unmeasured"
            if p.one_object
            else "two things"
            for p in rows
            if guard(p)
        )
        print(f"{name}: would part {sum(taken.values())}: {dict(sorted(taken.items()))}")
        which = Counter(f"{p.scan} {p.owners[0][0] or '-'}" for p in rows if guard(p))
        print("    " + ", ".join(f"{k} x{n}" for k, n in sorted(which.items())))
    alike = [
        p
        for p in rows
        if p.one_object and p.owners[0][0] and min(p.sizes) >= 20 and min(p.compact) >= 0.8
    ]
    if alike:
        touching = sorted(p.touching for p in alike if p.delta_e > 40)
        print(f"of those more than 40 apart, the smaller region's voxels touching: {touching}")
    within = [
        p.delta_e
        for p in rows
        if p.one_object and p.owners[0][0] and min(p.sizes) >= 20 and min(p.compact) >= 0.8
    ]
    if within:
        print(
            f"one measured object, both regions >= 20 voxels and compact: {len(within)};"
            f" dE deciles {np.round(np.quantile(within, np.linspace(0.1, 0.9, 9)), 1).tolist()},"
            f" max {max(within):.1f}"
        )


if __name__ == "__main__":
    main()
