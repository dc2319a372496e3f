"""Store.graph_ntriples: one graph as canonical N-Triples, seen by the tracer."""

import pytest
from pyoxigraph import Literal, NamedNode, RdfFormat, parse

from kg import Store
from ontologies.vocab import EPISODIC, MEMORY, RDFS_LABEL, engram


def test_graph_ntriples_holds_exactly_that_graph_with_canonical_literals(
    empty_store: Store,
) -> None:
    score = NamedNode("http://www.w3.org/2001/XMLSchema#double")
    with empty_store.transaction() as tx:
        tx.insert(engram("a"), engram("score"), Literal("0.5000", datatype=score), MEMORY)
        tx.insert(engram("a"), RDFS_LABEL, Literal('say "hi"\n'), MEMORY)
        tx.insert(engram("b"), RDFS_LABEL, Literal("elsewhere"), EPISODIC)
    data = empty_store.graph_ntriples(MEMORY)
    triples = {str(t) for t in parse(data, format=RdfFormat.N_TRIPLES)}
    assert triples == {
        f'{engram("a")} {engram("score")} "0.5"^^{score}',
        f'{engram("a")} {RDFS_LABEL} "say \\"hi\\"\\n"',
    }
    assert data.count(b"\n") == 2
    assert empty_store.graph_ntriples(NamedNode("https://example.org/none")) == b""


def test_graph_ntriples_is_traced_and_checks_its_argument(empty_store: Store) -> None:
    seen: list[tuple[str, str]] = []
    with empty_store.tracing(lambda kind, text, bindings: seen.append((kind, text))):
        empty_store.graph_ntriples(MEMORY)
    assert seen == [("query", f"DUMP GRAPH {MEMORY} AS N-Triples")]
    with pytest.raises(TypeError, match="graph must be a NamedNode"):
        empty_store.graph_ntriples("memory")  # type: ignore[arg-type]
