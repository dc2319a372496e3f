"""A directive list longer than the configured maximum is refused whole, with a clear 422, and
the list's reads of its own writes stay correct with the writes indexed."""

from collections.abc import Callable

import pytest
from pyoxigraph import Literal, NamedNode, Quad

from api.armor.session import ChangeSet
from tests.api.armor.conftest import Armor, directive
from tests.conftest import LiveServer


@pytest.mark.slow
def test_a_list_over_the_maximum_answers_422_and_writes_nothing(
    start_server: Callable[..., LiveServer],
) -> None:
    server = start_server(armor_max_list_length=3)
    armor = Armor(server.client, server.url)
    armor.load_empty("r")
    adds = [directive("ADD", "IND", "CLASS", [f"i{i}", "Box"], ref="r") for i in range(4)]
    answer = server.client.post("/armor_interface_serialized_srv", json={"armor_requests": adds})
    assert answer.status_code == 422
    body = answer.json()
    assert (body["field"], body["value"]) == ("armor_requests", 4)
    assert "at most 3 directives" in body["detail"]
    listed = armor.call("QUERY", "IND", "CLASS", ["Box"], ref="r")
    assert listed["queried_objects"] == []
    assert armor.call_list(adds[:3])["armor_responses"][2]["success"]


def _quad(s: str, p: str, o: str) -> Quad:
    return Quad(NamedNode(f"http://x/{s}"), NamedNode(f"http://x/{p}"), NamedNode(f"http://x/{o}"))


def test_a_change_sets_pattern_reads_match_a_scan() -> None:
    changes = ChangeSet()
    quads = [_quad(f"s{i % 5}", f"p{i % 3}", f"o{i % 4}") for i in range(60)]
    for quad in quads:
        changes.insert(quad)
    for quad in quads[::7]:
        changes.delete(quad)
    changes.insert(quads[0])
    terms = [None, NamedNode("http://x/s1"), NamedNode("http://x/p2"), NamedNode("http://x/o3")]
    for subject in (None, terms[1]):
        for predicate in (None, terms[2]):
            for obj in (None, terms[3], Literal("o3")):
                scanned = [
                    q
                    for q in changes.added
                    if (subject is None or q.subject == subject)
                    and (predicate is None or q.predicate == predicate)
                    and (obj is None or q.object == obj)
                ]
                assert changes.added_matching(subject, predicate, obj) == scanned  # type: ignore[arg-type]
    changes.clear()
    assert changes.added_matching(terms[1], None, None) == []  # type: ignore[arg-type]
