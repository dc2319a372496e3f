"""Keeping a follower's scene memory in step with the writer, one change at a time.

A follower (:mod:`kg.follow`) learns which subjects each of the writer's transactions touched.
:func:`apply_change` reloads only those into the follower's in-memory index: a class whose
counters or times moved, a class just learned (linked into the graph from its signature, as the
writer linked it), an experienced scene just stored, the memory's state. Anything else (a class
or scene that left the memory graph, a change too large to list) rebuilds the whole index, as
does a change that touched "everything".

>>> apply_change.__name__
'apply_change'
"""

import logging
from collections import defaultdict
from collections.abc import Iterable

from pyoxigraph import NamedNode

from kg import Store
from ontologies.vocab import (
    CLASS_SIGNATURE,
    COMPLEXITY,
    CONSECUTIVE_WEAK_COUNT,
    CREATED,
    ENGRAM_NS,
    EPISODIC,
    EXPERIENCED_SCENE,
    LAST_ACCESSED,
    LAST_SLEEP_AT,
    MEMORY,
    MEMORY_STATE_INDIVIDUAL,
    PINNED,
    RDF_TYPE,
    RDFS_SUBCLASSOF,
    RETRIEVE_COUNT,
    SCENE,
    SCORE,
    SLEEP_LEVELS,
    SLEEP_PASS_COUNT,
    STORE_COUNT,
    UPDATES_SINCE_SLEEP,
)
from reasoners import persist
from reasoners.memory import SceneMemory
from reasoners.model import MemoryModel
from reasoners.persist import Term
from reasoners.records import ClassRecord, ItemRecord
from reasoners.signature import Signature

__all__ = ["apply_change"]

log = logging.getLogger(__name__)


class _Rebuild(Exception):
    """The change cannot be applied piecewise."""


def apply_change(memory: SceneMemory, touched: Iterable[NamedNode] | None) -> bool:
    """Bring ``memory``'s index up to date with a change that touched ``touched`` (None:
    everything). Returns True if it was applied piecewise, False if the index was rebuilt."""
    if touched is not None:
        subjects = set(touched)
        try:
            memory.loaded.update(lambda model: _apply(memory.store, model, subjects))
            return True
        except _Rebuild as reason:
            log.info("rebuilding the scene memory index: %s", reason)
    memory.loaded.reload()
    return False


def _triples(
    store: Store, subjects: list[NamedNode], graph: NamedNode
) -> dict[NamedNode, dict[NamedNode, list[Term]]]:
    """The values of each of ``subjects`` in ``graph``, per property, in one query that looks
    each subject up (the loaders' queries read every class of the memory)."""
    out: dict[NamedNode, dict[NamedNode, list[Term]]] = {}
    for row in store.select_each("follow_subjects", "s", subjects, g=graph):
        values = out.setdefault(row["s"], defaultdict(list))  # type: ignore[arg-type]
        if (term := row["o"]) not in (seen := values[row["p"]]):  # type: ignore[index]
            seen.append(term)
    return out


def _apply(store: Store, m: MemoryModel, touched: set[NamedNode]) -> None:
    classes, items, state = [], [], False
    for subject in touched:
        if subject == MEMORY_STATE_INDIVIDUAL:
            state = True
        elif not subject.value.startswith(ENGRAM_NS):
            continue  # restriction and definition nodes, episodes, references
        elif (name := subject.value[len(ENGRAM_NS) :]).startswith("Scene-"):
            classes.append(subject)
        elif name.startswith("experience-") and name.count("-") == 1:
            items.append(subject)
        # experience-N-k: a primitive of a stored scene, read with the scene if at all
        if subject in m.trash.classes or subject in m.trash.items:
            raise _Rebuild(f"{subject.value} came back from the trash")
    rows = _triples(store, classes, MEMORY)
    for cls in classes:
        if SCENE not in rows.get(cls, {}).get(RDFS_SUBCLASSOF, ()):
            raise _Rebuild(f"{cls.value} left the memory graph")
    # existing classes first, then new ones simplest first (a parent before its children)
    fresh = sorted((c for c in rows if c not in m.graph.classes), key=persist._number)
    for cls in [c for c in rows if c in m.graph.classes]:
        values, record = rows[cls], m.graph.classes[cls]
        m.scores.set_counts(
            record,
            store=persist._int(values, STORE_COUNT),
            retrieve=persist._int(values, RETRIEVE_COUNT),
        )
        _annotations(record, values)
    for cls in fresh:
        values = rows[cls]
        if CLASS_SIGNATURE not in values:
            raise _Rebuild(f"{cls.value} has no engram:signature")
        record = ClassRecord(
            iri=cls,
            signature=Signature.from_json(persist._one(values, CLASS_SIGNATURE).value),
            store_count=persist._int(values, STORE_COUNT),
            retrieve_count=persist._int(values, RETRIEVE_COUNT),
            score=float(persist._one(values, SCORE).value),
            created=persist.parse_time(persist._one(values, CREATED)),
            last_accessed=persist.parse_time(persist._one(values, LAST_ACCESSED)),
        )
        _annotations(record, values)
        m.graph.add_class(record)
        m.state.next_class = max(m.state.next_class, persist._number(cls) + 1)
    found = _triples(store, items, EPISODIC)
    for item in items:
        if EXPERIENCED_SCENE not in found.get(item, {}).get(RDF_TYPE, ()):
            raise _Rebuild(f"{item.value} left the episodic graph")
        values = found[item]
        owner = next((t for t in values[RDF_TYPE] if t in m.graph.classes), None)
        if not isinstance(owner, NamedNode):
            raise _Rebuild(f"{item.value} belongs to no live class")
        scene = ItemRecord(
            iri=item,
            cls=owner,
            complexity=persist._int(values, COMPLEXITY),
            created=persist.parse_time(persist._one(values, CREATED)),
            last_accessed=persist.parse_time(persist._one(values, LAST_ACCESSED)),
            weak_count=persist._int(values, CONSECUTIVE_WEAK_COUNT),
            pinned=persist._bool(values, PINNED),
            level=m.items.records[item].level if item in m.items.records else None,
        )
        if item in m.items.records:
            m.items.remove(item)
        m.items.add(scene)
        m.state.next_item = max(m.state.next_item, persist._number(item) + 1)
    if state:
        quads = store.quads(MEMORY_STATE_INDIVIDUAL, None, None, MEMORY)
        now: dict[NamedNode, list[Term]] = {}
        for quad in quads:
            now.setdefault(quad.predicate, []).append(quad.object)  # type: ignore[arg-type]
        m.state.has_state = bool(now)
        if LAST_SLEEP_AT in now:
            m.state.last_sleep_at = persist.parse_time(now[LAST_SLEEP_AT][0])
        m.state.updates_since_sleep = persist._int(now, UPDATES_SINCE_SLEEP)
        m.state.sleep_passes = persist._int(now, SLEEP_PASS_COUNT)
        if SLEEP_LEVELS in now:  # a sleep pass: the levels it gave
            levels = persist.read_levels(now[SLEEP_LEVELS])
            for cls, record in m.graph.classes.items():
                record.level = levels.get(cls)
            for item, scene_record in m.items.records.items():
                scene_record.level = levels.get(item)
    m.scores.refresh()


def _annotations(record: ClassRecord, values: dict[NamedNode, list[Term]]) -> None:
    record.score = float(persist._one(values, SCORE).value)
    record.last_accessed = persist.parse_time(persist._one(values, LAST_ACCESSED))
    record.weak_count = persist._int(values, CONSECUTIVE_WEAK_COUNT)
    record.pinned = persist._bool(values, PINNED)
