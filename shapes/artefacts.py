"""Sensor artefacts: the depth noise of a frame, flying pixels and veils, sparse outliers.

A depth sensor averages the surfaces inside a pixel at a depth edge and returns *flying pixels*
on the ray between the foreground and the background; along a silhouette they form a *veil*.
On an organised frame (a depth image, a bag or PCD with width x height) they are found in the
image:

- the noise is measured first: on a smooth surface the second difference of three neighbouring
  depths along a row is noise only, so ``sigma_1m = 1.4826 * median|d[i-1] - 2 d[i] + d[i+1]|
  / (sqrt(6) z²)`` (median: edges do not count), and ``sigma(z) = sigma_1m * z²`` as for a
  structured-light or stereo sensor whose depth comes from disparity;
- a pixel is *supported* by each of its 8 neighbours whose depth lies within
  ``T(z) = max(min_jump_m, jump_sigmas * sigma(z))`` of its own. A pixel on a surface has 3 or
  more supporting neighbours (5 on a straight edge, 3 in a corner); a mixed pixel takes a random
  depth between the two sides and has at most its few mixed neighbours on the edge line. Pixels
  with fewer than ``min_support`` supporting neighbours are dropped;
- at a depth edge (the neighbourhood spans more than T), a pixel whose surface is seen at more
  than ``max_ray_angle_deg`` from its normal (the local surface from the neighbours at +-1
  pixel lies along the ray: a veil) is dropped too.

On an unorganised cloud, the same artefacts are sparse: :func:`sparse_voxels` drops voxels with
fewer than ``min_neighbours`` occupied voxels in their 3 x 3 x 3 block (a real surface seen by
the camera fills at least a line of them), and :func:`sparse_points` drops the points of an
object far sparser than its surface (the k-th neighbour distance against the median).

>>> depth = np.full((5, 5), 1.0)
>>> depth[2, 2] = 0.8  # one flying pixel in front of a flat wall
>>> flying_pixels(depth, 0.001).nonzero()
(array([2]), array([2]))
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from scipy.spatial import cKDTree

from shapes.arrays import column_max, column_min, unique_sorted
from shapes.types import FloatArray

__all__ = ["depth_noise_1m", "flying_pixels", "sparse_points", "sparse_voxels"]

BoolArray = npt.NDArray[np.bool_]


_NOISE_ROW_STRIDE = 3


def depth_noise_1m(depth: FloatArray) -> float:
    """Robust depth noise of an image at 1 m, assuming ``sigma(z) = sigma_1m * z²``.

    NaN marks pixels without a return. Returns 0.0 when fewer than 100 triples are valid.
    A Kinect's depths are quantised (steps of 3 mm at 1 m, 1.6 cm at 2.4 m), so on a
    surface seen from afar most second differences are exactly zero and their median says
    nothing: the estimate then comes from the first of the 75th and 90th percentiles that is
    a step (at least ``_LEAST_STEP_M``), scaled as for a normal distribution.

    >>> rng = np.random.default_rng(0)
    >>> flat = 1.0 + rng.normal(0.0, 0.002, (200, 200))
    >>> round(depth_noise_1m(flat), 4)
    0.002
    """
    d = np.asarray(depth, dtype=np.float64)
    if len(d) >= 100 * _NOISE_ROW_STRIDE:  # a median over every third row is as good
        d = d[::_NOISE_ROW_STRIDE]
    second = d[:, :-2] - 2 * d[:, 1:-1] + d[:, 2:]
    z = d[:, 1:-1]
    ok = np.isfinite(second) & (z > 0)
    if ok.sum() < 100:
        return 0.0
    size = np.abs(second[ok])
    e = size / (math.sqrt(6.0) * z[ok] ** 2)
    step = size >= _LEAST_STEP_M
    for percent, normal_quantile in _NOISE_QUANTILES:
        if step.mean() > 1.0 - percent / 100.0:
            return float(np.percentile(e, percent)) / normal_quantile
    return 0.0


_LEAST_STEP_M = 5e-5
"""A second difference smaller than this is zero: half the finest depth unit of a file we read
(0.1 mm), far above the rounding of depths stored as 32-bit floats."""
_NOISE_QUANTILES = ((50.0, 0.6745), (75.0, 1.1503), (90.0, 1.6449))
"""Percentiles of |e| tried in turn, each with the same percentile of |N(0, 1)|."""


_NEIGHBOURS = [(dy, dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if (dy, dx) != (0, 0)]


def flying_pixels(
    depth: FloatArray,
    sigma_1m: float,
    *,
    min_jump_m: float = 0.01,
    jump_sigmas: float = 4.0,
    min_support: int = 3,
    max_ray_angle_deg: float = 85.0,
    focal_px: float = 570.0,
    step: int = 1,
) -> BoolArray:
    """Mask of the pixels to drop as flying pixels or veils (see the module docstring).

    ``depth`` is ``(H, W)`` in metres with NaN for no return; ``sigma_1m`` the noise at 1 m
    (:func:`depth_noise_1m`); ``focal_px`` the focal length, which sets the pixel's footprint.
    ``step``: judge only the pixels of every ``step``-th row and column (their neighbours are
    still the image's own); the mask is then ``depth[::step, ::step]``'s, the same as the full
    mask's ``[::step, ::step]`` at a fraction of the cost.

    >>> depth = np.full((5, 5), 1.0)
    >>> depth[2, 2] = 0.8
    >>> flying_pixels(depth, 0.001, step=2).nonzero()
    (array([1]), array([1]))
    """
    if step < 1:
        raise ValueError(f"step: expected a positive integer, got {step!r}")
    image = np.asarray(depth, dtype=np.float32)
    d = image[::step, ::step]
    h, w = d.shape
    valid = np.isfinite(d)
    z = np.where(valid, d, np.float32(1.0))
    jump = np.maximum(np.float32(min_jump_m), np.float32(jump_sigmas * sigma_1m) * z * z)
    padded = np.pad(image, 1, constant_values=np.nan)
    support = np.zeros(d.shape, dtype=np.int8)
    gap = np.empty_like(d)
    near = np.empty(d.shape, dtype=np.bool_)
    for dy, dx in _NEIGHBOURS:
        n = padded[1 + dy :: step, 1 + dx :: step][:h, :w]
        np.abs(np.subtract(n, d, out=gap), out=gap)
        support += np.less_equal(gap, jump, out=near)
    # The 3 x 3 extremes (NaN ignored), a row of three and then a column of three.
    lo, hi = _extremes_3x3(padded, step, (h, w))
    drop = valid & (support < min_support)
    edge = np.flatnonzero(valid & ~drop & (hi - lo > jump))
    if len(edge):
        # At a depth edge, the slope of the surface along the ray from the neighbours on
        # either side (both on the pixel's own surface): the depth change over the pixel's
        # footprint z / f. A veil runs nearly along the ray. Pixels are read by their flat
        # index (np.take), at a fraction of the cost of an index by row and column.
        ys, xs = np.divmod(edge, w)
        here, tol = np.take(d, edge), np.take(jump, edge)
        footprint = here / focal_px
        slope = np.zeros(len(edge), dtype=np.float32)
        width = padded.shape[1]
        centre = (1 + step * ys) * width + (1 + step * xs)  # the pixels in the padded image
        for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
            a = np.take(padded, centre + (dy * width + dx))
            b = np.take(padded, centre - (dy * width + dx))
            slope_here = np.abs(a - b) / (2 * footprint * math.hypot(dy, dx))
            both = (np.abs(a - here) <= tol) & (np.abs(b - here) <= tol)
            slope = np.where(both, np.maximum(slope, slope_here), slope)
        veil = slope > math.tan(math.radians(max_ray_angle_deg))
        np.put(drop, edge[veil], True)
    return np.asarray(drop, dtype=np.bool_)


def _extremes_3x3(
    padded: npt.NDArray[np.float32], step: int, shape: tuple[int, int]
) -> tuple[FloatArray, FloatArray]:
    """The smallest and largest value of the 3 x 3 neighbourhood (itself included, NaN
    ignored) of every ``step``-th pixel of every ``step``-th row of an image padded by one
    pixel; ``shape``: how many such pixels down and across."""
    h, w = shape
    out = []
    for pick in (np.fmin, np.fmax):
        rows = pick(pick(padded[:, :-2:step], padded[:, 1:-1:step]), padded[:, 2::step])
        rows = rows[:, :w]
        out.append(pick(pick(rows[:-2:step], rows[1:-1:step]), rows[2::step])[:h])
    return out[0], out[1]


def sparse_voxels(
    voxels: FloatArray, voxel_m: float, min_neighbours: int = 2, among: FloatArray | None = None
) -> BoolArray:
    """Mask of voxel centres with fewer than ``min_neighbours`` occupied voxels around them
    (in their 3 x 3 x 3 block of the grid), counted among ``among`` (default: ``voxels``).

    >>> line = np.array([[0.0, 0, 0], [0.01, 0, 0], [0.02, 0, 0], [0.5, 0.5, 0.5]])
    >>> sparse_voxels(line, 0.01).tolist()
    [True, False, True, True]
    """
    every = voxels if among is None else among
    cells = np.floor(every / voxel_m + 0.5).astype(np.int64)
    origin = column_min(cells) - 1
    span = column_max(cells) - origin + 2

    def flat_keys(c: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
        k = c - origin
        return np.asarray((k[:, 0] * span[1] + k[:, 1]) * span[2] + k[:, 2], dtype=np.int64)

    # Each occupied cell once (two voxel means may round to one cell), and three sentinels
    # past the end, so that the column read below never runs off it.
    sentinel = np.iinfo(np.int64).max
    occupied = np.concatenate((unique_sorted(flat_keys(cells)), np.full(3, sentinel)))
    keys = flat_keys(cells if among is None else np.floor(voxels / voxel_m + 0.5).astype(np.int64))
    # Probed in sorted order (each probe is the sorted keys plus a constant), which
    # searchsorted walks through far faster than keys in voxel order.
    order = np.argsort(keys, kind="stable")
    flat = keys[order]
    count = np.zeros(len(voxels), dtype=np.int64)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            # A column of three cells (dz = -1, 0, 1) is three consecutive keys: one search
            # finds the first, and the occupied ones among them follow it in the sorted keys.
            middle = flat + (dx * span[1] + dy) * span[2]
            at = np.searchsorted(occupied, middle - 1)
            for j in range(3):
                found = occupied[at + j] <= middle + 1
                if dx == dy == 0:
                    found &= occupied[at + j] != middle  # the voxel's own cell
                count += found
    sparse = np.empty(len(voxels), dtype=np.bool_)
    sparse[order] = count < min_neighbours
    return sparse


def sparse_points(points: FloatArray, neighbours: int = 8, ratio: float = 2.5) -> BoolArray:
    """Mask of the points of one object whose ``neighbours``-th nearest neighbour is more than
    ``ratio`` times farther than the median point's: flying pixels and veils in an unorganised
    cloud, which thin out along the rays while the surface keeps the sensor's pixel density.

    >>> rng = np.random.default_rng(0)
    >>> surface = np.column_stack((rng.random((400, 2)) * 0.05, np.zeros(400)))
    >>> veil = np.array([[0.02, 0.02, 0.03], [0.02, 0.02, 0.06]])
    >>> sparse_points(np.vstack((surface, veil)))[-2:].tolist(), int(sparse_points(surface).sum())
    ([True, True], 0)
    """
    if len(points) <= neighbours + 1:
        return np.zeros(len(points), dtype=np.bool_)
    dist, _ = cKDTree(points).query(points, k=neighbours + 1)
    far = dist[:, -1]
    return np.asarray(far > ratio * np.median(far), dtype=np.bool_)
