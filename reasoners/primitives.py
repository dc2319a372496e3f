"""What perception hands the scene memory: geometric primitives of one scene.

Frame (SIT v1): x points to the observer's right, y away from the observer (behind), z up.
Lengths are metres. Axes (a plane's normal) are stored as unit vectors.

>>> ball = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
>>> table = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 2))
>>> table.axis
(0.0, 0.0, 1.0)
>>> Primitive("x", "Cube", centre=(0, 0, 0))  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
reasoners.errors.InvalidPrimitiveError: primitive 'x': kind: got 'Cube', expected one of ...
"""

import math
from dataclasses import dataclass
from typing import Literal

from reasoners.errors import InvalidPrimitiveError

__all__ = ["KINDS", "ORIENTABLE_KINDS", "Kind", "Primitive", "Vector"]

Kind = Literal["Sphere", "Cylinder", "Cone", "Plane"]
KINDS: tuple[Kind, ...] = ("Sphere", "Cylinder", "Cone", "Plane")
ORIENTABLE_KINDS = frozenset({"Cylinder", "Cone", "Plane"})
Vector = tuple[float, float, float]

_ONLY_FOR = {"apex": "Cone", "point_on_axis": "Cylinder", "hessian": "Plane"}
_EXTENT = ("extent_x", "extent_y")


@dataclass(frozen=True)
class Primitive:
    """One perceived object, approximated by a sphere, cylinder, cone or plane.

    ``axis`` is required for cylinders, cones (axis) and planes (normal) and refused for spheres;
    it is normalised to unit length. ``apex`` is for cones, ``point_on_axis`` for cylinders,
    ``hessian`` (offset d of n . x + d = 0) for planes. ``radius`` and ``height`` are positive,
    ``colour`` is RGB in [0, 1], ``tracking_id`` a non-negative integer. ``extent_x`` and
    ``extent_y`` (planes only, positive, metres) are the sides along x and y of the rectangle
    that bounds the plane's measured points: how large a table or floor was seen.

    Raises :class:`~reasoners.errors.InvalidPrimitiveError` (a ``ValueError``) naming the field,
    the value and what was expected.
    """

    id: str
    kind: Kind
    centre: Vector
    axis: Vector | None = None
    radius: float | None = None
    height: float | None = None
    apex: Vector | None = None
    point_on_axis: Vector | None = None
    hessian: float | None = None
    colour: Vector | None = None
    tracking_id: int | None = None
    extent_x: float | None = None
    extent_y: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.id, str) or not self.id.strip():
            raise InvalidPrimitiveError(
                f"primitive id: got {self.id!r}, expected a non-empty string"
            )
        if self.kind not in KINDS:
            self._fail("kind", self.kind, f"one of {', '.join(KINDS)}")
        self._set("centre", self._vector("centre", self.centre))
        if self.kind in ORIENTABLE_KINDS:
            if self.axis is None:
                self._fail("axis", None, f"a non-zero 3-vector (a {self.kind} needs its axis)")
            axis = self._vector("axis", self.axis)
            norm = math.hypot(*axis)  # no overflow: (1e200, 0, 0) is a fine direction
            if not norm >= 1e-9 or not math.isfinite(norm):
                self._fail("axis", self.axis, "a non-zero 3-vector")
            self._set("axis", (axis[0] / norm, axis[1] / norm, axis[2] / norm))
        elif self.axis is not None:
            self._fail("axis", self.axis, "None (a sphere has no axis)")
        for name in ("radius", "height"):
            value = getattr(self, name)
            if value is not None:
                number = self._number(name, value)
                if number <= 0:
                    self._fail(name, value, "a positive length in metres")
                self._set(name, number)
        if self.height is not None and self.kind not in ("Cylinder", "Cone"):
            self._fail("height", self.height, f"None (a {self.kind} has no height)")
        if self.radius is not None and self.kind == "Plane":
            self._fail("radius", self.radius, "None (a Plane has no radius)")
        for name, kind in _ONLY_FOR.items():
            value = getattr(self, name)
            if value is None:
                continue
            if self.kind != kind:
                self._fail(name, value, f"None (only a {kind} has it)")
            checked = self._number(name, value) if name == "hessian" else self._vector(name, value)
            self._set(name, checked)
        for name in _EXTENT:
            value = getattr(self, name)
            if value is None:
                continue
            if self.kind != "Plane":
                self._fail(name, value, "None (only a Plane has an extent)")
            number = self._number(name, value)
            if number <= 0:
                self._fail(name, value, "a positive length in metres")
            self._set(name, number)
        if self.colour is not None:
            colour = self._vector("colour", self.colour)
            if not all(0.0 <= c <= 1.0 for c in colour):
                self._fail("colour", self.colour, "three channels in [0, 1]")
            self._set("colour", colour)
        if self.tracking_id is not None and (
            isinstance(self.tracking_id, bool)
            or not isinstance(self.tracking_id, int)
            or self.tracking_id < 0
        ):
            self._fail("tracking_id", self.tracking_id, "a non-negative integer")

    @property
    def orientable(self) -> bool:
        """True for cylinders, cones and planes."""
        return self.kind in ORIENTABLE_KINDS

    def _set(self, name: str, value: object) -> None:
        object.__setattr__(self, name, value)

    def _fail(self, name: str, value: object, expected: str) -> None:
        raise InvalidPrimitiveError(
            f"primitive {self.id!r}: {name}: got {value!r}, expected {expected}"
        )

    def _number(self, name: str, value: object) -> float:
        if (
            isinstance(value, bool)
            or not isinstance(value, int | float)
            or not math.isfinite(value)
        ):
            self._fail(name, value, "a finite number")
        return float(value)  # type: ignore[arg-type]

    def _vector(self, name: str, value: object) -> Vector:
        if not isinstance(value, tuple | list) or len(value) != 3:
            self._fail(name, value, "three finite numbers (x, y, z)")
        x, y, z = (self._number(name, c) for c in value)  # type: ignore[attr-defined]
        return (x, y, z)
