"""The server protocol's time limits (api/header_timeout.py): a stalled body answers 408 on
every route, directives included; a body that keeps coming, however slowly, does not; a
connection keeps working after a body that stalled on another one."""

import json
import socket
import time
from collections.abc import Callable

import pytest

from api.header_timeout import with_header_timeout
from tests.conftest import LiveServer

DIRECTIVE = json.dumps(
    {
        "armor_request": {
            "reference_name": "r",
            "command": "GET",
            "primary_command_spec": "ALL",
            "secondary_command_spec": "REFS",
        }
    }
).encode()


@pytest.fixture
def server(start_server: Callable[..., LiveServer]) -> LiveServer:
    """A server with a 1 s body timeout (and the default 10 s header timeout)."""
    return start_server(body_timeout_s=1)


def _connect(server: LiveServer) -> socket.socket:
    host, port = server.url.removeprefix("http://").split(":")
    return socket.create_connection((host, int(port)), timeout=10)


def _head(path: str, length: int) -> bytes:
    return (
        f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
        f"Content-Length: {length}\r\n\r\n"
    ).encode()


def _answer(connection: socket.socket) -> bytes:
    received = b""
    while b"\r\n\r\n" not in received or not received.rstrip().endswith(b"}"):
        part = connection.recv(4096)
        if not part:
            break
        received += part
    return received


def test_a_stalled_directive_body_answers_408_within_the_limit(server: LiveServer) -> None:
    with _connect(server) as connection:
        connection.sendall(_head("/armor_interface_srv", len(DIRECTIVE)) + DIRECTIVE[:20])
        started = time.monotonic()
        answer = _answer(connection)
        waited = time.monotonic() - started
        assert connection.recv(4096) == b""  # closed
    assert answer.startswith(b"HTTP/1.1 408"), answer
    assert json.loads(answer.split(b"\r\n\r\n", 1)[1]) == {
        "detail": "request body: nothing received for 1 s",
        "error": "BodyTimeoutError",
    }
    assert 0.9 < waited < 8


def test_a_body_that_keeps_coming_slowly_is_answered(server: LiveServer) -> None:
    with _connect(server) as connection:
        connection.sendall(_head("/armor_interface_srv", len(DIRECTIVE)))
        for start in range(0, len(DIRECTIVE), len(DIRECTIVE) // 5 + 1):  # 1.5 s in all, 0.3 s apart
            time.sleep(0.3)
            connection.sendall(DIRECTIVE[start : start + len(DIRECTIVE) // 5 + 1])
        answer = _answer(connection)
    assert answer.startswith(b"HTTP/1.1 200"), answer
    assert b'"success":true' in answer


def test_other_connections_are_served_while_one_body_stalls(server: LiveServer) -> None:
    with _connect(server) as stalled:
        stalled.sendall(_head("/armor_interface_srv", len(DIRECTIVE)) + DIRECTIVE[:20])
        for _ in range(3):
            answer = server.client.post(
                "/armor_interface_srv",
                content=DIRECTIVE,
                headers={"Content-Type": "application/json"},
            )
            assert answer.status_code == 200
        assert _answer(stalled).startswith(b"HTTP/1.1 408")


@pytest.mark.parametrize("given", [0, -1.0, float("nan")])
def test_a_timeout_that_is_not_positive_is_refused(given: float) -> None:
    with pytest.raises(ValueError, match="body_timeout_s: got"):
        with_header_timeout(10, body_timeout_s=given)
