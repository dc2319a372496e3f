"""The one request path of the two ARMOR services over HTTP: errors in FastAPI's own shapes, the
token, bodies in chunks, the body size limit, the app's exception handlers, the OpenAPI
description; and a directive runs on the event loop only if nothing can make it wait."""

import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from starlette._utils import get_route_path

from api.armor import ArmorEngine
from api.config import Settings
from api.main import create_app
from api.protocol import ArmorDirectiveListRes, ArmorDirectiveReq, ArmorRequest, ArmorResponse
from api.routes.armor import _route_path
from kg import Store
from kg.errors import StoreError
from tests.conftest import free_port, serve

from .conftest import Armor, directive, start_live_server

SINGLE = "/armor_interface_srv"
LIST = "/armor_interface_serialized_srv"
JSON = {"content-type": "application/json"}


def _directive(ref: str, command: str, first: str, second: str, *args: str) -> dict[str, object]:
    return directive(command, first, second, list(args), ref=ref)


def test_json_subtypes_answer_as_application_json(armor: Armor, ref: str) -> None:
    """``application/x+json`` is JSON too, as FastAPI has it: the same answers."""
    armor.load_empty(ref)
    assert armor.call("ADD", "IND", "CLASS", ["k1", "Kitchen"], ref=ref)["success"]
    single = {"armor_request": _directive(ref, "QUERY", "IND", "", "k1")}
    batch = {
        "armor_requests": [
            _directive(ref, "ADD", "IND", "CLASS", "k2", "Kitchen"),
            _directive(ref, "QUERY", "IND", "CLASS", "Kitchen"),
            _directive(ref, "QUERY", "IND", "", "nobody"),
        ]
    }
    for path, body in (
        ("/armor_interface_srv", single),
        ("/armor_interface_serialized_srv", batch),
    ):
        for values in ("armor", "short"):
            answers = [
                armor.http.post(
                    path, json=body, params={"values": values}, headers={"content-type": kind}
                )
                for kind in ("application/json", "application/x+json")
            ]
            assert [a.status_code for a in answers] == [200, 200]
            assert [a.headers["content-type"] for a in answers] == ["application/json"] * 2
            first, second = (a.json() for a in answers)
            if path.endswith("serialized_srv"):  # k2 exists the second time: same answers
                assert first == second
            else:
                assert answers[0].content == answers[1].content


def test_errors_are_fastapis_own(armor: Armor, ref: str) -> None:
    armor.load_empty(ref)
    body = {"armor_request": _directive(ref, "QUERY", "IND", "", "k1")}
    bad_values = armor.http.post("/armor_interface_srv", json=body, params={"values": "fancy"})
    assert bad_values.status_code == 422
    assert bad_values.json()["detail"][0]["loc"] == ["query", "values"]
    wrong_type = {"armor_request": {**body["armor_request"], "args": "k1"}}
    answer = armor.http.post("/armor_interface_srv", json=wrong_type)
    assert answer.status_code == 422
    assert answer.json()["detail"][0]["loc"] == ["body", "armor_request", "args"]
    empty = armor.http.post("/armor_interface_srv", headers={"content-type": "application/json"})
    assert empty.status_code == 422
    assert empty.json()["detail"][0]["loc"] == ["body"]


_QUERY = _directive("r", "QUERY", "IND", "", "k1")
# (case, request, status, the first error's type and loc, or the detail)
MALFORMED: list[tuple[str, dict[str, Any], int, Any]] = [
    (
        "invalid JSON",
        {"content": b'{"armor_request": {', "headers": JSON},
        422,
        ("json_invalid", ["body", 19]),
    ),
    ("empty body", {"headers": JSON}, 422, ("missing", ["body"])),
    ("JSON null", {"content": b"null", "headers": JSON}, 422, ("model_attributes_type", ["body"])),
    ("a list", {"json": [1, 2]}, 422, ("model_attributes_type", ["body"])),
    (
        "wrong type",
        {"json": {"armor_request": {**_QUERY, "args": "k1"}}},
        422,
        ("list_type", ["body", "armor_request", "args"]),
    ),
    (
        "a number for a string",
        {"json": {"armor_request": {"command": 7}}},
        422,
        ("string_type", ["body", "armor_request", "command"]),
    ),
    (
        "an unknown field",
        {"json": {"armor_request": {"command": "QUERY", "colour": "red"}}},
        422,
        ("extra_forbidden", ["body", "armor_request", "colour"]),
    ),
    (
        "bad values",
        {"json": {"armor_request": _QUERY}, "params": {"values": "fancy"}},
        422,
        ("literal_error", ["query", "values"]),
    ),
    (
        "blank values",
        {"json": {"armor_request": _QUERY}, "params": {"values": ""}},
        422,
        ("literal_error", ["query", "values"]),
    ),
    (
        "text/plain",
        {"content": b'{"armor_request": {}}', "headers": {"content-type": "text/plain"}},
        422,
        ("model_attributes_type", ["body"]),
    ),
    (
        "no content type",
        {"content": b'{"armor_request": {}}'},
        422,
        ("model_attributes_type", ["body"]),
    ),
    (
        "a non-finite number",
        {"content": b'{"armor_request": {"command": NaN}}', "headers": JSON},
        422,
        ("finite_number", ["body", "armor_request", "command"]),
    ),
    (
        "latin-1 bytes",
        {"content": b'{"armor_request": {"command": "\xe9"}}', "headers": JSON},
        400,
        "There was an error parsing the body",
    ),
    (
        "nested too deep",
        {"content": b"[" * 5000 + b"]" * 5000, "headers": JSON},
        400,
        "There was an error parsing the body",
    ),
]


@pytest.mark.parametrize(
    ("case", "request_", "status", "expected"), MALFORMED, ids=[case for case, *_ in MALFORMED]
)
def test_malformed_requests_get_fastapis_own_errors(
    armor: Armor, case: str, request_: dict[str, Any], status: int, expected: Any
) -> None:
    answer = armor.http.post(SINGLE, **request_)
    assert answer.status_code == status, answer.text
    detail = answer.json()["detail"]
    if isinstance(expected, str):
        assert detail == expected
    else:
        assert (detail[0]["type"], detail[0]["loc"]) == expected


def test_a_bad_values_and_a_bad_body_are_reported_together(armor: Armor) -> None:
    answer = armor.http.post(
        LIST, json={"armor_requests": [{"command": 7}]}, params={"values": "fancy"}
    )
    assert answer.status_code == 422
    assert [e["loc"] for e in answer.json()["detail"]] == [
        ["query", "values"],
        ["body", "armor_requests", 0, "command"],
    ]


def test_values_is_read_from_any_query_string(armor: Armor, ref: str) -> None:
    """The last ``values`` counts and other parameters are ignored, as FastAPI reads a query."""
    armor.load_empty(ref)
    assert armor.call("ADD", "IND", "CLASS", ["k1", "Kitchen"], ref=ref)["success"]
    body = {"armor_request": _directive(ref, "QUERY", "IND", "CLASS", "Kitchen")}
    for params in ({"values": ["plain", "short"]}, {"other": "1", "values": "short"}):
        answer = armor.http.post(SINGLE, json=body, params=params)
        assert answer.status_code == 200, answer.text
        assert answer.json()["armor_response"]["queried_objects"] == ["k1"]


def test_a_body_sent_in_chunks_is_read_whole(armor: Armor, ref: str) -> None:
    armor.load_empty(ref)
    assert armor.call("ADD", "IND", "CLASS", ["k1", "Kitchen"], ref=ref)["success"]
    body = (
        b'{"armor_request": '
        + httpx.Request("POST", "/", json=_directive(ref, "QUERY", "IND", "", "k1")).content
        + b"}"
    )

    def chunks() -> Iterator[bytes]:
        for start in range(0, len(body), 7):
            yield body[start : start + 7]

    chunked = armor.http.post(SINGLE, content=chunks(), headers=JSON)
    whole = armor.http.post(SINGLE, content=body, headers=JSON)
    assert chunked.status_code == 200 and chunked.content == whole.content
    assert chunked.json()["armor_response"]["queried_objects"] == [f"<http://ex.org/{ref}#Kitchen>"]


@pytest.mark.parametrize(("method", "path"), [("GET", SINGLE), ("PUT", LIST), ("DELETE", SINGLE)])
def test_other_methods_get_405(armor: Armor, method: str, path: str) -> None:
    answer = armor.http.request(method, path)
    assert answer.status_code == 405
    assert answer.headers["allow"] == "POST"
    assert answer.json() == {"detail": "Method Not Allowed"}


def test_a_trailing_slash_redirects(armor: Armor) -> None:
    answer = armor.http.post(SINGLE + "/", json={}, follow_redirects=False)
    assert answer.status_code == 307
    assert answer.headers["location"].endswith(SINGLE)


@pytest.mark.parametrize(
    ("error", "status"), [(StoreError("the disk is full"), 503), (RuntimeError("boom"), 500)]
)
def test_an_engine_exception_is_answered_by_the_apps_handlers(
    armor: Armor, monkeypatch: pytest.MonkeyPatch, error: Exception, status: int
) -> None:
    def fail(self: ArmorEngine, *args: Any, **kwargs: Any) -> None:
        raise error

    monkeypatch.setattr(ArmorEngine, "execute_now", fail)
    body = {"armor_request": _QUERY}
    # the server closes the connection after an unhandled exception: one connection a request
    answer = armor.http.post(SINGLE, json=body, headers={"connection": "close"})
    assert answer.status_code == status
    if status == 503:
        assert answer.json() == {"detail": "the disk is full", "error": "StoreError"}


@pytest.fixture(scope="module")
def with_token(tmp_path_factory: pytest.TempPathFactory) -> Iterator[httpx.Client]:
    with (
        start_live_server(tmp_path_factory.mktemp("token"), token="s3cret") as running,
        httpx.Client(base_url=running.url, timeout=60) as http,
    ):
        yield http


@pytest.mark.parametrize(
    "headers", [{}, {"authorization": "Bearer wrong"}, {"authorization": "Basic s3cret"}]
)
@pytest.mark.parametrize("path", [SINGLE, LIST])
def test_a_missing_or_wrong_token_gets_401(
    with_token: httpx.Client, path: str, headers: dict[str, str]
) -> None:
    answer = with_token.post(path, json={}, headers=headers)
    assert answer.status_code == 401
    assert answer.headers["www-authenticate"] == "Bearer"
    assert "Authorization: Bearer <token>" in answer.json()["detail"]


def test_the_token_is_checked_before_the_body_is_read(with_token: httpx.Client) -> None:
    answer = with_token.post(SINGLE, content=b'{"armor_request": {', headers=JSON)
    assert answer.status_code == 401


def test_the_right_token_lets_directives_through(with_token: httpx.Client) -> None:
    request = {"armor_request": _directive("any", "GET", "ALL", "REFS")}
    answer = with_token.post(SINGLE, json=request, headers={"authorization": "bearer  s3cret"})
    assert answer.status_code == 200
    assert answer.json()["armor_response"]["success"]


def test_a_body_over_the_apps_limit_gets_413(tmp_path: Path) -> None:
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=tmp_path)
    app = create_app(settings)
    app.max_body_size = 2000
    with serve(app, settings) as running, httpx.Client(base_url=running.url, timeout=60) as http:
        small = {"armor_request": _directive("any", "GET", "ALL", "REFS")}
        assert http.post(SINGLE, json=small).status_code == 200
        large = {"armor_request": _directive("r", "QUERY", "IND", "", "x" * 3000)}
        answer = http.post(SINGLE, json=large)
        assert answer.status_code == 413, answer.text
        chunked = http.post(SINGLE, content=iter([b"{" + b" " * 1500] * 2), headers=JSON)
        assert chunked.status_code == 413, chunked.text


def test_the_openapi_description_has_both_services_with_their_models(armor: Armor) -> None:
    spec = armor.http.get("/openapi.json").json()
    schemas = spec["components"]["schemas"]
    for path, request, response in (
        (SINGLE, ArmorRequest, ArmorResponse),
        (LIST, "ArmorDirectiveListReq", ArmorDirectiveListRes),
    ):
        operation = spec["paths"][path]["post"]
        request_name = request if isinstance(request, str) else request.__name__
        body = operation["requestBody"]["content"]["application/json"]["schema"]
        assert body == {"$ref": f"#/components/schemas/{request_name}"}
        answer = operation["responses"]["200"]["content"]["application/json"]["schema"]
        assert answer == {"$ref": f"#/components/schemas/{response.__name__}"}
        assert {"200", "401", "422"} <= set(operation["responses"])
        values = next(p for p in operation["parameters"] if p["name"] == "values")
        assert values["in"] == "query" and values["schema"]["enum"] == ["armor", "plain", "short"]
    single = ArmorRequest.model_json_schema(ref_template="#/components/schemas/{model}")
    assert schemas["ArmorRequest"] == {k: v for k, v in single.items() if k != "$defs"}
    assert schemas["ArmorDirectiveReq"] == single["$defs"]["ArmorDirectiveReq"]
    assert "QueryItem" in schemas and "HTTPValidationError" in schemas


def test_a_write_runs_on_the_event_loop_only_if_nothing_can_make_it_wait(tmp_path: Path) -> None:
    engine = ArmorEngine(Store(tmp_path / "store"))

    def load(ref: str, buffered_reasoner: bool) -> None:
        args = ["", "http://ex.org/" + ref, "false", "PELLET", str(buffered_reasoner)]
        directive = _directive(ref, "LOAD", "FILE", "", *args)
        assert engine.execute(ArmorDirectiveReq.model_validate(directive)).success

    load("buffered", True)
    load("unbuffered", False)

    def add(ref: str, name: str) -> ArmorDirectiveReq:
        return ArmorDirectiveReq.model_validate(_directive(ref, "ADD", "IND", "CLASS", name, "C"))

    def query(ref: str, name: str) -> ArmorDirectiveReq:
        return ArmorDirectiveReq.model_validate(_directive(ref, "QUERY", "IND", "", name))

    done = engine.execute_now(add("buffered", "a"))
    assert done is not None and done.success
    assert engine.execute_now(add("unbuffered", "a")) is None  # its commit would reason
    assert (
        engine.execute_now(
            ArmorDirectiveReq.model_validate(_directive("buffered", "REASON", "", ""))
        )
        is None
    )
    # another list holds the reference's lock: the write would wait, the query does not
    held, release = threading.Event(), threading.Event()

    def hold() -> None:
        with engine.registry.locked(["buffered"]):
            held.set()
            release.wait(timeout=30)

    holder = threading.Thread(target=hold)
    holder.start()
    held.wait(timeout=30)
    try:
        assert engine.execute_now(add("buffered", "b")) is None
        answer = engine.execute_now(query("buffered", "a"))
        assert answer is not None and answer.success
    finally:
        release.set()
        holder.join(timeout=30)
    assert engine.execute_now(query("buffered", "b")) is not None  # b was never added
    assert not engine.execute(query("buffered", "b")).success
    done = engine.execute_now(add("buffered", "b"))
    assert done is not None and done.success


@pytest.mark.parametrize(
    ("path", "root_path"),
    [
        (SINGLE, ""),
        ("/engram" + SINGLE, "/engram"),
        ("/engram", "/engram"),
        ("/engramx" + SINGLE, "/engram"),
        (SINGLE, "/engram"),
        ("/engram/", "/engram"),
    ],
)
def test_a_services_path_is_read_as_starlettes_router_reads_it(path: str, root_path: str) -> None:
    """Under a ``root_path`` (a proxy's prefix) the services answer where a route would."""
    scope = {"type": "http", "path": path, "root_path": root_path}
    assert _route_path(scope) == get_route_path(scope)
