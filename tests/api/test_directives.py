"""The two ARMOR services as functions from a request body to a response body
(:mod:`api.directives`), and the client's local transport, which answers through them."""

import json
from typing import Any

import httpx
import pytest
from fastapi import HTTPException
from fastapi.exceptions import RequestValidationError
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from api.armor import ArmorEngine
from api.client import ArmorClient
from api.client._local import LocalTransport
from api.directives import LIST, SINGLE, answer_blocking, read_request
from api.protocol import ArmorDirectiveListRes, ArmorRequest, ArmorResponse
from kg import Store
from tests.api.armor.conftest import directive


def _directive(command: str, first: str = "", second: str = "", *args: str) -> dict[str, Any]:
    return directive(command, first, second, list(args), ref="kitchen")


def _body(value: Any) -> bytes:
    return json.dumps(value).encode()


@pytest.fixture
def engine() -> ArmorEngine:
    """An engine over an in-memory store with a reference ``kitchen`` holding ``k1: Kitchen``."""
    engine = ArmorEngine(Store())
    load = _directive("LOAD", "FILE", "", "", "http://ex.org/kitchen", "false", "PELLET", "true")
    for request in (load, _directive("ADD", "IND", "CLASS", "k1", "Kitchen")):
        answer = json.loads(answer_blocking(engine, SINGLE, _body({"armor_request": request})))
        assert answer["armor_response"]["success"], answer
    return engine


def test_a_single_directive_answers_an_armor_response(engine: ArmorEngine) -> None:
    query = _body({"armor_request": _directive("QUERY", "IND", "CLASS", "Kitchen")})
    content = answer_blocking(engine, SINGLE, query)
    answer = ArmorResponse.model_validate_json(content).armor_response
    assert answer.success and answer.queried_objects == ["<http://ex.org/kitchen#k1>"]
    short = answer_blocking(engine, SINGLE, query, query="values=short")
    assert ArmorResponse.model_validate_json(short).armor_response.queried_objects == ["k1"]


def test_a_list_answers_one_response_per_directive(engine: ArmorEngine) -> None:
    directives = [
        _directive("ADD", "IND", "CLASS", "k2", "Kitchen"),
        _directive("QUERY", "IND", "CLASS", "Kitchen"),
    ]
    content = answer_blocking(engine, LIST, _body({"armor_requests": directives}), query=b"x=1")
    answer = ArmorDirectiveListRes.model_validate_json(content)
    assert answer.success and len(answer.armor_responses) == 2
    assert sorted(answer.armor_responses[1].queried_objects) == [
        "<http://ex.org/kitchen#k1>",
        "<http://ex.org/kitchen#k2>",
    ]


@pytest.mark.parametrize(
    ("body", "query", "content_type", "locs"),
    [
        (b"", b"", "application/json", [("body",)]),
        (
            b'{"armor_request": {"args": "k"}}',
            b"",
            "application/json",
            [("body", "armor_request", "args")],
        ),
        (b"{}", b"values=fancy", "application/json", [("query", "values")]),
        (b'{"x": 1}', b"values=no", "application/json", [("query", "values"), ("body", "x")]),
        (b"{}", b"", "text/plain", [("body",)]),
        (b"{}", b"", None, [("body",)]),
        (b'{"armor_request": ', b"", "application/json", [("body", 18)]),
    ],
)
def test_a_request_that_does_not_validate_raises_fastapis_error(
    body: bytes, query: bytes, content_type: str | None, locs: list[tuple[Any, ...]]
) -> None:
    with pytest.raises(RequestValidationError) as raised:
        read_request(SINGLE, body, query=query, content_type=content_type)
    assert [tuple(error["loc"]) for error in raised.value.errors()] == locs


@pytest.mark.parametrize("body", [b'{"armor_request": {"command": "\xe9"}}', b"[" * 5000])
def test_a_body_that_cannot_be_decoded_raises_400(body: bytes) -> None:
    with pytest.raises(HTTPException) as raised:
        read_request(SINGLE, body)
    assert raised.value.status_code == 400


@pytest.mark.parametrize(
    "content_type", ["application/json", "Application/JSON; charset=utf-8", "application/ld+json"]
)
def test_json_content_types_are_read_as_json(content_type: str) -> None:
    call = read_request(SINGLE, b'{"armor_request": {"command": "GET"}}', content_type=content_type)
    assert [d.command for d in call.directives] == ["GET"]


_JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.text(max_size=5),
    lambda inner: (
        st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner, max_size=3)
    ),
    max_leaves=8,
)
_FIELDS = st.sampled_from(
    ["client_name", "reference_name", "command", "primary_command_spec", "args", "other"]
)
_DIRECTIVES = st.dictionaries(
    _FIELDS, st.text(max_size=5) | st.lists(st.text(max_size=3)) | _JSON_VALUES
)


@settings(max_examples=60, deadline=None)
@given(
    st.one_of(
        st.fixed_dictionaries({"armor_request": _DIRECTIVES}),
        st.dictionaries(st.sampled_from(["armor_request", "armor_requests"]), _DIRECTIVES),
        _JSON_VALUES,
    )
)
def test_a_body_is_accepted_and_read_as_fastapi_reads_it(value: Any) -> None:
    """Straight from the bytes or not, the answer is FastAPI's: Python's JSON parser, then the
    model validated in Python mode, errors located under ``body``."""
    try:
        expected = ArmorRequest.model_validate(value, from_attributes=True)
    except ValidationError as error:
        with pytest.raises(RequestValidationError) as raised:
            read_request(SINGLE, _body(value))
        locs = [("body", *e["loc"]) for e in error.errors(include_url=False)]
        assert [tuple(e["loc"]) for e in raised.value.errors()] == locs
    else:
        assert read_request(SINGLE, _body(value)).directives == [expected.armor_request]


@pytest.fixture
def local(engine: ArmorEngine) -> httpx.Client:
    return httpx.Client(base_url="http://local", transport=LocalTransport(engine))


def test_the_local_transport_answers_as_the_server(
    engine: ArmorEngine, local: httpx.Client
) -> None:
    body = {"armor_request": _directive("QUERY", "IND", "CLASS", "Kitchen")}
    answer = local.post("/armor_interface_srv", json=body, params={"values": "short"})
    assert answer.status_code == 200
    assert answer.headers["content-type"] == "application/json"
    assert answer.content == answer_blocking(engine, SINGLE, _body(body), query="values=short")
    assert answer.json()["armor_response"]["queried_objects"] == ["k1"]


@pytest.mark.parametrize(
    ("method", "path", "body", "status", "detail"),
    [
        ("POST", "/armor_interface_srv", {"armor_request": {"args": "k"}}, 422, None),
        ("POST", "/armor_interface_serialized_srv", {"armor_requests": 1}, 422, None),
        ("GET", "/armor_interface_srv", None, 405, "Method Not Allowed"),
        ("POST", "/elsewhere", {}, 404, "Not Found"),
    ],
)
def test_the_local_transport_refuses_as_the_server(
    local: httpx.Client, method: str, path: str, body: Any, status: int, detail: str | None
) -> None:
    answer = local.request(method, path, json=body)
    assert answer.status_code == status
    if detail is None:
        assert answer.json()["detail"][0]["loc"][0] == "body"
    else:
        assert answer.json() == {"detail": detail}


def test_the_client_works_over_the_local_transport(local: httpx.Client) -> None:
    client = ArmorClient("tester", "kitchen", http=local)
    assert client.query.ind_b2_class("Kitchen") == ["k1"]
