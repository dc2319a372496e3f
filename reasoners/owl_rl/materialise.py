"""REASON for one reference: materialise the closure into its inferred graph, once, atomically.

The reasoner keeps, per store and pair of graphs, the engine of the last run (every fact of the
closure, indexed) and the asserted triples it saw. A repeat call learns what changed in the
asserted graph, from the caller (``changes=``: the directive layer knows what it wrote; the
reasoner then only looks up the listed subjects) or by reading the graph as N-Triples and
comparing it with what it saw (a scan of the graph), and

- if triples were only added (and no SWRL rule changed), feeds the new ones to the engine, which
  derives only their consequences (semi-naive), and writes only the new inferred triples;
- if instance triples were retracted (listed, recorded, or found by reading the graph),
  re-derives only the region of the closure they touch (:mod:`.retract`: the individuals
  linked to them) and writes the difference;
- otherwise (a retraction of schema or SWRL triples, equality in the closure, a changed SWRL
  rule, or no state yet) recomputes the closure from scratch, then writes only the difference
  with what the inferred graph holds.

Every write is all or nothing. A small one is a transaction; a closure of thousands of triples
written into an empty inferred graph (the first REASON of a reference: about 100k triples at
50k asserted) goes through :meth:`kg.Store.fill_graph`, Oxigraph's bulk loader behind a crash
marker, which on disk takes about half a transaction's time (0.9 s against 1.8 s at 50k).

OWL 2 RL has no cheap retraction in general (a triple may be derived several ways, and the
schema reaches everything), hence the recomputation when the region argument does not apply; it
costs what the first REASON costs. The inferred graph belongs to the reasoner: a writer that
changes it otherwise must call :func:`forget` so that the next call starts afresh.

>>> from kg import Store
>>> from pyoxigraph import NamedNode
>>> from ontologies.vocab import RDF_TYPE, RDFS_SUBCLASSOF, reference_graph
>>> store = Store()
>>> a, i = reference_graph("doc"), reference_graph("doc", inferred=True)
>>> ex = "http://example.org/"
>>> with store.transaction() as tx:
...     tx.insert(NamedNode(ex + "Cube"), RDFS_SUBCLASSOF, NamedNode(ex + "Box"), a)
...     tx.insert(NamedNode(ex + "c1"), RDF_TYPE, NamedNode(ex + "Cube"), a)
>>> report = materialise(store, asserted=a, inferred=i)
>>> report.incremental, report.consistent
(False, True)
>>> [str(q.object) for q in store.quads(NamedNode(ex + "c1"), RDF_TYPE, None, i)]
['<http://example.org/Box>']
>>> with store.transaction() as tx:
...     tx.insert(NamedNode(ex + "c2"), RDF_TYPE, NamedNode(ex + "Cube"), a)
>>> report = materialise(store, asserted=a, inferred=i)
>>> report.incremental, report.added
(True, 1)
"""

import itertools
import logging
import threading
import time
import weakref
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field

from pyoxigraph import Literal, NamedNode, Quad

from kg import Store
from ontologies.vocab import SWRL_NS
from reasoners.collector import collector_paused
from reasoners.owl_rl._terms import HAS_KEY, to_term
from reasoners.owl_rl.consistency import Clash, clashes
from reasoners.owl_rl.engine import AXIOMS, Engine, Fact
from reasoners.owl_rl.errors import UnknownReasonerError
from reasoners.owl_rl.keys import add_key_rules
from reasoners.owl_rl.retract import Retraction, inferred_delta, retract
from reasoners.owl_rl.swrl import SwrlRunner, parse_rules

__all__ = [
    "REASONER_NAMES",
    "AssertedChanges",
    "ConsistencyReport",
    "ReasonReport",
    "forget",
    "is_consistent",
    "materialise",
    "record",
]

log = logging.getLogger(__name__)

AddedTriple = tuple[NamedNode, NamedNode, NamedNode | Literal]


@dataclass(frozen=True)
class AssertedChanges:
    """What the caller asserted and retracted in a reference since its previous REASON.

    Only subjects and predicates matter for additions (the reasoner reads their stored values),
    so literals may be given in any lexical form. Any retraction means a recomputation.
    """

    added: Sequence[AddedTriple] = ()
    removed: Sequence[AddedTriple] = ()


REASONER_NAMES = frozenset({"owl2rl", "pellet", "hermit", "fact", "snorocket", ""})
"""Accepted reasoner names, compared case-insensitively: ARMOR's names all mean this engine."""


@dataclass(frozen=True)
class ConsistencyReport:
    """Whether the closure violates an OWL 2 RL inconsistency rule, and which ones."""

    consistent: bool
    clashes: tuple[Clash, ...] = ()


@dataclass(frozen=True)
class ReasonReport:
    """What one REASON did to the inferred graph.

    ``added`` / ``removed``: triples written to / deleted from it; ``duration_s``: wall time of
    the call; ``incremental``: True when only the consequences of new triples were derived
    (also for a call that found nothing changed); ``consistent`` and ``clashes``: the OWL 2 RL
    inconsistency rules on the new closure; ``inferred_total``: triples the graph now holds.
    """

    added: int
    removed: int
    duration_s: float
    incremental: bool
    consistent: bool
    clashes: tuple[Clash, ...] = ()
    inferred_total: int = 0
    scoped: bool = False
    """A retraction re-derived within the part of the closure it touches (:mod:`.retract`)."""


@dataclass
class _State:
    engine: Engine
    asserted: set[Fact]
    asserted_dump: bytes | None  # the asserted graph as last read, if still current
    inferred_count: int
    generation: int
    consistency: ConsistencyReport
    terms: dict[str, NamedNode | Literal]
    journal: list[AddedTriple] = field(default_factory=list)
    """Triples committed to the asserted graph without a REASON since (see :func:`record`)."""
    journal_removed: list[AddedTriple] = field(default_factory=list)
    """Triples retracted from the asserted graph without a REASON since (see :func:`record`)."""
    pending: bool = False
    """True while the state holds a writer's uncommitted changes (see :mod:`.pending`)."""


@dataclass
class _Slot:
    """The reasoner's memory of one (asserted, inferred) pair, and the lock serialising it."""

    lock: threading.Lock = field(default_factory=threading.Lock)
    state: _State | None = None


_slots: "weakref.WeakKeyDictionary[Store, dict[tuple[str, str], _Slot]]" = (
    weakref.WeakKeyDictionary()
)
_slots_lock = threading.Lock()
_INCREMENTAL_LIMIT = 0.25
"""Above this share of new asserted triples (and 1,000) a recomputation costs no more."""
_BULK_MIN = 5_000
"""From this many triples, a closure written into an empty inferred graph is bulk loaded."""
_STREAM_MIN = 5_000
"""From this many asserted triples, the first REASON writes its closure while deriving it."""
_STREAM_STEP = 20_000
"""Instance facts the engine processes between two pieces handed to the bulk loader."""


def _slot(store: Store, asserted: NamedNode, inferred: NamedNode) -> _Slot:
    """The state kept for a pair of graphs; ``TypeError`` for a graph that is not a NamedNode,
    ``ValueError`` if the two are one graph."""
    _check_graph("asserted", asserted)
    _check_graph("inferred", inferred)
    if asserted == inferred:
        raise ValueError(f"inferred: got {inferred}, expected a graph other than asserted")
    with _slots_lock:
        return _slots.setdefault(store, {}).setdefault(_key(asserted, inferred), _Slot())


def _check_reasoner(reasoner: str) -> str:
    if not isinstance(reasoner, str) or reasoner.strip().lower() not in REASONER_NAMES:
        raise UnknownReasonerError(
            f"reasoner: got {reasoner!r}, expected one of OWL2RL, PELLET, HERMIT, FACT, "
            "SNOROCKET (any case; all run the OWL 2 RL engine)"
        )
    return "owl2rl"


def _check_graph(name: str, graph: object) -> NamedNode:
    if not isinstance(graph, NamedNode):
        raise TypeError(f"{name}: got {graph!r}, expected a NamedNode")
    return graph


def _key(asserted: NamedNode, inferred: NamedNode) -> tuple[str, str]:
    return asserted.value, inferred.value


def _facts(data: bytes) -> list[Fact]:
    """The triples of an N-Triples document as facts (subjects and predicates hold no spaces)."""
    facts = []
    for line in data.decode().split("\n"):
        if line:
            s, p, rest = line.split(" ", 2)
            facts.append((s, p, rest[:-2]))
    return facts


def _engine(facts: list[Fact]) -> Engine:
    """An engine holding ``facts``, the axioms and the SWRL rules among the facts, not yet run."""
    engine = Engine()
    engine.add_all(facts)
    engine.add_all(AXIOMS)
    rules = parse_rules(engine)
    if rules:
        engine.fact_hooks.append(SwrlRunner(rules))
    add_key_rules(engine)
    return engine


def _closure(facts: list[Fact]) -> Engine:
    engine = _engine(facts)
    engine.run()
    engine.take_log()
    return engine


def closure(triples: Iterable[Fact]) -> tuple[set[Fact], ConsistencyReport]:
    """Every fact entailed by ``triples`` (N-Triples terms), literal subjects and the axioms
    included, and the consistency report, computed in memory: no store, no canonicalisation.

    What conformance tests compare (a conclusion graph may type a literal). Raises
    :class:`SwrlRuleError` for a SWRL rule the engine cannot run.

    >>> facts, report = closure([("<a>", "<http://www.w3.org/2002/07/owl#differentFrom>", "<a>")])
    >>> report.consistent, report.clashes[0].rule
    (False, 'eq-diff1')
    """
    engine = _closure(list(triples))
    return set(engine.facts()), _report_consistency(engine)


def _outputs(engine: Engine, asserted: set[Fact]) -> set[Fact]:
    return set(_stream_outputs(engine, asserted))


def _stream_outputs(engine: Engine, asserted: set[Fact]) -> Iterator[Fact]:
    """The closure's facts that belong in the inferred graph (no literal subject, not asserted)."""
    for p, index in engine.sp.items():
        for s, objects in index.items():
            if s[0] != '"':
                for o in objects:
                    if (s, p, o) not in asserted:
                        yield s, p, o


def _touches_swrl(facts: list[Fact]) -> bool:
    """Does a fact belong to a rule run as a fact hook (SWRL, ``owl:hasKey``)? Those are
    attached when the engine is built, so such a change needs a full run."""
    prefix = f"<{SWRL_NS}"
    return any(f[1].startswith(prefix) or f[2].startswith(prefix) or f[1] == HAS_KEY for f in facts)


def _report_consistency(engine: Engine) -> ConsistencyReport:
    found = tuple(clashes(engine))
    return ConsistencyReport(consistent=not found, clashes=found)


def materialise(
    store: Store,
    *,
    asserted: NamedNode,
    inferred: NamedNode,
    reasoner: str = "owl2rl",
    changes: AssertedChanges | None = None,
) -> ReasonReport:
    """Write the OWL 2 RL (+ SWRL) closure of graph ``asserted`` into graph ``inferred``.

    ``inferred`` ends up holding exactly the entailed triples that are not in ``asserted``
    (literal-subject triples, which RDF cannot store, and ``x owl:sameAs x`` excepted), written
    all or nothing (one transaction, or one :meth:`kg.Store.fill_graph` into an empty graph):
    if anything fails, ``inferred`` is left as it was.

    ``changes`` (optional) says what was asserted and retracted in ``asserted`` since the
    previous call for this pair of graphs, in any number of transactions (the directive layer
    knows: it wrote them), less what was passed to :func:`record` meanwhile. It spares reading
    the whole asserted graph; it must then be complete. Without it the reasoner reads the graph
    and compares it with what it saw last time.

    Raises :class:`UnknownReasonerError` for a reasoner name that is not an alias of this
    engine, :class:`SwrlRuleError` for a SWRL rule it cannot run, ``TypeError`` for a graph
    that is not a NamedNode.
    """
    _check_reasoner(reasoner)
    slot = _slot(store, asserted, inferred)
    with slot.lock, collector_paused():
        try:
            return _materialise(store, asserted, inferred, slot, changes)
        except BaseException:
            slot.state = None  # the engine may be ahead of the store: start afresh next time
            raise


def _materialise(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    slot: _Slot,
    changes: AssertedChanges | None,
) -> ReasonReport:
    start = time.perf_counter()
    state = slot.state
    if state is not None and state.pending:  # another writer's uncommitted work: not the store's
        log.warning("REASON %s: dropping an uncommitted writer's reasoner state", asserted)
        state = slot.state = None
    generation = store.generation
    if (
        state is not None
        and state.generation == generation
        and not (state.journal or state.journal_removed)
    ):
        return _report(state, 0, 0, start, incremental=True)
    data: bytes | None = None
    given: list[AddedTriple] | None = None  # the caller's complete list of changed triples
    if state is not None:
        new_facts: list[Fact] | None
        journal, state.journal = state.journal, []
        journal_removed, state.journal_removed = state.journal_removed, []
        if changes is not None:
            given = [*journal, *journal_removed, *changes.added, *changes.removed]
        if changes is not None and not (changes.removed or journal_removed):
            new_facts = _added_facts(store, asserted, state, [*journal, *changes.added])
        elif changes is not None:
            new_facts = None  # a retraction: recomputed below from the caller's list
        else:
            data = store.graph_ntriples(asserted)
            new_facts = _new_facts(state, data)
            if new_facts is None:  # a retraction found by reading: re-derived in its region?
                scoped = _retract_read(store, asserted, inferred, state, data, generation, start)
                if scoped is not None:
                    return scoped
        if new_facts is not None:
            limit = max(_INCREMENTAL_LIMIT * len(state.asserted), 1_000)
            if not _touches_swrl(new_facts) and len(new_facts) <= limit:
                state.asserted_dump = data
                return _incremental(store, inferred, state, new_facts, generation, start)
    if state is not None and given is not None:  # a listed retraction
        scoped = _retract_listed(store, asserted, inferred, state, given, generation, start)
        if scoped is not None:
            return scoped
    previous = state if state is not None and not state.pending else None
    slot.state = None
    if data is None and previous is not None and given is not None:
        # the asserted graph is the one reasoned last time, with the caller's changes applied:
        # no need to read all of it again
        facts = list(_asserted_after(store, asserted, previous, given))
    else:
        if data is None:
            data = store.graph_ntriples(asserted)
        facts = _facts(data)
    asserted_facts = set(facts)
    terms: dict[str, NamedNode | Literal] = previous.terms if previous is not None else {}
    to_remove: set[Fact] | list[Fact] = []
    streamed = (
        previous is None and len(facts) >= _STREAM_MIN and not any(store.quads(graph=inferred))
    )
    if streamed:  # the first REASON of a large reference: the closure written as derived
        engine = _engine(facts)
        added, committed = _fill_while_reasoning(store, inferred, engine, asserted_facts)
        count = added
    else:
        engine = _closure(facts)
        if previous is not None:  # the inferred graph holds the last closure's output
            wanted = _outputs(engine, asserted_facts)
            before, was_asserted = previous.engine, previous.asserted
            to_remove = [f for f in _stream_outputs(before, was_asserted) if f not in wanted]
            to_add = [f for f in wanted if f not in before or f in was_asserted]
            previous = None  # its engine can go
            added, committed = _write(store, inferred, to_add, to_remove, terms)
            count = len(wanted)
        elif current := set(_facts(store.graph_ntriples(inferred))):
            wanted = _outputs(engine, asserted_facts)
            to_remove = current - wanted
            added, committed = _write(store, inferred, wanted - current, to_remove, terms)
            count = len(wanted)
        else:  # a small first REASON: the closure goes out as text, no set of it
            added, committed = _fill(store, inferred, engine, asserted_facts, terms)
            count = added
    state = _State(
        engine,
        asserted_facts,
        data,
        count,
        _generation_after(store, generation, committed),
        _report_consistency(engine),
        terms,
    )
    slot.state = state
    report = _report(state, added, len(to_remove), start, incremental=False)
    log.info(
        "REASON %s: full, +%d -%d in %.3f s",
        asserted,
        report.added,
        report.removed,
        report.duration_s,
    )
    return report


def _new_facts(state: _State, data: bytes) -> list[Fact] | None:
    """The triples added to the asserted graph since ``state``; None if some were removed.

    Compares N-Triples lines (bytes) with the previous read when there is one: cheaper than
    parsing the whole graph again.
    """
    if state.asserted_dump is not None:
        if data == state.asserted_dump:
            return []
        before, now = set(state.asserted_dump.split(b"\n")), set(data.split(b"\n"))
        if not before <= now:
            return None
        return _facts(b"\n".join(now - before))
    graph = set(_facts(data))
    return list(graph - state.asserted) if state.asserted <= graph else None


def _added_facts(
    store: Store, asserted: NamedNode, state: _State, added: Iterable[AddedTriple]
) -> list[Fact]:
    """The asserted graph's new triples, as stored (canonical literals), from the caller's list."""
    new_facts: set[Fact] = set()
    for subject, predicate, _ in added:
        _check_graph("changes.added subject", subject)
        _check_graph("changes.added predicate", predicate)
        for quad in store.quads(subject, predicate, None, asserted):
            fact = (str(quad.subject), str(quad.predicate), str(quad.object))
            if fact not in state.asserted:
                new_facts.add(fact)
    return list(new_facts)


def _asserted_after(
    store: Store, asserted: NamedNode, state: _State, changed: Iterable[AddedTriple]
) -> set[Fact]:
    """The asserted graph as ``state`` saw it, with the stored values of every subject and
    predicate in ``changed`` read again (what was retracted goes, what was added comes)."""
    facts = set(state.asserted)
    engine = state.engine
    for subject, predicate in {(s, p) for s, p, _ in changed}:
        _check_graph("changes subject", subject)
        _check_graph("changes predicate", predicate)
        s, p = str(subject), str(predicate)
        for o in engine.objects(s, p):
            facts.discard((s, p, o))
        for quad in store.quads(subject, predicate, None, asserted):
            facts.add((s, p, str(quad.object)))
    return facts


def _retract_region(state: _State, removed: set[Fact], added: set[Fact]) -> Retraction | None:
    """Apply a change to ``state``'s asserted facts and re-derive its region of the closure
    (:func:`.retract.retract`); None, with the state as it was, where that does not apply."""
    limit = int(max(_INCREMENTAL_LIMIT * len(state.asserted), 1_000))
    if len(added) > limit:
        return None
    facts = state.asserted
    facts.difference_update(removed)
    facts.update(added)
    change = retract(state.engine, facts, removed=list(removed), added=list(added), limit=limit)
    if change is None:
        facts.difference_update(added)
        facts.update(removed)
    return change


def _retract_listed(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    state: _State,
    given: list[AddedTriple],
    generation: int,
    start: float,
) -> ReasonReport | None:
    """Re-derive only the region of the closure that the listed retractions touch (see
    :mod:`.retract`) and write the difference; None (the state untouched) if that does not
    apply, and the caller recomputes the whole closure."""
    removed, added = _listed_difference(store, asserted, state, given)
    return _retract_facts(store, asserted, inferred, state, removed, added, generation, start)


def _retract_read(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    state: _State,
    data: bytes,
    generation: int,
    start: float,
) -> ReasonReport | None:
    """As :func:`_retract_listed`, the changes found by comparing the asserted graph as read
    (``data``) with what ``state`` saw."""
    if state.asserted_dump is not None:
        before, now = set(state.asserted_dump.split(b"\n")), set(data.split(b"\n"))
        removed = set(_facts(b"\n".join(before - now)))
        added = set(_facts(b"\n".join(now - before)))
    else:
        graph = set(_facts(data))
        removed, added = state.asserted - graph, graph - state.asserted
    report = _retract_facts(store, asserted, inferred, state, removed, added, generation, start)
    if report is not None:
        state.asserted_dump = data
    return report


def _retract_facts(
    store: Store,
    asserted: NamedNode,
    inferred: NamedNode,
    state: _State,
    removed: set[Fact],
    added: set[Fact],
    generation: int,
    start: float,
) -> ReasonReport | None:
    change = _retract_region(state, removed, added)
    if change is None:
        return None
    facts, engine = state.asserted, state.engine
    to_add, to_remove = inferred_delta(engine, facts, change, removed=removed, added=added)
    written, committed = _write(store, inferred, to_add, to_remove, state.terms)
    state.inferred_count += written - len(to_remove)
    state.asserted_dump = None
    state.generation = _generation_after(store, generation, committed)
    state.consistency = _report_consistency(engine)
    report = _report(state, written, len(to_remove), start, incremental=False, scoped=True)
    log.info(
        "REASON %s: retraction re-derived in a region of %d terms, +%d -%d in %.4f s",
        asserted,
        change.region,
        report.added,
        report.removed,
        report.duration_s,
    )
    return report


def asserted_objects(state: _State, s: str, p: str) -> set[str]:
    """The objects of ``s p`` that ``state`` holds as asserted."""
    objects = {o for o in state.engine.objects(s, p) if (s, p, o) in state.asserted}
    if (s, p, s) in state.asserted:  # x owl:sameAs x: asserted, never in the engine
        objects.add(s)
    return objects


def _listed_difference(
    store: Store, asserted: NamedNode, state: _State, changed: Iterable[AddedTriple]
) -> tuple[set[Fact], set[Fact]]:
    """(retracted, added) asserted triples: the stored values of every subject and predicate
    in ``changed`` against those ``state`` saw."""
    removed: set[Fact] = set()
    added: set[Fact] = set()
    for subject, predicate in {(s, p) for s, p, _ in changed}:
        _check_graph("changes subject", subject)
        _check_graph("changes predicate", predicate)
        s, p = str(subject), str(predicate)
        before = asserted_objects(state, s, p)
        now = {str(quad.object) for quad in store.quads(subject, predicate, None, asserted)}
        removed.update((s, p, o) for o in before - now)
        added.update((s, p, o) for o in now - before)
    return removed, added


def _generation_after(store: Store, before: int, committed: bool) -> int:
    """The store generation the state matches, or -1 if another writer got in between."""
    expected = before + 1 if committed else before
    return expected if store.generation == expected else -1


def _report(
    state: _State,
    added: int,
    removed: int,
    start: float,
    *,
    incremental: bool,
    scoped: bool = False,
) -> ReasonReport:
    return ReasonReport(
        added=added,
        removed=removed,
        duration_s=time.perf_counter() - start,
        incremental=incremental,
        consistent=state.consistency.consistent,
        clashes=state.consistency.clashes,
        inferred_total=state.inferred_count,
        scoped=scoped,
    )


def _advance(state: _State, new_facts: list[Fact]) -> tuple[list[Fact], list[Fact]]:
    """Run ``state``'s engine on ``new_facts`` and count them asserted: (the facts the inferred
    graph gains, the facts it loses: those newly asserted that it held). Shared by the
    incremental REASON here and its prepared form (:mod:`reasoners.owl_rl.pending`)."""
    engine = state.engine
    # a newly asserted triple that was inferred leaves the inferred graph
    to_remove = [f for f in new_facts if f in engine and f not in state.asserted]
    engine.add_all(new_facts)
    engine.run()
    derived = engine.take_log()
    state.asserted.update(new_facts)
    to_add = [f for f in derived if f[0][0] != '"' and f not in state.asserted]
    return to_add, to_remove


def _incremental(
    store: Store,
    inferred: NamedNode,
    state: _State,
    new_facts: list[Fact],
    generation: int,
    start: float,
) -> ReasonReport:
    to_add, to_remove = _advance(state, new_facts)
    added, committed = _write(store, inferred, to_add, to_remove, state.terms)
    state.inferred_count += added - len(to_remove)
    state.generation = _generation_after(store, generation, committed)
    state.consistency = _report_consistency(state.engine)
    report = _report(state, added, len(to_remove), start, incremental=True)
    log.info(
        "REASON: incremental, +%d -%d in %.4f s", report.added, report.removed, report.duration_s
    )
    return report


def _fill(
    store: Store,
    graph: NamedNode,
    engine: Engine,
    asserted: set[Fact],
    terms: dict[str, NamedNode | Literal],
) -> tuple[int, bool]:
    """Write the closure into the empty ``graph``: (triples added, whether it committed).

    A large closure goes through :meth:`kg.Store.fill_graph` (Oxigraph's bulk loader behind a
    crash marker: all or nothing, about twice as fast on disk as a transaction at 100k
    triples), as N-Triples text, which the engine's facts already are; a small one through a
    transaction, which costs less below :data:`_BULK_MIN` triples.
    """
    facts = list(_stream_outputs(engine, asserted))
    if len(facts) < _BULK_MIN:
        return _write(store, graph, facts, [], terms)
    store.fill_graph(graph, "".join([f"{s} {p} {o} .\n" for s, p, o in facts]).encode())
    return len(facts), True


def _fill_while_reasoning(
    store: Store, graph: NamedNode, engine: Engine, asserted: set[Fact]
) -> tuple[int, bool]:
    """Run ``engine`` to its closure while its new facts are bulk loaded into the empty
    ``graph`` (:meth:`kg.Store.fill_graph` with pieces): Oxigraph parses, sorts and writes one
    piece in its own thread while the engine derives the next, so the write costs little more
    than the reasoning. All or nothing, as :func:`_fill`. Returns (triples added, True)."""
    added = 0

    def pieces() -> Iterator[bytes]:
        nonlocal added
        for _ in itertools.chain(engine.run_stepwise(_STREAM_STEP), [None]):
            lines = [
                f"{s} {p} {o} .\n"
                for s, p, o in engine.take_log()
                if s[0] != '"' and (s, p, o) not in asserted
            ]
            added += len(lines)
            if lines:
                yield "".join(lines).encode()

    store.fill_graph(graph, pieces())
    return added, True


def _write(
    store: Store,
    graph: NamedNode,
    to_add: Iterable[Fact],
    to_remove: Iterable[Fact],
    terms: dict[str, NamedNode | Literal],
) -> tuple[int, bool]:
    """Apply the changes to ``graph`` in one transaction: (triples added, whether it committed).

    ``terms`` caches the term objects of N-Triples terms across calls (most repeat).
    """

    def term(text: str) -> NamedNode | Literal:
        found = terms.get(text)
        if found is None:
            found = terms[text] = to_term(text)
        return found

    with store.transaction() as tx:
        for s, p, o in to_remove:
            tx.delete(term(s), term(p), term(o), graph)  # type: ignore[arg-type]
        # Built directly rather than by tx.insert, which checks each term: these are IRIs and
        # literals read from the store (never blank nodes), in a graph checked by the caller.
        # At 100k triples this saves a tenth of a REASON.
        quads: list[Quad] = []
        last_s = last_p = ""
        subject: NamedNode | Literal = graph
        predicate: NamedNode | Literal = graph
        for s, p, o in to_add:  # grouped by predicate and subject when streamed from the engine
            if p is not last_p:
                predicate, last_p = term(p), p
            if s is not last_s:
                subject, last_s = term(s), s
            obj = terms.get(o) or term(o)
            quads.append(Quad(subject, predicate, obj, graph))  # type: ignore[arg-type]
        tx.inserts.extend(quads)
        committed = not tx.is_empty
    return len(quads), committed


def forget(store: Store, *, asserted: NamedNode, inferred: NamedNode) -> None:
    """Drop the reasoner's state for a pair of graphs (after writing to ``inferred`` directly)."""
    slot = _slot(store, asserted, inferred)
    with slot.lock:
        slot.state = None


def record(
    store: Store, *, asserted: NamedNode, inferred: NamedNode, changes: AssertedChanges
) -> None:
    """Note changes committed to ``asserted`` without a REASON (a buffered reasoner's writes).

    The next call with ``changes=`` (:func:`materialise`, or :func:`~.pending.prepare`) then
    derives their consequences too, so that the caller needs to pass only what it wrote since.
    Retractions are kept too: the next call re-derives the part of the closure they touch
    (:mod:`.retract`), or recomputes the closure from the kept state when that does not apply.
    More changes than an incremental run is worth drop the state: the next REASON recomputes.
    """
    slot = _slot(store, asserted, inferred)
    with slot.lock:
        state = slot.state
        if state is None or not (changes.added or changes.removed):
            return
        state.journal.extend(changes.added)
        state.journal_removed.extend(changes.removed)
        limit = max(_INCREMENTAL_LIMIT * len(state.asserted), 1_000)
        if state.pending or len(state.journal) + len(state.journal_removed) > limit:
            slot.state = None


def is_consistent(store: Store, *, asserted: NamedNode, inferred: NamedNode) -> ConsistencyReport:
    """Check the OWL 2 RL inconsistency rules on the closure of ``asserted``, naming the clashes.

    Uses the last REASON's closure when nothing was written since; otherwise computes the
    closure in memory (nothing is written).
    """
    state = _slot(store, asserted, inferred).state
    if (
        state is not None
        and state.generation == store.generation
        and not (state.pending or state.journal or state.journal_removed)
    ):
        return state.consistency
    engine = _closure(_facts(store.graph_ntriples(asserted)))
    return _report_consistency(engine)
