"""Fixtures of the autobiographical memory tests: memories with a fixed clock, and a scene
memory graph written the way the scene memory writes it."""

import datetime as dt
from collections.abc import Iterator
from pathlib import Path

import pytest
from pyoxigraph import Literal

from episodes import EpisodeMemory
from kg import Store, ensure_ontology
from ontologies.vocab import (
    EPISODIC,
    MEMORY,
    OWL_CLASS,
    RDF_TYPE,
    RDFS_SUBCLASSOF,
    SCENE,
    SCORE,
    engram,
)

NOW = dt.datetime(2026, 2, 26, 10, 0, tzinfo=dt.UTC)


def fixed_clock() -> dt.datetime:
    return NOW


@pytest.fixture
def memory() -> EpisodeMemory:
    """An EpisodeMemory over an in-memory store, "now" fixed at 2026-02-26 10:00 UTC."""
    store = Store()
    ensure_ontology(store)
    return EpisodeMemory(store, clock=fixed_clock)


@pytest.fixture
def disk_memory(tmp_path: Path) -> Iterator[EpisodeMemory]:
    """An EpisodeMemory over an on-disk store with a data directory for stream files."""
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    memory = EpisodeMemory(store, data_dir=tmp_path, clock=fixed_clock)
    yield memory
    memory.close()
    if memory._recordings is not None:
        memory._recordings.close_all()


def learn_scene_classes(store: Store, scores: dict[str, float], items: int) -> None:
    """Write learned classes with scores and experienced scenes, as the scene memory does."""
    with store.transaction() as tx:
        for name, score in scores.items():
            cls = engram(name)
            tx.insert(cls, RDF_TYPE, OWL_CLASS, MEMORY)
            tx.insert(cls, RDFS_SUBCLASSOF, SCENE, MEMORY)
            tx.insert(cls, SCORE, Literal(score), MEMORY)
        for i in range(items):
            tx.insert(engram(f"scene-{i}"), RDF_TYPE, SCENE, EPISODIC)
