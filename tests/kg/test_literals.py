"""Literals keep their datatype through the store: what goes in comes out, by every read."""

import pytest
from pyoxigraph import Literal, NamedNode, RdfFormat

from kg import Store
from kg.literals import REWRITTEN
from ontologies.vocab import MEMORY, XSD_NS

S, P = NamedNode("http://example.org/s"), NamedNode("http://example.org/p")
VALUES = {"dateTimeStamp": "2026-01-01T00:00:00Z", "negativeInteger": "-5"}
WRITTEN = [Literal(VALUES.get(n, "5"), datatype=NamedNode(XSD_NS + n)) for n in sorted(REWRITTEN)]


@pytest.mark.parametrize("literal", WRITTEN, ids=str)
def test_a_literal_comes_back_from_every_read_as_written(literal: Literal) -> None:
    store = Store()
    with store.transaction() as tx:
        tx.insert(S, P, literal, MEMORY)
    assert [q.object for q in store.quads(graph=MEMORY)] == [literal]
    assert [q.object for q in store.quads(S, P, literal, MEMORY)] == [literal]
    assert store.graph_ntriples(MEMORY).decode() == f"{S} {P} {literal} .\n"
    with store.transaction() as tx:
        tx.delete(S, P, literal, MEMORY)
    assert len(store) == 0


def test_loaded_documents_bulk_writes_and_out_of_range_values_keep_their_datatype() -> None:
    store = Store()
    turtle = (
        "@prefix xsd: <http://www.w3.org/2001/XMLSchema#> . "
        '<http://example.org/s> <http://example.org/p> "300"^^xsd:byte , 7 .'
    )
    with store.transaction() as tx:
        tx.load(turtle, format=RdfFormat.TURTLE, graph=MEMORY)
    objects = {str(q.object) for q in store.quads(graph=MEMORY)}
    assert objects == {f'"300"^^<{XSD_NS}byte>', f'"7"^^<{XSD_NS}integer>'}
    other = NamedNode("http://example.org/other")
    store.fill_graph(other, store.graph_ntriples(MEMORY))
    assert set(store.graph_ntriples(other).splitlines()) == {
        f"{S} {P} {q.object}".encode() + b" ." for q in store.quads(graph=MEMORY)
    }
    with store.transaction() as tx:
        tx.delete_matching(obj=Literal("300", datatype=NamedNode(XSD_NS + "byte")), graph=other)
    assert {str(q.object) for q in store.quads(graph=other)} == {f'"7"^^<{XSD_NS}integer>'}
