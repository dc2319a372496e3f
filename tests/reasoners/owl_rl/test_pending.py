"""prepare(): the inferred delta of uncommitted changes equals a full REASON once committed;
record(): assertions committed without a REASON are picked up by the next incremental one."""

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import Literal, NamedNode, Quad

from kg import Store
from reasoners.owl_rl import (
    AssertedChanges,
    PendingChanges,
    Prepared,
    materialise,
    prepare,
    record,
)
from reasoners.owl_rl.materialise import _slot

from .conftest import ASSERTED, INFERRED, graph_triples
from .test_incremental import RDF, RDFS, Triple, _full, _insert, _terms, axioms, facts, statements

Terms = tuple[NamedNode, NamedNode, NamedNode | Literal]
steps = st.lists(
    st.one_of(
        st.tuples(st.just("add"), st.one_of(axioms(), facts())),
        st.tuples(st.just("remove"), st.integers(0, 50)),
    ),
    min_size=1,
    max_size=5,
)


class Writer:
    """A writer like a directive list: net changes, its inferred delta, prepare() as it goes."""

    def __init__(self, store: Store, base: list[Triple]) -> None:
        self.store = store
        self.view = list(dict.fromkeys(base))
        self.added: dict[Terms, None] = {}
        self.removed: set[Terms] = set()
        self.since_added: list[Terms] = []
        self.since_removed: list[Terms] = []
        self.inferred_added: dict[Quad, None] = {}
        self.inferred_removed: set[Quad] = set()
        self.prepared: Prepared | None = None

    def add(self, triples: list[Triple]) -> None:
        for triple in triples:
            terms = _terms(triple)
            self.removed.discard(terms)
            self.added[terms] = None
            self.since_added.append(terms)
            if triple not in self.view:
                self.view.append(triple)

    def remove(self, index: int) -> None:
        if not self.view:
            return
        triple = self.view.pop(index % len(self.view))
        terms = _terms(triple)
        self.added.pop(terms, None)
        self.removed.add(terms)  # as the directive layer does: deleting an absent triple is a no-op
        self.since_removed.append(terms)

    def reason(self) -> Prepared:
        prepared = prepare(
            self.store,
            asserted=ASSERTED,
            inferred=INFERRED,
            changes=AssertedChanges(added=self.since_added, removed=self.since_removed),
            pending=PendingChanges(added=list(self.added), removed=list(self.removed)),
            after=self.prepared,
        )
        self.since_added, self.since_removed = [], []
        if prepared.replaces:
            self.inferred_added = dict.fromkeys(prepared.added)
            self.inferred_removed = set(prepared.removed)
        else:
            for quad in prepared.removed:
                if self.inferred_added.pop(quad, 0) == 0:
                    self.inferred_removed.add(quad)
            for quad in prepared.added:
                self.inferred_removed.discard(quad)
                self.inferred_added[quad] = None
        self.prepared = prepared
        return prepared

    def commit(self) -> None:
        with self.store.transaction() as tx:
            for s, p, o in self.removed:
                tx.delete(s, p, o, ASSERTED)
            for s, p, o in self.added:
                tx.insert(s, p, o, ASSERTED)
            tx.deletes.extend(self.inferred_removed)
            tx.inserts.extend(self.inferred_added)
        assert self.prepared is not None
        self.prepared.confirm(self.store)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(base=statements, plan=steps, reason_each_step=st.booleans())
def test_committed_delta_equals_full_reason(
    base: list[Triple], plan: list[tuple[str, object]], reason_each_step: bool
) -> None:
    store = Store()
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    writer = Writer(store, base)
    for kind, argument in plan:
        if kind == "add":
            writer.add(argument)  # type: ignore[arg-type]
        else:
            writer.remove(argument)  # type: ignore[arg-type]
        if reason_each_step:
            writer.reason()
    writer.reason()
    writer.commit()
    assert graph_triples(store) == _full(writer.view)
    # the kept state is the store's: a later incremental REASON still equals a full one
    more: list[Triple] = [("i5", RDF + "type", "C0"), ("i5", "p0", "i4")]
    _insert(store, more)
    report = materialise(
        store,
        asserted=ASSERTED,
        inferred=INFERRED,
        changes=AssertedChanges(added=[_terms(t) for t in more]),
    )
    assert graph_triples(store) == _full(writer.view + more)
    assert report.inferred_total == len(graph_triples(store))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(base=statements, additions=st.lists(st.one_of(axioms(), facts()), min_size=1, max_size=4))
def test_a_discarded_writer_leaves_nothing_and_the_next_reason_recomputes(
    base: list[Triple], additions: list[list[Triple]]
) -> None:
    store = Store()
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    before = graph_triples(store)
    writer = Writer(store, base)
    for group in additions:
        writer.add(group)
    writer.reason().discard()
    assert graph_triples(store) == before  # nothing was written
    assert _slot(store, ASSERTED, INFERRED).state is None
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=AssertedChanges())
    assert not report.incremental
    assert graph_triples(store) == _full(base) == before


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    base=statements,
    batches=st.lists(st.lists(st.one_of(axioms(), facts()), min_size=1, max_size=3), max_size=3),
)
def test_recorded_assertions_are_reasoned_over_incrementally(
    base: list[Triple], batches: list[list[list[Triple]]]
) -> None:
    """A buffered reasoner: several commits without a REASON, then a REASON told nothing new."""
    store = Store()
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    everything = list(base)
    for batch in batches:
        added = [t for group in batch for t in group]
        _insert(store, added)
        record(
            store,
            asserted=ASSERTED,
            inferred=INFERRED,
            changes=AssertedChanges(added=[_terms(t) for t in added]),
        )
        everything += added
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=AssertedChanges())
    assert report.incremental
    assert graph_triples(store) == _full(everything)


def test_a_recorded_retraction_is_re_derived_in_its_region_by_the_next_reason() -> None:
    store = Store()
    base: list[Triple] = [("C0", RDFS + "subClassOf", "C1"), ("i0", RDF + "type", "C0")]
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    with store.transaction() as tx:
        tx.delete(*_terms(base[1]), ASSERTED)
    record(
        store,
        asserted=ASSERTED,
        inferred=INFERRED,
        changes=AssertedChanges(removed=[_terms(base[1])]),
    )
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=AssertedChanges())
    assert report.scoped and not report.incremental
    assert graph_triples(store) == _full(base[:1])


def test_another_callers_reason_during_a_writer_drops_the_tentative_state() -> None:
    """The writer's confirm() then finds the state replaced and leaves no state behind."""
    store = Store()
    base: list[Triple] = [("C0", RDFS + "subClassOf", "C1")]
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    writer = Writer(store, base)
    writer.add([("i0", RDF + "type", "C0")])
    writer.reason()
    materialise(store, asserted=ASSERTED, inferred=INFERRED)  # not the writer's: drops its state
    writer.commit()
    assert _slot(store, ASSERTED, INFERRED).state is None
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == _full(writer.view)


def test_pending_literals_are_compared_in_their_stored_form() -> None:
    """ "01"^^xsd:integer asserted by the writer is the stored "1": not a new fact."""
    store = Store()
    base: list[Triple] = [("p0", RDFS + "domain", "C0"), ("i0", "level", 1)]
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    integer = NamedNode("http://www.w3.org/2001/XMLSchema#integer")
    again = (
        NamedNode(_terms(base[1])[0].value),
        _terms(base[1])[1],
        Literal("01", datatype=integer),
    )
    prepared = prepare(
        store,
        asserted=ASSERTED,
        inferred=INFERRED,
        changes=AssertedChanges(added=[again]),
        pending=PendingChanges(added=[again]),
    )
    assert prepared.incremental and (prepared.added, prepared.removed) == ([], [])
    prepared.discard()
