"""What the scene memory holds, read from its model without writing anything.

:class:`MemoryReads` answers the views, the explanations (:mod:`reasoners.explain`), the ARMOR
score queries and the question grammar: the live classes and experienced scenes, their scores
and scores' terms, their relatives, what a signature is recognised as, and the trash. Every read
holds the model's lock, so it sees the model between two operations, never during one.

>>> import datetime as dt
>>> from kg import Store
>>> from reasoners.memory import SceneMemory
>>> from kg.primitive import Primitive
>>> memory = SceneMemory(Store(), clock=lambda: dt.datetime(2025, 1, 1, tzinfo=dt.UTC))
>>> stored = memory.store_scene([Primitive("ball", "Sphere", centre=(.3, .3, .3), radius=.05),
...                              Primitive("table", "Plane", centre=(.3, .1, .1), axis=(0, 0, 1))])
>>> memory.reads.items_of(stored.stored_as) == [stored.scene_item]
True
>>> memory.reads.item_scores(stored.stored_as).level
'HIGH'
"""

import datetime as dt
import heapq
from operator import attrgetter

from pyoxigraph import NamedNode

from kg.clock import Clock
from reasoners import forgetting
from reasoners.clock import read_clock
from reasoners.errors import UnknownItemError
from reasoners.loading import LoadedModel
from reasoners.model import MemoryModel
from reasoners.policy import Policy
from reasoners.records import ClassRecord
from reasoners.results import ClassSummary, ItemScores, Match, Recognition, ScoreTerms, TrashEntry
from reasoners.score_view import ScoreView
from reasoners.signature import Signature

__all__ = [
    "MemoryReads",
    "best_recognition",
    "ordered_recognitions",
    "recognitions_in",
    "unknown_item",
]

_BY_IRI = attrgetter("iri.value")
_BY_COMPLEXITY_AND_STORES = attrgetter("signature.complexity", "store_count")
"""The order of recognitions (:func:`recognitions_in`): a memory of 100,000 classes recognises
thousands of them in every update."""


def recognitions_in(model: MemoryModel, signature: Signature) -> list[Recognition]:
    """The classes of ``model`` that ``signature`` belongs to: most complex (most confident)
    first, then most stored, then by IRI."""
    classes = model.graph.classes
    records = [classes[cls] for cls in model.graph.index.recognised(signature)]
    return ordered_recognitions(records, signature.complexity)


def ordered_recognitions(records: list[ClassRecord], complexity: int) -> list[Recognition]:
    """:func:`recognitions_in` of a scene of ``complexity`` that belongs to the classes of
    ``records`` (which this sorts in place)."""
    # two stable sorts on keys read in C (last key first): most complex, then most stored
    # (reverse keeps the order of equals), then by IRI
    records.sort(key=_BY_IRI)
    records.sort(key=_BY_COMPLEXITY_AND_STORES, reverse=True)
    d = complexity
    return [Recognition(r.iri, r.signature.complexity / d, r.signature.complexity) for r in records]


def best_recognition(records: list[ClassRecord], complexity: int) -> Recognition | None:
    """The first of :func:`ordered_recognitions` (None for no records), without ordering the
    others: a learn needs the rest only for its result, which is built while the store writes."""
    if not records:
        return None
    key = _BY_COMPLEXITY_AND_STORES
    top = key(max(records, key=key))
    best = min((r for r in records if key(r) == top), key=_BY_IRI)
    return Recognition(best.iri, best.signature.complexity / complexity, best.signature.complexity)


def unknown_item(model: MemoryModel, iri: NamedNode) -> UnknownItemError:
    """The error for an IRI that is not a live class or experienced scene of ``model``."""
    if iri in model.trash.classes or iri in model.trash.items:
        return UnknownItemError(f"iri: {iri.value} is in the trash; restore it first")
    return UnknownItemError(
        f"iri: got {iri.value!r}, expected a learned scene class or an experienced scene"
    )


class MemoryReads:
    """Reads of ``loaded``'s model; scores as ``view`` gives them under ``policy``, at the time
    ``clock`` gives."""

    def __init__(self, loaded: LoadedModel, view: ScoreView, policy: Policy, clock: Clock) -> None:
        self._loaded = loaded
        self._view = view
        self._policy = policy
        self._clock = clock

    def _live(self, iri: NamedNode) -> ClassRecord:
        """The record of a live class (the caller holds the lock); UnknownItemError otherwise."""
        m = self._loaded.model
        record = m.graph.classes.get(iri)
        if record is None:
            raise unknown_item(m, iri)
        return record

    def now(self) -> dt.datetime:
        """The memory clock's current time (to the millisecond)."""
        return read_clock(self._clock)

    def item_scores(self, iri: NamedNode) -> ItemScores:
        """The raw terms, normalised score and level of a class or experienced scene, now.

        Raises :class:`~reasoners.errors.UnknownItemError` for an IRI that is not live."""
        with self._loaded.lock:
            m, p = self._loaded.model, self._policy
            if iri in m.graph.classes:
                return self._view.class_scores(m.graph.classes[iri])
            if iri not in m.items.records:
                raise unknown_item(m, iri)
            now, record = self.now(), m.items.records[iri]
            raw = forgetting.item_raw(m, p, record, now)
            top = max(
                (forgetting.item_raw(m, p, r, now) for r in m.items.records.values()), default=0.0
            )
            return self._view.scores(record, raw, top)

    def classes(self) -> list[ClassSummary]:
        """Every live learned class with its signature, direct edges and scores, simplest first."""
        with self._loaded.lock:
            m = self._loaded.model
            zetas, top = m.scores.zetas(), m.scores.max_score
            return [
                ClassSummary(
                    iri=record.iri,
                    signature=record.signature,
                    parents=tuple(sorted(m.graph.parents[record.iri], key=str)),
                    children=tuple(sorted(m.graph.children[record.iri], key=str)),
                    items=len(m.items.items_of.get(record.iri, ())),
                    scores=self._view.class_scores(record, (zetas[record.iri], top)),
                )
                for record in sorted(
                    m.graph.classes.values(), key=lambda r: (r.signature.complexity, r.iri.value)
                )
            ]

    def state(self, best: int = 10) -> tuple[int, int, list[tuple[NamedNode, float]]]:
        """(learned classes, experienced scenes, the ``best`` classes by live raw score ζ as
        (class, ζ), best first, ties by IRI)."""
        with self._loaded.lock:
            m = self._loaded.model
            zetas = m.scores.zetas()
            top = heapq.nsmallest(best, zetas.items(), key=lambda kv: (-kv[1], kv[0].value))
            return len(m.graph.classes), len(m.items.records), top

    def items(self) -> list[NamedNode]:
        """Every live experienced scene, oldest first."""
        with self._loaded.lock:
            items = self._loaded.model.items.records
            return sorted(items, key=lambda i: items[i].created)

    def trash(self) -> list[NamedNode]:
        """Everything in the trash that :meth:`~reasoners.memory.SceneMemory.restore` accepts."""
        with self._loaded.lock:
            m = self._loaded.model
            return [*m.trash.classes, *m.trash.items]

    def signature(self, iri: NamedNode) -> Signature:
        """The signature of a live class. Raises UnknownItemError otherwise."""
        with self._loaded.lock:
            return self._live(iri).signature

    def relatives(self, iri: NamedNode) -> tuple[tuple[NamedNode, ...], tuple[NamedNode, ...]]:
        """(direct parents, direct children) of a live class, each sorted by IRI.

        Raises :class:`~reasoners.errors.UnknownItemError` for an IRI that is not a live class."""
        with self._loaded.lock:
            m = self._loaded.model
            self._live(iri)
            return (
                tuple(sorted(m.graph.parents[iri], key=str)),
                tuple(sorted(m.graph.children[iri], key=str)),
            )

    def score_terms(self, iri: NamedNode) -> ScoreTerms:
        """The terms ζ of a live class adds up now (raises UnknownItemError otherwise)."""
        with self._loaded.lock:
            m, record = self._loaded.model, self._live(iri)
            children = sorted(m.graph.children[iri], key=str)
            return ScoreTerms(
                complexity=record.signature.complexity,
                max_complexity=m.scores.max_complexity,
                store_count=record.store_count,
                max_store=m.scores.max_store,
                retrieve_count=record.retrieve_count,
                max_retrieve=m.scores.max_retrieve,
                children_zeta=tuple(m.scores.zeta(m.graph.classes[c]) for c in children),
                weights=m.scores.weights,
                zeta=m.scores.zeta(record),
                max_zeta=m.scores.max_score,
            )

    def recognitions(self, signature: Signature) -> list[Recognition]:
        """The live classes a signature belongs to, most confident first."""
        with self._loaded.lock:
            return recognitions_in(self._loaded.model, signature)

    def closest(self, signature: Signature, limit: int = 5) -> list[Match]:
        """The ``limit`` live classes most similar to a signature, best first."""
        with self._loaded.lock:
            similar = self._loaded.model.graph.index.most_similar(signature, limit)
            return [Match(c, s) for c, s in similar]

    def trashed(self, iri: NamedNode) -> TrashEntry | None:
        """What the trash holds under ``iri``, or None."""
        with self._loaded.lock:
            m = self._loaded.model
            if iri in m.trash.classes:
                c = m.trash.classes[iri]
                return TrashEntry(iri, "class", c.forgotten_at, signature=c.signature)
            if iri in m.trash.items:
                i = m.trash.items[iri]
                return TrashEntry(iri, "item", i.forgotten_at, cls=i.cls)
            return None

    def maxima(self) -> dict[str, int]:
        """How many live classes and experienced scenes there are, and the largest class
        complexity, experienced-scene complexity, store and retrieve counts that the scores
        are normalised by."""
        with self._loaded.lock:
            m = self._loaded.model
            return {
                "classes": len(m.graph.classes),
                "items": len(m.items.records),
                "complexity": m.scores.max_complexity,
                "item_complexity": m.items.max_complexity,
                "store": m.scores.max_store,
                "retrieve": m.scores.max_retrieve,
            }

    def best(self, count: int = 3) -> list[tuple[NamedNode, float]]:
        """The ``count`` live classes of largest live raw score ζ as (class, ζ), best first,
        ties by IRI (as :meth:`state`, without a pass over every class in Python)."""
        with self._loaded.lock:
            return self._loaded.model.scores.top(count)

    def learned_at(self, cls: NamedNode) -> dt.datetime:
        """When a live class was learned (raises UnknownItemError otherwise)."""
        with self._loaded.lock:
            return self._live(cls).created

    def seen(self, cls: NamedNode) -> list[tuple[NamedNode, dt.datetime]]:
        """The live experienced scenes stored as ``cls`` and when each was seen, oldest first
        (ties by IRI)."""
        with self._loaded.lock:
            m = self._loaded.model
            return sorted(
                ((i, m.items.records[i].created) for i in m.items.items_of.get(cls, ())),
                key=lambda pair: (pair[1], pair[0].value),
            )

    def items_of(self, cls: NamedNode) -> list[NamedNode]:
        """The live experienced scenes stored as ``cls``, sorted by IRI."""
        with self._loaded.lock:
            return sorted(self._loaded.model.items.items_of.get(cls, ()), key=str)

    def live_class(self, signature: Signature) -> NamedNode | None:
        """The live class learned with exactly this signature, or None."""
        with self._loaded.lock:
            return self._loaded.model.graph.index.with_signature(signature)
