"""``client.memory``: Engram's memory directives (no armor_py_api counterpart)."""

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from api.client._values import Value, parse_value
from kg.primitive import Primitive

if TYPE_CHECKING:
    from api.client._client import ArmorClient
    from api.protocol import ArmorDirectiveRes

__all__ = [
    "ArmorMemoryClient",
    "MemoryAnswer",
    "Primitive",
    "primitive_directives",
    "scene_directives",
]


def primitive_directives(primitive: Primitive) -> list[tuple[str, str, str, list[str]]]:
    """``ADD IND CLASS`` and one ``ADD DATAPROP IND`` per attribute, named as in Engram's
    ontology (``centreX``, ``radius``, ``trackingId``): how a primitive travels in ARMOR.

    >>> ball = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
    >>> for directive in primitive_directives(ball)[:3]:
    ...     print(*directive)
    ADD IND CLASS ['ball', 'Sphere']
    ADD DATAPROP IND ['centreX', 'ball', 'DOUBLE', '0.3']
    ADD DATAPROP IND ['centreY', 'ball', 'DOUBLE', '0.3']
    """
    out: list[tuple[str, str, str, list[str]]] = [
        ("ADD", "IND", "CLASS", [primitive.id, primitive.kind])
    ]
    for name, value in primitive.attributes().items():
        if isinstance(value, int):
            out.append(("ADD", "DATAPROP", "IND", [name, primitive.id, "INTEGER", str(value)]))
        else:
            out.append(("ADD", "DATAPROP", "IND", [name, primitive.id, "DOUBLE", repr(value)]))
    return out


def scene_directives(
    primitives: Iterable[Primitive], episode: str | None = None
) -> list[tuple[str, str, str, list[str]]]:
    """One scene as one directive list: ``LOAD INIT``, each primitive's directives
    (:func:`primitive_directives`), ``SCENE UPDATED`` (naming ``episode`` when given)."""
    directives: list[tuple[str, str, str, list[str]]] = [("LOAD", "INIT", "", [])]
    for primitive in primitives:
        directives += primitive_directives(primitive)
    directives.append(("SCENE", "UPDATED", "", [episode] if episode else []))
    return directives


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
    def of(cls, response: "ArmorDirectiveRes") -> "MemoryAnswer":
        details: dict[str, list[str]] = {}
        for item in response.sparql_queried_objects:
            details.setdefault(item.key, []).append(item.value)
        return cls(list(response.queried_objects), details)


class ArmorMemoryClient:
    """Scenes in, recognition and retrieval out. Raises like the other clients."""

    def __init__(self, client: "ArmorClient") -> None:
        self._client = client

    def store_scene(
        self, primitives: Iterable[Primitive], episode: str | None = None
    ) -> MemoryAnswer:
        """LOAD INIT, the primitives' ADDs and SCENE UPDATED, as one list (one transaction).

        ``details["learned"]`` is ``["true"]`` when a new class was learned.
        """
        result = self._client.call_list(scene_directives(primitives, episode))
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
