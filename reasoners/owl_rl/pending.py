"""REASON over a writer's uncommitted changes: the inferred graph's delta, computed, not written.

A directive list writes a reference's asserted graph and wants the inferences of those writes
committed in the same transaction. :func:`prepare` takes what the writer has not committed yet
(:class:`PendingChanges`, its whole view, and ``changes=``, what it wrote since its previous
call) and returns a :class:`Prepared`: the triples to insert into and delete from the inferred
graph, and the consistency of the new closure. Nothing is written; the writer puts the delta
into its own transaction, then calls :meth:`Prepared.confirm` once that committed, or
:meth:`Prepared.discard` if it did not.

The work is the same as :func:`~reasoners.owl_rl.materialise`'s: after additions only, the kept
engine derives just their consequences (time proportional to the change), and the delta is
relative to the writer's view so far (``replaces=False``: the previous delta of the same writer
plus this one); after a retraction of instance triples, the kept engine re-derives the region of
the closure they touch (:mod:`.retract`; the delta is again relative to the writer's view,
``incremental=False``); after another retraction, a changed SWRL rule, or with no kept state,
the closure is recomputed from the committed graph plus the pending changes, and the delta is
relative to the committed inferred graph (``replaces=True``: it replaces the writer's earlier
delta).

Between ``prepare`` and ``confirm`` the reasoner's kept state is *tentative*: a concurrent
:func:`~reasoners.owl_rl.materialise` of the same graphs drops it, ``discard`` drops it (the
next REASON recomputes), and ``confirm`` makes it the committed state. Writers of one reference
must be serialised by the caller (the directive layer holds the reference's lock).

>>> from kg import Store
>>> from pyoxigraph import NamedNode, Quad
>>> from ontologies.vocab import RDF_TYPE, RDFS_SUBCLASSOF, reference_graph
>>> from reasoners.owl_rl import materialise
>>> store, ex = Store(), "http://example.org/"
>>> a, i = reference_graph("doc"), reference_graph("doc", inferred=True)
>>> cube, box, c1 = NamedNode(ex + "Cube"), NamedNode(ex + "Box"), NamedNode(ex + "c1")
>>> new = [(cube, RDFS_SUBCLASSOF, box), (c1, RDF_TYPE, cube)]
>>> prepared = prepare(
...     store, asserted=a, inferred=i,
...     changes=AssertedChanges(added=new), pending=PendingChanges(added=new),
... )
>>> [str(q.object) for q in prepared.added if q.subject == c1]
['<http://example.org/Box>']
>>> with store.transaction() as tx:
...     tx.inserts.extend(Quad(s, p, o, a) for s, p, o in new)
...     tx.inserts.extend(prepared.added)
>>> prepared.confirm(store)
>>> materialise(store, asserted=a, inferred=i).added  # the state is the store's: nothing to do
0
"""

import logging
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from pyoxigraph import Literal, NamedNode, Quad

from kg import Store
from ontologies.vocab import RDF_NS, XSD_STRING
from reasoners.collector import collector_paused
from reasoners.owl_rl._terms import to_term
from reasoners.owl_rl.consistency import Clash
from reasoners.owl_rl.engine import Fact
from reasoners.owl_rl.materialise import (
    _INCREMENTAL_LIMIT,
    AddedTriple,
    AssertedChanges,
    _added_facts,
    _advance,
    _check_graph,
    _check_reasoner,
    _closure,
    _facts,
    _outputs,
    _report_consistency,
    _retract_region,
    _Slot,
    _slot,
    _State,
    _touches_swrl,
    asserted_objects,
)
from reasoners.owl_rl.retract import inferred_delta

__all__ = ["PendingChanges", "Prepared", "prepare"]

log = logging.getLogger(__name__)

_SCRATCH = NamedNode("urn:engram:owl-rl:canonical")
_STRING_TYPES = frozenset({XSD_STRING.value, RDF_NS + "langString"})


@dataclass(frozen=True)
class PendingChanges:
    """A writer's net uncommitted changes to the asserted graph: ``cleared`` first (the graph is
    emptied), then ``removed``, then ``added``."""

    added: Sequence[AddedTriple] = ()
    removed: Sequence[AddedTriple] = ()
    cleared: bool = False


class Prepared:
    """The inferred graph's delta for a writer's pending changes, and the new consistency.

    ``added`` / ``removed``: quads of the inferred graph to insert / delete; ``replaces``: the
    delta is relative to the committed inferred graph (it replaces an earlier delta of the same
    writer), otherwise relative to the writer's view after its previous :func:`prepare`;
    ``incremental``: only the consequences of new triples were derived.
    """

    def __init__(
        self,
        slot: _Slot,
        state: _State,
        *,
        added: list[Quad],
        removed: list[Quad],
        replaces: bool,
        incremental: bool,
        duration_s: float,
    ) -> None:
        self._slot, self._state = slot, state
        self._open = True
        self.added, self.removed = added, removed
        self.replaces, self.incremental, self.duration_s = replaces, incremental, duration_s
        self.consistent: bool = state.consistency.consistent
        self.clashes: tuple[Clash, ...] = state.consistency.clashes

    def confirm(self, store: Store) -> None:
        """The writer committed the delta (and its pending changes): keep the state as the store's.

        If another caller replaced the tentative state meanwhile, the kept state is dropped
        instead (the next REASON recomputes).
        """
        if not self._open:
            return
        self._open = False
        with self._slot.lock:
            if self._slot.state is self._state and self._state.pending:
                self._state.pending = False
                self._state.generation = store.generation
            else:
                self._slot.state = None

    def discard(self) -> None:
        """The writer did not commit: drop the tentative state; the next REASON recomputes."""
        if not self._open:
            return
        self._open = False
        with self._slot.lock:
            if self._slot.state is self._state:
                self._slot.state = None

    def _supersede(self) -> None:
        """A later :func:`prepare` of the same writer carries on from this one."""
        self._open = False


_NO_CHANGES = AssertedChanges()
_NO_PENDING = PendingChanges()


def prepare(
    store: Store,
    *,
    asserted: NamedNode,
    inferred: NamedNode,
    reasoner: str = "owl2rl",
    changes: AssertedChanges = _NO_CHANGES,
    pending: PendingChanges = _NO_PENDING,
    after: Prepared | None = None,
    recompute: bool = False,
) -> Prepared:
    """The inferred graph's delta if ``pending`` were committed to ``asserted``; nothing written.

    ``pending``: every uncommitted change of the writer to ``asserted``. ``changes``: what the
    writer asserted and retracted since ``after`` (its previous call, whose delta it already
    holds), or since it started if ``after`` is None. Both list triples as terms, in any lexical
    form. ``recompute``: ignore the kept state (the writer changed ``inferred`` itself).

    Raises :class:`UnknownReasonerError` for a reasoner name that is not an alias of this
    engine, :class:`SwrlRuleError` for a SWRL rule it cannot run, ``TypeError`` for a graph
    that is not a NamedNode; the kept state is then dropped.
    """
    _check_reasoner(reasoner)
    slot = _slot(store, asserted, inferred)
    if after is not None:
        after._supersede()
    with slot.lock, collector_paused():
        try:
            return _prepare(store, asserted, inferred, slot, changes, pending, after, recompute)
        except BaseException:
            slot.state = None
            raise


def _prepare(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    slot: _Slot,
    changes: AssertedChanges,
    pending: PendingChanges,
    after: Prepared | None,
    recompute: bool,
) -> Prepared:
    start = time.perf_counter()
    state = slot.state
    if after is not None and after._state is not state:
        state = None  # someone else's REASON replaced the writer's state: start again
    elif after is None and state is not None and state.pending:
        log.warning("REASON %s: dropping another writer's uncommitted reasoner state", asserted)
        state = None
    if recompute or (after is None and pending.cleared):
        state = None
    if state is not None and after is None and state.journal_removed:
        state = None  # retractions committed without a REASON: recomputed from the store
    if state is not None:
        journal: list[AddedTriple] = []
        if after is None:
            journal, state.journal = state.journal, []
        if changes.removed:
            scoped = _retract(store, asserted, inferred, slot, state, changes, pending, journal)
            if scoped is not None:
                return scoped
            return _recompute(store, asserted, inferred, slot, pending, start)
        new_facts = set(_added_facts(store, asserted, state, journal))
        new_facts.update(f for f in canonical(changes.added) if f not in state.asserted)
        limit = max(_INCREMENTAL_LIMIT * len(state.asserted), 1_000)
        facts = list(new_facts)
        if not _touches_swrl(facts) and len(facts) <= limit:
            return _incremental(slot, state, inferred, facts, start)
    return _recompute(store, asserted, inferred, slot, pending, start)


def _retract(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    slot: _Slot,
    state: _State,
    changes: AssertedChanges,
    pending: PendingChanges,
    journal: list[AddedTriple],
) -> Prepared | None:
    """A retraction re-derived in its region of the closure (:mod:`.retract`), the delta
    relative to the writer's view so far; None (the state untouched) if that does not apply."""
    start = time.perf_counter()
    removed, added = _view_difference(store, asserted, state, pending, changes, journal)
    change = _retract_region(state, removed, added)
    if change is None:
        return None
    facts = state.asserted
    state.pending, state.generation, state.asserted_dump = True, -1, None
    to_add, to_remove = inferred_delta(state.engine, facts, change, removed=removed, added=added)
    state.inferred_count += len(to_add) - len(to_remove)
    state.consistency = _report_consistency(state.engine)
    prepared = Prepared(
        slot,
        state,
        added=_quads(to_add, inferred, state.terms),
        removed=_quads(to_remove, inferred, state.terms),
        replaces=False,
        incremental=False,
        duration_s=time.perf_counter() - start,
    )
    log.info(
        "REASON %s (pending): retraction re-derived in a region of %d terms, +%d -%d in %.4f s",
        asserted,
        change.region,
        len(prepared.added),
        len(prepared.removed),
        prepared.duration_s,
    )
    return prepared


def _view_difference(
    store: Store,
    asserted: NamedNode,
    state: _State,
    pending: PendingChanges,
    changes: AssertedChanges,
    journal: list[AddedTriple],
) -> tuple[set[Fact], set[Fact]]:
    """(retracted, added) triples of the writer's view of ``asserted`` (the committed graph with
    ``pending`` applied) against ``state``'s, for every subject and predicate that changed."""
    pending_added: dict[tuple[str, str], set[str]] = {}
    for s, p, o in canonical(pending.added):
        pending_added.setdefault((s, p), set()).add(o)
    pending_removed: dict[tuple[str, str], set[str]] = {}
    for s, p, o in canonical(pending.removed):
        pending_removed.setdefault((s, p), set()).add(o)
    removed: set[Fact] = set()
    added: set[Fact] = set()
    changed = [*journal, *changes.added, *changes.removed]
    for subject, predicate in {(s, p) for s, p, _ in changed}:
        _check_graph("changes subject", subject)
        _check_graph("changes predicate", predicate)
        s, p = str(subject), str(predicate)
        before = asserted_objects(state, s, p)
        now: set[str] = set()
        if not pending.cleared:
            now = {str(q.object) for q in store.quads(subject, predicate, None, asserted)}
            now -= pending_removed.get((s, p), set())
        now |= pending_added.get((s, p), set())
        removed.update((s, p, o) for o in before - now)
        added.update((s, p, o) for o in now - before)
    return removed, added


def _incremental(
    slot: _Slot, state: _State, inferred: NamedNode, new_facts: list[Fact], start: float
) -> Prepared:
    state.pending, state.generation, state.asserted_dump = True, -1, None
    to_add, to_remove = _advance(state, new_facts)
    state.inferred_count += len(to_add) - len(to_remove)
    state.consistency = _report_consistency(state.engine)
    added, removed = _quads(to_add, inferred, state.terms), _quads(to_remove, inferred, state.terms)
    prepared = Prepared(
        slot,
        state,
        added=added,
        removed=removed,
        replaces=False,
        incremental=True,
        duration_s=time.perf_counter() - start,
    )
    log.info(
        "REASON (pending): incremental, +%d -%d in %.4f s",
        len(added),
        len(removed),
        prepared.duration_s,
    )
    return prepared


def _recompute(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    slot: _Slot,
    pending: PendingChanges,
    start: float,
) -> Prepared:
    slot.state = None
    facts: set[Fact] = set() if pending.cleared else set(_facts(store.graph_ntriples(asserted)))
    facts.difference_update(canonical(pending.removed))
    facts.update(canonical(pending.added))
    engine = _closure(list(facts))
    wanted = _outputs(engine, facts)
    current = set(_facts(store.graph_ntriples(inferred)))
    terms: dict[str, NamedNode | Literal] = {}
    state = _State(
        engine,
        facts,
        None,
        len(wanted),
        -1,
        _report_consistency(engine),
        terms,
        pending=True,
    )
    slot.state = state
    prepared = Prepared(
        slot,
        state,
        added=_quads(wanted - current, inferred, terms),
        removed=_quads(current - wanted, inferred, terms),
        replaces=True,
        incremental=False,
        duration_s=time.perf_counter() - start,
    )
    log.info(
        "REASON %s (pending): full, +%d -%d in %.3f s",
        asserted,
        len(prepared.added),
        len(prepared.removed),
        prepared.duration_s,
    )
    return prepared


def canonical(triples: Iterable[AddedTriple]) -> list[Fact]:
    """Triples as the store would give them back: N-Triples terms, canonical literals.

    The store keeps typed literals by value (``"01"^^xsd:integer`` reads back as ``"1"``); the
    engine must see them the same way, so literals of types other than strings go through a
    scratch store, the rest is written by pyoxigraph's own ``str``.

    >>> from pyoxigraph import Literal, NamedNode
    >>> x = NamedNode("http://example.org/x")
    >>> integer = NamedNode("http://www.w3.org/2001/XMLSchema#integer")
    >>> canonical([(x, x, Literal("01", datatype=integer))])[0][2]
    '"1"^^<http://www.w3.org/2001/XMLSchema#integer>'
    """
    facts: list[Fact] = []
    typed: list[Quad] = []
    for s, p, o in triples:
        _check_graph("changes subject", s)
        _check_graph("changes predicate", p)
        if isinstance(o, Literal) and o.datatype.value not in _STRING_TYPES:
            typed.append(Quad(s, p, o, _SCRATCH))
        else:
            facts.append((str(s), str(p), str(o)))
    if typed:
        scratch = Store()
        with scratch.transaction() as tx:
            tx.inserts.extend(typed)
        facts.extend(_facts(scratch.graph_ntriples(_SCRATCH)))
    return facts


def _quads(
    facts: Iterable[Fact], graph: NamedNode, terms: dict[str, NamedNode | Literal]
) -> list[Quad]:
    def term(text: str) -> NamedNode | Literal:
        found = terms.get(text)
        if found is None:
            found = terms[text] = to_term(text)
        return found

    return [Quad(term(s), term(p), term(o), graph) for s, p, o in facts]  # type: ignore[arg-type]
