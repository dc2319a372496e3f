"""A sleep pass, the memory's one large transaction, is handed to disk in the background once
it has committed, so that the updates after it write into an empty memtable (issue 31: learns
right after a pass no slower than in a settled store)."""

from pathlib import Path

import pytest

from kg import Store
from ontologies.vocab import MEMORY, MEMORY_STATE_INDIVIDUAL, SLEEP_PASS_COUNT
from reasoners.memory import SceneMemory
from reasoners.operations import Sleep, StoreScene

from .conftest import FakeClock, worked_example


def passes_committed(store: Store) -> list[int]:
    """The pass count the store holds, read straight from the underlying store."""
    return [
        int(q.object.value)
        for q in store._store.quads_for_pattern(
            MEMORY_STATE_INDIVIDUAL, SLEEP_PASS_COUNT, None, MEMORY
        )
    ]


@pytest.fixture
def flushes(monkeypatch: pytest.MonkeyPatch) -> list[list[int]]:
    """Each background flush started, as the pass counts the store held at that moment."""
    started: list[list[int]] = []
    real = Store.flush_in_background

    def record(self: Store) -> None:
        started.append(passes_committed(self))
        real(self)

    monkeypatch.setattr(Store, "flush_in_background", record)
    return started


def test_a_sleep_pass_is_flushed_in_the_background_once_committed(
    tmp_path: Path, clock: FakeClock, flushes: list[list[int]]
) -> None:
    store = Store(tmp_path / "store")
    memory = SceneMemory(store, clock=clock)
    memory.store_scene(worked_example())
    assert flushes == []  # an update is not a large write
    memory.sleep()
    assert flushes == [[1]]
    store.close()  # waits for the flush; the directory is free again
    assert passes_committed(Store(tmp_path / "store")) == [1]


def test_a_pass_in_a_batch_is_flushed_after_the_batch_commits(
    tmp_path: Path, clock: FakeClock, flushes: list[list[int]]
) -> None:
    memory = SceneMemory(Store(tmp_path / "store"), clock=clock)
    memory.commit([StoreScene(worked_example()), Sleep(), StoreScene(worked_example())])
    assert flushes == [[1]]


def test_an_in_memory_store_has_nothing_to_flush() -> None:
    store = Store()
    store.flush_in_background()
    assert store._flusher is None
