"""The analysts' default graph is the live memory: forgotten items only by ``GRAPH <trash>``."""

import gc
from pathlib import Path

import httpx

from api.config import Settings
from api.main import create_app
from kg import Store
from ontologies.vocab import TRASH
from reasoners.memory import SceneMemory
from tests.conftest import free_port, serve
from tests.reasoners.memory.conftest import FakeClock
from tests.reasoners.memory.test_forgetting import BIG, SMALL

SCENES = """PREFIX engram: <https://w3id.org/engram/ontology#>
SELECT (COUNT(DISTINCT ?scene) AS ?n) WHERE { ?scene a engram:ExperiencedScene }"""
TRASHED = """PREFIX engram: <https://w3id.org/engram/ontology#>
SELECT (COUNT(DISTINCT ?scene) AS ?n) WHERE {
  GRAPH <https://w3id.org/engram/graph/trash> { ?scene a engram:ExperiencedScene } }"""


def _forgetful_store(path: Path) -> tuple[int, int]:
    """A store on disk where sleep passes forgot a class and its scene; (live, forgotten)."""
    clock = FakeClock()
    memory = SceneMemory(Store(path), clock=clock)
    for _ in range(30):
        memory.store_scene(BIG)
    for _ in range(5):
        memory.retrieve(BIG)
    memory.store_scene(SMALL)
    clock.advance(days=2)
    for _ in range(memory.policy.weakPassesToForget):
        memory.sleep()
    reads = memory.reads
    counts = len(reads.items()), len(reads.trash()) - 1  # the class is in the trash too
    del memory
    gc.collect()  # closes the store, so that the server can open it
    return counts


def _count(http: httpx.Client, query: str, **params: str) -> int:
    answer = http.get("/sparql", params={"query": query, **params})
    assert answer.status_code == 200, answer.text
    return int(answer.json()["results"]["bindings"][0]["n"]["value"])


def test_a_plain_query_counts_the_live_memory_and_the_trash_answers_by_name(
    tmp_path: Path,
) -> None:
    live, forgotten = _forgetful_store(tmp_path / "store")
    assert live and forgotten
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path)
    with (
        serve(create_app(settings), settings) as running,
        httpx.Client(base_url=running.url, timeout=30) as http,
    ):
        assert _count(http, SCENES) == live
        assert _count(http, TRASHED) == forgotten
        # a default graph named in the request is used as it is
        assert _count(http, SCENES, **{"default-graph-uri": TRASH.value}) == forgotten
