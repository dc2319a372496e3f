"""The server answers while the scene memory opens in the background, and saves the memory's
index file when it stops, so that the next start reads it."""

import gc
import threading
import time
from collections.abc import Callable
from pathlib import Path

import httpx
import pytest

from api.client import ArmorClient, ArmorServiceInternalError, Primitive
from api.config import Settings
from api.main import create_app
from reasoners import index_file
from tests.conftest import LiveServer, free_port, serve

SCENE = [
    Primitive("ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05),
    Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1)),
]
COUNT = "SELECT (COUNT(*) AS ?n) WHERE { ?s ?p ?o }"


def _wait_for(client: httpx.Client, state: str) -> dict[str, object]:
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        body: dict[str, object] = client.get("/health").json()
        if body["memory"]["state"] == state:  # type: ignore[index]
            return body
        time.sleep(0.05)
    raise AssertionError(f"the memory never reached {state!r}")


@pytest.mark.slow
def test_health_and_sparql_answer_while_the_memory_loads_and_directives_say_loading(
    start_server: Callable[..., LiveServer], monkeypatch: pytest.MonkeyPatch
) -> None:
    release = threading.Event()
    real = index_file.open_model

    def slow_open(*args: object, **kwargs: object) -> object:
        release.wait(30)
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(index_file, "open_model", slow_open)
    monkeypatch.setattr("reasoners.loading.LOADING_WAIT_S", 0.0)
    server = start_server()
    try:
        health = server.client.get("/health")
        assert health.status_code == 200
        assert health.json()["status"] == "loading"
        assert health.json()["memory"] == {"state": "loading", "loaded_from": None}
        sparql = server.client.get("/sparql", params={"query": COUNT})
        assert sparql.status_code == 200
        with ArmorClient("camera", "engram", base_url=server.url) as client:
            with pytest.raises(ArmorServiceInternalError) as raised:
                client.memory.store_scene(SCENE)
            assert raised.value.exit_code == 212
            assert "still loading" in str(raised.value)
            release.set()
            body = _wait_for(server.client, "ready")
            assert body["status"] == "ok"
            assert client.memory.store_scene(SCENE).details["learned"] == ["true"]
    finally:
        release.set()


@pytest.mark.slow
def test_a_stopped_server_saves_the_index_file_and_the_next_start_reads_it(
    tmp_path: Path,
) -> None:
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path / "data")
    running = serve(create_app(settings), settings)
    with httpx.Client(base_url=running.url, timeout=60) as http:
        assert _wait_for(http, "ready")["memory"] == {"state": "ready", "loaded_from": "store"}
        with ArmorClient("camera", "engram", base_url=running.url) as client:
            stored = client.memory.store_scene(SCENE)
        # the loaded heap is out of the collector's full passes while it serves
        deadline = time.monotonic() + 30
        while not gc.get_freeze_count() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert gc.get_freeze_count() > 0
    running.stop()
    assert gc.get_freeze_count() == 0  # and back in them once it stopped: the store can close
    assert settings.store_dir.with_name("store" + index_file.SUFFIX).exists()
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path / "data")
    with serve(create_app(settings), settings) as running:
        with httpx.Client(base_url=running.url, timeout=60) as http:
            body = _wait_for(http, "ready")
            assert body["memory"] == {"state": "ready", "loaded_from": "index file"}
            with ArmorClient("camera", "engram", base_url=running.url) as client:
                again = client.memory.store_scene(SCENE)
        assert again.details["learned"] == ["false"]
        assert again.values == stored.values
