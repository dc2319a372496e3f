"""Sleep passes, levels, forgetting to the trash, pinning, restoring, consistency."""

import pytest
from pyoxigraph import Literal

from kg import Store
from ontologies.vocab import (
    DEFAULT_POLICY,
    EPISODIC,
    MEMORY,
    OWL_EQUIVALENT_CLASS,
    RDF_TYPE,
    TBOX,
    TRASH,
    engram,
)
from reasoners.errors import RestoreConflictError, UnknownItemError
from reasoners.memory import SceneMemory

from .conftest import FakeClock, plane, sphere, worked_example

BIG = [
    sphere("ball", 0.0, 0.0, 0.3),
    plane("table", 0.2, 0.2, 0.0),
    sphere("orange", 0.4, 0.4, 0.3),
]
SMALL = [sphere("a", 0.0, 0.9, 0.9), sphere("b", 0.5, 0.9, 0.9)]


def set_policy(store: Store, **values: float) -> None:
    with store.transaction() as tx:
        for name, number in values.items():
            tx.delete_matching(DEFAULT_POLICY, engram(name), None, graph=TBOX)
            tx.insert(DEFAULT_POLICY, engram(name), Literal(number), TBOX)


@pytest.fixture
def lived(memory: SceneMemory, clock: FakeClock) -> SceneMemory:
    """A memory where one scene was seen 30 times and recalled often, another once."""
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    memory.store_scene(SMALL)
    return memory


def test_a_weak_class_is_forgotten_after_k_passes_and_the_grace_period(
    lived: SceneMemory, clock: FakeClock
) -> None:
    small = lived.recognise(SMALL)[0].cls
    k = lived.policy.weakPassesToForget
    clock.advance(seconds=lived.policy.forgetGracePeriodSeconds + 1)
    for _ in range(k - 1):
        report = lived.sleep()
        assert report.levels[small] == "WEAK" and report.forgotten_classes == ()
    assert lived.reads.item_scores(small).consecutive_weak == k - 1
    report = lived.sleep()
    assert report.forgotten_classes == (small,)
    [item] = [i for i in report.forgotten_items]
    assert small in lived.reads.trash() and item in lived.reads.trash()
    store = lived.store
    assert not list(store.quads(small, None, None, MEMORY))
    assert not list(store.quads(item, None, None, EPISODIC))
    assert list(store.quads(item, RDF_TYPE, small, TRASH))
    assert lived.recognise(SMALL) == []  # nothing is recognised as a forgotten class
    # consistency: no live experienced scene points at a class that is gone
    live = {c.iri for c in lived.reads.classes()}
    assert all(
        q.object in live or not q.object.value.startswith(engram("Scene-").value)
        for q in store.quads(None, RDF_TYPE, None, EPISODIC)
    )


def test_nothing_is_forgotten_within_the_grace_period(lived: SceneMemory) -> None:
    for _ in range(lived.policy.weakPassesToForget + 2):
        assert lived.sleep().forgotten_classes == ()


def test_pinned_classes_and_classes_of_pinned_scenes_are_kept(
    lived: SceneMemory, clock: FakeClock
) -> None:
    small = lived.recognise(SMALL)[0].cls
    lived.pin(small)
    clock.advance(days=2)
    for _ in range(lived.policy.weakPassesToForget + 1):
        assert small not in lived.sleep().forgotten_classes
    assert lived.reads.item_scores(small).pinned


def test_a_pinned_scene_keeps_its_class(lived: SceneMemory, clock: FakeClock) -> None:
    small = lived.recognise(SMALL)[0].cls
    [item] = [i for i in lived.reads.items() if lived.reads.item_scores(i).cls == small]
    lived.pin(item)
    clock.advance(days=2)
    for _ in range(lived.policy.weakPassesToForget + 1):
        report = lived.sleep()
        assert small not in report.forgotten_classes and item not in report.forgotten_items
    assert lived.reads.item_scores(item).pinned


def test_restore_brings_back_the_same_definition_and_its_scenes(
    lived: SceneMemory, clock: FakeClock
) -> None:
    small = lived.recognise(SMALL)[0].cls
    signature = lived.reads.signature(small)
    before = lived.reads.item_scores(small)
    triples_before = {(q.predicate, q.object) for q in lived.store.quads(small, None, None, MEMORY)}
    clock.advance(days=1)
    for _ in range(lived.policy.weakPassesToForget):
        report = lived.sleep()
    assert small in report.forgotten_classes
    with pytest.raises(UnknownItemError, match="is in the trash; restore it first"):
        lived.pin(small)
    restored = lived.restore(small)
    assert restored[0] == small and len(restored) == 2
    assert lived.reads.signature(small) == signature
    after = lived.reads.item_scores(small)
    assert (after.store_count, after.retrieve_count, after.created) == (
        before.store_count,
        before.retrieve_count,
        before.created,
    )
    assert after.consecutive_weak == 0
    assert [r.cls for r in lived.recognise(SMALL)] == [small]
    assert lived.reads.trash() == []
    triples_after = {(q.predicate, q.object) for q in lived.store.quads(small, None, None, MEMORY)}
    changing = {engram(n) for n in ("level", "consecutiveWeakCount", "score")} | {
        OWL_EQUIVALENT_CLASS  # a fresh skolem node; the definition is compared via the signature
    }
    assert {t for t in triples_before if t[0] not in changing} == {
        t for t in triples_after if t[0] not in changing
    }
    assert not list(lived.store.quads(None, None, None, TRASH))
    assert SceneMemory(lived.store, clock=clock).reads.classes() == lived.reads.classes()


def test_restore_refuses_a_signature_learned_again(lived: SceneMemory, clock: FakeClock) -> None:
    small = lived.recognise(SMALL)[0].cls
    clock.advance(days=1)
    for _ in range(lived.policy.weakPassesToForget):
        lived.sleep()
    relearned = lived.store_scene(SMALL).stored_as
    assert relearned != small
    with pytest.raises(RestoreConflictError, match="same signature as the live class"):
        lived.restore(small)


def test_an_old_scene_can_be_forgotten_while_its_class_stays(clock: FakeClock) -> None:
    store = Store()
    memory = SceneMemory(store, clock=clock)
    old = memory.store_scene(worked_example()).scene_item
    clock.advance(days=30)
    for _ in range(5):
        memory.store_scene(worked_example())
    k = memory.policy.weakPassesToForget
    for _ in range(k):
        report = memory.sleep()
    assert old in report.forgotten_items
    assert report.forgotten_classes == ()
    cls = memory.reads.classes()[0].iri
    assert memory.reads.item_scores(cls).store_count == 6  # the semantic knowledge outlives it
    assert memory.restore(old) == (old,)
    assert memory.reads.item_scores(old).cls == cls


def test_policy_values_are_read_from_the_store(clock: FakeClock) -> None:
    store = Store()
    SceneMemory(store)  # loads the T-Box
    set_policy(store, learnThreshold=0.1, alignedThresholdZ=0.5)
    memory = SceneMemory(store, clock=clock)
    assert memory.policy.learnThreshold == 0.1
    # with z aligned up to 0.5 m the sphere is no longer above the plane
    relations = {
        r.relation.value.rsplit("#")[-1] for r in memory.store_scene(worked_example()).relations
    }
    assert "isAboveOf" not in relations


def test_a_pinned_class_keeps_its_scenes(lived: SceneMemory, clock: FakeClock) -> None:
    small = lived.recognise(SMALL)[0].cls
    [item] = [i for i in lived.reads.items() if lived.reads.item_scores(i).cls == small]
    lived.pin(small)
    clock.advance(days=2)
    for _ in range(lived.policy.weakPassesToForget + 1):
        report = lived.sleep()
        assert item not in report.forgotten_items
    assert item in lived.reads.items()


def test_a_scene_forgotten_alone_is_reported_once_and_comes_back_with_its_class(
    clock: FakeClock,
) -> None:
    store = Store()
    memory = SceneMemory(store, clock=clock)
    old = memory.store_scene(worked_example()).scene_item
    clock.advance(days=30)
    for _ in range(5):
        memory.store_scene(worked_example())
    cls = memory.reads.classes()[0].iri
    k = memory.policy.weakPassesToForget
    reports = [memory.sleep() for _ in range(k)]
    assert old in reports[-1].forgotten_items and reports[-1].forgotten_classes == ()
    # a stronger class, and a policy under which the first class is WEAK: it goes later
    for _ in range(30):
        memory.store_scene(SMALL)
    for _ in range(5):
        memory.retrieve(SMALL)
    set_policy(store, weakLevelThreshold=0.5)
    memory = SceneMemory(store, clock=clock)
    clock.advance(days=2)
    later = [memory.sleep() for _ in range(k)]
    forgotten = [i for report in later for i in report.forgotten_items]
    assert cls in later[-1].forgotten_classes
    assert old not in forgotten, "reported when it was forgotten, not again with its class"
    assert len(forgotten) == len(set(forgotten)) == 5
    restored = memory.restore(cls)
    assert set(restored) == {cls, old, *forgotten}
    assert old in memory.reads.items() and memory.reads.trash() == []
