"""``GET /memory/history`` and ``GET /memory/as-of`` on the lived week (Scene-2 forgotten on
Tuesday), through a live server: the JSON contract the web views chart."""

import re
from pathlib import Path

import pytest

from ontologies.vocab import engram
from tests.conftest import LiveServer

pytestmark = pytest.mark.slow  # a live server

LEVELS = {"HIGH", "MEDIUM", "LOW", "WEAK", None}


def test_history_of_a_forgotten_class(lived_server: LiveServer) -> None:
    response = lived_server.client.get("/memory/history", params={"class": "Scene-2"})
    assert response.status_code == 200
    body = response.json()
    assert body["class"] == engram("Scene-2").value
    events = body["events"]
    assert events[0]["kind"] == "learned" and events[-1]["kind"] == "forgotten"
    assert events[-1]["level"] == "WEAK" and events[-1]["time"].startswith("2026-03-03")
    assert [e["time"] for e in events] == sorted(e["time"] for e in events)
    for event in events:
        assert set(event) == {"time", "kind", "score", "level"}
        assert event["level"] in LEVELS
        assert event["score"] is None or isinstance(event["score"], float)


def test_history_of_a_class_seen_often(lived_server: LiveServer) -> None:
    events = lived_server.client.get(
        "/memory/history", params={"class": engram("Scene-1").value}
    ).json()["events"]
    kinds = [e["kind"] for e in events]
    assert kinds[:2] == ["learned", "reinforced"] and kinds.count("reinforced") >= 29
    assert "retrieved" in kinds and "level" in kinds


def test_as_of_before_and_after_forgetting(lived_server: LiveServer) -> None:
    def classes(time: str) -> dict[str, object]:
        response = lived_server.client.get("/memory/as-of", params={"time": time})
        assert response.status_code == 200, response.text
        return {c["class"].rsplit("#")[-1]: c["level"] for c in response.json()["classes"]}

    monday = classes("2026-03-02")  # a date: the end of that day
    assert {"Scene-1", "Scene-2"} <= set(monday)
    tuesday = classes("2026-03-03T23:00:00Z")
    assert "Scene-2" not in tuesday and tuesday["Scene-1"] == "HIGH"
    assert classes("2020-01-01T00:00:00+02:00") == {}


@pytest.mark.parametrize(
    ("path", "params", "status", "field"),
    [
        ("/memory/history", {"class": "Scene-99"}, 404, None),
        ("/memory/history", {}, 422, "class"),
        ("/memory/as-of", {"time": "yesterday"}, 422, "time"),
        ("/memory/as-of", {"time": "2026-03-02T10:00:00"}, 422, "time"),
        ("/memory/as-of", {"time": "2026-13-45"}, 422, "time"),
    ],
)
def test_bad_requests_get_clear_answers(
    lived_server: LiveServer, path: str, params: dict[str, str], status: int, field: str | None
) -> None:
    response = lived_server.client.get(path, params=params)
    assert response.status_code == status, response.text
    if field is not None:
        assert field in response.text


def test_the_readme_as_of_query_answers_through_sparql(lived_server: LiveServer) -> None:
    readme = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")
    section = readme.split("### The memory's history", 1)[1].split("\n## ", 1)[0]
    [query] = re.findall(r"```sparql\n(.*?)```", section, flags=re.DOTALL)
    response = lived_server.client.post("/sparql", data={"query": query})
    assert response.status_code == 200, response.text
    rows = response.json()["results"]["bindings"]
    assert {r["class"]["value"].rsplit("#")[-1] for r in rows} == {"Scene-1", "Scene-2"}
    assert {r["kind"]["value"] for r in rows} == {"retrieved", "learned"}
