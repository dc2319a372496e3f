"""Numbers that are not finite in a JSON body answer 422 naming the field, on every endpoint."""

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from api.finite_json import could_hold_non_finite
from tests.conftest import LiveServer

pytestmark = pytest.mark.slow

NON_FINITE = ["NaN", "Infinity", "-Infinity", "1e999", "-1e999"]


def _json_operations(live_server: LiveServer) -> list[tuple[str, str]]:
    spec = live_server.client.get("/openapi.json").json()
    found = []
    for path, operations in spec["paths"].items():
        for method, operation in operations.items():
            content = operation.get("requestBody", {}).get("content", {})
            if "application/json" in content:
                found.append((method, path.replace("{", "").replace("}", "")))
    return found


def test_every_json_endpoint_refuses_non_finite_numbers(live_server: LiveServer) -> None:
    operations = _json_operations(live_server)
    assert len(operations) >= 10
    for method, path in operations:
        for number in NON_FINITE:
            answer = live_server.client.request(
                method,
                path,
                content=f'{{"outer": {{"inner": [1, {number}]}}}}',
                headers={"Content-Type": "application/json"},
            )
            assert answer.status_code == 422, (method, path, number, answer.text)
            [error] = answer.json()["detail"]
            assert error["loc"] == ["body", "outer", "inner", 1]
            assert error["type"] == "finite_number"


def test_a_non_finite_annotation_confidence_is_refused_and_nothing_is_stored(
    live_server: LiveServer,
) -> None:
    begun = live_server.client.post("/episodes", json={"activity": "babbling", "id": "ep1"})
    assert begun.status_code == 201, begun.text
    before = live_server.client.get("/episodes/ep1").json()
    answer = live_server.client.post(
        "/episodes/ep1/annotations",
        content='{"key": "mood", "value": "calm", "confidence": NaN}',
        headers={"Content-Type": "application/json"},
    )
    assert answer.status_code == 422
    assert answer.json()["detail"][0]["loc"] == ["body", "confidence"]
    assert live_server.client.get("/episodes/ep1").json() == before


def test_finite_numbers_pass_untouched(live_server: LiveServer) -> None:
    answer = live_server.client.post(
        "/sparql",
        content='{"note": 1e300}',
        headers={"Content-Type": "application/json"},
    )
    assert answer.status_code == 415  # the route's own answer: the middleware let it through


SPELLINGS = re.compile(rb"NaN|Infinity|[eE][+-]?\d{3}|\d{300}")
"""Every way JSON text can spell a number that is not finite (what the scan must catch)."""


@pytest.mark.parametrize(
    ("body", "suspect"),
    [
        (b'{"a": 1.5e-7, "b": "Class_3", "c": [1, 22, 333]}', False),
        (b'{"a": 1e999}', True),
        (b'{"a": -1E+308}', True),
        (b'{"a": 2e-400}', True),
        (b'{"a": NaN}', True),
        (b'{"a": -Infinity}', True),
        (b'{"a": ' + b"9" * 300 + b"}", True),
        (b'{"a": ' + b"9" * 299 + b"}", False),
    ],
)
def test_the_scan_finds_every_spelling_of_a_non_finite_number(body: bytes, suspect: bool) -> None:
    assert could_hold_non_finite(body) is suspect


@given(st.binary(max_size=80) | st.text("0123456789eE+-.NaInfity ", max_size=400).map(str.encode))
def test_the_scan_misses_nothing_the_pattern_finds(body: bytes) -> None:
    if SPELLINGS.search(body):
        assert could_hold_non_finite(body)
