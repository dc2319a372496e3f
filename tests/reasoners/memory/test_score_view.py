"""The score view: after any sequence of updates, retrievals and sleep passes, the analysts'
query returns each class's normalised score and level exactly as QUERY MEMORY SCORES does."""

import contextlib
import random
import re
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyoxigraph import Literal, NamedNode

from kg import Store
from ontologies.vocab import (
    LEGACY_LEVEL,
    LEGACY_SCORE,
    MEMORY,
    SCORE_TERM_PROPERTIES,
)
from reasoners.errors import InvalidSceneError
from reasoners.memory import SceneMemory
from reasoners.scoring import rounded

from .conftest import FakeClock, random_scene
from .test_forgetting import BIG, SMALL, set_policy

REPO = Path(__file__).resolve().parents[3]

Op = tuple[str, int]
OPS = st.lists(
    st.tuples(
        st.sampled_from(["store", "store", "store", "retrieve", "sleep", "wait", "pin"]),
        st.integers(0, 10_000),
    ),
    min_size=1,
    max_size=25,
)


def analyst_scores(store: Store) -> dict[NamedNode, tuple[float, str]]:
    rows = store.select("memory_class_scores")
    return {row["class"]: (float(row["score"].value), row["level"].value) for row in rows}  # type: ignore[misc]


def api_scores(memory: SceneMemory) -> dict[NamedNode, tuple[float, str]]:
    return {c.iri: (rounded(c.scores.normalised), c.scores.level) for c in memory.reads.classes()}


def run(memory: SceneMemory, clock: FakeClock, op: Op) -> None:
    kind, seed = op
    rng = random.Random(seed)
    try:
        if kind == "store":
            memory.store_scene(random_scene(rng))
        elif kind == "retrieve":
            memory.retrieve(random_scene(rng, 2, 3))
        elif kind == "sleep":
            memory.sleep()
        elif kind == "pin" and memory.reads.classes():
            memory.pin(rng.choice(memory.reads.classes()).iri)
        else:
            clock.advance(hours=seed % 48)
    except InvalidSceneError:  # a random scene without relations: nothing happens
        pass


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(ops=OPS)
def test_the_analysts_query_agrees_with_the_api_after_every_change(ops: list[Op]) -> None:
    clock = FakeClock()
    store = Store()
    set_policy(store, forgetGracePeriodSeconds=3600.0)  # loads the T-Box first
    memory = SceneMemory(store, clock=clock)
    for op in ops:
        run(memory, clock, op)
        assert analyst_scores(store) == api_scores(memory), op
    # and a memory reopened from the store reads the same view, writing nothing
    before = len(store)
    reopened = SceneMemory(store, clock=clock)
    assert len(store) == before and api_scores(reopened) == api_scores(memory)


def test_untouched_classes_read_their_live_scores_between_sleep_passes() -> None:
    """The issue's repro: a ball on a table, then two cylinders; no sleep pass ran."""
    clock = FakeClock()
    memory = SceneMemory(Store(), clock=clock)
    memory.store_scene(BIG)
    for _ in range(3):
        memory.store_scene(SMALL)
    view = analyst_scores(memory.store)
    assert set(view) == {c.iri for c in memory.reads.classes()} and len(view) == 2
    assert view == api_scores(memory)
    assert {level for _, level in view.values()} <= {"HIGH", "LOW", "WEAK"}


TERMS = "|".join(re.escape(p.value) for p in SCORE_TERM_PROPERTIES)


def _terms_written(texts: list[str]) -> set[NamedNode]:
    found = re.findall(f"<([^>]+)> <(?:{TERMS})>", "\n".join(texts))
    return {NamedNode(iri) for iri in found}


def test_the_view_of_an_update_is_its_branch_written_before_the_next_read() -> None:
    """An update's own transaction writes no score terms; the next read of the store first
    writes those of the stored class and its ancestors, and nothing else. A new maximum
    changes the four values on the memory state, not every class."""
    memory = SceneMemory(Store(), clock=FakeClock())
    for seed in range(60):
        with contextlib.suppress(InvalidSceneError):  # a scene without relations
            memory.store_scene(random_scene(random.Random(seed)))
    assert analyst_scores(memory.store) == api_scores(memory)  # the view written so far
    update: list[str] = []
    with memory.store.tracing(lambda kind, text, _: kind != "query" and update.append(text)):
        result = memory.store_scene(random_scene(random.Random(3)))
    assert update and not _terms_written(update)
    read: list[str] = []
    with memory.store.tracing(lambda kind, text, _: kind != "query" and read.append(text)):
        view = analyst_scores(memory.store)
    branch = {result.stored_as} | memory.loaded.model.graph.ancestors(result.stored_as)
    rewritten = _terms_written(read)
    assert len(memory.reads.classes()) > len(branch) + 5
    assert rewritten and rewritten <= branch, "only the branch's terms are rewritten"
    assert view == api_scores(memory)


def test_the_updates_between_two_reads_write_each_changed_class_once() -> None:
    memory = SceneMemory(Store(), clock=FakeClock())
    scenes = [random_scene(random.Random(seed)) for seed in range(40)]
    written: list[str] = []
    with memory.store.tracing(lambda kind, text, _: kind != "query" and written.append(text)):
        for scene in scenes:
            with contextlib.suppress(InvalidSceneError):
                memory.store_scene(scene)
        view = analyst_scores(memory.store)
    writes = re.findall(f"<(?:{TERMS})>", "\n".join(written))
    assert len(writes) == 3 * len(memory.reads.classes()) == 3 * len(_terms_written(written))
    assert view == api_scores(memory)


def test_an_update_left_unread_by_a_crash_is_in_the_view_when_the_memory_reopens(
    tmp_path: Path,
) -> None:
    """The view is derived: a process that dies between an update and the next read leaves
    terms the reopened memory finds stale and rewrites, in one transaction, before any read."""
    script = f"""
import random, os
from kg import Store
from reasoners.memory import SceneMemory
from tests.reasoners.memory.conftest import random_scene
memory = SceneMemory(Store({str(tmp_path / "store")!r}))
for seed in range(30):
    try:
        memory.store_scene(random_scene(random.Random(seed)))
    except Exception:
        pass
assert memory.transactions.begun > memory.transactions.viewed
memory.store.flush()
os._exit(0)  # no read, no shutdown: the view was never written
"""
    subprocess.run([sys.executable, "-c", script], check=True, cwd=REPO, timeout=120)
    store = Store(tmp_path / "store")
    found = store._store.quads_for_pattern(None, SCORE_TERM_PROPERTIES[0], None, MEMORY)
    terms = {q.subject for q in found}
    memory = SceneMemory(store)
    assert len(terms) < len(memory.reads.classes()), "the crash left the view behind"
    assert analyst_scores(store) == api_scores(memory)


def test_a_store_written_before_the_view_gets_it_when_the_memory_opens() -> None:
    clock = FakeClock()
    store = Store()
    memory = SceneMemory(store, clock=clock)
    memory.store_scene(BIG)
    memory.store_scene(SMALL)
    expected = api_scores(memory)
    memory.transactions.settle_view()
    with store.transaction() as tx:  # as an older Engram left it
        for prop in SCORE_TERM_PROPERTIES:
            tx.delete_matching(None, prop, None, graph=MEMORY)
        tx.insert(memory.reads.classes()[0].iri, LEGACY_SCORE, Literal(0.5), MEMORY)
        tx.insert(memory.reads.classes()[0].iri, LEGACY_LEVEL, Literal("HIGH"), MEMORY)
    assert analyst_scores(store) == {}
    reopened = SceneMemory(store, clock=clock)
    assert analyst_scores(store) == expected == api_scores(reopened)
    assert not list(store.quads(None, LEGACY_SCORE, None, None))


@pytest.mark.parametrize("value", [0.0, 0.2, 0.6, 1.0, 0.4472135955, 1 / 3, 0.0000005])
def test_rounding_matches_sparql_round(value: float) -> None:
    text = "SELECT (ROUND(?x * 1000000) / 1000000 AS ?r) WHERE {}"
    rows = Store().query_graphs(text, graphs=[MEMORY], bindings={"x": Literal(value)})
    [row] = list(rows)  # type: ignore[call-overload]
    assert float(row["r"].value) == rounded(value)


def test_readers_beside_writers_see_every_update_that_returned_before_they_read() -> None:
    """Writer threads store scenes and each reads the analysts' query after every update:
    its class is there (the view written for it, by the writer in progress or by the reader);
    reader threads query all along; nothing deadlocks and the view ends equal to the API."""
    memory = SceneMemory(Store(), clock=FakeClock())
    errors: list[BaseException] = []
    stop = threading.Event()

    def writer(first: int) -> None:
        try:
            for seed in range(first, first + 15):
                try:
                    stored = memory.store_scene(random_scene(random.Random(seed))).stored_as
                except InvalidSceneError:
                    continue
                assert stored in analyst_scores(memory.store)
        except BaseException as error:
            errors.append(error)

    def reader() -> None:
        try:
            while not stop.is_set():
                analyst_scores(memory.store)
        except BaseException as error:
            errors.append(error)

    writers = [threading.Thread(target=writer, args=(n * 100,)) for n in range(3)]
    readers = [threading.Thread(target=reader) for _ in range(2)]
    for thread in writers + readers:
        thread.start()
    for thread in writers:
        thread.join(timeout=120)
    stop.set()
    for thread in readers:
        thread.join(timeout=30)
    assert not any(t.is_alive() for t in writers + readers), "a reader or writer is stuck"
    assert not errors, errors
    assert analyst_scores(memory.store) == api_scores(memory)
