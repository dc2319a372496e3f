"""Objects taller than the height band: clusters cut at its top, grown upwards.

Step 4 of :mod:`shapes.segment`: a cluster that stands on its support and is cut at the band's
top grows upwards through the free voxels over the band (:func:`grown_upwards`,
:mod:`shapes.grow_upwards`); what then ends under ``max_tall_height_m`` in view is a tall
object, what goes on is a part of something larger.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shapes.arrays import column_max, column_min, inside_box
from shapes.grow_upwards import grow_upwards
from shapes.segment.clusters import Cluster, KeptPoints
from shapes.segment.objects import (
    nearer_m,
    seen_standing,
)
from shapes.segment.params import SegmentationParams
from shapes.segment.reach import Reach, reaching
from shapes.types import FloatArray, SupportPlane


def grown_upwards(
    found: list[Cluster],
    free: npt.NDArray[np.bool_],
    box: tuple[FloatArray, FloatArray],
    kept: KeptPoints,
    reach: Reach,
    margin_m: float,
    params: SegmentationParams,
) -> list[Cluster]:
    """``found`` (clusters on one support) with each cluster seen standing on it
    (:func:`seen_standing`) and cut at the band's top (:func:`_cut_at_band_top`) grown
    upwards: joined with the ``free`` voxels over the band (:func:`_above_band`, inside ``box``
    and no farther across the support from the clusters that grow than the band's rise,
    ``max_tall_height_m - max_height_m``) that link to it within ``cluster_eps_m``
    (:func:`shapes.grow_upwards.grow_upwards`). Clusters that the voxels above join become one,
    in the first one's place. A group that reaches ``max_tall_height_m`` (``min_cut_share`` of
    its voxels within ``cut_band_m`` of it), or goes on past its top in the image
    (:func:`_goes_on_above`), does not end, and its clusters are left as they were, cut: a
    wall, a door, a person. Clusters that hang or stay within the band are left as
    they are: only what stands may reach higher, so the voxels above the band never join a
    stray part to anything."""
    seeds = [
        k
        for k, c in enumerate(found)
        if _cut_at_band_top(c, params) and seen_standing(c, margin_m, params)
    ]
    if not seeds:
        return list(found)
    support = found[seeds[0]].support
    assert support is not None
    rise = params.max_tall_height_m - params.max_height_m
    every = np.vstack([found[k].voxels[:, :2] for k in seeds])
    lo = np.maximum(box[0], column_min(every) - rise)
    hi = np.minimum(box[1], column_max(every) + rise)
    voxels = kept.voxels
    tall = _above_band(voxels, free, support, (lo, hi), params)
    if len(tall) == 0:
        return list(found)
    groups = grow_upwards([found[k].voxels for k in seeds], voxels[tall], params.cluster_eps_m)
    top = support.signed_distance(voxels[tall]) >= params.max_tall_height_m - params.cut_band_m
    grown: dict[int, Cluster] = {}
    dropped: set[int] = set()
    for members, added in groups:
        ks = [seeds[m] for m in members]
        size = len(added) + sum(len(found[k].voxels) for k in ks)
        if len(added) == 0 or (
            int(top[added].sum()) >= params.min_cut_voxels
            and int(top[added].sum()) >= params.min_cut_share * size
        ):
            continue
        marked = np.zeros(len(voxels), dtype=np.bool_)
        marked[tall[added]] = True
        idx = np.flatnonzero(marked[kept.voxel_of])
        parts = [found[k] for k in ks]
        first = parts[0]
        whole = Cluster(
            np.vstack([*(c.points for c in parts), kept.points[idx]]),
            None
            if kept.colours is None or first.colours is None
            else np.vstack(
                [
                    *(c.colours for c in parts if c.colours is not None),
                    kept.colours[0][kept.colours[1][idx]],
                ]
            ),
            np.vstack([*(c.voxels for c in parts), voxels[tall[added]]]),
            first.support,
            max([c.noise_m for c in parts] + [kept.noise_m(idx)]),
            None
            if kept.pixels is None or first.pixels is None
            else np.concatenate(
                [*(c.pixels for c in parts if c.pixels is not None), kept.pixels[idx]]
            ),
        )
        if _goes_on_above(whole, reach, params):
            continue
        grown[ks[0]] = whole
        dropped.update(ks[1:])
    return [grown.get(k, c) for k, c in enumerate(found) if k not in dropped]


def _cut_at_band_top(cluster: Cluster, params: SegmentationParams) -> bool:
    """Whether a cluster within the height band reaches its top (``min_cut_share`` of its
    voxels, and ``min_cut_voxels``, within ``cut_band_m`` of ``max_height_m``)."""
    assert cluster.support is not None
    height = cluster.support.signed_distance(cluster.voxels)
    return reaching(height >= params.max_height_m - params.cut_band_m, params)


def _above_band(
    voxels: FloatArray,
    free: npt.NDArray[np.bool_],
    support: SupportPlane,
    box: tuple[FloatArray, FloatArray],
    params: SegmentationParams,
) -> npt.NDArray[np.intp]:
    """The ``free`` voxels over the height band of ``support`` and under
    ``max_tall_height_m``, inside ``box`` (across the support): where a cluster cut at the
    band's top may go on."""
    lo, hi = box
    idx = np.flatnonzero(free & inside_box(voxels, lo, hi))
    height = support.signed_distance(voxels[idx])
    return idx[(height >= params.max_height_m) & (height < params.max_tall_height_m)]


def _goes_on_above(cluster: Cluster, reach: Reach, params: SegmentationParams) -> bool:
    """Whether a cluster grown over the band goes on past its top in the image: on at least
    ``min_hidden_share`` of its lines across the image, no pixel within ``floating_probe_px``
    past its pixel farthest from the open edge holds a depth beyond that pixel's by more than
    ``cut_band_m`` (or three times its noise). An object that ends shows what lies behind it
    there; a person's hips under the shirt a plane took, or a thing against something as near,
    do not. False when the image is unknown."""
    seen = reach.image()
    if seen is None or cluster.pixels is None:
        return False
    view, image = seen
    depth = reach.depth_of(cluster.points)
    row, col = np.divmod(np.asarray(cluster.pixels), view.width)
    vertical = view.open_edge in ("top", "bottom")
    along, across = (row, col) if vertical else (col, row)
    limit = image.shape[0] if vertical else view.width
    sign = -1 if view.open_edge in ("bottom", "right") else 1  # away from the open edge
    order = np.lexsort((along * sign, across))
    ends = order[np.r_[across[order][1:] != across[order][:-1], True]]
    margin = nearer_m(cluster, params)
    behind = np.zeros(len(ends), dtype=np.bool_)
    for step in range(1, params.floating_probe_px + 1):
        beyond = along[ends] + sign * step
        inside = (beyond >= 0) & (beyond < limit)
        r, c = (beyond, across[ends]) if vertical else (across[ends], beyond)
        found = image[r[inside], c[inside]] > depth[ends][inside] + margin
        behind[np.flatnonzero(inside)[found]] = True
    on = ~behind
    return bool(len(ends)) and float(on.mean()) >= params.min_hidden_share
