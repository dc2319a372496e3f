"""A reset empties a data directory of its memory: every graph but the T-Box and the memory's
files, so that living the same life again gives the same store as living it once."""

import gc
from pathlib import Path

from api.summary import reset_memories
from kg import Store, ensure_ontology
from ontologies.vocab import TBOX
from tests.web.conftest import build_memory


def _held(data_dir: Path) -> tuple[dict[str, int], list[str]]:
    """The store's graph sizes and the files of the data directory outside the store."""
    store = Store(data_dir / "store")
    sizes = store.graph_sizes()
    del store
    gc.collect()
    files = sorted(
        p.relative_to(data_dir).as_posix()
        for p in data_dir.rglob("*")
        if p.is_file() and "store" not in p.relative_to(data_dir).parts[0]
    )
    return sizes, files


def _reset(data_dir: Path) -> list[Path]:
    store = Store(data_dir / "store")
    deleted = reset_memories(store)
    left = store.graph_sizes()
    del store
    gc.collect()
    assert set(left) <= {TBOX.value}, left
    return deleted


def test_a_life_lived_again_after_a_reset_gives_the_same_store(tmp_path: Path) -> None:
    data_dir = tmp_path / "data"
    build_memory(data_dir)
    once = _held(data_dir)
    assert once[0]["https://w3id.org/engram/graph/history"] > 0
    assert any(f.startswith("streams/") for f in once[1])
    assert data_dir / "streams" in _reset(data_dir)
    assert not (data_dir / "streams").exists()
    build_memory(data_dir)
    assert _held(data_dir) == once


def test_a_reset_keeps_the_ontology_and_the_backups(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    tbox = store.graph_sizes()[TBOX.value]
    (tmp_path / "backups" / "b1").mkdir(parents=True)
    assert reset_memories(store) == []
    assert store.graph_sizes() == {TBOX.value: tbox}
    assert (tmp_path / "backups" / "b1").is_dir()
