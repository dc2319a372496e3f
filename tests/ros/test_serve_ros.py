"""``engram serve --ros``: HTTP and ROS on one engine; the node outlives a master restart."""

import uuid
from collections.abc import Iterator
from dataclasses import dataclass

import httpx
import pytest

from tests.api.armor.conftest import request
from tests.ros.conftest import Launched, RosArmor
from tests.ros.processes import Master, service_registered, wait_for


@dataclass
class Served:
    master: Master
    http: httpx.Client
    ros: RosArmor


@pytest.fixture(scope="module")
def served(launched: Launched) -> Iterator[Served]:
    """``engram serve --ros`` on its own master (which a test restarts)."""
    url = f"http://127.0.0.1:{launched.http_port}"
    with httpx.Client(base_url=url, timeout=30) as http:
        wait_for(lambda: http.get("/health").status_code == 200, "the HTTP server")
        yield Served(launched.serve_master, http, RosArmor(launched.serve_master.uri))


def _http(served: Served, *args: object, ref: str) -> dict[str, object]:
    body = {"armor_request": request(*args, ref=ref).model_dump()}  # type: ignore[arg-type]
    answer = served.http.post("/armor_interface_srv", json=body)
    assert answer.status_code == 200, answer.text
    result: dict[str, object] = answer.json()["armor_response"]
    return result


def test_what_ros_clients_write_http_reads_and_back(served: Served) -> None:
    ref = "ref_" + uuid.uuid4().hex[:8]
    load = request("LOAD", "FILE", "", ["", "http://ex.org/" + ref, "false", "", "true"], ref=ref)
    assert served.ros.execute(load).success
    assert served.ros.execute(request("ADD", "IND", "CLASS", ["robot", "Agent"], ref=ref)).success
    assert _http(served, "QUERY", "IND", "CLASS", ["Agent"], ref=ref)["queried_objects"] == [
        f"<http://ex.org/{ref}#robot>"
    ]
    assert _http(served, "ADD", "IND", "CLASS", ["cup", "Agent"], ref=ref)["success"]
    seen = served.ros.execute(request("QUERY", "IND", "CLASS", ["Agent"], ref=ref))
    assert sorted(seen.queried_objects) == [
        f"<http://ex.org/{ref}#cup>",
        f"<http://ex.org/{ref}#robot>",
    ]


def test_the_node_registers_again_after_a_master_restart(served: Served) -> None:
    master = served.master
    master.stop()
    master.start()  # same port, a master that knows nothing
    wait_for(
        lambda: service_registered(master.uri, "/armor_interface_serialized_srv"),
        "engram to register again",
        timeout_s=30,
    )
    ref = "ref_" + uuid.uuid4().hex[:8]
    load = request("LOAD", "FILE", "", ["", "http://ex.org/" + ref, "false", "", "true"], ref=ref)
    assert served.ros.execute(load).success
    assert _http(served, "GET", "ALL", "REFS", ref=ref)["success"]


def test_engrams_log_stays_on_the_servers_console_once_ros_started(launched: Launched) -> None:
    """rospy.init_node sends the root logger to its log file; serve's console keeps it."""
    wait_for(
        lambda: "serving /armor_interface_srv" in launched.serve.log_path.read_text(),
        "the node's log line",
        timeout_s=10,
    )
