"""The class panel's score-history chart, against GET /memory/history's contract (mocked in the
browser with ``page.route``: the endpoint belongs to another area), and its message when the
server has no such endpoint (404)."""

import io
import json
from typing import Any
from urllib.parse import parse_qs, urlparse

import numpy as np
import pytest
from PIL import Image

from tests.web.conftest import ViewServer, Watched

pytestmark = pytest.mark.slow

EVENTS = [
    {"time": "2026-01-26T08:00:00Z", "kind": "learned", "score": 2.4, "level": "LOW"},
    {"time": "2026-01-26T08:20:00Z", "kind": "reinforced", "score": 3.3, "level": "LOW"},
    {"time": "2026-01-26T09:00:00Z", "kind": "retrieved", "score": None, "level": None},
    {"time": "2026-01-27T03:00:00+00:00", "kind": "rescored", "score": 4.32, "level": None},
    {"time": "2026-01-27T03:00:00+00:00", "kind": "level", "score": 4.32, "level": "HIGH"},
    {"time": "2026-01-27T10:00:00Z", "kind": "pinned", "score": None, "level": None},
    {"time": "2026-01-28T03:00:00Z", "kind": "rescored", "score": 4.08, "level": "LOW"},
]
"""Scores are raw scores ζ (unbounded, as GET /memory/history gives them); the levels a class
has are WEAK, LOW and HIGH."""


def _open_a_class(watched: Watched, view_server: ViewServer) -> dict[str, Any]:
    page = watched.page
    page.goto(f"{view_server.url}/web/#graph")
    page.wait_for_selector("#cy[data-nodes]")
    chosen: dict[str, Any] = view_server.client.get("/views/classes").json()["classes"][0]
    page.evaluate("n => { window.engramGraph.$id(n).emit('tap'); }", chosen["name"])
    page.wait_for_selector(f"#class-detail[data-selected='{chosen['name']}']")
    return chosen


def _pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def _near(pixels: np.ndarray, rgb: tuple[int, int, int]) -> int:
    return int(np.all(np.abs(pixels - rgb) < 24, axis=2).sum())


def test_the_chart_draws_the_events_of_the_class(watched: Watched, view_server: ViewServer) -> None:
    asked: list[str] = []

    def history(route: Any) -> None:
        asked.append(route.request.url)
        iri = parse_qs(urlparse(route.request.url).query)["class"][0]
        body = {"class": iri, "events": EVENTS}
        route.fulfill(status=200, content_type="application/json", body=json.dumps(body))

    watched.page.route("**/memory/history?*", history)
    chosen = _open_a_class(watched, view_server)
    page = watched.page
    panel = page.wait_for_selector("#class-history[data-history='shown'] [data-drawn]")
    assert [parse_qs(urlparse(u).query)["class"] for u in asked] == [[chosen["iri"]]]
    assert page.get_attribute("#class-history", "data-events") == str(len(EVENTS))
    rows = page.locator("#class-history table.events tr").all_inner_texts()
    assert rows[0].split("\t")[2] == "raw score ζ"
    assert rows[1].split("\t")[:4] == ["2026-01-28 03:00:00 UTC", "rescored", "4.080", "LOW"]
    assert "pinned" in rows[2] and len(rows) == 1 + 7
    axes = page.evaluate(
        "() => { const u = document.querySelector('.history-chart').uplot;"
        " return { top: u.scales.score.max, levels: u.axes[2].values(u, [0, 1, 2, 3]) }; }"
    )
    assert axes["top"] >= 4.32  # the raw score is drawn whole, not clipped at 1
    assert axes["levels"] == ["WEAK", "LOW", "HIGH", ""]
    assert "raw score ζ" in page.inner_text("#class-history")
    legend = page.inner_text("#class-history .kinds")
    assert "rescored 2" in legend and "learned 1" in legend
    pixels = _pixels(panel.screenshot())
    assert _near(pixels, (21, 101, 192)) > 150  # the score line and the "learned" mark
    assert _near(pixels, (106, 27, 154)) > 60  # the level steps
    assert _near(pixels, (40, 53, 147)) >= 16  # the "pinned" mark


def test_a_server_without_the_endpoint_gets_a_message(
    watched: Watched, view_server: ViewServer
) -> None:
    watched.page.route(
        "**/memory/history?*",
        lambda route: route.fulfill(
            status=404, content_type="application/json", body='{"detail": "Not Found"}'
        ),
    )
    chosen = _open_a_class(watched, view_server)
    page = watched.page
    page.wait_for_selector("#class-history[data-history='missing']")
    text = page.inner_text("#class-history")
    assert f"No score history for {chosen['name']}" in text and "404" in text
    assert page.locator("#class-history canvas").count() == 0
    assert "Stored scenes" in page.inner_text("#class-detail")  # the rest of the panel is there


def test_a_malformed_answer_is_reported_not_drawn(
    watched: Watched, view_server: ViewServer
) -> None:
    watched.page.route(
        "**/memory/history?*",
        lambda route: route.fulfill(status=200, content_type="application/json", body="{}"),
    )
    _open_a_class(watched, view_server)
    watched.page.wait_for_selector("#class-history[data-history='error']")
    assert "no list of events" in watched.page.inner_text("#class-history")
