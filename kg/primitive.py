"""The one primitive type: what perception sees, the client sends, the memory stores and reads back.

A primitive is one perceived object approximated by a sphere, cylinder, cone or plane. Every
layer uses this type: the Python client sends it (:mod:`api.client`), the ARMOR engine parses
the ``ADD DATAPROP IND`` directives into it, the scene memory encodes it, :mod:`kg.scene_triples`
writes it as triples and reads it back, and the views return it as JSON. This module imports
only the standard library and :mod:`kg.errors`, so a robot importing the client loads nothing of
the store.

Frame (SIT v1): x points to the observer's right, y away from the observer (behind), z up.
Lengths are metres. Axes (a plane's normal) are stored as unit vectors.

Its attributes carry the names of Engram's ontology (``centreX``, ``radius``, ``trackingId``:
:data:`ATTRIBUTES`), which name the ARMOR directives and the stored triples alike;
:meth:`Primitive.attributes` and :meth:`Primitive.from_attributes` convert both ways.

>>> ball = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
>>> table = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 2))
>>> table.axis
(0.0, 0.0, 1.0)
>>> ball.attributes()
{'centreX': 0.3, 'centreY': 0.3, 'centreZ': 0.3, 'radius': 0.05}
>>> Primitive.from_attributes("ball", "Sphere", ball.attributes()) == ball
True
>>> Primitive("x", "Cube", centre=(0, 0, 0))  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
kg.errors.InvalidPrimitiveError: primitive 'x': kind: got 'Cube', expected one of ...
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from kg.errors import InvalidPrimitiveError

__all__ = [
    "ATTRIBUTES",
    "KINDS",
    "ORIENTABLE_KINDS",
    "Kind",
    "Primitive",
    "Vector",
]

Kind = Literal["Sphere", "Cylinder", "Cone", "Plane"]
KINDS: tuple[Kind, ...] = ("Sphere", "Cylinder", "Cone", "Plane")
ORIENTABLE_KINDS = frozenset({"Cylinder", "Cone", "Plane"})
Vector = tuple[float, float, float]

_UNIT_TOLERANCE = 1e-12
"""An axis whose length is this close to 1 is unit already; dividing it again by its computed
length could change its last bits, so normalising would not be idempotent."""
_ONLY_FOR = {
    "apex": "Cone",
    "point_on_axis": "Cylinder",
    "hessian": "Plane",
    "extent_x": "Plane",
    "extent_y": "Plane",
}
_VECTOR_ATTRIBUTES: dict[str, tuple[str, str, str]] = {
    "centre": ("centreX", "centreY", "centreZ"),
    "axis": ("axisX", "axisY", "axisZ"),
    "apex": ("apexX", "apexY", "apexZ"),
    "point_on_axis": ("pointOnAxisX", "pointOnAxisY", "pointOnAxisZ"),
    "colour": ("colourR", "colourG", "colourB"),
}
_NUMBER_ATTRIBUTES = {
    "radius": "radius",
    "height": "height",
    "hessian": "hessianOffset",
    "extent_x": "extentX",
    "extent_y": "extentY",
    "tracking_id": "trackingId",
}
ATTRIBUTES: dict[str, tuple[str, int | None]] = {
    **{
        name: (field, i)
        for field, names in _VECTOR_ATTRIBUTES.items()
        for i, name in enumerate(names)
    },
    **{name: (field, None) for field, name in _NUMBER_ATTRIBUTES.items()},
}
"""Each attribute's name in Engram's ontology -> (the :class:`Primitive` field, the component
index for a vector field, None for a number)."""


@dataclass(frozen=True)
class Primitive:
    """One perceived object, approximated by a sphere, cylinder, cone or plane.

    ``axis`` is required for cylinders, cones (axis) and planes (normal) and refused for spheres;
    it is normalised to unit length (one within 1e-12 of it is kept as given). ``apex`` is for
    cones, ``point_on_axis`` for cylinders, ``hessian`` (offset d of n . x + d = 0) for planes.
    ``radius`` and ``height`` are positive, ``colour`` is RGB in [0, 1], ``tracking_id`` a
    non-negative integer. ``extent_x`` and ``extent_y`` (planes only, positive, metres) are the
    sides along x and y of the rectangle bounding the plane's measured points: how large a table
    or floor was seen.

    Raises :class:`~kg.errors.InvalidPrimitiveError` (a ``ValueError``) naming the primitive,
    the field, the value and what was expected.
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
            if abs(norm - 1.0) > _UNIT_TOLERANCE:  # a unit axis stays as given: reads back equal
                axis = (axis[0] / norm, axis[1] / norm, axis[2] / norm)
            self._set("axis", axis)
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
            if name in ("apex", "point_on_axis"):
                self._set(name, self._vector(name, value))
                continue
            number = self._number(name, value)
            if name != "hessian" and number <= 0:
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

    @classmethod
    def from_attributes(
        cls, id: str, kind: str, attributes: Mapping[str, float | int]
    ) -> "Primitive":
        """The primitive whose attributes, named as in Engram's ontology (:data:`ATTRIBUTES`),
        are ``attributes``: the inverse of :meth:`attributes`.

        Raises :class:`~kg.errors.InvalidPrimitiveError` for a name that is no attribute, a
        vector given in part (``centreX`` without ``centreY``), no centre, a ``trackingId``
        that is not a whole number, and whatever the constructor refuses.
        """
        fields: dict[str, object] = {}
        vectors: dict[str, list[float | int | None]] = {}
        for name, value in attributes.items():
            if name not in ATTRIBUTES:
                raise InvalidPrimitiveError(
                    f"primitive {id!r}: attribute: got {name!r}, expected one of "
                    f"{', '.join(ATTRIBUTES)}"
                )
            field, index = ATTRIBUTES[name]
            if index is None:
                fields[field] = value
            else:
                vectors.setdefault(field, [None, None, None])[index] = value
        for field, vector in vectors.items():
            if None in vector:
                missing = _VECTOR_ATTRIBUTES[field][vector.index(None)]
                raise InvalidPrimitiveError(f"primitive {id!r}: {field} lacks its {missing[-1]}")
            fields[field] = tuple(vector)
        if "centre" not in fields:
            raise InvalidPrimitiveError(f"primitive {id!r}: no centre (centreX/Y/Z)")
        tracking = fields.get("tracking_id")
        if isinstance(tracking, float) and tracking.is_integer():
            fields["tracking_id"] = int(tracking)
        return cls(id, kind, **fields)  # type: ignore[arg-type]

    def attributes(self) -> dict[str, float | int]:
        """The set attributes, named as in Engram's ontology (:data:`ATTRIBUTES`), in the
        order a client sends them: ``{"centreX": 0.3, ..., "radius": 0.05}``."""
        out: dict[str, float | int] = {}
        for field, names in _VECTOR_ATTRIBUTES.items():
            vector = getattr(self, field)
            if vector is not None:
                out.update(zip(names, vector, strict=True))
        for field, name in _NUMBER_ATTRIBUTES.items():
            value = getattr(self, field)
            if value is not None:
                out[name] = value
        return out

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
