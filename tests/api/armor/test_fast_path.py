"""The ARMOR short path (:mod:`api.fast_armor`) answers byte for byte as FastAPI's usual route,
takes only the requests it should, and leaves every error to the usual route.

Each request is sent twice to the same live server: once with the short path on, once with it
off (every request then takes FastAPI's usual route); the status, the headers (but ``date``) and
the body bytes must be the same. A counter in front of FastAPI's stack tells which path answered.
"""

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi import FastAPI
from starlette.types import ASGIApp, Receive, Scope, Send

from api.armor import ArmorEngine
from api.config import Settings
from api.deps import require_token
from api.fast_armor import ArmorFastPath
from api.main import create_app
from kg.errors import StoreError
from tests.conftest import free_port, serve

SINGLE = "/armor_interface_srv"
LIST = "/armor_interface_serialized_srv"
REF = "fast"


class _Counting:
    """ASGI app in front of FastAPI's usual stack: counts the requests that reach it."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app
        self.count = 0

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            self.count += 1
        await self.app(scope, receive, send)


@dataclass
class Served:
    app: FastAPI
    http: httpx.Client
    fast: ArmorFastPath
    usual: _Counting

    def both(self, method: str, path: str, **kwargs: Any) -> tuple[httpx.Response, httpx.Response]:
        """The answers with the short path on, then off; asserts which path answered."""
        self.fast.enabled = True
        before = self.usual.count
        fast = self.http.request(method, path, **kwargs)
        took_usual = self.usual.count - before
        self.fast.enabled = False
        usual = self.http.request(method, path, **kwargs)
        self.fast.enabled = True
        assert self.usual.count - before == took_usual + 1
        self.took_usual = took_usual
        return fast, usual

    took_usual: int = 0


def _same(fast: httpx.Response, usual: httpx.Response) -> None:
    assert fast.status_code == usual.status_code, (fast.text, usual.text)
    assert fast.content == usual.content
    headers = [(k, v) for k, v in fast.headers.multi_items() if k != "date"]
    assert headers == [(k, v) for k, v in usual.headers.multi_items() if k != "date"]


def _serve(
    data_dir: Path, prepare: Callable[[FastAPI], None] = lambda app: None, **overrides: Any
) -> Iterator[Served]:
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data_dir, **overrides)
    app = create_app(settings)
    prepare(app)
    server, thread, url = serve(app, settings)
    with httpx.Client(base_url=url, timeout=60) as http:
        http.get("/health").raise_for_status()  # builds the middleware stack
        layer: Any = app.middleware_stack
        while not isinstance(layer, ArmorFastPath):
            layer = layer.app
        layer.app = usual = _Counting(layer.app)
        yield Served(app, http, layer, usual)
    server.should_exit = True
    thread.join(timeout=30)


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    yield from _serve(tmp_path_factory.mktemp("fast"))


def _directive(command: str, first: str = "", second: str = "", *args: str) -> dict[str, Any]:
    return {
        "client_name": "tester",
        "reference_name": REF,
        "command": command,
        "primary_command_spec": first,
        "secondary_command_spec": second,
        "args": list(args),
    }


@pytest.fixture(scope="module")
def loaded(served: Served) -> Served:
    load = _directive("LOAD", "FILE", "", "", "http://ex.org/fast", "false", "PELLET", "true")
    answer = served.http.post(SINGLE, json={"armor_request": load})
    assert answer.json()["armor_response"]["success"], answer.text
    return served


SINGLES = [
    _directive("ADD", "IND", "CLASS", "k1", "Kitchen"),
    _directive("add", "ind", "class", "k2", "Kitchen"),
    _directive("ADD", "DATAPROP", "IND", "size", "k1", "INTEGER", "12"),
    _directive("QUERY", "IND", "", "k1"),
    _directive("QUERY", "IND", "CLASS", "Kitchen"),
    _directive("QUERY", "DATAPROP", "IND", "size", "k1"),
    _directive("QUERY", "IND", "", "nobody"),  # success false, exit code 0
    _directive("ADD", "DATAPROP", "IND", "size", "k1", "INTEGER", "twelve"),  # a protocol error
    _directive("FLY", "IND", ""),  # unknown command
    {**_directive("QUERY", "IND", "", "k1"), "reference_name": ""},
    {**_directive("QUERY", "IND", "", "k1"), "reference_name": "no_such_reference"},
    {"command": "QUERY"},  # ROS defaults for the missing fields
    _directive("QUERY", "SPARQL", "", "SELECT ?s WHERE { ?s a ?c } ORDER BY ?s"),
]


@pytest.mark.parametrize("values", [None, "armor", "plain", "short"])
def test_single_directives_answer_byte_identically(loaded: Served, values: str | None) -> None:
    params = {"values": values} if values else None
    for directive in SINGLES:
        fast, usual = loaded.both("POST", SINGLE, json={"armor_request": directive}, params=params)
        _same(fast, usual)
        assert fast.status_code == 200
        assert loaded.took_usual == 0, directive


def test_lists_answer_byte_identically(loaded: Served) -> None:
    reads = [_directive("QUERY", "IND", "CLASS", "Kitchen"), _directive("QUERY", "IND", "", "k1")]
    writes = [_directive("ADD", "IND", "CLASS", "k3", "Kitchen"), *reads]
    failing = [_directive("ADD", "IND", "CLASS", "k4", "Kitchen"), _directive("FLY", "IND", "")]
    for directives in (reads, writes, failing, []):
        fast, usual = loaded.both("POST", LIST, json={"armor_requests": directives})
        _same(fast, usual)
        assert fast.status_code == 200 and loaded.took_usual == 0
    # the failing list wrote nothing, either time
    answer = loaded.http.post(SINGLE, json={"armor_request": _directive("QUERY", "IND", "", "k4")})
    assert not answer.json()["armor_response"]["success"]


def test_a_body_sent_in_chunks_takes_the_short_path(loaded: Served) -> None:
    body = (
        b'{"armor_request": '
        + httpx.Request("POST", "/", json=_directive("QUERY", "IND", "", "k1")).content
        + b"}"
    )

    def chunks() -> Iterator[bytes]:
        for start in range(0, len(body), 7):
            yield body[start : start + 7]

    headers = {"content-type": "application/json"}
    loaded.fast.enabled = True
    before = loaded.usual.count
    chunked = loaded.http.post(SINGLE, content=chunks(), headers=headers)
    assert loaded.usual.count == before
    whole = loaded.http.post(SINGLE, content=body, headers=headers)
    assert chunked.status_code == 200 and chunked.content == whole.content
    assert chunked.json()["armor_response"]["queried_objects"] == ["<http://ex.org/fast#Kitchen>"]


MALFORMED: list[tuple[str, dict[str, Any]]] = [
    (
        "invalid JSON",
        {"content": b'{"armor_request": {', "headers": {"content-type": "application/json"}},
    ),
    ("empty body", {"headers": {"content-type": "application/json"}}),
    ("JSON null", {"content": b"null", "headers": {"content-type": "application/json"}}),
    ("a list", {"json": [1, 2]}),
    ("wrong type", {"json": {"armor_request": {**_directive("QUERY", "IND", ""), "args": "k1"}}}),
    ("a number for a string", {"json": {"armor_request": {"command": 7}}}),
    ("an unknown field", {"json": {"armor_request": {"command": "QUERY", "colour": "red"}}}),
    (
        "bad values",
        {
            "json": {"armor_request": _directive("QUERY", "IND", "", "k1")},
            "params": {"values": "fancy"},
        },
    ),
    (
        "text/plain",
        {"content": b'{"armor_request": {}}', "headers": {"content-type": "text/plain"}},
    ),
    ("no content type", {"content": b'{"armor_request": {}}'}),
    (
        "latin-1 bytes",
        {
            "content": b'{"armor_request": {"command": "\xe9"}}',
            "headers": {"content-type": "application/json"},
        },
    ),
]


@pytest.mark.parametrize("path", [SINGLE, LIST])
@pytest.mark.parametrize(("case", "request_"), MALFORMED, ids=[case for case, _ in MALFORMED])
def test_malformed_bodies_get_fastapis_own_errors(
    loaded: Served, path: str, case: str, request_: dict[str, Any]
) -> None:
    fast, usual = loaded.both("POST", path, **request_)
    _same(fast, usual)
    assert fast.status_code in (400, 415, 422), (case, fast.status_code, fast.text)
    assert loaded.took_usual == 1, case
    assert fast.json()["detail"]


def test_a_missing_or_wrong_value_names_the_field(loaded: Served) -> None:
    wrong = {"armor_request": {**_directive("QUERY", "IND", ""), "args": "k1"}}
    answer = loaded.http.post(SINGLE, json=wrong)
    assert answer.status_code == 422
    assert answer.json()["detail"][0]["loc"] == ["body", "armor_request", "args"]
    bad = loaded.http.post(SINGLE, json={"armor_request": {}}, params={"values": "fancy"})
    assert bad.status_code == 422
    assert bad.json()["detail"][0]["loc"] == ["query", "values"]


@pytest.mark.parametrize(
    ("method", "path", "params"),
    [
        ("GET", SINGLE, None),
        ("PUT", LIST, None),
        ("POST", SINGLE + "/", None),
        ("POST", SINGLE, {"values": "plain", "extra": "1"}),
        ("POST", SINGLE, {"values": ["plain", "short"]}),
    ],
)
def test_other_requests_take_the_usual_route(
    loaded: Served, method: str, path: str, params: dict[str, Any] | None
) -> None:
    request = {"armor_request": _directive("QUERY", "IND", "", "k1")}
    fast, usual = loaded.both(method, path, json=request, params=params, follow_redirects=False)
    _same(fast, usual)
    assert loaded.took_usual == 1


@pytest.mark.parametrize(
    ("error", "status"), [(StoreError("the disk is full"), 503), (RuntimeError("boom"), 500)]
)
def test_an_engine_exception_is_answered_by_the_apps_handlers(
    loaded: Served, monkeypatch: pytest.MonkeyPatch, error: Exception, status: int
) -> None:
    def fail(self: ArmorEngine, *args: Any, **kwargs: Any) -> None:
        raise error

    monkeypatch.setattr(ArmorEngine, "execute_now", fail)
    request = {"armor_request": _directive("QUERY", "IND", "", "k1")}
    # the server closes the connection after an unhandled exception: one connection a request
    fast, usual = loaded.both("POST", SINGLE, json=request, headers={"connection": "close"})
    _same(fast, usual)
    assert fast.status_code == status and loaded.took_usual == 0


@pytest.fixture
def with_token(tmp_path: Path) -> Iterator[Served]:
    yield from _serve(tmp_path, token="s3cret")


def test_the_token_is_checked_and_its_errors_are_fastapis(with_token: Served) -> None:
    request = {"armor_request": _directive("GET", "ALL", "REFS")}
    for headers in ({}, {"authorization": "Bearer wrong"}, {"authorization": "Basic s3cret"}):
        fast, usual = with_token.both("POST", SINGLE, json=request, headers=headers)
        _same(fast, usual)
        assert fast.status_code == 401 and with_token.took_usual == 1
    fast, usual = with_token.both(
        "POST", SINGLE, json=request, headers={"authorization": "bearer  s3cret"}
    )
    _same(fast, usual)
    assert fast.status_code == 200 and with_token.took_usual == 0


def test_a_body_size_limit_turns_the_short_path_off(tmp_path: Path) -> None:
    app = create_app(Settings(data_dir=tmp_path))
    assert ArmorFastPath(app.router, fastapi=app).enabled
    app.max_body_size = 1000
    assert not ArmorFastPath(app.router, fastapi=app).enabled


@pytest.fixture
def limited(tmp_path: Path) -> Iterator[Served]:
    def limit(app: FastAPI) -> None:
        app.max_body_size = 2000

    yield from _serve(tmp_path, prepare=limit)


def test_a_body_over_the_limit_gets_413(limited: Served) -> None:
    assert not limited.fast.enabled
    small = {"armor_request": _directive("GET", "ALL", "REFS")}
    assert limited.http.post(SINGLE, json=small).status_code == 200
    large = {"armor_request": _directive("QUERY", "IND", "", "x" * 3000)}
    answer = limited.http.post(SINGLE, json=large)
    assert answer.status_code == 413, answer.text


def test_dependency_overrides_turn_the_short_path_off(loaded: Served) -> None:
    async def no_token() -> None:
        return None

    request = {"armor_request": _directive("QUERY", "IND", "", "k1")}
    loaded.app.dependency_overrides[require_token] = no_token
    try:
        before = loaded.usual.count
        answer = loaded.http.post(SINGLE, json=request)
        assert answer.status_code == 200 and loaded.usual.count == before + 1
    finally:
        loaded.app.dependency_overrides.clear()
