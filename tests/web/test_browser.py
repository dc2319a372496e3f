"""The four views in a real headless Chromium against the live server: their elements, their
pixels, no console error, and no request to any host but the server.

Each test saves a screenshot under ``docs/screenshots/`` (the README shows them).
"""

import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image

from tests.web.browser import chromium_path, until
from tests.web.conftest import ViewServer, Watched

pytestmark = pytest.mark.slow

playwright_api = pytest.importorskip("playwright.sync_api")
if chromium_path() is None:  # scripts/test installs it; say what is missing elsewhere
    pytest.skip("Debian package chromium-headless-shell is not installed", allow_module_level=True)


def _pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def _colours(png: bytes) -> int:
    return len(np.unique(_pixels(png).reshape(-1, 3), axis=0))


def _save(view_server: ViewServer, page: Any, name: str) -> None:
    view_server.screenshots.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(view_server.screenshots / f"{name}.png"))


def test_memory_graph_draws_classes_and_shows_a_class(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    page.goto(f"{view_server.url}/")  # / leads to the views
    page.wait_for_selector("#cy[data-nodes='4']")
    assert page.get_attribute("#cy", "data-edges") == "1"
    shot = page.locator("#cy").screenshot()
    pixels = _pixels(shot)
    green = np.all(np.abs(pixels - [46, 125, 50]) < 12, axis=2).sum()  # HIGH nodes
    amber = np.all(np.abs(pixels - [249, 168, 37]) < 12, axis=2).sum()  # LOW nodes
    assert green > 500 and amber > 500
    best = page.evaluate(
        "fetch('/views/classes').then(r => r.json()).then(b => "
        "b.classes.reduce((a, c) => c.score > a.score ? c : a).name)"
    )
    page.evaluate("name => { window.engramGraph.$id(name).emit('tap'); }", best)
    page.wait_for_selector(f"#class-detail[data-selected='{best}']")
    text = page.inner_text("#class-detail")
    assert "a sphere left of a cylinder" in text and "Unpin" in text
    page.fill("#graph-search", "cone isBehindOf")
    page.wait_for_selector("#graph-count[data-matches='2']")
    _save(view_server, page, "memory-graph")


def test_large_memories_draw_an_overview_that_selects_classes(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    page.goto(f"{view_server.url}/web/?overview#graph")  # as a memory of 10,000 classes draws
    canvas = page.wait_for_selector("#graph-overview[data-positions]")
    positions = json.loads(canvas.get_attribute("data-positions") or "[]")
    assert len(positions) == 4
    pixels = _pixels(canvas.screenshot())
    for point in positions:
        x, y = round(point["x"]), round(point["y"])
        assert np.abs(pixels[y, x] - [255, 255, 255]).sum() > 60, point
    page.wait_for_selector("#graph-overview[data-edges-drawn]")  # edges follow the nodes
    pixels = _pixels(canvas.screenshot())
    at = {p["name"]: (p["x"], p["y"]) for p in positions}
    classes = view_server.client.get("/views/classes").json()["classes"]
    edges = [(at[p], at[c["name"]]) for c in classes for p in c["parents"] if p in at]
    assert edges
    for (x0, y0), (x1, y1) in edges:  # the line's middle is darker than the background
        x, y = round((x0 + x1) / 2), round((y0 + y1) / 2)
        patch = pixels[y - 1 : y + 2, x - 1 : x + 2].reshape(-1, 3)
        assert (255 * 3 - patch.sum(axis=1)).max() > 45, (x, y)
    target = positions[-1]
    canvas.click(position={"x": target["x"], "y": target["y"]})
    page.wait_for_selector(f"#class-detail[data-selected='{target['name']}']")
    page.fill("#graph-search", "cone isBehindOf")
    page.wait_for_selector("#graph-count[data-matches='2']")


def test_pin_asks_for_nothing_without_a_token_and_pins(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    page.goto(f"{view_server.url}/web/#graph")
    page.wait_for_selector("#cy[data-nodes='4']")
    classes = view_server.client.get("/views/classes").json()["classes"]
    loose = next(c for c in classes if not c["pinned"])
    page.evaluate("n => { window.engramGraph.$id(n).emit('tap'); }", loose["name"])
    page.wait_for_selector(f"#class-detail[data-selected='{loose['name']}'] #pin")
    page.click("#pin")
    page.wait_for_selector("#class-detail:has-text('Unpin')")
    after = view_server.client.get(f"/views/classes/{loose['name']}").json()
    assert after["node"]["pinned"] is True
    page.click("#pin")  # and back, for the other tests
    page.wait_for_selector("#class-detail:has-text('Pin (never forget)')")


def test_scene_in_3d_draws_the_primitives_where_they_are(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    page.goto(f"{view_server.url}/web/#scene")
    canvas = page.wait_for_selector("#scene-canvas canvas[data-primitives='3']")
    projected = json.loads(canvas.get_attribute("data-projected") or "[]")
    pixels = _pixels(canvas.screenshot())
    background = np.array([0xEE, 0xF1, 0xF5])
    expected = {"ball": [242, 204, 26], "can": [26, 77, 230]}  # stored colours, lit
    for point in projected:
        x, y = round(point["x"]), round(point["y"])
        patch = pixels[y - 2 : y + 3, x - 2 : x + 3].reshape(-1, 3)
        assert np.abs(patch - background).sum(axis=1).min() > 30, point["id"]
        if point["id"] in expected:
            mean = patch.mean(axis=0)
            hue = np.argmax(mean) if point["id"] == "can" else None
            assert hue in (None, 2), (point, mean)
    drawn = np.abs(pixels - background).sum(axis=2) > 30
    assert drawn.mean() > 0.05
    page.check("#scene-relations")
    page.wait_for_timeout(200)
    with_arrows = _pixels(canvas.screenshot())
    assert (np.abs(with_arrows - pixels).sum(axis=2) > 30).sum() > 100  # arrows and labels
    labels = json.loads(canvas.get_attribute("data-labels") or "[]")
    assert "can isAboveOf table" in {label["text"] for label in labels}
    for label in labels:  # each label's texture holds its whole text
        assert label["textWidth"] < label["canvasWidth"], label
    _save(view_server, page, "scene-3d")


def test_live_mode_follows_the_latest_scene(watched: Watched, view_server: ViewServer) -> None:
    page = watched.page
    first = view_server.client.get("/views/scenes").json()["scenes"][-1]["name"]
    page.goto(f"{view_server.url}/web/#scene/{first}")
    page.wait_for_selector(f"#scene-canvas canvas[data-scene='{first}']")
    page.check("#scene-live")
    latest = view_server.client.get("/views/scenes/latest").json()["scene"]["name"]
    page.wait_for_selector(f"#scene-canvas canvas[data-scene='{latest}']")


def test_episodes_timeline_channels_plot_and_camera(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    page.goto(f"{view_server.url}/web/#episodes")
    page.wait_for_selector("#timeline .vis-item.episode", state="visible")
    for kind in ("annotation", "scene", "run", "rating"):
        assert page.locator(f"#timeline .vis-item.{kind}").count() >= 1, kind
    assert _colours(page.locator("#timeline").screenshot()) > 20
    page.locator("#timeline .vis-item.episode", has_text="tidying").click()
    page.wait_for_selector("#episode-detail[data-episode='tidying-1'] .plot canvas")
    plot = page.locator(".plot[data-channel='arm/joints']")
    assert plot.get_attribute("data-points") == "300"
    plot_pixels = _pixels(plot.locator("canvas").first.screenshot())
    blue = np.all(np.abs(plot_pixels - [21, 101, 192]) < 40, axis=2).sum()
    assert blue > 100  # the shoulder's curve
    camera = page.wait_for_selector(".camera canvas[data-painted]")
    page.locator(".scrubber").fill("20")
    page.wait_for_selector(".camera canvas[data-painted='2']")
    orange = _pixels(camera.screenshot())
    assert (np.abs(orange - [200, 60, 20]).sum(axis=2) < 40).mean() > 0.3  # frame 201's bar
    page.select_option("#replay-speed", "10")
    page.click("#replay-play")
    until(page, "() => Number(document.querySelector('#replay-seek').value) > 100")
    page.click("#replay-stop")
    _save(view_server, page, "episodes")


def test_query_page_runs_an_example_and_downloads_csv(
    watched: Watched, view_server: ViewServer
) -> None:
    page = watched.page
    page.goto(f"{view_server.url}/web/#query")
    page.wait_for_selector("#query-examples option", state="attached")
    assert "PREFIX engram:" in page.input_value("#query-text")
    page.select_option("#query-examples", "Triples per graph")
    page.click("#query-run")
    page.wait_for_selector("#query-results table td")
    assert "graph/tbox" in page.inner_text("#query-results")
    with page.expect_download() as download:
        page.click("#query-csv")
    body = Path(download.value.path()).read_text()
    assert body.splitlines()[0].strip() == "graph,triples"
    page.fill("#query-text", "DELETE WHERE { ?s ?p ?o }")
    page.click("#query-run")
    page.wait_for_selector("#query-results .error")
    watched.errors.clear()  # the refused update is logged by the browser as a failed request
    _save(view_server, page, "query")
