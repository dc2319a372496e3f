"""Fixtures shared by every test package: stores, and a real server on a loopback port."""

import base64
import socket
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack
from dataclasses import dataclass
from itertools import count
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
import uvicorn

from api.config import Settings
from api.header_timeout import with_header_timeout
from api.main import create_app
from kg import Store, ensure_ontology


def wire_array(value: dict[str, Any]) -> np.ndarray:
    """The array of a sample value in its JSON form ``{"dtype", "shape", "b64"}``
    (:mod:`episodes.streams.wire`), decoded here without the server's code."""
    raw = base64.b64decode(value["b64"])
    return np.frombuffer(raw, dtype=value["dtype"]).reshape(value["shape"])


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


@dataclass
class RunningServer:
    """A uvicorn server running in a daemon thread at ``url``; :meth:`stop` ends it, and so does
    leaving a ``with`` block over it."""

    url: str
    server: uvicorn.Server
    thread: threading.Thread

    def stop(self) -> None:
        """Ask the server to exit and wait (up to 30 s) for its thread to end."""
        self.server.should_exit = True
        self.thread.join(timeout=30)

    def __enter__(self) -> "RunningServer":
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.stop()


def serve(app: Any, settings: Settings) -> RunningServer:
    """Run ``app`` with uvicorn in a daemon thread on ``settings``' host and port, with ``engram
    serve``'s protocol and time limits; returns once it serves.

    Raises :class:`RuntimeError` if it does not start within 30 s.
    """
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
    return RunningServer(f"http://{settings.host}:{settings.port}", server, thread)


def _starter(data_dir: Callable[[], Path], running: ExitStack) -> Callable[..., LiveServer]:
    """Starts a server with the given settings overrides over ``data_dir()`` unless one is
    given; ``running`` stops it and closes its client."""

    def start(**overrides: Any) -> LiveServer:
        overrides.setdefault("data_dir", data_dir())
        settings = Settings(host="127.0.0.1", port=free_port(), **overrides)
        url = running.enter_context(serve(create_app(settings), settings)).url
        client = running.enter_context(httpx.Client(base_url=url, timeout=60))
        return LiveServer(url, settings, client)

    return start


@pytest.fixture
def start_server(tmp_path: Path) -> Iterator[Callable[..., LiveServer]]:
    """Start a server with the given settings overrides; every server stops after the test."""
    dirs = iter(tmp_path / f"data-{n}" for n in count())
    with ExitStack() as running:
        yield _starter(lambda: next(dirs), running)


@pytest.fixture(scope="module")
def start_module_server(
    tmp_path_factory: pytest.TempPathFactory,
) -> Iterator[Callable[..., LiveServer]]:
    """:func:`start_server` for fixtures shared by a module: every server stops after it."""
    with ExitStack() as running:
        yield _starter(lambda: tmp_path_factory.mktemp("server"), running)


@pytest.fixture
def live_server(start_server: Callable[..., LiveServer]) -> LiveServer:
    """A server with default settings (no token) over a fresh store."""
    return start_server()
