"""Reinforcing a known class: the exact class is found by its signature, and the list of every
class the scene belongs to, which only the result needs, is built while the store writes."""

import random
import threading
from collections.abc import Callable

import pytest

from kg import Store
from kg.transaction import Transaction
from reasoners.memory import SceneMemory
from reasoners.operations import StoreScene

from .conftest import FakeClock, random_scene


@pytest.fixture
def memory_with_forty_scenes(clock: FakeClock) -> tuple[SceneMemory, list[list]]:  # type: ignore[type-arg]
    memory = SceneMemory(Store(), clock=clock)
    rng = random.Random(31)
    scenes = [random_scene(rng, 2, 5) for _ in range(40)]
    for scene in scenes:
        try:
            memory.store_scene(scene)
        except Exception:  # a scene without relations
            continue
    return memory, scenes


def test_a_reinforce_lists_the_classes_as_recognise_did_before_it(
    memory_with_forty_scenes: tuple[SceneMemory, list[list]],  # type: ignore[type-arg]
) -> None:
    memory, scenes = memory_with_forty_scenes
    checked = 0
    for scene in scenes:
        try:
            before = memory.recognise(scene)
        except Exception:
            continue
        result = memory.store_scene(scene)
        assert not result.learned and result.confidence == 1.0
        assert result.recognised == tuple(before)
        assert result.stored_as == before[0].cls
        checked += 1
    assert checked > 20


def test_a_reinforce_in_a_batch_lists_the_classes_too(
    memory_with_forty_scenes: tuple[SceneMemory, list[list]],  # type: ignore[type-arg]
) -> None:
    memory, scenes = memory_with_forty_scenes
    scene = next(s for s in scenes if len(memory.recognise(s)) > 1)
    before = memory.recognise(scene)
    (result,) = memory.commit([StoreScene(scene)])
    assert result.recognised == tuple(before)


def test_work_handed_to_while_writing_runs_while_the_store_writes() -> None:
    store = Store()
    memory = SceneMemory(store)
    work_ran = threading.Event()
    seen: list[bool] = []
    prepare = store._prepare

    def slow_prepare(tx: Transaction) -> Callable[[], None]:
        write = prepare(tx)

        def waiting_write() -> None:
            seen.append(work_ran.wait(timeout=10))  # False if the work waits for the write
            write()

        return waiting_write

    store._prepare = slow_prepare  # type: ignore[method-assign]
    with memory.transactions.write(refresh_alongside=True):
        memory.transactions.while_writing(work_ran.set)
    assert seen == [True]


def test_a_failing_while_writing_step_rebuilds_the_model(
    memory_with_forty_scenes: tuple[SceneMemory, list[list]],  # type: ignore[type-arg]
) -> None:
    memory, _ = memory_with_forty_scenes
    classes = memory.reads.classes()

    def fail() -> None:
        raise RuntimeError("boom")

    with (
        pytest.raises(RuntimeError, match="boom"),
        memory.transactions.write(refresh_alongside=True),
    ):
        memory.transactions.while_writing(fail)
    assert memory.reads.classes() == classes
    # in a batch: at the block's end
    with (
        pytest.raises(RuntimeError, match="boom"),
        memory.transactions.batch(),
        memory.transactions.write(),
    ):
        memory.transactions.while_writing(fail)
    assert memory.reads.classes() == classes
