"""Mount, buffering, the list service as one transaction, and concurrent clients."""

import threading
from collections.abc import Callable

from tests.api.armor.conftest import Armor, directive


def test_mount_conflict_sequence(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    assert armor.call("MOUNT", ref=ref, client="alice")["success"]
    assert armor.call("MOUNT", ref=ref, client="alice")["success"]  # again: a warning only
    busy = armor.call("MOUNT", ref=ref, client="bob")
    assert (busy["success"], busy["exit_code"]) == (False, 203)
    assert (
        busy["error_description"]
        == f"bob cannot be mounted on {ref}. Another client is already mounted on it."
    )
    assert armor.call("GET", "REF", "CLIENT", [ref], ref=ref)["queried_objects"] == ["alice"]
    for command in (
        ["ADD", "IND", "CLASS", ["x", "C"]],
        ["REMOVE", "IND", "", ["x"]],
        ["APPLY", "", "", []],
        ["REASON", "", "", []],
        ["RENAME", "IND", "", ["x", "y"]],
    ):
        refused = armor.call(*command, ref=ref, client="bob")  # type: ignore[arg-type]
        assert (refused["success"], refused["exit_code"]) == (False, 102), command
        assert (
            refused["error_description"]
            == f"bob cannot connect to {ref}. Another client is already mounted on it."
        )
    assert armor.call("QUERY", "IND", "CLASS", ["C"], ref=ref, client="bob")[
        "success"
    ]  # queries never gated
    assert armor.call("ADD", "IND", "CLASS", ["x", "C"], ref=ref, client="alice")["success"]
    assert armor.call("UNMOUNT", ref=ref, client="bob")["success"]  # not bob's: ignored
    assert armor.call("GET", "REF", "CLIENT", [ref], ref=ref)["queried_objects"] == ["alice"]
    assert armor.call("UNMOUNT", ref=ref, client="alice")["success"]
    assert armor.call("ADD", "IND", "CLASS", ["y", "C"], ref=ref, client="bob")["success"]
    assert armor.call("MOUNT", ref="never_loaded_ref", client="bob")["exit_code"] == 203


def test_load_mounted_keeps_the_reference_when_the_mount_fails(armor: Armor, ref: str) -> None:
    args = ["", f"http://ex.org/{ref}", "false", "PELLET", "true"]
    assert armor.call("LOAD", "FILE", "MOUNTED", args, ref=ref, client="alice")["success"]
    again = armor.call("LOAD", "FILE", "MOUNTED", args, ref=ref, client="bob")
    assert (again["success"], again["exit_code"]) == (False, 203)
    assert again["error_description"].startswith(
        "Reference loaded from file but bob cannot be mounted"
    )
    assert ref in armor.call("GET", "ALL", "REFS", ref=ref)["queried_objects"]


def test_buffered_manipulation_is_invisible_until_apply(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded(buffered=True)
    armor.call("ADD", "IND", "CLASS", ["a", "Box"], ref=ref)
    armor.call("ADD", "DATAPROP", "IND", ["size", "a", "INTEGER", "2"], ref=ref)
    armor.call("REPLACE", "DATAPROP", "IND", ["size", "a", "INTEGER", "3", "2"], ref=ref)
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref)["queried_objects"] == []
    bad = armor.call("ADD", "IND", "CLASS", ["only_one"], ref=ref)  # checked when queued
    assert bad["exit_code"] == 208
    assert armor.call("APPLY", ref=ref)["success"]
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref, values="short")[
        "queried_objects"
    ] == ["a"]
    assert armor.call("QUERY", "DATAPROP", "IND", ["size", "a"], ref=ref)["queried_objects"] == [
        '"3"^^xsd:integer'
    ]
    armor.call("REMOVE", "IND", "CLASS", ["a", "Box"], ref=ref)
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref, values="short")[
        "queried_objects"
    ] == ["a"]
    assert armor.call("REASON", ref=ref)["success"]  # REASON applies the buffer first
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref)["queried_objects"] == []


def test_unbuffered_manipulation_is_visible_at_once(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded(buffered=False)
    armor.call("ADD", "IND", "CLASS", ["a", "Box"], ref=ref)
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref, values="short")[
        "queried_objects"
    ] == ["a"]


def test_buffered_reasoner_is_stale_until_reason(armor: Armor, ref: str) -> None:
    for name, buffered_reasoner in ((ref + "_b", "true"), (ref + "_u", "false")):
        armor.call(
            "LOAD",
            "FILE",
            "",
            ["", f"http://ex.org/{ref}", "false", "PELLET", buffered_reasoner],
            ref=name,
        )
        armor.call("ADD", "CLASS", "CLASS", ["Kitchen", "Room"], ref=name)
        armor.call("ADD", "IND", "CLASS", ["k", "Kitchen"], ref=name)
        armor.call("ADD", "OBJECTPROP", "IND", ["contains", "k", "cup"], ref=name)
        armor.call("ADD", "DATAPROP", "IND", ["size", "k", "INTEGER", "1"], ref=name)
    text = "SELECT ?x WHERE { ?x a ?c FILTER(STRENDS(STR(?c), '#Room')) }"
    # asserted facts are current either way; only inferred triples wait for REASON
    stale = armor.call("QUERY", "SPARQL", "", [text], ref=ref + "_b", values="short")
    fresh = armor.call("QUERY", "SPARQL", "", [text], ref=ref + "_u", values="short")
    assert (stale["queried_objects"], fresh["queried_objects"]) == ([""], ["{x=k}"])
    armor.call("REASON", ref=ref + "_b")
    assert armor.call("QUERY", "SPARQL", "", [text], ref=ref + "_b", values="short")[
        "queried_objects"
    ] == ["{x=k}"]


def test_list_executes_in_order_and_later_directives_see_earlier_writes(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    result = armor.call_list(
        [
            directive("ADD", "IND", "CLASS", ["a", "Box"], ref=ref),
            directive("QUERY", "IND", "CLASS", ["Box"], ref=ref),
            directive("REMOVE", "IND", "CLASS", ["a", "Box"], ref=ref),
            directive("QUERY", "IND", "", ["a"], ref=ref),
            directive("ADD", "IND", "CLASS", ["b", "Box"], ref=ref),
        ]
    )
    assert result["success"] is True
    responses = result["armor_responses"]
    assert len(responses) == 5
    assert responses[1]["queried_objects"] == [f"<http://ex.org/{ref}#a>"]
    assert (responses[3]["success"], responses[3]["exit_code"]) == (
        False,
        0,
    )  # an answer, not an error
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref, values="short")[
        "queried_objects"
    ] == ["b"]


def test_a_failing_directive_undoes_the_whole_list(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    armor.call("ADD", "IND", "CLASS", ["kept", "Box"], ref=ref)
    result = armor.call_list(
        [
            directive("ADD", "IND", "CLASS", ["a", "Box"], ref=ref),
            directive("REMOVE", "IND", "", ["kept"], ref=ref),
            directive("ADD", "DATAPROP", "IND", ["size", "a", "INTEGER", "huge"], ref=ref),
            directive("ADD", "IND", "CLASS", ["b", "Box"], ref=ref),
            directive("MOUNT", client="x", ref=ref),
        ]
    )
    assert result["success"] is False
    codes = [(r["success"], r["exit_code"]) for r in result["armor_responses"]]
    assert codes == [(True, 0), (True, 0), (False, 208), (True, 0), (True, 0)]  # each one reported
    assert armor.call("QUERY", "IND", "CLASS", ["Box"], ref=ref, values="short")[
        "queried_objects"
    ] == ["kept"]
    assert armor.call("GET", "REF", "CLIENT", [ref], ref=ref)["queried_objects"] == ["none"]


def test_empty_list_and_list_across_references(armor: Armor, ref: str) -> None:
    assert armor.call_list([]) == {"success": True, "is_consistent": False, "armor_responses": []}
    result = armor.call_list(
        [
            directive("LOAD", "FILE", "", ["", "http://ex.org/one"], ref=ref + "_1"),
            directive("LOAD", "FILE", "", ["", "http://ex.org/two"], ref=ref + "_2"),
            directive("ADD", "IND", "CLASS", ["a", "A"], ref=ref + "_1"),
            directive("ADD", "IND", "CLASS", ["a", "A"], ref=ref + "_2"),
            directive("QUERY", "IND", "CLASS", ["A"], ref=ref + "_1"),
        ]
    )
    assert result["success"] and result["is_consistent"]
    assert result["armor_responses"][4]["queried_objects"] == ["<http://ex.org/one#a>"]


def test_concurrent_writers_lose_no_update_and_readers_see_committed_states(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    errors: list[str] = []

    def writer(worker: int) -> None:
        for i in range(15):
            # each list adds a pair; a reader must never see one half of a pair
            result = armor.call_list(
                [
                    directive("ADD", "IND", "CLASS", [f"w{worker}_{i}_a", "Item"], ref=ref),
                    directive("ADD", "IND", "CLASS", [f"w{worker}_{i}_b", "Item"], ref=ref),
                ]
            )
            if not result["success"]:
                errors.append(str(result))

    def reader() -> None:
        for _ in range(20):
            items = armor.call("QUERY", "IND", "CLASS", ["Item"], ref=ref, values="short")[
                "queried_objects"
            ]
            if len(items) % 2:
                errors.append(f"half a list visible: {len(items)} items")

    threads = [threading.Thread(target=writer, args=(w,)) for w in range(6)]
    threads += [threading.Thread(target=reader) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []
    items = armor.call("QUERY", "IND", "CLASS", ["Item"], ref=ref)["queried_objects"]
    assert len(items) == 6 * 15 * 2
