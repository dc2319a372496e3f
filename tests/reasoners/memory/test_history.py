"""The memory's history: each event recorded with its change, "as of T" rebuilt from it."""

import datetime as dt

import pytest

from kg import Store
from ontologies.vocab import HISTORY
from reasoners import history
from reasoners.memory import SceneMemory

from .conftest import FakeClock, plane, sphere

BIG = [
    sphere("ball", 0.0, 0.0, 0.3),
    plane("table", 0.2, 0.2, 0.0),
    sphere("orange", 0.4, 0.4, 0.3),
]
SMALL = [sphere("a", 0.0, 0.9, 0.9), sphere("b", 0.5, 0.9, 0.9)]


def kinds(memory: SceneMemory, iri: object) -> list[str]:
    return [e.kind for e in history.events(memory.store, iri)]  # type: ignore[arg-type]


def history_quads(store: Store) -> int:
    return sum(1 for _ in store.quads(None, None, None, HISTORY))


def test_every_kind_of_event_is_recorded_with_its_time_score_and_level(
    memory: SceneMemory, clock: FakeClock
) -> None:
    big = memory.store_scene(BIG).stored_as
    clock.advance(seconds=1)
    memory.store_scene(BIG)
    clock.advance(seconds=1)
    memory.retrieve(BIG)
    clock.advance(seconds=1)
    memory.pin(big)
    memory.pin(big, False)
    clock.advance(seconds=1)
    memory.sleep()
    events = history.events(memory.store, big)
    assert [e.kind for e in events] == [
        "learned",
        "reinforced",
        "retrieved",
        "pinned",
        "unpinned",
        "level",
    ]
    assert [e.time for e in events][:3] == [
        "2025-03-01T09:00:00.000+00:00",
        "2025-03-01T09:00:01.000+00:00",
        "2025-03-01T09:00:02.000+00:00",
    ]
    scores = memory.reads.item_scores(big)
    assert events[-1].level == scores.stored_level == "HIGH"
    assert events[-1].score == pytest.approx(scores.raw_score)
    assert events[0].level is None and events[0].score is not None


def test_as_of_rebuilds_the_classes_across_forgetting_and_restore(
    memory: SceneMemory, clock: FakeClock
) -> None:
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    small = memory.store_scene(SMALL).stored_as
    big = memory.recognise(BIG)[0].cls
    learned = clock.now
    clock.advance(days=1)
    for _ in range(memory.policy.weakPassesToForget):
        clock.advance(seconds=10)
        report = memory.sleep()
    assert small in report.forgotten_classes
    forgotten = clock.now
    clock.advance(hours=1)
    memory.restore(small)
    restored = clock.now

    def names(at: dt.datetime) -> dict[str, str | None]:
        return {s.cls.value: s.level for s in history.as_of(memory.store, at)}

    assert history.as_of(memory.store, learned - dt.timedelta(seconds=1)) == []
    assert set(names(learned)) == {big.value, small.value}
    assert names(forgotten) == {big.value: "HIGH"}
    assert names(forgotten - dt.timedelta(seconds=1)) == {big.value: "HIGH", small.value: "WEAK"}
    assert set(names(restored)) == {big.value, small.value}
    [state] = [s for s in history.as_of(memory.store, restored) if s.cls == small]
    assert state.last_event == "restored" and state.score is not None
    assert [e.kind for e in history.events(memory.store, small)][-2:] == ["forgotten", "restored"]
    [item] = memory.reads.items_of(small)
    assert kinds(memory, item) == ["forgotten", "restored"]
    for at in (learned, forgotten - dt.timedelta(seconds=1), forgotten, restored):  # the SPARQL
        rows = memory.store.select("history_as_of", asOf=history._time_literal(at))
        assert sorted(r["class"].value for r in rows) == sorted(names(at))


def test_an_event_is_stored_if_and_only_if_its_change_is(
    memory: SceneMemory, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    big = memory.store_scene(BIG).stored_as
    before = history_quads(memory.store)

    def fail(*args: object, **kwargs: object) -> None:
        raise RuntimeError("disk full")

    monkeypatch.setattr("reasoners.memory.SceneMemory._bump_update", fail)
    with pytest.raises(RuntimeError, match="disk full"):
        memory.store_scene(BIG)  # the event is written before the step that fails
    assert history_quads(memory.store) == before
    assert kinds(memory, big) == ["learned"]
    assert memory.reads.item_scores(big).store_count == 1
    monkeypatch.undo()
    with (
        memory.transactions.batch() as writes
    ):  # a batch the caller never commits records nothing either
        memory.store_scene(BIG)
        assert any(True for _ in writes.quads(memory.store, None, None, None, HISTORY))
    assert kinds(memory, big) == ["learned"]


def test_sleep_records_only_level_changes_and_periodic_rescoring(
    memory: SceneMemory, clock: FakeClock
) -> None:
    for _ in range(5):
        memory.store_scene(BIG)
    memory.store_scene(SMALL)
    memory.sleep()
    after_first = history_quads(memory.store)
    for _ in range(history.RESCORE_EVERY_PASSES - 2):  # nothing changes: nothing recorded
        memory.sleep()
    assert history_quads(memory.store) == after_first
    memory.store_scene(BIG)  # one event of 8 quads; ζ of BIG's class changes
    grown = history_quads(memory.store)
    assert grown - after_first == 8
    memory.sleep()  # the periodic pass: only classes whose ζ changed since the pass before
    assert history_quads(memory.store) - grown <= 5 * 2


def test_history_is_not_in_the_analyst_default_graph() -> None:
    from kg.datasets import NOT_IN_DEFAULT

    assert HISTORY in NOT_IN_DEFAULT


def test_as_of_refuses_a_naive_time(memory: SceneMemory) -> None:
    with pytest.raises(ValueError, match="timezone-aware"):
        history.as_of(memory.store, dt.datetime(2025, 1, 1))


def test_the_learning_decision_is_recorded_as_prov(memory: SceneMemory) -> None:
    small = memory.store_scene(SMALL)
    big = memory.store_scene([*SMALL, *BIG])  # contains SMALL's relations: placed under it
    assert big.learned and big.parents == (small.stored_as,)
    decision = history.learned_decision(memory.store, big.stored_as)
    assert decision is not None
    assert decision.scene == big.scene_item and decision.parents == (small.stored_as,)
    assert decision.best == small.stored_as
    assert decision.confidence == pytest.approx(big.confidence)
    [row] = memory.store.select("history_decision", cls=big.stored_as)  # the same, in SPARQL
    assert (row["scene"], row["best"], row["parents"].value) == (
        decision.scene,
        decision.best,
        small.stored_as.value,
    )
    first = history.learned_decision(memory.store, small.stored_as)
    assert first is not None and first.best is None and first.confidence == 0.0


def test_the_learning_explanation_reads_the_recorded_decision(memory: SceneMemory) -> None:
    from reasoners.explain import explain_learning

    small = memory.store_scene(SMALL)
    big = memory.store_scene([*SMALL, *BIG])
    why = explain_learning(memory, big.stored_as)
    assert why.recorded and why.scene == big.scene_item.value
    assert why.best == small.stored_as.value
    assert why.best_confidence == pytest.approx(big.confidence)
    assert f"fitted its scene with confidence d(Scene-1) / d(scene) = {why.best_complexity}/" in (
        why.words
    )
