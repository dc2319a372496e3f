"""The query sandbox: a worker that dies is replaced, and a worker cannot reach the network."""

import json
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest
from pyoxigraph import Literal

from kg import Store, ensure_ontology
from kg.errors import QueryRefusedError, QueryWorkerCrashedError, UnsupportedQueryError
from kg.sandbox import QueryForm, QueryRunner
from ontologies.vocab import MEMORY, RDFS_LABEL, engram
from tests.listener import listening

pytestmark = pytest.mark.slow

JSON = {
    QueryForm.SOLUTIONS: "application/sparql-results+json",
    QueryForm.BOOLEAN: "application/sparql-results+json",
}


@pytest.fixture
def runner(tmp_path: Path) -> Iterator[QueryRunner]:
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    # no nesting limit: let a deep query reach the parser and crash the worker
    running = QueryRunner(store, snapshot_dir=tmp_path / "snapshots", workers=1, max_depth=10**6)
    yield running
    running.close()


def test_a_worker_killed_by_a_query_answers_crashed_and_is_replaced(runner: QueryRunner) -> None:
    nested = "SELECT * WHERE " + "{" * 5000 + " ?s ?p ?o " + "}" * 5000
    with pytest.raises(QueryWorkerCrashedError, match="a new worker is ready"):
        runner.run(nested, media_types=JSON)
    answer = runner.run("ASK { ?s ?p ?o }", media_types=JSON)
    assert (answer.form, answer.body.count(b"true")) == (QueryForm.BOOLEAN, 1)


def test_a_query_over_given_graphs_reads_only_them(runner: QueryRunner) -> None:
    data = {"http://x/g": b"<http://x/a> <http://x/p> <http://x/b> .\n"}
    answer = runner.run(
        "SELECT (COUNT(*) AS ?n) WHERE { ?s ?p ?o }",
        media_types=JSON,
        default_graphs=["http://x/g"],
        named_graphs=["http://x/g"],
        graph_data=data,
    )
    assert b'"value":"1"' in answer.body.replace(b" ", b"")


def test_an_unacceptable_form_is_not_evaluated(runner: QueryRunner) -> None:
    answer = runner.run("CONSTRUCT WHERE { ?s ?p ?o }", media_types=JSON)
    assert (answer.form, answer.media_type, answer.body) == (QueryForm.GRAPH, None, b"")


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("SELECT * WHERE { sErViCe <http://127.0.0.1:9/> { ?s ?p ?o } }", QueryRefusedError),
        ("SELECT * WHERE { FILTER(<http://x/f>(1)) }", UnsupportedQueryError),
    ],
)
def test_refusals(runner: QueryRunner, text: str, error: type[Exception]) -> None:
    with pytest.raises(error):
        runner.run(text, media_types=JSON)


def test_the_network_guard_stops_oxigraphs_service_call(tmp_path: Path) -> None:
    script = textwrap.dedent(
        """
        import socket
        import pyoxigraph
        from kg._no_network import forbid_network
        forbid_network()
        left, right = socket.socketpair()  # Unix sockets keep working
        left.send(b"x")
        assert right.recv(1) == b"x"
        try:
            list(pyoxigraph.Store().query(
                "SELECT * WHERE { SERVICE <http://127.0.0.1:PORT/sparql> { ?s ?p ?o } }"
            ))
        except OSError as error:
            print("refused:", error)
        """
    )
    with listening() as listener:
        done = subprocess.run(
            [sys.executable, "-c", script.replace("PORT", str(listener.port))],
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
    assert done.returncode == 0, done.stderr
    assert "refused:" in done.stdout
    assert not listener.contacted.is_set()


def _count_labels(runner: QueryRunner) -> int:
    answer = runner.run(
        "SELECT (COUNT(*) AS ?n) WHERE { ?s <http://www.w3.org/2000/01/rdf-schema#label> 'x' }",
        media_types=JSON,
    )
    return int(json.loads(answer.body)["results"]["bindings"][0]["n"]["value"])


def _label(store: Store, name: str) -> None:
    with store.transaction() as tx:
        tx.insert(engram(name), RDFS_LABEL, Literal("x"), MEMORY)


@pytest.mark.parametrize(("max_age_s", "seen_after_commit"), [(0.0, 1), (3600.0, 0)])
def test_a_query_sees_every_earlier_commit_unless_staleness_is_allowed(
    tmp_path: Path, max_age_s: float, seen_after_commit: int
) -> None:
    store = Store(tmp_path / "store")
    running = QueryRunner(
        store, snapshot_dir=tmp_path / "snapshots", workers=1, snapshot_max_age_s=max_age_s
    )
    try:
        assert _count_labels(running) == 0
        _label(store, "a")
        assert _count_labels(running) == seen_after_commit
    finally:
        running.close()


def test_each_query_sees_deletions_bulk_loads_and_many_commits_made_before_it(
    tmp_path: Path,
) -> None:
    store = Store(tmp_path / "store")
    running = QueryRunner(store, snapshot_dir=tmp_path / "snapshots", workers=2)
    try:
        assert _count_labels(running) == 0
        for n in range(30):  # inserts only: replayed as quads
            _label(store, f"a{n}")
            assert _count_labels(running) == n + 1
        with store.transaction() as tx:  # a deletion: replayed as an update
            tx.delete(engram("a0"), RDFS_LABEL, Literal("x"), MEMORY)
            tx.insert(engram("b"), RDFS_LABEL, Literal("x"), MEMORY)
        assert [_count_labels(running) for _ in range(3)] == [30, 30, 30]
        store.fill_graph(  # a bulk load, which the commit log does not hold: a new copy
            engram("bulk"), b'<http://x/s> <http://www.w3.org/2000/01/rdf-schema#label> "x" .\n'
        )
        _label(store, "c")
        assert [_count_labels(running) for _ in range(3)] == [32, 32, 32]
    finally:
        running.close()
    assert not (tmp_path / "snapshots").exists()


def test_a_copy_that_cannot_take_the_commits_is_taken_afresh(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    running = QueryRunner(store, snapshot_dir=tmp_path / "snapshots", workers=1)
    try:
        assert _count_labels(running) == 0
        _label(store, "a")
        store.commit_log().record(store.generation + 1, update="NOT AN UPDATE")
        store._generation += 1  # a commit the worker's copy cannot replay
        assert _count_labels(running) == 1
        _label(store, "b")
        assert _count_labels(running) == 2
    finally:
        running.close()
