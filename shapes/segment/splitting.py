"""The splitter's glue: which of the seam cuts of :mod:`shapes.split` are taken.

Step 6 of :mod:`shapes.segment`. A cut is not taken when its parts stand on top of each other
(:func:`_stacked`); it is taken whole when every part stands on the support
(:func:`_each_stands`), else only for what hangs over nothing that stands (:func:`_taken_cut`);
parts that lie along each other stay one (:mod:`shapes.nested_parts`), and so do parts that close
a ring around a common centre (:mod:`shapes.ring_cut`), and so do parts that all lie low
(:mod:`shapes.lying_cut`). A cut refused as stacked is taken after all, its stacked parts
joined, where every two touching parts differ in colour (:mod:`shapes.colour_seam`). The
splitter reads the noise of a cluster's normals clear of the
support's corner (:func:`_clear_of_the_base`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import numpy.typing as npt
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from shapes.arrays import column_max, column_min, column_span
from shapes.colour_seam import joined_where_stacked, touching_parts_differ
from shapes.lying_cut import lies_low
from shapes.nested_parts import joined_where_nested
from shapes.ring_cut import closes_a_ring
from shapes.segment.params import SegmentationParams
from shapes.split import split_each
from shapes.types import FloatArray


def split_clusters(
    labels: npt.NDArray[np.int64],
    voxels: FloatArray,
    viewpoint: FloatArray | None,
    params: SegmentationParams,
    sigma_1m: float,
    heights: FloatArray | None = None,
    margin_m: float = 0.0,
    colours_lab: Callable[[npt.NDArray[np.intp]], FloatArray] | None = None,
) -> npt.NDArray[np.int64]:
    """Labels with every cluster cut along its concave seams (:mod:`shapes.split`), where
    :func:`_taken_cut` takes the cut (``heights``: each voxel's height over the support, when
    known; ``margin_m``: the support's noise margin), and where no part lies along another
    (:mod:`shapes.nested_parts`: a handset in its cradle is one thing with its base). A cut whose
    parts, so joined, close a ring around their common centre (no gap between neighbouring parts
    wider than ``max_ring_gap_deg``, :mod:`shapes.ring_cut`) is not taken: a bowl seen from
    above. Nor is a cut whose parts all stay lower than ``max_lying_height_m`` over the support
    (:mod:`shapes.lying_cut`): one thing lying on it, a drill on its side. A cut with parts
    stacked on top of each other is refused (:func:`_stacked`), unless, those parts joined,
    every two parts that touch differ in colour by more than ``min_part_colour_difference``
    (``colours_lab``: the CIELAB colours of the voxels asked for, None without colours;
    :mod:`shapes.colour_seam`): lying things set down against each other."""
    out = labels.copy()
    next_label = int(labels.max(initial=-1)) + 1
    order = np.argsort(labels, kind="stable")
    bounds = np.searchsorted(labels[order], np.arange(next_label + 1))
    cut, noise = [], []
    for label in range(next_label):
        members = order[bounds[label] : bounds[label + 1]]
        if len(members) < 2 * params.min_cluster_voxels:
            continue
        if column_span(voxels[members, :2]).max() < params.min_split_extent_m:
            continue  # narrower than two of the smallest objects side by side
        ranges = 1.0 if viewpoint is None else np.linalg.norm(voxels[members] - viewpoint, axis=1)
        cut.append(members)
        noise.append(sigma_1m * float(np.median(ranges)) ** 2)
    found = split_each(
        [voxels[m] for m in cut],
        viewpoint,
        min_voxels=params.min_cluster_voxels,
        noise_m=noise,
        judged=None if heights is None else [_clear_of_the_base(heights[m], params) for m in cut],
    )
    for members, parts in zip(cut, found, strict=True):
        if parts.max() == 0:
            continue
        if _stacked(voxels[members], parts, params.cluster_eps_m):
            # Things stacked in the image; distinct things if every two that touch differ in
            # colour once the stacked parts are joined (:mod:`shapes.colour_seam`).
            if colours_lab is None or params.min_part_colour_difference <= 0:
                continue
            parts = joined_where_stacked(voxels[members], parts, params.cluster_eps_m)
            if parts.max() == 0 or not touching_parts_differ(
                voxels[members],
                parts,
                colours_lab(members),
                near_m=params.cluster_eps_m,
                min_difference=params.min_part_colour_difference,
            ):
                continue
        if heights is not None:
            parts = _taken_cut(voxels[members], heights[members], parts, margin_m, params)
        parts = joined_where_nested(
            voxels[members], parts, near_m=params.cluster_eps_m, slice_m=params.voxel_m
        )
        if closes_a_ring(voxels[members], parts, params.max_ring_gap_deg):
            continue  # one thing cut along its own inside: a bowl seen from above
        if heights is not None and lies_low(heights[members], parts, params.max_lying_height_m):
            continue  # one thing lying on the support, cut along its own shape: a drill
        for part in range(1, int(parts.max()) + 1):
            out[members[parts == part]] = next_label
            next_label += 1
    return out


def _clear_of_the_base(heights: FloatArray, params: SegmentationParams) -> npt.NDArray[np.bool_]:
    """The voxels of a cluster over which the splitter reads how noisy its normals are: those
    ``max_base_height_m`` or more over the support. Below, every standing object meets the
    support in a concave corner, a true seam, not noise (on a box beside a telephone, 28 % of
    the voxels of the lowest 2 cm are seam against 13 % above 4 cm). A flat thing, with less
    than half of its voxels above that height, is read whole: its seams there are its own."""
    clear = heights >= params.max_base_height_m
    return clear if 2 * int(clear.sum()) >= len(heights) else np.ones(len(heights), dtype=bool)


def _stacked(voxels: FloatArray, parts: npt.NDArray[np.int64], min_apart_m: float) -> bool:
    """Whether two parts stand on top of each other (their centres closer than ``min_apart_m``
    across the table): objects on a table touch side by side, so such a cut runs through one
    object (an occlusion line, say) and is not taken."""
    centres = np.array([voxels[parts == k, :2].mean(axis=0) for k in range(int(parts.max()) + 1)])
    gaps = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=2)
    return bool((gaps[np.triu_indices(len(centres), 1)] < min_apart_m).any())


def _each_stands(
    heights: FloatArray, parts: npt.NDArray[np.int64], params: SegmentationParams
) -> bool:
    """Whether every part of a cut reaches down to the support (its lowest voxel less than
    ``max_base_height_m`` over it): objects that touch stand side by side on the table, while
    a bottle's handle or shoulder cut off by a seam hangs above it."""
    lowest = [float(heights[parts == k].min()) for k in range(int(parts.max()) + 1)]
    return max(lowest) < params.max_base_height_m


def _taken_cut(
    voxels: FloatArray,
    heights: FloatArray,
    parts: npt.NDArray[np.int64],
    margin_m: float,
    params: SegmentationParams,
) -> npt.NDArray[np.int64]:
    """The parts of a seam cut that are taken, as labels 0, 1, ... (all 0: the cut is refused).

    Every part, when each stands (:func:`_each_stands`). Otherwise a part is cut off on its own
    when it hangs clear of the support as :func:`floats` reads a hanging bottom (lowest voxel
    ``margin_m + max_base_height_m`` or more over it) over no part that stands (its centre
    across the support outside each standing part's extent grown by ``cluster_eps_m``): a
    monitor's screen whose lower edge touches the rim of a cup in front of it. The other parts
    stay one, as a refused cut leaves them: a bottle's shoulder, which hangs over its standing
    body, keeps the body whole, and an open cup's front wall is not cut from its inside (the
    splitter finds a seam where the inside meets the bottom). No part is cut off when the
    others would then fall apart (no chain of voxels ``cluster_eps_m`` apart joins them): what
    hangs holds them together, as a table's top its legs.
    """
    count = int(parts.max()) + 1
    lowest = np.array([float(heights[parts == k].min()) for k in range(count)])
    footprints = [
        (
            column_min(voxels[parts == k, :2]) - params.cluster_eps_m,
            column_max(voxels[parts == k, :2]) + params.cluster_eps_m,
        )
        for k in np.flatnonzero(lowest < params.max_base_height_m)
    ]
    apart = []
    for k in np.flatnonzero(lowest >= margin_m + params.max_base_height_m):
        centre = voxels[parts == k, :2].mean(axis=0)
        if footprints and not any(np.all((centre >= lo) & (centre <= hi)) for lo, hi in footprints):
            apart.append(int(k))
    taken = np.zeros(len(parts), dtype=np.int64)
    if not apart:
        return parts.copy() if _each_stands(heights, parts, params) else taken
    if not _connected(voxels[~np.isin(parts, apart)], params.cluster_eps_m):
        return taken  # what hangs holds the rest together: parts of one thing
    for label, part in enumerate(apart, start=1):
        taken[parts == part] = label
    return taken


def _connected(voxels: FloatArray, link_m: float) -> bool:
    """Whether voxels form one piece, each linked to another within ``link_m``."""
    pairs = cKDTree(voxels).query_pairs(link_m, output_type="ndarray")
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(voxels), len(voxels))
    )
    return int(connected_components(graph, directed=False)[0]) == 1
