"""The scene memory end to end: learn, reinforce, structure, retrieve, transactions, restart."""

import threading
from operator import attrgetter
from pathlib import Path

import pytest
from pyoxigraph import Literal, NamedNode

from kg import Store
from ontologies.vocab import (
    EPISODIC,
    EXPERIENCED_SCENE,
    HAPPENED_DURING,
    HAS_PRIMITIVE,
    MEMORY,
    OWL_EQUIVALENT_CLASS,
    OWL_INTERSECTION_OF,
    OWL_MIN_QUALIFIED_CARDINALITY,
    OWL_ON_CLASS,
    OWL_ON_PROPERTY,
    PLANE,
    RDF_FIRST,
    RDF_NIL,
    RDF_REST,
    RDF_TYPE,
    RDFS_SUBCLASSOF,
    RETRIEVE_COUNT,
    SCENE,
    SPHERE,
    STORE_COUNT,
    engram,
)
from reasoners.errors import InvalidSceneError, NotInTrashError, UnknownItemError
from reasoners.memory import SceneMemory
from reasoners.score_view import ScoreView

from .conftest import FakeClock, plane, sphere, worked_example


def definition(store: Store, cls: NamedNode) -> set[tuple[str, str, int]]:
    """The (property, class, n) restrictions of ``cls`` as stored, read straight from triples."""
    [equivalent] = [q.object for q in store.quads(cls, OWL_EQUIVALENT_CLASS, None, MEMORY)]
    [head] = [q.object for q in store.quads(equivalent, OWL_INTERSECTION_OF, None, MEMORY)]
    found = set()
    while head != RDF_NIL:
        [restriction] = [q.object for q in store.quads(head, RDF_FIRST, None, MEMORY)]
        values = {q.predicate: q.object for q in store.quads(restriction, None, None, MEMORY)}
        found.add(
            (
                values[OWL_ON_PROPERTY].value.rsplit("#")[-1],
                values[OWL_ON_CLASS].value.rsplit("#")[-1],
                int(values[OWL_MIN_QUALIFIED_CARDINALITY].value),
            )
        )
        [head] = [q.object for q in store.quads(head, RDF_REST, None, MEMORY)]
    return found


def value(store: Store, subject: NamedNode, prop: NamedNode) -> str:
    [quad] = list(store.quads(subject, prop, None, None))
    return quad.object.value


def snapshot(store: Store) -> set[str]:
    return {str(q) for q in store.quads()}


def test_worked_example_learns_the_reference_class_with_its_inverse_side(
    memory: SceneMemory,
) -> None:
    result = memory.store_scene(worked_example())
    assert result.learned and result.recognised == () and result.confidence == 0.0
    assert definition(memory.store, result.stored_as) == {
        ("sphereIsAboveOf", "Plane", 1),
        ("sphereIsBehindOf", "Plane", 1),
        ("planeIsBelowOf", "Sphere", 1),
        ("planeIsInFrontOf", "Sphere", 1),
    }
    assert len(list(memory.store.quads(result.stored_as, RDFS_SUBCLASSOF, SCENE, MEMORY))) == 1
    types = {q.object for q in memory.store.quads(result.scene_item, RDF_TYPE, None, EPISODIC)}
    assert {EXPERIENCED_SCENE, result.stored_as} <= types
    assert len(list(memory.store.quads(result.scene_item, HAS_PRIMITIVE, None, EPISODIC))) == 2
    assert result.scores.normalised == 1.0


def test_the_same_scene_again_reinforces_its_class(memory: SceneMemory, clock: FakeClock) -> None:
    first = memory.store_scene(worked_example())
    clock.advance(minutes=5)
    again = memory.store_scene(worked_example())
    assert not again.learned
    assert again.stored_as == first.stored_as
    assert again.confidence == 1.0
    assert again.scene_item != first.scene_item
    assert value(memory.store, first.stored_as, STORE_COUNT) == "2"
    assert memory.reads.item_scores(first.stored_as).last_accessed == clock.now


def test_a_scene_close_enough_reinforces_instead_of_learning(memory: SceneMemory) -> None:
    """0.8 <= confidence < 1 reinforces the best class (the originals did nothing)."""
    base = [sphere("a", 0, 0, 0.3), plane("p", 0.3, 0.3, 0)]
    learned = memory.store_scene(base).stored_as
    # a third object far away adds one more relation pair to a scene of complexity 10
    richer = memory.recognise([*base, sphere("b", 0.6, 0.6, 0.6)])
    assert richer and richer[0].cls == learned
    assert 0 < richer[0].confidence < 1


def test_two_spheres_above_one_plane_become_a_child_class(memory: SceneMemory) -> None:
    one = memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)])
    two = memory.store_scene(
        [sphere("s1", 0.29, 0.1, 0.3), sphere("s2", 0.31, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]
    )
    assert two.learned  # confidence 4/11 < 0.8
    assert [r.cls for r in two.recognised] == [one.stored_as]
    assert two.parents == (one.stored_as,)
    edges = {q.triple for q in memory.store.quads(two.stored_as, RDFS_SUBCLASSOF, None, MEMORY)}
    assert {t.object for t in edges} == {SCENE, one.stored_as}


def test_a_class_learned_in_between_replaces_the_edge_it_splits(memory: SceneMemory) -> None:
    top = memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]).stored_as
    far = [sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1), sphere("q", 0.3, 0.1, 0.6)]
    bottom = memory.store_scene([*far, plane("r", 0.9, 0.9, 0.9)]).stored_as
    middle = memory.store_scene(far).stored_as
    summary = {c.iri: c for c in memory.reads.classes()}
    assert summary[bottom].parents == (middle,)
    assert summary[middle].parents == (top,)
    assert summary[top].children == (middle,)
    assert not list(memory.store.quads(bottom, RDFS_SUBCLASSOF, top, MEMORY))


def test_recognise_writes_nothing(memory: SceneMemory) -> None:
    learned = memory.store_scene(worked_example()).stored_as
    before = snapshot(memory.store)
    assert [r.cls for r in memory.recognise(worked_example())] == [learned]
    assert snapshot(memory.store) == before


def test_retrieve_finds_exact_generalisations_specialisations_and_similar(
    memory: SceneMemory,
) -> None:
    above = [("Sphere", "isAboveOf", "Plane")]
    small = memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.9, 0.1, 0.1)])
    full = memory.store_scene(worked_example()).stored_as
    other = memory.store_scene([sphere("a", 0, 0, 0), sphere("b", 0.5, 0, 0)]).stored_as
    classes_before = {c.iri for c in memory.reads.classes()}

    result = memory.retrieve(worked_example(), spread=True)
    assert result.exact == full and result.recalled == full
    assert [g.cls for g in result.generalisations] == []
    assert result.similar[0].cls == full and result.similar[0].similarity == 1.0
    assert other not in {m.cls for m in result.similar}  # nothing in common
    assert result.activation is not None and result.activation[0].cls == full

    partial = memory.retrieve(above)
    assert partial.exact is None
    assert {m.cls for m in partial.specialisations} == {full, small.stored_as}
    assert partial.recalled == partial.specialisations[0].cls
    assert {c.iri for c in memory.reads.classes()} == classes_before  # the cue was never stored
    assert value(memory.store, partial.recalled, RETRIEVE_COUNT) == "1"

    bigger = memory.retrieve([*worked_example(), plane("q", 0.9, 0.9, 0.9)])
    assert full in {g.cls for g in bigger.generalisations}
    assert bigger.recalled == bigger.generalisations[0].cls


def test_retrieval_raises_the_counters_of_the_whole_branch(memory: SceneMemory) -> None:
    parent = memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)])
    child = memory.store_scene(
        [sphere("s1", 0.29, 0.1, 0.3), sphere("s2", 0.31, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]
    )
    result = memory.retrieve(child.signature)
    assert result.exact == child.stored_as
    assert set(result.branch) == {child.stored_as, parent.stored_as}
    for cls in result.branch:
        assert memory.reads.item_scores(cls).retrieve_count == 1


def test_episode_link(memory: SceneMemory) -> None:
    episode = NamedNode("https://w3id.org/engram/episode/demo-1")
    item = memory.store_scene(worked_example(), episode=episode).scene_item
    assert value(memory.store, item, HAPPENED_DURING) == episode.value


@pytest.mark.parametrize(
    ("scene", "error", "fragment"),
    [
        ([sphere("a", 0, 0, 0)], InvalidSceneError, "got 1 object(s) and no spatial relation"),
        ([], InvalidSceneError, "got 0 object(s)"),
        ([sphere("a", 0, 0, 0), sphere("a", 1, 1, 1)], InvalidSceneError, "'a' more than once"),
        ([sphere("a", 0, 0, 0), ("Sphere", 0, 0, 0)], InvalidSceneError, "expected kg.primitive."),
    ],
)
def test_bad_scenes_change_nothing(
    memory: SceneMemory, scene: list, error: type, fragment: str
) -> None:
    memory.store_scene(worked_example())
    before = snapshot(memory.store)
    with pytest.raises(error) as caught:
        memory.store_scene(scene)
    assert fragment in str(caught.value)
    assert snapshot(memory.store) == before


@pytest.mark.parametrize("call", ["pin", "reads.item_scores", "reads.signature"])
def test_unknown_iris_are_refused_clearly(memory: SceneMemory, call: str) -> None:
    with pytest.raises(UnknownItemError, match="expected a learned scene class"):
        attrgetter(call)(memory)(engram("Scene-99"))


def test_restore_refuses_what_is_not_in_the_trash(memory: SceneMemory) -> None:
    learned = memory.store_scene(worked_example()).stored_as
    with pytest.raises(NotInTrashError, match="expected an IRI in the trash"):
        memory.restore(learned)


def test_a_clock_without_time_zone_is_refused(memory: SceneMemory, clock: FakeClock) -> None:
    clock.now = clock.now.replace(tzinfo=None)
    with pytest.raises(ValueError, match="expected a timezone-aware datetime"):
        memory.store_scene(worked_example())
    assert memory.reads.classes() == []


def test_failure_after_the_store_step_leaves_the_store_and_the_memory_unchanged(
    memory: SceneMemory, monkeypatch: pytest.MonkeyPatch
) -> None:
    memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)])
    before, classes_before = snapshot(memory.store), memory.reads.classes()

    def broken(*args: object) -> None:
        raise RuntimeError("power cut during consolidation")

    monkeypatch.setattr(ScoreView, "rescore", broken)
    two = [sphere("s1", 0.29, 0.1, 0.3), sphere("s2", 0.31, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]
    with pytest.raises(RuntimeError, match="power cut"):
        memory.store_scene(two)
    with pytest.raises(RuntimeError, match="power cut"):
        memory.retrieve([("Sphere", "isAboveOf", "Plane")])
    assert snapshot(memory.store) == before
    assert memory.reads.classes() == classes_before
    monkeypatch.undo()
    assert memory.store_scene(two).stored_as == engram("Scene-2")


def test_a_reopened_disk_store_rebuilds_the_index(tmp_path: Path, clock: FakeClock) -> None:
    store = Store(tmp_path / "store")
    memory = SceneMemory(store, clock=clock)
    one = memory.store_scene([sphere("s", 0.3, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]).stored_as
    two_scene = [
        sphere("s1", 0.29, 0.1, 0.3),
        sphere("s2", 0.31, 0.1, 0.3),
        plane("p", 0.3, 0.1, 0.1),
    ]
    two = memory.store_scene(two_scene).stored_as
    memory.retrieve([("Sphere", "isAboveOf", "Plane")])
    memory.sleep()
    classes = memory.reads.classes()
    del memory, store

    reopened = SceneMemory(Store(tmp_path / "store"), clock=clock)
    assert reopened.reads.classes() == classes
    assert [r.cls for r in reopened.recognise(two_scene)] == [two, one]
    third = reopened.store_scene(worked_example())
    assert third.stored_as == engram("Scene-3") and third.scene_item == engram("experience-3")


def test_concurrent_stores_are_serialised(memory: SceneMemory) -> None:
    scenes = [[sphere("a", 0, 0, 0.1 * k), plane("p", 0.3, 0.3, 0)] for k in range(1, 5)] + [
        worked_example()
    ]
    errors: list[BaseException] = []

    def worker(k: int) -> None:
        try:
            for i in range(6):
                memory.store_scene(scenes[(k + i) % len(scenes)])
                memory.retrieve([("Sphere", "isAboveOf", "Plane")])
        except BaseException as error:  # pragma: no cover - reported below
            errors.append(error)

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []
    assert len(memory.reads.items()) == 24
    assert sum(c.scores.store_count for c in memory.reads.classes()) == 24
    assert memory.reads.classes() == SceneMemory(memory.store).reads.classes()


def test_sleep_levels_and_score_bounds(memory: SceneMemory, clock: FakeClock) -> None:
    for _ in range(5):
        memory.store_scene(worked_example())
    memory.store_scene([sphere("a", 0, 0, 0), sphere("b", 0.5, 0, 0)])
    report = memory.sleep()
    scores = [c.scores for c in memory.reads.classes()]
    assert max(s.normalised for s in scores) == 1.0
    assert all(0.0 <= s.normalised <= 1.0 for s in scores)
    assert {s.iri: s.stored_level for s in scores} == report.levels
    assert set(report.levels.values()) <= {"HIGH", "LOW", "WEAK"}


def test_maybe_sleep_runs_when_the_interval_has_passed(
    memory: SceneMemory, clock: FakeClock
) -> None:
    assert memory.maybe_sleep() is None
    memory.store_scene(worked_example())
    assert memory.maybe_sleep() is None
    clock.advance(seconds=memory.policy.sleepIntervalSeconds + 1)
    report = memory.maybe_sleep()
    assert report is not None and report.at == clock.now
    assert memory.maybe_sleep() is None  # nothing happened since


def test_scores_stay_in_the_unit_interval_for_items(memory: SceneMemory, clock: FakeClock) -> None:
    items = [memory.store_scene(worked_example()).scene_item]
    clock.advance(hours=30)
    items.append(memory.store_scene(worked_example()).scene_item)
    old, new = (memory.reads.item_scores(i) for i in items)
    assert new.normalised == 1.0
    assert 0.0 <= old.normalised < new.normalised
    assert old.cls == new.cls == memory.reads.classes()[0].iri


def test_literal_counts_in_the_store_are_integers(memory: SceneMemory) -> None:
    cls = memory.store_scene(worked_example()).stored_as
    [quad] = list(memory.store.quads(cls, STORE_COUNT, None, MEMORY))
    assert quad.object == Literal(1)
    assert (SPHERE, PLANE) != (PLANE, SPHERE)
