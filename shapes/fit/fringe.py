"""The fringe of a cluster's outline as the sensor sees it, and a standing thing's side wall.

A depth camera's pixels along a depth edge measure neither surface well: a structured-light or
stereo sensor (the Kinect) spreads the nearer surface's depth a few pixels past the edge, and
others return mixed depths between the two. Those points lie off every model of the object
near its outline, and they pull the fit towards a model wider than the thing (the TUM desk's
roll of tape: docs/perception.md, "Rings and outlines (stop 38)"). :func:`fringe` finds the
points on that fringe, so that the choice can leave the ones a model does not explain out of its
cost; :func:`side_wall_circle` measures a standing round thing's circle from its side wall
alone, as ``tests/data/real_scans/measure.py`` measures the ground truth, so that a fringe or an
open top does not pull it.
"""

from __future__ import annotations

import numpy as np

from shapes.fit.models import Mask
from shapes.types import FloatArray, SupportPlane

__all__ = ["fringe", "side_wall_circle"]


_STEP_POINTS = 64
"""The points, at most, whose nearest neighbours give the image's step: those nearest the
middle of the cluster's image."""


def _across(direction: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Two unit vectors square to ``direction`` (a unit vector) and to each other.

    >>> [(v + 0.0).tolist() for v in _across(np.array([0.0, 0.0, 1.0]))]
    [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    x, y, z = (float(c) for c in direction)
    # The cross products written out: numpy's cross costs more than the rest on 3-vectors.
    u = (0.0, z, -y) if abs(x) < 0.9 else (-z, 0.0, x)  # with (1, 0, 0), else (0, 1, 0)
    norm = (u[0] ** 2 + u[1] ** 2 + u[2] ** 2) ** 0.5
    e1 = (u[0] / norm, u[1] / norm, u[2] / norm)
    e2 = (y * e1[2] - z * e1[1], z * e1[0] - x * e1[2], x * e1[1] - y * e1[0])
    return np.array(e1), np.array(e2)


def _eroded(grid: Mask, cells: int) -> Mask:
    """The cells of ``grid`` whose square of ``cells`` cells every way is all set (an erosion
    by a 3 x 3 square ``cells`` times, nothing set beyond the grid), by an integral image.

    >>> _eroded(np.ones((4, 5), dtype=bool), 1).astype(int).tolist()
    [[0, 0, 0, 0, 0], [0, 1, 1, 1, 0], [0, 1, 1, 1, 0], [0, 0, 0, 0, 0]]
    """
    width = 2 * cells + 1
    sums = np.pad(np.pad(grid, cells).astype(np.int32).cumsum(0).cumsum(1), ((1, 0), (1, 0)))
    window = sums[width:, width:] - sums[:-width, width:] - sums[width:, :-width]
    return np.asarray(window + sums[:-width, :-width] == width * width)


def _quantile(values: FloatArray, share: float) -> float:
    """The value ``share`` of the way up the sorted ``values`` (the nearest rank below; no
    interpolation, which costs more than the selection)."""
    k = int(share * (len(values) - 1))
    return float(np.partition(values, k)[k])


def _median(values: FloatArray) -> float:
    return _quantile(values, 0.5)


def fringe(points: FloatArray, eye: FloatArray, *, cells: int = 1, cell_steps: float = 1.5) -> Mask:
    """Which ``points`` lie on the fringe of the cluster's outline as seen from ``eye``.

    Each point's ray is put on the plane one unit in front of the eye, across the mean ray
    (its place in the image, whatever the sensor's pixel size). The image's step is the median
    distance from a point to its nearest neighbour there, among the 64 nearest the middle of
    the image (the pixel stride the points were taken at). On a grid of ``cell_steps`` steps
    a cell (coarse enough that the points leave no empty cell inside the cluster), the fringe
    is the cells that an erosion by ``cells`` cells removes: the points within about
    ``cells * cell_steps`` steps of the outline, the outer one and that of any hole the
    cluster has. Every point is on the fringe with fewer than 10 points.

    >>> u, v = np.meshgrid(np.arange(-20, 21) * 0.002, np.arange(-20, 21) * 0.002)
    >>> square = np.column_stack((u.ravel(), v.ravel(), np.ones(u.size)))  # 41 x 41 steps
    >>> on = fringe(square, np.zeros(3), cells=3)
    >>> steps_in = 20 - np.abs(square[:, :2]).max(axis=1) / 0.002  # steps from the outline
    >>> bool(on[steps_in < 4].all()), bool(on[steps_in > 6].any())
    (True, False)
    """
    if len(points) < 10:
        return np.ones(len(points), dtype=bool)
    rays = np.asarray(points, dtype=np.float64) - eye
    mean = rays.mean(axis=0)
    mean /= np.linalg.norm(mean)
    e1, e2 = _across(mean)
    depth = rays @ mean
    flat = np.column_stack((rays @ e1, rays @ e2)) / depth[:, None]
    # The step from a patch of the image: the points nearest the middle, pairwise (a tree over
    # them all would cost more than the rest of this function).
    off = flat - flat.mean(axis=0)
    near = (off * off).sum(axis=1)
    if len(flat) > _STEP_POINTS:
        patch = flat[np.argpartition(near, _STEP_POINTS)[:_STEP_POINTS]]
    else:
        patch = flat
    gaps = ((patch[:, None, :] - patch[None, :, :]) ** 2).sum(axis=2)
    np.fill_diagonal(gaps, np.inf)
    step = float(np.sqrt(np.median(gaps.min(axis=1))))
    if not step > 0:
        return np.ones(len(points), dtype=bool)
    cell = np.floor((flat - flat.min(axis=0)) / (cell_steps * step)).astype(np.intp)
    grid = np.zeros(tuple(cell.max(axis=0) + 1), dtype=bool)
    grid[cell[:, 0], cell[:, 1]] = True
    inner = _eroded(grid, cells)
    return np.asarray(~inner[cell[:, 0], cell[:, 1]])


def side_wall_circle(
    points: FloatArray,
    support: SupportPlane,
    *,
    cut_m: float,
    min_band_m: float,
    rounds: int = 10,
) -> tuple[FloatArray, float, Mask] | None:
    """The circle of a round thing standing on ``support``, through its side wall alone.

    The side wall is the points lower than ``cut_m`` under the thing's top (the 99th
    percentile of the heights over the support): a lid, a rim, a ring's top and what is seen
    through an open top drop out. The circle (algebraic least squares, seen along the
    support's normal) is fitted again without the side points farther from it than three
    scaled median deviations (at least ``min_band_m``), up to ``rounds`` times. Returns the
    foot of the axis on the support, the radius and which points are the side's points kept;
    None with fewer than 20 of them.

    >>> table = SupportPlane((0.0, 0.0, 1.0), 0.0)
    >>> a, h = np.meshgrid(np.linspace(-1.2, 1.2, 30), np.linspace(0.0, 0.1, 20))
    >>> a, h = a.ravel(), h.ravel()
    >>> can = np.column_stack((0.2 + 0.03 * np.sin(a), -0.03 * np.cos(a), h))
    >>> stray = np.array([[0.2, -0.07, 0.05]] * 5)  # a fringe 4 cm off the wall
    >>> foot, r, kept = side_wall_circle(np.vstack((can, stray)), table, cut_m=0.015,
    ...                                  min_band_m=0.003)
    >>> np.round(foot, 4).tolist() == [0.2, 0.0, 0.0], round(r, 4), int((~kept[-5:]).sum())
    (True, 0.03, 5)
    """
    normal = np.asarray(support.normal, dtype=np.float64)
    height = points @ normal + support.offset
    side = height < _quantile(height, 0.99) - cut_m
    e1, e2 = _across(normal)
    a, b = points @ e1, points @ e2
    kept = side
    centre, radius = np.zeros(2), 0.0
    for _ in range(rounds):
        if kept.sum() < 20:
            return None
        design = np.column_stack((a[kept], b[kept], np.ones(int(kept.sum()))))
        try:  # the normal equations: three unknowns, far cheaper than a least-squares solver
            sol = np.linalg.solve(design.T @ design, design.T @ (a[kept] ** 2 + b[kept] ** 2))
        except np.linalg.LinAlgError:
            return None
        centre = sol[:2] / 2
        radius = float(np.sqrt(max(sol[2] + centre @ centre, 0.0)))
        off = np.hypot(a - centre[0], b - centre[1]) - radius
        own = off[kept]
        spread = 1.4826 * _median(np.abs(own - _median(own)))
        again = side & (np.abs(off) <= max(3.0 * spread, min_band_m))
        if np.array_equal(again, kept):
            break
        kept = again
    if kept.sum() < 20 or not radius > 0:
        return None
    foot = centre[0] * e1 + centre[1] * e2 - support.offset * normal
    return foot, radius, kept
