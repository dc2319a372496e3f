"""``engram ros`` on a real master, called with rospy as ARMOR's clients call ARMOR."""

import socket
import struct
import uuid
from collections.abc import Callable
from io import BytesIO
from pathlib import Path

import pytest

from api.protocol import ArmorDirectiveListRes
from api.ros._ros import rosgraph, rospy
from api.ros.convert import response_of
from tests.api.armor.conftest import directives
from tests.conftest import LiveServer
from tests.ros.conftest import ARMOR_FILE_DIRS, MAX_LIST_LENGTH, RosArmor
from tests.ros.sequences import armor_py_api_client_test, every_family
from tests.third_party.load_armor_py_api import (
    CLIENT_TEST_OUTPUT,
    VENDORED,
    armor_py_api,
    individuals,
    run_client_test,
)


def test_every_family_answers_over_ros_as_over_http(
    ros_armor: RosArmor, start_server: Callable[..., LiveServer], tmp_path: Path
) -> None:
    http = start_server(armor_file_dirs=ARMOR_FILE_DIRS).client
    ref = "ref_" + uuid.uuid4().hex[:8]
    for request in directives(every_family(tmp_path / "saved.owl"), ref):
        over_ros = ros_armor.execute(request)
        answer = http.post("/armor_interface_srv", json={"armor_request": request.model_dump()})
        assert answer.status_code == 200, answer.text
        over_http = answer.json()["armor_response"]
        assert over_ros.model_dump() == over_http, request
    # the list service, on a sequence of armor_py_api (the memory is this node's to share with
    # the perception test, so its answers depend on what was perceived before)
    scene = directives(armor_py_api_client_test(), ref + "_list")
    listed = ros_armor.execute_list(scene)
    over_ros_list = ArmorDirectiveListRes(
        success=listed.success,
        is_consistent=listed.is_consistent,
        armor_responses=[response_of(r) for r in listed.armor_responses],
    )
    answer = http.post(
        "/armor_interface_serialized_srv",
        json={"armor_requests": [d.model_dump() for d in scene]},
    )
    assert over_ros_list.model_dump() == answer.json()
    assert over_ros_list.success


def test_a_directive_list_is_one_transaction_over_ros(ros_armor: RosArmor) -> None:
    ref = "ref_" + uuid.uuid4().hex[:8]
    load = ("LOAD", "FILE", "", ["", "http://ex.org/" + ref, "false", "PELLET", "true"])
    ros_armor.execute(directives([load], ref)[0])
    failing = directives(
        [("ADD", "IND", "CLASS", ["kept_not", "Class_1"]), ("ADD", "IND", "CLASS", ["only"])],
        ref,
    )
    result = ros_armor.execute_list(failing)
    assert not result.success
    assert [r.exit_code for r in result.armor_responses][1] != 0
    query = directives([("QUERY", "IND", "CLASS", ["Class_1"])], ref)[0]
    assert ros_armor.execute(query).queried_objects == []


def test_armor_py_api_client_test_runs_unchanged_over_ros(
    ros_armor: RosArmor, tmp_path: Path
) -> None:
    """armor_py_api itself (vendored, tests/third_party), over rospy: its ``client_test.py`` as
    a script, and the file it makes the node save holds what ARMOR saved for it."""
    with armor_py_api(stand_in=False):
        printed, saved = run_client_test(tmp_path)
    assert printed == CLIENT_TEST_OUTPUT
    assert individuals(saved) == individuals(VENDORED / "test" / "inferred_test.owl")


def test_the_same_sequence_as_one_list(ros_armor: RosArmor) -> None:
    ref = "ref_" + uuid.uuid4().hex[:8]
    result = ros_armor.execute_list(directives(armor_py_api_client_test(), ref))
    assert result.success, result
    assert len(result.armor_responses) == len(armor_py_api_client_test())
    assert result.armor_responses[-1].success  # ind_1 exists


def _call_bytes(ros: RosArmor, request: object) -> tuple[bytes, bytes]:
    """A TCPROS service connection header and one serialized ArmorDirectiveList request."""
    header = rosgraph.network.encode_ros_handshake_header(
        {
            "callerid": "/impatient_client",
            "service": "/armor_interface_serialized_srv",
            "md5sum": ros.types.srv.ArmorDirectiveList._md5sum,
            "persistent": "1",
        }
    )
    buffer = BytesIO()
    request.serialize(buffer)  # type: ignore[attr-defined]
    body = buffer.getvalue()
    return header, struct.pack("<I", len(body)) + body


@pytest.mark.parametrize("cut", ["after the request", "in the middle of the request"])
def test_a_client_that_disconnects_mid_call_leaves_the_node_serving(
    ros_armor: RosArmor, cut: str
) -> None:
    ref = "ref_" + uuid.uuid4().hex[:8]
    steps = [("ADD", "IND", "CLASS", [f"ind_{i}", "Class_1"]) for i in range(300)]
    load = ("LOAD", "FILE", "", ["", "http://ex.org/" + ref, "false", "PELLET", "true"])
    request = ros_armor.types.srv.ArmorDirectiveListRequest(
        [ros_armor.request(d) for d in directives([load, *steps], ref)]
    )
    header, call = _call_bytes(ros_armor, request)
    uri = rospy.ServiceProxy(
        "/armor_interface_serialized_srv", ros_armor.types.srv.ArmorDirectiveList
    )._get_service_uri(request)
    host, port = rospy.core.parse_rosrpc_uri(uri)
    with socket.create_connection((host, port), timeout=10) as raw:
        raw.sendall(header)
        raw.sendall(call if cut == "after the request" else call[: len(call) // 2])
    # the node answers the next clients as before
    query = directives([("QUERY", "IND", "CLASS", ["Class_1"])], ref)[0]
    answer = ros_armor.execute(query)
    assert answer.exit_code in (0, 207)
    assert ros_armor.execute_list(directives(armor_py_api_client_test(), ref + "_b")).success


def test_a_list_longer_than_the_maximum_fails_the_call_and_changes_nothing(
    ros_armor: RosArmor,
) -> None:
    ref = "ref_" + uuid.uuid4().hex[:8]
    load = ("LOAD", "FILE", "", ["", "http://ex.org/" + ref, "false", "PELLET", "true"])
    assert ros_armor.execute(directives([load], ref)[0]).success
    steps = [("ADD", "IND", "CLASS", [f"ind_{i}", "Class_1"]) for i in range(MAX_LIST_LENGTH + 1)]
    with pytest.raises(rospy.ServiceException, match="at most 2000 directives"):
        ros_armor.execute_list(directives(steps, ref))
    query = directives([("QUERY", "IND", "CLASS", ["Class_1"])], ref)[0]
    assert ros_armor.execute(query).queried_objects == []
