"""A cluster's outline as the sensor sees it: its width, row by row, on a plane across the rays.

Range noise moves a point along its own ray; the ray's direction (the pixel) is exact. So the
outline of a cluster in the image keeps its shape however coarse or noisy the depths are. Each
point is moved along its ray onto the plane through the cluster's median point square to that
point's ray; there its coordinates are its place in the image, scaled by the range to metres. The
rows run along "up" (the support's normal, as the image shows it) and the widths across it.

:func:`outline_rows` gives the width of each row; :func:`top_fullness` reads from them how
the outline closes at its top: a sphere's outline is a circle, so over its top half width the
rows fill π/4 of the widest; a cone's narrows linearly to its apex (half or less); a standing
cylinder's top is the ellipse of its end disc, flatter than a circle (more than π/4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from shapes.types import FloatArray

__all__ = ["Outline", "outline_rows", "pointed", "top_fullness", "top_lean"]


@dataclass(frozen=True)
class Outline:
    """A cluster's outline, row by row from its top down (all in metres, on the plane across
    the median point's ray at its range): each row's distance under the outline's top,
    its width, its middle across (from the median point's ray), and the pitch of a pixel
    there."""

    depth_m: FloatArray
    width_m: FloatArray
    middle_m: FloatArray
    pitch_m: float

    @property
    def widest_m(self) -> float:
        """The outline's width: the 90th percentile of its rows' widths (a stray row's pixel
        or two does not count)."""
        return float(np.percentile(self.width_m, 90))


def outline_rows(
    points: FloatArray, viewpoint: FloatArray, up: FloatArray, *, min_rows: int = 4
) -> Outline | None:
    """The outline of ``points`` seen from ``viewpoint`` (module docstring), its rows square to
    ``up`` projected on the plane across the median point's ray; None when fewer than
    ``min_rows`` rows hold points, or when ``up`` lies within about 12° of that ray (a view from
    straight above has no rows by height).

    The row pitch is the points' median spacing on that plane (a pixel, for a full-resolution
    organised cluster); a row's width is the span of its points across plus one pitch.

    >>> x, z = np.meshgrid(np.arange(-0.05, 0.05, 0.002) + 0.001, np.arange(-0.05, 0.05, 0.002))
    >>> inside = x**2 + z**2 < 0.05**2  # a disc of radius 5 cm, 2 m ahead, on a 2 mm grid
    >>> disc = np.column_stack((x[inside], np.full(inside.sum(), 2.0), z[inside]))
    >>> o = outline_rows(disc, np.zeros(3), np.array([0.0, 0.0, 1.0]))
    >>> round(o.widest_m, 3), round(top_fullness(o), 2)
    (0.1, 0.8)
    """
    pts = np.asarray(points, dtype=np.float64)
    eye = np.asarray(viewpoint, dtype=np.float64)
    if len(pts) < 10:
        return None
    centre = np.median(pts, axis=0)
    view = centre - eye
    reach = float(np.linalg.norm(view))
    if reach <= 0:
        return None
    view /= reach
    n = np.asarray(up, dtype=np.float64)
    rows_dir = n - (n @ view) * view
    if np.linalg.norm(rows_dir) < 0.2:  # seen from within about 12° of straight above
        return None
    rows_dir /= np.linalg.norm(rows_dir)
    across_dir = np.cross(view, rows_dir)
    rays = pts - eye
    along = rays @ view
    if np.any(along <= 0):
        return None
    on_plane = rays * (reach / along)[:, None]
    across = on_plane @ across_dir
    height = on_plane @ rows_dir
    flat = np.column_stack((across, height))
    spacing, _ = cKDTree(flat).query(flat, k=2)
    pitch = float(np.median(spacing[:, 1]))
    if not pitch > 0:
        return None
    top = float(height.max())
    index = np.floor((top - height) / pitch).astype(np.intp)
    order = np.argsort(index, kind="stable")
    index, across = index[order], across[order]
    starts = np.flatnonzero(np.r_[True, index[1:] != index[:-1]])
    if len(starts) < min_rows:
        return None
    right, left = np.maximum.reduceat(across, starts), np.minimum.reduceat(across, starts)
    depth = (index[starts] + 0.5) * pitch
    return Outline(
        np.asarray(depth, dtype=np.float64),
        np.asarray(right - left + pitch, dtype=np.float64),
        np.asarray((right + left) / 2, dtype=np.float64),
        pitch,
    )


def top_fullness(outline: Outline) -> float | None:
    """The mean width of the outline's rows over its top half width (the rows no deeper under
    its top than half its widest), as a share of the widest; None when the outline is not that
    tall. About π/4 for a circle, 1/2 for a cone whose apex is in view and that reaches its
    widest no higher than half that width under it, up to 1 for a rectangle (module docstring).

    >>> d = np.arange(0.0, 0.1, 0.002) + 0.001
    >>> circle = Outline(d, 2 * np.sqrt(np.maximum(0.05**2 - (d - 0.05) ** 2, 0)), 0 * d, 0.002)
    >>> round(top_fullness(circle), 2)
    0.79
    """
    half = outline.widest_m / 2
    if outline.depth_m.max() + outline.pitch_m / 2 < half:
        return None
    # Rows with no point (a gap) count as empty: sum over the pitch's rows, not the present.
    top_rows = outline.depth_m < half
    rows = max(1, round(half / outline.pitch_m))
    return float(np.minimum(outline.width_m[top_rows], outline.widest_m).sum() / rows / (2 * half))


def top_lean(outline: Outline) -> float:
    """How far the middles of the outline's rows over its top half width stray from the middle
    of its widest rows, on average, as a share of its width: about 0 for a thing standing
    upright and whole in view (a cone, a sphere, a standing cylinder: their outlines are
    symmetric about the image of the vertical through them); more for a part whose one side is
    cut (a sliver of a ball left by a split or an occluder) or a thing leaning.

    >>> d = np.arange(0.0, 0.05, 0.002) + 0.001
    >>> arc = 2 * np.sqrt(np.maximum(0.05**2 - (d - 0.05) ** 2, 0))
    >>> round(top_lean(Outline(d, arc, 0 * d, 0.002)), 2)  # a whole circle's top
    0.0
    >>> round(top_lean(Outline(d, arc / 2, -arc / 4, 0.002)), 2)  # its left half alone
    0.2
    """
    widest = outline.width_m >= np.percentile(outline.width_m, 90)
    axis = float(np.median(outline.middle_m[widest]))
    top = outline.depth_m < outline.widest_m / 2
    if not top.any():
        return 0.0
    return float(np.abs(outline.middle_m[top] - axis).mean() / outline.widest_m)


def pointed(
    outline: Outline, *, threshold_m: float, coarse_share: float, max_fullness: float
) -> bool:
    """Whether ``outline`` closes to a point at its top where the depths cannot tell the kinds:
    the selection threshold ``threshold_m`` at least ``coarse_share`` of half the outline's
    width, and its :func:`top_fullness` below ``max_fullness``. A sphere's outline (a circle)
    or a standing cylinder's (a rectangle under the ellipse of its top) never does; a cone's,
    apex up, does.

    >>> d = np.arange(0.0, 0.1, 0.002) + 0.001
    >>> h = np.repeat(d, 50)
    >>> x = np.tile(np.linspace(-0.5, 0.5, 50), len(d)) * h  # a cone's outline, apex up
    >>> cone = outline_rows(np.column_stack((x, np.full(len(x), 2.0), -h)), np.zeros(3),
    ...                     np.array([0.0, 0.0, 1.0]))
    >>> pointed(cone, threshold_m=0.03, coarse_share=0.4, max_fullness=0.6)
    True
    """
    if threshold_m < coarse_share * outline.widest_m / 2:
        return False
    fullness = top_fullness(outline)
    return fullness is not None and fullness < max_fullness
