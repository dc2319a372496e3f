"""Property tests: own-class membership, transitive reduction, score bounds, pinning, restore,
and the signature -> OWL -> signature round trip."""

import json
import random
from dataclasses import replace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import NamedNode

from kg import Store
from ontologies.vocab import PRIMITIVE_LEAF_TYPES, engram
from reasoners import persist
from reasoners.errors import InvalidSceneError
from reasoners.memory import SceneMemory
from reasoners.model import MemoryModel
from reasoners.reads import best_recognition, ordered_recognitions
from reasoners.records import ClassRecord
from reasoners.signature import Signature

from .conftest import START, FakeClock, random_scene
from .test_forgetting import set_policy

SETTINGS = settings(
    max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


def stored_memory(seed: int, count: int) -> tuple[SceneMemory, list, FakeClock]:
    clock = FakeClock(START)
    memory = SceneMemory(Store(), clock=clock)
    rng = random.Random(seed)
    results = []
    for _ in range(count):
        scene = random_scene(rng)
        if memory.encoder.signature(scene).complexity:
            results.append((scene, memory.store_scene(scene)))
        clock.advance(minutes=rng.randint(1, 90))
    return memory, results, clock


@SETTINGS
@given(seed=st.integers(0, 10_000), count=st.integers(1, 25))
def test_a_scene_always_belongs_to_the_class_it_was_stored_as(seed: int, count: int) -> None:
    memory, results, _ = stored_memory(seed, count)
    for scene, result in results:
        assert result.stored_as in {r.cls for r in memory.recognise(scene)}


@SETTINGS
@given(seed=st.integers(0, 10_000), count=st.integers(2, 30))
def test_edges_are_the_transitive_reduction_of_signature_dominance(seed: int, count: int) -> None:
    memory, _, _ = stored_memory(seed, count)
    classes = {c.iri: c.signature for c in memory.reads.classes()}
    below = {  # a ⊏ b: a meets all of b's restrictions and differs
        (a, b) for a in classes for b in classes if a != b and classes[a].satisfies(classes[b])
    }
    reduction = {
        (a, b) for a, b in below if not any((a, c) in below and (c, b) in below for c in classes)
    }
    edges = {(c.iri, p) for c in memory.reads.classes() for p in c.parents}
    assert edges == reduction


@SETTINGS
@given(seed=st.integers(0, 10_000), count=st.integers(1, 25), sleep=st.booleans())
def test_scores_lie_in_the_unit_interval_and_the_best_is_one(
    seed: int, count: int, sleep: bool
) -> None:
    memory, results, _ = stored_memory(seed, count)
    if sleep:
        memory.sleep()
    if not results:
        return
    scores = [c.scores.normalised for c in memory.reads.classes()]
    assert all(0.0 <= s <= 1.0 for s in scores) and max(scores) == 1.0
    items = [memory.reads.item_scores(i).normalised for i in memory.reads.items()]
    assert all(0.0 <= s <= 1.0 for s in items) and max(items) == 1.0


@SETTINGS
@given(seed=st.integers(0, 10_000), count=st.integers(2, 20), data=st.data())
def test_nothing_pinned_is_forgotten_and_restore_gives_back_the_definition(
    seed: int, count: int, data: st.DataObject
) -> None:
    memory, results, clock = stored_memory(seed, count)
    if not results:
        return
    # A harsh policy: everything below the best is WEAK and goes at the first pass.
    set_policy(
        memory.store, weakLevelThreshold=0.99, weakPassesToForget=1, forgetGracePeriodSeconds=0.0
    )
    memory = SceneMemory(memory.store, clock=clock)
    classes = [c.iri for c in memory.reads.classes()]
    pinned = data.draw(st.sets(st.sampled_from(classes)))
    pinned_items = data.draw(st.sets(st.sampled_from(memory.reads.items())))
    for iri in [*pinned, *pinned_items]:
        memory.pin(iri)
    signatures = {c: memory.reads.signature(c) for c in classes}
    clock.advance(hours=1)
    report = memory.sleep()
    assert not set(report.forgotten_classes) & pinned
    assert not set(report.forgotten_items) & pinned_items
    live = {c.iri for c in memory.reads.classes()}
    for item in memory.reads.items():  # semantic and episodic memory stay consistent
        assert memory.reads.item_scores(item).cls in live
    for cls in report.forgotten_classes:
        memory.restore(cls)
        assert memory.reads.signature(cls) == signatures[cls]
    assert {c.iri for c in memory.reads.classes()} == set(classes)
    assert SceneMemory(memory.store, clock=clock).reads.classes() == memory.reads.classes()


keys = st.tuples(
    st.sampled_from(
        [engram(f"{leaf}IsAboveOf") for leaf in ("sphere", "cone", "plane")]
        + [engram("cylinderIsParallelWith")]
    ),
    st.sampled_from(PRIMITIVE_LEAF_TYPES),
)


@SETTINGS
@given(counts=st.dictionaries(keys, st.integers(1, 6), min_size=1, max_size=8))
def test_signature_to_owl_to_signature(counts: dict[tuple[NamedNode, NamedNode], int]) -> None:
    signature = Signature(counts)
    store = Store()
    record = ClassRecord(engram("Scene-7"), signature, 1, 0, 0.5, START, START)
    with store.transaction() as tx:
        persist.write_class(tx, record)
    model = persist.load_model(store)
    assert model.graph.classes[engram("Scene-7")].signature == signature
    assert Signature.from_json(signature.to_json()) == signature
    # rows in any order read back to the same signature, its keys in IRI order
    rows = json.loads(signature.to_json())
    shuffled = Signature.from_json(json.dumps(rows[::-1]))
    assert shuffled == signature and list(shuffled) == list(signature)
    assert list(signature) == sorted(signature, key=lambda key: (key[0].value, key[1].value))


@pytest.mark.parametrize(
    "text",
    ['[["http://x/p", "http://x/T", 0]]', '[["http://x/p", 5, 1]]', '[["http://x/p"]]', "{"],
)
def test_malformed_signature_json_is_refused(text: str) -> None:
    with pytest.raises(InvalidSceneError, match="signature"):
        Signature.from_json(text)


@SETTINGS
@given(seed=st.integers(0, 10_000), cut=st.integers(1, 12))
def test_a_partial_refresh_makes_every_class_at_least_that_complex_current(
    seed: int, cut: int
) -> None:
    """What ``zeta`` relies on: ``refresh(down_to=d)`` leaves every class of complexity d or
    more with the Z a from-scratch derivation gives, and the full refresh later finishes the
    rest exactly."""
    rng = random.Random(seed)
    leaves = [engram(f"{leaf}IsAboveOf") for leaf in ("sphere", "cone", "plane")]
    model = MemoryModel()
    for number in range(1, 25):
        counts = {
            (rng.choice(leaves), rng.choice(PRIMITIVE_LEAF_TYPES)): rng.randint(1, 3)
            for _ in range(rng.randint(1, 4))
        }
        signature = Signature(counts)
        if model.graph.index.with_signature(signature) is None:
            model.graph.add_class(
                ClassRecord(engram(f"Scene-{number}"), signature, 1, 0, 0.0, START, START)
            )
    model.scores.refresh()
    for record in rng.sample(
        list(model.graph.classes.values()), k=min(6, len(model.graph.classes))
    ):
        model.scores.set_counts(
            record, store=record.store_count + rng.randint(1, 9), retrieve=rng.randint(0, 4)
        )

    scratch = MemoryModel()
    scratch.load(
        [replace(r, z=(0, 0, 0), sums=[0, 0, 0]) for r in model.graph.classes.values()],
        [(child, parent) for child, parents in model.graph.parents.items() for parent in parents],
    )
    model.scores.refresh(down_to=cut)
    for cls, record in model.graph.classes.items():
        if record.signature.complexity >= cut:
            assert record.z == scratch.graph.classes[cls].z, cls
    model.scores.refresh()
    assert {c: r.z for c, r in model.graph.classes.items()} == {
        c: r.z for c, r in scratch.graph.classes.items()
    }


@given(
    st.lists(
        st.tuples(st.integers(1, 4), st.integers(0, 3), st.integers(1, 30)),
        max_size=12,
        unique_by=lambda t: t[2],
    ),
    st.integers(4, 9),
)
def test_the_best_recognition_is_the_first_of_the_ordered_ones(
    classes: list[tuple[int, int, int]], complexity: int
) -> None:
    """What a learn decides on before the write is what the result, ordered alongside the
    write, puts first: ties of complexity and store count go to the smaller IRI."""
    leaf = PRIMITIVE_LEAF_TYPES[0]
    records = [
        ClassRecord(
            engram(f"Scene-{number}"),
            Signature({(engram(f"p{k}"), leaf): 1 for k in range(d)}),
            stores,
            0,
            0.0,
            START,
            START,
        )
        for d, stores, number in classes
    ]
    best = best_recognition(list(records), complexity)
    ordered = ordered_recognitions(list(records), complexity)
    assert best == (ordered[0] if ordered else None)
