"""The store's commit log: what a copy of the store replays to catch up."""

from pathlib import Path

import pyoxigraph
from pyoxigraph import Literal

from kg import Store
from kg.commit_log import CommitLog
from ontologies.vocab import MEMORY, RDFS_LABEL, engram


def _replay(copy: pyoxigraph.Store, log: CommitLog, since: int, upto: int) -> None:
    commits = log.since(since, upto)
    assert commits is not None
    for commit in commits:
        if commit.inserts:
            copy.extend(commit.inserts)
        if commit.update:
            copy.update(commit.update)


def test_a_copy_replaying_the_log_holds_what_the_store_holds(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    log = store.commit_log()
    store.backup(tmp_path / "copy")
    copy = pyoxigraph.Store(str(tmp_path / "copy"))
    start = store.generation
    with store.transaction() as tx:
        tx.insert(engram("a"), RDFS_LABEL, Literal("a"), MEMORY)
        tx.insert(engram("b"), RDFS_LABEL, Literal("b"), MEMORY)
    with store.transaction() as tx:
        tx.delete(engram("a"), RDFS_LABEL, Literal("a"), MEMORY)
        tx.insert(engram("c"), RDFS_LABEL, Literal("c", language="en"), MEMORY)
    with store.transaction() as tx:
        tx.clear_graph(engram("elsewhere"))
        tx.insert(engram("d"), RDFS_LABEL, Literal("d"), engram("elsewhere"))
    _replay(copy, log, start, store.generation)
    assert set(copy) == set(store.quads())
    _replay(copy, log, start, store.generation)  # replaying again changes nothing
    assert set(copy) == set(store.quads())


def test_a_bulk_load_is_not_in_the_log_and_earlier_copies_must_be_taken_again(
    tmp_path: Path,
) -> None:
    store = Store(tmp_path / "store")
    log = store.commit_log()
    before = store.generation
    store.fill_graph(engram("bulk"), b"<http://x/a> <http://x/p> <http://x/b> .\n")
    assert log.since(before, store.generation) is None
    after = store.generation
    with store.transaction() as tx:
        tx.insert(engram("a"), RDFS_LABEL, Literal("a"), MEMORY)
    commits = log.since(after, store.generation)
    assert commits is not None and [c.generation for c in commits] == [after + 1]


def test_the_log_keeps_about_max_quads() -> None:
    log = CommitLog(max_quads=10)
    quad = pyoxigraph.Quad(engram("a"), RDFS_LABEL, Literal("a"), MEMORY)
    for generation in range(1, 101):
        log.record(generation, inserts=[quad, quad])
    assert log.floor == 95
    assert log.since(94, 100) is None
    commits = log.since(95, 100)
    assert commits is not None and [c.generation for c in commits] == [96, 97, 98, 99, 100]
