"""The lived week of :mod:`api.ask.samples` (episodes and scenes, one scene class forgotten)
to ask: "now" is Wednesday 2026-03-04 10:00 UTC."""

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from api.ask import Asker
from api.ask.samples import START, TWO_BALLS, live_a_week
from api.config import Settings
from api.main import create_app
from kg import Store
from kg.clock import SimulatedClock
from tests.conftest import LiveServer, free_port, serve

__all__ = ["TWO_BALLS"]


@pytest.fixture
def clock() -> SimulatedClock:
    return SimulatedClock(START)


@pytest.fixture
def asker(clock: SimulatedClock) -> Asker:
    """An Asker over the lived week, "now" Wednesday 2026-03-04 10:00 UTC."""
    return Asker(*live_a_week(Store(), clock))


def write_lived_week(data: Path) -> Path:
    """A data directory holding the lived week (for the CLI and the server)."""
    store = Store(data / "store")
    live_a_week(store, SimulatedClock(START))
    store.flush()
    del store
    return data


@pytest.fixture
def lived_data_dir(tmp_path: Path) -> Path:
    return write_lived_week(tmp_path / "data")


@pytest.fixture(scope="module")
def lived_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    """A server over the lived week, shared by the tests of one module."""
    data = write_lived_week(tmp_path_factory.mktemp("lived"))
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data)
    with (
        serve(create_app(settings), settings) as running,
        httpx.Client(base_url=running.url, timeout=60) as client,
    ):
        yield LiveServer(running.url, settings, client)
