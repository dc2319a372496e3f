"""The JSON of the web views, read from a live server over the demo-like memory."""

from typing import Any

import pytest

from tests.web.conftest import SCRIPT, TICKS, ViewServer

pytestmark = pytest.mark.slow


def test_class_list_has_scores_levels_and_marks(view_server: ViewServer) -> None:
    body = view_server.client.get("/views/classes").json()
    assert body["total"] == len(set(SCRIPT)) == len(body["classes"])
    levels = {c["level"] for c in body["classes"]}
    assert levels <= {"HIGH", "LOW", "WEAK"}
    best = max(body["classes"], key=lambda c: c["score"])
    assert best["score"] == 1.0 and best["pinned"] and best["store_count"] == 3
    complexities = [c["complexity"] for c in body["classes"]]
    assert complexities == sorted(complexities)


def test_class_list_searches_names_and_relations(view_server: ViewServer) -> None:
    found = view_server.client.get("/views/classes", params={"q": "cone isBehindOf"}).json()
    assert found["total"] == 2  # the funnel scene and the ball before a cone
    assert all(any("cone isBehindOf" in r for r in c["relations"]) for c in found["classes"])
    page = view_server.client.get("/views/classes", params={"limit": 1, "offset": 1}).json()
    assert page["total"] == len(set(SCRIPT)) and len(page["classes"]) == 1


def test_class_detail_reads_the_definition_in_words(view_server: ViewServer) -> None:
    classes = view_server.client.get("/views/classes").json()["classes"]
    best = max(classes, key=lambda c: c["score"])
    detail = view_server.client.get(f"/views/classes/{best['name']}").json()
    assert "a sphere left of a cylinder" in detail["words"]
    assert "a cylinder above a plane" in detail["words"]
    assert len(detail["scenes"]) == 3  # breakfast was stored three times
    assert detail["history"][-1]["score"] == 1.0


def test_scene_detail_has_the_stored_primitives(view_server: ViewServer) -> None:
    latest = view_server.client.get("/views/scenes/latest").json()
    kinds = sorted(p["kind"] for p in latest["primitives"])
    assert kinds == ["Cylinder", "Plane", "Sphere"]
    can = next(p for p in latest["primitives"] if p["id"] == "can")
    assert can["centre"] == [0.12, 0.0, 0.07] and can["height"] == 0.14
    assert can["colour"] == [0.1, 0.3, 0.9]
    assert {"subject": "can", "relation": "isAboveOf", "object": "table"} in latest["relations"]


def test_episode_timeline_has_annotations_scenes_runs_and_ratings(view_server: ViewServer) -> None:
    body = view_server.client.get("/views/episodes").json()
    assert [e["activity"] for e in body["episodes"]] == ["tidying", "babbling"]
    tidying = body["episodes"][0]
    assert "agent: HyungJin" in tidying["participants"]
    assert tidying["annotations"][0]["start"] is not None
    assert len(tidying["scenes"]) >= 3 and tidying["channels"] == 2
    assert tidying["runs"][0]["name"] == "grasp-detector"
    assert tidying["ratings"][0]["value"] == 8


def test_channels_and_decimated_plot(view_server: ViewServer) -> None:
    base = f"/views/episodes/{view_server.episode}"
    channels = {c["name"]: c for c in view_server.client.get(f"{base}/channels").json()["channels"]}
    assert channels["arm/joints"]["samples"] == TICKS and channels["arm/joints"]["numeric"]
    assert channels["cam/rgb"]["image"] and sum(channels["cam/rgb"]["coverage"]) == TICKS // 10
    plot = view_server.client.get(f"{base}/plot", params={"channel": "arm/joints", "points": 50})
    data = plot.json()
    assert len(data["t"]) == 50 and data["samples"] == TICKS
    assert data["series"] == ["shoulder position", "elbow position"]
    assert max(data["values"][0]) == pytest.approx(1.0, abs=1e-3)  # the sine's peak survives
    frames = view_server.client.get(f"{base}/frames", params={"channel": "cam/rgb"}).json()
    assert frames["total"] == TICKS // 10


@pytest.mark.parametrize(
    ("path", "params", "status", "fragment"),
    [
        ("/views/classes/Scene-99", {}, 404, "Scene-99"),
        ("/views/scenes/no such scene", {}, 404, "no such scene"),
        ("/views/classes", {"limit": 0}, 422, "limit"),
        ("/views/episodes/tidying-1/plot", {"channel": "cam/rgb"}, 422, "numeric"),
        ("/views/episodes/tidying-1/plot", {"channel": "nope"}, 404, "nope"),
        (
            "/views/episodes/tidying-1/plot",
            {"channel": "arm/joints", "points": 5000},
            422,
            "points",
        ),
        ("/views/episodes/bad id!/channels", {}, 422, "bad id!"),
        ("/views/episodes/babbling-9/channels", {}, 404, ""),
    ],
)
def test_bad_requests_answer_4xx_naming_the_value(
    view_server: ViewServer, path: str, params: dict[str, Any], status: int, fragment: str
) -> None:
    answer = view_server.client.get(path, params=params)
    assert answer.status_code == status, answer.text
    assert fragment in answer.text


def test_views_are_in_the_openapi(view_server: ViewServer) -> None:
    spec = view_server.client.get("/openapi.json").json()
    assert "/views/classes" in spec["paths"] and "ClassNode" in spec["components"]["schemas"]
    assert "PlotData" in spec["components"]["schemas"]
