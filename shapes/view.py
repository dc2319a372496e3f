"""What a depth image sees: the rectangle of pixels that hold depths, and its edges.

A depth camera's image is a window on the scene. Something the window's edge cuts goes on
outside the view (a chair whose wheels alone are seen, a wall, a box on the floor behind), so
a cluster cut by the edge is a part of something the camera does not see whole, as one cut by
the height limit is. The window is the rectangle of rows and columns that hold depths, not the
whole image: a Kinect leaves its first and last rows and some columns empty. That margin is
narrow (on the Kinect scans, at most 17 rows and 32 columns of 640 x 480); where the valid
pixels end farther in, the scene's returns end there (a simulated table with nothing behind
it, the sky), not the view, and the window's edge is the image's own.

One edge is different: the one the camera looks down through (the image's bottom edge, for a
camera looking at a table or a floor). What it cuts is the near side and the base of an object
whose top is in view: an object standing on the support where the view begins, not a part of
something larger. That edge is the *open* edge and cuts nothing.

>>> rows, cols = np.divmod(np.arange(100 * 120), 120)  # a 100 x 120 image, every pixel valid
>>> down = np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]])  # image down (sensor y) is world -z
>>> view = image_view((100, 120), np.arange(100 * 120), down)
>>> view.rows, view.cols, view.open_edge
((0, 99), (0, 119), 'bottom')
>>> view.at_closed_edge(np.array([5 * 120 + 60, 97 * 120 + 60, 50 * 120 + 3]), band_px=8).tolist()
[True, False, True]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.types import FloatArray

__all__ = ["ImageView", "image_view"]

_EDGES = ("top", "bottom", "left", "right")
_OUTWARD = np.array([[0, -1, 0], [0, 1, 0], [-1, 0, 0], [1, 0, 0]], dtype=float)
"""Each edge's outward direction in the sensor's optical frame (x right, y down)."""


@dataclass(frozen=True)
class ImageView:
    """The window of a depth image that holds depths: its first and last rows and columns
    (inclusive), the image's width, and the edge the camera looks down through."""

    rows: tuple[int, int]
    cols: tuple[int, int]
    width: int
    open_edge: str

    def at_closed_edge(self, pixels: npt.NDArray[np.intp], band_px: int) -> npt.NDArray[np.bool_]:
        """Which of the flat row-major ``pixels`` lie within ``band_px`` of an edge of the
        window other than the open one."""
        row, col = np.divmod(np.asarray(pixels), self.width)
        gaps = {
            "top": row - self.rows[0],
            "bottom": self.rows[1] - row,
            "left": col - self.cols[0],
            "right": self.cols[1] - col,
        }
        near = np.zeros(len(row), dtype=bool)
        for edge, gap in gaps.items():
            if edge != self.open_edge:
                near |= gap <= band_px
        return near

    def cut_at_closed_edge(
        self,
        pixels: npt.NDArray[np.intp],
        band_px: int,
        depth_image: FloatArray,
        farther_m: float,
    ) -> npt.NDArray[np.bool_]:
        """Which of the flat row-major ``pixels`` (a region of ``depth_image``, which holds
        NaN where there is no depth) lie within ``band_px`` of an edge of the window other
        than the open one, on a line across that edge (a row, for the left and right edges)
        where nothing behind the region is seen between it and the edge: no pixel between the
        region's outermost pixel on that line and the window's edge holds a depth more than
        ``farther_m`` beyond that pixel's. Where the background shows past its outline, the
        region ends in view there, and the edge does not cut it."""
        pixels = np.asarray(pixels)
        row, col = np.divmod(pixels, self.width)
        flat = depth_image.ravel()
        lines = {  # edge: (distance to it, the line across it, outward step in flat pixels)
            "top": (row - self.rows[0], col, -self.width),
            "bottom": (self.rows[1] - row, col, self.width),
            "left": (col - self.cols[0], row, -1),
            "right": (self.cols[1] - col, row, 1),
        }
        cut = np.zeros(len(pixels), dtype=bool)
        for edge, (gap, across, step) in lines.items():
            near = np.flatnonzero(gap <= band_px)
            if edge == self.open_edge or not len(near):
                continue
            # The outermost pixel of each line, and whether anything farther shows past it.
            order = near[np.lexsort((gap[near], across[near]))]
            first = np.r_[True, across[order][1:] != across[order][:-1]]
            ends = order[first]
            behind_m = flat[pixels[ends]] + farther_m
            seen_behind = np.zeros(len(ends), dtype=bool)
            for k in range(1, band_px + 1):
                inside = np.flatnonzero(gap[ends] >= k)
                beyond = flat[pixels[ends[inside]] + k * step]
                seen_behind[inside[beyond > behind_m[inside]]] = True
            line_cut = np.isin(across[near], across[ends][~seen_behind])
            cut[near[line_cut]] = True
        return cut

    def hidden_below(
        self,
        pixels: npt.NDArray[np.intp],
        depth_m: FloatArray,
        depth_image: FloatArray,
        probe_px: int,
        nearer_m: float,
    ) -> float:
        """The share of a region's lines across the image whose last pixel towards the open
        edge has, within ``probe_px`` beyond it, a pixel of ``depth_image`` more than
        ``nearer_m`` nearer than the region there: where its lower edge is the outline of
        something in front of it (an occluder), not its own. ``pixels`` are flat row-major,
        ``depth_m`` their depths; the depth image holds NaN where there is no depth."""
        row, col = np.divmod(np.asarray(pixels), self.width)
        vertical = self.open_edge in ("top", "bottom")
        along, across = (row, col) if vertical else (col, row)
        limit = depth_image.shape[0] if vertical else self.width
        sign = 1 if self.open_edge in ("bottom", "right") else -1
        order = np.lexsort((along * sign, across))
        last = np.r_[across[order][1:] != across[order][:-1], True]
        ends = order[last]
        end_across, end_depth = across[ends], depth_m[ends]
        hidden = np.zeros(len(ends), dtype=bool)
        for step in range(1, probe_px + 1):
            beyond = along[ends] + sign * step
            inside = (beyond >= 0) & (beyond < limit)
            r, c = (beyond, end_across) if vertical else (end_across, beyond)
            found = depth_image[r[inside], c[inside]] < end_depth[inside] - nearer_m
            hidden[np.flatnonzero(inside)[found]] = True
        return float(hidden.mean()) if len(ends) else 0.0


def image_view(
    shape: tuple[int, int],
    pixels: npt.NDArray[np.intp],
    world_from_sensor_rotation: FloatArray,
    min_valid_share: float = 0.01,
    max_margin_share: float = 0.1,
) -> ImageView:
    """The window of an image of ``shape`` (rows, columns) whose valid pixels are the flat
    row-major ``pixels``: the first and last rows (columns) in which at least
    ``min_valid_share`` of the pixels hold a depth (a few stray depths in the empty margin
    move nothing). An empty margin wider than ``max_margin_share`` of the image is no
    margin of the sensor's, and the window reaches the image's edge there. Its open edge is
    the one whose outward direction points most downward in
    the world (world z is up), given the sensor's rotation into the world.

    With no row (column) holding that share, the window spans the image's rows (columns).
    """
    height, width = int(shape[0]), int(shape[1])
    per_pixel = np.bincount(np.asarray(pixels), minlength=height * width)
    if len(per_pixel) == height * width:
        # The counts of each row and column from one count per pixel: the same integers as
        # counting each pixel's row and column, at half the cost of dividing every index.
        counts = per_pixel.reshape(height, width)
        per_row, per_column = counts.sum(axis=1), counts.sum(axis=0)
    else:  # pixels past the image's end (a :class:`Frame` holds none)
        row, col = np.divmod(np.asarray(pixels), width)
        per_row, per_column = np.bincount(row, minlength=height), np.bincount(col, minlength=width)
    rows = np.flatnonzero(per_row >= min_valid_share * width)
    cols = np.flatnonzero(per_column >= min_valid_share * height)
    rows = rows if len(rows) else np.array([0, height - 1])
    cols = cols if len(cols) else np.array([0, width - 1])
    downward = _OUTWARD @ np.asarray(world_from_sensor_rotation)[2]
    return ImageView(
        _within_margin(int(rows[0]), int(rows[-1]), height, max_margin_share),
        _within_margin(int(cols[0]), int(cols[-1]), width, max_margin_share),
        width,
        _EDGES[int(np.argmin(downward))],
    )


def _within_margin(first: int, last: int, size: int, max_margin_share: float) -> tuple[int, int]:
    """The first and last valid row (column), each moved to the image's edge when the empty
    margin before it is wider than ``max_margin_share`` of the ``size``."""
    margin = max_margin_share * size
    return (first if first <= margin else 0, last if size - 1 - last <= margin else size - 1)
