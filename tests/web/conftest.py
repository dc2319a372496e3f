"""A demo-like memory behind a live server, shared by the view tests of one module.

The memory is built in this process with the public APIs (scene memory, episode memory and its
stream recorder) on the data directory the server then opens: four kinds of scene stored inside
an episode that recorded joint states and a camera, a second episode, sleep passes that forget
the scene seen once, one class pinned, an annotation over a range, an augmentation run with a
rating.
"""

import datetime as dt
import gc
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from pyoxigraph import NamedNode

from api.config import Settings
from api.main import create_app
from episodes import ArgumentSpec, EpisodeMemory
from kg import Store
from kg.clock import SimulatedClock
from kg.primitive import Primitive
from reasoners.memory import SceneMemory
from tests.conftest import free_port, serve
from tests.web.browser import CHROMIUM_ARGS, chromium_path

START = dt.datetime(2026, 1, 26, 8, 0, tzinfo=dt.UTC)
T0_NS = int(START.timestamp() * 1e9)
TICKS = 300
TICK_NS = 10_000_000
VIEWPORT = {"width": 1280, "height": 800}

YELLOW, BLUE, RED, GREEN, GREY = (
    (0.95, 0.8, 0.1),
    (0.1, 0.3, 0.9),
    (0.9, 0.15, 0.1),
    (0.1, 0.7, 0.2),
    (0.6, 0.6, 0.6),
)


def _table() -> Primitive:
    return Primitive("table", "Plane", centre=(0.0, 0.0, 0.0), axis=(0, 0, 1), colour=GREY)


_BREAKFAST = [
    _table(),
    Primitive("ball", "Sphere", centre=(-0.18, 0.0, 0.04), radius=0.04, colour=YELLOW),
    Primitive(
        "can",
        "Cylinder",
        centre=(0.12, 0.0, 0.07),
        axis=(0, 0, 1),
        radius=0.04,
        height=0.14,
        colour=BLUE,
    ),
]

SCENES: dict[str, list[Primitive]] = {
    "breakfast": _BREAKFAST,
    "funnel": [
        *_BREAKFAST,
        Primitive(
            "funnel",
            "Cone",
            centre=(0.0, 0.2, 0.06),
            axis=(0, 0, 1),
            radius=0.05,
            height=0.12,
            colour=RED,
        ),
    ],
    "two cans": [
        Primitive(
            "left",
            "Cylinder",
            centre=(-0.15, 0.1, 0.05),
            axis=(0, 0, 1),
            radius=0.035,
            height=0.1,
            colour=GREEN,
        ),
        Primitive(
            "right",
            "Cylinder",
            centre=(0.15, -0.05, 0.09),
            axis=(0, 0, 1),
            radius=0.04,
            height=0.18,
            colour=RED,
        ),
    ],
    "ball before a cone": [
        Primitive("ball", "Sphere", centre=(0.0, -0.12, 0.05), radius=0.05, colour=RED),
        Primitive(
            "cone",
            "Cone",
            centre=(0.0, 0.18, 0.07),
            axis=(0, 0, 1),
            radius=0.05,
            height=0.14,
            colour=GREEN,
        ),
    ],
}
SCRIPT = ("breakfast", "funnel", "two cans", "breakfast", "ball before a cone", "breakfast")


@dataclass
class ViewServer:
    """The live server over the demo-like memory, and what the memory was built with."""

    url: str
    client: httpx.Client
    episode: str
    screenshots: Path


def build_memory(data_dir: Path) -> str:
    """Write the demo-like memory into ``data_dir``; returns the recorded episode's id."""
    store = Store(data_dir / "store")
    clock = SimulatedClock(START)
    memory = SceneMemory(store, clock=clock)
    episodes = EpisodeMemory(store, data_dir=data_dir, clock=clock)
    episode = episodes.begin(
        "tidying",
        activity_type="demonstration",
        arguments=[ArgumentSpec("agent", "HyungJin"), ArgumentSpec("object", "table")],
        episode_id="tidying-1",
        record=True,
    )
    recorder = episodes.streams.recordings.get(episode.id)
    recorder.add_provider("arm/joints", "joint_state", names=["shoulder", "elbow"])
    recorder.add_provider("cam/rgb", "image", encoding="rgb8")
    for i in range(TICKS):
        phase = i / 50
        joints = np.array([np.sin(phase), np.cos(phase) * 0.5])
        samples: dict[str, object] = {"arm/joints": joints}
        if i % 10 == 0:
            image = np.zeros((24, 32, 3), dtype=np.uint8)
            image[:, : 1 + (i // 10) % 32] = (200, 60, 20)
            samples["cam/rgb"] = image
        recorder.tick(samples, time_ns=T0_NS + i * TICK_NS)
    for k, title in enumerate(SCRIPT):
        clock.now = START + dt.timedelta(minutes=10 * k)
        memory.store_scene(SCENES[title], episode=NamedNode(episode.iri))
    clock.now = START + dt.timedelta(hours=2)
    episodes.annotate(
        episode.id,
        key="phase",
        value="setting the table",
        start=START + dt.timedelta(minutes=5),
        end=START + dt.timedelta(minutes=40),
    )
    episodes.end(episode.id)
    run = episodes.runs.start(episode.id, name="grasp-detector", producer="tests")
    episodes.runs.end(episode.id, run.id)
    episodes.ratings.rate(episode.id, run.id, person="Ana", value=8)
    clock.now = START + dt.timedelta(hours=3)
    other = episodes.begin("babbling", arguments=[ArgumentSpec("agent", "iCub")])
    clock.now = START + dt.timedelta(hours=4)
    episodes.end(other.id)
    for day in range(1, 7):  # nights: the scene seen once fades and is forgotten
        clock.now = START + dt.timedelta(days=day)
        memory.sleep()
    for summary in memory.reads.classes():
        if summary.scores.store_count >= 3:
            memory.pin(summary.iri)
    store.flush()
    del memory, episodes, store
    gc.collect()  # the memories hold the store in cycles; free them to unlock the directory
    return episode.id


@pytest.fixture(scope="module")
def view_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[ViewServer]:
    """A live server on loopback over the demo-like memory."""
    data_dir = tmp_path_factory.mktemp("views") / "data"
    episode = build_memory(data_dir)
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data_dir)
    with (
        serve(create_app(settings), settings) as running,
        httpx.Client(base_url=running.url, timeout=60) as client,
    ):
        shots = Path(__file__).parents[2] / "docs" / "screenshots"
        yield ViewServer(running.url, client, episode, shots)


@dataclass
class Watched:
    """A page and what it said and asked for."""

    page: Any
    errors: list[str] = field(default_factory=list)
    foreign: list[str] = field(default_factory=list)
    requests: list[str] = field(default_factory=list)


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    """Debian's headless Chromium driven by Playwright (skips when either is missing)."""
    playwright_api = pytest.importorskip("playwright.sync_api")
    if chromium_path() is None:  # scripts/test installs it; say what is missing elsewhere
        pytest.skip("Debian package chromium-headless-shell is not installed")
    with playwright_api.sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=str(chromium_path()), args=CHROMIUM_ARGS)
        yield chromium
        chromium.close()


HISTORY_ROUTE = "/memory/history"
"""Another area's endpoint the class panel reads; until a server has it, it answers 404 and
the page says so (Chromium logs the 404 of any fetch as a console error: not a page error)."""


def _is_error(message: Any) -> bool:
    if message.type != "error":
        return False
    resource = str((message.location or {}).get("url", ""))
    return not (HISTORY_ROUTE in resource and "404" in message.text)


@pytest.fixture
def watched(browser: Any, view_server: ViewServer) -> Iterator[Watched]:
    """A fresh page that records console errors and requests, and blocks any foreign host."""
    context = browser.new_context(viewport=VIEWPORT, accept_downloads=True)
    page = context.new_page()
    seen = Watched(page)
    page.on("console", lambda m: seen.errors.append(m.text) if _is_error(m) else None)
    page.on("pageerror", lambda e: seen.errors.append(str(e)))

    def guard(route: Any) -> None:
        url = route.request.url
        seen.requests.append(url)
        if url.startswith(view_server.url + "/") or url.startswith("data:"):
            route.continue_()
        else:
            seen.foreign.append(url)
            route.abort()

    page.route("**/*", guard)
    yield seen
    context.close()
    assert seen.errors == [], seen.errors
    assert seen.foreign == [], seen.foreign
