"""Explanations derived on demand: recognition, learning, placement, level, forgetting, restore."""

import pytest
from pyoxigraph import NamedNode

from kg import Store, ensure_ontology
from kg.primitive import Primitive
from reasoners.errors import UnknownItemError
from reasoners.explain import (
    ForgettingExplanation,
    LearningExplanation,
    LevelExplanation,
    PlacementExplanation,
    RecognitionExplanation,
    RestoreExplanation,
    explain,
    explain_subsumption,
    to_jsonable,
)
from reasoners.memory import SceneMemory

from .conftest import FakeClock, plane, sphere
from .test_forgetting import set_policy

SMALL = [sphere("ball", 0.3, 0.3, 0.3), plane("table", 0.3, 0.1, 0.1)]
BIG = [*SMALL, sphere("orange", 0.3, 0.3, 0.5)]
LONE = [sphere("a", 0.0, 0.9, 0.9), sphere("b", 0.5, 0.9, 0.9)]


def cone(name: str, x: float, y: float, z: float) -> Primitive:
    return Primitive(name, "Cone", centre=(x, y, z), axis=(0, 0, 1), radius=0.05, height=0.1)


def test_a_first_class_was_learned_because_nothing_was_known(memory: SceneMemory) -> None:
    stored = memory.store_scene(SMALL)
    learning, placement, level = explain(memory, stored.stored_as)
    assert isinstance(learning, LearningExplanation) and learning.best is None
    assert learning.words.endswith("I knew none.")
    assert isinstance(placement, PlacementExplanation) and placement.parents == ()
    assert isinstance(level, LevelExplanation) and level.level == "HIGH"


def test_learning_names_the_best_class_and_the_confidence_arithmetic(
    memory: SceneMemory,
) -> None:
    small = memory.store_scene(SMALL).stored_as
    big = memory.store_scene(BIG)
    assert big.learned
    learning = explain(memory, big.stored_as)[0]
    assert isinstance(learning, LearningExplanation)
    assert learning.best == small.value
    assert (learning.best_complexity, learning.complexity) == (4, big.signature.complexity)
    assert learning.best_confidence == pytest.approx(big.confidence)
    assert f"4/{big.signature.complexity}" in learning.words
    assert "below the learn threshold 0.8" in learning.words


def test_a_scene_learned_from_is_explained_by_its_class_learning(memory: SceneMemory) -> None:
    memory.store_scene(SMALL)
    big = memory.store_scene(BIG)
    scene = explain(memory, big.scene_item)[0]
    assert isinstance(scene, LearningExplanation)
    assert scene.cls == big.stored_as.value and scene.scene == big.scene_item.value


def test_a_reinforcing_scene_met_every_restriction_of_its_class(memory: SceneMemory) -> None:
    first = memory.store_scene(BIG)
    again = memory.store_scene(BIG)
    assert not again.learned
    scene = explain(memory, again.scene_item)[0]
    assert isinstance(scene, RecognitionExplanation)
    assert scene.stored_as == first.stored_as.value
    assert all(check.met for check in scene.met)
    assert len(scene.met) == len(first.signature)
    assert scene.confidence == 1.0 and scene.beyond == ()
    assert "Confidence = d(Scene-1) / d(scene) = 10/10 = 1.00" in scene.words


def test_a_scene_with_more_than_its_class_says_what_was_beyond(clock: FakeClock) -> None:
    store = Store()
    ensure_ontology(store)
    set_policy(store, learnThreshold=0.3)
    memory = SceneMemory(store, clock=clock)
    big = memory.store_scene(BIG)
    stored = memory.store_scene([*BIG, cone("hat", 0.9, 0.9, 0.9)])
    assert not stored.learned
    scene = explain(memory, stored.scene_item)[0]
    assert isinstance(scene, RecognitionExplanation)
    assert scene.stored_as == big.stored_as.value and scene.threshold == 0.3
    assert scene.class_complexity == 10 and scene.scene_complexity == stored.signature.complexity
    assert scene.confidence == pytest.approx(stored.confidence)
    assert all(c.met for c in scene.met)
    assert {c.leaf for c in scene.beyond} >= {"Cone"}
    assert "Beyond Scene-1 the scene had" in scene.words


def test_placement_names_the_parent_restrictions_the_child_meets(memory: SceneMemory) -> None:
    small = memory.store_scene(SMALL).stored_as
    big = memory.store_scene(BIG).stored_as
    placement = explain(memory, big)[1]
    assert isinstance(placement, PlacementExplanation)
    [link] = placement.parents
    assert link.parent == small.value
    assert {(c.prop, c.leaf, c.required) for c in link.restrictions} == {
        ("sphereIsAboveOf", "Plane", 1),
        ("sphereIsBehindOf", "Plane", 1),
        ("planeIsBelowOf", "Sphere", 1),
        ("planeIsInFrontOf", "Sphere", 1),
    }
    assert all(c.met for c in link.restrictions)
    assert "Scene-2 is a kind of Scene-1 because it meets every restriction" in placement.words


def test_subsumption_the_other_way_names_the_missing_restrictions(memory: SceneMemory) -> None:
    small = memory.store_scene(SMALL).stored_as
    big = memory.store_scene(BIG).stored_as
    answer = explain_subsumption(memory, small, big)
    assert not answer.is_kind
    assert {c.prop for c in answer.missed} >= {"sphereIsAboveOf", "sphereIsBelowOf"}
    assert answer.words.startswith("Scene-1 is not a kind of Scene-2")
    assert explain_subsumption(memory, big, small).is_kind


def test_level_terms_add_up_to_the_score(memory: SceneMemory) -> None:
    cls = memory.store_scene(SMALL).stored_as
    memory.store_scene(BIG)
    level = explain(memory, cls)[2]
    assert isinstance(level, LevelExplanation)
    scores = memory.reads.item_scores(cls)
    assert sum(level.terms.values()) == pytest.approx(scores.raw_score)
    assert level.normalised == pytest.approx(scores.normalised)
    assert level.level == scores.level


def test_level_of_a_scene_subtracts_the_decay(memory: SceneMemory, clock: FakeClock) -> None:
    item = memory.store_scene(SMALL).scene_item
    clock.advance(hours=5)
    level = explain(memory, item)[1]
    assert isinstance(level, LevelExplanation) and level.terms["decay"] > 0
    others = sum(v for k, v in level.terms.items() if k != "decay")
    assert max(0.0, min(1.0, others - level.terms["decay"])) == pytest.approx(level.zeta)


def test_a_pinned_weak_class_is_kept_and_says_so(memory: SceneMemory, clock: FakeClock) -> None:
    live_a_while(memory)
    lone = memory.store_scene(LONE).stored_as
    memory.pin(lone)
    clock.advance(days=1)
    memory.sleep()
    level = explain(memory, lone)[2]
    assert isinstance(level, LevelExplanation)
    assert level.level == "WEAK" and level.consecutive_weak == 1 and level.pinned
    assert not level.next_pass_forgets and "pinned, so I keep it" in level.words
    memory.pin(lone, False)
    unpinned = explain(memory, lone)[2]
    assert isinstance(unpinned, LevelExplanation) and not unpinned.next_pass_forgets
    memory.sleep()
    after_two = explain(memory, lone)[2]
    assert isinstance(after_two, LevelExplanation) and after_two.next_pass_forgets
    assert "the next sleep pass forgets it" in after_two.words


def live_a_while(memory: SceneMemory) -> None:
    """One scene seen 30 times and recalled 5 times: a scene seen once is WEAK beside it."""
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)


def forget_lone(memory: SceneMemory, clock: FakeClock) -> NamedNode:
    live_a_while(memory)
    lone = memory.store_scene(LONE).stored_as
    clock.advance(days=1)
    for _ in range(memory.policy.weakPassesToForget):
        report = memory.sleep()
    assert report.forgotten_classes == (lone,)
    return lone


def test_forgetting_gives_the_weak_passes_grace_and_pin(
    memory: SceneMemory, clock: FakeClock
) -> None:
    lone = forget_lone(memory, clock)
    forgetting, restore = explain(memory, lone)
    assert isinstance(forgetting, ForgettingExplanation)
    assert forgetting.weak_passes == memory.policy.weakPassesToForget == 3
    assert not forgetting.pinned and forgetting.store_count == 1
    assert forgetting.created is not None
    assert (forgetting.forgotten_at - forgetting.created).total_seconds() > forgetting.grace_s
    assert "WEAK at 3 consecutive sleep passes" in forgetting.words
    assert isinstance(restore, RestoreExplanation) and restore.restorable
    [item] = restore.brings_back
    scene = explain(memory, NamedNode(item))[0]
    assert isinstance(scene, ForgettingExplanation) and scene.with_class == lone.value


def test_restore_is_refused_when_a_live_class_has_the_signature(
    memory: SceneMemory, clock: FakeClock
) -> None:
    lone = forget_lone(memory, clock)
    relearned = memory.store_scene(LONE)
    assert relearned.learned
    restore = explain(memory, lone)[1]
    assert isinstance(restore, RestoreExplanation) and not restore.restorable
    assert "same signature" in restore.words


def test_after_restore_the_class_is_explained_as_live_again(
    memory: SceneMemory, clock: FakeClock
) -> None:
    lone = forget_lone(memory, clock)
    memory.restore(lone)
    kinds = [e.kind for e in explain(memory, lone)]
    assert kinds == ["learning", "placement", "level"]


def test_unknown_iris_are_refused(memory: SceneMemory) -> None:
    with pytest.raises(UnknownItemError, match="expected a learned scene class"):
        explain(memory, NamedNode("https://w3id.org/engram/ontology#Scene-99"))


def test_every_explanation_is_json_with_words(memory: SceneMemory, clock: FakeClock) -> None:
    import json

    lone = forget_lone(memory, clock)
    live = memory.reads.items()[-1]
    for iri in (lone, live, memory.reads.item_scores(live).cls):
        assert iri is not None
        for explanation in explain(memory, iri):
            body = to_jsonable(explanation)
            assert body["kind"] == explanation.kind and body["words"] == explanation.words
            json.dumps(body)


def test_best_equals_the_state_ranking(memory: SceneMemory) -> None:
    import random

    from .conftest import random_scene

    rng = random.Random(3)
    for _ in range(40):
        memory.store_scene(random_scene(rng))
    memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    for count in (1, 3, 10, 100):
        assert memory.reads.best(count) == memory.reads.state(count)[2]
    assert memory.reads.best(0) == []
