"""Fixtures shared by every test package."""

from collections.abc import Iterator
from pathlib import Path

import pytest

from kg import Store, ensure_ontology


@pytest.fixture
def empty_store() -> Store:
    """An in-memory store with nothing in it."""
    return Store()


@pytest.fixture
def store_with_ontology() -> Store:
    """An in-memory store holding the Engram T-Box."""
    store = Store()
    ensure_ontology(store)
    return store


@pytest.fixture
def disk_store(tmp_path: Path) -> Iterator[Store]:
    """An on-disk store in a temporary directory, holding the Engram T-Box."""
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    yield store
    del store
