"""Reopening reads back exactly the model the writing process held (``persist.load_model``)."""

import random
from operator import attrgetter
from pathlib import Path

from kg import Store
from ontologies.vocab import CLASS_SIGNATURE, MEMORY, PRIMITIVE_LEAF_TYPES, engram
from reasoners import persist
from reasoners.memory import SceneMemory
from reasoners.model import MemoryModel
from reasoners.signature import Signature

from .conftest import FakeClock, plane, random_scene, sphere, worked_example

BIG = [sphere("ball", 0.0, 0.0, 0.3), plane("table", 0.2, 0.2, 0.0), sphere("o", 0.4, 0.4, 0.3)]
SMALL = [sphere("a", 0.0, 0.9, 0.9), sphere("b", 0.5, 0.9, 0.9)]
FIELDS = [
    "graph.classes",
    "graph.parents",
    "graph.children",
    "items.records",
    "items.items_of",
    "trash.classes",
    "trash.items",
    "scores.complexities",
    "items.complexities",
    "scores.store_counts",
    "scores.retrieve_counts",
    "graph.restrictions",
    "graph.stored_restrictions",
    "state.next_class",
    "state.next_item",
    "state.last_sleep_at",
    "state.updates_since_sleep",
    "state.sleep_passes",
    "state.has_state",
]


def model_of(memory: SceneMemory) -> MemoryModel:
    return memory.loaded.model  # the mirror under test; the public API only shows parts of it


def assert_same_model(loaded: MemoryModel, built: MemoryModel) -> None:
    for name in FIELDS:
        assert attrgetter(name)(loaded) == attrgetter(name)(built), name


def test_the_loaded_model_equals_the_one_built_in_the_same_process(
    tmp_path: Path, clock: FakeClock
) -> None:
    memory = SceneMemory(Store(tmp_path / "store"), clock=clock)
    assert_same_model(persist.load_model(memory.store), model_of(memory))  # empty
    rng = random.Random(5)
    for _ in range(20):
        memory.store_scene(BIG)
        clock.advance(seconds=30)
    for _ in range(3):
        memory.retrieve(BIG)
    memory.store_scene(SMALL)
    one = Signature({(engram("sphereIsAboveOf"), PRIMITIVE_LEAF_TYPES[0]): 3})
    [single] = memory.learn_classes([one])
    memory.pin(single)  # a class defined by one restriction, kept through the sleep passes
    memory.store_scene(worked_example())
    for _ in range(12):
        memory.store_scene(random_scene(rng, 2, 5))
        clock.advance(seconds=5)
    big = memory.recognise(BIG)[0].cls
    memory.pin(big)
    [kept] = [i for i in memory.reads.items() if memory.reads.item_scores(i).cls == big][:1]
    memory.pin(kept)
    clock.advance(days=2)
    for _ in range(memory.policy.weakPassesToForget):
        memory.sleep()
    built = model_of(memory)
    assert built.graph.classes and built.items.records
    assert built.trash.classes and built.trash.items  # the trash is read back too
    assert any(len(r.signature) == 1 for r in built.graph.classes.values())  # one-restriction class
    assert any(len(r.signature) > 1 for r in built.graph.classes.values())  # an intersection
    assert any(built.graph.parents.values()) and built.state.last_sleep_at is not None
    assert any(r.pinned for r in built.graph.classes.values())
    assert any(r.pinned for r in built.items.records.values())
    assert any(r.level is not None for r in built.items.records.values())
    assert_same_model(persist.load_model(memory.store, built.scores.weights), built)
    del memory  # closes the store, which one process at a time may open
    reopened = Store(tmp_path / "store")
    assert_same_model(persist.load_model(reopened, built.scores.weights), built)
    assert_same_model(model_of(SceneMemory(reopened, clock=clock)), built)


def test_classes_without_a_signature_annotation_are_read_from_their_definitions(
    tmp_path: Path, clock: FakeClock
) -> None:
    """A store written before ``engram:signature`` existed (or a class whose annotation was
    dropped) opens from the ``owl:intersectionOf`` lists, to the same model."""
    memory = SceneMemory(Store(tmp_path / "store"), clock=clock)
    rng = random.Random(11)
    for _ in range(15):
        memory.store_scene(random_scene(rng, 2, 5))
    one = Signature({(engram("sphereIsAboveOf"), PRIMITIVE_LEAF_TYPES[0]): 2})
    memory.learn_classes([one])
    built = model_of(memory)
    with memory.store.transaction() as tx:
        tx.delete_matching(None, CLASS_SIGNATURE, None, graph=MEMORY)
    assert not list(memory.store.quads(None, CLASS_SIGNATURE, None, MEMORY))
    assert_same_model(persist.load_model(memory.store, built.scores.weights), built)
