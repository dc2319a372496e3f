"""Web views: the memory graph of 10,000 classes and a 10-minute 100 Hz channel's plot.

Targets: the class list endpoint < 100 ms and the graph's first paint < 2 s in headless
Chromium for 10,000 classes; plot data for a 10-minute 100 Hz channel decimated to ≤ 2,000
points < 50 ms, also on its first read (nothing cached in the server: the median of
``--repeat`` reads, the server's cache emptied before each). Each figure is printed
with its ratio to ``GET /health`` measured in the same run against the same server (the cost
of one request); the plot's first read also beside the replay read it replaced.

    PYTHONPATH=. .venv/bin/python bench/views.py [--classes 10000] [--repeat 5]
"""

import argparse
import gc
import random
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import uvicorn

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from api.config import Settings
from api.main import create_app
from api.views import channels
from bench.scene_memory import random_scene
from episodes import EpisodeMemory
from kg import Store
from reasoners.memory import SceneMemory
from tests.conftest import free_port
from tests.web.browser import CHROMIUM_ARGS, chromium_path

SEED = 18
T0_NS = 1_770_000_000_000_000_000


def build(data_dir: Path, classes: int, samples: int) -> None:
    store = Store(data_dir / "store")
    memory = SceneMemory(store)
    rng = random.Random(SEED)
    learned = 0
    while learned < classes:
        batch: list[Any] = []
        while len(batch) < min(500, classes - learned):
            signature = memory.encoder.signature(random_scene(rng, rng.randint(2, 5)))
            if signature:
                batch.append(signature)
        learned += len(memory.learn_classes(batch))
    episodes = EpisodeMemory(store, data_dir=data_dir)
    episode = episodes.begin("babbling", episode_id="long", record=True)
    recorder = episodes.streams.recordings.get(episode.id)
    recorder.add_provider("arm/effort", "float_array", dtype="float64", shape=[4])
    values = np.random.default_rng(SEED).normal(size=(samples, 4))
    for i in range(samples):
        recorder.tick({"arm/effort": values[i]}, time_ns=T0_NS + i * 10_000_000)
    episodes.end(episode.id)
    store.flush()
    del memory, episodes, store
    gc.collect()


def serve(settings: Settings) -> tuple[uvicorn.Server, threading.Thread, str]:
    """The app on a loopback port; waits for it to open a large memory (minutes at most)."""
    server = uvicorn.Server(
        uvicorn.Config(
            create_app(settings), host=settings.host, port=settings.port, log_level="warning"
        )
    )
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 600
    while not server.started:
        if not thread.is_alive() or time.monotonic() > deadline:
            raise RuntimeError("the server did not start")
        time.sleep(0.1)
    url = f"http://{settings.host}:{settings.port}"
    while httpx.get(f"{url}/health", timeout=60).json().get("status") == "loading":
        if time.monotonic() > deadline:  # the memory opens in the background
            raise RuntimeError("the memory did not finish loading")
        time.sleep(0.2)
    return server, thread, url


def timed(client: httpx.Client, url: str, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        began = time.perf_counter()
        answer = client.get(url)
        times.append(time.perf_counter() - began)
        answer.raise_for_status()
    return statistics.median(times)


# "painted": the page's frame callback after the nodes are drawn (mark "graph-frame"), when
# the browser starts producing the frame that shows them; the edges are drawn in a task after
# that frame (mark "graph-edges")
PHASES = """new Promise(r => requestAnimationFrame(() => {
  const mark = (n) => performance.getEntriesByName(n)[0]?.startTime ?? NaN;
  const list = performance.getEntriesByType("resource")
    .find((e) => e.name.includes("/views/classes"));
  r({painted: mark("graph-frame"), load: mark("graph-load"), fetched: mark("graph-fetched"),
     drawn: mark("graph-drawn"), bytes: list ? list.encodedBodySize : NaN,
     request: list ? list.responseStart - list.requestStart : NaN});
}))"""


def first_paint(url: str, classes: int) -> dict[str, float]:
    """The page's own clock (ms from the navigation's start): the graph painted, and its
    phases (module start, class list fetched, nodes drawn, edges drawn in a later task; the
    list's bytes and server time); plus ``wall``, ms around the page load as seen from here."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(chromium_path()), args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        began = time.perf_counter()
        page.goto(f"{url}/web/#graph")
        page.wait_for_selector(f"#cy[data-nodes='{classes}']", timeout=120_000)
        phases: dict[str, float] = page.evaluate(PHASES)
        phases["wall"] = (time.perf_counter() - began) * 1000
        phases["edges"] = float("nan")  # a small graph is drawn whole, with no overview
        if page.query_selector("#graph-overview") is not None:
            page.wait_for_selector("#graph-overview[data-edges-drawn]", timeout=120_000)
            phases["edges"] = page.evaluate(
                "new Promise(r => requestAnimationFrame(() => requestAnimationFrame("
                "() => r(performance.getEntriesByName('graph-edges')[0].startTime))))"
            )
        browser.close()
    return phases


def replay_read_s(bag: Path) -> tuple[float, float]:
    """The first read of the channel as the views read it before they used the file's indexes:
    build a replayer (every tick record decoded; the channel list stopped there), then replay
    the channel's samples. Returns (the whole read, the replayer alone)."""
    from api.views import channels
    from episodes.streams import Replayer

    began = time.perf_counter()
    replayer = Replayer(bag)
    built = time.perf_counter() - began
    channels._read_series(replayer, "arm/effort", replayer.providers["arm/effort"])
    return time.perf_counter() - began, built


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--classes", type=int, default=10_000)
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--data", type=Path, help="Reuse (or keep) the memory built in this directory."
    )
    args = parser.parse_args()
    samples = int(args.minutes * 60 * 100)
    with tempfile.TemporaryDirectory(prefix="engram-bench-views-") as work:
        data_dir = args.data or Path(work) / "data"
        began = time.perf_counter()
        if not (data_dir / "store").exists():
            build(data_dir, args.classes, samples)
        print(
            f"built {args.classes} classes and {samples} samples "
            f"in {time.perf_counter() - began:.1f} s"
        )
        # No periodic sleep pass while measuring: one over 10,000 classes holds the memory for
        # seconds and changes every score, which is a different measurement.
        settings = Settings(
            host="127.0.0.1", port=free_port(), data_dir=data_dir, sleep_check_s=3600
        )
        server, thread, url = serve(settings)
        try:
            with httpx.Client(base_url=url, timeout=120) as client:
                health = timed(client, "/health", args.repeat)
            # just after loading: the server may still be deriving the class list (api.main
            # starts that once the memory is loaded); the page then waits for it
            cold_paint = first_paint(url, args.classes)
            paint = first_paint(url, args.classes)
            time.sleep(2)  # the browser's exit is over
            with httpx.Client(base_url=url, timeout=120) as client:
                listed_began = time.perf_counter()
                client.get("/views/episodes/long/channels").raise_for_status()
                listed = time.perf_counter() - listed_began
                plot_url = "/views/episodes/long/plot?channel=arm/effort&points=2000"
                firsts = []
                for _ in range(args.repeat):  # the server's cache emptied before each read
                    channels._cache.clear()
                    cold_began = time.perf_counter()
                    client.get(plot_url).raise_for_status()
                    firsts.append(time.perf_counter() - cold_began)
                cold = statistics.median(firsts)
                plot = timed(client, plot_url, args.repeat)
                listing = timed(client, "/views/classes", args.repeat)
                compact = timed(client, "/views/classes?relations=false", args.repeat)
        finally:
            server.should_exit = True
            thread.join(timeout=30)
        replayed, replayer_built = replay_read_s(data_dir / "streams" / "long")
    rows = [
        ("GET /health (baseline)", health, None),
        (f"GET /views/classes, {args.classes} classes", listing, 0.100),
        ("  the same, relations=false (what the page reads)", compact, 0.100),
        (f"plot of {samples} samples to 2,000 points (cached read)", plot, 0.050),
        ("the episode's channel list, first read of the file", listed, None),
        ("  the same from the replayer, as before (in process)", replayer_built, None),
        (f"plot of {samples} samples, first read of the file (median)", cold, 0.050),
        ("  the same read by replay, as before (in process)", replayed, None),
        (f"graph first paint, {args.classes} classes, just after loading", cold_paint, 2.0),
        ("  the same, once the server has derived the class list", paint, 2.0),
    ]
    for name, value, target in rows:
        phases = value if isinstance(value, dict) else None
        seconds = phases["painted"] / 1000 if phases else float(value)  # type: ignore[arg-type]
        goal = f"target < {target * 1000:.0f} ms" if target else ""
        print(f"{name:58s} {seconds * 1000:9.1f} ms  {seconds / health:8.1f}x /health  {goal}")
        if phases:
            print(
                "    module start {load:.0f} ms, list fetched {fetched:.0f} ms (server "
                "{request:.0f} ms, {bytes:.0f} bytes), drawn {drawn:.0f} ms, edges drawn "
                "{edges:.0f} ms; wall {wall:.0f} ms".format(**phases)
            )


if __name__ == "__main__":
    main()
