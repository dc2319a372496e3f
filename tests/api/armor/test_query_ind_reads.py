"""QUERY IND reads the classes of an individual as triple patterns: the same answer as the stored
query ``sparql/armor_ind_classes.rq`` it replaces, on the same view of the reference.

The property tests build random small graphs (subclass cycles, class expressions as skolem IRIs
and blank nodes, literals as objects, owl:Thing and owl:NamedIndividual, individuals with several
types, triples in the asserted and in the inferred graph, in another reference's graph, and a
directive list's own pending writes) and compare both readings through one session.
"""

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import BlankNode, Literal, NamedNode, Quad

from api.armor.context import Context
from api.armor.queries import _classes_of, query_ind, query_ind_class
from api.armor.references import Reference, Registry
from api.armor.session import Session
from api.protocol import ArmorDirectiveReq
from kg import Store
from ontologies.vocab import (
    OWL_NAMED_INDIVIDUAL,
    OWL_THING,
    RDF_TYPE,
    RDFS_SUBCLASSOF,
    SKOLEM_PREFIX,
)

BASE = "http://ex.org/q"
PREFIX = BASE + "#"
REF = Reference(name="q", prefix=BASE)
OTHER = Reference(name="other", prefix=BASE)
"""Another reference over the same IRIs: its triples must never show in ``REF``'s answers."""

INDIVIDUALS = [NamedNode(PREFIX + f"ind{i}") for i in range(3)]
CLASSES = [NamedNode(PREFIX + f"C{i}") for i in range(5)]
SKOLEMS = [NamedNode(SKOLEM_PREFIX + f"x{i}") for i in range(2)]
LITERALS = [Literal("C0"), Literal(PREFIX + "C1"), Literal(3)]
SUBJECTS = INDIVIDUALS[:1] + CLASSES + SKOLEMS + [OWL_THING, OWL_NAMED_INDIVIDUAL, "blank"]
OBJECTS = CLASSES + SKOLEMS + [OWL_THING, OWL_NAMED_INDIVIDUAL, "blank", *LITERALS]


def _context(session: Session, reference: Reference = REF) -> Context:
    request = ArmorDirectiveReq(
        client_name="t", reference_name=reference.name, command="QUERY", args=["ind0"]
    )
    return Context(session=session, request=request, key="QUERY_IND_", signature="[individual]")


def _sparql_classes(session: Session, ind: NamedNode) -> set[NamedNode | Literal]:
    rows = session.select(REF, "armor_ind_classes", ind=ind, skolem=Literal(SKOLEM_PREFIX))
    return {row["class"] for row in rows if "class" in row}


def _session(store: Store) -> Session:
    session = Session(store, Registry(store))
    session.update(REF)
    session.update(OTHER)
    return session


# (subject index, predicate is rdf:type, object index, graph: 0 asserted, 1 inferred, 2 other)
_edge = st.tuples(
    st.integers(0, len(SUBJECTS) - 1),
    st.booleans(),
    st.integers(0, len(OBJECTS) - 1),
    st.integers(0, 2),
)
_typing = st.tuples(
    st.integers(0, len(INDIVIDUALS) - 1),
    st.integers(0, len(OBJECTS) - 1),
    st.integers(0, 2),
)


def _quads(
    edges: list[tuple[int, bool, int, int]],
    typings: list[tuple[int, int, int]],
    *,
    blank: bool,
) -> list[Quad]:
    """The graph's quads; ``"blank"`` is one blank node (skolemised by the store) if ``blank``,
    else one more skolem IRI, which is what a stored blank node is."""
    node = BlankNode("b") if blank else NamedNode(SKOLEM_PREFIX + "b")
    graphs = [REF.asserted, REF.inferred, OTHER.asserted]

    def term(value: object) -> NamedNode | BlankNode | Literal:
        return node if value == "blank" else value  # type: ignore[return-value]

    quads = []
    for s, is_type, o, g in edges:
        predicate = RDF_TYPE if is_type else RDFS_SUBCLASSOF
        quads.append(Quad(term(SUBJECTS[s]), predicate, term(OBJECTS[o]), graphs[g]))  # type: ignore[arg-type]
    for i, o, g in typings:
        quads.append(Quad(INDIVIDUALS[i], RDF_TYPE, term(OBJECTS[o]), graphs[g]))
    return quads


def _assert_same_answers(session: Session) -> None:
    ctx = _context(session)
    for ind in INDIVIDUALS:
        patterns = _classes_of(ctx, ind)
        assert len(patterns) == len(set(patterns)), patterns  # DISTINCT, as the query
        assert set(patterns) == _sparql_classes(session, ind)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    edges=st.lists(_edge, max_size=14),
    typings=st.lists(_typing, min_size=1, max_size=6),
    blank=st.booleans(),
)
def test_pattern_reads_answer_as_the_sparql_query_on_committed_graphs(
    edges: list[tuple[int, bool, int, int]], typings: list[tuple[int, int, int]], blank: bool
) -> None:
    store = Store()
    with store.transaction() as tx:
        for quad in _quads(edges, typings, blank=blank):
            tx.insert(quad.subject, quad.predicate, quad.object, quad.graph_name)  # type: ignore[arg-type]
    _assert_same_answers(_session(store))


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    committed=st.lists(_edge, max_size=10),
    typings=st.lists(_typing, min_size=1, max_size=5),
    pending=st.lists(_edge, max_size=6),
    pending_typings=st.lists(_typing, max_size=3),
    removed=st.lists(st.integers(0, 20), max_size=4),
)
def test_pattern_reads_see_the_lists_own_pending_writes_as_the_sparql_query(
    committed: list[tuple[int, bool, int, int]],
    typings: list[tuple[int, int, int]],
    pending: list[tuple[int, bool, int, int]],
    pending_typings: list[tuple[int, int, int]],
    removed: list[int],
) -> None:
    """Reads before the list's first SPARQL read (store plus overlaid changes), and after it
    (the list's workspace, which later writes follow) agree with the query."""
    store = Store()
    base = _quads(committed, typings, blank=False)
    with store.transaction() as tx:
        tx.inserts.extend(base)
    session = _session(store)
    deletes = [base[i] for i in removed if i < len(base)]
    adds = _quads(pending, pending_typings, blank=False)

    def write(quads: list[Quad], *, delete: bool) -> None:
        for reference in (REF, OTHER):
            mine = [q for q in quads if q.graph_name in reference.graphs]
            if delete:
                session.write(reference, delete=mine)
            else:
                session.write(reference, insert=mine)

    write(deletes, delete=True)
    ctx = _context(session)
    before_workspace = {ind: set(_classes_of(ctx, ind)) for ind in INDIVIDUALS}
    _assert_same_answers(session)  # the first SPARQL read builds the workspace if one is needed
    assert before_workspace == {ind: set(_classes_of(ctx, ind)) for ind in INDIVIDUALS}
    write(adds, delete=False)
    _assert_same_answers(session)


def test_classes_follow_cycles_class_expressions_and_the_inferred_graph() -> None:
    c = {name: NamedNode(PREFIX + name) for name in ("A", "B", "C", "D", "E", "Typed")}
    ind = INDIVIDUALS[0]
    expression = BlankNode()
    store = Store()
    with store.transaction() as tx:
        tx.insert(c["A"], RDFS_SUBCLASSOF, c["B"], REF.asserted)
        tx.insert(c["B"], RDFS_SUBCLASSOF, c["A"], REF.asserted)  # a cycle
        tx.insert(c["B"], RDFS_SUBCLASSOF, OWL_THING, REF.asserted)
        tx.insert(OWL_THING, RDFS_SUBCLASSOF, c["E"], REF.inferred)  # reached through owl:Thing
        tx.insert(ind, RDF_TYPE, c["A"], REF.asserted)
        tx.insert(ind, RDF_TYPE, OWL_NAMED_INDIVIDUAL, REF.asserted)
        tx.insert(ind, RDF_TYPE, Literal("D"), REF.asserted)
        tx.insert(ind, RDF_TYPE, expression, REF.inferred)  # typed by the inferred graph
        tx.insert(expression, RDFS_SUBCLASSOF, c["C"], REF.asserted)
        tx.insert(c["C"], RDFS_SUBCLASSOF, c["Typed"], OTHER.asserted)  # another reference's
    session = _session(store)
    ctx = _context(session)
    assert sorted(n.value for n in _classes_of(ctx, ind)) == [
        PREFIX + name for name in ("A", "B", "C", "E")
    ]
    expected = [f"<{PREFIX}{name}>" for name in ("A", "B", "C", "E")]  # ARMOR writes <IRI>
    assert query_ind(ctx).queried_objects == expected
    assert query_ind(_context(session, OTHER)).success is False  # ind0 has no type there


def test_a_lists_own_write_is_read_and_an_unknown_individual_has_no_class(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    session = _session(store)
    ctx = _context(session)
    a, b = NamedNode(PREFIX + "A"), NamedNode(PREFIX + "B")
    assert query_ind(ctx).success is False
    session.write(REF, insert=[Quad(INDIVIDUALS[0], RDF_TYPE, a, REF.asserted)])
    session.write(REF, insert=[Quad(a, RDFS_SUBCLASSOF, b, REF.inferred)])
    assert query_ind(ctx).queried_objects == [f"<{a.value}>", f"<{b.value}>"]
    session.write(REF, delete=[Quad(a, RDFS_SUBCLASSOF, b, REF.inferred)])
    assert query_ind(ctx).queried_objects == [f"<{a.value}>"]
    class_ind = Context(
        session=session,
        request=ArmorDirectiveReq(client_name="t", reference_name="q", command="QUERY", args=["A"]),
        key="QUERY_IND_CLASS",
        signature="[class]",
    )
    assert query_ind_class(class_ind).queried_objects == [f"<{INDIVIDUALS[0].value}>"]
