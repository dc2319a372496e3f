"""One episode's triples out of one memory and into another, as TriG."""

import pytest

from episodes import ArgumentSpec, EpisodeMemory, EpisodeStateError, InvalidInputError
from kg import Store, ensure_ontology
from ontologies.vocab import EPISODES
from tests.conftest import LiveServer
from tests.episodes.conftest import fixed_clock, store_experienced_scene


def test_an_exported_episode_loads_into_another_memory_unchanged(memory: EpisodeMemory) -> None:
    memory.begin(
        "babbling",
        arguments=[ArgumentSpec("agent", "HyungJin"), ArgumentSpec("object", "ball")],
        begin="2026-01-26T15:30:00+01:00",
        episode_id="ep1",
    )
    memory.begin("point", arguments=[ArgumentSpec("agent", "HyungJin")], episode_id="ep2")
    memory.end("ep1", end="2026-01-26T15:40:00+01:00")
    memory.annotate("ep1", key="comment", value="good", author="Alice")
    run = memory.runs.start("ep1", name="edges", producer="canny", parameters={"t": 1})
    memory.ratings.rate("ep1", run.id, person="Bob", value=8)
    memory.link_scene("ep1", store_experienced_scene(memory.store, "scene-1"))
    data = memory.export_rdf("ep1")
    assert b"ep2" not in data

    other_store = Store()
    ensure_ontology(other_store)
    other = EpisodeMemory(other_store, clock=fixed_clock)
    assert other.import_rdf(data) == memory.get("ep1")
    assert other.runs.of_episode("ep1") == memory.runs.of_episode("ep1")
    assert other.ratings.rank("edges").candidates == memory.ratings.rank("edges").candidates
    with pytest.raises(EpisodeStateError):
        other.import_rdf(data)
    memory.delete("ep1")
    assert memory.get("ep2").arguments[0].value == "HyungJin"


@pytest.mark.parametrize(
    ("data", "fragment"),
    [
        (b"not trig {", "TriG"),
        (b"", "exactly one"),
        (
            b"<https://w3id.org/engram/graph/episodes> { <https://w3id.org/engram/episode/e1> a "
            b"<https://w3id.org/engram/ontology#Episode> . <http://evil/x> <http://p> 1 . }",
            "its parts",
        ),
        (
            b"<https://w3id.org/engram/graph/tbox> { <https://w3id.org/engram/episode/e1> a "
            b"<https://w3id.org/engram/ontology#Episode> . }",
            "episodes graph",
        ),
    ],
)
def test_bad_import_writes_nothing(memory: EpisodeMemory, data: bytes, fragment: str) -> None:
    before = len(memory.store)
    with pytest.raises(InvalidInputError, match=fragment):
        memory.import_rdf(data)
    assert len(memory.store) == before
    assert list(memory.store.quads(None, None, None, EPISODES)) == []


def test_rdf_round_trip_over_http(start_server: object) -> None:
    first: LiveServer = start_server()  # type: ignore[operator]
    second: LiveServer = start_server()  # type: ignore[operator]
    body = {"activity": "wave", "id": "w1", "begin": "2026-01-26T15:30:00+00:00"}
    assert first.client.post("/episodes", json=body).status_code == 201
    exported = first.client.get("/episodes/w1/rdf")
    assert exported.status_code == 200
    assert exported.headers["content-type"].startswith("application/trig")
    loaded = second.client.post("/episodes/rdf", content=exported.content)
    assert loaded.status_code == 201, loaded.text
    assert loaded.json() == first.client.get("/episodes/w1").json()
    assert second.client.post("/episodes/rdf", content=b"{").status_code == 422
    assert first.client.get("/episodes/nope/rdf").status_code == 404
