"""A memory on a real SPARQL server behaves as the embedded store does: atomic transactions,
isolated reads, its own named graphs, the Graph Store Protocol, and a journal of changes."""

import threading

import httpx
import pytest
from pyoxigraph import Literal, NamedNode

from kg import Store, TransactionError
from kg.errors import ReadOnlyStoreError, StoreError, StoreUnavailableError
from kg.fleet import RemoteMemory, open_remote
from kg.namespace import Namespace
from ontologies.vocab import EPISODES, MEMORY, RDFS_LABEL, engram

pytestmark = pytest.mark.slow

A, B = engram("a"), engram("b")


@pytest.fixture
def remote(sparql_server: tuple[str, str], memory_name: str) -> RemoteMemory:
    url, profile = sparql_server
    memory = open_remote(url, memory_name, profile=profile)
    yield memory  # type: ignore[misc]
    memory.close()


def test_a_transaction_commits_its_triples_and_moves_the_revision_by_one(
    remote: RemoteMemory,
) -> None:
    store, before = remote.store, remote.dataset.revision
    with store.transaction() as tx:
        tx.insert(A, RDFS_LABEL, Literal("a"), MEMORY)
        tx.insert(B, RDFS_LABEL, Literal("b"), EPISODES)
    assert store.graph_sizes() == {MEMORY.value: 1, EPISODES.value: 1}
    assert remote.dataset.read_revision() == before + 1
    with store.transaction() as tx:
        tx.delete_matching(A, graph=MEMORY)
    assert [q.object for q in store.quads(graph=MEMORY)] == []
    assert remote.dataset.read_revision() == before + 2


def test_a_failing_transaction_keeps_nothing_of_it_and_leaves_the_revision(
    remote: RemoteMemory,
) -> None:
    store = remote.store
    with store.transaction() as tx:
        tx.insert(A, RDFS_LABEL, Literal("kept"), MEMORY)
    revision = remote.dataset.read_revision()
    # a later operation of the same request fails on the server: the earlier ones must not stay
    failing = f"INSERT DATA {{ GRAPH {MEMORY} {{ {B} {RDFS_LABEL} 1 }} }} ;\n"
    failing += f"LOAD <http://127.0.0.1:9/nothing-here> INTO GRAPH {MEMORY}"
    with pytest.raises(TransactionError):
        remote.dataset.update(failing)
    remote.dataset.settle()
    assert [q.object.value for q in store.quads(A, RDFS_LABEL, None, MEMORY)] == ["kept"]
    assert not list(store.quads(B, None, None, MEMORY))
    assert remote.dataset.read_revision() == revision


def test_an_update_request_is_all_or_nothing_on_the_server(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, _ = sparql_server
    g = f"https://example.org/{memory_name}"
    failing = (
        f"INSERT DATA {{ GRAPH <{g}> {{ <urn:a> <urn:p> 1 }} }} ;\n"
        f"LOAD <http://127.0.0.1:9/nothing-here> INTO GRAPH <{g}>"
    )
    answer = httpx.post(
        f"{url}/update", content=failing, headers={"Content-Type": "application/sparql-update"}
    )
    assert answer.status_code >= 400
    ask = httpx.post(
        f"{url}/query",
        data={"query": f"ASK {{ GRAPH <{g}> {{ ?s ?p ?o }} }}"},
        headers={"Accept": "application/sparql-results+json"},
    )
    assert ask.json()["boolean"] is False


def test_readers_never_see_half_a_transaction(remote: RemoteMemory) -> None:
    store, seen, done = remote.store, set(), threading.Event()

    def read() -> None:
        while not done.is_set():
            seen.add(len(list(store.quads(None, RDFS_LABEL, None, MEMORY))) % 50)

    reader = threading.Thread(target=read)
    reader.start()
    try:
        for round_ in range(6):
            with store.transaction() as tx:
                for i in range(50):
                    tx.insert(engram(f"n{round_}-{i}"), RDFS_LABEL, Literal(str(i)), MEMORY)
    finally:
        done.set()
        reader.join()
    assert seen == {0}


def test_each_memory_sees_only_its_own_graphs(
    sparql_server: tuple[str, str], memory_name: str
) -> None:
    url, profile = sparql_server
    one = open_remote(url, memory_name + "-1", profile=profile)
    two = open_remote(url, memory_name + "-2", profile=profile)
    try:
        with one.store.transaction() as tx:
            tx.insert(A, RDFS_LABEL, Literal("one"), MEMORY)
        with two.store.transaction() as tx:
            tx.insert(A, RDFS_LABEL, Literal("two"), MEMORY)
        rows = one.store.query_graphs(
            "SELECT ?g ?label WHERE { GRAPH ?g { ?s ?p ?label } }", graphs=[MEMORY]
        )
        assert [(r["g"], r["label"].value) for r in rows] == [(MEMORY, "one")]  # type: ignore[index]
        union = one.store._query("SELECT ?l WHERE { ?s ?p ?l }", {})
        assert [r["l"].value for r in union] == ["one"]
        assert one.store.graph_sizes() == {MEMORY.value: 1}
    finally:
        one.close()
        two.close()


def test_a_graph_reads_and_fills_through_the_graph_store_protocol(remote: RemoteMemory) -> None:
    store = remote.store
    graph = NamedNode("https://w3id.org/engram/graph/ref/demo/inferred")
    assert store.graph_ntriples(graph) == b""
    store.fill_graph(graph, b'<http://ex.org/a> <http://ex.org/p> "1" .\n')
    assert store.graph_ntriples(graph) == b'<http://ex.org/a> <http://ex.org/p> "1" .\n'
    stored = Namespace(remote.dataset.namespace.name).remote_iri(graph.value)
    answer = httpx.get(
        remote.dataset.server.store_url,
        params={"graph": stored},
        headers={"Accept": "application/n-triples"},
    )
    assert answer.status_code == 200 and b"http://ex.org/a" in answer.content
    with pytest.raises(TransactionError):
        store.fill_graph(NamedNode(graph.value + "2"), b"not n-triples")
    assert store.graph_ntriples(NamedNode(graph.value + "2")) == b""


def test_a_follower_reads_but_may_not_write(
    sparql_server: tuple[str, str], remote: RemoteMemory
) -> None:
    url, profile = sparql_server
    follower = open_remote(url, remote.dataset.namespace.name, profile=profile, follow=True)
    try:
        with (
            pytest.raises(ReadOnlyStoreError, match="read-only"),
            follower.store.transaction() as tx,
        ):
            tx.insert(A, RDFS_LABEL, Literal("no"), MEMORY)
        with remote.store.transaction() as tx:
            tx.insert(A, RDFS_LABEL, Literal("yes"), MEMORY)
        assert [q.object.value for q in follower.store.quads(A, RDFS_LABEL)] == ["yes"]
    finally:
        follower.close()


def test_an_unreachable_server_is_a_clear_unavailable_error() -> None:
    from tests.conftest import free_port

    with pytest.raises(StoreUnavailableError, match="cannot be reached"):
        open_remote(f"http://127.0.0.1:{free_port()}", "robot")


def test_a_store_on_a_server_keeps_the_embedded_api(remote: RemoteMemory, tmp_path) -> None:  # type: ignore[no-untyped-def]
    store = remote.store
    assert isinstance(store, Store)
    assert store.select("graph_sizes") == [] and len(store) == 0
    with store.transaction() as tx:
        tx.insert(A, RDFS_LABEL, Literal("a"), MEMORY)
    assert len(store) == 1
    with pytest.raises(StoreError, match="backed up by the server"):
        store.backup(tmp_path / "copy")
