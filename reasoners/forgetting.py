"""Forgetting (DESIGN, "Forget"): what a sleep pass decides, and the move to the trash.

:func:`plan` reads the model and writes nothing: every class's and experienced scene's level
from its live normalised score, its consecutive WEAK count, and what is forgotten now. A class
or experienced scene is forgotten when it has been WEAK for ``weakPassesToForget`` consecutive
passes, is older than ``forgetGracePeriodSeconds`` and is not pinned; a class with a pinned
experienced scene is kept, and a pinned class keeps its experienced scenes.
:func:`move_to_trash` then moves the forgotten classes (their experienced scenes with them)
and scenes into the ``trash`` graph, in the sleep pass's transaction
(:meth:`reasoners.memory.SceneMemory.sleep`), each with the level and consecutive WEAK count of
the pass that forgot it (a class forgotten at its k-th WEAK pass holds k).
"""

import dataclasses
import datetime as dt
from collections.abc import Sequence

from pyoxigraph import Literal, NamedNode

from kg.transaction import QuadReader, Transaction
from ontologies.vocab import (
    EPISODIC,
    FORGOTTEN_AT,
    FORGOTTEN_SIGNATURE,
    HAS_PRIMITIVE,
    LEVEL,
    OWL_EQUIVALENT_CLASS,
    RDFS_SUBCLASSOF,
    TRASH,
    TRASH_CLASS,
)
from reasoners import persist
from reasoners.model import MemoryModel
from reasoners.policy import Policy
from reasoners.records import ItemRecord, TrashedClass, TrashedItem
from reasoners.scoring import WEAK, episodic_score, level_of, log_ratio

__all__ = ["SleepPlan", "item_raw", "leaving_items", "move_to_trash", "plan"]


@dataclasses.dataclass(frozen=True)
class SleepPlan:
    """A sleep pass's decisions, taken on the model as it was before the pass."""

    zetas: dict[NamedNode, float]
    """Every live class's raw ζ."""
    class_levels: dict[NamedNode, str]
    weak_counts: dict[NamedNode, int]
    """Each class's consecutive WEAK passes, this one included."""
    item_levels: dict[NamedNode, str]
    item_weak: dict[NamedNode, int]
    doomed_classes: list[NamedNode]
    doomed_items: list[NamedNode]
    """Experienced scenes forgotten alone (those of a doomed class go with it)."""


def item_raw(
    model: MemoryModel,
    policy: Policy,
    record: ItemRecord,
    now: dt.datetime,
    normalised: dict[NamedNode, float] | None = None,
) -> float:
    """An experienced scene's raw episodic score; ``normalised`` holds every class's normalised
    score when the caller has them already."""
    cls = model.graph.classes[record.cls]
    max_d = model.items.max_complexity
    return episodic_score(
        policy,
        complexity_ratio=record.complexity / max_d if max_d else 0.0,
        class_normalised=model.scores.normalised(cls)
        if normalised is None
        else normalised[cls.iri],
        store_ratio=log_ratio(cls.store_count, model.scores.max_store),
        retrieve_ratio=log_ratio(cls.retrieve_count, model.scores.max_retrieve),
        age_s=(now - record.last_accessed).total_seconds(),
    )


def plan(model: MemoryModel, policy: Policy, now: dt.datetime) -> SleepPlan:
    """Levels, WEAK counts and what is forgotten, for a sleep pass at ``now``."""
    high, weak = policy.highLevelThreshold, policy.weakLevelThreshold
    zetas = model.scores.zetas()
    top = model.scores.max_score
    normalised = {cls: zeta / top if top > 0 else 0.0 for cls, zeta in zetas.items()}
    class_levels = {cls: level_of(n, high=high, weak=weak) for cls, n in normalised.items()}
    weak_counts = {
        cls: record.weak_count + 1 if class_levels[cls] == WEAK else 0
        for cls, record in model.graph.classes.items()
    }
    raw = {
        iri: item_raw(model, policy, r, now, normalised) for iri, r in model.items.records.items()
    }
    top = max(raw.values(), default=0.0)
    item_levels = {
        iri: level_of(value / top if top > 0 else 0.0, high=high, weak=weak)
        for iri, value in raw.items()
    }
    item_weak = {
        iri: model.items.records[iri].weak_count + 1 if level == WEAK else 0
        for iri, level in item_levels.items()
    }
    grace = dt.timedelta(seconds=policy.forgetGracePeriodSeconds)
    k = policy.weakPassesToForget
    protected = {r.cls for r in model.items.records.values() if r.pinned}
    doomed_classes = [
        cls
        for cls, record in model.graph.classes.items()
        if weak_counts[cls] >= k
        and now - record.created >= grace
        and not record.pinned
        and cls not in protected
    ]
    doomed = set(doomed_classes)
    doomed_items = [
        iri
        for iri, record in model.items.records.items()
        if record.cls not in doomed
        and item_weak[iri] >= k
        and now - record.created >= grace
        and not record.pinned
        and not model.graph.classes[record.cls].pinned  # a pinned class keeps its scenes
    ]
    return SleepPlan(
        zetas, class_levels, weak_counts, item_levels, item_weak, doomed_classes, doomed_items
    )


def leaving_items(
    model: MemoryModel, classes: Sequence[NamedNode], items: Sequence[NamedNode]
) -> list[NamedNode]:
    """The experienced scenes that :func:`move_to_trash` moves with ``classes`` and ``items``,
    each once."""
    doomed = set(classes)
    own = [i for c in classes for i in model.items.items_of.get(c, ())]
    if doomed:
        own += [i for i, r in model.items.records.items() if r.cls in doomed]
    return [i for i in dict.fromkeys([*own, *items]) if i in model.items.records]


def move_to_trash(
    tx: Transaction,
    model: MemoryModel,
    reader: QuadReader,
    classes: Sequence[NamedNode],
    items: Sequence[NamedNode],
    now: dt.datetime,
) -> list[NamedNode]:
    """Move ``classes`` (with their experienced scenes) and ``items`` to the trash, in the model
    and in ``tx``, each with the level its record holds; return the experienced scenes moved,
    each once."""
    moved: list[NamedNode] = []
    stamp = persist.time_literal(now)
    added: set[tuple[NamedNode, NamedNode]] = set()
    for cls in classes:
        record = model.graph.classes[cls]
        own = persist.delete_class(tx, reader, cls)
        for quad in own:
            if quad.predicate not in (RDFS_SUBCLASSOF, OWL_EQUIVALENT_CLASS) and (
                quad.predicate not in persist.VIEW_PREDICATES
            ):
                persist.insert_quad(tx, quad, TRASH)
        tx.insert(cls, RDFS_SUBCLASSOF, TRASH_CLASS, TRASH)
        tx.insert(cls, FORGOTTEN_AT, stamp, TRASH)
        if record.level is not None:
            tx.insert(cls, LEVEL, Literal(record.level), TRASH)
        tx.insert(cls, FORGOTTEN_SIGNATURE, Literal(record.signature.to_json()), TRASH)
        added |= model.graph.remove_class(cls)
        added = {(c, p) for c, p in added if c in model.graph.classes and p in model.graph.classes}
        for key, n in record.signature.items():
            if (
                not model.graph.restrictions[(key, n)]
                and (key, n) in model.graph.stored_restrictions
            ):
                persist.delete_restriction(tx, key, n)
                model.graph.stored_restrictions.discard((key, n))
        model.trash.classes[cls] = TrashedClass(cls, record.signature, now)
        own_items = model.items.items_of.get(cls, ()) or _items_of(model, cls)
        items = [*items, *sorted(own_items, key=str)]
    persist.write_edges(tx, added)
    for item in items:
        if item not in model.items.records:
            continue
        removed = model.items.remove(item)
        persist.move(tx, reader, [item], EPISODIC, TRASH, follow=HAS_PRIMITIVE)
        tx.insert(item, FORGOTTEN_AT, stamp, TRASH)
        if removed.level is not None:
            tx.insert(item, LEVEL, Literal(removed.level), TRASH)
        model.trash.items[item] = TrashedItem(item, removed.cls, now)
        moved.append(item)
    return moved


def _items_of(model: MemoryModel, cls: NamedNode) -> list[NamedNode]:
    return [i for i, r in model.items.records.items() if r.cls == cls]
