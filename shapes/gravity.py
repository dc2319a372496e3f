"""Gravity from the scene: which way is up when the sensor's pose is not known.

A camera looks down at a table at 30 to 55 degrees, so in its own frame no plane is
horizontal. The scene says where up is: the *dominant support*, the largest plane with objects
standing on it on the camera's side, else the largest plane (the floor). Its normal, turned
towards the camera, is up (in a cloud that is not in a camera's frame, with points at
z <= 0.1 m, towards the side with more objects on it); :func:`gravity_from_scene` returns the
rotation that takes it to the world's z axis, and keeps the camera at the origin.

On an organised frame (a camera's optical frame: x right, y down, z forward) a plane whose
normal points away from the camera's up side (``-y``) by more than ``max_up_angle_deg`` is a
wall or a ceiling, never the support: a camera is not held upside down.

>>> from shapes.frame import Frame
>>> rng = np.random.default_rng(0)
>>> xy = rng.uniform(-0.5, 0.5, (4000, 2))
>>> tilt = np.radians(40)  # a floor 1 m below, seen by a camera pitched 40 deg down
>>> floor = np.column_stack((xy[:, 0], np.full(4000, 1.0), xy[:, 1] + 1.5))
>>> rot = np.array([[1, 0, 0], [0, np.cos(tilt), -np.sin(tilt)], [0, np.sin(tilt), np.cos(tilt)]])
>>> g = gravity_from_scene(Frame(floor @ rot.T), SegmentationParams(), seed=0)
>>> (np.round(g.up, 3) + 0.0).tolist(), round(g.tilt_deg - 90)  # degrees below the horizon
([0.0, -0.766, -0.643], 40)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from shapes.arrays import column_max, column_min
from shapes.frame import Frame
from shapes.segment import SegmentationParams, Survey, survey
from shapes.types import FloatArray

__all__ = ["Gravity", "gravity_from_scene", "gravity_from_survey", "rotation_to_z"]

_MIN_OBJECT_HEIGHT_M = 0.02
"""Voxels at least this far above a plane may be an object standing on it."""


@dataclass(frozen=True)
class Gravity:
    """Up in the sensor frame (unit) and the world-from-sensor transform that makes it z."""

    up: FloatArray
    world_from_sensor: FloatArray
    support_voxels: int
    objects_voxels: int

    @property
    def tilt_deg(self) -> float:
        """Angle between the sensor's z axis and up, in degrees."""
        return math.degrees(math.acos(max(-1.0, min(1.0, float(self.up[2])))))

    def describe(self) -> str:
        """One line for a user: where up came from and how the sensor looks."""
        below = self.tilt_deg - 90.0
        on = f", {self.objects_voxels} voxels of objects on it" if self.objects_voxels else ""
        return (
            f"gravity from the scene: the normal of its support ({self.support_voxels} "
            f"voxels{on}); the sensor's z axis points {abs(below):.0f} deg "
            f"{'below' if below >= 0 else 'above'} the horizon"
        )


def rotation_to_z(up: FloatArray) -> FloatArray:
    """The smallest rotation (3x3) taking the unit vector ``up`` to ``(0, 0, 1)``.

    >>> np.round(rotation_to_z(np.array([0.0, -1.0, 0.0])) @ [0, -1, 0], 6).tolist()
    [0.0, 0.0, 1.0]
    """
    u = np.asarray(up, dtype=np.float64) / np.linalg.norm(up)
    z = np.array([0.0, 0.0, 1.0])
    c = float(u @ z)
    if c < -1 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    v = np.cross(u, z)
    k = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.asarray(np.eye(3) + k + k @ k / (1.0 + c), dtype=np.float64)


def _objects_on(
    normal: FloatArray, offset: float, plane: FloatArray, free: FloatArray, max_height_m: float
) -> int:
    """Free voxels standing on a plane: above it, lower than ``max_height_m``, inside its
    bounding rectangle (in the plane's own axes)."""
    height = free @ normal + offset
    e1 = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    axes = np.column_stack((e1, e2))
    across = plane @ axes
    lo, hi = column_min(across), column_max(across)
    flat = free @ axes
    u, v = flat[:, 0], flat[:, 1]
    inside = (u > lo[0]) & (u < hi[0]) & (v > lo[1]) & (v < hi[1])
    return int(np.count_nonzero(inside & (height > _MIN_OBJECT_HEIGHT_M) & (height < max_height_m)))


def gravity_from_scene(
    frame: Frame, params: SegmentationParams, *, seed: int, max_up_angle_deg: float = 80.0
) -> Gravity | None:
    """Up from the frame's dominant support (see the module doc), or None if no plane is found.

    The search runs in the sensor frame (the frame's own pose is ignored) on the points and
    planes that segmentation keeps (:func:`shapes.segment.survey`).
    """
    return gravity_from_survey(
        frame, survey(frame, params, seed), params, max_up_angle_deg=max_up_angle_deg
    )


def gravity_from_survey(
    frame: Frame, surveyed: Survey, params: SegmentationParams, *, max_up_angle_deg: float = 80.0
) -> Gravity | None:
    """:func:`gravity_from_scene` from the frame's survey, when the caller has it already (it
    is segmentation's first step, so a pipeline surveys each frame once)."""
    voxels, planes = surveyed.voxels, surveyed.planes
    if not planes:
        return None
    in_plane = np.zeros(len(voxels), dtype=bool)
    for p in planes:
        in_plane |= p.inliers
    free = voxels[~in_plane]
    cos_up = math.cos(math.radians(max_up_angle_deg))
    from_camera = surveyed.in_camera_frame
    candidates = []
    for p in planes:
        normal, offset = np.asarray(p.normal, dtype=np.float64), float(p.offset)
        if from_camera and offset < 0:
            normal, offset = -normal, -offset  # towards the camera at the origin
        elif not from_camera and _objects_on(
            -normal, -offset, voxels[p.inliers], free, params.max_height_m
        ) > _objects_on(normal, offset, voxels[p.inliers], free, params.max_height_m):
            normal, offset = -normal, -offset  # towards the objects standing on it
        if frame.pixels is not None and -normal[1] < cos_up:
            continue  # a wall or a ceiling of a camera's optical frame
        size = int(p.inliers.sum())
        on = _objects_on(normal, offset, voxels[p.inliers], free, params.max_height_m)
        candidates.append((on >= params.min_cluster_voxels, size, on, normal))
    if not candidates:
        return None
    _, size, on, up = max(candidates, key=lambda c: (c[0], c[1]))
    pose = np.eye(4)
    pose[:3, :3] = rotation_to_z(up)
    return Gravity(up, pose, size, on)
