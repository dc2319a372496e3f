"""Plain, frozen value types shared by the perception stages.

Field names follow the attributes of the Engram ontology (``engram:centreX`` to
``engram:trackingId``) so that the client that writes them to the memory maps one field to one
property; see :meth:`Primitive.attributes`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import StrEnum

import numpy as np
import numpy.typing as npt

__all__ = ["FloatArray", "Primitive", "ShapeKind", "SupportPlane", "Vec3", "vec3"]

FloatArray = npt.NDArray[np.float64]
Vec3 = tuple[float, float, float]


def vec3(values: npt.ArrayLike) -> Vec3:
    """Turn three numbers into a plain tuple of floats.

    >>> vec3(np.array([1, 2, 3]))
    (1.0, 2.0, 3.0)
    """
    a = np.asarray(values, dtype=np.float64).reshape(3)
    return (float(a[0]), float(a[1]), float(a[2]))


class ShapeKind(StrEnum):
    """The four primitive kinds; the values are the ontology's class names."""

    SPHERE = "Sphere"
    CYLINDER = "Cylinder"
    CONE = "Cone"
    PLANE = "Plane"


@dataclass(frozen=True)
class SupportPlane:
    """The support (table) plane ``normal . x + offset = 0``, normal pointing up, unit length."""

    normal: Vec3
    offset: float
    centre: Vec3 | None = None
    """The mean of the plane's points (on the plane), when known."""
    extent: tuple[float, float] | None = None
    """The sides of the plane's points' bounding rectangle along world x and y, in metres."""

    def signed_distance(self, points: FloatArray) -> FloatArray:
        """Height of each point above the plane, in metres (negative below)."""
        return np.asarray(points @ np.asarray(self.normal) + self.offset, dtype=np.float64)


@dataclass(frozen=True)
class Primitive:
    """One perceived object approximated by a geometric primitive, in the world frame (metres).

    Which fields are set depends on ``kind``:

    - Sphere: ``centre``, ``radius``.
    - Cylinder: ``centre`` (middle of the axis segment), ``axis`` (unit, pointing away from the
      support when upright), ``radius``, ``height``, ``point_on_axis`` (the centre of the base).
    - Cone: ``centre`` (centroid of the solid cone, a quarter of the height above the base),
      ``axis`` (unit, from apex to base), ``apex``, ``radius`` (of the base), ``height``.
    - Plane: ``centre`` (mean of the plane's inliers, on the plane), ``axis`` (the unit normal,
      pointing out of the object), ``hessian_offset`` d with ``axis . x + d = 0``.

    A support (the table or floor the objects stand on) may carry ``extent``: the sides of its
    points' bounding rectangle along world x and y, in metres (:attr:`SupportPlane.extent`).

    ``colour`` is the mean RGB in [0, 1] of the object's points when the cloud has colours,
    ``tracking_id`` the tracker's id (never reused), ``inlier_ratio`` the share of the cluster's
    points within the selection threshold of the chosen model.

    >>> p = Primitive(ShapeKind.SPHERE, centre=(0.1, 0.2, 0.05), radius=0.05, tracking_id=3)
    >>> p.attributes()["radius"], p.attributes()["trackingId"]
    (0.05, 3)
    """

    kind: ShapeKind
    centre: Vec3
    axis: Vec3 | None = None
    radius: float | None = None
    height: float | None = None
    apex: Vec3 | None = None
    point_on_axis: Vec3 | None = None
    hessian_offset: float | None = None
    colour: Vec3 | None = None
    tracking_id: int | None = None
    inlier_ratio: float = 1.0
    stamp: float | None = field(default=None, compare=False)
    extent: tuple[float, float] | None = None

    def with_tracking(self, tracking_id: int, colour: Vec3 | None) -> Primitive:
        """A copy carrying a tracking id and a colour."""
        return replace(self, tracking_id=tracking_id, colour=colour)

    @property
    def half_angle(self) -> float | None:
        """Half opening angle of a cone in radians (``atan(radius / height)``), else None."""
        if self.kind is not ShapeKind.CONE or not self.radius or not self.height:
            return None
        return math.atan2(self.radius, self.height)

    def attributes(self) -> dict[str, float | int]:
        """The set attributes keyed by the ontology's property local names.

        Keys: centreX/Y/Z, axisX/Y/Z, radius, height, apexX/Y/Z, pointOnAxisX/Y/Z,
        hessianOffset, extentX/Y, colourR/G/B, trackingId. Unset fields are left out.
        """
        out: dict[str, float | int] = {}

        def put3(prefix: str, value: Vec3 | None) -> None:
            if value is not None:
                for suffix, v in zip("XYZ", value, strict=True):
                    out[prefix + suffix] = v

        put3("centre", self.centre)
        put3("axis", self.axis)
        if self.radius is not None:
            out["radius"] = self.radius
        if self.height is not None:
            out["height"] = self.height
        put3("apex", self.apex)
        put3("pointOnAxis", self.point_on_axis)
        if self.hessian_offset is not None:
            out["hessianOffset"] = self.hessian_offset
        if self.extent is not None:
            out["extentX"], out["extentY"] = self.extent
        if self.colour is not None:
            for suffix, v in zip("RGB", self.colour, strict=True):
                out["colour" + suffix] = v
        if self.tracking_id is not None:
            out["trackingId"] = self.tracking_id
        return out
