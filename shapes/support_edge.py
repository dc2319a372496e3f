"""What stands under a support's edge is a part of the support (stop 38).

A camera looking down at a desk sees, through the gap under the desk's front edge, the floor
and what stands on it there: the desk's legs, its modesty panel, the frame under its top. Each
is a cluster on the floor, a lower support, and passes every rule of an object: it stands on
the floor inside its outline, and its top is not seen hanging. It is not seen at all: the
desk's edge hides it. Such a cluster goes on up, out of view, towards the desk; it is a part
of the desk, not an object of the scene.

A cluster on one support, wholly under a higher support's plane, stands under that support's
edge when

- its footprint reaches under the higher support (:func:`reaches_under`): one of its voxels,
  across the supports, lies inside the convex hull of the higher support's main piece grown by
  ``margin_m``;
- and the higher support hides its top (:func:`hidden_by_edge`): on at least
  ``min_hidden_share`` of the lines across the image on which the cluster has points (columns,
  for a camera looking down at a table), the first pixel past its outermost pixel away from
  the image's open edge that lies nearer than it by ``nearer_m``, within ``probe_px``
  (:func:`occluders_above`), is a point of the higher support's edge: no higher than
  ``nearer_m`` over its plane and no lower than ``edge_depth_m`` under it (the
  thickness of a table's top, its front face and its apron).

An object on the floor under a table whose top the camera sees (a bin standing clear of the
edge in view, whose top shows with the floor or a wall above it) keeps its top in view and is
kept; so is one whose top a chair's seat hides (the seat lies far under the table's plane), and
one that stands clear of the table's outline. What is dropped with the legs is an object on the
floor under the table whose top the table's edge hides (a bin pushed under a desk, seen only
through the gap): the camera does not see its top, and cannot tell it from a leg.

>>> from shapes.support_region import support_region
>>> ticks = np.arange(0.0, 1.0, 0.05)
>>> desk_xy = np.array([[x, y] for x in ticks for y in ticks])  # a desk 1 m square, 0.7 m up
>>> desk = support_region(desk_xy, 0.05)  # its main piece's outline; its plane is z = 0.7
>>> leg = np.array([[0.02, 0.02, z] for z in np.arange(0.0, 0.2, 0.01)])  # its foot, in view
>>> hidden = np.array([-0.01, -0.02, -0.03])  # the heights over the desk of what hides its top
>>> reaches_under(leg, desk, margin_m=0.05)
True
>>> hidden_by_edge(hidden, 3, edge_depth_m=0.08, nearer_m=0.03, min_hidden_share=0.5)
True
>>> chair = np.array([-0.25, -0.26, -0.24])  # a chair's seat hides it instead: an object
>>> hidden_by_edge(chair, 3, edge_depth_m=0.08, nearer_m=0.03, min_hidden_share=0.5)
False
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shapes.support_region import SupportRegion
from shapes.types import FloatArray
from shapes.view import ImageView

__all__ = ["hidden_by_edge", "occluders_above", "reaches_under"]


def occluders_above(
    view: ImageView,
    pixels: npt.NDArray[np.intp],
    depth_m: FloatArray,
    depth_image: FloatArray,
    probe_px: int,
    nearer_m: float,
) -> tuple[int, npt.NDArray[np.intp]]:
    """How many lines across the image a region has pixels on (columns, when the open edge
    is the top or bottom one; rows otherwise), and the flat pixels, one for each line where
    one is found, of the first pixel past the region's outermost pixel *away* from the open
    edge, within ``probe_px``, whose depth in ``depth_image`` (NaN where none) is more than
    ``nearer_m`` nearer than that outermost pixel's (``depth_m``, the region's depths): what
    hides the region's top, as :meth:`ImageView.hidden_below` finds what hides its bottom."""
    row, col = np.divmod(np.asarray(pixels), view.width)
    vertical = view.open_edge in ("top", "bottom")
    along, across = (row, col) if vertical else (col, row)
    limit = depth_image.shape[0] if vertical else view.width
    away = -1 if view.open_edge in ("bottom", "right") else 1
    order = np.lexsort((along * away, across))  # the outermost pixel away from the edge last
    last = np.r_[across[order][1:] != across[order][:-1], True]
    ends = order[last]
    found = np.full(len(ends), -1, dtype=np.intp)
    for step in range(1, probe_px + 1):
        beyond = along[ends] + away * step
        open_ = np.flatnonzero((found < 0) & (beyond >= 0) & (beyond < limit))
        r, c = (beyond, across[ends]) if vertical else (across[ends], beyond)
        flat = r[open_] * view.width + c[open_]
        nearer = depth_image.ravel()[flat] < depth_m[ends[open_]] - nearer_m
        found[open_[nearer]] = flat[nearer]
    return len(ends), found[found >= 0]


def reaches_under(voxels: FloatArray, region: SupportRegion, margin_m: float) -> bool:
    """Whether a cluster's footprint reaches under a higher support: one of its ``voxels``
    (world frame) lies, across the supports, inside the hull of the higher support's main
    piece (``region``) grown by ``margin_m``."""
    return bool(region.contains(voxels[:, :2], margin_m).any())


def hidden_by_edge(
    occluder_heights: FloatArray,
    lines: int,
    *,
    edge_depth_m: float,
    nearer_m: float,
    min_hidden_share: float,
) -> bool:
    """Whether a higher support's edge hides a cluster's top: of the ``lines`` across the
    image the cluster has points on, at least ``min_hidden_share`` have what hides them
    (``occluder_heights``: each one's height over the support, :func:`occluders_above`) no
    lower than ``edge_depth_m`` under the support's plane and no higher than ``nearer_m``
    over it."""
    edge = (occluder_heights >= -edge_depth_m) & (occluder_heights <= nearer_m)
    return lines > 0 and int(edge.sum()) >= min_hidden_share * lines
