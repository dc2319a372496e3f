"""Hostile SPARQL against a real server: no query crashes it, escapes it or outlasts its limit.

Each test is a finding of the hardening campaign (issue 12): nested braces that overflowed the
parser's stack in the server, ``SERVICE`` hidden behind a comment ended by a carriage return,
ASK and aggregates evaluated in full before the time limit applied, an unbounded body, and an
unknown function answered as an internal error.
"""

import threading
from collections.abc import Callable, Iterator

import httpx
import pytest

from tests.api.armor.conftest import Armor, directive
from tests.conftest import LiveServer
from tests.listener import Listener, listening

pytestmark = pytest.mark.slow

NESTED = "SELECT * WHERE " + "{" * 2300 + " ?s ?p ?o " + "}" * 2300
FOUR_VALUES = (
    "ASK { "
    + " ".join(f"VALUES ?{name} {{ {' '.join(str(i) for i in range(90))} }}" for name in "abcd")
    + " FILTER(?a + ?b + ?c + ?d < 0) }"
)
UNKNOWN_FUNCTION = "SELECT ?x WHERE { BIND(<http://example.org/nope>(1) AS ?x) }"


@pytest.fixture
def listener() -> Iterator[Listener]:
    with listening() as running:
        yield running


def test_deeply_nested_braces_are_refused_and_the_server_lives(live_server: LiveServer) -> None:
    answer = live_server.client.get("/sparql", params={"query": NESTED})
    assert answer.status_code == 400
    assert "nests 2300 levels" in answer.json()["detail"]
    assert live_server.client.get("/health").status_code == 200


def test_a_query_nested_within_the_limit_still_runs(live_server: LiveServer) -> None:
    text = "ASK " + "{" * 100 + " ?s ?p ?o " + "}" * 100
    answer = live_server.client.get("/sparql", params={"query": text})
    assert answer.status_code == 200
    assert answer.json()["boolean"] is True


@pytest.mark.parametrize("line_end", ["\r", "\n", "\r\n"])
def test_service_after_a_comment_is_refused_and_never_called(
    live_server: LiveServer, listener: Listener, line_end: str
) -> None:
    text = (
        f"SELECT * WHERE {{ # x{line_end}SERVICE <http://127.0.0.1:{listener.port}/sparql> "
        "{ ?s ?p ?o } }"
    )
    answer = live_server.client.get("/sparql", params={"query": text})
    assert answer.status_code == 403
    assert "SERVICE" in answer.json()["detail"]
    assert not listener.contacted.wait(0.5)


def test_service_spelled_with_escapes_is_refused(
    live_server: LiveServer, listener: Listener
) -> None:
    text = f"ASK {{ SERVIC\\u0045 SILENT <http://127.0.0.1:{listener.port}/> {{ ?s ?p ?o }} }}"
    answer = live_server.client.get("/sparql", params={"query": text})
    assert answer.status_code in (400, 403)
    assert not listener.contacted.wait(0.5)


def test_the_word_service_outside_code_is_no_reason_to_refuse(live_server: LiveServer) -> None:
    text = "SELECT ?service WHERE { BIND('SERVICE' AS ?service) } # SERVICE <http://x/>"
    answer = live_server.client.get("/sparql", params={"query": text})
    assert answer.status_code == 200
    assert answer.json()["results"]["bindings"][0]["service"]["value"] == "SERVICE"


def test_ask_over_big_values_blocks_stops_at_the_time_limit(
    start_server: Callable[..., LiveServer],
) -> None:
    server = start_server(sparql_timeout_s=1.0)
    # before the fix, the check evaluated this in the server for about 40 s, past this timeout
    with httpx.Client(base_url=server.url, timeout=20) as client:
        answer = client.get("/sparql", params={"query": FOUR_VALUES})
        assert answer.status_code == 503
        assert "time limit of 1 s" in answer.json()["detail"]
        assert client.get("/health").status_code == 200


def test_a_20_mib_body_is_refused_with_413_and_health_keeps_answering(
    live_server: LiveServer,
) -> None:
    body = b"SELECT * WHERE { ?s ?p ?o } #" + b"x" * (20 * 1024 * 1024)
    healthy: list[int] = []

    def poll_health() -> None:
        with httpx.Client(base_url=live_server.url, timeout=10) as client:
            healthy.append(client.get("/health").status_code)

    poller = threading.Thread(target=poll_health)
    poller.start()
    answer = live_server.client.post(
        "/sparql", content=body, headers={"Content-Type": "application/sparql-query"}
    )
    poller.join()
    assert answer.status_code == 413
    assert "longer than the limit of 1048576 bytes" in answer.json()["detail"]
    assert healthy == [200]
    assert live_server.client.get("/health").status_code == 200


def test_a_query_longer_than_the_limit_in_the_url_is_refused(
    start_server: Callable[..., LiveServer],
) -> None:
    server = start_server(sparql_max_query_bytes=100)
    text = "SELECT * WHERE { ?s ?p ?o } #" + "x" * 200
    answer = server.client.get("/sparql", params={"query": text})
    assert answer.status_code == 413
    assert "longer than the limit of 100" in answer.json()["detail"]


def test_an_unknown_function_is_a_bad_request(live_server: LiveServer) -> None:
    answer = live_server.client.get("/sparql", params={"query": UNKNOWN_FUNCTION})
    assert answer.status_code == 400
    assert "http://example.org/nope" in answer.json()["detail"]


# The same through ARMOR's QUERY SPARQL ------------------------------------------------------


@pytest.fixture
def armor(live_server: LiveServer) -> Armor:
    armor = Armor(live_server.client, live_server.url)
    armor.load_empty("hostile")
    return armor


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        (NESTED, "nests 2300 levels"),
        (UNKNOWN_FUNCTION, "http://example.org/nope"),
        ("SELECT * WHERE { # x\rSERVICE <http://127.0.0.1:9/> { ?s ?p ?o } }", "SERVICE"),
    ],
    ids=["nested", "unknown-function", "service"],
)
def test_armor_query_sparql_answers_210(
    armor: Armor, live_server: LiveServer, text: str, fragment: str
) -> None:
    result = armor.call("QUERY", "SPARQL", "", [text], ref="hostile")
    assert (result["success"], result["exit_code"]) == (False, 210)
    assert fragment in result["error_description"]
    assert live_server.client.get("/health").status_code == 200


def test_armor_query_sparql_times_out_with_its_own_timeout(armor: Armor) -> None:
    select = FOUR_VALUES.replace("ASK {", "SELECT (COUNT(*) AS ?n) WHERE {", 1)
    result = armor.call("QUERY", "SPARQL", "", [select, "500"], ref="hostile")
    assert (result["success"], result["exit_code"], result["timeout"]) == (False, 210, True)


def test_armor_query_sparql_sees_the_lists_own_writes(armor: Armor) -> None:
    select = "SELECT ?i WHERE { ?i a ?c } ORDER BY ?i"
    answer = armor.call_list(
        [
            directive("ADD", "IND", "CLASS", ["box1", "Box"], ref="hostile"),
            directive("QUERY", "SPARQL", "", [select], ref="hostile"),
        ]
    )
    responses = answer["armor_responses"]
    assert [r["success"] for r in responses] == [True, True]
    assert "box1" in responses[1]["queried_objects"][0]
