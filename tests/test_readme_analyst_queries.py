"""The README's analyst queries run against a served memory and answer what they promise."""

import gc
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

import sparql
from api.config import Settings
from api.main import create_app
from kg import Store
from reasoners.memory import SceneMemory
from tests.conftest import free_port, serve
from tests.reasoners.memory.conftest import FakeClock, worked_example
from tests.reasoners.memory.test_forgetting import BIG, SMALL

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
SECTION = README.split("### The memory for analysts", 1)[1].split("\n## ", 1)[0]
QUERIES = re.findall(r"^\| [^|]+ \| `(\w+)\.rq` \|$", SECTION, flags=re.MULTILINE)


def test_the_readme_lists_the_analyst_queries() -> None:
    assert QUERIES == [
        "memory_class_scores",
        "memory_weak_classes",
        "memory_trash",
        "memory_hierarchy",
        "memory_counts",
        "memory_scene",
    ]


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[httpx.Client, dict]]:
    """A server over a memory with a forgotten class, a fresh WEAK class and a hierarchy."""
    data = tmp_path_factory.mktemp("analyst")
    clock = FakeClock()
    memory = SceneMemory(Store(data / "store"), clock=clock)
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    memory.store_scene(SMALL)
    clock.advance(days=2)
    for _ in range(memory.policy.weakPassesToForget):
        memory.sleep()
    memory.store_scene(worked_example())  # a parent of BIG's class, seen once
    memory.store_scene(SMALL)  # learned again, seen once: WEAK
    facts = {
        "scores": {
            c.iri.value: (c.scores.normalised, c.scores.level) for c in memory.reads.classes()
        },
        "edges": {(c.iri.value, p.value) for c in memory.reads.classes() for p in c.parents},
        "trash": {i.value for i in memory.reads.trash()},
        "counts": (len(memory.reads.classes()), len(memory.reads.items())),
    }
    del memory
    gc.collect()  # closes the store for the server
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data)
    with (
        serve(create_app(settings), settings) as running,
        httpx.Client(base_url=running.url, timeout=30) as http,
    ):
        yield http, facts


def rows(http: httpx.Client, name: str) -> list[dict[str, str]]:
    answer = http.post("/sparql", data={"query": sparql.load(name)})
    assert answer.status_code == 200, answer.text
    bindings: list[dict[str, Any]] = answer.json()["results"]["bindings"]
    return [{k: v["value"] for k, v in row.items()} for row in bindings]


def test_class_scores_and_levels_are_the_apis(served: tuple[httpx.Client, dict]) -> None:
    http, facts = served
    got = {r["class"]: (r["score"], r["level"]) for r in rows(http, "memory_class_scores")}
    assert set(got) == set(facts["scores"])
    for cls, (score, level) in got.items():
        body = {
            "armor_request": {
                "client_name": "analyst",
                "reference_name": "memory",
                "command": "QUERY",
                "primary_command_spec": "MEMORY",
                "secondary_command_spec": "SCORES",
                "args": [cls],
            }
        }
        api = http.post("/armor_interface_srv", json=body).json()["armor_response"]
        assert float(api["queried_objects"][0]) == float(score)
        assert {"key": "level", "value": level} in api["sparql_queried_objects"]
        assert level == facts["scores"][cls][1]


def test_weak_classes_are_the_weak_ones(served: tuple[httpx.Client, dict]) -> None:
    http, facts = served
    weak = {r["class"] for r in rows(http, "memory_weak_classes")}
    assert weak and weak == {c for c, (_, level) in facts["scores"].items() if level == "WEAK"}


def test_the_trash_lists_what_was_forgotten(served: tuple[httpx.Client, dict]) -> None:
    http, facts = served
    found = rows(http, "memory_trash")
    assert {r["item"] for r in found} == facts["trash"]
    assert {r["kind"] for r in found} == {"class", "experienced scene"}


def test_the_hierarchy_is_the_direct_edges(served: tuple[httpx.Client, dict]) -> None:
    http, facts = served
    edges = {(r["child"], r["parent"]) for r in rows(http, "memory_hierarchy")}
    assert edges and edges == facts["edges"]


def test_the_counts(served: tuple[httpx.Client, dict]) -> None:
    http, facts = served
    [count] = rows(http, "memory_counts")
    assert (int(count["classes"]), int(count["scenes"])) == facts["counts"]
    assert int(count["forgottenClasses"]) + int(count["forgottenScenes"]) == len(facts["trash"])


def test_a_scenes_primitives_and_relations(served: tuple[httpx.Client, dict]) -> None:
    """The worked example (stored last but one): a sphere above and behind a plane."""
    http, _ = served
    found = rows(http, "memory_scene")
    numbers = sorted({int(r["scene"].rsplit("-", 1)[1]) for r in found})
    last = next(r["scene"] for r in found if r["scene"].endswith(f"-{numbers[-2]}"))
    relations = {
        (r["name"], r["relation"].rsplit("#", 1)[1], r["otherName"])
        for r in found
        if r["scene"] == last and "relation" in r
    }
    assert relations == {("S", "isAboveOf", "P"), ("S", "isBehindOf", "P")}  # primary ones
