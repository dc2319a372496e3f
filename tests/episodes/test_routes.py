"""The episode endpoints through a real server on loopback: answers, error table, write guard."""

from collections.abc import Callable
from typing import Any

import pytest

from api.client import ArmorClient, Primitive
from tests.conftest import LiveServer

NOW = "2026-02-26T10:00:00+00:00"
EXPERIENCED_SCENES = (
    "SELECT ?scene WHERE { ?scene a <https://w3id.org/engram/ontology#ExperiencedScene> }"
)


def store_scene_over_http(client: Any) -> str:
    """Store a ball on a table through the directive API; the experienced scene's IRI."""
    armor = ArmorClient("camera", "scenes", base_url=str(client.base_url))
    armor.memory.store_scene(
        [
            Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05),
            Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1), hessian=-0.1),
        ]
    )
    armor.close()
    rows = client.get(
        "/sparql", params={"query": EXPERIENCED_SCENES}, headers={"Accept": "application/json"}
    ).json()["results"]["bindings"]
    return str(rows[-1]["scene"]["value"])


@pytest.fixture
def server_with_episode(live_server: LiveServer) -> LiveServer:
    answer = live_server.client.post(
        "/episodes",
        json={
            "activity": "babbling",
            "type": "action",
            "id": "ep1",
            "begin": "2026-01-26T15:30:00+00:00",
            "arguments": [
                {"role": "agent", "value": "HyungJin"},
                {"role": "object", "value": "left hand"},
            ],
        },
    )
    assert answer.status_code == 201, answer.text
    return live_server


def test_begin_end_get_and_recall(server_with_episode: LiveServer) -> None:
    client = server_with_episode.client
    ended = client.post("/episodes/ep1/end", json={"end": "2026-01-26T15:40:00+00:00"})
    assert ended.status_code == 200
    assert ended.json()["end"] == "2026-01-26T15:40:00+00:00"
    got = client.get("/episodes/ep1").json()
    assert got["activity"] == "babbling" and got["state_at_begin"]["learned_classes"] == 0
    recalled = client.get(
        "/episodes/recall",
        params={"activity": "babbling", "agent": "HyungJin", "which": "last", "now": NOW},
    )
    assert recalled.status_code == 200
    assert recalled.json()["episode"]["id"] == "ep1"
    assert recalled.json()["when"] == "one month ago, on January 26th"
    assert client.get("/episodes/count", params={"activity": "babbling"}).json() == {"count": 1}
    listed = client.get("/episodes", params={"activity": "babbling", "object": "left hand"})
    assert [r["episode"]["id"] for r in listed.json()] == ["ep1"]
    between = client.get(
        "/episodes/between",
        params={"start": "2026-01-26T15:35:00Z", "end": "2026-01-26T15:36:00Z", "now": NOW},
    )
    assert [r["episode"]["id"] for r in between.json()] == ["ep1"]


def test_annotation_and_scene_link(server_with_episode: LiveServer) -> None:
    client = server_with_episode.client
    made = client.post(
        "/episodes/ep1/annotations",
        json={
            "key": "gesture",
            "value": "wave",
            "author": "vision",
            "confidence": 0.7,
            "start": "2026-01-26T15:31:00+00:00",
            "end": "2026-01-26T15:32:00+00:00",
        },
    )
    assert made.status_code == 201 and made.json()["confidence"] == 0.7
    scene = store_scene_over_http(client)
    assert client.post("/episodes/ep1/scenes", json={"scene": scene}).status_code == 204
    got = client.get("/episodes/ep1").json()
    assert got["scenes"] == [scene] and got["annotations"][0]["value"] == "wave"


BAD_TIME = "2026-01-26T15:30:00"


@pytest.mark.parametrize(
    ("send", "code", "field", "fragment"),
    [
        (lambda c: c.get("/episodes/nope"), 404, None, "nope"),
        (lambda c: c.post("/episodes/nope/end", json={}), 404, None, "nope"),
        (lambda c: c.delete("/episodes/nope"), 404, None, "nope"),
        (
            lambda c: c.post("/episodes", json={"activity": "x", "begin": BAD_TIME}),
            422,
            "begin",
            "time zone",
        ),
        (lambda c: c.post("/episodes", json={"activity": ""}), 422, "activity", "non-empty"),
        (lambda c: c.post("/episodes", json={"activity": "x", "id": "a b"}), 422, "id", "letters"),
        (lambda c: c.post("/episodes", json={"activity": "x", "id": "ep1"}), 409, None, "exists"),
        (
            lambda c: c.post("/episodes/ep1/end", json={"end": "2026-01-26T15:00:00Z"}),
            422,
            "end",
            "not before",
        ),
        (lambda c: c.post("/episodes/ep1/end", json={"end": "tomorrow"}), 422, "end", "ISO 8601"),
        (
            lambda c: c.post(
                "/episodes/ep1/annotations", json={"key": "k", "value": "v", "confidence": 2}
            ),
            422,
            "confidence",
            "0 to 1",
        ),
        (
            lambda c: c.get("/episodes/between", params={"start": "x", "end": "y"}),
            422,
            "start",
            "ISO 8601",
        ),
        (
            lambda c: c.get(
                "/episodes/recall", params={"activity": "babbling", "which": "nth", "n": 0}
            ),
            422,
            "n",
            "from 1",
        ),
        (
            lambda c: c.get("/episodes/recall", params={"activity": "babbling", "now": "now"}),
            422,
            "now",
            "ISO 8601",
        ),
        (
            lambda c: c.get("/episodes/recall", params={"activity": "juggling"}),
            404,
            None,
            "juggling",
        ),
        (
            lambda c: c.get(
                "/episodes/lacking",
                params={"activity": "babbling", "augmentation": "edges", "versions": 0},
            ),
            422,
            "versions",
            "from 1",
        ),
        (lambda c: c.post("/episodes/ep1/runs/0123abcd/end"), 404, None, "0123abcd"),
        (
            lambda c: c.post(
                "/episodes/ep1/runs/0123abcd/ratings", json={"person": "A", "value": 11}
            ),
            422,
            "value",
            "1 to 10",
        ),
        (
            lambda c: c.get("/augmentations/edges/ranking", params={"alpha": 2}),
            422,
            "alpha",
            "between 0 and 1",
        ),
        (
            lambda c: c.post("/episodes/ep1/scenes", json={"scene": "not an iri"}),
            422,
            "scene",
            "IRI",
        ),
    ],
)
def test_bad_input_gets_a_4xx_naming_field_value_and_expectation(
    server_with_episode: LiveServer,
    send: Callable[[Any], Any],
    code: int,
    field: str | None,
    fragment: str,
) -> None:
    answer = send(server_with_episode.client)
    assert answer.status_code == code, answer.text
    body = answer.json()
    assert fragment in body["detail"]
    if field is not None:
        assert body["field"] == field
        assert "value" in body and body["expected"]


def test_ending_twice_is_a_conflict(server_with_episode: LiveServer) -> None:
    client = server_with_episode.client
    assert client.post("/episodes/ep1/end", json={}).status_code == 200
    second = client.post("/episodes/ep1/end", json={})
    assert second.status_code == 409 and "already ended" in second.json()["detail"]


def test_writes_need_the_token_when_one_is_set(start_server: Callable[..., LiveServer]) -> None:
    server = start_server(token="s3cret")
    body = {"activity": "say", "begin": "2026-01-26T15:30:00+00:00", "id": "s1"}
    assert server.client.post("/episodes", json=body).status_code == 401
    assert server.client.get("/episodes", params={"activity": "say"}).json() == []
    headers = {"Authorization": "Bearer s3cret"}
    assert server.client.post("/episodes", json=body, headers=headers).status_code == 201
    assert server.client.delete("/episodes/s1").status_code == 401
    assert server.client.delete("/episodes/s1", headers=headers).status_code == 204
