"""Episode snapshots of a running server rank the scene classes by their live scores."""

import datetime as dt

from api.memory_state import live_memory_state
from episodes import EpisodeMemory
from episodes.snapshot import read_memory_state
from kg import Store
from kg.primitive import Primitive
from reasoners.memory import SceneMemory

T0 = dt.datetime(2026, 1, 1, tzinfo=dt.UTC)
ALONE = [
    Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05),
    Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1)),
]
OFTEN = [
    Primitive("can", "Cylinder", centre=(0.0, 0.0, 0.3), axis=(0, 0, 1), radius=0.03, height=0.1),
    Primitive("cone", "Cone", centre=(0.5, 0.5, 0.1), axis=(0, 0, 1), radius=0.03, height=0.1),
]


def test_snapshots_hold_the_live_scores_not_the_stored_ones() -> None:
    store = Store()
    memory = SceneMemory(store, clock=lambda: T0)
    alone = memory.store_scene(ALONE).stored_as
    for _ in range(5):  # raises the largest store count, which lowers ALONE's live score
        memory.store_scene(OFTEN)
    episodes = EpisodeMemory(store, clock=lambda: T0, memory_state=live_memory_state(memory))
    episode = episodes.begin("watching")
    assert episode.state_at_begin is not None
    snapshot = {e.cls: e.score for e in episode.state_at_begin.best_classes}
    live = memory.reads.item_scores(alone).raw_score
    assert snapshot[alone.value] == live
    stored = {e.cls: e.score for e in read_memory_state(store).best_classes}
    assert stored[alone.value] > live  # written when ALONE was stored, not updated since
    assert episode.state_at_begin.learned_classes == len(memory.reads.classes())
    assert episode.state_at_begin.episodic_items == len(memory.reads.items())
