"""Live scene views are fed by one producer per server: however many streams are open, a
write costs one read of the latest scene, and every stream still gets it."""

import json
import threading
from collections.abc import Callable
from typing import Any

import httpx
import pytest

from api.client import ArmorClient, Primitive
from api.views import scenes
from tests.conftest import LiveServer

STREAMS = 12
FOLLOW = {"Accept": "text/event-stream"}


def _scene(offset: float) -> list[Primitive]:
    return [
        Primitive("ball", "Sphere", centre=(offset, 0.0, 0.04), radius=0.04),
        Primitive(
            "can",
            "Cylinder",
            centre=(offset + 0.2, 0.0, 0.07),
            axis=(0, 0, 1),
            radius=0.04,
            height=0.14,
        ),
    ]


def test_many_streams_cost_one_read_per_write(
    start_server: Callable[..., LiveServer], monkeypatch: pytest.MonkeyPatch
) -> None:
    server = start_server()
    with ArmorClient("camera", "engram", base_url=server.url) as client:
        client.memory.store_scene(_scene(0.0))
    reads: list[int] = []
    latest = scenes.latest_scene

    def counted(store: Any) -> Any:
        reads.append(1)
        return latest(store)

    monkeypatch.setattr(scenes, "latest_scene", counted)
    received: list[list[str]] = [[] for _ in range(STREAMS)]
    connected = threading.Barrier(STREAMS + 1, timeout=30)
    pushed = threading.Barrier(STREAMS + 1, timeout=30)

    def listen(index: int) -> None:
        with (
            httpx.Client(base_url=server.url, timeout=30, headers=FOLLOW) as http,
            http.stream("GET", "/views/scenes/live") as answer,
        ):
            for line in answer.iter_lines():
                if line.startswith("data:"):
                    received[index].append(json.loads(line[5:])["scene"]["name"])
                    (connected if len(received[index]) == 1 else pushed).wait()
                    if len(received[index]) == 2:
                        return

    threads = [threading.Thread(target=listen, args=(i,), daemon=True) for i in range(STREAMS)]
    for thread in threads:
        thread.start()
    connected.wait()
    before = len(reads)
    with ArmorClient("camera", "engram", base_url=server.url) as client:
        client.memory.store_scene(_scene(1.0))
    pushed.wait()
    for thread in threads:
        thread.join(timeout=30)
    assert len({tuple(names) for names in received}) == 1  # every stream saw the same two
    assert len(received[0]) == 2 and received[0][0] != received[0][1]
    assert before <= 2, reads  # the first read, shared by every stream (not one per stream)
    assert len(reads) - before <= 3  # the scene store's writes, read once each
