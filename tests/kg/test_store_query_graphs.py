"""Store.query_graphs: a caller's SPARQL over chosen graphs only."""

import pytest
from pyoxigraph import Literal, NamedNode, QuerySolutions

from kg import QueryRefusedError, QuerySyntaxError, Store
from ontologies.vocab import RDFS_LABEL, reference_graph

A, B = reference_graph("a"), reference_graph("b")
S = NamedNode("http://ex.org/s")


@pytest.fixture
def two_graphs() -> Store:
    store = Store()
    with store.transaction() as tx:
        tx.insert(S, RDFS_LABEL, Literal("in a"), A)
        tx.insert(S, RDFS_LABEL, Literal("in b"), B)
    return store


def _labels(
    store: Store, graphs: list[NamedNode], text: str = "SELECT ?l WHERE { ?s ?p ?l }"
) -> list[str]:
    result = store.query_graphs(text, graphs=graphs)
    assert isinstance(result, QuerySolutions)
    return sorted(row["l"].value for row in result)  # type: ignore[union-attr]


def test_default_graph_is_the_union_of_the_chosen_graphs(two_graphs: Store) -> None:
    assert _labels(two_graphs, [A]) == ["in a"]
    assert _labels(two_graphs, [A, B]) == ["in a", "in b"]


def test_graph_clause_cannot_reach_other_graphs(two_graphs: Store) -> None:
    assert _labels(two_graphs, [A], "SELECT ?l WHERE { GRAPH ?g { ?s ?p ?l } }") == ["in a"]


def test_bindings_are_bound_as_values(two_graphs: Store) -> None:
    result = two_graphs.query_graphs(
        "SELECT ?l WHERE { ?s ?p ?l }", graphs=[A, B], bindings={"l": Literal("in b")}
    )
    assert isinstance(result, QuerySolutions)
    assert [row["l"] for row in result] == [Literal("in b")]


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("SELECT ?s WHERE { ?s ?p }", QuerySyntaxError),
        ("INSERT DATA { <http://x> <http://y> <http://z> }", QuerySyntaxError),
        ("SELECT * WHERE { SERVICE <http://ex.org/sparql> { ?s ?p ?o } }", QueryRefusedError),
    ],
)
def test_refuses_bad_text_updates_and_service(
    two_graphs: Store, text: str, error: type[Exception]
) -> None:
    with pytest.raises(error):
        two_graphs.query_graphs(text, graphs=[A])
    assert len(two_graphs) == 2
