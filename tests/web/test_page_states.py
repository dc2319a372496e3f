"""What the pages show besides their data: user strings as text (never HTML), a loading
indicator while a view reads, and a banner saying what failed when the server is gone."""

import datetime as dt
import gc
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from api.config import Settings
from api.main import create_app
from episodes import ArgumentSpec, EpisodeMemory
from kg import Store
from tests.conftest import RunningServer, free_port, serve
from tests.web.browser import until
from tests.web.conftest import VIEWPORT

HOSTILE = "<img src=http://127.0.0.1:9/x>"
"""Markup that fetches from a closed port if any page renders it as HTML."""

START = dt.datetime(2026, 1, 26, 8, 0, tzinfo=dt.UTC)


def _hostile_memory(data_dir: Path) -> None:
    """One episode whose every user string is ``HOSTILE`` (tagged by where it is shown)."""
    store = Store(data_dir / "store")
    clock = {"now": START}
    episodes = EpisodeMemory(store, data_dir=data_dir, clock=lambda: clock["now"])
    episode = episodes.begin(
        HOSTILE,
        activity_type=f"type {HOSTILE}",
        arguments=[
            ArgumentSpec("agent", f"agent {HOSTILE}"),
            ArgumentSpec("object", f"object {HOSTILE}"),
            ArgumentSpec("recipient", f"recipient {HOSTILE}"),
        ],
        episode_id="hostile",
    )
    episodes.annotate(
        episode.id,
        key=f"key {HOSTILE}",
        value=f"value {HOSTILE}",
        start=START,
        end=START + dt.timedelta(minutes=5),
    )
    clock["now"] = START + dt.timedelta(minutes=30)
    episodes.end(episode.id)
    run = episodes.runs.start(episode.id, name=f"run {HOSTILE}", producer="tests")
    episodes.runs.end(episode.id, run.id)
    episodes.ratings.rate(episode.id, run.id, person=f"person {HOSTILE}", value=8)
    store.flush()
    del episodes, store
    gc.collect()


def _server(data_dir: Path) -> RunningServer:
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data_dir)
    return serve(create_app(settings), settings)


@pytest.fixture
def hostile_server(tmp_path: Path) -> Iterator[RunningServer]:
    _hostile_memory(tmp_path / "data")
    with _server(tmp_path / "data") as running:
        yield running


@pytest.fixture
def page(browser: Any) -> Iterator[Any]:
    """A fresh page that records every request it makes."""
    context = browser.new_context(viewport=VIEWPORT)
    page = context.new_page()
    page.requests = []  # type: ignore[attr-defined]
    page.on("request", lambda r: page.requests.append(r.url))  # type: ignore[attr-defined]
    yield page
    context.close()


def test_episode_strings_show_as_text_and_fetch_nothing(
    page: Any, hostile_server: RunningServer
) -> None:
    page.goto(f"{hostile_server.url}/web/#episodes")
    page.wait_for_selector("#timeline .vis-item.rating", state="visible")
    shown = page.inner_text("#timeline")
    for where in ("agent", "object", "recipient", "key", "value", "run", "person"):
        assert f"{where} {HOSTILE}" in shown, where
    assert page.locator("#timeline img").count() == 0
    page.locator("#timeline .vis-item.episode").hover()
    page.wait_for_selector(".vis-tooltip", state="visible")
    assert f"(type {HOSTILE})" in page.inner_text(".vis-tooltip")
    assert not [url for url in page.requests if "127.0.0.1:9/" in url]


def test_a_view_shows_it_is_loading_until_its_data_comes_and_what_it_shows(
    page: Any, hostile_server: RunningServer
) -> None:
    held: list[Any] = []
    page.route(lambda url: "/views/episodes?" in url, lambda route: held.append(route))
    page.goto(f"{hostile_server.url}/web/#episodes")
    until(page, "() => document.body.dataset.loading === 'true'")
    page.wait_for_timeout(100)  # let the held request reach the route
    assert page.locator("#loading").is_visible()
    answer = held[0].fetch()
    body = answer.json()
    body["total"] = 10_000  # as if the memory held more than the timeline draws
    held[0].fulfill(response=answer, json=body)
    page.wait_for_selector("#timeline .vis-item.episode", state="visible")
    assert page.locator("#loading").is_hidden()
    assert page.inner_text("#timeline-note") == "Showing the newest 1 of 10000 episodes."


def test_with_the_server_gone_pages_say_so(page: Any, tmp_path: Path) -> None:
    with _server(tmp_path / "data") as server:
        page.goto(f"{server.url}/web/#query")
        page.wait_for_selector("#query-examples option", state="attached")
        assert page.locator("#banner").is_hidden()
        server.stop()
        page.click("#query-run")
        page.wait_for_selector("#banner", state="visible")
        assert "did not answer /sparql: is it still running?" in page.inner_text("#banner")
        assert "still running" in page.inner_text("#query-results .error")
        page.click("#banner-close")
        assert page.locator("#banner").is_hidden()
        page.evaluate("location.hash = '#graph'")
        page.wait_for_selector("#banner", state="visible")
        assert "is it still running?" in page.inner_text("#banner")
        assert page.locator("#loading").is_hidden()
        page.evaluate("location.hash = '#episodes'")  # a view whose module never loaded
        until(page, "() => document.querySelector('#banner').textContent.includes('episodes')")
        assert "could not be loaded from the server" in page.inner_text("#banner")


def test_the_api_reference_needs_no_other_host(page: Any, hostile_server: RunningServer) -> None:
    foreign: list[str] = []

    def guard(route: Any) -> None:
        if route.request.url.startswith(hostile_server.url + "/"):
            route.continue_()
        else:
            foreign.append(route.request.url)
            route.abort()

    page.route("**/*", guard)
    page.goto(f"{hostile_server.url}/redoc")
    assert page.url == f"{hostile_server.url}/docs"
    page.wait_for_selector("#swagger-ui .opblock", state="visible")
    assert page.locator("#swagger-ui .opblock").count() > 20
    assert "Engram" in page.inner_text("#swagger-ui .info")
    assert foreign == []
