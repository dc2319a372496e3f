"""An incremental REASON gives what a full one gives; retractions fall back to recomputation."""

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import Literal, NamedNode, RdfFormat

from kg import Store
from reasoners.owl_rl import AssertedChanges, forget, materialise, record
from reasoners.owl_rl.synthetic import scene_ontology

from .conftest import ASSERTED, INFERRED, graph_triples, owlrl_inferences

EX = "http://example.org/h#"
RDF = "http://www.w3.org/1999/02/22-rdf-syntax-ns#"
RDFS = "http://www.w3.org/2000/01/rdf-schema#"
OWL = "http://www.w3.org/2002/07/owl#"
INTEGER = NamedNode("http://www.w3.org/2001/XMLSchema#integer")

Triple = tuple[str, str, str | int]
classes = st.sampled_from([f"C{i}" for i in range(5)])
properties = st.sampled_from([f"p{i}" for i in range(4)])
individuals = st.sampled_from([f"i{i}" for i in range(6)])
property_kinds = st.sampled_from(["SymmetricProperty", "TransitiveProperty", "FunctionalProperty"])


def _n(name: str) -> str:
    return name if ":" in name else EX + name


@st.composite
def axioms(draw: st.DrawFn) -> list[Triple]:
    """One T-Box axiom, as triples with named (not blank) restriction and list nodes."""
    kind = draw(st.integers(0, 10))
    c1, c2, p1, p2 = draw(classes), draw(classes), draw(properties), draw(properties)
    c3, value, kind_of_property = draw(classes), draw(individuals), draw(property_kinds)
    # Nodes are named after their content: RDF lists stay well formed (one rdf:first a node).
    r = f"R{kind}_{p1}_{c2}_{value}"
    head, tail = f"L_{c2}_{c3}", f"M_{c3}"
    return [
        [(c1, RDFS + "subClassOf", c2)],
        [(c1, OWL + "equivalentClass", c2)],
        [(p1, RDFS + "domain", c1)],
        [(p1, RDFS + "range", c1)],
        [(p1, OWL + "inverseOf", p2)],
        [(p1, RDF + "type", OWL + kind_of_property)],
        [(p1, RDFS + "subPropertyOf", p2)],
        [
            (r, OWL + "onProperty", p1),
            (r, OWL + "someValuesFrom", c2),
            (c1, OWL + "equivalentClass", r),
        ],
        [
            (r, OWL + "onProperty", p1),
            (r, OWL + "hasValue", draw(individuals)),
            (r, RDFS + "subClassOf", c1),
        ],
        [(r, OWL + "onProperty", p1), (r, OWL + "allValuesFrom", c2), (c1, RDFS + "subClassOf", r)],
        [
            (c1, OWL + "intersectionOf", head),
            (head, RDF + "first", c2),
            (head, RDF + "rest", tail),
            (tail, RDF + "first", c3),
            (tail, RDF + "rest", RDF + "nil"),
        ],
    ][kind]


@st.composite
def facts(draw: st.DrawFn) -> list[Triple]:
    kind = draw(st.integers(0, 2))
    if kind == 0:
        return [(draw(individuals), RDF + "type", draw(classes))]
    if kind == 1:
        return [(draw(individuals), draw(properties), draw(individuals))]
    return [(draw(individuals), "level", draw(st.integers(0, 2)))]


statements = st.lists(st.one_of(axioms(), facts()), max_size=14).map(
    lambda groups: [t for group in groups for t in group]
)


def _terms(triple: Triple) -> tuple[NamedNode, NamedNode, NamedNode | Literal]:
    s, p, o = triple
    obj = Literal(str(o), datatype=INTEGER) if isinstance(o, int) else NamedNode(_n(o))
    return NamedNode(_n(s)), NamedNode(_n(p)), obj


def _insert(store: Store, triples: list[Triple]) -> None:
    with store.transaction() as tx:
        for triple in triples:
            tx.insert(*_terms(triple), ASSERTED)


def _full(triples: list[Triple]) -> set[str]:
    store = Store()
    _insert(store, triples)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    return graph_triples(store)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    base=statements,
    additions=st.lists(st.one_of(axioms(), facts()), min_size=1, max_size=5),
    listed=st.booleans(),
)
def test_incremental_equals_full_recomputation(
    base: list[Triple], additions: list[list[Triple]], listed: bool
) -> None:
    """With the additions listed by the caller (``changes=``) or found by reading the graph."""
    store = Store()
    _insert(store, base)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    added = [t for group in additions for t in group]
    _insert(store, added)
    changes = AssertedChanges(added=[_terms(t) for t in added]) if listed else None
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
    assert report.incremental
    assert graph_triples(store) == _full(base + added)
    assert report.inferred_total == len(graph_triples(store))


@settings(max_examples=30, deadline=None)
@given(triples=statements.filter(bool), data=st.data())
def test_retraction_recomputes_and_equals_full(triples: list[Triple], data: st.DataObject) -> None:
    store = Store()
    _insert(store, triples)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    gone = data.draw(st.sampled_from(triples))
    with store.transaction() as tx:
        s, p, o = gone
        obj = Literal(str(o), datatype=INTEGER) if isinstance(o, int) else NamedNode(_n(o))
        tx.delete(NamedNode(_n(s)), NamedNode(_n(p)), obj, ASSERTED)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert not report.incremental
    assert graph_triples(store) == _full([t for t in triples if t != gone])


def test_nothing_changed_is_a_cheap_no_op() -> None:
    store = Store()
    _insert(store, [("C0", RDFS + "subClassOf", "C1"), ("i0", RDF + "type", "C0")])
    first = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    again = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert (again.added, again.removed, again.incremental) == (0, 0, True)
    assert again.inferred_total == first.inferred_total == len(graph_triples(store))


def test_a_newly_asserted_triple_leaves_the_inferred_graph() -> None:
    store = Store()
    _insert(store, [("C0", RDFS + "subClassOf", "C1"), ("i0", RDF + "type", "C0")])
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    derived = f"<{EX}i0> <{RDF}type> <{EX}C1>"
    assert derived in graph_triples(store)
    _insert(store, [("i0", RDF + "type", "C1")])
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert report.incremental and report.removed == 1
    assert derived not in graph_triples(store)
    assert derived in graph_triples(store, ASSERTED)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(triples=statements)
def test_random_ontologies_equal_owlrl(triples: list[Triple]) -> None:
    store = Store()
    _insert(store, triples)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == owlrl_inferences(store)


def test_listed_changes_use_the_stored_form_of_literals_and_removals_recompute() -> None:
    store = Store()
    _insert(store, [("C0", RDFS + "subClassOf", "C1"), ("p0", RDFS + "domain", "C0")])
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    double = NamedNode("http://www.w3.org/2001/XMLSchema#double")
    value = (NamedNode(EX + "i0"), NamedNode(EX + "p0"), Literal("0.5000", datatype=double))
    with store.transaction() as tx:
        tx.insert(*value, ASSERTED)
    report = materialise(
        store, asserted=ASSERTED, inferred=INFERRED, changes=AssertedChanges(added=[value])
    )
    assert report.incremental and report.added == 2  # i0 a C0, i0 a C1
    # the stored form is "0.5": a later comparison with the graph finds nothing new
    with store.transaction() as tx:  # a write elsewhere, so that the graph is read again
        tx.insert(
            NamedNode(EX + "x"),
            NamedNode(EX + "y"),
            NamedNode(EX + "z"),
            NamedNode(EX + "other-graph"),
        )
    again = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert again.incremental
    assert (again.added, again.removed) == (0, 0)
    with store.transaction() as tx:
        tx.delete(*value, ASSERTED)
    report = materialise(
        store, asserted=ASSERTED, inferred=INFERRED, changes=AssertedChanges(removed=[value])
    )
    assert not report.incremental and report.removed == 2
    assert not any(EX + "i0" in t for t in graph_triples(store))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(triples=statements.filter(bool), data=st.data())
def test_a_listed_retraction_recomputes_from_memory_and_equals_full(
    triples: list[Triple], data: st.DataObject
) -> None:
    """The caller lists what it retracted and added: the recomputation reads neither graph
    whole (the asserted graph is the last one with the listed changes, the inferred graph the
    last closure) and writes only the difference."""
    store = Store()
    _insert(store, triples)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    gone = data.draw(st.sampled_from(triples))
    added = data.draw(st.lists(facts(), max_size=2).map(lambda g: [t for f in g for t in f]))
    with store.transaction() as tx:
        tx.delete(*_terms(gone), ASSERTED)
        for triple in added:
            tx.insert(*_terms(triple), ASSERTED)
    reads: list[str] = []
    changes = AssertedChanges(added=[_terms(t) for t in added], removed=[_terms(gone)])
    with store.tracing(lambda kind, text, _: reads.append(text)):
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
    assert not report.incremental
    assert not [text for text in reads if text.startswith("DUMP GRAPH")]
    remaining = [t for t in triples if t != gone or t in added]
    assert graph_triples(store) == _full(remaining + added)
    assert report.inferred_total == len(graph_triples(store))


def test_a_recomputation_after_a_restart_writes_nothing_when_nothing_changed() -> None:
    store = Store()
    _insert(store, [("C0", RDFS + "subClassOf", "C1"), ("i0", RDF + "type", "C0")])
    first = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    forget(store, asserted=ASSERTED, inferred=INFERRED)  # as after a restart
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert (report.incremental, report.added, report.removed) == (False, 0, 0)
    assert report.inferred_total == first.inferred_total == len(graph_triples(store))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    triples=statements.filter(bool),
    data=st.data(),
    told=st.sampled_from(["listed", "recorded", "read"]),
)
def test_retractions_and_additions_equal_a_fresh_full_reason(
    triples: list[Triple], data: st.DataObject, told: str
) -> None:
    """Several rounds of random retractions and additions, listed by the caller, recorded as
    committed without a REASON, or found by reading the graph: each REASON's inferred graph
    equals a fresh full REASON's, whether the retraction was re-derived in its region or the
    closure recomputed."""
    store = Store()
    _insert(store, triples)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    current = list(dict.fromkeys(triples))
    for _ in range(data.draw(st.integers(1, 3))):
        gone = data.draw(st.lists(st.sampled_from(current), min_size=1, max_size=3, unique=True))
        added = data.draw(st.lists(facts(), max_size=2).map(lambda g: [t for f in g for t in f]))
        with store.transaction() as tx:
            for triple in gone:
                tx.delete(*_terms(triple), ASSERTED)
            for triple in added:
                tx.insert(*_terms(triple), ASSERTED)
        # deletions first, then insertions, as the transaction applies them
        current = list(dict.fromkeys([t for t in current if t not in gone] + added))
        changes: AssertedChanges | None = AssertedChanges(
            added=[_terms(t) for t in added], removed=[_terms(t) for t in gone]
        )
        if told == "recorded":
            assert changes is not None
            record(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
            changes = AssertedChanges()
        elif told == "read":
            changes = None
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
        assert graph_triples(store) == _full(current)
        assert report.inferred_total == len(graph_triples(store))
        if not current:
            return


def test_a_retracted_instance_triple_is_re_derived_in_its_region_only() -> None:
    """Two unrelated individuals: retracting one's type re-derives that individual only."""
    store = Store()
    _insert(
        store,
        [
            ("C0", RDFS + "subClassOf", "C1"),
            ("p0", RDFS + "domain", "C2"),
            ("i0", RDF + "type", "C0"),
            ("i0", "p0", "i1"),
            ("i2", RDF + "type", "C0"),
        ],
    )
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    gone = ("i0", RDF + "type", "C0")
    with store.transaction() as tx:
        tx.delete(*_terms(gone), ASSERTED)
    changes = AssertedChanges(removed=[_terms(gone)])
    reads: list[str] = []
    with store.tracing(lambda kind, text, _: reads.append(text)):
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
    assert report.scoped and not report.incremental
    assert (report.added, report.removed) == (0, 1)  # i0 a C1 goes; i0 a C2 (domain) stays
    assert not [text for text in reads if text.startswith("DUMP GRAPH")]
    assert f"<{EX}i2> <{RDF}type> <{EX}C1>" in graph_triples(store)
    # unlisted: the reasoner reads the asserted graph, finds the retraction, and scopes it too
    with store.transaction() as tx:
        tx.delete(*_terms(("i2", RDF + "type", "C0")), ASSERTED)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert report.scoped and (report.added, report.removed) == (0, 1)
    assert not any(f"<{EX}i2>" in t for t in graph_triples(store))


def test_a_retracted_schema_triple_recomputes_the_closure() -> None:
    store = Store()
    _insert(store, [("C0", RDFS + "subClassOf", "C1"), ("i0", RDF + "type", "C0")])
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    gone = ("C0", RDFS + "subClassOf", "C1")
    with store.transaction() as tx:
        tx.delete(*_terms(gone), ASSERTED)
    changes = AssertedChanges(removed=[_terms(gone)])
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED, changes=changes)
    assert not report.scoped and report.removed >= 1
    assert graph_triples(store) == _full([("i0", RDF + "type", "C0")])


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_retractions_in_a_scene_ontology_equal_a_fresh_full_reason(data: st.DataObject) -> None:
    """The synthetic scenes (restrictions, intersections, inverse, symmetric and transitive
    properties, data values): random instance retractions, re-derived in their regions."""
    lines = scene_ontology(1_000, seed=data.draw(st.integers(0, 3)))
    store = Store()
    with store.transaction() as tx:
        tx.load(("\n".join(lines) + "\n").encode(), format=RdfFormat.N_TRIPLES, graph=ASSERTED)
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    instances = [q for q in store.quads(graph=ASSERTED) if "#scene" in str(q.subject)]
    gone = data.draw(st.lists(st.sampled_from(instances), min_size=1, max_size=4, unique=True))
    with store.transaction() as tx:
        tx.deletes.extend(gone)
    triples = [(q.subject, q.predicate, q.object) for q in gone]
    report = materialise(
        store,
        asserted=ASSERTED,
        inferred=INFERRED,
        changes=AssertedChanges(removed=triples),  # type: ignore[arg-type]
    )
    assert report.scoped
    fresh = Store()
    with fresh.transaction() as tx:
        tx.load(store.graph_ntriples(ASSERTED), format=RdfFormat.N_TRIPLES, graph=ASSERTED)
    materialise(fresh, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == graph_triples(fresh)
