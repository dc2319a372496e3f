"""A fleet on one Oxigraph server: two Engram servers each write their robot's memory, a third
follows both (robot A's as its own memory, robot B's as a fleet memory), and fleet queries run
across both memories on the server's own endpoint and on the follower's ``/sparql``."""

import re
import time
from collections.abc import Callable
from pathlib import Path

import httpx
import pytest

from api.client import ArmorClient, Primitive
from kg.fleet import open_remote
from tests.backends.servers import OxigraphServer
from tests.conftest import LiveServer

pytestmark = pytest.mark.slow

BALL = Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05)
TABLE = Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1))
CONE = Primitive("cone", "Cone", centre=(0.3, 0.6, 0.1), axis=(0, 0, 1), radius=0.04)
SPHERE = Primitive("orb", "Sphere", centre=(0.3, 0.2, 0.1), radius=0.05)

CLASSES_BOTH_HOLD = """
PREFIX owl: <http://www.w3.org/2002/07/owl#>
PREFIX rdfs: <http://www.w3.org/2000/01/rdf-schema#>
PREFIX rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#>
PREFIX engram: <https://w3id.org/engram/ontology#>
PREFIX a: <https://w3id.org/engram/memory/robot-a/graph/>
PREFIX b: <https://w3id.org/engram/memory/robot-b/graph/>
SELECT ?classA ?classB WHERE {
  GRAPH a:memory { ?classA rdfs:subClassOf engram:Scene }
  GRAPH b:memory { ?classB rdfs:subClassOf engram:Scene }
  FILTER NOT EXISTS {
    GRAPH a:memory {
      ?classA owl:equivalentClass/(owl:intersectionOf/rdf:rest*/rdf:first)? ?r .
      ?r a owl:Restriction }
    FILTER NOT EXISTS { GRAPH b:memory {
      ?classB owl:equivalentClass/(owl:intersectionOf/rdf:rest*/rdf:first)? ?r } }
  }
  FILTER NOT EXISTS {
    GRAPH b:memory {
      ?classB owl:equivalentClass/(owl:intersectionOf/rdf:rest*/rdf:first)? ?r .
      ?r a owl:Restriction }
    FILTER NOT EXISTS { GRAPH a:memory {
      ?classA owl:equivalentClass/(owl:intersectionOf/rdf:rest*/rdf:first)? ?r } }
  }
}
"""

ROOT = Path(__file__).resolve().parents[2]
LAST_CONE_BEHIND_SPHERE = re.findall(
    r"```sparql\n(.*?)```",
    (ROOT / "README.md").read_text(encoding="utf-8").split("\n## A fleet\n", 1)[1],
    re.S,
)[0]
"""The README's fleet query (the first of its section "A fleet"), as the README shows it."""


def _fleet_query(where: OxigraphServer | LiveServer, query: str) -> list[dict[str, str]]:
    """Rows of ``query`` on the SPARQL server's endpoint or on an Engram's ``/sparql``."""
    endpoint = f"{where.url}/query" if isinstance(where, OxigraphServer) else f"{where.url}/sparql"
    answer = httpx.post(
        endpoint,
        data={"query": query},
        headers={"Accept": "application/sparql-results+json"},
    )
    answer.raise_for_status()
    rows = answer.json()["results"]["bindings"]
    return [{k: v["value"] for k, v in row.items()} for row in rows]


@pytest.fixture
def fleet_server(tmp_path_factory: pytest.TempPathFactory) -> OxigraphServer:
    server = OxigraphServer(tmp_path_factory.mktemp("fleet") / "db").start()
    yield server  # type: ignore[misc]
    server.stop()


def test_two_writers_and_a_follower_share_one_server_and_answer_fleet_queries(
    fleet_server: OxigraphServer, start_server: Callable[..., LiveServer]
) -> None:
    url = fleet_server.url
    robot_a = start_server(store_url=url, memory="robot-a")
    robot_b = start_server(store_url=url, memory="robot-b")
    follower = start_server(store_url=url, memory="robot-a", follow=True, fleet="robot-b")

    with ArmorClient("camera", "engram", base_url=robot_a.url) as client:
        learned = client.memory.store_scene([BALL, TABLE])
        client.memory.store_scene([CONE, SPHERE])
    with ArmorClient("camera", "engram", base_url=robot_b.url) as client:
        client.memory.store_scene([BALL, TABLE])
    assert learned.details["learned"] == ["true"]

    # the follower catches up from the journal: its scene memory knows A's class and its count
    with ArmorClient("analyst", "engram", base_url=follower.url) as client:
        deadline = time.monotonic() + 30
        while True:
            try:
                scores = client.memory.scores(learned.values[0])
                break
            except Exception:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
    assert scores.details["store_count"] == ["1"]

    # a follower may not write
    sleep = {"client_name": "x", "reference_name": "engram", "command": "MEMORY"}
    sleep |= {"primary_command_spec": "SLEEP", "args": []}
    refused = follower.client.post("/armor_interface_srv", json={"armor_request": sleep})
    assert "read-only" in refused.text

    both = _fleet_query(fleet_server, CLASSES_BOTH_HOLD)
    assert [(r["classA"].rsplit("#")[-1], r["classB"].rsplit("#")[-1]) for r in both] == [
        ("Scene-1", "Scene-1")
    ]
    last = _fleet_query(fleet_server, LAST_CONE_BEHIND_SPHERE)
    assert [r["graph"] for r in last] == ["https://w3id.org/engram/memory/robot-a/graph/episodic"]

    # the follower's /sparql sees both robots: A's as its own memory (Engram's graph names, and
    # its server names), B's under its server names
    assert _fleet_query(follower, CLASSES_BOTH_HOLD) == both
    last_seen = _fleet_query(follower, LAST_CONE_BEHIND_SPHERE)
    assert [r["graph"] for r in last_seen] == ["https://w3id.org/engram/graph/episodic"]
    assert [r["time"] for r in last_seen] == [r["time"] for r in last]
    count_b = (
        "SELECT (COUNT(*) AS ?n) WHERE { GRAPH <https://w3id.org/engram/memory/robot-b/graph/"
        "memory> { ?c <http://www.w3.org/2000/01/rdf-schema#subClassOf>"
        " <https://w3id.org/engram/ontology#Scene> } }"
    )
    assert _fleet_query(follower, count_b) == [{"n": "1"}]
    with ArmorClient("camera", "engram", base_url=robot_b.url) as client:
        client.memory.store_scene([CONE, SPHERE])  # robot B learns a second class
    assert _fleet_query(follower, count_b) == [{"n": "2"}]

    # each robot's own /sparql sees its memory only
    count = (
        "SELECT (COUNT(*) AS ?n) WHERE { GRAPH <https://w3id.org/engram/graph/memory> {"
        " ?c <http://www.w3.org/2000/01/rdf-schema#subClassOf>"
        " <https://w3id.org/engram/ontology#Scene> } }"
    )
    for robot, classes in ((robot_a, "2"), (robot_b, "2"), (follower, "2")):
        answer = robot.client.get(
            "/sparql", params={"query": count}, headers={"Accept": "text/csv"}
        )
        assert answer.text.split() == ["n", classes]


@pytest.mark.parametrize("fleet", [["robot-a"], ["robot-b", "robot-b"], ["no spaces"]])
def test_a_fleet_names_other_memories_each_once(fleet: list[str]) -> None:
    with pytest.raises(ValueError, match=r"memory|fleet"):
        open_remote("http://127.0.0.1:9", "robot-a", follow=True, fleet=fleet)
