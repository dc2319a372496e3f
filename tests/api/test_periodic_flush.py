"""The server's periodic task flushes the store after writes, so a crash replays little."""

import time
from collections.abc import Callable

import pytest

from kg import Store
from tests.conftest import LiveServer

LOAD = {
    "armor_request": {
        "client_name": "tester",
        "reference_name": "flushed",
        "command": "LOAD",
        "primary_command_spec": "FILE",
        "args": ["", "http://ex.org/flushed", "false", "PELLET", "true"],
    }
}


def test_the_server_flushes_only_after_it_committed_something(
    start_server: Callable[..., LiveServer], monkeypatch: pytest.MonkeyPatch
) -> None:
    flushes: list[int] = []
    original = Store.flush

    def counted(self: Store) -> None:
        flushes.append(self.generation)
        original(self)

    monkeypatch.setattr(Store, "flush", counted)
    server = start_server(sleep_check_s=0.05)
    time.sleep(0.5)  # ten checks with nothing committed
    assert flushes == []
    answer = server.client.post("/armor_interface_srv", json=LOAD).json()
    assert answer["armor_response"]["success"], answer
    deadline = time.monotonic() + 10
    while not flushes and time.monotonic() < deadline:
        time.sleep(0.02)
    assert len(flushes) == 1
    time.sleep(0.3)
    assert len(flushes) == 1, "no second flush without a new write"
