"""The HTTP guard (api/security.py): trusted Host names, no cross-site writes, security
headers, body limits and stalled bodies, and no server path in an answer."""

import base64
import hashlib
import re
import socket
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import pytest

from api.config import Settings
from api.main import create_app
from api.security import allowed_host_names, content_security_policy
from tests.conftest import LiveServer, free_port, serve

EVIL = "http://attacker.example"
TRIG = b"<urn:x> <urn:y> <urn:z> ."


@pytest.fixture
def server(start_server: Callable[..., LiveServer]) -> LiveServer:
    """A server with default settings, a 64 KiB body limit and a 1 s body timeout."""
    return start_server(max_body_bytes=64 * 1024, max_upload_bytes=128 * 1024, body_timeout_s=1)


def _episodes(server: LiveServer) -> int:
    return int(server.client.get("/episodes/count", params={"activity": "wave"}).json()["count"])


def test_a_foreign_host_name_is_refused_before_any_route(server: LiveServer) -> None:
    """DNS rebinding: the attacker's page reaches 127.0.0.1 under its own name."""
    answer = server.client.post(
        "/episodes", json={"activity": "wave"}, headers={"Host": "attacker.example"}
    )
    assert answer.status_code == 400, answer.text
    assert answer.json()["error"] == "UntrustedHostError"
    assert "attacker.example" in answer.json()["detail"]
    assert (
        server.client.get("/health", headers={"Host": "attacker.example:8000"}).status_code == 400
    )
    assert _episodes(server) == 0


@pytest.mark.parametrize("host", ["127.0.0.1", "localhost", "LOCALHOST:1234", "[::1]:80"])
def test_the_loopback_names_are_served(server: LiveServer, host: str) -> None:
    assert server.client.get("/health", headers={"Host": host}).status_code == 200


def test_configured_host_names_replace_the_defaults(
    start_server: Callable[..., LiveServer],
) -> None:
    server = start_server(allowed_hosts="robot.lan")
    assert server.client.get("/health", headers={"Host": "robot.lan:8000"}).status_code == 200
    assert server.client.get("/health").status_code == 400  # 127.0.0.1 no longer listed
    assert allowed_host_names(Settings(allowed_hosts="*")) is None


def test_the_default_names_include_this_machine() -> None:
    names = allowed_host_names(Settings(host="0.0.0.0"))
    assert names is not None
    assert {"localhost", "127.0.0.1", "::1", socket.gethostname().lower()} <= names
    assert "0.0.0.0" not in names


# Writes a page on another site could send without a preflight (the issue's list).
CROSS_SITE_WRITES = [
    ("/episodes/rdf", {"content": TRIG, "headers": {"Content-Type": "text/plain"}}),
    ("/episodes/import/upload?activity=wave", {"content": b"#ROSBAG V2.0\n"}),
    ("/episodes/e1/end", {}),
    ("/episodes/e1/streams/close", {}),
    ("/episodes/e1/runs/r1/end", {}),
    ("/backup", {}),
    ("/episodes", {"data": {"activity": "wave"}}),  # form-encoded
]


@pytest.mark.parametrize(("path", "options"), CROSS_SITE_WRITES, ids=lambda v: str(v)[:30])
def test_a_write_from_another_origin_is_refused(
    server: LiveServer, path: str, options: dict[str, object]
) -> None:
    headers = {**options.pop("headers", {}), "Origin": EVIL}  # type: ignore[dict-item]
    answer = server.client.post(path, headers=headers, **options)  # type: ignore[arg-type]
    assert answer.status_code == 403, answer.text
    assert answer.json()["error"] == "CrossSiteRequestError"
    assert EVIL in answer.json()["detail"]
    assert not (server.settings.backup_dir).exists()


def test_a_write_the_browser_marks_cross_site_is_refused_without_origin(
    server: LiveServer,
) -> None:
    for site in ("cross-site", "same-site"):
        answer = server.client.post("/episodes/rdf", content=TRIG, headers={"Sec-Fetch-Site": site})
        assert answer.status_code == 403, answer.text
    assert not (server.settings.backup_dir).exists()


def test_a_null_origin_may_not_write(server: LiveServer) -> None:
    """Sandboxed frames and file:// pages send ``Origin: null``."""
    answer = server.client.post("/backup", headers={"Origin": "null"})
    assert answer.status_code == 403


def test_the_servers_own_pages_and_plain_clients_may_write(server: LiveServer) -> None:
    own = server.url  # http://127.0.0.1:<port>, what the browser sends from /web/
    answer = server.client.post(
        "/episodes",
        json={"activity": "wave", "id": "w1"},
        headers={"Origin": own, "Sec-Fetch-Site": "same-origin"},
    )
    assert answer.status_code == 201, answer.text
    assert server.client.post("/episodes", json={"activity": "wave"}).status_code == 201
    # reads are never refused for their origin
    assert server.client.get("/health", headers={"Origin": EVIL}).status_code == 200
    assert _episodes(server) == 2


def test_an_allowed_origin_may_write_and_the_token_still_applies(
    start_server: Callable[..., LiveServer],
) -> None:
    server = start_server(token="s3cret", allowed_origins="https://dashboard.lab")
    headers = {"Origin": "https://dashboard.lab"}
    assert server.client.post("/backup", headers=headers).status_code == 401
    headers["Authorization"] = "Bearer s3cret"
    assert server.client.post("/backup", headers=headers).status_code == 201
    refused = server.client.post("/backup", headers={**headers, "Origin": EVIL})
    assert refused.status_code == 403  # a token does not let another site write


def test_pages_and_answers_carry_the_security_headers(server: LiveServer) -> None:
    for path in ("/web/", "/health", "/web/app.js"):
        headers = server.client.get(path).headers
        assert headers["x-frame-options"] == "DENY"
        assert headers["x-content-type-options"] == "nosniff"
        policy = headers["content-security-policy"]
        assert "frame-ancestors 'none'" in policy and "object-src 'none'" in policy
        assert "'unsafe-inline'" not in policy.split("script-src", 1)[1].split(";")[0]
    # refusals carry them too
    assert "x-frame-options" in server.client.get("/health", headers={"Host": "x.example"}).headers


def test_the_policy_allows_the_pages_import_map_by_its_hash() -> None:
    page = (Path(__file__).parents[2] / "api" / "web" / "index.html").read_text()
    (importmap,) = re.findall(r'<script type="importmap">(.*?)</script>', page, re.DOTALL)
    digest = base64.b64encode(hashlib.sha256(importmap.encode()).digest()).decode()
    script_src = content_security_policy().split("script-src", 1)[1].split(";")[0]
    assert f"'sha256-{digest}'" in script_src.split()


def test_a_body_declared_longer_than_the_limit_answers_413(server: LiveServer) -> None:
    answer = server.client.post(
        "/episodes/rdf", content=b" " * (64 * 1024 + 1), headers={"Content-Type": "text/trig"}
    )
    assert answer.status_code == 413, answer.text
    assert "max_body_bytes" in answer.json()["detail"]


def _chunks(total: int, size: int = 16 * 1024) -> Iterator[bytes]:
    for _ in range(total // size):
        yield b" " * size


def test_a_streamed_body_is_cut_off_at_the_limit(server: LiveServer) -> None:
    """No Content-Length (chunked): the guard counts the bytes as they come."""
    answer = server.client.post("/episodes/rdf", content=_chunks(1024 * 1024))
    assert answer.status_code == 413, answer.text
    upload = server.client.post(
        "/episodes/import/upload", params={"activity": "wave"}, content=_chunks(1024 * 1024)
    )
    assert upload.status_code == 413, upload.text
    assert "max_upload_bytes" in upload.json()["detail"]
    assert not any((server.settings.data_dir / "uploads").iterdir())


def test_an_upload_may_be_longer_than_other_bodies(server: LiveServer) -> None:
    """Uploads have their own limit (128 KiB here, above the 64 KiB of other bodies)."""
    answer = server.client.post(
        "/episodes/import/upload", params={"activity": "wave"}, content=b"x" * 100_000
    )
    assert answer.status_code == 422, answer.text  # read whole, then found not to be a bag
    assert answer.json()["field"] == "body"


def test_a_stalled_body_answers_408(server: LiveServer) -> None:
    host, port = server.url.removeprefix("http://").split(":")
    with socket.create_connection((host, int(port)), timeout=10) as connection:
        connection.sendall(
            b"POST /episodes/rdf HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: text/trig\r\n"
            b"Content-Length: 1000\r\n\r\n<urn:x>"
        )
        started = time.monotonic()
        answer = connection.recv(4096)
        assert time.monotonic() - started < 8
    assert answer.startswith(b"HTTP/1.1 408"), answer
    assert b"nothing received" in answer


def test_answers_name_files_inside_the_data_directory_not_its_path(server: LiveServer) -> None:
    data = str(server.settings.data_dir)
    missing = server.client.post(
        "/episodes/import", json={"path": "bags/none.bag", "activity": "wave"}
    )
    assert missing.status_code in (404, 422) and data not in missing.text
    outside = server.client.post("/episodes/import", json={"path": "/etc", "activity": "wave"})
    assert outside.status_code == 422 and data not in outside.text
    backup = server.client.post("/backup")
    assert backup.status_code == 201 and data not in backup.text


@pytest.fixture
def header_timed_server(tmp_path: Path) -> Iterator[str]:
    """A server with ``engram serve``'s protocol and a 0.5 s header timeout; its host:port."""
    settings = Settings(
        host="127.0.0.1", port=free_port(), data_dir=tmp_path / "data", header_timeout_s=0.5
    )
    with serve(create_app(settings), settings):
        yield f"{settings.host}:{settings.port}"


@pytest.mark.parametrize(
    "sent", [b"", b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\n"], ids=["nothing", "half"]
)
def test_half_sent_headers_are_timed_out(header_timed_server: str, sent: bytes) -> None:
    host, port = header_timed_server.split(":")
    with socket.create_connection((host, int(port)), timeout=10) as connection:
        connection.sendall(sent)
        started = time.monotonic()
        answer = connection.recv(4096)
        assert time.monotonic() - started < 5
        assert answer.startswith(b"HTTP/1.1 408"), answer
        assert connection.recv(4096) == b""  # closed


def test_headers_sent_in_time_are_answered(header_timed_server: str) -> None:
    with httpx.Client(base_url=f"http://{header_timed_server}", timeout=10) as http:
        for _ in range(3):  # kept alive between requests
            assert http.get("/health").status_code == 200
            time.sleep(0.3)
