"""Fixtures shared by every test package: stores, and a real server on a loopback port."""

import socket
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
import uvicorn

from api.config import Settings
from api.header_timeout import with_header_timeout
from api.main import create_app
from kg import Store, ensure_ontology


@pytest.fixture
def empty_store() -> Store:
    """An in-memory store with nothing in it."""
    return Store()


@pytest.fixture
def store_with_ontology() -> Store:
    """An in-memory store holding the Engram T-Box."""
    store = Store()
    ensure_ontology(store)
    return store


@pytest.fixture
def disk_store(tmp_path: Path) -> Iterator[Store]:
    """An on-disk store in a temporary directory, holding the Engram T-Box."""
    store = Store(tmp_path / "store")
    ensure_ontology(store)
    yield store
    del store


@dataclass
class LiveServer:
    """A running server: its base URL, its settings and an HTTP client bound to it."""

    url: str
    settings: Settings
    client: httpx.Client


def free_port() -> int:
    """A TCP port on 127.0.0.1 that was free a moment ago."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port


def serve(app: Any, settings: Settings) -> tuple[uvicorn.Server, threading.Thread, str]:
    """Run ``app`` with uvicorn in a daemon thread on ``settings``' host and port, with ``engram
    serve``'s protocol and time limits; returns once it serves, with its base URL. Stop it with
    ``server.should_exit = True; thread.join()``."""
    config = uvicorn.Config(
        app,
        host=settings.host,
        port=settings.port,
        log_level="warning",
        http=with_header_timeout(settings.header_timeout_s, body_timeout_s=settings.body_timeout_s),
    )
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if not thread.is_alive() or time.monotonic() > deadline:
            raise RuntimeError("the test server did not start")
        time.sleep(0.02)
    return server, thread, f"http://{settings.host}:{settings.port}"


@pytest.fixture
def start_server(tmp_path: Path) -> Iterator[Callable[..., LiveServer]]:
    """Start a server with the given settings overrides; every server stops after the test."""
    running: list[tuple[uvicorn.Server, threading.Thread, httpx.Client]] = []

    def start(**overrides: Any) -> LiveServer:
        overrides.setdefault("data_dir", tmp_path / f"data-{len(running)}")
        settings = Settings(host="127.0.0.1", port=free_port(), **overrides)
        server, thread, url = serve(create_app(settings), settings)
        client = httpx.Client(base_url=url, timeout=60)
        running.append((server, thread, client))
        return LiveServer(url, settings, client)

    yield start
    for server, thread, client in running:
        client.close()
        server.should_exit = True
        thread.join(timeout=30)


@pytest.fixture
def live_server(start_server: Callable[..., LiveServer]) -> LiveServer:
    """A server with default settings (no token) over a fresh store."""
    return start_server()
