"""Fixtures of the autobiographical memory tests: memories with a fixed clock, and a scene
memory graph written the way the scene memory writes it."""

import datetime as dt
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from pyoxigraph import Literal

from episodes import EpisodeMemory
from kg import Store, ensure_ontology
from ontologies.vocab import (
    EPISODIC,
    EXPERIENCED_SCENE,
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
    memory.streams.recordings.close_all()


def record_frames(memory: EpisodeMemory, episode_id: str, frames: dict[str, range]) -> None:
    """Record ticks 1..max into the open recording of ``episode_id``: provider ``clock`` (a
    string) at every frame, and each provider ``name`` of ``frames`` (a two-value float array)
    at the frames listed for it, and only there."""
    recorder = memory.streams.recordings.get(episode_id)
    recorder.add_provider("clock", "string")
    for name in frames:
        recorder.add_provider(name, "float_array", shape=[2])
    last = max(max(numbers) for numbers in frames.values())
    for frame in range(1, last + 1):
        samples: dict[str, object] = {"clock": f"tick {frame}"}
        for name, numbers in frames.items():
            if frame in numbers:
                samples[name] = np.array([frame, 0.5])
        assert recorder.tick(samples).frame == frame


def store_experienced_scene(store: Store, name: str) -> str:
    """Write the experienced scene ``engram:<name>`` as the scene memory does; its IRI."""
    scene = engram(name)
    with store.transaction() as tx:
        tx.insert(scene, RDF_TYPE, EXPERIENCED_SCENE, EPISODIC)
    return scene.value


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
