"""The short request path (event loop, pydantic straight from the bytes) answers as FastAPI's
usual path does, and a directive runs on the event loop only if nothing can make it wait."""

import threading
from pathlib import Path

from api.armor import ArmorDirectiveReq, ArmorEngine
from kg import Store

from .conftest import Armor


def _directive(ref: str, command: str, first: str, second: str, *args: str) -> dict[str, object]:
    return {
        "client_name": "tester",
        "reference_name": ref,
        "command": command,
        "primary_command_spec": first,
        "secondary_command_spec": second,
        "args": list(args),
    }


def test_the_short_path_and_fastapis_usual_path_answer_alike(armor: Armor, ref: str) -> None:
    """``application/json`` takes the short path; ``application/x+json`` FastAPI's usual one."""
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
