"""What the store holds (docs/data-model.md): a sleep pass writes only what cannot be derived;
the WEAK count that forgot an item is the one the trash, the history and /explain give; a store
written before this data model is migrated once when the memory opens."""

import base64
import random
import zlib

from pyoxigraph import Literal, NamedNode, Quad

from kg import Store
from ontologies.vocab import (
    CONSECUTIVE_WEAK_COUNT,
    EPISODIC,
    EVENT_CLASS,
    EVENT_PARENT,
    EVENT_PARENTS,
    HISTORY,
    HISTORY_PASS_ENTRIES,
    HISTORY_PASS_EVENTS,
    LEVEL,
    MEMORY,
    MEMORY_STATE_INDIVIDUAL,
    SCORE_TERM_PROPERTIES,
    SCORE_TERMS,
    SLEEP_LEVELS,
    TRASH,
)
from reasoners import history, persist
from reasoners.explain import explain_forgetting
from reasoners.memory import SceneMemory
from reasoners.score_table import SCALE

from .conftest import FakeClock, random_scene
from .test_forgetting import BIG, SMALL


def quads(store: Store, graph: NamedNode) -> set[Quad]:
    return set(store.quads(None, None, None, graph))


def analyst_scores(store: Store) -> dict[object, tuple[str, str]]:
    rows = store.select("memory_class_scores")
    return {r["class"]: (r["score"].value, r["level"].value) for r in rows}  # type: ignore[union-attr]


def lived(memory: SceneMemory) -> NamedNode:
    """One scene seen 30 times and recalled often, another once (returned: its class)."""
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    return memory.store_scene(SMALL).stored_as


def many_classes(memory: SceneMemory, n: int) -> None:
    rng = random.Random(5)
    while len(memory.reads.classes()) < n:
        try:
            memory.store_scene(random_scene(rng, 2, 4))
        except Exception:  # a scene without relations
            continue


def test_a_sleep_pass_that_moves_every_level_writes_a_few_quads(
    memory: SceneMemory, clock: FakeClock
) -> None:
    """The bench's hard case: one class reinforced many times moves the maxima, so nearly every
    class changes level; the pass writes one history literal and one levels literal, not a
    node or a value per class."""
    many_classes(memory, 40)
    memory.sleep()
    for _ in range(30):
        memory.store_scene(BIG)
    memory.transactions.settle_view()
    levels_before = {c.iri: c.scores.stored_level for c in memory.reads.classes()}
    before = {g: quads(memory.store, g) for g in (MEMORY, EPISODIC, HISTORY)}
    clock.advance(seconds=1)
    report = memory.sleep()
    changed = [c for c, level in report.levels.items() if level != levels_before[c]]
    assert len(changed) >= 20  # the hard case
    after = {g: quads(memory.store, g) for g in (MEMORY, EPISODIC, HISTORY)}
    written = {g: after[g] ^ before[g] for g in after}
    assert len(written[HISTORY]) == 1  # one literal with every level change
    [entries] = written[HISTORY]
    assert len(history.pass_entries(entries.object)) == len(changed)
    for graph in (MEMORY, EPISODIC):  # WEAK counts (and the memory state) only
        assert {q.predicate for q in written[graph] if q.subject != MEMORY_STATE_INDIVIDUAL} <= {
            CONSECUTIVE_WEAK_COUNT
        }
    weak = [q for q in after[MEMORY] | after[EPISODIC] if q.predicate == CONSECUTIVE_WEAK_COUNT]
    assert all(q.object != Literal(0) for q in weak)  # a zero count is not stored
    reopened = SceneMemory(memory.store, clock=clock)  # the levels come back from the literal
    assert {c.iri: c.scores.stored_level for c in reopened.reads.classes()} == report.levels
    assert {i: reopened.reads.item_scores(i).stored_level for i in report.item_levels} == dict(
        report.item_levels
    )
    assert [e.kind for e in history.events(memory.store, changed[0])][-1] == "level"


def test_the_weak_count_that_forgot_a_class_is_the_same_everywhere(
    memory: SceneMemory, clock: FakeClock
) -> None:
    small = lived(memory)
    clock.advance(days=1)
    k = memory.policy.weakPassesToForget
    for _ in range(k):
        report = memory.sleep()
    assert report.forgotten_classes == (small,)
    trash = {q.predicate: q.object for q in memory.store.quads(small, None, None, TRASH)}
    assert trash[CONSECUTIVE_WEAK_COUNT] == Literal(k)
    assert trash[LEVEL] == Literal("WEAK")
    why = explain_forgetting(memory, small)
    assert why.weak_passes == k and f"WEAK at {k} consecutive sleep passes" in why.words
    assert history.events(memory.store, small)[-1].level == "WEAK"
    [item] = [i for i in report.forgotten_items]
    scene = {q.predicate: q.object for q in memory.store.quads(item, None, None, TRASH)}
    assert explain_forgetting(memory, item).weak_passes == int(
        scene.get(CONSECUTIVE_WEAK_COUNT, Literal(0)).value
    )
    assert history.events(memory.store, item)[-1].level == scene[LEVEL].value


def test_a_learned_class_records_its_parents_in_one_literal(memory: SceneMemory) -> None:
    small = memory.store_scene(SMALL).stored_as
    other = memory.store_scene(BIG).stored_as
    both = memory.store_scene([*SMALL, *BIG])
    assert set(both.parents) == {small, other}
    [learned] = [q.subject for q in memory.store.quads(None, EVENT_CLASS, both.stored_as, HISTORY)]
    [listed] = memory.store.quads(learned, EVENT_PARENTS, None, HISTORY)  # type: ignore[arg-type]
    assert sorted(listed.object.value.split()) == sorted([small.value, other.value])
    assert not list(memory.store.quads(None, EVENT_PARENT, None, HISTORY))
    decision = history.learned_decision(memory.store, both.stored_as)
    assert decision is not None and set(decision.parents) == {small, other}


def to_old_layout(memory: SceneMemory) -> None:
    """Rewrite ``memory``'s store as the memory before docs/data-model.md left it: levels on
    each item, packed score terms, zero WEAK counts written, the trash holding the WEAK count
    of the pass before the one that forgot (a scene forgotten with its class: its own),
    parents one triple each."""
    store, m = memory.store, memory.loaded.model
    with store.transaction() as tx:
        tx.delete_matching(MEMORY_STATE_INDIVIDUAL, SLEEP_LEVELS, None, graph=MEMORY)
        for records, graph in ((m.graph.classes, MEMORY), (m.items.records, EPISODIC)):
            for iri, record in records.items():  # type: ignore[attr-defined]
                if record.level is not None:
                    tx.insert(iri, LEVEL, Literal(record.level), graph)
                if not record.weak_count:
                    tx.insert(iri, CONSECUTIVE_WEAK_COUNT, Literal(0), graph)
        for cls, record in m.graph.classes.items():
            for prop in SCORE_TERM_PROPERTIES:
                tx.delete_matching(cls, prop, None, graph=MEMORY)
            packed = " ".join(repr(z / SCALE) for z in record.z)
            tx.insert(cls, SCORE_TERMS, Literal(packed), MEMORY)
        alone = [i for i, t in m.trash.items.items() if t.cls not in m.trash.classes]
        for entry in [*m.trash.classes, *alone]:
            [count] = store.quads(entry, CONSECUTIVE_WEAK_COUNT, None, TRASH)
            tx.delete(entry, CONSECUTIVE_WEAK_COUNT, count.object, TRASH)  # type: ignore[arg-type]
            before = int(count.object.value) - 1
            if before:
                tx.insert(entry, CONSECUTIVE_WEAK_COUNT, Literal(before), TRASH)
        for quad in store.quads(None, EVENT_PARENTS, None, HISTORY):
            tx.delete(quad.subject, quad.predicate, quad.object, HISTORY)  # type: ignore[arg-type]
            for parent in quad.object.value.split():
                tx.insert(quad.subject, EVENT_PARENT, NamedNode(parent), HISTORY)  # type: ignore[arg-type]


def test_an_old_store_is_migrated_once_when_the_memory_opens(clock: FakeClock) -> None:
    memory = SceneMemory(Store(), clock=clock)
    small = lived(memory)
    many_classes(memory, 12)
    both = memory.store_scene([*SMALL, *BIG]).stored_as
    clock.advance(days=1)
    for _ in range(memory.policy.weakPassesToForget):
        memory.sleep()
    assert memory.reads.trashed(small) is not None
    expected_scores = analyst_scores(memory.store)
    expected_classes = memory.reads.classes()
    expected_items = {
        i: memory.reads.item_scores(i)
        for c in expected_classes
        for i in memory.reads.items_of(c.iri)
    }
    parents = history.learned_decision(memory.store, both)
    as_of = history.as_of(memory.store, clock.now)
    new_layout = {g: quads(memory.store, g) for g in (MEMORY, EPISODIC, TRASH)}
    levels = memory.store.quads(MEMORY_STATE_INDIVIDUAL, SLEEP_LEVELS, None, MEMORY)
    expected_levels = persist.read_levels(q.object for q in levels)
    assert len(expected_levels) == len(expected_classes) + len(expected_items)
    to_old_layout(memory)
    assert analyst_scores(memory.store) == {}  # the analysts' query needs typed terms

    migrated = SceneMemory(memory.store, clock=clock)
    assert analyst_scores(memory.store) == expected_scores
    assert migrated.reads.classes() == expected_classes
    assert {i: migrated.reads.item_scores(i) for i in expected_items} == expected_items
    assert history.learned_decision(memory.store, both) == parents  # old parents still read
    assert history.as_of(memory.store, clock.now) == as_of
    levels = memory.store.quads(MEMORY_STATE_INDIVIDUAL, SLEEP_LEVELS, None, MEMORY)
    assert persist.read_levels(q.object for q in levels) == expected_levels
    for graph in (MEMORY, EPISODIC, TRASH):
        unordered = {q for q in new_layout[graph] if q.predicate != SLEEP_LEVELS}
        assert {q for q in quads(memory.store, graph) if q.predicate != SLEEP_LEVELS} == unordered
    assert explain_forgetting(migrated, small).weak_passes == memory.policy.weakPassesToForget

    written: list[str] = []
    with memory.store.tracing(lambda kind, text, _: kind != "query" and written.append(text)):
        again = SceneMemory(memory.store, clock=clock)  # migrated once: nothing to write
        assert again.reads.classes() == expected_classes
    assert written == []


def test_a_history_with_packed_sleep_passes_is_rewritten_as_text_when_the_memory_opens(
    clock: FakeClock,
) -> None:
    memory = SceneMemory(Store(), clock=clock)
    lived(memory)
    many_classes(memory, 12)
    clock.advance(days=1)
    memory.sleep()
    texts = set(memory.store.quads(None, HISTORY_PASS_EVENTS, None, HISTORY))
    assert texts  # the pass changed levels
    at = clock.now
    expected = history.as_of(memory.store, at)
    sparql = memory.store.select("history_as_of", asOf=history._time_literal(at))
    assert {r["level"].value for r in sparql if "level" in r} & {"HIGH", "LOW", "WEAK"}
    with memory.store.transaction() as tx:  # as the previous data model wrote a pass's events
        for quad in texts:
            lines = "\n".join(history.pass_entries(quad.object)).encode()
            packed = Literal(base64.b64encode(zlib.compress(lines)).decode())
            tx.delete(quad.subject, quad.predicate, quad.object, HISTORY)  # type: ignore[arg-type]
            tx.insert(quad.subject, HISTORY_PASS_ENTRIES, packed, HISTORY)  # type: ignore[arg-type]
    assert history.as_of(memory.store, at) == expected  # read as it is

    SceneMemory(memory.store, clock=clock)
    assert set(memory.store.quads(None, HISTORY_PASS_EVENTS, None, HISTORY)) == texts
    assert not list(memory.store.quads(None, HISTORY_PASS_ENTRIES, None, HISTORY))
    assert memory.store.select("history_as_of", asOf=history._time_literal(at)) == sparql
