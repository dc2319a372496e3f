"""Point-cloud sources: PLY/PCD files (open3d), NumPy files, ROS bags, chosen by path.

>>> import tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "cloud.npy"
>>> np.save(path, np.array([[0.0, 0.0, 1.0], [0.1, 0.0, 1.0]]))
>>> [f.points.shape for f in open_source(path)]
[(2, 3)]
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import open3d as o3d

from shapes.bags import bag_message_count, read_bag
from shapes.cloudfile import check_cloud_file
from shapes.errors import InvalidCloudError, SourceError
from shapes.frame import Frame, frame_from_depth_image
from shapes.types import FloatArray

__all__ = ["CLOUD_SUFFIXES", "open_source", "read_cloud_file", "source_length"]

CLOUD_SUFFIXES = (".ply", ".pcd", ".xyz", ".xyzrgb", ".pts")
ARRAY_SUFFIXES = (".npy", ".npz")
BAG_SUFFIXES = (".bag", ".mcap", ".db3")


def read_cloud_file(path: str | Path, *, world_from_sensor: FloatArray | None = None) -> Frame:
    """One frame from a PLY/PCD/XYZ file (open3d), with its colours if the file has them.

    Raises SourceError if the file is missing, malformed or truncated (see
    :func:`~shapes.cloudfile.check_cloud_file`) or holds no finite point. Points that are NaN or
    infinite (an organised cloud's empty pixels) are dropped; an organised PCD (HEIGHT > 1)
    keeps the pixel of each point.
    """
    p = Path(path)
    if not p.is_file():
        raise SourceError(f"cloud file: {str(p)!r} does not exist or is not a file")
    if p.suffix.lower() not in CLOUD_SUFFIXES:
        raise SourceError(f"cloud file: expected a suffix in {CLOUD_SUFFIXES}, got {str(p)!r}")
    layout = check_cloud_file(p)
    cloud = o3d.io.read_point_cloud(p, remove_nan_points=False, remove_infinite_points=False)
    points = np.asarray(cloud.points, dtype=np.float64)
    if layout is not None and len(points) != layout.points:
        raise SourceError(
            f"cloud file {str(p)!r}: the header declares {layout.points} points, "
            f"{len(points)} could be read"
        )
    if len(points) == 0:
        raise SourceError(f"cloud file {str(p)!r}: no point could be read (empty or not a cloud)")
    colours = np.asarray(cloud.colors, dtype=np.float64) if cloud.has_colors() else None
    finite = np.isfinite(points).all(axis=1)
    if not finite.any():
        raise SourceError(f"cloud file {str(p)!r}: every point is NaN or infinite")
    pose = np.eye(4) if world_from_sensor is None else world_from_sensor
    shape = layout.image_shape if layout is not None else None
    pixels = np.flatnonzero(finite) if shape is not None else None
    return Frame(
        points[finite],
        None if colours is None else colours[finite],
        None,
        p.stem,
        pose,
        shape,
        pixels,
    )


def _read_array(path: Path, pose: FloatArray) -> Frame:
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise SourceError(f"array file {str(path)!r}: cannot be read ({exc})") from exc
    if isinstance(data, np.lib.npyio.NpzFile):
        with data:
            if "depth" in data.files:
                return _read_depth_image(path, data, pose)
            if "points" not in data.files:
                raise SourceError(
                    f"array file {str(path)!r}: expected an array named 'points' (and optionally "
                    f"'colours'), got {data.files}"
                )
            points, colours = data["points"], data["colours"] if "colours" in data.files else None
    else:
        arr = np.asarray(data)
        if arr.ndim == 2 and arr.shape[1] == 6:
            points, colours = arr[:, :3], arr[:, 3:]
        else:
            points, colours = arr, None
    try:
        return Frame(points, colours, None, path.stem, pose)
    except InvalidCloudError as exc:
        raise InvalidCloudError(f"array file {str(path)!r}: {exc}") from exc


DEPTH_IMAGE_KEYS = ("depth", "fx", "fy", "cx", "cy")


def _read_depth_image(path: Path, data: np.lib.npyio.NpzFile, pose: FloatArray) -> Frame:
    """An organised frame from an ``.npz`` depth image (see :func:`open_source`)."""
    missing = [key for key in DEPTH_IMAGE_KEYS if key not in data.files]
    if missing:
        raise SourceError(
            f"array file {str(path)!r}: a depth image needs the arrays {DEPTH_IMAGE_KEYS} "
            f"(and optionally 'depth_scale' and 'rgb'), missing {missing}"
        )
    try:
        scalars = {key: float(data[key]) for key in ("fx", "fy", "cx", "cy")}
        scale = float(data["depth_scale"]) if "depth_scale" in data.files else 1.0
        rgb = data["rgb"] if "rgb" in data.files else None
        return frame_from_depth_image(
            data["depth"],
            depth_scale=scale,
            rgb=rgb,
            world_from_camera=pose,
            frame_id=path.stem,
            **scalars,
        )
    except (TypeError, ValueError) as exc:  # InvalidCloudError is a ValueError
        raise InvalidCloudError(f"array file {str(path)!r}: {exc}") from exc


def _is_ros2_dir(path: Path) -> bool:
    return path.is_dir() and (path / "metadata.yaml").is_file()


def open_source(
    path: str | Path,
    *,
    topic: str | None = None,
    world_from_sensor: FloatArray | None = None,
) -> Iterator[Frame]:
    """Frames from a point-cloud file, a NumPy file or a ROS bag, chosen by the path.

    - ``.ply``, ``.pcd``, ``.xyz``, ``.xyzrgb``, ``.pts``: one frame (open3d);
    - ``.npy`` with ``(N, 3)`` points or ``(N, 6)`` points and RGB; ``.npz`` with ``points``
      and optional ``colours``: one frame;
    - ``.npz`` holding a depth image (pinhole optical frame: x right, y down, z forward):
      ``depth`` (H x W), ``fx fy cx cy`` in pixels, optional ``depth_scale`` (metres per unit
      of ``depth``, default 1) and ``rgb`` (H x W x 3): one organised frame;
    - ``.bag`` (ROS 1), a ROS 2 bag directory or its ``.mcap``/``.db3`` file: one frame per
      PointCloud2 message (``topic`` picks one topic).

    Raises SourceError for a missing path or an unknown kind of file.
    """
    p = Path(path)
    pose = np.eye(4) if world_from_sensor is None else world_from_sensor
    if not p.exists():
        raise SourceError(f"source: {str(p)!r} does not exist")
    suffix = p.suffix.lower()
    if suffix in BAG_SUFFIXES or _is_ros2_dir(p):
        yield from read_bag(p, topic=topic, world_from_sensor=pose)
    elif suffix in CLOUD_SUFFIXES:
        yield read_cloud_file(p, world_from_sensor=pose)
    elif suffix in ARRAY_SUFFIXES:
        yield _read_array(p, pose)
    else:
        raise SourceError(
            f"source: expected a point-cloud file {CLOUD_SUFFIXES}, a NumPy file "
            f"{ARRAY_SUFFIXES}, a ROS 1 .bag or a ROS 2 bag directory, got {str(p)!r}"
        )


def source_length(path: str | Path, *, topic: str | None = None) -> int:
    """How many frames :func:`open_source` yields at most (for a progress bar)."""
    p = Path(path)
    if p.suffix.lower() in BAG_SUFFIXES or _is_ros2_dir(p):
        return bag_message_count(p, topic)
    if not p.exists():
        raise SourceError(f"source: {str(p)!r} does not exist")
    return 1
