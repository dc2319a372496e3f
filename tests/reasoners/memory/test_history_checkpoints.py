"""History checkpoints: "as of T" read from the latest checkpoint and its epoch's journal gives
the answer of the full scan, and of the SPARQL, whatever happened and whenever T is."""

import contextlib
import datetime as dt
import itertools
import random
import re
from pathlib import Path
from unittest import mock

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import Literal, NamedNode

from kg import Store
from kg.transaction import Transaction
from ontologies.vocab import (
    CHECKPOINT_STATE,
    CHECKPOINT_SUMMARY,
    EVENT_CLASS,
    EVENT_KIND,
    EVENT_LEVEL,
    EVENT_SCORE,
    EVENT_STATE,
    HISTORY,
    HISTORY_ENTRY,
    HISTORY_NS,
    HISTORY_PASS_EVENTS,
    PROV_AT_TIME,
)
from reasoners import history
from reasoners.errors import UnknownItemError
from reasoners.memory import SceneMemory

from .conftest import START, FakeClock, random_scene
from .test_forgetting import set_policy

SETTINGS = settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)


def checkpoint_times(store: Store) -> list[dt.datetime]:
    nodes = {q.subject for q in store.quads(None, CHECKPOINT_SUMMARY, None, HISTORY)}
    return [
        dt.datetime.fromisoformat(q.object.value)  # type: ignore[union-attr]
        for node in nodes
        for q in store.quads(node, PROV_AT_TIME, None, HISTORY)  # type: ignore[arg-type]
    ]


def to_legacy(store: Store) -> None:
    """Rewrite the history as a store from before checkpoints held it: each class event's state
    on the event (``engram:eventState``), no journal, no checkpoint."""
    with store.transaction() as tx:
        for quad in store.quads(None, HISTORY_ENTRY, None, HISTORY):
            tail, state = quad.object.value.split(" ", 1)  # type: ignore[union-attr]
            tx.insert(NamedNode(HISTORY_NS + tail), EVENT_STATE, Literal(state), HISTORY)
            tx.delete(quad.subject, quad.predicate, quad.object, HISTORY)  # type: ignore[arg-type]
        for quad in store.quads(None, HISTORY_PASS_EVENTS, None, HISTORY):
            for event, line in pass_events(quad.object):  # each an event node then
                _, kind, level, score, cls = line.split(" ")
                write_event(tx, event, NamedNode(cls), kind, float(score), level)
                tx.insert(event, EVENT_STATE, Literal(line.split(" ", 1)[1]), HISTORY)
            tx.delete(quad.subject, quad.predicate, quad.object, HISTORY)  # type: ignore[arg-type]
        for predicate in (CHECKPOINT_SUMMARY, CHECKPOINT_STATE, PROV_AT_TIME):
            for quad in store.quads(None, predicate, None, HISTORY):
                if "checkpoint-" in quad.subject.value:  # type: ignore[union-attr]
                    tx.delete(quad.subject, predicate, quad.object, HISTORY)  # type: ignore[arg-type]


def assert_same_answers(store: Store, times: list[dt.datetime], rng: random.Random) -> None:
    for at in times:
        fast = history.as_of(store, at)
        assert fast == history.as_of(store, at, use_checkpoints=False), at
    # the SPARQL, independent of both: on the history as it is (a sleep pass's events are lines
    # of one text per pass, which the query parses) and as it was written when they were nodes
    nodes = as_event_nodes(store)
    for at in rng.sample(times, min(6, len(times))):
        got = [(s.cls.value, s.last_event, s.score, s.level) for s in history.as_of(store, at)]
        assert sparql_as_of(store, at) == got, at
        assert sparql_as_of(nodes, at) == got, at


def sparql_as_of(store: Store, at: dt.datetime) -> list[tuple[str, str, float | None, str | None]]:
    """The analysts' as-of query's answer, as (class, last event, score, level) by class."""
    rows = store.select("history_as_of", asOf=history._time_literal(at))
    return sorted(
        (r["class"].value, r["kind"].value, _float(r.get("score")), _text(r.get("level")))
        for r in rows
    )


def _float(term: object) -> float | None:
    return float(term.value) if isinstance(term, Literal) else None


def _text(term: object) -> str | None:
    return term.value if isinstance(term, Literal) else None


def as_event_nodes(store: Store) -> Store:
    """The history graph as it was written when a sleep pass's events were nodes: each line of
    a pass's literal as an event of its own (its IRI sorts where the pass's does)."""
    nodes = Store()
    with nodes.transaction() as tx:
        for quad in store.quads(None, None, None, HISTORY):
            tx.insert(quad.subject, quad.predicate, quad.object, HISTORY)  # type: ignore[arg-type]
        for quad in store.quads(None, HISTORY_PASS_EVENTS, None, HISTORY):
            for event, line in pass_events(quad.object):
                _, kind, level, score, cls = line.split(" ")
                write_event(tx, event, NamedNode(cls), kind, float(score), level)
    return nodes


def pass_events(text: object) -> list[tuple[NamedNode, str]]:
    """The lines of a pass's literal, each with an event IRI of its own that sorts where the
    pass's does."""
    lines = history.pass_entries(text)
    return [
        (NamedNode(f"{HISTORY_NS}{line.split()[0]}-{n:06d}"), line) for n, line in enumerate(lines)
    ]


def write_event(
    tx: Transaction, event: NamedNode, cls: NamedNode, kind: str, score: float, level: str
) -> None:
    moment = dt.datetime.fromtimestamp(int(event.value[len(HISTORY_NS) :][:13]) / 1000, dt.UTC)
    tx.insert(event, EVENT_CLASS, cls, HISTORY)
    tx.insert(event, EVENT_KIND, Literal(kind), HISTORY)
    tx.insert(event, PROV_AT_TIME, history._time_literal(moment), HISTORY)
    tx.insert(event, EVENT_SCORE, Literal(score), HISTORY)
    tx.insert(event, EVENT_LEVEL, Literal(level), HISTORY)


@SETTINGS
@given(seed=st.integers(0, 1_000_000), steps=st.integers(10, 60), legacy_at=st.integers(-1, 60))
def test_as_of_with_checkpoints_is_the_full_scan(seed: int, steps: int, legacy_at: int) -> None:
    rng = random.Random(seed)
    clock = FakeClock()
    store = Store()
    SceneMemory(store, clock=clock)  # loads the T-Box
    set_policy(
        store,
        weakLevelThreshold=rng.choice([0.2, 0.4, 0.6]),
        weakPassesToForget=rng.choice([1, 2]),
        forgetGracePeriodSeconds=0.0,
    )
    memory = SceneMemory(store, clock=clock)
    scenes = [random_scene(rng, 2, 3) for _ in range(8)]
    times = [START - dt.timedelta(seconds=1)]
    with mock.patch.object(history, "CHECKPOINT_MIN_EVENTS", rng.choice([1, 3, 8])):
        for step in range(steps):
            if step == legacy_at:  # a store from before checkpoints, reopened by this code
                to_legacy(store)
                memory = SceneMemory(store, clock=clock)
            # time moves on, stands still, and now and then goes back a little
            delta = rng.choice([0, 0, 1, 60, 3600, 86_400, -1, -120])
            clock.advance(milliseconds=rng.randint(0, 999), seconds=delta)
            action = rng.random()
            if action < 0.35:
                memory.store_scene(rng.choice(scenes))
            elif action < 0.45:
                memory.retrieve(rng.choice(scenes))
            elif action < 0.75:
                memory.sleep()
            elif action < 0.82 and memory.reads.trash():
                with contextlib.suppress(UnknownItemError):  # a scene whose class is trashed
                    memory.restore(rng.choice(memory.reads.trash()))
            elif action < 0.87 and memory.reads.classes():
                cls = rng.choice(memory.reads.classes()).iri
                memory.pin(cls, rng.random() < 0.5)
            elif action < 0.92:  # a restart: the epoch is read back from the store
                memory = SceneMemory(store, clock=clock)
            elif action < 0.96:  # a batch the caller never commits writes nothing
                try:
                    with memory.transactions.batch():
                        memory.store_scene(rng.choice(scenes))
                        memory.sleep()
                        raise RuntimeError("rolled back")
                except RuntimeError:
                    pass
            else:  # a batch the caller commits
                with memory.transactions.batch() as writes:
                    memory.store_scene(rng.choice(scenes))
                    memory.sleep()
                    with store.transaction() as tx:
                        writes.copy_into(tx)
            times.append(clock.now)
    marks = checkpoint_times(store)
    around = [t + dt.timedelta(milliseconds=d) for t in [*times, *marks] for d in (-1, 0, 1)]
    between = [t + (u - t) / 2 for t, u in itertools.pairwise(times)]
    assert_same_answers(store, sorted(set(around + between)), rng)


def test_a_sleep_pass_writes_a_checkpoint_once_the_epoch_is_large_enough(
    memory: SceneMemory, clock: FakeClock
) -> None:
    rng = random.Random(7)
    with mock.patch.object(history, "CHECKPOINT_MIN_EVENTS", 4):
        memory.sleep()
        assert checkpoint_times(memory.store) == []  # nothing happened: no checkpoint
        while len(list(memory.store.quads(None, HISTORY_ENTRY, None, HISTORY))) < 4:
            clock.advance(seconds=1)
            memory.store_scene(random_scene(rng))
        clock.advance(seconds=1)
        memory.sleep()
        assert checkpoint_times(memory.store) == [clock.now]
        assert history.current_epoch(memory.store) == 1
        memory.sleep()  # the new epoch holds too few events
        assert len(checkpoint_times(memory.store)) == 1
        before = {s.cls for s in history.as_of(memory.store, clock.now)}
        reopened = SceneMemory(memory.store, clock=clock)
        clock.advance(seconds=1)
        reopened.store_scene(random_scene(rng))
        epochs = {q.subject for q in memory.store.quads(None, HISTORY_ENTRY, None, HISTORY)}
        assert NamedNode(f"{HISTORY_NS}epoch-1") in epochs  # after the restart too
        assert before <= {s.cls for s in history.as_of(memory.store, clock.now)}


def test_an_old_history_gets_a_checkpoint_at_the_next_sleep_pass(
    memory: SceneMemory, clock: FakeClock
) -> None:
    rng = random.Random(3)
    for _ in range(5):
        clock.advance(seconds=1)
        memory.store_scene(random_scene(rng))
    at = clock.now
    expected = history.as_of(memory.store, at)
    to_legacy(memory.store)
    assert history.as_of(memory.store, at) == expected  # the full scan reads the old states
    reopened = SceneMemory(memory.store, clock=clock)
    clock.advance(seconds=1)
    reopened.sleep()
    assert len(checkpoint_times(memory.store)) == 1
    assert history.as_of(memory.store, at) == expected


def test_the_readme_as_of_query_is_the_memory_s(memory: SceneMemory, clock: FakeClock) -> None:
    """The README's SPARQL (the time written in) answers as ``history_as_of.rq``, level changes
    of sleep passes included."""
    readme = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")
    [query] = [q for q in re.findall(r"```sparql\n(.*?)```", readme, re.S) if "PassEvents" in q]
    rng = random.Random(11)
    for _ in range(6):
        clock.advance(seconds=1)
        memory.store_scene(random_scene(rng, 2, 3))
    clock.advance(days=1)
    memory.sleep()
    at = clock.now
    written_in = query.replace("2026-03-02T12:00:00Z", history._time_literal(at).value)
    rows = memory.store._select(written_in, {})
    answer = sorted(
        (r["class"].value, r["kind"].value, _float(r.get("score")), _text(r.get("level")))
        for r in rows
    )
    assert answer == sparql_as_of(memory.store, at)
    assert {kind for _, kind, _, _ in answer} == {"level"}  # the pass's lines, read by SPARQL
