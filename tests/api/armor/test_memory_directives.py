"""A scripted perception client sends ten scenes through LOAD INIT … SCENE UPDATED."""

import datetime as dt
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import httpx
import pytest
from pyoxigraph import NamedNode

from api.armor import ArmorEngine
from api.client import ArmorClient, ArmorServiceInternalError, Primitive, primitive_directives
from api.protocol import ArmorDirectiveReq
from kg import Store
from kg.transaction import Transaction
from ontologies.vocab import ENGRAM_NS, EPISODIC, MEMORY, TRASH
from reasoners.clock import SettableClock
from reasoners.memory import SceneMemory
from reasoners.operations import StoreScene
from tests.api.armor.conftest import Armor, Step, directives, start_live_server

TABLE = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1), hessian=-0.1)


def _ball(name: str, x: float) -> Primitive:
    return Primitive(name, "Sphere", centre=(x, 0.3, 0.3), radius=0.05, colour=(1, 0, 0))


def _cup(name: str, x: float) -> Primitive:
    return Primitive(
        name, "Cylinder", centre=(x, 0.3, 0.2), axis=(0, 0, 1), radius=0.04, height=0.1
    )


def test_ten_scenes_learn_recognise_retrieve_sleep_and_pin(armor: Armor, ref: str) -> None:
    client = ArmorClient("camera", ref, base_url=armor.url)
    scenes = [
        [_ball("b1", 0.3), TABLE],
        [_ball("b1", 0.31), TABLE],  # the same arrangement: reinforced, not learned
        [_ball("b1", 0.3), _ball("b2", 0.5), TABLE],  # more specific: learned
        [_cup("c1", 0.3), TABLE],
        [_cup("c1", 0.32), TABLE],
        [_ball("b1", 0.3), _cup("c1", 0.6), TABLE],
        [_ball("b1", 0.3), TABLE],
        [_ball("b1", 0.3), _ball("b2", 0.5), TABLE],
        [_cup("c1", 0.3), _cup("c2", 0.6), TABLE],
        [_ball("b1", 0.3), TABLE],
    ]
    answers = [client.memory.store_scene(scene) for scene in scenes]
    learned = [a.details["learned"] == ["true"] for a in answers]
    assert learned == [True, False, True, True, False, True, False, False, True, False]
    first = answers[0].values[0]
    assert (
        answers[1].values == [first]
        and answers[6].values == [first]
        and answers[9].values == [first]
    )
    assert first in answers[2].details["recognised"][0] or any(
        first in r for r in answers[2].details["recognised"]
    )
    assert answers[2].details["parent"] == [first]
    scores = client.memory.scores(first)
    assert scores.details["store_count"] == ["4"]
    assert client.memory.level(first) in {"HIGH", "LOW", "WEAK"}
    recalled = client.memory.retrieve(["Sphere isAboveOf Plane"])
    assert recalled.values == [first]
    assert client.memory.scores(first).details["retrieve_count"] == ["1"]
    sleep = client.memory.sleep()
    assert sleep.details["rescored"] and int(sleep.details["rescored"][0]) >= 5
    client.memory.pin(first)
    assert client.memory.scores(first).details["pinned"] == ["true"]
    client.close()


def test_memory_directive_errors_and_rollback(armor: Armor, ref: str) -> None:
    def call(
        command: str, first: str = "", second: str = "", args: list[str] | None = None
    ) -> dict[str, object]:
        return armor.call(command, first, second, args, ref=ref, client="cam")

    assert call("SCENE", "UPDATED")["exit_code"] == 212  # no open scene
    assert call("LOAD", "INIT")["success"]
    assert call("LOAD", "INIT")["exit_code"] == 212  # already open
    assert call("ADD", "IND", "CLASS", ["x", "Cube"])["exit_code"] == 212
    assert call("ADD", "DATAPROP", "IND", ["weight", "x", "DOUBLE", "1"])["exit_code"] == 212
    call("ADD", "IND", "CLASS", ["lonely", "Sphere"])
    for axis, value in zip("XYZ", ("0.1", "0.2", "0.3"), strict=True):
        call("ADD", "DATAPROP", "IND", [f"centre{axis}", "lonely", "DOUBLE", value])
    alone = call("SCENE", "UPDATED")
    assert alone["exit_code"] == 212 and "relation" in str(alone["error_description"])
    # a list whose scene is fine but whose other directive fails stores nothing
    # and leaves no scene open
    client = ArmorClient("cam2", ref, base_url=armor.url)
    directives = [("LOAD", "INIT", "", [])]
    for primitive in (_ball("b", 0.3), TABLE):
        directives += primitive_directives(primitive)
    directives += [("SCENE", "UPDATED", "", []), ("ADD", "IND", "CLASS", ["only_one"])]
    result = client.call_list(directives)  # type: ignore[arg-type]
    assert result.success is False
    assert (
        client.call("SCENE", "UPDATED", "", []).exit_code == 212
    )  # the list's LOAD INIT was undone too
    try:
        client.memory.scores("Scene-999")
    except ArmorServiceInternalError as error:
        assert error.exit_code == 212
    else:
        raise AssertionError("scores of an unknown class must fail")
    client.close()


# One transaction per list, memory directives included ------------------------------------------


def _requests(steps: list[Step]) -> list[ArmorDirectiveReq]:
    return directives(steps, "scenes", client="cam")


def _scene(*primitives: Primitive) -> list[tuple[str, str, str, list[str]]]:
    out: list[tuple[str, str, str, list[str]]] = [("LOAD", "INIT", "", [])]
    for primitive in primitives:
        out += primitive_directives(primitive)
    return [*out, ("SCENE", "UPDATED", "", [])]


TWO_SCENES = _scene(_ball("b", 0.3), TABLE) + _scene(_cup("c", 0.3), TABLE)
LOAD_REFERENCE = [("LOAD", "FILE", "", ["", "http://ex.org/scenes", "false", "PELLET", "true"])]


def _memory_triples(store: Store) -> dict[str, int]:
    sizes = store.graph_sizes()
    return {g.value: sizes.get(g.value, 0) for g in (MEMORY, EPISODIC, TRASH)}


@pytest.fixture
def engine(tmp_path: Path) -> ArmorEngine:
    return ArmorEngine(Store(tmp_path / "store"))


def test_a_list_with_two_scenes_commits_both_in_one_transaction(engine: ArmorEngine) -> None:
    writes: list[int] = []

    def trace(kind: str, text: str, bindings: object) -> None:
        if kind in ("update", "extend"):
            writes.append(1)

    with engine.store.tracing(trace):
        result = engine.execute_list(_requests(LOAD_REFERENCE + TWO_SCENES))
    assert result.success, result
    assert len(writes) == 1, "the reference, both scenes and their scores: one write"
    stored = [r.queried_objects for r in result.armor_responses if r.queried_objects]
    assert stored == [[f"<{ENGRAM_NS}Scene-1>"], [f"<{ENGRAM_NS}Scene-2>"]]
    memory = engine.memory.memory
    assert [c.iri.value.rsplit("#")[-1] for c in memory.reads.classes()] == ["Scene-1", "Scene-2"]
    assert len(memory.reads.items()) == 2


def test_the_list_hands_the_memory_its_scenes_and_writes_as_values(
    engine: ArmorEngine, monkeypatch: pytest.MonkeyPatch
) -> None:
    memory = engine.memory.memory
    handed: list[tuple[list[object], Transaction | None]] = []
    commit = type(memory).commit

    def recorded(
        self: object,
        operations: list[object],
        alongside: Transaction | None = None,
        **options: bool,
    ) -> object:
        handed.append((list(operations), alongside))
        return commit(memory, operations, alongside, **options)

    monkeypatch.setattr(type(memory), "commit", recorded)
    assert engine.execute_list(_requests(LOAD_REFERENCE + TWO_SCENES)).success
    [(operations, alongside)] = handed
    assert [type(o) for o in operations] == [StoreScene, StoreScene]
    assert [sorted(p.id for p in o.primitives) for o in operations] == [
        ["b", "table"],
        ["c", "table"],
    ]
    assert alongside is not None and alongside.inserts  # the reference's settings, as data
    assert not any(callable(value) for o in operations for value in vars(o).values())


@pytest.mark.parametrize(
    "failing",
    [
        pytest.param(
            ("ADD", "IND", "CLASS", ["only_one"]), id="a directive fails while the list runs"
        ),
        pytest.param(("MEMORY", "RESTORE", "", ["Scene-1"]), id="memory work fails at the commit"),
    ],
)
def test_a_failing_directive_leaves_nothing_of_two_scenes(
    engine: ArmorEngine, failing: tuple[str, str, str, list[str]], monkeypatch: pytest.MonkeyPatch
) -> None:
    memory = engine.memory.memory
    if failing[0] == "MEMORY":  # passes its check while the list runs, fails at the commit
        monkeypatch.setattr(
            type(memory.reads), "trash", lambda self: [NamedNode(ENGRAM_NS + "Scene-1")]
        )
    before = _memory_triples(engine.store)
    result = engine.execute_list(_requests(LOAD_REFERENCE + TWO_SCENES + [failing]))
    assert result.success is False
    assert result.armor_responses[-1].success is False
    assert _memory_triples(engine.store) == before
    assert engine.registry.get("scenes") is None, "the reference write went too"
    assert memory.reads.classes() == [] and memory.reads.items() == []
    # the memory is sound afterwards: the same list without the failing directive commits
    assert engine.execute_list(_requests(LOAD_REFERENCE + TWO_SCENES)).success
    assert [c.iri.value.rsplit("#")[-1] for c in memory.reads.classes()] == ["Scene-1", "Scene-2"]


KILLED_WRITER = textwrap.dedent(
    """
    import sys
    from api.armor import ArmorEngine
    from api.protocol import ArmorDirectiveReq
    from api.client import Primitive, primitive_directives
    from kg import Store

    engine = ArmorEngine(Store(sys.argv[1]))
    table = Primitive("t", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1))
    n = 0
    while True:
        n += 1
        ball = Primitive("b", "Sphere", centre=(0.3 + n % 7 / 100, 0.3, 0.3), radius=0.05)
        cup = Primitive("c", "Cylinder", centre=(0.3, 0.3, 0.2), axis=(0, 0, 1), radius=0.04)
        directives = [("ADD", "IND", "", [f"list{n}"])]
        for primitives in ([ball, table], [cup, ball, table]):
            directives.append(("LOAD", "INIT", "", []))
            for p in primitives:
                directives += primitive_directives(p)
            directives.append(("SCENE", "UPDATED", "", []))
        requests = [
            ArmorDirectiveReq(client_name="cam", reference_name="marks", command=c,
                              primary_command_spec=a, secondary_command_spec=b, args=args)
            for c, a, b, args in directives
        ]
        if n == 1:
            load = ("LOAD", "FILE", "", ["", "http://ex.org/marks", "false", "PELLET", "true"])
            requests.insert(0, ArmorDirectiveReq(client_name="cam", reference_name="marks",
                command=load[0], primary_command_spec=load[1], args=load[3]))
        assert engine.execute_list(requests).success
        if n == 3:
            print("writing", flush=True)
    """
)


@pytest.mark.slow
def test_sigkill_while_lists_of_two_scenes_commit_leaves_whole_lists(tmp_path: Path) -> None:
    path = tmp_path / "store"
    with subprocess.Popen(
        [sys.executable, "-c", KILLED_WRITER, str(path)], stdout=subprocess.PIPE, text=True
    ) as writer:
        assert writer.stdout is not None
        assert writer.stdout.readline() == "writing\n"
        time.sleep(1.0)
        os.kill(writer.pid, signal.SIGKILL)
        writer.wait(timeout=10)

    engine = ArmorEngine(Store(path))
    marks = {
        q.subject.value.rsplit("#", 1)[-1]
        for q in engine.store.quads(None, None, None)
        if q.subject.value.rsplit("#", 1)[-1].startswith("list")
    }
    lists = len(marks)
    assert lists >= 3 and marks == {f"list{n}" for n in range(1, lists + 1)}
    items = engine.memory.memory.reads.items()
    assert len(items) == 2 * lists, "every committed list's two scenes, no half list"
    assert sum(c.scores.store_count for c in engine.memory.memory.reads.classes()) == len(items)


# A settable clock ------------------------------------------------------------------------------


def test_the_clock_directives_are_refused_unless_the_clock_is_settable(
    armor: Armor, ref: str
) -> None:
    for command in (["SET", ["2030-01-01T00:00:00+00:00"]], ["ADVANCE", ["60"]]):
        answer = armor.call("MEMORY", "CLOCK", command[0], command[1], ref=ref)  # type: ignore[arg-type]
        assert answer["exit_code"] == 212 and "ENGRAM_CLOCK_SETTABLE" in answer["error_description"]


@pytest.fixture
def settable(tmp_path: Path) -> ArmorEngine:
    store = Store(tmp_path / "store")
    clock = SettableClock(lambda: dt.datetime(2026, 1, 1, 9, tzinfo=dt.UTC))
    return ArmorEngine(store, scene_memory=SceneMemory(store, clock=clock))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["MEMORY", "CLOCK", "SET", ["tomorrow"]], "expected an ISO 8601 time with its offset"),
        (["MEMORY", "CLOCK", "SET", ["2026-01-02T09:00:00"]], "with its offset"),
        (["MEMORY", "CLOCK", "SET", ["2025-01-01T09:00:00+00:00"]], "never goes back"),
        (["MEMORY", "CLOCK", "ADVANCE", ["-5"]], "from 0 to 1e11"),
        (["MEMORY", "CLOCK", "ADVANCE", ["nan"]], "from 0 to 1e11"),
        (["MEMORY", "CLOCK", "ADVANCE", ["١٢"]], "from 0 to 1e11"),
    ],
)
def test_bad_clock_values_are_refused(settable: ArmorEngine, args: list, message: str) -> None:
    result = settable.execute_list(_requests([tuple(args)]))  # type: ignore[list-item]
    answer = result.armor_responses[0]
    assert answer.exit_code == 212 and message in answer.error_description
    assert settable.memory.memory.clock().isoformat() == "2026-01-01T09:00:00+00:00"


def test_a_simulated_life_forgets_a_scene_seen_once(settable: ArmorEngine) -> None:
    """Days pass by directive: a class seen once goes WEAK and is forgotten after k passes."""
    memory = settable.memory.memory
    directives = []
    for _ in range(30):
        directives += _scene(_cup("c", 0.3), _ball("b", 0.6), TABLE)
    directives += [("RETRIEVE", "SCENE", "", ["Cylinder isAboveOf Plane"])] * 5
    directives += _scene(_ball("b", 0.3), _ball("b2", 0.5))
    assert settable.execute_list(_requests(directives)).success
    forgotten: list[str] = []
    for _ in range(memory.policy.weakPassesToForget):
        result = settable.execute_list(
            _requests([("MEMORY", "CLOCK", "ADVANCE", ["86400"]), ("MEMORY", "SLEEP", "", [])])
        )
        assert result.success, result
        forgotten += result.armor_responses[1].queried_objects
    assert len(forgotten) == 1 and len(memory.reads.trash()) == 2  # the class and its one scene
    now = settable.execute_list(_requests([("QUERY", "MEMORY", "CLOCK", [])]))
    days = memory.policy.weakPassesToForget
    assert now.armor_responses[0].queried_objects == [f"2026-01-0{1 + days}T09:00:00+00:00"]


def test_a_failing_list_leaves_the_clock_as_it_was(settable: ArmorEngine) -> None:
    result = settable.execute_list(
        _requests([("MEMORY", "CLOCK", "ADVANCE", ["3600"]), ("ADD", "IND", "CLASS", ["x"])])
    )
    assert not result.success
    assert settable.memory.memory.clock().isoformat() == "2026-01-01T09:00:00+00:00"


def test_a_settable_server_drives_the_clock_over_http(tmp_path: Path) -> None:
    with (
        start_live_server(tmp_path, clock_settable=True) as running,
        httpx.Client(base_url=running.url, timeout=30) as http,
    ):
        armor = Armor(http, running.url)
        answer = armor.call("MEMORY", "CLOCK", "SET", ["2040-05-01T12:00:00+00:00"], ref="r")
        assert answer["success"] and answer["queried_objects"] == ["2040-05-01T12:00:00+00:00"]
        answer = armor.call("MEMORY", "CLOCK", "ADVANCE", ["90"], ref="r")
        assert answer["queried_objects"] == ["2040-05-01T12:01:30+00:00"]
