"""What segmentation finds before it needs a pose, in the sensor frame.

Steps 1 to 3 of :mod:`shapes.segment`: the points kept within the depth cut
(:func:`depth_cut_m`), artefacts dropped and strided (:func:`pixel_stride`), their voxel grid
(:func:`voxel_grid`) and the planes among the voxels (:mod:`shapes.segment.planes`). Shared by
gravity (:func:`shapes.gravity.gravity_from_survey`) and :func:`shapes.segment.segment`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from shapes.arrays import column_max, column_min, unique_inverse
from shapes.artefacts import depth_noise_1m, flying_pixels
from shapes.frame import Frame
from shapes.segment.params import SegmentationParams
from shapes.segment.planes import Plane, find_planes
from shapes.types import FloatArray


@dataclass(frozen=True, eq=False)
class Survey:
    """What segmentation finds before it needs a pose, all in the sensor frame: the points
    kept (artefacts dropped, strided), their range, their voxel grid and the planes among the
    voxels. Computed once per frame and shared by :func:`shapes.gravity.gravity_from_survey`
    (which way is up) and :func:`segment`."""

    keep: npt.NDArray[np.bool_]
    """Which of the frame's points are kept."""
    points: FloatArray
    depth: FloatArray
    """Each kept point's range (its z), or 1 for every point of a cloud not in a camera's
    frame (points at z <= 0.1 m), whose ranges are unknown."""
    voxels: FloatArray
    voxel_of: npt.NDArray[np.intp]
    tolerance: FloatArray
    """Per voxel, how far from a plane it may lie and still belong to it."""
    planes: tuple[Plane, ...]
    sigma_1m: float
    in_camera_frame: bool
    reason: str | None = None
    """Why nothing can be found (no point within range), else None."""
    depth_image: FloatArray | None = None
    """Every depth of an organised frame as its image, NaN where there is none (and, when
    artefacts are filtered, beyond the depth cut)."""


def survey(frame: Frame, params: SegmentationParams, seed: int) -> Survey:
    """Steps 1 to 3 of :mod:`shapes.segment`, in the sensor frame: the kept points, their voxel grid
    and the planes. Deterministic for a given ``seed``; the frame's pose plays no part."""
    sigma_1m = 0.0
    image = None if frame.pixels is None else _depth_image(frame)
    if params.filter_artefacts and image is not None:
        sigma_1m = depth_noise_1m(image)
    cut = depth_cut_m(sigma_1m, params)
    keep = frame.points[:, 2] <= cut
    if not keep.any():
        return _nothing_to_survey(keep, frame, f"no point within {cut:.2f} m")
    # The stride comes from the points within range: the artefacts are then judged only on
    # the pixels it keeps (a quarter of them at stride 2).
    stride = pixel_stride(int(keep.sum()), params)
    if frame.pixels is None or frame.image_shape is None:
        stride = 1
    if params.filter_artefacts and image is not None:
        image[image > cut] = np.nan  # nothing beyond the cut is nearer than what it keeps
        keep &= _artefact_mask(frame, image, sigma_1m, stride)
        if not keep.any():
            reason = f"no point within {cut:.2f} m but flying pixels and veils"
            return _nothing_to_survey(keep, frame, reason)
    elif stride > 1:
        assert frame.image_shape is not None
        on_grid = np.zeros(frame.image_shape, dtype=np.bool_)
        on_grid[::stride, ::stride] = True
        keep &= on_grid.ravel()[frame.pixels]
    points = np.compress(keep, frame.points, axis=0)  # frame.points[keep], at a fifth of the cost
    depth = points[:, 2]
    in_camera_frame = frame.pixels is not None or bool((depth > 0.1).all())
    if not in_camera_frame:
        # Not in a camera's frame (e.g. a cloud already in the world frame): the range of each
        # point is unknown, so the noise is taken as the same everywhere.
        depth = np.ones(len(depth))
    # The grid is laid in the sensor frame, where the points were measured: laid in the world
    # frame, a point on a cell boundary changes cells with the least change of the pose, and
    # every fit downstream with it.
    voxels, voxel_of = voxel_grid(points, params.voxel_m)
    counts = np.bincount(voxel_of, minlength=len(voxels))
    voxel_depth = np.bincount(voxel_of, weights=depth, minlength=len(voxels)) / counts
    tolerance = np.maximum(params.support_threshold_m, 3 * sigma_1m * voxel_depth**2)
    planes = find_planes(voxels, params, seed, tolerance)
    return Survey(
        keep,
        points,
        depth,
        voxels,
        voxel_of,
        tolerance,
        tuple(planes),
        sigma_1m,
        in_camera_frame,
        depth_image=image,
    )


def _nothing_to_survey(keep: npt.NDArray[np.bool_], frame: Frame, reason: str) -> Survey:
    empty = np.zeros((0, 3))
    return Survey(
        keep,
        empty,
        np.zeros(0),
        empty,
        np.zeros(0, dtype=np.intp),
        np.zeros(0),
        (),
        0.0,
        frame.pixels is not None,
        reason,
    )


def depth_cut_m(sigma_1m: float, params: SegmentationParams) -> float:
    """The range beyond which points are dropped: ``max_depth_m`` when set, else where the
    depth noise ``sigma_1m z²`` reaches ``max_range_noise_m`` (``default_depth_m`` when the
    noise is not known).

    >>> params = SegmentationParams()
    >>> round(depth_cut_m(0.001, params), 2), depth_cut_m(0.0, params)
    (4.47, 3.0)
    """
    if params.max_depth_m is not None:
        return params.max_depth_m
    if sigma_1m <= 0.0:
        return params.default_depth_m
    return math.sqrt(params.max_range_noise_m / sigma_1m)


def pixel_stride(points: int, params: SegmentationParams) -> int:
    """The pixel stride that brings an organised frame of ``points`` valid points near
    ``target_points`` (1: every pixel, as with ``target_points <= 0``).

    >>> [pixel_stride(n, SegmentationParams()) for n in (40_000, 145_000, 307_200, 1_000_000)]
    [1, 2, 2, 4]
    """
    if params.target_points <= 0:
        return 1
    return max(1, round(math.sqrt(points / params.target_points)))


def voxel_grid(points: FloatArray, voxel_m: float) -> tuple[FloatArray, npt.NDArray[np.intp]]:
    """Voxel means and, for each input point, the index of its voxel.

    >>> means, index = voxel_grid(np.array([[0.001, 0, 0], [0.003, 0, 0], [0.5, 0, 0]]), 0.01)
    >>> means.round(3).tolist(), index.tolist()
    ([[0.002, 0.0, 0.0], [0.5, 0.0, 0.0]], [0, 0, 1])
    """
    keys = np.floor(points / voxel_m).astype(np.int64)
    keys -= column_min(keys)
    span = column_max(keys) + 1
    flat = (keys[:, 0] * span[1] + keys[:, 1]) * span[2] + keys[:, 2]
    _, index, counts = unique_inverse(flat)
    means = np.empty((len(counts), 3))
    for axis in range(3):
        means[:, axis] = np.bincount(index, weights=points[:, axis]) / counts
    return means, index.astype(np.intp)


def _depth_image(frame: Frame) -> FloatArray:
    """The depths of an organised frame's points as its image, NaN where there is no point."""
    assert frame.image_shape is not None and frame.pixels is not None
    image = np.full(frame.image_shape[0] * frame.image_shape[1], np.nan)
    image[frame.pixels] = frame.points[:, 2]
    return image.reshape(frame.image_shape)


def _focal_px(frame: Frame) -> float:
    """The focal length in pixels of an organised frame, from its points and pixel columns."""
    assert frame.image_shape is not None and frame.pixels is not None
    every = max(1, len(frame.pixels) // 2000)
    u = (frame.pixels[::every] % frame.image_shape[1]).astype(np.float64)
    slope = frame.points[::every, 0] / frame.points[::every, 2]
    if np.ptp(u) == 0:
        return 570.0
    a = np.polyfit(u, slope, 1)[0]
    return float(1.0 / a) if a > 0 else 570.0


def _artefact_mask(
    frame: Frame, image: FloatArray, sigma_1m: float, stride: int
) -> npt.NDArray[np.bool_]:
    """Which of an organised frame's points lie on every ``stride``-th pixel of every
    ``stride``-th row and are neither flying pixels nor veils of ``image`` (its depths, NaN
    where there is none)."""
    assert frame.pixels is not None
    on_grid = np.zeros(image.shape, dtype=np.bool_)
    drop = flying_pixels(image, sigma_1m, focal_px=_focal_px(frame), step=stride)
    on_grid[::stride, ::stride] = ~drop
    return np.asarray(on_grid.ravel()[frame.pixels], dtype=np.bool_)
