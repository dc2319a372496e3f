"""The episodes' snapshots of the scene memory, ranked by the live scores of the running memory.

``episodes`` reads the memory's state from the graph by default, where a class's
``engram:rawScore`` is the one its own last update consolidated; the server
holds the live memory, whose scores are current, and hands this reader to ``EpisodeMemory``.
"""

from episodes.model import ClassEntry, MemorySnapshot
from episodes.snapshot import MemoryState
from kg import Store
from reasoners.memory import SceneMemory

__all__ = ["live_memory_state"]

BEST = 10
"""Classes recorded in a snapshot, as ``episodes.snapshot.read_memory_state`` records."""


def live_memory_state(memory: SceneMemory) -> MemoryState:
    """A reader of ``memory``'s counts and best classes by live raw score ζ."""

    def read(store: Store) -> MemorySnapshot:
        classes, items, best = memory.reads.state(BEST)
        return MemorySnapshot(
            learned_classes=classes,
            episodic_items=items,
            best_classes=tuple(
                ClassEntry(cls=cls.value, score=score, rank=rank)
                for rank, (cls, score) in enumerate(best, start=1)
            ),
        )

    return read
