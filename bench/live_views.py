"""Scene stores with live views open: the time of storing a scene over HTTP (one directive list)
with no ``/views/scenes/live`` stream open, then with ``--streams`` (50) open, and the ratio.

Target (issue 29): within 1.5 times. The streams are read by one asyncio thread in this process
(as 50 browser tabs would hold them), the server runs in another thread; both runs use the same
server and store, alternating, so the ratio compares like with like.

    PYTHONPATH=. .venv/bin/python bench/live_views.py [--streams 50] [--stores 40]
"""

import argparse
import asyncio
import random
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from api.client import ArmorClient, Primitive
from api.config import Settings
from api.main import create_app
from tests.conftest import free_port, serve

SEED = 29


def _scene(rng: random.Random) -> list[Primitive]:
    x = rng.uniform(-1, 1)
    return [
        Primitive("ball", "Sphere", centre=(x, 0.0, 0.04), radius=rng.uniform(0.02, 0.08)),
        Primitive(
            "can",
            "Cylinder",
            centre=(x + rng.uniform(0.1, 0.4), 0.0, 0.07),
            axis=(0, 0, 1),
            radius=0.04,
            height=rng.uniform(0.05, 0.2),
        ),
    ]


def store_times_ms(client: ArmorClient, rng: random.Random, count: int) -> list[float]:
    times = []
    for _ in range(count):
        began = time.perf_counter()
        client.memory.store_scene(_scene(rng))
        times.append((time.perf_counter() - began) * 1000)
    return times


class Streams:
    """``count`` live streams held open by one asyncio loop in a thread, until ``close``."""

    def __init__(self, url: str, count: int) -> None:
        self.url, self.count = url, count
        self.events = 0
        self.opened = threading.Event()
        self._stop: asyncio.Event | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._thread = threading.Thread(target=lambda: asyncio.run(self._run()), daemon=True)
        self._thread.start()
        if not self.opened.wait(60):
            raise RuntimeError("the streams did not open")

    async def _listen(self, http: httpx.AsyncClient, ready: list[int]) -> None:
        while not self._stop.is_set():  # type: ignore[union-attr]
            async with http.stream("GET", "/views/scenes/live") as answer:
                async for line in answer.aiter_lines():
                    if line.startswith("data:"):
                        self.events += 1
                        ready.append(1)
                        if len(ready) >= self.count:
                            self.opened.set()
                    if self._stop.is_set():  # type: ignore[union-attr]
                        return

    async def _run(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stop = asyncio.Event()
        limits = httpx.Limits(max_connections=self.count + 5)
        headers = {"Accept": "text/event-stream"}
        async with httpx.AsyncClient(
            base_url=self.url, timeout=60, limits=limits, headers=headers
        ) as http:
            ready: list[int] = []
            tasks = [asyncio.create_task(self._listen(http, ready)) for _ in range(self.count)]
            await self._stop.wait()
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

    def close(self) -> None:
        if self._loop is not None and self._stop is not None:
            self._loop.call_soon_threadsafe(self._stop.set)
        self._thread.join(timeout=30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--streams", type=int, default=50)
    parser.add_argument("--stores", type=int, default=40, help="scene stores per run")
    parser.add_argument("--rounds", type=int, default=2, help="runs of each kind, alternating")
    args = parser.parse_args()
    rng = random.Random(SEED)
    with tempfile.TemporaryDirectory() as work:
        settings = Settings(host="127.0.0.1", port=free_port(), data_dir=Path(work) / "data")
        server, thread, url = serve(create_app(settings), settings)
        try:
            with ArmorClient("camera", "engram", base_url=url, timeout=60) as client:
                store_times_ms(client, rng, 10)  # warm up: the first scenes learn classes
                without: list[float] = []
                with_streams: list[float] = []
                for _ in range(args.rounds):
                    without += store_times_ms(client, rng, args.stores)
                    streams = Streams(url, args.streams)
                    try:
                        with_streams += store_times_ms(client, rng, args.stores)
                    finally:
                        streams.close()
                    print(f"  {args.streams} streams received {streams.events} events")
        finally:
            server.should_exit = True
            thread.join(timeout=30)
    base, loaded = statistics.median(without), statistics.median(with_streams)
    print(f"scene store p50 without streams: {base:.1f} ms ({len(without)} stores)")
    print(f"scene store p50 with {args.streams} live streams: {loaded:.1f} ms")
    print(f"ratio: {loaded / base:.2f} (target <= 1.5)")


if __name__ == "__main__":
    main()
