"""SceneMemory.commit: operations given as values, run in order, written with the caller's own
writes in one transaction, or nothing at all."""

import ast
import datetime as dt
from pathlib import Path

import pytest
from pyoxigraph import Literal, NamedNode, Quad

from kg import Store
from kg.transaction import Transaction
from reasoners.clock import SettableClock
from reasoners.errors import OperationFailedError, UnknownItemError
from reasoners.memory import SceneMemory
from reasoners.operations import AdvanceClock, Pin, Restore, Retrieve, Sleep, StoreScene
from reasoners.results import RetrievalResult, SleepReport, StoreResult

from .conftest import START, plane, sphere, worked_example

REPO = Path(__file__).resolve().parents[3]
CALLER = NamedNode("urn:test:caller")
CALLER_QUAD = Quad(NamedNode("urn:test:s"), NamedNode("urn:test:p"), Literal("o"), CALLER)


def caller_writes() -> Transaction:
    writes = Transaction()
    writes.inserts.append(CALLER_QUAD)
    return writes


def snapshot(store: Store) -> set[str]:
    return {str(q) for q in store.quads()}


@pytest.fixture
def settable() -> SettableClock:
    return SettableClock(real=lambda: START)  # stands at START until advanced


@pytest.fixture
def memory(settable: SettableClock) -> SceneMemory:
    return SceneMemory(Store(), clock=settable)


def test_operations_and_the_callers_writes_land_in_one_transaction(memory: SceneMemory) -> None:
    writes: list[str] = []

    def trace(kind: str, text: str, bindings: object) -> None:
        if kind in ("update", "extend"):
            writes.append(kind)

    two = [sphere("a", 0.29, 0.1, 0.3), sphere("b", 0.31, 0.1, 0.3), plane("p", 0.3, 0.1, 0.1)]
    with memory.store.tracing(trace):
        results = memory.commit(
            [
                StoreScene(worked_example()),
                StoreScene(two),
                Retrieve([("Sphere", "isAboveOf", "Plane")]),
                AdvanceClock(60),
                Sleep(),
            ],
            caller_writes(),
        )
    assert len(writes) == 1
    first, second, retrieved, now, report = results
    assert isinstance(first, StoreResult) and isinstance(second, StoreResult)
    assert first.learned and second.learned  # the second saw the first: a class of its own
    assert isinstance(retrieved, RetrievalResult) and retrieved.recalled is not None
    assert now == START + dt.timedelta(seconds=60)
    assert isinstance(report, SleepReport) and report.at == now
    assert CALLER_QUAD in set(memory.store.quads(graph=CALLER))
    assert len(memory.reads.classes()) == 2


def test_a_failing_operation_writes_nothing_and_names_itself(
    memory: SceneMemory, settable: SettableClock
) -> None:
    learned = memory.store_scene(worked_example()).stored_as
    before, classes = snapshot(memory.store), memory.reads.classes()
    missing = NamedNode("urn:test:missing")
    with pytest.raises(OperationFailedError) as caught:
        memory.commit(
            [StoreScene(worked_example()), AdvanceClock(3600), Pin(learned), Restore(missing)],
            caller_writes(),
        )
    assert caught.value.index == 3
    assert isinstance(caught.value.error, UnknownItemError)
    assert "operations[3]" in str(caught.value) and missing.value in str(caught.value)
    assert snapshot(memory.store) == before  # neither the memory's writes nor the caller's
    assert memory.reads.classes() == classes  # the model is as before the commit
    assert settable() == START  # and so is the clock
    assert memory.commit([Pin(learned)]) == [None]  # the memory is sound afterwards
    assert memory.reads.item_scores(learned).pinned


def test_the_periodic_sleep_pass_follows_an_update_only_when_asked(memory: SceneMemory) -> None:
    every = memory.policy.sleepEveryUpdates
    scenes = [StoreScene(worked_example())] * every
    memory.commit(scenes)
    assert memory.loaded.model.state.sleep_passes == 0
    memory.commit(scenes[:1], sleep_if_due=True)
    assert memory.loaded.model.state.sleep_passes == 1


def test_the_scene_memory_never_imports_the_api() -> None:
    """The walk of a scene crosses api/ → reasoners/ → kg/ and never climbs back up."""
    climbing = []
    for path in sorted((REPO / "reasoners").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = (
                [a.name for a in node.names]
                if isinstance(node, ast.Import)
                else [node.module or ""]
                if isinstance(node, ast.ImportFrom)
                else []
            )
            climbing += [
                f"{path.relative_to(REPO)}: {n}" for n in names if n.split(".")[0] == "api"
            ]
    assert climbing == []
