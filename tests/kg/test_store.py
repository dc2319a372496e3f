"""Reading the store through named queries with bound terms, and the tracer that sees it all."""

from pathlib import Path

import pytest
from pyoxigraph import Literal, NamedNode

from kg import Store, StoreLockedError
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
