"""The lived week of :mod:`api.ask.samples` (episodes and scenes, one scene class forgotten)
to ask: "now" is Wednesday 2026-03-04 10:00 UTC."""

from pathlib import Path

import pytest

from api.ask import Asker
from api.ask.samples import TWO_BALLS, Clock, live_a_week
from kg import Store

__all__ = ["TWO_BALLS"]


@pytest.fixture
def clock() -> Clock:
    return Clock()


@pytest.fixture
def asker(clock: Clock) -> Asker:
    """An Asker over the lived week, "now" Wednesday 2026-03-04 10:00 UTC."""
    return Asker(*live_a_week(Store(), clock))


@pytest.fixture
def lived_data_dir(tmp_path: Path) -> Path:
    """A data directory holding the lived week (for the CLI and the server)."""
    data = tmp_path / "data"
    store = Store(data / "store")
    live_a_week(store, Clock())
    store.flush()
    del store
    return data
