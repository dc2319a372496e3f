"""Clusters made of a depth edge's pixels give no primitive.

The last step of :mod:`shapes.segment`. Where the depth jumps between a near surface and a far
one (an object's silhouette against a wall or a sofa), a sensor returns mixed depths a pixel or
two wide; the flying-pixel filter (:mod:`shapes.artefacts`) drops the loose ones, but a line of
them along a long straight edge (the top of a laptop's screen) supports itself and becomes a
cluster of its own. Such a cluster is a band in front of the far side: most of its pixels have,
within ``sliver_window_px``, at least ``sliver_min_farther`` pixels (a row or a column of the
window) farther than themselves by more than ``sliver_jump_ratio`` of their depth. A surface of
an object seen by the camera has an inside, away from its outline; a cluster *most* of whose
pixels (``max_edge_share``) lie at such an edge has none, and no primitive fitted to it
describes a surface.

Only what lies *farther* counts. A surface partly hidden by something nearer (a sphere behind
another, the top of a box behind a telephone) is a real surface seen past an occluder, and its
pixels along the occluder's outline stay inside it; sensor outliers in front of a surface do not
make it an edge either. The jump is a share of the depth, not a multiple of the noise: 5 % of the
range within two pixels is steeper than any surface the camera sees at up to 80 degrees from its
normal (about ``2 tan(80°) / f`` of the range across two pixels: 2.2 % at f = 525 px), and ten
noise levels or more for the sensors of ``tests/data/real_scans`` out to 3 m.
"""

from __future__ import annotations

import numpy as np

from shapes.segment.clusters import Cluster
from shapes.segment.params import SegmentationParams
from shapes.types import FloatArray


def edge_share(cluster: Cluster, depth_image: FloatArray, params: SegmentationParams) -> float:
    """The share of ``cluster``'s pixels in front of a depth edge: with ``sliver_min_farther`` or
    more pixels of the ``sliver_window_px`` square around them farther by more than
    ``sliver_jump_ratio`` of their own depth, in ``depth_image`` (the frame's depths as an
    image, NaN where there is none: no depth is nothing farther). Judged on at most
    ``sliver_samples`` of its pixels evenly spread over its list; 0.0 for a cluster without
    pixels.

    >>> depth = np.full((9, 9), 2.0)
    >>> depth[4, :] = 1.0  # a one-pixel line 1 m nearer than the wall behind it
    >>> line = Cluster(np.zeros((9, 3)), None, np.zeros((1, 3)), pixels=np.arange(36, 45))
    >>> edge_share(line, depth, SegmentationParams())
    1.0
    """
    if cluster.pixels is None or len(cluster.pixels) == 0:
        return 0.0
    step = max(1, len(cluster.pixels) // params.sliver_samples)
    pixels = cluster.pixels[::step]
    height, width = depth_image.shape
    rows, cols = np.divmod(pixels, width)
    flat = depth_image.ravel()
    here = flat[pixels]
    reach = params.sliver_window_px // 2
    offsets = np.arange(-reach, reach + 1)
    # The window of every sampled pixel at once, one row per pixel (clipped at the image's
    # borders, where a border pixel then stands in for the missing ones).
    r = np.clip(rows[:, None] + offsets, 0, height - 1)[:, :, None] * width
    c = np.clip(cols[:, None] + offsets, 0, width - 1)[:, None, :]
    window = flat[(r + c).reshape(len(pixels), -1)]
    with np.errstate(invalid="ignore"):
        farther = np.count_nonzero(
            window - here[:, None] > params.sliver_jump_ratio * here[:, None], axis=1
        )
    at_edge = farther >= params.sliver_min_farther
    return float(np.mean(at_edge))


def off_depth_edges(
    clusters: list[Cluster], depth_image: FloatArray | None, params: SegmentationParams
) -> list[Cluster]:
    """``clusters`` without those more than ``max_edge_share`` of whose pixels lie at a depth
    edge (:func:`edge_share`). All of them when there is no depth image (an unorganised cloud)
    or ``max_edge_share`` is 1 or more (the step is off)."""
    if depth_image is None or params.max_edge_share >= 1.0:
        return clusters
    return [c for c in clusters if edge_share(c, depth_image, params) <= params.max_edge_share]
