"""Restoring a store from a backup (kg/restore.py): the backup's triples come back, the store
it replaces is kept, and a bad backup or a store held by a server changes nothing."""

import gc
from pathlib import Path

import pytest
from pyoxigraph import Literal

from kg import Store, StoreLockedError, ensure_ontology
from kg.errors import InvalidInputError, NotFoundError
from kg.restore import restore_backup
from ontologies.vocab import MEMORY, RDFS_LABEL, engram
from tests.conftest import LiveServer

THING = engram("thing")


def _labels(store_dir: Path) -> set[str]:
    store = Store(store_dir)
    found = {q.object.value for q in store.quads(THING, RDFS_LABEL, None, MEMORY)}
    del store
    gc.collect()
    return found


def _label(store: Store, text: str) -> None:
    with store.transaction() as tx:
        tx.insert(THING, RDFS_LABEL, Literal(text), MEMORY)


@pytest.fixture
def data_dir_with_a_backup(tmp_path: Path) -> Path:
    """A data directory whose store was labelled "before", backed up, then labelled "after"."""
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    _label(store, "before")
    store.backup(tmp_path / "backups" / "b1")
    _label(store, "after")
    del store
    gc.collect()
    return tmp_path


def test_a_restore_brings_the_backup_back_and_keeps_the_store_it_replaces(
    data_dir_with_a_backup: Path,
) -> None:
    data = data_dir_with_a_backup
    kept = restore_backup(data / "backups" / "b1", data / "store")
    assert _labels(data / "store") == {"before"}
    assert kept is not None and kept.parent == data / "backups"
    assert _labels(kept) == {"before", "after"}
    assert _labels(data / "backups" / "b1") == {"before"}  # the backup itself is untouched
    assert not (data / "store.restoring").exists()


def test_a_restore_makes_a_store_where_there_was_none(data_dir_with_a_backup: Path) -> None:
    data = data_dir_with_a_backup
    fresh = data / "other" / "store"
    assert restore_backup(data / "backups" / "b1", fresh) is None
    assert _labels(fresh) == {"before"}


def _not_a_store(data: Path) -> Path:
    (data / "junk").mkdir()
    (data / "junk" / "notes.txt").write_text("hello")
    return data / "junk"


def _store_without_ontology(data: Path) -> Path:
    bare = Store(data / "bare")
    _label(bare, "bare")
    del bare
    gc.collect()
    return data / "bare"


@pytest.mark.parametrize(
    ("make", "error", "fragment"),
    [
        (lambda data: data / "missing", NotFoundError, "is not a directory"),
        (_not_a_store, InvalidInputError, "no CURRENT file"),
        (_store_without_ontology, InvalidInputError, "without the Engram T-Box"),
        (lambda data: data / "store", InvalidInputError, "is the store itself"),
    ],
)
def test_a_bad_backup_is_refused_and_changes_nothing(
    data_dir_with_a_backup: Path, make: object, error: type[Exception], fragment: str
) -> None:
    data = data_dir_with_a_backup
    backup = make(data)  # type: ignore[operator]
    with pytest.raises(error, match=fragment):
        restore_backup(backup, data / "store")
    assert _labels(data / "store") == {"before", "after"}
    assert not (data / "store.restoring").exists()
    assert sorted(p.name for p in (data / "backups").iterdir()) == ["b1"]


def test_a_store_a_server_holds_is_not_restored(live_server: LiveServer, tmp_path: Path) -> None:
    data = live_server.settings.data_dir
    assert live_server.client.post("/backup").status_code == 201
    (backup,) = (data / "backups").iterdir()
    with pytest.raises(StoreLockedError, match="open in another process"):
        restore_backup(backup, data / "store")
    assert sorted(p.name for p in (data / "backups").iterdir()) == [backup.name]
    assert live_server.client.get("/health").status_code == 200
