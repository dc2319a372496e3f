"""Find, and where it is safe mend, damage to the scene memory's graphs that would stop it
loading: what ``engram check`` reports and what start-up names instead of a traceback.

A store edited by hand (or by a tool that does not know Engram's layout) can lose a triple the
memory cannot do without, such as the cardinality of a restriction. Each :class:`Damage` names
the node, what is wrong, and how to repair it. A restriction is a shared node whose IRI is a
digest of its property, class and cardinality (:func:`reasoners.persist.restriction_iri`), so a
missing or wrong part of it is recovered exactly, from the learned classes' signatures or by
trying cardinalities: that is the one repair :func:`fix_memory` makes by itself. Anything else
is reported with what to do (restore a backup, or forget the class).
"""

import json
from collections import defaultdict
from dataclasses import dataclass, field

from pyoxigraph import Literal, NamedNode, Quad

from kg.errors import StoreError
from kg.store import Store
from ontologies.vocab import (
    CREATED,
    EPISODIC,
    LAST_ACCESSED,
    MEMORY,
    OWL_MIN_QUALIFIED_CARDINALITY,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    OWL_RESTRICTION,
    RDF_TYPE,
    SCORE,
)
from reasoners.errors import InvalidSceneError
from reasoners.memory import SceneMemory
from reasoners.persist import is_restriction, restriction_iri
from reasoners.signature import Key, Signature

__all__ = [
    "Damage",
    "DamagedMemoryError",
    "check_memory",
    "describe",
    "fix_memory",
    "open_scene_memory",
]

_MAX_TRIED_CARDINALITY = 10_000
_RESTORE = "restore the store from a backup (engram backup), or rebuild it"


class DamagedMemoryError(StoreError):
    """The memory graphs miss something the scene memory needs; the message says what."""


@dataclass(frozen=True)
class Damage:
    """One thing wrong in the memory graphs, and its repair."""

    node: str
    problem: str
    repair: str
    deletes: tuple[Quad, ...] = field(default=(), repr=False)
    inserts: tuple[Quad, ...] = field(default=(), repr=False)

    @property
    def fixable(self) -> bool:
        """True if :func:`fix_memory` can mend it by itself."""
        return bool(self.inserts or self.deletes)

    def __str__(self) -> str:
        return f"{self.node}: {self.problem}; {self.repair}"


def _known_restrictions(
    classes: dict[NamedNode, dict[str, list[object]]],
) -> dict[str, tuple[Key, int]]:
    """Every restriction the classes' signatures name, by IRI."""
    known: dict[str, tuple[Key, int]] = {}
    for values in classes.values():
        for text in values.get("signature", []):
            try:
                signature = Signature.from_json(str(getattr(text, "value", text)))
            except InvalidSceneError:
                continue
            for key, n in _counts(signature):
                known[restriction_iri(key, n).value] = (key, n)
    return known


def _counts(signature: Signature) -> list[tuple[Key, int]]:
    """The ((property, leaf class), count) entries of ``signature``."""
    return [((NamedNode(p), NamedNode(t)), int(n)) for p, t, n in json.loads(signature.to_json())]


def _by_subject(
    rows: list[dict[str, NamedNode | Literal]], subject: str
) -> dict[NamedNode, dict[str, list[object]]]:
    grouped: dict[NamedNode, dict[str, list[object]]] = {}
    for row in rows:
        node = row[subject]
        assert isinstance(node, NamedNode)
        values = grouped.setdefault(node, defaultdict(list))
        for column, term in row.items():
            if column != subject and term not in values[column]:
                values[column].append(term)
    return grouped


def _restriction_quads(node: NamedNode, key: Key, n: int) -> tuple[Quad, ...]:
    return (
        Quad(node, RDF_TYPE, OWL_RESTRICTION, MEMORY),
        Quad(node, OWL_ON_PROPERTY, key[0], MEMORY),
        Quad(node, OWL_ON_CLASS, key[1], MEMORY),
        Quad(node, OWL_MIN_QUALIFIED_CARDINALITY, Literal(n), MEMORY),
    )


def _recover(
    node: NamedNode, values: dict[str, list[object]], known: dict[str, tuple[Key, int]]
) -> tuple[Key, int] | None:
    if node.value in known:
        return known[node.value]
    properties, classes = values.get("property", []), values.get("onClass", [])
    if len(properties) == 1 and len(classes) == 1:
        prop, cls = properties[0], classes[0]
        if isinstance(prop, NamedNode) and isinstance(cls, NamedNode):
            key = (prop, cls)
            for n in range(_MAX_TRIED_CARDINALITY + 1):
                if restriction_iri(key, n) == node:
                    return key, n
    return None


def _restriction_damage(
    store: Store, classes: dict[NamedNode, dict[str, list[object]]]
) -> list[Damage]:
    rows = _by_subject(store.select("memory_load_restrictions", g=MEMORY), "restriction")
    for row in store.select("memory_load_definitions", g=MEMORY):
        for iri in row["restrictions"].value.split():
            rows.setdefault(NamedNode(iri), defaultdict(list))  # a restriction with no property
    known = _known_restrictions(classes)
    damages = []
    for node, values in rows.items():
        counts = values.get("n", [])
        problems = []
        if len(values.get("property", [])) != 1:
            problems.append(f"{len(values.get('property', []))} owl:onProperty values, expected 1")
        if len(values.get("onClass", [])) != 1:
            problems.append(f"{len(values.get('onClass', []))} owl:onClass values, expected 1")
        if len(counts) != 1:
            problems.append(f"{len(counts)} owl:minQualifiedCardinality values, expected 1")
        elif not (
            isinstance(counts[0], Literal)
            and counts[0].value.isascii()
            and counts[0].value.isdigit()
        ):
            problems.append(
                f"owl:minQualifiedCardinality {counts[0]}, expected a non-negative integer"
            )
        if not problems:
            continue
        problem = "a restriction with " + " and ".join(problems)
        recovered = _recover(node, values, known) if is_restriction(node) else None
        if recovered is None:
            damages.append(Damage(node.value, problem, f"cannot be recovered; {_RESTORE}"))
            continue
        key, n = recovered
        wanted = _restriction_quads(node, key, n)
        present = [
            q
            for prop in (OWL_ON_PROPERTY, OWL_ON_CLASS, OWL_MIN_QUALIFIED_CARDINALITY)
            for q in store.quads(node, prop, None, MEMORY)
        ]
        damages.append(
            Damage(
                node.value,
                problem,
                f"its IRI says it is ≥{n} {key[0].value}.{key[1].value}; "
                "`engram check --fix` writes that back",
                deletes=tuple(q for q in present if q not in wanted),
                inserts=tuple(q for q in wanted if q not in present),
            )
        )
    return damages


def _class_damage(
    classes: dict[NamedNode, dict[str, list[object]]], defined: set[NamedNode]
) -> list[Damage]:
    damages = []
    for cls, values in classes.items():
        problems = []
        signatures = values.get("signature", [])
        if not signatures and cls not in defined:
            problems.append("no engram:signature and no owl:equivalentClass definition")
        for text in signatures:
            try:
                Signature.from_json(str(getattr(text, "value", text)))
            except InvalidSceneError as error:
                problems.append(f"an unreadable engram:signature ({error})")
        for column, prop in (
            ("score", SCORE),
            ("created", CREATED),
            ("lastAccessed", LAST_ACCESSED),
        ):
            if not values.get(column):
                problems.append(f"no {prop.value}")
        if problems:
            damages.append(
                Damage(cls.value, "a learned class with " + " and ".join(problems), _RESTORE)
            )
    return damages


def _item_damage(store: Store, classes: dict[NamedNode, dict[str, list[object]]]) -> list[Damage]:
    items = _by_subject(store.select("memory_load_items", g=EPISODIC), "item")
    damages = []
    for item, values in items.items():
        if not any(t in classes for t in values.get("type", [])):
            damages.append(
                Damage(
                    item.value,
                    "an experienced scene whose class is not a learned class of the memory graph",
                    _RESTORE,
                )
            )
    return damages


def check_memory(store: Store) -> list[Damage]:
    """Everything in the memory and episodic graphs that would stop the scene memory loading."""
    classes = _by_subject(store.select("memory_load_classes", g=MEMORY), "class")
    defined = {row["class"] for row in store.select("memory_load_definitions", g=MEMORY)}
    return [
        *_restriction_damage(store, classes),
        *_class_damage(classes, defined),  # type: ignore[arg-type]
        *_item_damage(store, classes),
    ]


def fix_memory(store: Store, damages: list[Damage]) -> int:
    """Apply the repairs of the fixable ``damages`` in one transaction; return how many."""
    fixable = [d for d in damages if d.fixable]
    with store.transaction() as tx:
        for damage in fixable:
            tx.deletes.extend(damage.deletes)
            tx.inserts.extend(damage.inserts)
    return len(fixable)


def describe(damages: list[Damage]) -> str:
    """One paragraph naming every damaged node and its repair."""
    lines = [f"the memory graphs are damaged ({len(damages)} problem(s)):"]
    lines += [f"  - {damage}" for damage in damages]
    if any(d.fixable for d in damages):
        lines.append("run `engram check --fix` to repair what can be repaired safely")
    return "\n".join(lines)


def open_scene_memory(store: Store) -> SceneMemory:
    """The scene memory over ``store``; if it cannot load, :class:`DamagedMemoryError` naming
    the damaged nodes and their repairs instead of the loader's own exception."""
    try:
        return SceneMemory(store)
    except Exception as error:
        damages = check_memory(store)
        if not damages:
            raise
        raise DamagedMemoryError(describe(damages)) from error
