"""A simulated structured-light depth camera (640 x 480) with the artefacts of real sensors.

The scene is a :class:`~shapes.synthetic.TabletopScene` (table top at z = 0, world z up), and
optionally a floor (``floor_z``) and a wall (the plane ``y = wall_y``) in view. Each pixel's ray
is cast exactly; the exact depth ``z`` (along the optical axis) is then corrupted, in this order:

1. **flying pixels**: at a depth edge (the 3 x 3 neighbourhood spans more than
   ``edge_jump_m``), a pixel returns, with probability ``flying_probability``, a *mixed* depth
   ``z_near + u (z_far - z_near)``, ``u ~ U(0, 1)``: a point on the ray between the foreground
   and the background, as a sensor that averages both surfaces inside one pixel does;
2. **axial noise** growing with the square of the range: ``sigma(z) = sigma_1m * z**2``
   (Kinect-like: a structured-light sensor's depth error grows with z² because depth comes from
   disparity);
3. **quantisation**: depth is rounded to steps of ``quantum_1m * z**2`` (disparity steps);
4. **dropouts**: a random ``dropout_fraction`` of the pixels, and, with probability
   ``grazing_dropout``, every pixel whose ray meets its surface at more than ``grazing_deg``
   from the normal (the projected pattern is too stretched there to be matched);
5. **outliers**: a random ``outlier_fraction`` of the valid pixels return a depth drawn
   uniformly between 0.4 m and their true depth (specular glints, multipath).

The output is organised: a ``(height, width)`` depth image with NaN where there is no return,
the object label of every pixel (-1 table, -2 floor, -3 wall, -4 nothing), and the
:class:`~shapes.frame.Frame` built from it by :func:`~shapes.frame.frame_from_depth_image`.

>>> from shapes.synthetic import TabletopScene, TruthObject
>>> scene = TabletopScene((TruthObject("Sphere", (0.0, 0.1, 0.0), radius=0.05, height=0.1),))
>>> shot = DepthCamera().shoot(scene, np.random.default_rng(0))
>>> shot.depth.shape, shot.frame.image_shape
((480, 640), (480, 640))
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import numpy.typing as npt

from shapes.frame import Frame, frame_from_depth_image
from shapes.synthetic import TabletopScene, TruthObject, _cast, _valid, look_at
from shapes.types import FloatArray

__all__ = ["CLEAN", "DepthCamera", "DepthShot", "Room", "SensorModel", "resting"]

TABLE, FLOOR, WALL, NOTHING = -1, -2, -3, -4


@dataclass(frozen=True)
class SensorModel:
    """The corruptions of :class:`DepthCamera`; see the module docstring for each one."""

    sigma_1m: float = 0.0015
    quantum_1m: float = 0.0015
    edge_jump_m: float = 0.02
    flying_probability: float = 0.5
    dropout_fraction: float = 0.01
    grazing_deg: float = 80.0
    grazing_dropout: float = 0.8
    outlier_fraction: float = 0.0


CLEAN = SensorModel(0.0, 0.0, 0.02, 0.0, 0.0, 90.0, 0.0, 0.0)
"""No corruption at all: the exact ray-cast depth."""


@dataclass(frozen=True)
class Room:
    """What else is in view: a floor ``floor_z`` below the table top, a wall at ``y = wall_y``."""

    floor_z: float | None = None
    wall_y: float | None = None


@dataclass(frozen=True)
class DepthCamera:
    """A 640 x 480 pinhole depth camera (Kinect-like intrinsics) looking down at the table."""

    width: int = 640
    height: int = 480
    fx: float = 570.0
    fy: float = 570.0
    cx: float = 319.5
    cy: float = 239.5
    world_from_camera: FloatArray = field(
        default_factory=lambda: look_at((0.0, -0.95, 0.6), (0.0, 0.1, 0.0))
    )

    def scaled(self, factor: float) -> DepthCamera:
        """The same view with ``factor`` times as many pixels along each side."""
        return DepthCamera(
            max(1, round(self.width * factor)),
            max(1, round(self.height * factor)),
            self.fx * factor,
            self.fy * factor,
            (self.width * factor - 1) / 2,
            (self.height * factor - 1) / 2,
            self.world_from_camera,
        )

    def rays(self) -> FloatArray:
        """Camera-frame rays with unit depth, one per pixel, row-major."""
        v, u = np.mgrid[0 : self.height, 0 : self.width]
        return np.column_stack(
            (((u - self.cx) / self.fx).ravel(), ((v - self.cy) / self.fy).ravel(), np.ones(u.size))
        )

    def shoot(
        self,
        scene: TabletopScene,
        rng: np.random.Generator,
        sensor: SensorModel | None = None,
        room: Room | None = None,
        stamp: float | None = None,
    ) -> DepthShot:
        """Ray-cast the scene and corrupt the depth as :class:`SensorModel` says."""
        sensor = SensorModel() if sensor is None else sensor
        room = Room() if room is None else room
        pose = self.world_from_camera
        rays = self.rays()
        dirs = rays @ pose[:3, :3].T  # world directions; a hit at t has camera depth t
        origin = pose[:3, 3]
        candidates = [_plane_hit(origin, dirs, 2, 0.0)]
        x = origin[0] + candidates[0] * dirs[:, 0]
        y = origin[1] + candidates[0] * dirs[:, 1]
        half_w, half_d = scene.table_size[0] / 2, scene.table_size[1] / 2
        candidates[0] = _valid(candidates[0], (np.abs(x) <= half_w) & (np.abs(y) <= half_d))
        labels = [TABLE]
        if room.floor_z is not None:
            candidates.append(_plane_hit(origin, dirs, 2, room.floor_z))
            labels.append(FLOOR)
        if room.wall_y is not None:
            candidates.append(_plane_hit(origin, dirs, 1, room.wall_y))
            labels.append(WALL)
        candidates += [_cast(o, origin, dirs) for o in scene.objects]
        labels += list(range(len(scene.objects)))
        stacked = np.vstack(candidates)
        which = stacked.argmin(axis=0)
        depth = stacked[which, np.arange(stacked.shape[1])]
        hit = np.isfinite(depth)
        label = np.where(hit, np.asarray(labels)[which], NOTHING)
        shape = (self.height, self.width)
        exact = np.where(hit, depth, np.nan).reshape(shape)
        z = _corrupt(exact, rays.reshape(*shape, 3), sensor, rng)
        frame = frame_from_depth_image(
            z,
            fx=self.fx,
            fy=self.fy,
            cx=self.cx,
            cy=self.cy,
            world_from_camera=pose,
            stamp=stamp,
            frame_id="depth_camera",
        )
        return DepthShot(frame, z, exact, label.reshape(shape).astype(np.int64))


@dataclass(frozen=True, eq=False)
class DepthShot:
    """One frame: the Frame, the corrupted and the exact depth images, and each pixel's label."""

    frame: Frame
    depth: FloatArray
    exact_depth: FloatArray
    labels: npt.NDArray[np.int64]

    def object_pixels(self) -> npt.NDArray[np.int64]:
        """How many valid pixels each object (label >= 0) has, indexed by object."""
        valid = np.isfinite(self.depth) & (self.labels >= 0)
        return np.bincount(self.labels[valid], minlength=int(self.labels.max(initial=-1)) + 1)


def _plane_hit(origin: FloatArray, dirs: FloatArray, axis: int, level: float) -> FloatArray:
    d = dirs[:, axis]
    t = (level - origin[axis]) / np.where(np.abs(d) > 1e-12, d, 1e-12)
    return _valid(t, np.isfinite(t))


def _neighbourhood(img: FloatArray, reduce: str) -> FloatArray:
    """3 x 3 min or max of an image, NaN (no return) ignored."""
    fill = np.inf if reduce == "min" else -np.inf
    padded = np.pad(np.where(np.isnan(img), fill, img), 1, constant_values=fill)
    h, w = img.shape
    views = [padded[i : i + h, j : j + w] for i in range(3) for j in range(3)]
    out = np.min(views, axis=0) if reduce == "min" else np.max(views, axis=0)
    return np.asarray(out, dtype=np.float64)


def _corrupt(
    exact: FloatArray, rays: FloatArray, sensor: SensorModel, rng: np.random.Generator
) -> FloatArray:
    z = exact.copy()
    valid = np.isfinite(z)
    near, far = _neighbourhood(exact, "min"), _neighbourhood(exact, "max")
    edge = valid & np.isfinite(far) & (far - near > sensor.edge_jump_m)
    flying = edge & (rng.random(z.shape) < sensor.flying_probability)
    z[flying] = near[flying] + rng.random(int(flying.sum())) * (far[flying] - near[flying])
    z[valid] += rng.standard_normal(int(valid.sum())) * sensor.sigma_1m * z[valid] ** 2
    if sensor.quantum_1m > 0:
        step = sensor.quantum_1m * z[valid] ** 2
        z[valid] = np.round(z[valid] / step) * step
    drop = rng.random(z.shape) < sensor.dropout_fraction
    if sensor.grazing_dropout > 0:
        pts = rays * exact[..., None]
        normal = np.cross(np.gradient(pts, axis=1), np.gradient(pts, axis=0))
        cos = np.abs(np.einsum("ijk,ijk->ij", normal, rays)) / (
            np.linalg.norm(normal, axis=2) * np.linalg.norm(rays, axis=2) + 1e-300
        )
        grazing = np.nan_to_num(cos, nan=1.0) < math.cos(math.radians(sensor.grazing_deg))
        drop |= grazing & ~edge & (rng.random(z.shape) < sensor.grazing_dropout)
    z[drop] = np.nan
    valid = np.isfinite(z)
    out = valid & (rng.random(z.shape) < sensor.outlier_fraction)
    z[out] = 0.4 + rng.random(int(out.sum())) * np.maximum(z[out] - 0.4, 0.0)
    return z


def resting(obj: TruthObject) -> TruthObject:
    """The object lowered or lifted so that its lowest point touches the table (z = 0).

    A tilted cylinder rests on its rim (or its side when lying, tilt 90 degrees); a cone tilted
    by 90 degrees plus its half angle lies on its side, apex on the table.

    >>> import math
    >>> from shapes.synthetic import TruthObject
    >>> lying = resting(TruthObject("Cylinder", (0.0, 0.0, 0.0), 0.03, 0.1, tilt=math.pi / 2))
    >>> round(lying.position[2], 6)
    0.03
    """
    if obj.kind in ("Sphere", "Box"):
        return replace(obj, position=(obj.position[0], obj.position[1], 0.0))
    angles = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    rim = np.column_stack((obj.radius * np.cos(angles), obj.radius * np.sin(angles), 0 * angles))
    top = np.array([[0.0, 0.0, obj.height]])
    if obj.kind == "Cylinder":
        top = rim + top
    local = np.vstack((rim, top))
    lowest = float((local @ obj.rotation.T)[:, 2].min())
    return replace(obj, position=(obj.position[0], obj.position[1], -lowest))
