"""``client.memory``: Engram's memory directives (no armor_py_api counterpart)."""

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from api.client._values import Value, parse_value
from api.protocol import ArmorDirectiveRes

if TYPE_CHECKING:
    from api.client._client import ArmorClient

__all__ = ["ArmorMemoryClient", "MemoryAnswer", "ScenePrimitive"]

_VECTORS = {"centre": "centre", "axis": "axis", "apex": "apex", "point_on_axis": "pointOnAxis"}
KINDS = ("Sphere", "Cylinder", "Cone", "Plane")
"""The primitive kinds the memory knows (Engram's ontology)."""


@dataclass(frozen=True)
class ScenePrimitive:
    """One primitive to send in a scene, with attributes as Engram's ontology names them."""

    name: str
    kind: str
    centre: tuple[float, float, float]
    axis: tuple[float, float, float] | None = None
    radius: float | None = None
    height: float | None = None
    apex: tuple[float, float, float] | None = None
    point_on_axis: tuple[float, float, float] | None = None
    hessian: float | None = None
    colour: tuple[float, float, float] | None = None
    tracking_id: int | None = None
    extent_x: float | None = None
    extent_y: float | None = None
    """A plane's extent along x and y in metres (a support's), sent as ``extentX``/``extentY``."""

    def __post_init__(self) -> None:
        """Refuse what no primitive can be, before anything is sent: raises ``ValueError``
        naming the primitive, the field, the value and what was expected, for a kind that is
        none of the four, a number that is not finite, a radius, height or extent that is not
        positive, a zero axis, a colour outside [0, 1] or a negative tracking id."""
        where = f"primitive {self.name!r}"
        if not isinstance(self.name, str) or not self.name.strip():
            raise ValueError(f"primitive name: got {self.name!r}, expected a non-empty string")
        if self.kind not in KINDS:
            raise ValueError(
                f"{where}: kind: got {self.kind!r}, expected one of {', '.join(KINDS)}"
            )
        for attribute in (*_VECTORS, "colour"):
            vector = getattr(self, attribute)
            if vector is not None and (len(vector) != 3 or not all(_finite(n) for n in vector)):
                raise ValueError(
                    f"{where}: {attribute}: got {vector!r}, expected three finite numbers"
                )
        for attribute in ("radius", "height", "extent_x", "extent_y"):
            number = getattr(self, attribute)
            if number is not None and not (_finite(number) and number > 0):
                raise ValueError(
                    f"{where}: {attribute}: got {number!r}, expected a positive number (metres)"
                )
        if self.hessian is not None and not _finite(self.hessian):
            raise ValueError(f"{where}: hessian: got {self.hessian!r}, expected a finite number")
        if self.axis is not None and not math.hypot(*self.axis) > 0:
            raise ValueError(f"{where}: axis: got {self.axis!r}, expected a non-zero vector")
        if self.colour is not None and not all(0 <= c <= 1 for c in self.colour):
            raise ValueError(f"{where}: colour: got {self.colour!r}, expected components in [0, 1]")
        if self.tracking_id is not None and self.tracking_id < 0:
            raise ValueError(f"{where}: tracking_id: got {self.tracking_id!r}, expected an id >= 0")

    def directives(self) -> list[tuple[str, str, str, list[str]]]:
        """``ADD IND CLASS`` and one ``ADD DATAPROP IND`` per attribute."""
        out: list[tuple[str, str, str, list[str]]] = [
            ("ADD", "IND", "CLASS", [self.name, self.kind])
        ]

        def value(prop: str, number: float, kind: str = "DOUBLE") -> None:
            out.append(("ADD", "DATAPROP", "IND", [prop, self.name, kind, repr(number)]))

        for attribute, prefix in _VECTORS.items():
            vector = getattr(self, attribute)
            if vector is not None:
                for axis, number in zip("XYZ", vector, strict=True):
                    value(f"{prefix}{axis}", float(number))
        if self.colour is not None:
            for channel, number in zip("RGB", self.colour, strict=True):
                value(f"colour{channel}", float(number))
        for attribute, prop in (("radius", "radius"), ("height", "height")):
            if getattr(self, attribute) is not None:
                value(prop, float(getattr(self, attribute)))
        if self.hessian is not None:
            value("hessianOffset", float(self.hessian))
        for attribute, prop in (("extent_x", "extentX"), ("extent_y", "extentY")):
            if getattr(self, attribute) is not None:
                value(prop, float(getattr(self, attribute)))
        if self.tracking_id is not None:
            out.append(
                (
                    "ADD",
                    "DATAPROP",
                    "IND",
                    ["trackingId", self.name, "INTEGER", str(self.tracking_id)],
                )
            )
        return out


def _finite(number: object) -> bool:
    return (
        isinstance(number, int | float) and not isinstance(number, bool) and math.isfinite(number)
    )


@dataclass(frozen=True)
class MemoryAnswer:
    """A memory directive's answer: its main values and its details as key -> values, as the
    ARMOR strings (``values``, ``details``) and as Python values (``typed_values``,
    ``typed_details``: IRIs as names, numbers as numbers, see :func:`parse_value`)."""

    values: list[str]
    details: Mapping[str, list[str]] = field(default_factory=dict)

    @property
    def typed_values(self) -> list[Value]:
        """``values`` as Python values: ``["<...#Scene-2>"]`` is ``["Scene-2"]``."""
        return [parse_value(v) for v in self.values]

    @property
    def typed_details(self) -> dict[str, list[Value]]:
        """``details`` as Python values: ``{"similar": ["<...#Scene-1> 0.5"]}`` is
        ``{"similar": [("Scene-1", 0.5)]}``, ``{"learned": ["true"]}`` ``{"learned": [True]}``."""
        return {key: [parse_value(v) for v in values] for key, values in self.details.items()}

    def detail(self, key: str) -> Value:
        """The first value of detail ``key`` as a Python value (``None`` if there is none)."""
        found = self.details.get(key) or []
        return parse_value(found[0]) if found else None

    @classmethod
    def of(cls, response: ArmorDirectiveRes) -> "MemoryAnswer":
        details: dict[str, list[str]] = {}
        for item in response.sparql_queried_objects:
            details.setdefault(item.key, []).append(item.value)
        return cls(list(response.queried_objects), details)


class ArmorMemoryClient:
    """Scenes in, recognition and retrieval out. Raises like the other clients."""

    def __init__(self, client: "ArmorClient") -> None:
        self._client = client

    def store_scene(
        self, primitives: Iterable[ScenePrimitive], episode: str | None = None
    ) -> MemoryAnswer:
        """LOAD INIT, the primitives' ADDs and SCENE UPDATED, as one list (one transaction).

        ``details["learned"]`` is ``["true"]`` when a new class was learned.
        """
        directives: list[tuple[str, str, str, list[str]]] = [("LOAD", "INIT", "", [])]
        for primitive in primitives:
            directives += primitive.directives()
        directives.append(("SCENE", "UPDATED", "", [episode] if episode else []))
        result = self._client.call_list(directives)
        return MemoryAnswer.of(self._client.raise_first_failure(result)[-1])

    def retrieve(self, cue: Iterable[str], spread: bool = False) -> MemoryAnswer:
        """Recall from relation triples such as ``"Sphere isAboveOf Plane"``."""
        res = self._client.checked("RETRIEVE", "SCENE", "SPREAD" if spread else "", list(cue))
        return MemoryAnswer.of(res)

    def sleep(self) -> MemoryAnswer:
        return MemoryAnswer.of(self._client.checked("MEMORY", "SLEEP", "", []))

    def pin(self, item: str, pinned: bool = True) -> None:
        self._client.checked("MEMORY", "PIN" if pinned else "UNPIN", "", [item])

    def restore(self, item: str) -> list[str]:
        return list(self._client.checked("MEMORY", "RESTORE", "", [item]).queried_objects)

    def scores(self, item: str) -> MemoryAnswer:
        return MemoryAnswer.of(self._client.checked("QUERY", "MEMORY", "SCORES", [item]))

    def level(self, item: str) -> str:
        return self._client.checked("QUERY", "MEMORY", "LEVEL", [item]).queried_objects[0]
