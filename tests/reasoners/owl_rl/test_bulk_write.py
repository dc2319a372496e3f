"""A full REASON into an empty inferred graph goes through the bulk loader: same triples, and
all or nothing (an injected failure or a killed process leaves the graph as it was)."""

import importlib
import logging
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from pyoxigraph import NamedNode, RdfFormat

from kg import Store, TransactionError
from ontologies.vocab import BULK_WRITES, RDF_TYPE
from reasoners.owl_rl import AssertedChanges, materialise
from reasoners.owl_rl.synthetic import EX, scene_ontology

from .conftest import (
    ASSERTED,
    INFERRED,
    KILLED_REASON,
    Loader,
    graph_triples,
    owlrl_inferences,
    recomputed,
)

materialise_module = importlib.import_module("reasoners.owl_rl.materialise")
SCENE = "\n".join(scene_ontology(3_000, seed=7)).encode()


def _on_disk(path: Path, document: bytes = SCENE) -> Store:
    store = Store(path)
    with store.transaction() as tx:
        tx.load(document, format=RdfFormat.N_TRIPLES, graph=ASSERTED)
    return store


def _transactional_closure(of: Store, monkeypatch: pytest.MonkeyPatch) -> set[str]:
    """The closure of ``of``'s asserted graph (same skolem IRIs) as the transactional path
    writes it (no bulk load)."""
    document = of.graph_ntriples(ASSERTED)
    with monkeypatch.context() as patch:
        patch.setattr(materialise_module, "_BULK_MIN", 10**9)
        store = Store()
        with store.transaction() as tx:
            tx.load(document, format=RdfFormat.N_TRIPLES, graph=ASSERTED)
        materialise(store, asserted=ASSERTED, inferred=INFERRED)
        return graph_triples(store)


def test_a_bulk_written_closure_equals_the_transactional_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = _on_disk(tmp_path / "store")
    loads: list[str] = []
    with store.tracing(lambda kind, text, _: loads.append(text)):
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert report.added >= materialise_module._BULK_MIN, "large enough for the bulk path"
    assert any(text.startswith(f"BULK LOAD INTO {INFERRED}") for text in loads)
    inferred = graph_triples(store)
    assert report.added == report.inferred_total == len(inferred)
    assert inferred == _transactional_closure(store, monkeypatch)
    assert list(store.quads(graph=BULK_WRITES)) == []


def test_the_bulk_path_equals_owlrl(load: Loader, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(materialise_module, "_BULK_MIN", 1)
    store = load("\n".join(scene_ontology(1_500, seed=3)).encode(), RdfFormat.N_TRIPLES)
    loads: list[str] = []
    with store.tracing(lambda kind, text, _: loads.append(text)):
        materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert any(text.startswith("BULK LOAD") for text in loads)
    assert graph_triples(store) == owlrl_inferences(store)


def test_incremental_reason_after_a_bulk_written_closure_equals_a_full_one(
    tmp_path: Path,
) -> None:
    store = _on_disk(tmp_path / "store")
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    obj = NamedNode(EX + "new_obj")
    added = [
        (obj, RDF_TYPE, NamedNode(EX + "Mug")),
        (obj, NamedNode(EX + "inScene"), NamedNode(EX + "scene1")),
        (obj, NamedNode(EX + "above"), NamedNode(EX + "scene1_obj0")),
    ]
    with store.transaction() as tx:
        for s, p, o in added:
            tx.insert(s, p, o, ASSERTED)
    report = materialise(
        store, asserted=ASSERTED, inferred=INFERRED, changes=AssertedChanges(added=added)
    )
    assert report.incremental and report.added > 0
    assert graph_triples(store) == recomputed(store)


def test_a_failure_between_the_load_and_its_end_leaves_the_old_graph_and_a_clean_store(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = _on_disk(tmp_path / "store")
    seen: list[int] = []

    def fail(self: Store, marker: object) -> None:
        seen.append(len(list(self.quads(graph=INFERRED))))  # the closure is loaded, not live
        raise OSError("disk full")

    with monkeypatch.context() as patch:
        patch.setattr(Store, "_end_bulk_write", fail)
        with pytest.raises(TransactionError, match="disk full"):
            materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert seen and seen[0] >= materialise_module._BULK_MIN
    assert graph_triples(store) == set(), "the inferred graph is as it was: empty"
    assert list(store.quads(graph=BULK_WRITES)) == []
    del store
    reopened = Store(tmp_path / "store")
    assert reopened.recover_bulk_writes() == []
    report = materialise(reopened, asserted=ASSERTED, inferred=INFERRED)
    assert not report.incremental and report.added == len(graph_triples(reopened))


def test_a_process_killed_during_a_full_reason_reopens_without_a_partial_closure(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "store"
    result = subprocess.run(
        [sys.executable, "-c", KILLED_REASON, str(path), "test"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == -signal.SIGKILL, result.stdout + result.stderr
    with caplog.at_level(logging.WARNING, logger="kg.store"):
        store = Store(path)  # opening recovers
    assert f"clearing {INFERRED}" in caplog.text, "killed between the load and its end"
    assert not list(store.quads(graph=BULK_WRITES))
    assert graph_triples(store) == set()
    assert len(graph_triples(store, ASSERTED)) > 0, "the committed assertions are kept"
    materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == _transactional_closure(store, monkeypatch)


def test_a_closure_written_while_derived_equals_owlrl(
    load: Loader, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(materialise_module, "_STREAM_MIN", 1)
    monkeypatch.setattr(materialise_module, "_STREAM_STEP", 500)  # several pieces
    store = load("\n".join(scene_ontology(1_500, seed=3)).encode(), RdfFormat.N_TRIPLES)
    loads: list[str] = []
    with store.tracing(lambda kind, text, _: loads.append(text)):
        report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert f"BULK LOAD INTO {INFERRED} (streamed)" in loads
    inferred = graph_triples(store)
    assert inferred == owlrl_inferences(store)
    assert report.added == report.inferred_total == len(inferred)
    assert list(store.quads(graph=BULK_WRITES)) == []


def test_a_reasoner_failing_while_its_closure_streams_leaves_the_graph_empty(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(materialise_module, "_STREAM_MIN", 1)
    monkeypatch.setattr(materialise_module, "_STREAM_STEP", 200)
    store = _on_disk(tmp_path / "store")
    engine_class = materialise_module.Engine
    real = engine_class.take_log
    calls: list[int] = []

    def failing(self: object) -> list[tuple[str, str, str]]:
        calls.append(1)
        if len(calls) == 3:  # two pieces are loaded by then
            raise RuntimeError("the reasoner broke")
        return real(self)  # type: ignore[arg-type]

    monkeypatch.setattr(engine_class, "take_log", failing)
    with pytest.raises(RuntimeError, match="the reasoner broke"):
        materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == set()
    assert list(store.quads(graph=BULK_WRITES)) == []
    monkeypatch.setattr(engine_class, "take_log", real)
    report = materialise(store, asserted=ASSERTED, inferred=INFERRED)
    assert graph_triples(store) == _transactional_closure(store, monkeypatch)
    assert report.added == len(graph_triples(store))


def test_streamed_pieces_that_do_not_parse_leave_the_graph_empty(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    good = b"<http://ex.org/a> <http://ex.org/p> <http://ex.org/b> .\n" * 50_000
    pieces = iter([good, b"<http://ex.org/a> not N-Triples\n", good, good])
    with pytest.raises(TransactionError, match="graph left empty"):
        store.fill_graph(INFERRED, pieces)
    assert graph_triples(store) == set()
    assert list(store.quads(graph=BULK_WRITES)) == []
    store.fill_graph(INFERRED, iter([b"<http://ex.org/a> <http://ex.org/p> <http://ex.org/c> .\n"]))
    assert len(graph_triples(store)) == 1
