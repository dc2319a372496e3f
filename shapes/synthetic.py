"""Synthetic tabletop scenes with ground truth, seen by a simulated depth camera.

A table (a horizontal rectangle at z = 0, world z up) carries spheres, upright cylinders,
upright cones (base down) and boxes. One pinhole camera ray-casts the scene, so only the
surfaces it faces are sampled and objects occlude each other and the table, as with a real depth
camera. Depth noise follows the Kinect axial model sigma(z) = 1.2 mm + 1.9 mm·(z - 0.4 m)²; a few
pixels drop out and a few "flying pixels" land between an edge and the camera. Everything is
drawn from the ``numpy.random.Generator`` passed in, so a seed gives the same cloud.

Ground truth uses the same conventions as :class:`shapes.types.Primitive`: a cylinder's centre
is the middle of its axis, a cone's centre is the centroid of the solid (a quarter of the height
above the base), a box is expected to be reported as a ``Plane``.

>>> rng = np.random.default_rng(1)
>>> scene = random_scene(rng, n_objects=3)
>>> shot = scene.render(rng)
>>> len(scene.objects), shot.frame.points.shape[1], shot.frame.colours is not None
(3, 3, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import numpy.typing as npt

from shapes.frame import Frame
from shapes.types import FloatArray, ShapeKind, Vec3, vec3

__all__ = [
    "PALETTE",
    "Camera",
    "NoiseModel",
    "SyntheticShot",
    "TabletopScene",
    "TruthObject",
    "look_at",
    "random_scene",
]

PALETTE: dict[str, Vec3] = {
    "red": (0.85, 0.12, 0.10),
    "green": (0.15, 0.70, 0.20),
    "blue": (0.12, 0.25, 0.85),
    "yellow": (0.90, 0.82, 0.15),
    "pink": (0.80, 0.25, 0.75),
}
TABLE_COLOUR: Vec3 = (0.55, 0.45, 0.35)
KINDS = ("Sphere", "Cylinder", "Cone", "Box")


def look_at(eye: npt.ArrayLike, target: npt.ArrayLike) -> FloatArray:
    """World-from-camera pose of an optical frame (x right, y down, z forward), world z up."""
    e = np.asarray(eye, dtype=np.float64)
    z = np.asarray(target, dtype=np.float64) - e
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = x, y, z, e
    return pose


@dataclass(frozen=True)
class Camera:
    """A pinhole depth camera; the default sees a 1.2 x 0.8 m table from about 1 m."""

    width: int = 320
    height: int = 240
    fx: float = 285.0
    fy: float = 285.0
    cx: float = 159.5
    cy: float = 119.5
    world_from_camera: FloatArray = field(
        default_factory=lambda: look_at((0.0, -0.72, 0.62), (0.0, 0.04, 0.0))
    )


@dataclass(frozen=True)
class NoiseModel:
    """Depth-camera noise: axial Gaussian (Kinect model), dropouts and flying pixels."""

    sigma_base_m: float = 0.0012
    sigma_quadratic: float = 0.0019
    dropout_fraction: float = 0.01
    flying_pixel_fraction: float = 0.002
    colour_sigma: float = 0.02

    def sigma(self, depth_m: FloatArray) -> FloatArray:
        """Standard deviation of the depth noise at each depth, in metres."""
        return np.asarray(
            self.sigma_base_m + self.sigma_quadratic * (depth_m - 0.4) ** 2, dtype=np.float64
        )


NO_NOISE = NoiseModel(0.0, 0.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class TruthObject:
    """One object on the table. ``position`` is the centre of its footprint on the table.

    ``radius`` is the sphere's, the cylinder's or the cone base's; ``height`` the extent along
    the vertical axis (a sphere's is its diameter); ``size`` a box's (length, width, height).
    """

    kind: str
    position: Vec3
    radius: float = 0.0
    height: float = 0.0
    size: Vec3 = (0.0, 0.0, 0.0)
    yaw: float = 0.0
    colour: Vec3 = PALETTE["red"]
    tilt: float = 0.0

    @property
    def rotation(self) -> FloatArray:
        """World-from-object rotation: a tilt about the object's x axis, then the yaw about z.

        The object frame has its origin at ``position`` (the base centre; a sphere's lowest
        point) and its axis along +z, from the base toward the top or apex.
        """
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        ct, st = math.cos(self.tilt), math.sin(self.tilt)
        yaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        tilt = np.array([[1.0, 0.0, 0.0], [0.0, ct, -st], [0.0, st, ct]])
        return np.asarray(yaw @ tilt, dtype=np.float64)

    @property
    def axis(self) -> Vec3:
        """The unit axis in the world frame (base toward top or apex)."""
        return vec3(self.rotation[:, 2])

    @property
    def expected_kind(self) -> ShapeKind:
        """The primitive the pipeline should report (a box's faces are planes)."""
        return ShapeKind.PLANE if self.kind == "Box" else ShapeKind(self.kind)

    @property
    def centre(self) -> Vec3:
        """The centre in the :class:`~shapes.types.Primitive` convention."""
        x, y, z = self.position
        if self.kind == "Sphere":
            return (x, y, z + self.radius)
        a = np.asarray(self.axis)
        if self.kind == "Cone":
            return vec3(np.asarray(self.position) + a * self.height / 4.0)
        h = self.size[2] if self.kind == "Box" else self.height
        return vec3(np.asarray(self.position) + a * h / 2.0)

    @property
    def apex(self) -> Vec3 | None:
        """A cone's apex, else None."""
        if self.kind != "Cone":
            return None
        return vec3(np.asarray(self.position) + np.asarray(self.axis) * self.height)

    @property
    def footprint_radius(self) -> float:
        """Radius of the circle that covers the object's footprint on the table."""
        if self.kind == "Box":
            return math.hypot(self.size[0], self.size[1]) / 2.0
        return self.radius

    def moved(self, dx: float, dy: float) -> TruthObject:
        """The same object shifted on the table."""
        x, y, z = self.position
        return replace(self, position=(x + dx, y + dy, z))


@dataclass(frozen=True)
class SyntheticShot:
    """One rendered frame, the object index of each point (-1 table), and the depth image."""

    frame: Frame
    labels: npt.NDArray[np.int64]
    depth: FloatArray
    rgb: FloatArray


def _nearest(t_all: list[FloatArray]) -> FloatArray:
    stacked = np.vstack(t_all)
    return np.asarray(stacked.min(axis=0), dtype=np.float64)


def _quadratic_roots(a: FloatArray, b: FloatArray, c: FloatArray) -> tuple[FloatArray, FloatArray]:
    disc = b * b - 4.0 * a * c
    ok = (disc >= 0) & (np.abs(a) > 1e-12)
    s = np.sqrt(np.where(ok, disc, 0.0))
    a_safe = np.where(ok, a, 1.0)
    t1 = np.where(ok, (-b - s) / (2 * a_safe), np.inf)
    t2 = np.where(ok, (-b + s) / (2 * a_safe), np.inf)
    return t1, t2


def _valid(t: FloatArray, ok: npt.NDArray[np.bool_]) -> FloatArray:
    return np.where(ok & (t > 1e-6), t, np.inf)


def _hit_object(obj: TruthObject, origin: FloatArray, dirs: FloatArray) -> FloatArray:
    """Ray parameter of the first hit on one object (inf for a miss)."""
    rot = obj.rotation
    o = (origin - np.asarray(obj.position)) @ rot  # local = R^T (p - pos)
    d = dirs @ rot
    ox, oy, oz = o
    dx, dy, dz = d[:, 0], d[:, 1], d[:, 2]
    hits: list[FloatArray] = []

    def cap(z_cap: float, radius: float) -> FloatArray:
        t = (z_cap - oz) / np.where(np.abs(dz) > 1e-12, dz, 1e-12)
        x, y = ox + t * dx, oy + t * dy
        return _valid(t, x * x + y * y <= radius * radius)

    if obj.kind == "Sphere":
        oc = o - np.array([0.0, 0.0, obj.radius])
        a = np.einsum("ij,ij->i", d, d)
        b = 2.0 * d @ oc
        t1, _ = _quadratic_roots(a, b, np.full_like(a, oc @ oc - obj.radius**2))
        hits.append(_valid(t1, np.isfinite(t1)))
    elif obj.kind == "Cylinder":
        a = dx * dx + dy * dy
        b = 2.0 * (ox * dx + oy * dy)
        t1, t2 = _quadratic_roots(a, b, np.full_like(a, ox * ox + oy * oy - obj.radius**2))
        for t in (t1, t2):
            z = oz + t * dz
            hits.append(_valid(t, np.isfinite(t) & (z >= 0) & (z <= obj.height)))
        hits += [cap(obj.height, obj.radius), cap(0.0, obj.radius)]
    elif obj.kind == "Cone":
        k2 = (obj.radius / obj.height) ** 2
        w0 = obj.height - oz
        a = dx * dx + dy * dy - k2 * dz * dz
        b = 2.0 * (ox * dx + oy * dy + k2 * w0 * dz)
        t1, t2 = _quadratic_roots(a, b, np.full_like(a, ox * ox + oy * oy - k2 * w0 * w0))
        for t in (t1, t2):
            z = oz + t * dz
            hits.append(_valid(t, np.isfinite(t) & (z >= 0) & (z <= obj.height)))
        hits.append(cap(0.0, obj.radius))
    elif obj.kind == "Box":
        lo = np.array([-obj.size[0] / 2, -obj.size[1] / 2, 0.0])
        hi = np.array([obj.size[0] / 2, obj.size[1] / 2, obj.size[2]])
        safe = np.where(np.abs(d) > 1e-12, d, 1e-12)
        ta, tb = (lo - o) / safe, (hi - o) / safe
        t_near = np.minimum(ta, tb).max(axis=1)
        t_far = np.maximum(ta, tb).min(axis=1)
        hits.append(_valid(t_near, t_near <= t_far))
    else:
        raise ValueError(f"kind: expected one of {KINDS}, got {obj.kind!r}")
    return _nearest(hits)


def _cast(obj: TruthObject, origin: FloatArray, dirs: FloatArray) -> FloatArray:
    """Like :func:`_hit_object`, but only for the rays that pass the object's bounding sphere."""
    height = obj.size[2] if obj.kind == "Box" else obj.height
    centre = np.asarray(obj.position) + obj.rotation[:, 2] * (height / 2)
    radius = math.hypot(obj.footprint_radius, height / 2) * 1.01
    oc = centre - origin
    along = dirs @ oc
    closest2 = oc @ oc - along**2 / np.einsum("ij,ij->i", dirs, dirs)
    near = np.flatnonzero((closest2 <= radius * radius) & (along > 0))
    t = np.full(len(dirs), np.inf)
    if len(near):
        t[near] = _hit_object(obj, origin, dirs[near])
    return t


@dataclass(frozen=True)
class TabletopScene:
    """A table with objects and a camera. ``render`` draws one noisy frame of it."""

    objects: tuple[TruthObject, ...]
    table_size: tuple[float, float] = (1.2, 0.8)
    camera: Camera = field(default_factory=Camera)

    def moved(self, index: int, dx: float, dy: float) -> TabletopScene:
        """The same scene with object ``index`` shifted on the table."""
        objs = list(self.objects)
        objs[index] = objs[index].moved(dx, dy)
        return replace(self, objects=tuple(objs))

    def without(self, index: int) -> TabletopScene:
        """The same scene with object ``index`` taken away."""
        return replace(self, objects=self.objects[:index] + self.objects[index + 1 :])

    def render(
        self, rng: np.random.Generator, noise: NoiseModel | None = None, stamp: float | None = None
    ) -> SyntheticShot:
        """Ray-cast one frame: points in the camera's optical frame plus the camera pose."""
        noise = NoiseModel() if noise is None else noise
        cam = self.camera
        pose = cam.world_from_camera
        v, u = np.mgrid[0 : cam.height, 0 : cam.width]
        dirs_cam = np.column_stack(
            (((u - cam.cx) / cam.fx).ravel(), ((v - cam.cy) / cam.fy).ravel(), np.ones(u.size))
        )
        dirs = dirs_cam @ pose[:3, :3].T
        origin = pose[:3, 3]
        # The table top: z = 0 inside the rectangle.
        t_table = -origin[2] / np.where(np.abs(dirs[:, 2]) > 1e-12, dirs[:, 2], 1e-12)
        x, y = origin[0] + t_table * dirs[:, 0], origin[1] + t_table * dirs[:, 1]
        inside = (np.abs(x) <= self.table_size[0] / 2) & (np.abs(y) <= self.table_size[1] / 2)
        t_all = [_valid(t_table, inside)] + [_cast(o, origin, dirs) for o in self.objects]
        stacked = np.vstack(t_all)
        which = stacked.argmin(axis=0)
        depth = stacked[which, np.arange(stacked.shape[1])]
        hit = np.isfinite(depth)
        hit &= rng.random(depth.size) >= noise.dropout_fraction
        noisy = depth + rng.standard_normal(depth.size) * noise.sigma(np.where(hit, depth, 1.0))
        flying = hit & (rng.random(depth.size) < noise.flying_pixel_fraction)
        noisy[flying] *= rng.uniform(0.6, 0.98, int(flying.sum()))
        palette = np.array([TABLE_COLOUR] + [o.colour for o in self.objects])
        rgb = palette[which] + rng.standard_normal((depth.size, 3)) * noise.colour_sigma
        rgb = np.clip(rgb, 0.0, 1.0)
        points = dirs_cam[hit] * noisy[hit, None]
        frame = Frame(points, rgb[hit], stamp, "synthetic_camera", pose)
        depth_img = np.where(hit, noisy, np.nan).reshape(cam.height, cam.width)
        return SyntheticShot(
            frame,
            (which[hit] - 1).astype(np.int64),
            depth_img,
            rgb.reshape(cam.height, cam.width, 3),
        )


def random_object(rng: np.random.Generator, kind: str, position: Vec3) -> TruthObject:
    """An object of ``kind`` with a size and colour drawn from realistic ranges."""
    colour = list(PALETTE.values())[int(rng.integers(len(PALETTE)))]
    if kind == "Sphere":
        r = float(rng.uniform(0.03, 0.07))
        return TruthObject(kind, position, radius=r, height=2 * r, colour=colour)
    if kind == "Cylinder":
        return TruthObject(
            kind,
            position,
            radius=float(rng.uniform(0.025, 0.05)),
            height=float(rng.uniform(0.08, 0.20)),
            colour=colour,
        )
    if kind == "Cone":
        return TruthObject(
            kind,
            position,
            radius=float(rng.uniform(0.035, 0.06)),
            height=float(rng.uniform(0.08, 0.15)),
            colour=colour,
        )
    if kind == "Box":
        size = vec3([rng.uniform(0.05, 0.12), rng.uniform(0.05, 0.12), rng.uniform(0.04, 0.12)])
        return TruthObject(
            kind, position, size=size, yaw=float(rng.uniform(0, math.pi)), colour=colour
        )
    raise ValueError(f"kind: expected one of {KINDS}, got {kind!r}")


def random_scene(
    rng: np.random.Generator,
    n_objects: int = 4,
    *,
    kinds: tuple[str, ...] = KINDS,
    gap_m: float = 0.06,
    region: tuple[float, float, float, float] = (-0.38, 0.38, -0.22, 0.26),
    camera: Camera | None = None,
) -> TabletopScene:
    """Place ``n_objects`` random objects on the table, at least ``gap_m`` apart.

    ``region`` is (xmin, xmax, ymin, ymax) of the footprint centres. Raises ValueError if the
    objects cannot be placed (too many for the region).
    """
    if n_objects < 0:
        raise ValueError(f"n_objects: expected a count >= 0, got {n_objects}")
    for k in kinds:
        if k not in KINDS:
            raise ValueError(f"kinds: expected names from {KINDS}, got {k!r}")
    placed: list[TruthObject] = []
    for _ in range(n_objects):
        kind = kinds[int(rng.integers(len(kinds)))]
        for _attempt in range(500):
            pos = (
                float(rng.uniform(region[0], region[1])),
                float(rng.uniform(region[2], region[3])),
                0.0,
            )
            obj = random_object(rng, kind, pos)
            if all(
                math.dist(obj.position, o.position)
                >= obj.footprint_radius + o.footprint_radius + gap_m
                for o in placed
            ):
                placed.append(obj)
                break
        else:
            raise ValueError(f"n_objects: could not place {n_objects} objects {gap_m} m apart")
    return TabletopScene(tuple(placed), camera=camera or Camera())
