"""Objects whose bottom lies in the support's margin band: the kept clusters grown down.

Step 8 of :mod:`shapes.segment`, after every rule of :mod:`shapes.segment.objects` has judged
the clusters: each kept cluster is given the voxels of its support's margin band (over the
plane, up to the support's noise margin, which segmentation leaves to the support) that lie
under its footprint and connect to it (:mod:`shapes.grow_downwards`). Only objects grow, so the
rule adds no cluster and drops none.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.spatial import cKDTree

from shapes.arrays import inside_box
from shapes.grow_downwards import grow_downwards
from shapes.segment.clusters import Cluster, KeptPoints
from shapes.segment.params import SegmentationParams
from shapes.types import FloatArray, SupportPlane


def grown_downwards(
    kept: list[list[Cluster]],
    supports: list[SupportPlane],
    margins: list[float],
    boxes: list[tuple[FloatArray, FloatArray]],
    points: KeptPoints,
    params: SegmentationParams,
) -> list[list[Cluster]]:
    """``kept`` (the clusters kept on each of ``supports``, in their order) with each cluster
    grown down into its support's margin band: the voxels of ``points`` over the support and
    not above its margin (``margins``), inside its box (``boxes``), in no kept cluster, that lie
    under the cluster's footprint on the ``voxel_m`` grid and link to it within
    ``bottom_link_m`` (:func:`shapes.grow_downwards.grow_downwards`; a band voxel under the
    footprints of two clusters of one support goes to neither). A grown cluster gains the points
    of its new voxels that lie over the support's plane. Every list keeps its length and order.
    """
    taken = _in_clusters(points.voxels, [c for found in kept for c in found])
    out: list[list[Cluster]] = []
    for k, found in enumerate(kept):
        if not found:
            out.append([])
            continue
        support = supports[k]
        height = support.signed_distance(points.voxels)
        band = np.flatnonzero(
            (height > 0)
            & (height <= margins[k])
            & ~taken
            & inside_box(points.voxels, boxes[k][0], boxes[k][1])
        )
        grown = grow_downwards(
            [c.voxels for c in found], points.voxels[band], params.voxel_m, params.bottom_link_m
        )
        out.append([_with_voxels(c, band[g], points) for c, g in zip(found, grown, strict=True)])
    return out


def _in_clusters(voxels: FloatArray, clusters: list[Cluster]) -> npt.NDArray[np.bool_]:
    """Which of ``voxels`` are voxels of one of ``clusters`` (the same coordinates)."""
    if not clusters:
        return np.zeros(len(voxels), dtype=np.bool_)
    gap, _ = cKDTree(np.vstack([c.voxels for c in clusters])).query(
        voxels, distance_upper_bound=1e-9
    )
    return np.asarray(np.isfinite(gap), dtype=np.bool_)


def _with_voxels(cluster: Cluster, added: npt.NDArray[np.intp], points: KeptPoints) -> Cluster:
    """``cluster`` with the voxels ``added`` (indices in ``points.voxels``) and their points
    over its support's plane; ``cluster`` itself when none is added."""
    if len(added) == 0:
        return cluster
    assert cluster.support is not None
    marked = np.zeros(len(points.voxels), dtype=np.bool_)
    marked[added] = True
    idx = np.flatnonzero(marked[points.voxel_of])
    idx = idx[cluster.support.signed_distance(points.points[idx]) > 0]
    if len(idx) == 0:
        return cluster
    return Cluster(
        np.vstack([cluster.points, points.points[idx]]),
        None
        if points.colours is None or cluster.colours is None
        else np.vstack([cluster.colours, points.colours[0][points.colours[1][idx]]]),
        np.vstack([cluster.voxels, points.voxels[added]]),
        cluster.support,
        cluster.noise_m,
        None
        if points.pixels is None or cluster.pixels is None
        else np.concatenate([cluster.pixels, points.pixels[idx]]),
    )
