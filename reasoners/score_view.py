"""The score view: what the store holds of the classes' scores, and a class's scores from it.

Semantic scores are derived from each class's raw terms (complexity, store and retrieve
counts), its children and the global maxima (:mod:`reasoners.model`). An update re-derives the
touched class and its ancestors in memory and writes the touched class's ``engram:rawScore``
(:meth:`ScoreView.rescore`); the view (the Z terms of the classes whose Z changed and the four
values on the memory state, :func:`reasoners.persist.write_view`), from which a SPARQL reader
derives every class's live normalised score and level, is written by :meth:`ScoreView.write`
into a transaction chosen by :class:`reasoners.transactions.Transactions` (before the next read,
or in each update on a shared server). A store written by an older Engram, or damaged, gets its
view back when the memory opens (:meth:`ScoreView.stale`, :meth:`ScoreView.repair`).
"""

import logging
from dataclasses import dataclass

from pyoxigraph import Literal, NamedNode

from kg.transaction import Transaction
from ontologies.vocab import (
    EPISODIC,
    LEGACY_LEVEL,
    LEGACY_SCORE,
    MEMORY,
    RDFS_LABEL,
    SCORE,
    SCORE_TERM_PROPERTIES,
    SKOS_NOTATION,
)
from reasoners import migration, persist
from reasoners.loading import LoadedModel
from reasoners.policy import Policy
from reasoners.records import ClassRecord, ItemRecord
from reasoners.results import ItemScores
from reasoners.scoring import level_of

__all__ = ["Repair", "ScoreView"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Repair:
    """What a store lacks of the view or still holds of an older data model."""

    legacy: bool
    """Annotations the view replaced (a score and level per class or scene) are present."""
    migrate: bool
    """The store predates the data model that stores only what cannot be derived."""
    factors_stale: bool
    """The scoring factors on the memory state do not match the model's."""
    unlabelled: tuple[ClassRecord, ...]
    """Classes learned before labels spelt out the definition."""


class ScoreView:
    """The score view of ``loaded``'s model, under ``policy`` (named ``policy_iri``)."""

    def __init__(self, loaded: LoadedModel, policy: Policy, policy_iri: NamedNode) -> None:
        self.loaded = loaded
        self.policy = policy
        self.policy_iri = policy_iri

    def write(self, tx: Transaction) -> None:
        """Write the view's pending changes into ``tx``."""
        persist.write_view(tx, self.loaded.model, self.policy_iri)

    def stale(self) -> Repair | None:
        """What the store lacks of the view (its terms missing or stale, written by an older
        Engram or by hand), or None when it is whole."""
        m, store = self.loaded.model, self.loaded.store
        legacy = any(
            True
            for prop, graph in (
                (LEGACY_SCORE, MEMORY),
                (LEGACY_LEVEL, MEMORY),
                (LEGACY_LEVEL, EPISODIC),
            )
            for _ in store.quads(None, prop, None, graph)
        )
        migrate = migration.needed(store, m)
        factors_stale = bool(m.graph.classes) and m.scores.written_factors != (
            *m.scores.coefficients(),
            m.scores.max_score,
        )
        unlabelled: list[ClassRecord] = []
        if self.loaded.source != "index file":  # a file is saved only by a repaired memory
            named = {q.subject for q in store.quads(None, SKOS_NOTATION, None, MEMORY)}
            unlabelled = [record for cls, record in m.graph.classes.items() if cls not in named]
        if not (legacy or migrate or m.scores.unwritten or factors_stale or unlabelled):
            return None
        return Repair(legacy, migrate, factors_stale, tuple(unlabelled))

    def repair(self, tx: Transaction, repair: Repair) -> None:
        """Write into ``tx`` what :meth:`stale` found missing, and drop the annotations the view
        replaced; migrate a store written before the data model stored only what cannot be
        derived (:mod:`reasoners.migration`). ``tx`` writes the whole view too."""
        m = self.loaded.model
        for record in m.graph.classes.values():  # terms missing, partial or damaged: rewritten
            if record.written_z is None:
                for prop in SCORE_TERM_PROPERTIES:
                    tx.delete_matching(record.iri, prop, None, graph=MEMORY)
        if repair.migrate:
            migration.migrate(tx, self.loaded.store, m)
        for record in repair.unlabelled:  # learned before labels spelt out the definition
            tx.delete_matching(record.iri, RDFS_LABEL, None, graph=MEMORY)
            persist.write_label(tx, record)
        if repair.legacy:
            tx.delete_matching(None, LEGACY_SCORE, None, graph=MEMORY)
            tx.delete_matching(None, LEGACY_LEVEL, None, graph=MEMORY)
            tx.delete_matching(None, LEGACY_LEVEL, None, graph=EPISODIC)
        if repair.factors_stale:
            m.scores.written_factors = None  # rewritten whole

    def rescore(
        self,
        tx: Transaction,
        classes: set[NamedNode],
        fresh: set[NamedNode] | frozenset[NamedNode] = frozenset(),
    ) -> None:
        """Synaptic consolidation. The model re-derives the score terms of the classes whose
        counts or children changed and of their ancestors, bottom-up; the maxima apply on read.
        The ``engram:score`` annotation of ``classes`` (the ones this update touched, whose own
        terms it rewrites anyway) is brought up to date; ``fresh`` classes are written whole
        later. Nothing else is rewritten: every other class's stored ζ is refreshed by the next
        sleep pass. Only the classes at least as complex as these are re-derived here (that is
        all their ζ depend on); their ancestors may be left to :meth:`ScoreTable.refresh`."""
        m = self.loaded.model
        m.scores.refresh(
            down_to=min(
                (m.graph.classes[c].signature.complexity for c in classes | fresh), default=0
            )
        )
        for cls in classes - fresh:
            self._write_score(tx, m.graph.classes[cls])
        for cls in fresh:
            m.graph.classes[cls].score = m.scores.zeta(m.graph.classes[cls])
            m.scores.scored.pop(cls, None)

    def _write_score(self, tx: Transaction, record: ClassRecord) -> None:
        m = self.loaded.model
        new = m.scores.zeta(record)
        m.scores.scored.pop(record.iri, None)
        if new != record.score:
            persist.set_value(tx, record.iri, SCORE, Literal(record.score), Literal(new), MEMORY)
            record.score = new

    def class_scores(
        self, record: ClassRecord, live: tuple[float, float] | None = None
    ) -> ItemScores:
        """A class's scores; ``live`` is its (ζ, largest ζ) when the caller has them already."""
        m = self.loaded.model
        zeta, top = live if live is not None else (m.scores.zeta(record), m.scores.max_score)
        return self.scores(record, zeta, top)

    def scores(self, record: ClassRecord | ItemRecord, raw: float, top: float) -> ItemScores:
        """The scores of a class or experienced scene whose raw score is ``raw`` when the
        largest of its kind is ``top``; a scene's counts are its class's."""
        p = self.policy
        normalised = raw / top if top > 0 else 0.0
        if isinstance(record, ClassRecord):
            kind, counts, complexity, cls = "class", record, record.signature.complexity, None
        else:
            counts, cls = self.loaded.model.graph.classes[record.cls], record.cls
            kind, complexity = "item", record.complexity
        return ItemScores(
            iri=record.iri,
            kind=kind,
            complexity=complexity,
            store_count=counts.store_count,
            retrieve_count=counts.retrieve_count,
            raw_score=raw,
            normalised=normalised,
            level=level_of(normalised, high=p.highLevelThreshold, weak=p.weakLevelThreshold),
            stored_level=record.level,
            consecutive_weak=record.weak_count,
            pinned=record.pinned,
            created=record.created,
            last_accessed=record.last_accessed,
            cls=cls,
        )
