"""The scene memory's operations: encode, recognise, learn, consolidate, forget and retrieve.

:class:`SceneMemory` is the façade the rest of Engram calls. Each of
:meth:`SceneMemory.store_scene`, :meth:`~SceneMemory.learn_classes`,
:meth:`~SceneMemory.retrieve`, :meth:`~SceneMemory.sleep`, :meth:`~SceneMemory.pin` and
:meth:`~SceneMemory.restore` is one ``store.transaction()``: all of its writes are visible, or
none (:mod:`reasoners.transactions`); :meth:`~SceneMemory.commit` runs several, described as
values (:mod:`reasoners.operations`), in one transaction with a caller's own writes.
Recognition uses an in-memory model (:mod:`reasoners.model`) read from the index file or rebuilt
from the store's triples (:mod:`reasoners.loading`), and rebuilt again if a transaction fails,
so the store stays the source of truth. Methods may be called from several threads; they are
serialised. The memory's parts, each one idea:

- :attr:`SceneMemory.loaded` (:class:`~reasoners.loading.LoadedModel`): the model, its
  readiness, the revision it mirrors, the index file;
- :attr:`SceneMemory.view` (:class:`~reasoners.score_view.ScoreView`): the score view a SPARQL
  reader derives live scores from, and the re-scoring after an update;
- :attr:`SceneMemory.transactions` (:class:`~reasoners.transactions.Transactions`): how the
  writes reach the store, and when the score view is written;
- :attr:`SceneMemory.reads` (:class:`~reasoners.reads.MemoryReads`): what the memory holds, for
  the views and the explanations.

An update writes only what it changed (the touched class's counters, time and
``engram:rawScore``, the new class and its edges, the new experienced scene); the score view
follows before the store is next read. A sleep pass writes only what the view cannot give: the
consecutive WEAK counts that changed, what it forgot, the level it gave each item (one literal,
``engram:sleepLevels``, the next pass's reference) and its level changes in the history (one
literal); not a class's level or ζ.

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
import logging
import time
import weakref
from collections.abc import Callable, Sequence
from operator import attrgetter

from pyoxigraph import Literal, NamedNode

from kg.clock import Clock, utc_now
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
    LEVEL,
    MEMORY,
    MEMORY_STATE_INDIVIDUAL,
    PINNED,
    RETRIEVE_COUNT,
    SCORE,
    STORE_COUNT,
    TRASH,
    UPDATES_SINCE_SLEEP,
)
from reasoners import forgetting, history, index_file, persist
from reasoners.clock import SettableClock, read_clock
from reasoners.collector import collector_paused
from reasoners.encode import Encoder, Relation
from reasoners.errors import (
    InvalidSceneError,
    NotInTrashError,
    OperationFailedError,
    RestoreConflictError,
    UnknownItemError,
)
from reasoners.loading import LoadedModel
from reasoners.model import MemoryModel
from reasoners.operations import (
    AdvanceClock,
    Cue,
    Operation,
    OperationResult,
    Pin,
    Restore,
    Retrieve,
    SetClock,
    Sleep,
    StoreScene,
)
from reasoners.policy import Policy, load_policy
from reasoners.reads import (
    MemoryReads,
    best_recognition,
    ordered_recognitions,
    recognitions_in,
    unknown_item,
)
from reasoners.records import ClassRecord, ItemRecord
from reasoners.results import (
    ItemScores,
    Match,
    Recognition,
    RetrievalResult,
    SleepReport,
    StoreResult,
)
from reasoners.score_view import ScoreView
from reasoners.scoring import WEAK
from reasoners.signature import Signature
from reasoners.transactions import Transactions

__all__ = ["SceneMemory"]

log = logging.getLogger(__name__)

_IRI_TEXT = attrgetter("value")


class SceneMemory:
    """A robot's scene memory kept in ``store`` (the T-Box is loaded if missing).

    ``clock`` returns the current time as a timezone-aware datetime; inject one to simulate
    time. ``policy`` names the ``engram:MemoryPolicy`` individual whose thresholds and weights
    apply. With ``background``, the model loads in a thread and the operations answer
    :class:`~reasoners.errors.MemoryLoadingError` until it is ready. Raises
    :class:`~reasoners.errors.PolicyError` if the policy is incomplete.
    """

    def __init__(
        self,
        store: Store,
        *,
        clock: Clock = utc_now,
        policy: NamedNode = DEFAULT_POLICY,
        background: bool = False,
    ) -> None:
        ensure_ontology(store)
        self.store = store
        self._clock = clock
        self.policy: Policy = load_policy(store, policy)
        self.encoder = Encoder.from_store(store, self.policy)
        p = self.policy
        weights = (p.complexityWeight, p.childrenWeight, p.storeWeight, p.retrieveWeight)
        self.loaded = LoadedModel(store, weights)
        self.view = ScoreView(self.loaded, self.policy, policy)
        self.transactions = Transactions(self.loaded, self.view, clock)
        self.reads = MemoryReads(self.loaded, self.view, self.policy, clock)
        store.add_read_barrier(_settle_view_of(weakref.ref(self.transactions)))
        self.loaded.open(background=background, then=self._repair_view)

    @property
    def clock(self) -> Clock:
        """The clock the memory reads (a :class:`~reasoners.clock.SettableClock` can be set)."""
        return self._clock

    def save_index(self) -> bool:
        """Write the pending score view, then save the model beside the store
        (:meth:`LoadedModel.save_index`); True if a file was written."""
        if index_file.index_path(self.store) is None or not self.loaded.ready:
            return False
        self.transactions.settle_view()  # so that the next open has no view to repair
        return self.loaded.save_index()

    def _repair_view(self) -> None:
        """Give the store the score view it lacks (one transaction, only when needed)."""
        repair = self.view.stale()
        if repair is None:
            return
        with self.transactions.write(view=True) as tx:
            self.view.repair(tx, repair)
        log.info(
            "scene memory: score view written for %d classes", len(self.loaded.model.graph.classes)
        )

    def _now(self) -> dt.datetime:
        return read_clock(self._clock)

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

    def _count_use(
        self, tx: Transaction, record: ClassRecord, now: dt.datetime, *, retrieved: bool
    ) -> None:
        """Raise a class's store count (or retrieve count) by one and set its access time to
        ``now``, in the model and in the transaction."""
        if retrieved:
            prop, old = RETRIEVE_COUNT, record.retrieve_count
            self.loaded.model.scores.set_counts(record, store=record.store_count, retrieve=old + 1)
        else:
            prop, old = STORE_COUNT, record.store_count
            self.loaded.model.scores.set_counts(
                record, store=old + 1, retrieve=record.retrieve_count
            )
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
        m = self.loaded.model
        m.state.updates_since_sleep += 1
        if m.state.has_state:
            old, new = (
                Literal(m.state.updates_since_sleep - 1),
                Literal(m.state.updates_since_sleep),
            )
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
        with self.loaded.lock:  # the result reads the model the transaction left
            with self.transactions.write(refresh_alongside=True) as tx:
                now = self._now()
                m = self.loaded.model
                classes = m.graph.index.recognised(signature)
                records = list(map(m.graph.classes.__getitem__, classes))
                best = best_recognition(records, signature.complexity)
                confidence = best.confidence if best else 0.0
                fresh: NamedNode | None = None
                recognised: list[Recognition] = []
                if best is not None and confidence >= self.policy.learnThreshold:
                    recognised = ordered_recognitions(records, signature.complexity)
                    record = m.graph.classes[best.cls]
                    self._count_use(tx, record, now, retrieved=False)
                else:
                    # the classes' order is the result's alone: it is taken while the store
                    # writes (a learn changes no recognised class's complexity or store count)
                    self.transactions.alongside(
                        lambda: recognised.extend(
                            ordered_recognitions(records, signature.complexity)
                        )
                    )
                    record = _new_class(m, signature, now)
                    parents, children, removed = m.graph.add_class(record, classes)
                    added = {(record.iri, p) for p in parents} | {(c, record.iri) for c in children}
                    persist.write_edges(tx, added, removed)
                    fresh = record.iri
                item = ItemRecord(
                    iri=persist.item_iri(m.state.next_item),
                    cls=record.iri,
                    complexity=signature.complexity,
                    created=now,
                    last_accessed=now,
                )
                m.state.next_item += 1
                m.items.add(item)
                persist.write_item(tx, item, scene, relations, episode)
                self.view.rescore(tx, {record.iri}, {fresh} if fresh else set())
                if fresh is not None:
                    persist.write_class(tx, record, stored=m.graph.stored_restrictions)
                history.stored(tx, m, record, item.iri, best, now, fresh)
                self._bump_update(tx)
                # the result's parents and scores read the model as this update leaves it,
                # which it is by then: taken while the store writes
                taken: list[tuple[tuple[NamedNode, ...], ItemScores]] = []
                self.transactions.alongside(
                    lambda: taken.append(
                        (
                            tuple(sorted(m.graph.parents[record.iri], key=_IRI_TEXT)),
                            self.view.class_scores(record),
                        )
                    )
                )
            ((placed_under, scores),) = taken
            result = StoreResult(
                scene_item=item.iri,
                stored_as=record.iri,
                learned=fresh is not None,
                recognised=tuple(recognised),
                confidence=confidence,
                signature=signature,
                relations=tuple(relations),
                parents=placed_under,
                scores=scores,
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
        with self.transactions.write() as tx:
            now = self._now()
            m = self.loaded.model
            added: set[tuple[NamedNode, NamedNode]] = set()
            removed: set[tuple[NamedNode, NamedNode]] = set()
            fresh: list[ClassRecord] = []
            for signature in signatures:
                if not signature or m.graph.index.with_signature(signature) is not None:
                    continue
                record = _new_class(m, signature, now)
                parents, children, cut = m.graph.add_class(record)
                for edge in cut:  # an edge added earlier in this batch is simply not written
                    if edge in added:
                        added.discard(edge)
                    else:
                        removed.add(edge)
                added |= {(record.iri, p) for p in parents} | {(c, record.iri) for c in children}
                fresh.append(record)
            persist.write_edges(tx, added, removed)
            new = {r.iri for r in fresh}
            self.view.rescore(tx, new, new)
            for record in fresh:
                persist.write_class(tx, record, stored=m.graph.stored_restrictions)
            history.record_all(tx, m, fresh, "learned", now)
            m.state.updates_since_sleep += len(fresh)
            persist.write_state(tx, m)
        return [r.iri for r in fresh]

    def recognise(self, primitives: Sequence[Primitive]) -> list[Recognition]:
        """The learned classes the scene belongs to, by confidence; writes nothing."""
        signature = self._encode(primitives)[2]
        with self.loaded.lock:
            return recognitions_in(self.loaded.model, signature)

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
        with self.transactions.write() as tx:
            now = self._now()
            m = self.loaded.model
            exact = m.graph.index.with_signature(signature)
            generalisations = [
                r for r in recognitions_in(self.loaded.model, signature) if r.cls != exact
            ]
            d = signature.complexity

            def spec_key(match: Match) -> tuple[float, int, str]:
                return (-match.similarity, -m.graph.classes[match.cls].store_count, match.cls.value)

            specialisations = sorted(
                (
                    Match(c, d / m.graph.classes[c].signature.complexity)
                    for c in m.graph.index.dominating(signature)
                    if c != exact
                ),
                key=spec_key,
            )
            similar = tuple(Match(c, s) for c, s in m.graph.index.most_similar(signature, limit))
            recalled = exact or (
                specialisations[0].cls
                if specialisations
                else generalisations[0].cls
                if generalisations
                else None
            )
            branch: tuple[NamedNode, ...] = ()
            if recalled is not None:
                members = {recalled} | m.graph.ancestors(recalled)
                branch = tuple(
                    sorted(members, key=lambda c: m.graph.classes[c].signature.complexity)
                )
                for cls in members:
                    self._count_use(tx, m.graph.classes[cls], now, retrieved=True)
                self.view.rescore(tx, members)
                history.record(tx, m, m.graph.classes[recalled], "retrieved", now)
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
        m = self.loaded.model
        activation = dict(seeds)
        frontier = dict(seeds)
        for _ in range(hops):
            following: dict[NamedNode, float] = {}
            for cls, value in frontier.items():
                for neighbour in m.graph.parents[cls] | m.graph.children[cls]:
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
        forgotten scene once. One transaction, handed to disk in the background once it has
        committed (the updates after it then cost what they cost in a settled store).
        """
        started = time.perf_counter()
        with collector_paused(), self.transactions.write(large=True) as tx:
            now = self._now()
            m = self.loaded.model
            rescored = len(m.graph.classes)
            plan = forgetting.plan(m, self.policy, now)
            class_levels, item_levels = plan.class_levels, plan.item_levels
            doomed_classes = plan.doomed_classes
            # one truth: what is forgotten goes to the trash with this pass's level and WEAK
            # count (the count that forgot it), as the history and /explain give them
            leaving = forgetting.leaving_items(m, doomed_classes, plan.doomed_items)
            for cls in doomed_classes:
                self._set_level(tx, m.graph.classes[cls], WEAK, plan.weak_counts[cls], MEMORY)
            for iri in leaving:
                self._set_level(
                    tx, m.items.records[iri], item_levels[iri], plan.item_weak[iri], EPISODIC
                )
            history.forgetting(tx, m, doomed_classes, leaving, plan.zetas, now)
            forgotten_items = forgetting.move_to_trash(
                tx, m, self.transactions.reader, doomed_classes, plan.doomed_items, now
            )
            # the graph changed: ζ of the forgotten classes' neighbours too
            zetas = m.scores.zetas() if doomed_classes else plan.zetas
            history.sleep_levels(tx, m, class_levels, zetas, now)
            history.checkpoint(tx, m, self.store, now)
            # a class's ζ and level are the view's: only the WEAK counts that changed are written
            for cls, record in m.graph.classes.items():
                self._set_level(tx, record, class_levels[cls], plan.weak_counts[cls], MEMORY)
            for iri, item in m.items.records.items():
                self._set_level(tx, item, item_levels[iri], plan.item_weak[iri], EPISODIC)
            m.scores.scored = zetas
            m.state.last_sleep_at = now
            m.state.updates_since_sleep = 0
            m.state.sleep_passes += 1
            persist.write_levels(tx, m)
            persist.write_state(tx, m)
        report = SleepReport(
            at=now,
            rescored=rescored,
            levels={c: class_levels[c] for c in m.graph.classes},
            item_levels={i: item_levels[i] for i in m.items.records},
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
        m = self.loaded.model
        return [i for i, t in m.trash.items.items() if t.cls == cls]

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
        with self.loaded.lock:
            m, p = self.loaded.model, self.policy
            if m.state.updates_since_sleep == 0:
                return None
            due = m.state.updates_since_sleep >= p.sleepEveryUpdates
            since = m.state.last_sleep_at or min(
                (r.created for r in m.graph.classes.values()), default=None
            )
            if not due and since is not None:
                due = (self._now() - since).total_seconds() >= p.sleepIntervalSeconds
            return self.sleep() if due else None

    # Several operations, one transaction -------------------------------------------------------

    def commit(
        self,
        operations: Sequence[Operation],
        alongside: Transaction | None = None,
        *,
        sleep_if_due: bool = False,
    ) -> list[OperationResult]:
        """Run ``operations`` in order, each seeing the ones before it, and write their changes
        and ``alongside`` (the caller's own writes, to graphs other than the memory's) in one
        store transaction; return each operation's result, in order.

        With ``sleep_if_due``, each stored scene and each retrieval is followed by the periodic
        sleep pass when one is due (:meth:`maybe_sleep`), in the same transaction. The memory's
        lock is held from the first operation to the commit. If an operation fails, nothing is
        written, the model is rebuilt from the store and a settable clock is put back; the
        error is raised as :class:`~reasoners.errors.OperationFailedError`, which names the
        operation. If the store refuses the transaction, its error is raised as it is.

        >>> from kg import Store
        >>> from reasoners.operations import Retrieve, StoreScene
        >>> from kg.primitive import Primitive
        >>> memory = SceneMemory(Store())
        >>> scene = [Primitive("ball", "Sphere", centre=(.3, .3, .3), radius=.05),
        ...          Primitive("table", "Plane", centre=(.3, .1, .1), axis=(0, 0, 1))]
        >>> stored, retrieved = memory.commit(
        ...     [StoreScene(scene), Retrieve([("Sphere", "isAboveOf", "Plane")])])
        >>> retrieved.recalled == stored.stored_as
        True
        """
        with self.transactions.batch() as writes:
            results = []
            for index, operation in enumerate(operations):
                try:
                    results.append(self._run(operation))
                    if sleep_if_due and isinstance(operation, StoreScene | Retrieve):
                        self.maybe_sleep()
                except Exception as error:
                    raise OperationFailedError(index, error) from error
            with self.store.transaction() as tx:
                writes.copy_into(tx)
                if alongside is not None:
                    tx.cleared.extend(alongside.cleared)
                    tx.patterns.extend(alongside.patterns)
                    tx.deletes.extend(alongside.deletes)
                    tx.inserts.extend(alongside.inserts)
        return results

    def _run(self, operation: Operation) -> OperationResult:
        match operation:
            case StoreScene(primitives, episode):
                return self.store_scene(primitives, episode=episode)
            case Retrieve(cue, spread):
                return self.retrieve(cue, spread=spread)
            case Sleep():
                return self.sleep()
            case Pin(iri, pinned):
                self.pin(iri, pinned)
                return None
            case Restore(iri):
                return self.restore(iri)
            case SetClock(when):
                self._settable_clock().set(when)
                return self._clock()
            case AdvanceClock(seconds):
                self._settable_clock().advance(seconds)
                return self._clock()
        raise TypeError(f"operation: got {operation!r}, expected a reasoners.operations value")

    def _settable_clock(self) -> SettableClock:
        if not isinstance(self._clock, SettableClock):
            raise TypeError("clock: the memory's clock is the real one; it cannot be set")
        return self._clock

    # Pin, restore, read ------------------------------------------------------------------------

    def pin(self, iri: NamedNode, pinned: bool = True) -> None:
        """Protect a class or experienced scene from forgetting (or lift the protection).

        Raises :class:`~reasoners.errors.UnknownItemError` for an IRI that is not live."""
        with self.transactions.write() as tx:
            m = self.loaded.model
            record: ClassRecord | ItemRecord
            if iri in m.graph.classes:
                record, graph = m.graph.classes[iri], MEMORY
            elif iri in m.items.records:
                record, graph = m.items.records[iri], EPISODIC
            else:
                raise unknown_item(m, iri)
            if record.pinned != pinned:
                persist.set_value(tx, iri, PINNED, Literal(record.pinned), Literal(pinned), graph)
                record.pinned = pinned
                history.record(
                    tx, self.loaded.model, record, "pinned" if pinned else "unpinned", self._now()
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
        with self.transactions.write() as tx:
            m = self.loaded.model
            if iri in m.trash.classes:
                restored = self._restore_class(tx, iri)
            elif iri in m.trash.items:
                trashed = m.trash.items[iri]
                if trashed.cls not in m.graph.classes:
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
        m = self.loaded.model
        trashed = m.trash.classes[cls]
        rival = m.graph.index.with_signature(trashed.signature)
        if rival is not None:
            raise RestoreConflictError(
                f"iri: {cls.value} has the same signature as the live class {rival.value}; "
                "nothing restored"
            )
        values = {}
        for quad in list(self.transactions.reader.quads(cls, None, None, TRASH)):
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
        del m.trash.classes[cls]
        parents, children, removed = m.graph.add_class(record)
        added = {(cls, p) for p in parents} | {(c, cls) for c in children}
        persist.write_edges(tx, added, removed)
        # every experienced scene of the class in the trash: those forgotten with it, and those
        # forgotten alone before (the class's memory comes back whole)
        items = sorted(self._trashed_with(cls), key=str)
        self._restore_items(tx, items)
        self.view.rescore(tx, set(), {cls})
        persist.write_class(tx, record, stored=m.graph.stored_restrictions)
        history.record(tx, self.loaded.model, record, "restored", self._now())
        return (cls, *items)

    def _restore_items(self, tx: Transaction, items: Sequence[NamedNode]) -> None:
        m = self.loaded.model
        for item in items:
            trashed = m.trash.items.pop(item)
            own = list(self.transactions.reader.quads(item, None, None, TRASH))
            values = {q.predicate: q.object for q in own}
            persist.move(
                tx, self.transactions.reader, [item], TRASH, EPISODIC, follow=HAS_PRIMITIVE
            )
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
            m.items.add(record)
            history.record(tx, self.loaded.model, record, "restored", self._now())


def _settle_view_of(transactions: "weakref.ref[Transactions]") -> Callable[[], None]:
    """The store's read barrier for a memory: one that does not keep it alive."""

    def settle() -> None:
        if (live := transactions()) is not None:
            live.settle_view()

    return settle


def _new_class(model: MemoryModel, signature: Signature, now: dt.datetime) -> ClassRecord:
    """A class learned now from ``signature``, stored once, under the model's next number."""
    record = ClassRecord(
        iri=persist.class_iri(model.state.next_class),
        signature=signature,
        store_count=1,
        retrieve_count=0,
        score=0.0,
        created=now,
        last_accessed=now,
    )
    model.state.next_class += 1
    return record
