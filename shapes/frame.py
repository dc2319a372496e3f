"""One input frame (a point cloud with optional colours) and its validation.

Points arrive in the sensor frame; ``world_from_sensor`` (4x4) takes them to a world frame whose
z axis points up, which is what the support-plane search assumes.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from shapes.errors import InvalidCloudError
from shapes.types import FloatArray

__all__ = ["Frame", "as_colours", "as_points", "as_transform", "frame_from_depth_image"]


def as_points(points: npt.ArrayLike, *, name: str = "points") -> FloatArray:
    """Validate an ``(N, 3)`` array of finite coordinates and return it as float64.

    Raises InvalidCloudError (a ValueError) naming the field, the value and what was expected.

    >>> as_points([[0, 0, 1]]).shape
    (1, 3)
    >>> as_points([])
    Traceback (most recent call last):
    ...
    shapes.errors.InvalidCloudError: points: expected an (N, 3) array with N >= 1, got shape (0,)
    """
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidCloudError(f"{name}: expected an (N, 3) array of numbers, got {exc}") from exc
    if arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] == 0:
        raise InvalidCloudError(
            f"{name}: expected an (N, 3) array with N >= 1, got shape {arr.shape}"
        )
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise InvalidCloudError(
            f"{name}: expected finite coordinates, got {int(bad.sum())} rows with NaN or "
            f"infinity (first at row {row}: {arr[row].tolist()}); drop them first"
        )
    return arr


def as_colours(colours: npt.ArrayLike, n_points: int, *, name: str = "colours") -> FloatArray:
    """Validate ``(N, 3)`` RGB colours: floats in [0, 1], or integers 0-255 (scaled to [0, 1])."""
    raw = np.asarray(colours)
    if raw.ndim != 2 or raw.shape != (n_points, 3):
        raise InvalidCloudError(
            f"{name}: expected an ({n_points}, 3) array (one RGB row per point), got shape "
            f"{raw.shape}"
        )
    if np.issubdtype(raw.dtype, np.integer):
        if raw.min() < 0 or raw.max() > 255:
            raise InvalidCloudError(
                f"{name}: integer colours must lie in 0..255, got {raw.min()}..{raw.max()}"
            )
        return raw.astype(np.float64) / 255.0
    try:
        arr = raw.astype(np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidCloudError(f"{name}: expected numbers, got dtype {raw.dtype}") from exc
    if not np.isfinite(arr).all() or arr.min() < 0.0 or arr.max() > 1.0:
        raise InvalidCloudError(
            f"{name}: float colours must be finite and lie in [0, 1], got "
            f"{np.nanmin(arr)}..{np.nanmax(arr)}"
        )
    return arr


def as_transform(matrix: npt.ArrayLike, *, name: str = "world_from_sensor") -> FloatArray:
    """Validate a 4x4 rigid transform (rotation part orthonormal, last row 0 0 0 1)."""
    try:
        t = np.asarray(matrix, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidCloudError(f"{name}: expected a 4x4 matrix of numbers, got {exc}") from exc
    if t.shape != (4, 4) or not np.isfinite(t).all():
        raise InvalidCloudError(f"{name}: expected a finite 4x4 matrix, got shape {t.shape}")
    r = t[:3, :3]
    if not np.allclose(r @ r.T, np.eye(3), atol=1e-6) or not np.allclose(
        t[3], [0.0, 0.0, 0.0, 1.0]
    ):
        raise InvalidCloudError(
            f"{name}: expected a rigid transform (orthonormal rotation, last row 0 0 0 1), "
            f"got {t.tolist()}"
        )
    return t


@dataclass(frozen=True, eq=False)
class Frame:
    """A validated point cloud in the sensor frame, with optional colours and a pose.

    An *organised* cloud (from a depth image or a bag with width x height) also carries
    ``image_shape`` (rows, columns) and ``pixels``, the flat row-major pixel of each point; the
    artefact filters then work on the image neighbourhoods.

    Raises InvalidCloudError if ``points`` is not a finite ``(N, 3)`` array, if ``colours``
    does not have one RGB row per point, or if ``world_from_sensor`` is not rigid.

    >>> f = Frame(np.zeros((2, 3)), stamp=1.5)
    >>> f.world_points().shape, f.stamp
    ((2, 3), 1.5)
    """

    points: FloatArray
    colours: FloatArray | None = None
    stamp: float | None = None
    frame_id: str = ""
    world_from_sensor: FloatArray = field(default_factory=lambda: np.eye(4))
    image_shape: tuple[int, int] | None = None
    pixels: npt.NDArray[np.intp] | None = None

    def __post_init__(self) -> None:
        pts = as_points(self.points)
        object.__setattr__(self, "points", pts)
        if (self.image_shape is None) != (self.pixels is None):
            raise InvalidCloudError(
                "pixels: expected both image_shape and pixels for an organised cloud, or "
                f"neither, got image_shape={self.image_shape!r} and "
                f"pixels {'None' if self.pixels is None else 'set'}"
            )
        if self.image_shape is not None and self.pixels is not None:
            pix = np.asarray(self.pixels, dtype=np.intp)
            size = int(self.image_shape[0]) * int(self.image_shape[1])
            if pix.shape != (len(pts),) or (len(pix) and (pix.min() < 0 or pix.max() >= size)):
                raise InvalidCloudError(
                    f"pixels: expected {len(pts)} flat indices in 0..{size - 1} of an image of "
                    f"shape {self.image_shape}, got shape {pix.shape}"
                )
            object.__setattr__(self, "pixels", pix)
        if self.colours is not None:
            object.__setattr__(self, "colours", as_colours(self.colours, len(pts)))
        object.__setattr__(self, "world_from_sensor", as_transform(self.world_from_sensor))

    def with_pose(self, world_from_sensor: npt.ArrayLike) -> Frame:
        """This frame with another pose; only the pose is validated (the points already were,
        and checking 300,000 of them again costs milliseconds).

        Raises InvalidCloudError if ``world_from_sensor`` is not rigid.

        >>> up = np.eye(4)
        >>> up[2, 3] = 1.0
        >>> Frame(np.zeros((1, 3))).with_pose(up).world_points().tolist()
        [[0.0, 0.0, 1.0]]
        """
        posed = copy.copy(self)
        object.__setattr__(posed, "world_from_sensor", as_transform(world_from_sensor))
        return posed

    def world_points(self, mask: npt.NDArray[np.bool_] | None = None) -> FloatArray:
        """The points (optionally a subset) in the world frame."""
        return self.world_points_of(self.points if mask is None else self.points[mask])

    def world_points_of(self, points: FloatArray) -> FloatArray:
        """Any ``(N, 3)`` points given in this frame's sensor frame, in the world frame."""
        t = self.world_from_sensor
        return np.asarray(points @ t[:3, :3].T + t[:3, 3], dtype=np.float64)


def frame_from_depth_image(
    depth: npt.ArrayLike,
    *,
    fx: float,
    fy: float,
    cx: float,
    cy: float,
    depth_scale: float = 1.0,
    rgb: npt.ArrayLike | None = None,
    world_from_camera: npt.ArrayLike | None = None,
    stamp: float | None = None,
    frame_id: str = "",
) -> Frame:
    """Un-project a depth image (pinhole intrinsics, optical frame: x right, y down, z forward).

    ``depth`` is ``(H, W)``; a pixel's depth in metres is ``depth * depth_scale`` (use 0.001 for
    millimetre ``uint16`` images). Pixels that are 0, NaN or infinite carry no point. ``rgb`` is
    an optional ``(H, W, 3)`` image aligned with the depth image.

    Raises InvalidCloudError on a wrong shape, non-positive focal lengths or no valid pixel.

    >>> f = frame_from_depth_image(np.full((2, 2), 2.0), fx=1.0, fy=1.0, cx=0.5, cy=0.5)
    >>> f.points.tolist()[0]
    [-1.0, -1.0, 2.0]
    """
    d = np.asarray(depth)
    if d.ndim != 2 or d.size == 0:
        raise InvalidCloudError(f"depth: expected an (H, W) image, got shape {d.shape}")
    for key, value in (("fx", fx), ("fy", fy), ("depth_scale", depth_scale)):
        if not np.isfinite(value) or value <= 0:
            raise InvalidCloudError(f"{key}: expected a positive number, got {value!r}")
    z = d.astype(np.float64) * depth_scale
    valid = np.isfinite(z) & (z > 0)
    if not valid.any():
        raise InvalidCloudError(
            "depth: expected at least one pixel with a positive depth, got none"
        )
    v, u = np.nonzero(valid)
    zz = z[v, u]
    points = np.column_stack(((u - cx) / fx * zz, (v - cy) / fy * zz, zz))
    colours = None
    if rgb is not None:
        img = np.asarray(rgb)
        if img.shape != (*d.shape, 3):
            raise InvalidCloudError(
                f"rgb: expected an image of shape {(*d.shape, 3)} aligned with the depth image, "
                f"got {img.shape}"
            )
        colours = img[v, u]
    pose = np.eye(4) if world_from_camera is None else world_from_camera
    return Frame(
        points,
        None if colours is None else as_colours(colours, len(points), name="rgb"),
        stamp,
        frame_id,
        np.asarray(pose, dtype=np.float64),
        (int(d.shape[0]), int(d.shape[1])),
        (v * d.shape[1] + u).astype(np.intp),
    )
