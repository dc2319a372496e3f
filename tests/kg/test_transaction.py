"""Transactions: all or nothing, precise deletion of class expressions, crash safety."""

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest
from pyoxigraph import BlankNode, DefaultGraph, Literal, NamedNode, RdfFormat

from kg import Store, TransactionError
from kg.skolem import is_skolem
from ontologies.vocab import (
    MEMORY,
    OWL_MIN_QUALIFIED_CARDINALITY,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    RDF_TYPE,
    RDFS_LABEL,
    SPHERE,
    engram,
)

SCENE_1 = engram("Scene-1")


def snapshot(store: Store) -> set[str]:
    return {str(quad) for quad in store.quads()}


def test_exception_inside_the_block_leaves_the_store_untouched(
    store_with_ontology: Store,
) -> None:
    before = snapshot(store_with_ontology)
    with (
        pytest.raises(RuntimeError, match="perception crashed"),
        store_with_ontology.transaction() as tx,
    ):
        tx.insert(SCENE_1, RDFS_LABEL, Literal("half"), MEMORY)
        tx.delete_matching(graph=MEMORY)
        tx.clear_graph(engram("tbox"))
        raise RuntimeError("perception crashed")
    assert snapshot(store_with_ontology) == before
    assert store_with_ontology.generation == 1  # only the ontology load


def test_deletions_apply_before_insertions(empty_store: Store) -> None:
    with empty_store.transaction() as tx:
        tx.insert(SCENE_1, RDFS_LABEL, Literal("old"), MEMORY)
    with empty_store.transaction() as tx:
        tx.delete(SCENE_1, RDFS_LABEL, Literal("old"), MEMORY)
        tx.insert(SCENE_1, RDFS_LABEL, Literal("old"), MEMORY)
        tx.insert(SCENE_1, RDFS_LABEL, Literal("new"), MEMORY)
    labels = {q.object.value for q in empty_store.quads(SCENE_1, RDFS_LABEL)}
    assert labels == {"old", "new"}


def test_delete_matching_sees_the_store_at_commit(empty_store: Store) -> None:
    with empty_store.transaction() as tx:
        for n in range(3):
            tx.insert(SCENE_1, engram("score"), Literal(n), MEMORY)
        tx.insert(engram("Scene-2"), engram("score"), Literal(9), MEMORY)
    with empty_store.transaction() as tx:
        tx.delete_matching(SCENE_1, engram("score"), graph=MEMORY)
        tx.insert(SCENE_1, engram("score"), Literal(5), MEMORY)
    assert sorted(str(q.object.value) for q in empty_store.quads(predicate=engram("score"))) == [
        "5",
        "9",
    ]


def test_clear_graph_empties_only_that_graph(store_with_ontology: Store) -> None:
    with store_with_ontology.transaction() as tx:
        tx.insert(SCENE_1, RDFS_LABEL, Literal("a"), MEMORY)
    with store_with_ontology.transaction() as tx:
        tx.clear_graph(MEMORY)
    assert list(store_with_ontology.graph_sizes()) == ["https://w3id.org/engram/graph/tbox"]


def test_empty_transaction_writes_nothing(empty_store: Store) -> None:
    with empty_store.transaction():
        pass
    assert empty_store.generation == 0


def test_work_alongside_the_write_runs_in_this_thread_and_finishes_with_it(
    empty_store: Store,
) -> None:
    seen: list[str] = []

    def bookkeeping() -> None:
        seen.append(threading.current_thread().name)

    with empty_store.transaction(alongside=bookkeeping) as tx:
        tx.insert(SCENE_1, RDFS_LABEL, Literal("a"), MEMORY)
    assert seen == [threading.current_thread().name]
    assert len(empty_store) == 1 and empty_store.generation == 1
    with empty_store.transaction(alongside=bookkeeping):
        pass  # nothing to write: the work still runs
    assert len(seen) == 2 and empty_store.generation == 1


class _DiskFull:
    """A pyoxigraph store whose writes fail, as on a full disk."""

    def __init__(self, inner: object) -> None:
        self._inner = inner

    def __getattr__(self, name: str) -> object:
        return getattr(self._inner, name)

    def update(self, text: str) -> None:
        raise OSError("disk full")


def test_a_failing_write_with_work_alongside_raises_and_changes_nothing(
    store_with_ontology: Store, monkeypatch: pytest.MonkeyPatch
) -> None:
    before = snapshot(store_with_ontology)
    monkeypatch.setattr(store_with_ontology, "_store", _DiskFull(store_with_ontology._store))
    ran: list[bool] = []
    with (
        pytest.raises(TransactionError, match="store unchanged: disk full"),
        store_with_ontology.transaction(alongside=lambda: ran.append(True)) as tx,
    ):
        tx.insert(SCENE_1, RDFS_LABEL, Literal("a"), MEMORY)
        tx.delete(SCENE_1, RDFS_LABEL, Literal("b"), MEMORY)
    assert ran == [True]
    monkeypatch.undo()
    assert snapshot(store_with_ontology) == before


def test_failing_work_alongside_propagates_after_the_write_is_applied(
    empty_store: Store,
) -> None:
    def broken() -> None:
        raise RuntimeError("bookkeeping failed")

    with (
        pytest.raises(RuntimeError, match="bookkeeping failed"),
        empty_store.transaction(alongside=broken) as tx,
    ):
        tx.insert(SCENE_1, RDFS_LABEL, Literal("a"), MEMORY)
    assert len(empty_store) == 1  # the write does not depend on the work alongside it


@pytest.mark.parametrize(
    ("graph", "message"),
    [(None, "graph must be a NamedNode"), (DefaultGraph(), "graph must be a NamedNode")],
)
def test_quads_outside_a_named_graph_are_refused(
    empty_store: Store, graph: object, message: str
) -> None:
    with pytest.raises(TypeError, match=message), empty_store.transaction() as tx:
        tx.insert(SCENE_1, RDFS_LABEL, Literal("a"), graph)  # type: ignore[arg-type]
    assert empty_store.generation == 0


def test_malformed_document_records_nothing(empty_store: Store) -> None:
    with pytest.raises(SyntaxError), empty_store.transaction() as tx:
        tx.insert(SCENE_1, RDFS_LABEL, Literal("a"), MEMORY)
        tx.load("<a> <b> .", format=RdfFormat.TURTLE, graph=MEMORY, base_iri="http://x/")
    assert len(empty_store) == 0


def test_blank_nodes_are_stored_as_skolem_iris_and_deleted_precisely(empty_store: Store) -> None:
    """Two restrictions that differ only in their node: deleting one leaves the other whole."""

    def restriction(tx_insert, node: BlankNode, cls: NamedNode) -> None:  # type: ignore[no-untyped-def]
        tx_insert(cls, engram("restricts"), node, MEMORY)
        tx_insert(node, OWL_ON_PROPERTY, engram("sphereIsAboveOf"), MEMORY)
        tx_insert(node, OWL_ON_CLASS, SPHERE, MEMORY)
        tx_insert(node, OWL_MIN_QUALIFIED_CARDINALITY, Literal(1), MEMORY)

    with empty_store.transaction() as tx:
        restriction(tx.insert, BlankNode(), engram("Scene-1"))
        restriction(tx.insert, BlankNode(), engram("Scene-2"))
    nodes = [q.object for q in empty_store.quads(predicate=engram("restricts"))]
    assert len(nodes) == 2 and all(is_skolem(node) for node in nodes)
    assert not any(isinstance(q.subject, BlankNode) for q in empty_store.quads())

    doomed = next(empty_store.quads(engram("Scene-1"), engram("restricts"))).object
    with empty_store.transaction() as tx:
        tx.delete_matching(doomed, graph=MEMORY)  # type: ignore[arg-type]
        tx.delete_matching(engram("Scene-1"), graph=MEMORY)
    remaining = list(empty_store.quads())
    assert len(remaining) == 4
    assert {q.subject for q in remaining} == {engram("Scene-2"), *[n for n in nodes if n != doomed]}


WRITER = textwrap.dedent(
    """
    import sys
    from pyoxigraph import Literal
    from kg import Store, TransactionError
    from ontologies.vocab import MEMORY, engram

    store = Store(sys.argv[1])
    n = 0
    while True:
        n += 1
        with store.transaction() as tx:
            tx.delete_matching(engram("head"), graph=MEMORY)
            tx.insert(engram("head"), engram("at"), Literal(n), MEMORY)
            for i in range(400):
                tx.insert(engram(f"t{n}-{i}"), engram("in"), Literal(n), MEMORY)
        if n == 3:
            print("writing", flush=True)
    """
)


def test_sigkill_while_writing_leaves_all_or_none_of_each_transaction(tmp_path: Path) -> None:
    path = tmp_path / "store"
    with subprocess.Popen(
        [sys.executable, "-c", WRITER, str(path)], stdout=subprocess.PIPE, text=True
    ) as writer:
        assert writer.stdout is not None
        assert writer.stdout.readline() == "writing\n"
        time.sleep(0.4)
        os.kill(writer.pid, signal.SIGKILL)
        writer.wait(timeout=10)

    store = Store(path)
    heads = [q.object.value for q in store.quads(engram("head"), engram("at"))]
    assert len(heads) == 1, (
        "exactly one head: the last transaction's delete and insert went together"
    )
    last = int(heads[0])
    sizes: dict[int, int] = {}
    for quad in store.quads(predicate=engram("in")):
        sizes[int(quad.object.value)] = sizes.get(int(quad.object.value), 0) + 1
    assert last >= 3
    assert sizes == dict.fromkeys(range(1, last + 1), 400)
    assert all(not isinstance(q.subject, BlankNode) for q in store.quads(RDF_TYPE))
