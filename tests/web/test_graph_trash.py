"""The memory graph's trash: forgotten classes listed on request, read in detail, and live again
once restored (the cached node list follows the memory)."""

import datetime as dt
import json
from typing import Any

import pytest
from pyoxigraph import NamedNode

from api.views.graph import class_detail, class_list_json
from kg import Store
from reasoners.memory import SceneMemory
from tests.web.conftest import SCENES, START


@pytest.fixture(scope="module")
def memory_with_a_forgotten_class() -> SceneMemory:
    """Breakfast seen eight times and recalled five, a ball before a cone seen once: after three
    nights the latter class is forgotten."""
    now = [START]
    memory = SceneMemory(Store(), clock=lambda: now[0])
    for k, title in enumerate(["breakfast"] * 8 + ["ball before a cone"]):
        now[0] = START + dt.timedelta(minutes=10 * k)
        memory.store_scene(SCENES[title])
    for _ in range(5):
        memory.retrieve([("Sphere", "isLeftOf", "Cylinder")])
    for _ in range(3):
        now[0] += dt.timedelta(hours=12)
        memory.sleep()
    return memory


def _names(memory: SceneMemory, **options: Any) -> dict[str, dict[str, Any]]:
    page = json.loads(class_list_json(memory, query=None, offset=0, limit=100, **options))
    return {c["name"]: c for c in page["classes"]}


def test_the_trash_shows_forgotten_classes_and_restoring_brings_them_back(
    memory_with_a_forgotten_class: SceneMemory,
) -> None:
    memory = memory_with_a_forgotten_class
    assert "Scene-2" not in _names(memory, trash=False)
    forgotten = _names(memory, trash=True)["Scene-2"]
    assert forgotten["forgotten"] and forgotten["level"] == "WEAK"
    assert any("cone" in r for r in forgotten["relations"])
    detail = class_detail(memory, "Scene-2")
    assert detail.node.forgotten and "a cone behind a sphere" in detail.words
    assert [s.forgotten for s in detail.scenes] == [True]
    memory.restore(NamedNode("https://w3id.org/engram/ontology#Scene-2"))
    restored = _names(memory, trash=True)["Scene-2"]
    assert not restored["forgotten"]
    assert "Scene-2" in _names(memory, trash=False, relations=False)
