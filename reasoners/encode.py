"""Encode one scene: spatial relations with the SIT v1 formulas, then its signature.

Frame (SIT v1): x right, y behind (away from the observer), z up. Only the primary direction of
each ordered relation is computed (``b isRightOf a`` when ``b.x - a.x > e``; left is its
inverse), symmetric relations once per unordered pair, and no closure: the signature counts
exactly what the formulas fire. Objects are pairwise different.

>>> from kg import Store, ensure_ontology
>>> from kg.primitive import Primitive
>>> from reasoners.policy import load_policy
>>> store = Store(); _ = ensure_ontology(store)
>>> encoder = Encoder.from_store(store, load_policy(store))
>>> scene = [Primitive("s", "Sphere", centre=(.3, .3, .3), radius=.05),
...          Primitive("p", "Plane", centre=(.3, .1, .1), axis=(0, 0, 1))]
>>> [(r.subject, r.relation.value.rsplit("#")[-1], r.object) for r in encoder.relations(scene)]
[(0, 'isBehindOf', 1), (0, 'isAboveOf', 1)]
>>> encoder.signature(scene).complexity
4
"""

import math
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from pyoxigraph import NamedNode

from kg.primitive import KINDS, Primitive, Vector
from kg.store import Store
from ontologies.vocab import (
    IS_ABOVE_OF,
    IS_ALONG_X_WITH,
    IS_ALONG_Y_WITH,
    IS_ALONG_Z_WITH,
    IS_BEHIND_OF,
    IS_COAXIAL_WITH,
    IS_PARALLEL_WITH,
    IS_PERPENDICULAR_WITH,
    IS_RIGHT_OF,
    SPATIAL_INVERSES,
    TBOX,
    engram,
)
from reasoners.errors import InvalidSceneError, PolicyError
from reasoners.policy import Policy
from reasoners.signature import Key, Signature

__all__ = ["Encoder", "Relation"]

SYMMETRIC = frozenset(r for r, inverse in SPATIAL_INVERSES.items() if r == inverse)


@dataclass(frozen=True)
class Relation:
    """``primitives[subject] relation primitives[object]`` (indices into the scene's list)."""

    subject: int
    relation: NamedNode
    object: int


class Encoder:
    """Computes relations and signatures with the thresholds of one policy."""

    def __init__(self, policy: Policy, properties: Mapping[tuple[NamedNode, NamedNode], NamedNode]):
        self.policy = policy
        self.properties = dict(properties)
        """(leaf class, relation) -> signature property."""
        self.leaf: dict[str, NamedNode] = {kind: engram(kind) for kind in KINDS}
        missing = [
            f"{leaf.value} {relation.value}"
            for leaf in self.leaf.values()
            for relation in SPATIAL_INVERSES
            if (leaf, relation) not in self.properties
        ]
        if missing:
            raise PolicyError(f"no signature property for: {', '.join(missing[:4])}")

    @classmethod
    def from_store(cls, store: Store, policy: Policy) -> "Encoder":
        """An encoder whose signature properties are those the T-Box annotates."""
        properties = {}
        for row in store.select("memory_signature_properties", graph=TBOX):
            prop, leaf, relation = row["property"], row["subjectType"], row["relation"]
            if isinstance(prop, NamedNode) and isinstance(leaf, NamedNode):
                properties[(leaf, relation)] = prop
        return cls(policy, properties)  # type: ignore[arg-type]

    # Relations ---------------------------------------------------------------------------------

    def relations(self, primitives: Sequence[Primitive]) -> list[Relation]:
        """Every relation the SIT v1 formulas fire between the primitives, primary direction."""
        p = self.policy
        ex, ey, ez = p.alignedThresholdX, p.alignedThresholdY, p.alignedThresholdZ
        out: list[Relation] = []
        count = len(primitives)
        for i in range(count):
            a = primitives[i]
            ax, ay, az = a.centre
            for j in range(count):
                if i == j:
                    continue
                bx, by, bz = primitives[j].centre
                # b R a for the ordered relations: "j isRightOf i" when j has the larger x.
                if bx - ax > ex:
                    out.append(Relation(j, IS_RIGHT_OF, i))
                if by - ay > ey:
                    out.append(Relation(j, IS_BEHIND_OF, i))
                if bz - az > ez:
                    out.append(Relation(j, IS_ABOVE_OF, i))
        for i in range(count):
            a = primitives[i]
            for j in range(i + 1, count):
                b = primitives[j]
                dx, dy, dz = (abs(u - v) for u, v in zip(a.centre, b.centre, strict=True))
                if dy <= ey and dz <= ez:
                    out.append(Relation(i, IS_ALONG_X_WITH, j))
                if dx <= ex and dz <= ez:
                    out.append(Relation(i, IS_ALONG_Y_WITH, j))
                if dx <= ex and dy <= ey:
                    out.append(Relation(i, IS_ALONG_Z_WITH, j))
                parallel = False
                if a.axis is not None and b.axis is not None:
                    cross = _cross(a.axis, b.axis)
                    parallel = all(abs(c) <= p.parallelThreshold for c in cross)
                    if parallel:
                        out.append(Relation(i, IS_PARALLEL_WITH, j))
                    if abs(_dot(a.axis, b.axis)) <= p.perpendicularThreshold:
                        out.append(Relation(i, IS_PERPENDICULAR_WITH, j))
                if self._coaxial(a, b, parallel) or self._coaxial(b, a, parallel):
                    out.append(Relation(i, IS_COAXIAL_WITH, j))
        return out

    def _coaxial(self, a: Primitive, b: Primitive, parallel: bool) -> bool:
        """b's centre lies within the threshold of a's axis line (a orientable; if b is
        orientable too, the two must be parallel: SIT v1's coaxial rule and its sphere variant)."""
        if a.axis is None or (b.axis is not None and not parallel):
            return False
        offset = tuple(v - u for u, v in zip(a.centre, b.centre, strict=True))
        t = _dot(a.axis, offset)  # type: ignore[arg-type]
        rest = [o - t * c for o, c in zip(offset, a.axis, strict=True)]
        return math.sqrt(sum(r * r for r in rest)) <= self.policy.coaxialThreshold

    # Signatures --------------------------------------------------------------------------------

    def signature(
        self, primitives: Sequence[Primitive], relations: Iterable[Relation] | None = None
    ) -> Signature:
        """The SIT v1 "full" signature: for R(s, o) the links ``<type(s)>R o`` and
        ``<type(o)>inverse(R) s``, counted as distinct objects per (property, leaf type)."""
        if relations is None:
            relations = self.relations(primitives)
        return Signature(_count(self.links(primitives, relations), primitives, self.leaf))

    def links(
        self, primitives: Sequence[Primitive], relations: Iterable[Relation]
    ) -> set[tuple[NamedNode, int]]:
        """The scene's signature links (property, object index), without duplicates."""
        links: set[tuple[NamedNode, int]] = set()
        for r in relations:
            s_leaf = self.leaf[primitives[r.subject].kind]
            o_leaf = self.leaf[primitives[r.object].kind]
            links.add((self.properties[(s_leaf, r.relation)], r.object))
            links.add((self.properties[(o_leaf, SPATIAL_INVERSES[r.relation])], r.subject))
        return links

    def cue_signature(self, triples: Sequence[tuple[str, str, str]]) -> Signature:
        """The signature of relations between object types, each triple with its own objects:
        ``("Sphere", "isAboveOf", "Plane")`` gives sphereIsAboveOf ≥1 Plane, planeIsBelowOf ≥1
        Sphere. Raises ``InvalidSceneError`` naming a bad type or relation."""
        if not triples:
            raise InvalidSceneError("cue: got no relations, expected at least one triple")
        relations = {r.value.rsplit("#", 1)[-1]: r for r in SPATIAL_INVERSES}
        counts: dict[Key, int] = defaultdict(int)
        for position, triple in enumerate(triples):
            if not isinstance(triple, tuple | list) or len(triple) != 3:
                raise InvalidSceneError(
                    f"cue relation {position}: got {triple!r}, "
                    "expected (subject type, relation, object type)"
                )
            s_kind, name, o_kind = triple
            for field, kind in (("subject type", s_kind), ("object type", o_kind)):
                if kind not in self.leaf:
                    raise InvalidSceneError(
                        f"cue relation {position}: {field}: got {kind!r}, "
                        f"expected one of {', '.join(KINDS)}"
                    )
            relation = relations.get(name)
            if relation is None:
                raise InvalidSceneError(
                    f"cue relation {position}: relation: got {name!r}, "
                    f"expected one of {', '.join(sorted(relations))}"
                )
            s_leaf, o_leaf = self.leaf[s_kind], self.leaf[o_kind]
            counts[(self.properties[(s_leaf, relation)], o_leaf)] += 1
            counts[(self.properties[(o_leaf, SPATIAL_INVERSES[relation])], s_leaf)] += 1
        return Signature(counts)


def _count(
    links: Iterable[tuple[NamedNode, int]],
    primitives: Sequence[Primitive],
    leaf: Mapping[str, NamedNode],
) -> dict[Key, int]:
    counts: dict[Key, int] = defaultdict(int)
    for prop, obj in links:  # links are distinct (property, object) pairs
        counts[(prop, leaf[primitives[obj].kind])] += 1
    return counts


def _cross(a: Vector, b: Vector) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a: Vector, b: Vector) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
