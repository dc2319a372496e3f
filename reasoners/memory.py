"""The scene memory: encode, recognise, learn, structure, consolidate, forget and retrieve.

Each of :meth:`SceneMemory.store_scene`, :meth:`~SceneMemory.retrieve`,
:meth:`~SceneMemory.sleep`, :meth:`~SceneMemory.pin` and :meth:`~SceneMemory.restore` is one
``store.transaction()``: all of its writes are visible, or none. Recognition uses an in-memory
index (:mod:`reasoners.index`) rebuilt from the store's triples when the memory opens, and again
if a transaction fails, so the store stays the source of truth. Methods may be called from
several threads; they are serialised.

Semantic scores are derived from each class's raw terms (complexity, store and retrieve
counts), its children and the global maxima (:mod:`reasoners.model`): an update re-derives the
touched class and its ancestors in memory and writes only what it changed in the store (the
touched class's counters, time and ``engram:rawScore``, the new class and its edges, the new
experienced scene). The score view (the Z terms of the classes whose Z changed and the four
values on the memory state, :func:`reasoners.persist.write_view`), from which a SPARQL reader
derives every class's live normalised score and level, is written by :meth:`~SceneMemory.
settle_view` before the store is next read, once for all the updates since the last read; on a
shared fleet server, which other robots read directly, in each update's transaction. A sleep
pass writes only what the view cannot give: the consecutive WEAK counts that changed, what it
forgot, the level it gave each item (one literal, ``engram:sleepLevels``, the next pass's
reference) and its level changes in the history (one literal); not a class's level or ζ.

>>> import datetime as dt
>>> from kg import Store
>>> from kg.primitive import Primitive
>>> memory = SceneMemory(Store(), clock=lambda: dt.datetime(2025, 1, 1, tzinfo=dt.UTC))
>>> scene = [Primitive("ball", "Sphere", centre=(.3, .3, .3), radius=.05),
...          Primitive("table", "Plane", centre=(.3, .1, .1), axis=(0, 0, 1))]
>>> first = memory.store_scene(scene)
>>> first.learned, first.stored_as.value.rsplit("#")[-1], first.signature.complexity
(True, 'Scene-1', 4)
>>> memory.store_scene(scene).learned
False
>>> memory.retrieve([("Sphere", "isAboveOf", "Plane")]).recalled == first.stored_as
True
"""

import datetime as dt
import heapq
import logging
import threading
import time
import weakref
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from operator import attrgetter

from pyoxigraph import Literal, NamedNode

from kg.ontology import ensure_ontology
from kg.primitive import Primitive
from kg.store import Store
from kg.transaction import Transaction
from ontologies.vocab import (
    COMPLEXITY,
    CONSECUTIVE_WEAK_COUNT,
    CREATED,
    DEFAULT_POLICY,
    EPISODIC,
    FORGOTTEN_AT,
    HAS_PRIMITIVE,
    LAST_ACCESSED,
    LEGACY_LEVEL,
    LEGACY_SCORE,
    LEVEL,
    MEMORY,
    MEMORY_STATE_INDIVIDUAL,
    PINNED,
    RDFS_LABEL,
    RETRIEVE_COUNT,
    SCORE,
    SCORE_TERM_PROPERTIES,
    SKOS_NOTATION,
    STORE_COUNT,
    TRASH,
    UPDATES_SINCE_SLEEP,
)
from reasoners import forgetting, history, index_file, migration, persist
from reasoners.batch import PendingWrites, QuadReader
from reasoners.clock import SettableClock
from reasoners.collector import collector_paused
from reasoners.encode import Encoder, Relation
from reasoners.errors import (
    InvalidSceneError,
    MemoryLoadingError,
    NotInTrashError,
    RestoreConflictError,
    UnknownItemError,
)
from reasoners.model import ClassRecord, ItemRecord, MemoryModel
from reasoners.policy import Policy, load_policy
from reasoners.results import (
    ClassSummary,
    ItemScores,
    Match,
    Recognition,
    RetrievalResult,
    ScoreTerms,
    SleepReport,
    StoreResult,
    TrashEntry,
)
from reasoners.scoring import WEAK, level_of
from reasoners.signature import Signature

__all__ = ["LOADING_WAIT_S", "Clock", "Cue", "SceneMemory"]

log = logging.getLogger(__name__)

Clock = Callable[[], dt.datetime]
Cue = Signature | Sequence[Primitive] | Sequence[tuple[str, str, str]]
"""A partial scene: primitives, relation triples between object types such as
``("Sphere", "isAboveOf", "Plane")``, or a signature."""


LOADING_WAIT_S = 1.0
"""How long a call made while the memory opens in the background waits for it before answering
:class:`MemoryLoadingError`."""


_BY_IRI = attrgetter("iri.value")
_BY_COMPLEXITY_AND_STORES = attrgetter("signature.complexity", "store_count")
"""The order of recognitions (:meth:`SceneMemory._recognitions`): a memory of 100,000 classes
recognises thousands of them in every update."""


def _utc_now() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


class SceneMemory:
    """A robot's scene memory kept in ``store`` (the T-Box is loaded if missing).

    ``clock`` returns the current time as a timezone-aware datetime; inject one to simulate
    time. ``policy`` names the ``engram:MemoryPolicy`` individual whose thresholds and weights
    apply. Raises :class:`~reasoners.errors.PolicyError` if the policy is incomplete.
    """

    def __init__(
        self,
        store: Store,
        *,
        clock: Clock = _utc_now,
        policy: NamedNode = DEFAULT_POLICY,
        background: bool = False,
    ) -> None:
        ensure_ontology(store)
        self.store = store
        self._clock = clock
        self._lock = threading.RLock()
        self._batch: PendingWrites | None = None
        self._reader: QuadReader = store
        """The store as the running operation sees it (its own pending writes included)."""
        self.policy: Policy = load_policy(store, policy)
        self.encoder = Encoder.from_store(store, self.policy)
        self._policy_iri = policy
        self.view_in_each_update = store.remote is not None
        """Write the score view in every update's transaction instead of before the next read:
        the default on a shared server, which other robots read directly, past this process's
        read barrier (set before the first update)."""
        self._counters = threading.Lock()
        self._begun = 0
        """Updates that left the view to be written, counted just before they commit."""
        self._viewed = 0
        """How many of those the written view includes."""
        self._wanted = 0
        """The most a reader is waiting for: a writer writes the view before it lets go."""
        self._rebuilding = False
        store.add_read_barrier(_settle_view_of(weakref.ref(self)))
        self._loaded: MemoryModel | None = None
        self._revision: str | None = None
        self._saved_revision: str | None = None
        self._loading_error: BaseException | None = None
        self.loaded_from = ""
        """Where the model came from: "index file", "store", or "" while it loads."""
        self._ready = threading.Event()
        if background:
            threading.Thread(
                target=self._open,
                kwargs={"background": True},
                name="engram-memory-open",
                daemon=True,
            ).start()
        else:
            self._open()

    def _open(self, *, background: bool = False) -> None:
        """Read the model from the index file beside the store, or rebuild it from the store."""
        began = time.perf_counter()
        try:
            model, revision, source = index_file.open_model(
                self.store, self._weights(), lambda: persist.load_model(self.store, self._weights())
            )
            # Not under the lock: a caller holding it may be waiting for this (see _model).
            self._revision, self.loaded_from = revision, source
            self._saved_revision = revision if source == "index file" else None
            self._loaded = model
            self._repair_view()
        except Exception as error:
            self._loaded, self._loading_error = None, error
            self._ready.set()
            if not background:
                raise
            log.exception("scene memory could not be opened")
            return
        self._ready.set()
        log.info(
            "scene memory opened from the %s in %.2f s: %d classes, %d experienced scenes",
            source,
            time.perf_counter() - began,
            len(model.classes),
            len(model.items),
        )

    @property
    def clock(self) -> Clock:
        """The clock the memory reads (a :class:`~reasoners.clock.SettableClock` can be set)."""
        return self._clock

    def reload(self) -> None:
        """Rebuild the in-memory index from the store: after another Engram changed it (a
        follower of a shared memory) or a failed write left the index unsure (kg.remote)."""
        with self._lock:
            self._rebuild()

    def _rebuild(self) -> None:
        """Read the model again from the store (under the lock). The reads do not write the
        view of the model they replace (:meth:`settle_view`); the next read checks the view of
        the new one."""
        self._rebuilding = True
        try:
            self._model = persist.load_model(self.store, self._weights())
            self._revision = index_file.stored_revision(self.store)
        finally:
            self._rebuilding = False

    def update_model(self, change: Callable[[MemoryModel], None]) -> None:
        """Run ``change`` on the in-memory index under the memory's lock: a follower of a shared
        memory applying what the writer changed (reasoners.follow). If ``change`` raises, the
        index may be half changed: :meth:`reload` it."""
        with self._lock:
            change(self._model)

    @property
    def _model(self) -> MemoryModel:
        """The in-memory model; :class:`MemoryLoadingError` while it is still being read."""
        model = self._loaded
        if model is None:
            self._ready.wait(LOADING_WAIT_S)  # a small memory is ready before the caller knows
            model = self._loaded
        if model is None:
            if self._loading_error is not None:
                raise MemoryLoadingError(
                    f"scene memory unavailable: opening it failed: {self._loading_error}"
                )
            raise MemoryLoadingError("scene memory unavailable: still loading, retry shortly")
        return model

    @_model.setter
    def _model(self, model: MemoryModel) -> None:
        self._loaded = model

    @property
    def ready(self) -> bool:
        """True once the model is loaded (False while loading or after a failed load)."""
        return self._loaded is not None

    def wait_ready(self, timeout_s: float | None = None) -> bool:
        """Wait until loading has finished (or failed); True if the memory is ready."""
        self._ready.wait(timeout_s)
        return self.ready

    def save_index(self) -> bool:
        """Save the model beside the store (see :mod:`reasoners.index_file`) if the store
        changed since the last save; True if a file was written. The store is flushed first,
        so that the file never names a revision the store could lose."""
        path = index_file.index_path(self.store)
        if path is None or not self.ready:
            return False
        self.settle_view()  # so that the next open has no view to repair
        with self._lock:
            revision = self._revision
            if revision is None or revision == self._saved_revision:
                return False
            self.store.flush()
            values = index_file.snapshot(self._model, revision, self._weights())
        index_file.write_snapshot(path, values)
        with self._lock:
            self._saved_revision = revision
        log.info("scene memory index saved at revision %s", revision)
        return True

    # Helpers -----------------------------------------------------------------------------------

    def _weights(self) -> tuple[float, float, float, float]:
        p = self.policy
        return (p.complexityWeight, p.childrenWeight, p.storeWeight, p.retrieveWeight)

    def _repair_view(self) -> None:
        """Write the score view where the store lacks it or it is stale (a store written by an
        older Engram, or by hand), and drop the annotations the view replaced; migrate a store
        written before the data model stored only what cannot be derived
        (:mod:`reasoners.migration`). One transaction, only when needed."""
        m = self._model
        legacy = any(
            True
            for prop, graph in (
                (LEGACY_SCORE, MEMORY),
                (LEGACY_LEVEL, MEMORY),
                (LEGACY_LEVEL, EPISODIC),
            )
            for _ in self.store.quads(None, prop, None, graph)
        )
        migrate = migration.needed(self.store, m)
        factors_stale = bool(m.classes) and m.written_factors != (*m.coefficients(), m.max_score)
        unlabelled: list[ClassRecord] = []
        if self.loaded_from != "index file":  # a file is saved only by a repaired memory
            named = {q.subject for q in self.store.quads(None, SKOS_NOTATION, None, MEMORY)}
            unlabelled = [record for cls, record in m.classes.items() if cls not in named]
        if not (legacy or migrate or m.unwritten or factors_stale or unlabelled):
            return
        with self._write(view=True) as tx:
            for record in m.classes.values():  # terms missing, partial or damaged: rewritten
                if record.written_z is None:
                    for prop in SCORE_TERM_PROPERTIES:
                        tx.delete_matching(record.iri, prop, None, graph=MEMORY)
            if migrate:
                migration.migrate(tx, self.store, m)
            for record in unlabelled:  # learned before labels spelt out the definition
                tx.delete_matching(record.iri, RDFS_LABEL, None, graph=MEMORY)
                persist.write_label(tx, record)
            if legacy:
                tx.delete_matching(None, LEGACY_SCORE, None, graph=MEMORY)
                tx.delete_matching(None, LEGACY_LEVEL, None, graph=MEMORY)
                tx.delete_matching(None, LEGACY_LEVEL, None, graph=EPISODIC)
            if factors_stale:
                m.written_factors = None  # rewritten whole
        log.info("scene memory: score view written for %d classes", len(m.classes))

    def _now(self) -> dt.datetime:
        now = self._clock()
        if not isinstance(now, dt.datetime) or now.tzinfo is None:
            raise ValueError(f"clock: got {now!r}, expected a timezone-aware datetime")
        # Times are kept at millisecond precision, in the model as in the store (xsd:dateTime
        # with microseconds makes HermiT refuse an export).
        return now.replace(microsecond=now.microsecond - now.microsecond % 1000)

    def settle_view(self) -> None:
        """Write the score view's pending changes (:func:`reasoners.persist.write_view`) in
        one transaction, if an update committed before this call left any; the store calls it
        before every read (:meth:`kg.store.Store.settle_reads`), so a reader never sees a stale
        view.

        An update writes the class it touched, its edges and its experienced scene; the score
        terms of its ancestors (a class's score depends on its children's) wait for the next
        read, so that the updates between two reads rewrite each changed class once. While
        another thread holds the memory (an update in progress), the caller waits for that
        thread to write the view as it lets go. Nothing is written while a batch of this thread
        is open (it has not committed yet) or while the model loads."""
        target = self._begun
        while self._viewed < target:
            if self._lock.acquire(blocking=False):  # free, or this thread's own
                try:
                    if self._batch is None and self._loaded is not None and not self._rebuilding:
                        self._want(target)
                        self._write_view_if_wanted()
                finally:
                    self._lock.release()
                return
            self._want(target)  # the holder writes it as it lets go, or this thread does
            if self._lock.acquire(timeout=0.01):
                self._lock.release()

    def _want(self, target: int) -> None:
        with self._counters:
            self._wanted = max(self._wanted, target)

    def _write_view_if_wanted(self) -> None:
        """Under the lock: write the view of every update begun so far if a reader waits for
        it."""
        if self._wanted <= self._viewed:
            return
        upto = self._begun
        with self._write(view=True):
            pass
        with self._counters:
            self._viewed = max(self._viewed, upto)

    def _let_go(self) -> None:
        """After a committed update, still under the lock: write the view if a reader waits
        (a failure is left to the reader, which tries again and reports it)."""
        try:
            self._write_view_if_wanted()
        except Exception:
            log.exception("scene memory: the score view could not be written after an update")

    @contextmanager
    def _write(
        self, *, refresh_alongside: bool = False, view: bool = False
    ) -> Iterator[PendingWrites]:
        """One transaction; if anything fails, the model is rebuilt from the store.

        With ``refresh_alongside``, the model's pending re-scoring (the ancestors of what the
        transaction touched) runs while the store applies the write, instead of before it.
        The transaction writes the score view with ``view`` or on a shared server; otherwise
        the view is marked stale for :meth:`settle_view`.
        """
        view = view or self.view_in_each_update
        with self._lock:
            if self._batch is not None:  # the batch's owner commits, or rolls back
                if not view:
                    self._begun += 1  # its commit is the owner's: a reader arriving waits
                self._read_history_epoch()
                yield self._batch
                if view:
                    persist.write_view(self._batch, self._model, self._policy_iri)
                return
            alongside = self._model.refresh if refresh_alongside else None
            revision = index_file.new_revision()
            try:
                with self.store.transaction(alongside=alongside) as tx:
                    writes = PendingWrites()
                    self._reader = writes.view(self.store)
                    self._read_history_epoch()
                    yield writes
                    if view:
                        persist.write_view(writes, self._model, self._policy_iri)
                    if not writes.is_empty:  # the index file names the revision it mirrors
                        index_file.record_revision(writes, self._revision, revision)
                        if not view:
                            self._begun += 1  # before the commit: no reader may miss it
                    writes.copy_into(tx)
                if not writes.is_empty:
                    self._revision = revision
            except BaseException:
                if self._loaded is not None:  # not while it loads: the loader will set it
                    self._rebuild()
                raise
            finally:
                self._reader = self.store
            if not view:
                self._let_go()

    def _read_history_epoch(self) -> None:
        if self._model.history_epoch is None:  # a model just loaded or rebuilt
            self._model.history_epoch = history.current_epoch(self._reader)

    @contextmanager
    def batch(self) -> Iterator[PendingWrites]:
        """Run several operations into one set of writes that the caller commits.

        Inside the ``with`` block, :meth:`store_scene`, :meth:`retrieve`, :meth:`sleep`,
        :meth:`pin`, :meth:`restore` and :meth:`learn_classes` write into the yielded
        :class:`~reasoners.batch.PendingWrites` instead of committing, each seeing the ones
        before it. The caller adds those writes to its own transaction and commits it inside the
        block (a directive list does so with its other writes). The memory's lock is held for the
        whole block, so no other thread sees the model between the operations and the commit; if
        the block raises (an operation failed, or the commit did), the model is rebuilt from the
        store, which the failed commit left as it was.
        """
        # a shared store catches up after a failed write now, not at this batch's commit
        self.store.settle()
        with self._lock:
            if self._batch is not None:
                raise RuntimeError("batch: a batch is already open on this memory")
            writes = PendingWrites()
            # the index file names the revision it mirrors: the batch's commit makes a new one
            revision = index_file.new_revision()
            index_file.record_revision(writes, self._revision, revision)
            self._batch, self._reader = writes, writes.view(self.store)
            clock = self._clock
            saved = clock.snapshot() if isinstance(clock, SettableClock) else None
            try:
                yield writes
                self._revision = revision
            except BaseException:
                self._rebuild()
                if isinstance(clock, SettableClock):
                    clock.restore(saved)
                raise
            finally:
                self._batch, self._reader = None, self.store
            self._let_go()

    def _scene(self, primitives: Sequence[Primitive], field: str = "primitives") -> list[Primitive]:
        scene = list(primitives)
        bad = [p for p in scene if not isinstance(p, Primitive)]
        if bad:
            raise InvalidSceneError(
                f"{field}: got {bad[0]!r}, expected kg.primitive.Primitive objects"
            )
        ids = [p.id for p in scene]
        duplicates = sorted({i for i in ids if ids.count(i) > 1})
        if duplicates:
            raise InvalidSceneError(
                f"{field}: ids must be unique within a scene, "
                f"got {', '.join(map(repr, duplicates))} more than once"
            )
        return scene

    def _encode(
        self, primitives: Sequence[Primitive]
    ) -> tuple[list[Primitive], list[Relation], Signature]:
        scene = self._scene(primitives)
        relations = self.encoder.relations(scene)
        signature = self.encoder.signature(scene, relations)
        if signature.complexity == 0:
            raise InvalidSceneError(
                f"primitives: got {len(scene)} object(s) and no spatial relation between them, "
                "expected a scene of at least two related objects"
            )
        return scene, relations, signature

    def _cue(self, cue: Cue) -> Signature:
        if isinstance(cue, Signature):
            if not cue:
                raise InvalidSceneError("cue: got an empty signature, expected at least one key")
            return cue
        items = list(cue)
        if not items:
            raise InvalidSceneError("cue: got nothing, expected primitives or relation triples")
        if all(isinstance(i, Primitive) for i in items):
            return self._encode(items)[2]  # type: ignore[arg-type]
        return self.encoder.cue_signature(items)  # type: ignore[arg-type]

    def _recognitions(self, signature: Signature) -> list[Recognition]:
        """Most complex (most confident) first, then most stored, then by IRI."""
        classes, d = self._model.classes, signature.complexity
        records = [classes[cls] for cls in self._model.index.recognised(signature)]
        # two stable sorts on keys read in C (last key first): most complex, then most stored
        # (reverse keeps the order of equals), then by IRI
        records.sort(key=_BY_IRI)
        records.sort(key=_BY_COMPLEXITY_AND_STORES, reverse=True)
        return [
            Recognition(r.iri, r.signature.complexity / d, r.signature.complexity) for r in records
        ]

    def _rescore(
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
        all their ζ depend on); their ancestors may be left to :meth:`MemoryModel.refresh`."""
        m = self._model
        m.refresh(
            down_to=min((m.classes[c].signature.complexity for c in classes | fresh), default=0)
        )
        for cls in classes - fresh:
            self._write_score(tx, m.classes[cls])
        for cls in fresh:
            m.classes[cls].score = m.zeta(m.classes[cls])
            m.scored.pop(cls, None)

    def _write_score(
        self, tx: Transaction, record: ClassRecord, value: float | None = None
    ) -> None:
        new = self._model.zeta(record) if value is None else value
        self._model.scored.pop(record.iri, None)
        if new != record.score:
            persist.set_value(tx, record.iri, SCORE, Literal(record.score), Literal(new), MEMORY)
            record.score = new

    def _class_scores(
        self, record: ClassRecord, live: tuple[float, float] | None = None
    ) -> ItemScores:
        """A class's scores; ``live`` is its (ζ, largest ζ) when the caller has them already."""
        m, p = self._model, self.policy
        zeta, top = live if live is not None else (m.zeta(record), m.max_score)
        normalised = zeta / top if top > 0 else 0.0
        return ItemScores(
            iri=record.iri,
            kind="class",
            complexity=record.signature.complexity,
            store_count=record.store_count,
            retrieve_count=record.retrieve_count,
            raw_score=zeta,
            normalised=normalised,
            level=level_of(normalised, high=p.highLevelThreshold, weak=p.weakLevelThreshold),
            stored_level=record.level,
            consecutive_weak=record.weak_count,
            pinned=record.pinned,
            created=record.created,
            last_accessed=record.last_accessed,
        )

    def _count_use(
        self, tx: Transaction, record: ClassRecord, now: dt.datetime, *, retrieved: bool
    ) -> None:
        """Raise a class's store count (or retrieve count) by one and set its access time to
        ``now``, in the model and in the transaction."""
        if retrieved:
            prop, old = RETRIEVE_COUNT, record.retrieve_count
            self._model.set_counts(record, store=record.store_count, retrieve=old + 1)
        else:
            prop, old = STORE_COUNT, record.store_count
            self._model.set_counts(record, store=old + 1, retrieve=record.retrieve_count)
        persist.set_value(tx, record.iri, prop, Literal(old), Literal(old + 1), MEMORY)
        persist.set_value(
            tx,
            record.iri,
            LAST_ACCESSED,
            persist.time_literal(record.last_accessed),
            persist.time_literal(now),
            MEMORY,
        )
        record.last_accessed = now

    def _bump_update(self, tx: Transaction) -> None:
        m = self._model
        m.updates_since_sleep += 1
        if m.has_state:
            old, new = Literal(m.updates_since_sleep - 1), Literal(m.updates_since_sleep)
            persist.set_value(tx, MEMORY_STATE_INDIVIDUAL, UPDATES_SINCE_SLEEP, old, new, MEMORY)
        else:
            persist.write_state(tx, m)

    # Store -------------------------------------------------------------------------------------

    def store_scene(
        self, primitives: Sequence[Primitive], *, episode: NamedNode | None = None
    ) -> StoreResult:
        """Encode the scene, reinforce its best class or learn a new one, record the experienced
        scene and consolidate the class's branch, as one transaction.

        The best recognised class (highest complexity) is reinforced when its confidence
        d(class)/d(scene) reaches the policy's learn threshold; otherwise a class
        ``C ≡ ⊓(≥n p.T)``, ``C ⊑ Scene`` is learned and linked to its direct parents and children.
        ``episode`` links the experienced scene to an autobiographical episode.

        Raises :class:`~reasoners.errors.InvalidSceneError` for duplicate ids or a scene without
        relations, and ``TypeError`` for an episode that is not a NamedNode; nothing is written.
        """
        if episode is not None and not isinstance(episode, NamedNode):
            raise TypeError(f"episode: got {episode!r}, expected a NamedNode or None")
        scene, relations, signature = self._encode(primitives)
        with self._lock:  # the result reads the model the transaction left
            with self._write(refresh_alongside=True) as tx:
                now = self._now()
                m = self._model
                recognised = self._recognitions(signature)
                best = recognised[0] if recognised else None
                confidence = best.confidence if best else 0.0
                fresh: NamedNode | None = None
                if best is not None and confidence >= self.policy.learnThreshold:
                    record = m.classes[best.cls]
                    self._count_use(tx, record, now, retrieved=False)
                else:
                    record = _new_class(m, signature, now)
                    parents, children, removed = m.add_class(record, [r.cls for r in recognised])
                    added = {(record.iri, p) for p in parents} | {(c, record.iri) for c in children}
                    persist.write_edges(tx, added, removed)
                    fresh = record.iri
                item = ItemRecord(
                    iri=persist.item_iri(m.next_item),
                    cls=record.iri,
                    complexity=signature.complexity,
                    created=now,
                    last_accessed=now,
                )
                m.next_item += 1
                m.add_item(item)
                persist.write_item(tx, item, scene, relations, episode)
                self._rescore(tx, {record.iri}, {fresh} if fresh else set())
                if fresh is not None:
                    persist.write_class(tx, record, stored=m.stored_restrictions)
                history.stored(tx, m, record, item.iri, recognised, now, fresh)
                self._bump_update(tx)
            result = StoreResult(
                scene_item=item.iri,
                stored_as=record.iri,
                learned=fresh is not None,
                recognised=tuple(recognised),
                confidence=confidence,
                signature=signature,
                relations=tuple(relations),
                parents=tuple(sorted(m.parents[record.iri], key=lambda c: c.value)),
                scores=self._class_scores(record),
            )
        log.info(
            "stored %s as %s (%s, confidence %.2f)",
            item.iri.value,
            record.iri.value,
            "learned" if fresh else "reinforced",
            confidence,
        )
        return result

    def learn_classes(self, signatures: Sequence[Signature]) -> list[NamedNode]:
        """Teach classes directly from signatures (importing a memory, preparing a benchmark),
        as one transaction: each new signature becomes ``C ≡ ⊓(≥n p.T)`` with store count 1,
        linked into the graph, and the touched branches are consolidated. Signatures already
        learned are skipped. Returns the new classes."""
        with self._write() as tx:
            now = self._now()
            m = self._model
            added: set[tuple[NamedNode, NamedNode]] = set()
            removed: set[tuple[NamedNode, NamedNode]] = set()
            fresh: list[ClassRecord] = []
            for signature in signatures:
                if not signature or m.index.with_signature(signature) is not None:
                    continue
                record = _new_class(m, signature, now)
                parents, children, cut = m.add_class(record)
                for edge in cut:  # an edge added earlier in this batch is simply not written
                    if edge in added:
                        added.discard(edge)
                    else:
                        removed.add(edge)
                added |= {(record.iri, p) for p in parents} | {(c, record.iri) for c in children}
                fresh.append(record)
            persist.write_edges(tx, added, removed)
            new = {r.iri for r in fresh}
            self._rescore(tx, new, new)
            for record in fresh:
                persist.write_class(tx, record, stored=m.stored_restrictions)
            history.record_all(tx, m, fresh, "learned", now)
            m.updates_since_sleep += len(fresh)
            persist.write_state(tx, m)
        return [r.iri for r in fresh]

    def recognise(self, primitives: Sequence[Primitive]) -> list[Recognition]:
        """The learned classes the scene belongs to, by confidence; writes nothing."""
        signature = self._encode(primitives)[2]
        with self._lock:
            return self._recognitions(signature)

    # Retrieve ----------------------------------------------------------------------------------

    def retrieve(
        self,
        cue: Cue,
        *,
        spread: bool = False,
        limit: int = 10,
        spread_decay: float = 0.5,
        spread_hops: int = 3,
    ) -> RetrievalResult:
        """Place the cue virtually (never written) and recall from it, as one transaction.

        Finds the exact match, the generalisations (classes the cue belongs to), the
        specialisations (classes containing the cue) and the ``limit`` most similar classes.
        The recalled class and its ancestors get their retrieve count raised and are
        re-scored. With ``spread``, activation spreads from the recalled class over the
        subclass graph, multiplied by ``spread_decay`` per hop, up to ``spread_hops`` hops.

        Raises :class:`~reasoners.errors.InvalidSceneError` for a malformed cue.
        """
        if limit < 1:
            raise ValueError(f"limit: got {limit!r}, expected a positive integer")
        signature = self._cue(cue)
        with self._write() as tx:
            now = self._now()
            m = self._model
            exact = m.index.with_signature(signature)
            generalisations = [r for r in self._recognitions(signature) if r.cls != exact]
            d = signature.complexity

            def spec_key(match: Match) -> tuple[float, int, str]:
                return (-match.similarity, -m.classes[match.cls].store_count, match.cls.value)

            specialisations = sorted(
                (
                    Match(c, d / m.classes[c].signature.complexity)
                    for c in m.index.dominating(signature)
                    if c != exact
                ),
                key=spec_key,
            )
            similar = tuple(Match(c, s) for c, s in m.index.most_similar(signature, limit))
            recalled = exact or (
                specialisations[0].cls
                if specialisations
                else generalisations[0].cls
                if generalisations
                else None
            )
            branch: tuple[NamedNode, ...] = ()
            if recalled is not None:
                members = {recalled} | m.ancestors(recalled)
                branch = tuple(sorted(members, key=lambda c: m.classes[c].signature.complexity))
                for cls in members:
                    self._count_use(tx, m.classes[cls], now, retrieved=True)
                self._rescore(tx, members)
                history.record(tx, m, m.classes[recalled], "retrieved", now)
            activation = None
            if spread and recalled is not None:
                activation = self._spread({recalled: 1.0}, spread_decay, spread_hops)
            self._bump_update(tx)
        log.info("retrieved %s for a cue of complexity %d", recalled and recalled.value, d)
        return RetrievalResult(
            signature=signature,
            exact=exact,
            generalisations=tuple(generalisations),
            specialisations=tuple(specialisations),
            similar=similar,
            recalled=recalled,
            branch=branch,
            activation=activation,
        )

    def _spread(self, seeds: dict[NamedNode, float], decay: float, hops: int) -> tuple[Match, ...]:
        m = self._model
        activation = dict(seeds)
        frontier = dict(seeds)
        for _ in range(hops):
            following: dict[NamedNode, float] = {}
            for cls, value in frontier.items():
                for neighbour in m.parents[cls] | m.children[cls]:
                    passed = value * decay
                    if passed > activation.get(neighbour, 0.0) and passed > following.get(
                        neighbour, 0.0
                    ):
                        following[neighbour] = passed
            activation.update(following)
            frontier = following
        ranked = sorted(activation.items(), key=lambda kv: (-kv[1], kv[0].value))
        return tuple(Match(cls, value) for cls, value in ranked)

    # Sleep -------------------------------------------------------------------------------------

    def sleep(self) -> SleepReport:
        """Systems consolidation: re-score the whole graph bottom-up, evaluate levels, forget.

        A class or experienced scene that is WEAK for ``weakPassesToForget`` consecutive passes,
        older than ``forgetGracePeriodSeconds`` and not pinned is moved to the ``trash`` graph;
        a forgotten class takes its experienced scenes with it. A class with a pinned experienced
        scene is kept, and a pinned class keeps its experienced scenes. The report names each
        forgotten scene once. One transaction.
        """
        started = time.perf_counter()
        with collector_paused(), self._write() as tx:
            now = self._now()
            m = self._model
            rescored = len(m.classes)
            plan = forgetting.plan(m, self.policy, now)
            class_levels, item_levels = plan.class_levels, plan.item_levels
            doomed_classes = plan.doomed_classes
            # one truth: what is forgotten goes to the trash with this pass's level and WEAK
            # count (the count that forgot it), as the history and /explain give them
            leaving = forgetting.leaving_items(m, doomed_classes, plan.doomed_items)
            for cls in doomed_classes:
                self._set_level(tx, m.classes[cls], WEAK, plan.weak_counts[cls], MEMORY)
            for iri in leaving:
                self._set_level(tx, m.items[iri], item_levels[iri], plan.item_weak[iri], EPISODIC)
            history.forgetting(tx, m, doomed_classes, leaving, plan.zetas, now)
            forgotten_items = forgetting.move_to_trash(
                tx, m, self._reader, doomed_classes, plan.doomed_items, now
            )
            # the graph changed: ζ of the forgotten classes' neighbours too
            zetas = m.zetas() if doomed_classes else plan.zetas
            history.sleep_levels(tx, m, class_levels, zetas, now)
            history.checkpoint(tx, m, self.store, now)
            # a class's ζ and level are the view's: only the WEAK counts that changed are written
            for cls, record in m.classes.items():
                self._set_level(tx, record, class_levels[cls], plan.weak_counts[cls], MEMORY)
            for iri, item in m.items.items():
                self._set_level(tx, item, item_levels[iri], plan.item_weak[iri], EPISODIC)
            m.scored = zetas
            m.last_sleep_at = now
            m.updates_since_sleep = 0
            m.sleep_passes += 1
            persist.write_levels(tx, m)
            persist.write_state(tx, m)
        report = SleepReport(
            at=now,
            rescored=rescored,
            levels={c: class_levels[c] for c in m.classes},
            item_levels={i: item_levels[i] for i in m.items},
            forgotten_classes=tuple(doomed_classes),
            forgotten_items=tuple(forgotten_items),
            duration_s=time.perf_counter() - started,
        )
        log.info(
            "sleep pass: %d classes re-scored, %d classes and %d items forgotten",
            report.rescored,
            len(report.forgotten_classes),
            len(report.forgotten_items),
        )
        return report

    def _trashed_with(self, cls: NamedNode) -> list[NamedNode]:
        m = self._model
        return [i for i, t in m.trashed_items.items() if t.cls == cls]

    @staticmethod
    def _set_level(
        tx: Transaction,
        record: ClassRecord | ItemRecord,
        level: str,
        weak: int,
        graph: NamedNode,
    ) -> None:
        """Give ``record`` a sleep pass's level (kept in the model; the pass writes them all in
        one literal) and WEAK count (written where it changed, absent when 0)."""
        record.level = level
        if record.weak_count != weak:
            if record.weak_count:
                tx.delete(record.iri, CONSECUTIVE_WEAK_COUNT, Literal(record.weak_count), graph)
            if weak:
                tx.insert(record.iri, CONSECUTIVE_WEAK_COUNT, Literal(weak), graph)
            record.weak_count = weak

    def maybe_sleep(self) -> SleepReport | None:
        """Run a sleep pass if ``sleepEveryUpdates`` updates or ``sleepIntervalSeconds`` seconds
        have passed since the last one (or since the first class was learned); else None."""
        with self._lock:
            m, p = self._model, self.policy
            if m.updates_since_sleep == 0:
                return None
            due = m.updates_since_sleep >= p.sleepEveryUpdates
            since = m.last_sleep_at or min((r.created for r in m.classes.values()), default=None)
            if not due and since is not None:
                due = (self._now() - since).total_seconds() >= p.sleepIntervalSeconds
            return self.sleep() if due else None

    # Pin, restore, read ------------------------------------------------------------------------

    def pin(self, iri: NamedNode, pinned: bool = True) -> None:
        """Protect a class or experienced scene from forgetting (or lift the protection).

        Raises :class:`~reasoners.errors.UnknownItemError` for an IRI that is not live."""
        with self._write() as tx:
            m = self._model
            record: ClassRecord | ItemRecord
            if iri in m.classes:
                record, graph = m.classes[iri], MEMORY
            elif iri in m.items:
                record, graph = m.items[iri], EPISODIC
            else:
                raise self._unknown(iri)
            if record.pinned != pinned:
                persist.set_value(tx, iri, PINNED, Literal(record.pinned), Literal(pinned), graph)
                record.pinned = pinned
                history.record(
                    tx, self._model, record, "pinned" if pinned else "unpinned", self._now()
                )

    def restore(self, iri: NamedNode) -> tuple[NamedNode, ...]:
        """Bring a forgotten class (with every experienced scene of it in the trash: those
        forgotten with it and those forgotten alone before) or a forgotten experienced scene back
        from the trash, exactly as it was (its WEAK count reset).

        Returns the restored IRIs. Raises :class:`~reasoners.errors.NotInTrashError` if the trash
        does not hold ``iri``, :class:`~reasoners.errors.RestoreConflictError` if a live class has
        the same signature, and :class:`~reasoners.errors.UnknownItemError` for an experienced
        scene whose class is itself in the trash.
        """
        with self._write() as tx:
            m = self._model
            if iri in m.trashed_classes:
                restored = self._restore_class(tx, iri)
            elif iri in m.trashed_items:
                trashed = m.trashed_items[iri]
                if trashed.cls not in m.classes:
                    raise UnknownItemError(
                        f"iri: {iri.value} was stored as {trashed.cls.value}, which is in the "
                        "trash too; restore the class first"
                    )
                self._restore_items(tx, [iri])
                restored = (iri,)
            else:
                raise NotInTrashError(f"iri: got {iri.value}, expected an IRI in the trash")
        log.info("restored %s", ", ".join(r.value for r in restored))
        return restored

    def _restore_class(self, tx: Transaction, cls: NamedNode) -> tuple[NamedNode, ...]:
        m = self._model
        trashed = m.trashed_classes[cls]
        rival = m.index.with_signature(trashed.signature)
        if rival is not None:
            raise RestoreConflictError(
                f"iri: {cls.value} has the same signature as the live class {rival.value}; "
                "nothing restored"
            )
        values = {}
        for quad in list(self._reader.quads(cls, None, None, TRASH)):
            values[quad.predicate] = quad.object
            persist.delete_quad(tx, quad, TRASH)
        record = ClassRecord(
            iri=cls,
            signature=trashed.signature,
            store_count=int(persist.text(values[STORE_COUNT])),
            retrieve_count=int(persist.text(values[RETRIEVE_COUNT])),
            score=float(persist.text(values[SCORE])),
            created=persist.parse_time(values[CREATED]),
            last_accessed=persist.parse_time(values[LAST_ACCESSED]),
            weak_count=0,
            pinned=persist.text(values.get(PINNED, Literal(False))) == "true",
        )
        del m.trashed_classes[cls]
        parents, children, removed = m.add_class(record)
        added = {(cls, p) for p in parents} | {(c, cls) for c in children}
        persist.write_edges(tx, added, removed)
        # every experienced scene of the class in the trash: those forgotten with it, and those
        # forgotten alone before (the class's memory comes back whole)
        items = sorted(self._trashed_with(cls), key=str)
        self._restore_items(tx, items)
        self._rescore(tx, set(), {cls})
        persist.write_class(tx, record, stored=m.stored_restrictions)
        history.record(tx, self._model, record, "restored", self._now())
        return (cls, *items)

    def _restore_items(self, tx: Transaction, items: Sequence[NamedNode]) -> None:
        m = self._model
        for item in items:
            trashed = m.trashed_items.pop(item)
            own = list(self._reader.quads(item, None, None, TRASH))
            values = {q.predicate: q.object for q in own}
            persist.move(tx, self._reader, [item], TRASH, EPISODIC, follow=HAS_PRIMITIVE)
            # move() re-inserts every triple; the trash-only ones must not reach `episodic`.
            for quad in own:
                if quad.predicate in (FORGOTTEN_AT, CONSECUTIVE_WEAK_COUNT, LEVEL):
                    persist.delete_quad(tx, quad, EPISODIC)
            record = ItemRecord(
                iri=item,
                cls=trashed.cls,
                complexity=int(persist.text(values[COMPLEXITY])),
                created=persist.parse_time(values[CREATED]),
                last_accessed=persist.parse_time(values[LAST_ACCESSED]),
                pinned=persist.text(values.get(PINNED, Literal(False))) == "true",
            )
            m.add_item(record)
            history.record(tx, self._model, record, "restored", self._now())

    def _unknown(self, iri: NamedNode) -> UnknownItemError:
        m = self._model
        if iri in m.trashed_classes or iri in m.trashed_items:
            return UnknownItemError(f"iri: {iri.value} is in the trash; restore it first")
        return UnknownItemError(
            f"iri: got {iri.value!r}, expected a learned scene class or an experienced scene"
        )

    def item_scores(self, iri: NamedNode) -> ItemScores:
        """The raw terms, normalised score and level of a class or experienced scene, now.

        Raises :class:`~reasoners.errors.UnknownItemError` for an IRI that is not live."""
        with self._lock:
            m, p = self._model, self.policy
            if iri in m.classes:
                return self._class_scores(m.classes[iri])
            if iri not in m.items:
                raise self._unknown(iri)
            now = self._now()
            record = m.items[iri]
            raw = forgetting.item_raw(m, p, record, now)
            top = max((forgetting.item_raw(m, p, r, now) for r in m.items.values()), default=0.0)
            normalised = raw / top if top > 0 else 0.0
            cls = m.classes[record.cls]
            return ItemScores(
                iri=iri,
                kind="item",
                complexity=record.complexity,
                store_count=cls.store_count,
                retrieve_count=cls.retrieve_count,
                raw_score=raw,
                normalised=normalised,
                level=level_of(normalised, high=p.highLevelThreshold, weak=p.weakLevelThreshold),
                stored_level=record.level,
                consecutive_weak=record.weak_count,
                pinned=record.pinned,
                created=record.created,
                last_accessed=record.last_accessed,
                cls=record.cls,
            )

    def classes(self) -> list[ClassSummary]:
        """Every live learned class with its signature, direct edges and scores, simplest first."""
        with self._lock:
            m = self._model
            zetas, top = m.zetas(), m.max_score
            return [
                ClassSummary(
                    iri=record.iri,
                    signature=record.signature,
                    parents=tuple(sorted(m.parents[record.iri], key=str)),
                    children=tuple(sorted(m.children[record.iri], key=str)),
                    items=len(m.items_of.get(record.iri, ())),
                    scores=self._class_scores(record, (zetas[record.iri], top)),
                )
                for record in sorted(
                    m.classes.values(), key=lambda r: (r.signature.complexity, r.iri.value)
                )
            ]

    def state(self, best: int = 10) -> tuple[int, int, list[tuple[NamedNode, float]]]:
        """(learned classes, experienced scenes, the ``best`` classes by live raw score ζ as
        (class, ζ), best first, ties by IRI)."""
        with self._lock:
            m = self._model
            zetas = m.zetas()
            top = heapq.nsmallest(best, zetas.items(), key=lambda kv: (-kv[1], kv[0].value))
            return len(m.classes), len(m.items), top

    def items(self) -> list[NamedNode]:
        """Every live experienced scene, oldest first."""
        with self._lock:
            return sorted(self._model.items, key=lambda i: self._model.items[i].created)

    def trash(self) -> list[NamedNode]:
        """Everything in the trash that :meth:`restore` accepts."""
        with self._lock:
            return [*self._model.trashed_classes, *self._model.trashed_items]

    def signature(self, iri: NamedNode) -> Signature:
        """The signature of a live class. Raises UnknownItemError otherwise."""
        with self._lock:
            record = self._model.classes.get(iri)
            if record is None:
                raise self._unknown(iri)
            return record.signature

    # Read-only views for explanations ----------------------------------------------------------

    def now(self) -> dt.datetime:
        """The memory clock's current time."""
        return self._now()

    def relatives(self, iri: NamedNode) -> tuple[tuple[NamedNode, ...], tuple[NamedNode, ...]]:
        """(direct parents, direct children) of a live class, each sorted by IRI.

        Raises :class:`~reasoners.errors.UnknownItemError` for an IRI that is not a live class."""
        with self._lock:
            m = self._model
            if iri not in m.classes:
                raise self._unknown(iri)
            return (
                tuple(sorted(m.parents[iri], key=str)),
                tuple(sorted(m.children[iri], key=str)),
            )

    def score_terms(self, iri: NamedNode) -> ScoreTerms:
        """The terms ζ of a live class adds up now (raises UnknownItemError otherwise)."""
        with self._lock:
            m = self._model
            record = m.classes.get(iri)
            if record is None:
                raise self._unknown(iri)
            children = sorted(m.children[iri], key=str)
            return ScoreTerms(
                complexity=record.signature.complexity,
                max_complexity=m.max_complexity,
                store_count=record.store_count,
                max_store=m.max_store,
                retrieve_count=record.retrieve_count,
                max_retrieve=m.max_retrieve,
                children_zeta=tuple(m.zeta(m.classes[c]) for c in children),
                weights=m.weights,
                zeta=m.zeta(record),
                max_zeta=m.max_score,
            )

    def recognitions(self, signature: Signature) -> list[Recognition]:
        """The live classes a signature belongs to, most confident first; writes nothing."""
        with self._lock:
            return self._recognitions(signature)

    def closest(self, signature: Signature, limit: int = 5) -> list[Match]:
        """The ``limit`` live classes most similar to a signature, best first; writes nothing."""
        with self._lock:
            return [Match(c, s) for c, s in self._model.index.most_similar(signature, limit)]

    def trashed(self, iri: NamedNode) -> TrashEntry | None:
        """What the trash holds under ``iri``, or None."""
        with self._lock:
            m = self._model
            if iri in m.trashed_classes:
                c = m.trashed_classes[iri]
                return TrashEntry(iri, "class", c.forgotten_at, signature=c.signature)
            if iri in m.trashed_items:
                i = m.trashed_items[iri]
                return TrashEntry(iri, "item", i.forgotten_at, cls=i.cls)
            return None

    def maxima(self) -> dict[str, int]:
        """How many live classes and experienced scenes there are, and the largest class
        complexity, experienced-scene complexity, store and retrieve counts that the scores
        are normalised by."""
        with self._lock:
            m = self._model
            return {
                "classes": len(m.classes),
                "items": len(m.items),
                "complexity": m.max_complexity,
                "item_complexity": m.max_item_complexity,
                "store": m.max_store,
                "retrieve": m.max_retrieve,
            }

    def best(self, count: int = 3) -> list[tuple[NamedNode, float]]:
        """The ``count`` live classes of largest live raw score ζ as (class, ζ), best first,
        ties by IRI (as :meth:`state`, without a pass over every class in Python)."""
        with self._lock:
            return self._model.top(count)

    def learned_at(self, cls: NamedNode) -> dt.datetime:
        """When a live class was learned (raises UnknownItemError otherwise)."""
        with self._lock:
            record = self._model.classes.get(cls)
            if record is None:
                raise self._unknown(cls)
            return record.created

    def seen(self, cls: NamedNode) -> list[tuple[NamedNode, dt.datetime]]:
        """The live experienced scenes stored as ``cls`` and when each was seen, oldest first
        (ties by IRI)."""
        with self._lock:
            m = self._model
            return sorted(
                ((i, m.items[i].created) for i in m.items_of.get(cls, ())),
                key=lambda pair: (pair[1], pair[0].value),
            )

    def items_of(self, cls: NamedNode) -> list[NamedNode]:
        """The live experienced scenes stored as ``cls``, sorted by IRI."""
        with self._lock:
            return sorted(self._model.items_of.get(cls, ()), key=str)

    def live_class(self, signature: Signature) -> NamedNode | None:
        """The live class learned with exactly this signature, or None."""
        with self._lock:
            return self._model.index.with_signature(signature)


def _settle_view_of(memory: "weakref.ref[SceneMemory]") -> Callable[[], None]:
    """The store's read barrier for a memory: one that does not keep it alive."""

    def settle() -> None:
        if (live := memory()) is not None:
            live.settle_view()

    return settle


def _maybe_str(value: str | None) -> Literal | None:
    return None if value is None else Literal(value)


def _new_class(model: MemoryModel, signature: Signature, now: dt.datetime) -> ClassRecord:
    """A class learned now from ``signature``, stored once, under the model's next number."""
    record = ClassRecord(
        iri=persist.class_iri(model.next_class),
        signature=signature,
        store_count=1,
        retrieve_count=0,
        score=0.0,
        created=now,
        last_accessed=now,
    )
    model.next_class += 1
    return record
