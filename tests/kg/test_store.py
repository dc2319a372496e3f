"""Reading the store through named queries with bound terms, and the tracer that sees it all."""

import logging
from pathlib import Path

import pytest
from pyoxigraph import Literal, NamedNode

from kg import Store, StoreLockedError
from kg.store import LARGE_WRITE_QUADS
from ontologies.vocab import DEFAULT_POLICY, MEMORY, RDFS_LABEL, TBOX, engram


def test_select_binds_terms_instead_of_splicing(empty_store: Store) -> None:
    hostile = Literal('x" } } ; DROP ALL ; #')
    with empty_store.transaction() as tx:
        tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("kept"), MEMORY)
    assert empty_store.select("tbox_version", graph=NamedNode("https://example.org/g")) == []
    # a hostile value bound to a variable is a value, never SPARQL
    rows = empty_store.select("policy_values", graph=MEMORY, policy=hostile)  # type: ignore[arg-type]
    assert rows == []
    assert empty_store.graph_sizes() == {MEMORY.value: 1}


def test_select_rows_leave_unbound_variables_out(store_with_ontology: Store) -> None:
    rows = store_with_ontology.select("policy_values", graph=TBOX, policy=DEFAULT_POLICY)
    assert {row["label"].value for row in rows} >= {"learn threshold", "parallel threshold"}
    assert all(set(row) >= {"property", "label", "value"} for row in rows)


def test_unknown_query_name_is_a_key_error_listing_known_names(empty_store: Store) -> None:
    with pytest.raises(KeyError, match="graph_sizes"):
        empty_store.select("no_such_query")


def test_select_refuses_a_query_of_another_form(empty_store: Store) -> None:
    with pytest.raises(TypeError, match="not an ASK query"):
        empty_store.ask("graph_sizes")


def test_tracer_sees_every_query_and_write(empty_store: Store) -> None:
    seen: list[tuple[str, str]] = []
    with empty_store.tracing(lambda kind, text, bindings: seen.append((kind, text))):
        empty_store.select("graph_sizes")
        with empty_store.transaction() as tx:
            tx.insert(engram("a"), RDFS_LABEL, Literal("a"), MEMORY)
        with empty_store.transaction() as tx:
            tx.delete(engram("a"), RDFS_LABEL, Literal("a"), MEMORY)
    empty_store.select("graph_sizes")  # after the block: not traced
    assert [kind for kind, _ in seen] == ["query", "extend", "update"]
    assert "GROUP BY ?graph" in seen[0][1]
    assert seen[2][1].startswith("DELETE DATA")


def test_tracer_given_at_construction_sees_bindings() -> None:
    seen: list[dict[str, object]] = []
    store = Store(tracer=lambda kind, text, bindings: seen.append(dict(bindings)))
    store.select("tbox_version", graph=TBOX)
    assert seen == [{"graph": TBOX}]


def test_second_open_of_a_store_directory_is_a_clear_error(tmp_path: Path) -> None:
    first = Store(tmp_path / "store")
    with pytest.raises(StoreLockedError, match="open in another process"):
        Store(tmp_path / "store")
    del first


def test_on_disk_store_keeps_committed_writes_after_reopening(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    with store.transaction() as tx:
        tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("kept"), MEMORY)
    del store
    reopened = Store(tmp_path / "store")
    assert reopened.graph_sizes() == {MEMORY.value: 1}


def test_backup_reopens_with_the_same_content(disk_store: Store, tmp_path: Path) -> None:
    target = disk_store.backup(tmp_path / "backup")
    copy = Store(target)
    assert copy.graph_sizes() == disk_store.graph_sizes()
    with pytest.raises(FileExistsError):
        disk_store.backup(target)


# Bulk writes (Store.fill_graph, Store.recover_bulk_writes) -------------------------------------
# (imports here: this section was appended to the file)
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import textwrap  # noqa: E402
import threading  # noqa: E402
import time  # noqa: E402

from pyoxigraph import QuerySolutions  # noqa: E402

from kg import TransactionError  # noqa: E402
from ontologies.vocab import BULK_WRITES  # noqa: E402

_BULK_GRAPH = NamedNode("https://w3id.org/engram/graph/ref/bulk/inferred")


def _bulk_document(n: int) -> bytes:
    lines = [f'<http://ex.org/s{i}> <http://ex.org/p{i % 7}> "{i}" .\n' for i in range(n)]
    return "".join(lines).encode()


def _markers(store: Store) -> list[object]:
    return list(store.quads(graph=BULK_WRITES))


def test_fill_graph_writes_every_triple_and_leaves_no_marker(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    with store.transaction() as tx:
        tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("kept"), MEMORY)
    before = store.generation
    store.fill_graph(_BULK_GRAPH, _bulk_document(3_000))
    assert store.generation == before + 1
    assert store.graph_sizes() == {MEMORY.value: 1, _BULK_GRAPH.value: 3_000}
    assert _markers(store) == []
    objects = {q.object for q in store.quads(NamedNode("http://ex.org/s42"), graph=_BULK_GRAPH)}
    assert objects == {Literal("42")}


def test_fill_graph_refuses_a_graph_that_holds_triples_and_writes_nothing(
    empty_store: Store,
) -> None:
    with empty_store.transaction() as tx:
        tx.insert(engram("old"), RDFS_LABEL, Literal("old"), _BULK_GRAPH)
    with pytest.raises(ValueError, match="holds triples, expected an empty graph"):
        empty_store.fill_graph(_BULK_GRAPH, _bulk_document(10))
    assert empty_store.graph_sizes() == {_BULK_GRAPH.value: 1}
    with pytest.raises(TypeError, match="NamedNode"):
        empty_store.fill_graph("not a graph", _bulk_document(1))  # type: ignore[arg-type]


def test_fill_graph_with_malformed_ntriples_leaves_the_graph_empty(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    document = _bulk_document(2_000) + b"<http://ex.org/broken> this is not N-Triples .\n"
    with pytest.raises(TransactionError, match="graph left empty"):
        store.fill_graph(_BULK_GRAPH, document)
    assert store.graph_sizes() == {}
    assert _markers(store) == []


def test_failure_after_the_bulk_load_leaves_the_graph_empty(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = Store(tmp_path / "store")

    def fail(self: Store, marker: object) -> None:
        assert len(list(self.quads(graph=_BULK_GRAPH))) == 1_000  # loaded, not yet finished
        raise OSError("injected failure between the load and the marker's removal")

    monkeypatch.setattr(Store, "_end_bulk_write", fail)
    with pytest.raises(TransactionError, match="injected failure"):
        store.fill_graph(_BULK_GRAPH, _bulk_document(1_000))
    assert store.graph_sizes() == {}
    assert _markers(store) == []


CRASHING_BULK_WRITER = textwrap.dedent(
    """
    import os, signal, sys
    from pyoxigraph import Literal, NamedNode
    from kg import Store
    from ontologies.vocab import MEMORY, RDFS_LABEL, engram

    store = Store(sys.argv[1])
    with store.transaction() as tx:
        tx.insert(engram("Scene-1"), RDFS_LABEL, Literal("kept"), MEMORY)
    store.flush()
    Store._end_bulk_write = lambda self, marker: os.kill(os.getpid(), signal.SIGKILL)
    lines = [f'<http://ex.org/s{i}> <http://ex.org/p> "{i}" .' for i in range(5000)]
    store.fill_graph(NamedNode(sys.argv[2]), ("\\n".join(lines) + "\\n").encode())
    print("not killed", flush=True)
    """
)


def test_a_process_killed_during_a_bulk_write_reopens_without_the_half_written_graph(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "store"
    script = [sys.executable, "-c", CRASHING_BULK_WRITER, str(path), _BULK_GRAPH.value]
    result = subprocess.run(script, capture_output=True, text=True, timeout=60)
    assert result.returncode == -signal.SIGKILL, result.stderr
    with caplog.at_level(logging.WARNING, logger="kg.store"):
        store = Store(path)  # opening recovers
    assert f"clearing {_BULK_GRAPH}" in caplog.text, "the writer died before the marker's removal"
    assert store.graph_sizes() == {MEMORY.value: 1}
    assert _markers(store) == []
    assert store.recover_bulk_writes() == []


def test_readers_see_a_filled_graph_empty_or_whole(tmp_path: Path) -> None:
    """Oxigraph ingests the bulk loader's files at once: a reader never counts a part."""
    store = Store(tmp_path / "store")
    query = f"SELECT (COUNT(*) AS ?n) {{ GRAPH {_BULK_GRAPH} {{ ?s ?p ?o }} }}"
    reads: list[tuple[float, int]] = []
    done = threading.Event()

    def read() -> None:
        while not done.is_set():
            rows = store.query_graphs(query, graphs=[_BULK_GRAPH])
            assert isinstance(rows, QuerySolutions)
            count = int(next(iter(rows))["n"].value)
            reads.append((time.perf_counter(), count))
            time.sleep(0.001)

    reader = threading.Thread(target=read)
    reader.start()
    try:
        time.sleep(0.02)
        start = time.perf_counter()
        store.fill_graph(_BULK_GRAPH, _bulk_document(60_000))
        end = time.perf_counter()
        time.sleep(0.02)
    finally:
        done.set()
        reader.join()
    assert any(start < at < end for at, _ in reads), "the reader ran during the load"
    assert {count for _, count in reads} == {0, 60_000}


def test_a_large_transaction_is_flushed_in_the_background(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    started: list[int] = []
    monkeypatch.setattr(Store, "flush_in_background", lambda self: started.append(len(self)))
    store = Store(tmp_path / "store")
    with store.transaction() as tx:
        for k in range(LARGE_WRITE_QUADS - 1):
            tx.insert(NamedNode(f"http://example.org/s{k}"), RDFS_LABEL, Literal(k), MEMORY)
    assert started == []
    with store.transaction() as tx:
        for k in range(LARGE_WRITE_QUADS):
            tx.insert(NamedNode(f"http://example.org/t{k}"), RDFS_LABEL, Literal(k), MEMORY)
    assert started == [2 * LARGE_WRITE_QUADS - 1]  # once the write is done


def test_flushes_from_many_threads_all_return(tmp_path: Path) -> None:
    # Two flushes at once on one RocksDB store can wait on each other for ever (seen as a hung
    # `engram ask --samples` while a large write's background flush ran): the store takes
    # them one at a time, whichever thread asks.
    store = Store(tmp_path / "store")

    def write_and_flush(k: int) -> None:
        for i in range(150):
            with store.transaction() as tx:
                for j in range(20):
                    tx.insert(
                        NamedNode(f"http://example.org/{k}/{i}/{j}"), RDFS_LABEL, Literal(j), MEMORY
                    )
            if i % 2:
                store.flush()
            else:
                store.flush_in_background()

    threads = [threading.Thread(target=write_and_flush, args=(k,), daemon=True) for k in range(3)]
    for thread in threads:
        thread.start()
    deadline = time.monotonic() + 90  # the 900 flushes take a few seconds when none hangs
    for thread in threads:
        thread.join(timeout=max(0.0, deadline - time.monotonic()))
    assert not any(thread.is_alive() for thread in threads), "a flush never returned"
    store.close()
    assert len(Store(tmp_path / "store")) == 3 * 150 * 20
