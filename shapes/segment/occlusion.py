"""Clusters parted at occlusion edges: what stands in front of another thing is not that thing.

Step 6 of :mod:`shapes.segment`, after the splitter (:mod:`shapes.segment.splitting`), which
cuts only at concave seams. A thing lying in front of another (a mallet's handle 3 cm in front
of a box, 0.45 m from the camera) meets it in the image at an occlusion edge: the depth steps
from the near surface to the far one between neighbouring pixels, or along a short ramp of mixed
depths where the sensor smooths. DBSCAN joins the two across the step when it is shorter than
``cluster_eps_m``.

In the image, a cluster's points are joined into *surfaces*: neighbouring pixels whose depths
differ by less than ``occlusion_slope`` times their distance across the ray (a surface turned
less than about 56° from the camera), or by less than ``occlusion_noise_multiple`` times the
depth noise. The points of a steeper step (the ramp of an occlusion edge, and a face seen nearly
edge-on) join nothing. A surface that lies nearer than its neighbour across most of the steps
they share is in front of it. A surface that stands on the support and lies across others (in
front of two that show on either side of it and reach away from it) is cut off as a part of its
own; the rest stays one part, even where the thing in front hides a band of it from top to
bottom (the box's two halves left and right of the handle). What hangs in from an edge of the
image's window (a hand holding the box) is cut off too, so that the edge judges it alone
(:func:`parts_in_front`).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy import ndimage
from scipy.spatial import cKDTree

from shapes.arrays import norm3
from shapes.types import FloatArray

# The four forward neighbours on the pixel grid: right, down, down-right, down-left.
_STEPS = ((0, 1), (1, 0), (1, 1), (1, -1))


def surfaces(
    points: FloatArray,
    depth: FloatArray,
    pixels: npt.NDArray[np.intp],
    image_width: int,
    max_slope: float,
    min_step_m: FloatArray | float = 0.0,
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    """The surface of each point (labels 0, 1, ...) and which surface is in front of which.

    ``points`` (any metric frame), their ``depth`` along the camera's axis and their flat
    row-major ``pixels`` in an image ``image_width`` wide, on one pixel grid (every k-th row and
    column). Neighbouring points (8-neighbours on the grid) lie on one surface when their depths
    differ by at most ``max_slope`` times their distance across the ray, or by at most
    ``min_step_m`` (per point: many times the depth noise at its range); a point with a steeper
    step to any neighbour joins no surface itself and takes the label of the nearest point in
    the image that does. The second array holds, per pair of surfaces ``(a, b)`` across which
    steps were seen, ``a`` in front of ``b`` (rows of two labels): ``a`` is nearer than ``b``
    on more of their steps than the reverse.

    >>> depth = np.r_[np.full(4, 1.0), np.full(4, 1.1)]
    >>> pixels = np.arange(8) * 2  # one row, every other pixel
    >>> points = np.column_stack([np.arange(8) * 0.002, np.zeros(8), depth])
    >>> labels, front = surfaces(points, depth, pixels, 16, 2.0)
    >>> labels.tolist(), front.tolist()
    ([0, 0, 0, 0, 1, 1, 1, 1], [[0, 1]])
    """
    rows, cols = np.divmod(pixels, image_width)
    # The grid's step: the gcd of the distinct offsets (a few hundred), not of every point's two.
    offsets = np.r_[rows - rows.min(), cols - cols.min()]
    stride = int(np.gcd.reduce(np.flatnonzero(np.bincount(offsets)))) or 1
    r, c = (rows - rows.min()) // stride, (cols - cols.min()) // stride + 1
    grid = np.full((int(r.max()) + 2, int(c.max()) + 2), -1, dtype=np.int64)
    grid[r, c] = np.arange(len(points))
    h, w = grid.shape
    # Depths and noise bounds on the grid (NaN where no point: no step there).
    near = np.full(grid.shape, np.nan)
    near[r, c] = depth
    least = np.zeros(grid.shape)
    least[r, c] = np.broadcast_to(np.asarray(min_step_m, dtype=np.float64), depth.shape)
    first, second = [], []
    for dr, dc in _STEPS:
        ra, ca = slice(0, h - dr), slice(1, w - 1)
        rb, cb = slice(dr, h), slice(1 + dc, w - 1 + dc)
        # Only the steps over the noise need their distance across the ray (most pairs are not).
        over = np.abs(near[ra, ca] - near[rb, cb]) > np.maximum(least[ra, ca], least[rb, cb])
        first.append(grid[ra, ca][over])
        second.append(grid[rb, cb][over])
    a, b = np.concatenate(first), np.concatenate(second)
    step = np.abs(depth[a] - depth[b])
    apart = norm3(np.take(points, a, axis=0) - np.take(points, b, axis=0))
    across = np.sqrt(np.maximum(apart**2 - step**2, 0.0))
    steep = step > max_slope * across
    a, b = a[steep], b[steep]
    n = len(points)
    if len(a) == 0:
        return np.zeros(n, dtype=np.int64), np.zeros((0, 2), dtype=np.int64)
    smooth = np.ones(len(points), dtype=bool)
    smooth[a] = False
    smooth[b] = False
    if not smooth.any():
        return np.zeros(n, dtype=np.int64), np.zeros((0, 2), dtype=np.int64)
    # Two smooth neighbours never step steeply (a steep step makes both ends steep): the
    # surfaces are the 8-connected pieces of the smooth points on the grid, numbered in the
    # order of their first point.
    on_grid = np.zeros(grid.shape, dtype=bool)
    on_grid[r[smooth], c[smooth]] = True
    pieces, count = ndimage.label(on_grid, structure=np.ones((3, 3), dtype=bool))
    earliest = np.full(count + 1, n)
    np.minimum.at(earliest, pieces[r[smooth], c[smooth]], np.flatnonzero(smooth))
    rank = np.full(count + 1, -1, dtype=np.int64)
    rank[1:] = np.argsort(np.argsort(earliest[1:], kind="stable"), kind="stable")
    # A steep point takes the surface of the nearest smooth point in the image.
    on_surface = rank[pieces]
    near_r, near_c = ndimage.distance_transform_edt(
        on_surface < 0, return_distances=False, return_indices=True
    )
    labels = on_surface[near_r[r, c], near_c[r, c]]
    # Numbered 0, 1, ... in the order of the labels left (np.unique's inverse; the labels are
    # small non-negative numbers, so a count of each stands in for its sort).
    present = np.bincount(labels) > 0
    labels = (np.cumsum(present) - 1)[labels].astype(np.int64)
    la, lb = labels[a], labels[b]
    cross = la != lb
    nearer = np.where(depth[a] < depth[b], la, lb)[cross]
    farther = np.where(depth[a] < depth[b], lb, la)[cross]
    count = int(labels.max()) + 1
    votes = np.bincount(nearer * count + farther, minlength=count * count).reshape(count, count)
    front = np.argwhere(votes > votes.T)
    return labels, front.astype(np.int64)


def parts_in_front(
    labels: npt.NDArray[np.int64],
    front: npt.NDArray[np.int64],
    voxel_of: npt.NDArray[np.intp],
    heights: FloatArray,
    image_at: FloatArray,
    at_edge: npt.NDArray[np.bool_] | None = None,
    *,
    points: FloatArray,
    min_voxels: int,
    max_base_height_m: float,
    min_reach_m: float,
    min_edge_points: int = 3,
) -> npt.NDArray[np.int64]:
    """The parts of one cluster's voxels (labels 0, 1, ...; all 0: no cut), from its points'
    surface ``labels`` and ``front`` (:func:`surfaces`).

    ``voxel_of``: each point's voxel among the cluster's (0 to len(``heights``) - 1);
    ``heights``: each voxel's height over the support; ``image_at``: each point's row and
    column in the image, ``points`` its position (metres); ``at_edge``: which points lie at an
    edge of the image's window that cuts what crosses it (None: none). A voxel belongs to the
    surface most of its points lie on. Parts are cut off, in this order, only while the voxels
    left hold ``min_voxels`` or more and stand on the support (lowest under
    ``max_base_height_m``):

    - the surfaces that hold ``min_edge_points`` points or more at the image's edge and hang
      over the support (their lowest voxel at ``max_base_height_m`` or more), together: a hand
      or an arm reaching into the scene, whatever it holds;
    - each surface of ``min_voxels`` voxels or more that stands on the support, behind no other
      as large, and lies across one: in front of two such surfaces that show on opposite sides
      of it in the image (their centres on either side of its own), each reaching away from it
      (the median distance of its points to the surface's nearest one) ``min_reach_m`` or
      more, and holding together more voxels than it. A thing lying across another, as a handle
      in front of a box. A cup's front wall hides its inside on one side only, the bands of a
      round thing's or a box's sides, seen edge-on on both sides of its front, hug its outline,
      and the slivers of a bowl's inside and rim beside its near wall are smaller than the wall.
    """
    count = int(labels.max()) + 1
    votes = np.bincount(voxel_of * count + labels, minlength=len(heights) * count)
    surface = votes.reshape(len(heights), count).argmax(axis=1)
    size = np.bincount(surface, minlength=count)
    lowest = np.full(count, np.inf)
    np.minimum.at(lowest, surface, heights)
    stands = lowest < max_base_height_m
    parts = np.zeros(len(heights), dtype=np.int64)

    def cut_off(mine: npt.NDArray[np.bool_]) -> None:
        rest = (parts == 0) & ~mine
        if (
            mine.any()
            and int(rest.sum()) >= min_voxels
            and float(heights[rest].min()) < max_base_height_m
        ):
            parts[mine & (parts == 0)] = int(parts.max()) + 1

    if at_edge is not None:
        edge_points = np.bincount(labels[at_edge], minlength=count)
        reaching = (edge_points >= min_edge_points) & (size > 0) & ~stands
        cut_off(reaching[surface])
    # Only surfaces of an object's size count: a few mixed pixels at an edge hide nothing.
    large = size >= min_voxels
    front = front[large[front[:, 0]] & large[front[:, 1]]]
    behind = set(front[:, 1].tolist())
    centre = np.zeros((count, 2))
    for axis in range(2):
        centre[:, axis] = np.bincount(labels, weights=image_at[:, axis], minlength=count)
    centre /= np.maximum(np.bincount(labels, minlength=count), 1)[:, None]
    for label in sorted(set(front[:, 0].tolist()) - behind):
        if not stands[label]:
            continue
        hidden = front[front[:, 0] == label, 1]
        towards = centre[hidden] - centre[label]
        opposite = np.argwhere(np.triu(towards @ towards.T < 0))
        if len(opposite) == 0:
            continue
        tree = cKDTree(points[labels == label])
        away = {
            int(k): float(np.median(tree.query(points[labels == k])[0]))
            for k in np.unique(hidden[opposite])
        }
        # What shows of the thing behind, on its two sides, outweighs the band in front of it;
        # a container's near wall outweighs the slivers of its own inside and rim beside it.
        if any(
            min(away[hidden[i]], away[hidden[j]]) >= min_reach_m
            and size[hidden[i]] + size[hidden[j]] > size[label]
            for i, j in opposite
        ):
            cut_off(surface == label)
    return parts
