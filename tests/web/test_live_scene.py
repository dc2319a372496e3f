"""The live 3D view is pushed by server-sent events: the stream sends the latest scene on
connecting and each newer scene a writer stores; the page draws it without polling.

A module of its own: it stores scenes, which the other view tests must not see."""

import json
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from api.client import ArmorClient, Primitive
from api.config import Settings
from api.main import create_app
from api.routes import views
from tests.conftest import free_port, serve
from tests.web.conftest import ViewServer, Watched

TOWER = [
    Primitive(
        "base",
        "Cylinder",
        centre=(0.0, 0.0, 0.05),
        axis=(0, 0, 1),
        radius=0.06,
        height=0.1,
        colour=(0.2, 0.6, 0.2),
    ),
    Primitive("top", "Sphere", centre=(0.0, 0.0, 0.16), radius=0.05, colour=(0.9, 0.2, 0.6)),
    Primitive(
        "side",
        "Cone",
        centre=(0.2, 0.0, 0.05),
        axis=(0, 0, 1),
        radius=0.04,
        height=0.1,
        colour=(0.9, 0.5, 0.1),
    ),
]


FOLLOW = {"Accept": "text/event-stream"}  # as an EventSource asks


def _store(view_server: ViewServer, primitives: list[Primitive]) -> str:
    with ArmorClient("camera", "engram", base_url=view_server.url) as client:
        client.memory.store_scene(primitives)
    latest: str = view_server.client.get("/views/scenes/latest").json()["scene"]["name"]
    return latest


def _events(lines: Iterator[str]) -> Iterator[dict[str, str]]:
    """Server-sent events as dicts of their fields (comments and retry lines skipped)."""
    event: dict[str, str] = {}
    for line in lines:
        if not line:
            if "data" in event:
                yield event
            event = {}
        elif not line.startswith(":"):
            key, _, value = line.partition(":")
            event[key] = value.removeprefix(" ")


def test_the_stream_sends_the_latest_scene_then_each_newly_stored_one(
    view_server: ViewServer,
) -> None:
    before = view_server.client.get("/views/scenes/latest").json()["scene"]["name"]
    http = httpx.Client(base_url=view_server.url, timeout=30, headers=FOLLOW)
    with http, http.stream("GET", "/views/scenes/live") as answer:
        assert answer.status_code == 200
        assert answer.headers["content-type"].startswith("text/event-stream")
        events = _events(answer.iter_lines())
        first = next(events)
        assert first["event"] == "scene"
        assert json.loads(first["data"])["scene"]["name"] == before
        stored = _store(view_server, TOWER)
        pushed = next(events)
        detail = json.loads(pushed["data"])
        assert detail["scene"]["name"] == stored != before
        assert sorted(p["id"] for p in detail["primitives"]) == ["base", "side", "top"]
        assert int(pushed["id"]) > int(first["id"])


def test_a_client_not_asking_for_a_stream_gets_the_current_scene_and_the_end(
    view_server: ViewServer,
) -> None:
    latest = view_server.client.get("/views/scenes/latest").json()["scene"]["name"]
    answer = view_server.client.get("/views/scenes/live", headers={"Accept": "*/*"})
    assert answer.status_code == 200
    events = list(_events(iter(answer.text.splitlines())))
    assert [json.loads(e["data"])["scene"]["name"] for e in events] == [latest]


@pytest.mark.slow
def test_the_live_page_draws_a_scene_stored_while_it_watches(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    oldest = view_server.client.get("/views/scenes").json()["scenes"][-1]["name"]
    page.goto(f"{view_server.url}/web/#scene/{oldest}")
    page.wait_for_selector(f"#scene-canvas canvas[data-scene='{oldest}']")
    page.check("#scene-live")
    page.wait_for_selector("#scene-canvas canvas[data-live='open']")
    latest = view_server.client.get("/views/scenes/latest").json()["scene"]["name"]
    page.wait_for_selector(f"#scene-canvas canvas[data-scene='{latest}']")  # on connecting
    stored = _store(view_server, TOWER[:2])
    page.wait_for_selector(
        f"#scene-canvas canvas[data-scene='{stored}'][data-primitives='2']", timeout=10_000
    )
    streams = [u for u in watched.requests if u.endswith("/views/scenes/live")]
    assert 1 <= len(streams) <= 2  # one stream (reconnected once if the test outlasts it)
    assert not [u for u in watched.requests if u.endswith("/views/scenes/latest")]  # no polling
    page.uncheck("#scene-live")
    assert page.get_attribute("#scene-canvas canvas", "data-live") is None


def test_an_open_stream_does_not_hold_a_stopping_server(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(views, "LIVE_STREAM_S", 1.0)
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path / "data")
    running = serve(create_app(settings), settings)
    url = running.url
    opened = threading.Event()

    def listen() -> None:
        http = httpx.Client(base_url=url, timeout=30, headers=FOLLOW)
        with http, http.stream("GET", "/views/scenes/live") as answer:
            opened.set()
            for _ in answer.iter_lines():
                pass

    listener = threading.Thread(target=listen, daemon=True)
    listener.start()
    assert opened.wait(10)
    began = time.monotonic()
    running.stop()
    assert not running.thread.is_alive()
    assert time.monotonic() - began < 5
