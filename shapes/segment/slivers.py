"""Clusters made of a depth edge's pixels give no primitive.

The last step of :mod:`shapes.segment`. Where the depth jumps between a near surface and a far
one (an object's silhouette against the floor or a wall), a sensor returns mixed depths and
smoothed ramps a pixel or two wide; the flying-pixel filter (:mod:`shapes.artefacts`) drops the
loose ones, but a line of them along a long straight edge (a laptop screen's top, a bowl's
rim) supports itself and becomes a cluster of its own. Such a cluster is a band along the edge:
most of its pixels lie within ``sliver_window_px`` of a jump larger than ``sliver_jump_ratio``
of their depth. A surface of an object seen by the camera has an inside, away from its
silhouette; a cluster *most* of whose pixels (``max_edge_share``) are at an edge has none, and
no primitive fitted to it describes a surface.

The jump is a share of the depth, not a multiple of the noise: at 5 % of the range within two
pixels it is steeper than any surface the camera sees at up to 80 degrees from its normal (that
one changes depth by about ``2 tan(80°) / f`` of the range across two pixels: 2.2 % at f = 525
px), and ten noise levels or more for the sensors of ``tests/data/real_scans`` out to 3 m.
"""

from __future__ import annotations

import numpy as np

from shapes.segment.clusters import Cluster
from shapes.segment.params import SegmentationParams
from shapes.types import FloatArray


def edge_share(cluster: Cluster, depth_image: FloatArray, params: SegmentationParams) -> float:
    """The share of ``cluster``'s pixels within ``sliver_window_px`` of a depth jump larger than
    ``sliver_jump_ratio`` of their own depth, in ``depth_image`` (the frame's depths as an image,
    NaN where there is none: no depth is no edge), judged on at most ``sliver_samples`` of its
    pixels evenly spread over its list. 0.0 for a cluster without pixels.

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
    low = np.full(len(pixels), np.inf)
    high = np.full(len(pixels), -np.inf)
    reach = params.sliver_window_px // 2
    with np.errstate(invalid="ignore"):
        for dy in range(-reach, reach + 1):
            r = np.clip(rows + dy, 0, height - 1) * width
            for dx in range(-reach, reach + 1):
                seen = flat[r + np.clip(cols + dx, 0, width - 1)]
                low = np.fmin(low, seen)
                high = np.fmax(high, seen)
        at_edge = high - low > params.sliver_jump_ratio * here
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
