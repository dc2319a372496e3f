"""``engram ros`` on a real master, called with rospy as ARMOR's clients call ARMOR."""

import socket
import struct
import uuid
from collections.abc import Callable
from io import BytesIO
from pathlib import Path

import pytest

from api.armor.models import ArmorDirectiveListRes
from api.client import ArmorClient
from api.ros._ros import rosgraph, rospy
from api.ros.convert import response_of
from tests.conftest import LiveServer
from tests.ros.conftest import ARMOR_FILE_DIRS, MAX_LIST_LENGTH, RosArmor
from tests.ros.sequences import (
    armor_py_api_client_test,
    directives,
    every_family,
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


def test_armor_py_api_client_test_runs_unchanged_over_ros(py_api_client: ArmorClient) -> None:
    """armor_py_api's client_test.py, call for call (api.client keeps armor_py_api's names)."""
    client = py_api_client
    steps = armor_py_api_client_test()
    owl, iri = steps[0][3][0], steps[0][3][1]
    client.utils.load_ref_from_file(owl, iri, True, "PELLET", True, False)
    client.utils.mount_on_ref()
    client.utils.set_log_to_terminal(True)
    client.manipulation.add_ind_to_class("ind_1", "Class_1")
    client.manipulation.add_ind_to_class("ind_2", "Class_2")
    client.manipulation.add_ind_to_class("ind_3", "Class_3")
    client.manipulation.add_objectprop_to_ind("OProperty_1", "ind_1", "ind_3")
    client.manipulation.add_objectprop_to_ind("OProperty_2", "ind_1", "ind_2")
    client.manipulation.add_dataprop_to_ind("DProperty_1", "ind_1", "INTEGER", "1")
    client.manipulation.replace_dataprop_b2_ind("DProperty_1", "ind_1", "INTEGER", "3", "1")
    client.utils.apply_buffered_changes()
    client.utils.sync_buffered_reasoner()
    assert client.query.check_ind_exists("ind_1")
    # "Success! ind_1 is in Class_4 now!": the reasoner classified it
    assert "ind_1" in client.query.ind_b2_class("Class_4")
    assert client.query.dataprop_b2_ind("DProperty_1", "ind_1") == ['"3"^^xsd:integer']
    client.utils.unmount_from_ref()


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
