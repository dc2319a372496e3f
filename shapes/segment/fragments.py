"""A fragment of an object joins the object it lies beside.

A step of :mod:`shapes.segment`, after the slivers. DBSCAN parts a surface wherever its voxels
are more than ``cluster_eps_m`` apart, and an object seen in pieces leaves small clusters beside
its main one: the rim of a cup or a bowl, a banana of a bunch, a strip of a laptop. Each was
fitted as an object of its own, a primitive that describes nothing (docs/perception.md, "Extra
pieces of found objects (stop 41)").

A *fragment* is a cluster with a visible surface smaller than the small objects the scans
measure: fewer than ``fragment_max_voxels`` voxels (1 cm voxels: square centimetres seen). A
fragment joins the nearest other cluster of its support that is not a fragment when the two
*touch in the image* (their pixels within ``fragment_touch_px`` of each other: nothing of the
support is seen between them) and lie within ``fragment_gap_m`` of each other in 3D, but no
nearer than DBSCAN parts things (``cluster_eps_m`` less a voxel): what lies nearer was cut by
the splitter or the occlusion step, on purpose, between two things. Two things side by side on
a support show the support between them in the image; the pieces of one object seen across a
step of its own depth do not. A fragment with no such neighbour stays as it is. On an
unorganised cloud (no image) the step does nothing.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from shapes.segment.clusters import Cluster
from shapes.segment.params import SegmentationParams


def touch_in_image(a: Cluster, b: Cluster, image_width: int, reach_px: int) -> bool:
    """Whether some image pixel of ``a`` lies within ``reach_px`` (in rows and in columns) of
    some image pixel of ``b`` (False if either has none)."""
    if a.pixels is None or b.pixels is None or len(a.pixels) == 0:
        return False
    ra, ca = np.divmod(a.pixels, image_width)
    rb, cb = np.divmod(b.pixels, image_width)
    box = (
        (rb >= ra.min() - reach_px)
        & (rb <= ra.max() + reach_px)
        & (cb >= ca.min() - reach_px)
        & (cb <= ca.max() + reach_px)
    )
    if not box.any():
        return False
    # Chebyshev distance (p = inf), on a tree: a near fragment holds hundreds of pixels.
    near = cKDTree(np.column_stack([rb[box], cb[box]]))
    d, _ = near.query(np.column_stack([ra, ca]), p=np.inf, distance_upper_bound=reach_px + 0.5)
    return bool(np.isfinite(d).any())


def gap_m(a: Cluster, b: Cluster, reach_m: float) -> float:
    """The least distance between ``a``'s points and ``b``'s; infinity when none of ``b``'s
    points lies within ``reach_m`` of ``a``'s box (the gap is then more than ``reach_m``)."""
    low, high = a.points.min(axis=0) - reach_m, a.points.max(axis=0) + reach_m
    near = b.points[np.all((b.points >= low) & (b.points <= high), axis=1)]
    if len(near) == 0:
        return float("inf")
    d, _ = cKDTree(near).query(a.points)
    return float(np.min(d))


def joined(main: Cluster, pieces: list[Cluster]) -> Cluster:
    """``main`` with the points, colours, voxels and pixels of ``pieces`` added (its support and
    noise kept; colours and pixels only if every part has them)."""
    if not pieces:
        return main
    every = [main, *pieces]
    colours = [c.colours for c in every if c.colours is not None]
    pixels = [c.pixels for c in every if c.pixels is not None]
    return Cluster(
        np.concatenate([c.points for c in every]),
        np.concatenate(colours) if len(colours) == len(every) else None,
        np.concatenate([c.voxels for c in every]),
        main.support,
        main.noise_m,
        np.concatenate(pixels) if len(pixels) == len(every) else None,
    )


def fragments_joined(
    clusters: list[Cluster], image_width: int | None, params: SegmentationParams
) -> list[Cluster]:
    """``clusters`` (of one support) with each fragment (under ``fragment_max_voxels`` voxels)
    joined to the nearest cluster that is not one among those it touches in the image (within
    ``fragment_touch_px``), when that cluster lies within ``fragment_gap_m`` of it and no nearer
    than ``cluster_eps_m - voxel_m`` (nearer, a cut of the splitter or the occlusion step parted
    them, and it stands); the others in their order.
    ``image_width``: the width of the image the clusters' pixels index. All of them when there
    is no image or ``fragment_max_voxels`` is 0 (the step is off).

    >>> def strip(x: float, col: int, n: int) -> Cluster:  # n points 1 cm apart, one a pixel
    ...     pts = np.array([[x + 0.01 * i, 0.0, 0.05] for i in range(n)])
    ...     return Cluster(pts, None, pts, None, 0.0, np.arange(col, col + n))
    >>> main, rim = strip(0.0, 0, 8), strip(0.11, 11, 3)  # 4 cm apart, 4 pixels in the image
    >>> params = SegmentationParams(fragment_max_voxels=5)
    >>> [len(c.points) for c in fragments_joined([main, rim], 100, params)]
    [11]
    >>> apart = strip(0.11, 20, 3)  # the same in 3D, 13 pixels away: the support between
    >>> [len(c.points) for c in fragments_joined([main, apart], 100, params)]
    [8, 3]
    """
    if image_width is None or params.fragment_max_voxels <= 0 or len(clusters) < 2:
        return clusters
    fragment = [len(c.voxels) < params.fragment_max_voxels for c in clusters]
    if not any(fragment) or all(fragment):
        return clusters
    # DBSCAN parts voxels more than cluster_eps_m apart, so points of two voxels it parted lie
    # at least that less a voxel apart; nearer, the splitter or the occlusion step cut them on
    # purpose (a seam between two things), and that cut stands.
    parted_gap_m = params.cluster_eps_m - params.voxel_m
    into: dict[int, list[Cluster]] = {}
    joined_away: set[int] = set()
    for k, cluster in enumerate(clusters):
        if not fragment[k]:
            continue
        gaps = [
            gap_m(cluster, other, params.fragment_gap_m)
            if not fragment[j]
            and touch_in_image(cluster, other, image_width, params.fragment_touch_px)
            else float("inf")
            for j, other in enumerate(clusters)
        ]
        nearest = int(np.argmin(gaps))
        if parted_gap_m <= gaps[nearest] <= params.fragment_gap_m:
            into.setdefault(nearest, []).append(cluster)
            joined_away.add(k)
    return [
        joined(cluster, into.get(k, []))
        for k, cluster in enumerate(clusters)
        if k not in joined_away
    ]
