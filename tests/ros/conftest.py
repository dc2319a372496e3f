"""A real ROS master and ``engram ros`` per test module, and rospy clients of its services."""

import gc
import os
import tempfile
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from api.protocol import (
    ArmorDirectiveReq,
    ArmorDirectiveRes,
)
from api.ros._ros import rospy
from api.ros.convert import response_of, ros_request
from api.ros.messages import ArmorMsgs, armor_msgs
from shapes.synthetic import Camera
from tests.conftest import free_port
from tests.ros.processes import Engram, Master


class RosArmor:
    """Calls ARMOR's two services with rospy's ServiceProxy, as ARMOR's clients do."""

    def __init__(self, master_uri: str) -> None:
        os.environ["ROS_MASTER_URI"] = master_uri  # read by rospy at each lookup
        self.types: ArmorMsgs = armor_msgs()
        self.single = rospy.ServiceProxy("/armor_interface_srv", self.types.srv.ArmorDirective)
        self.list = rospy.ServiceProxy(
            "/armor_interface_serialized_srv", self.types.srv.ArmorDirectiveList
        )

    def request(self, directive: ArmorDirectiveReq) -> Any:
        return ros_request(directive, self.types.msg)

    def execute(self, directive: ArmorDirectiveReq) -> ArmorDirectiveRes:
        return response_of(self.single(self.request(directive)).armor_response)

    def execute_list(self, directives: list[ArmorDirectiveReq]) -> Any:
        return self.list([self.request(d) for d in directives])


@pytest.fixture(autouse=True)
def _rospy_sockets() -> Iterator[None]:
    """rospy leaves sockets of its XML-RPC connections unclosed (their warnings are ignored)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        yield


@pytest.fixture(autouse=True, scope="module")
def _collect_rospy_sockets() -> Iterator[None]:
    """Those of them in reference cycles: collected before the next module's tests. And the
    connections rospy keeps to each master it called (its XML-RPC proxies, cached for the
    process's life), closed: left open, they are reported at the interpreter's exit, after
    pytest's summary (run ``-p tests.open_sockets`` to see)."""
    yield
    for proxy in rospy.core._xmlrpc_cache.values():
        proxy("close")()
    rospy.core._xmlrpc_cache.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResourceWarning)
        gc.collect()


CLOUD_TOPIC = "/engram_test/points"
RESULT_TOPIC = "/engram_test/scenes"


MAX_LIST_LENGTH = 2000
ARMOR_TEST_FILES = Path(__file__).parents[1] / "api" / "armor" / "data"
"""The ontologies the ARMOR sequences load with LOAD FILE."""
ARMOR_FILE_DIRS = os.pathsep.join([tempfile.gettempdir(), str(ARMOR_TEST_FILES)])
"""Where the tests' ARMOR file commands go: the ontologies above, and SAVE into temporary files."""
"""ENGRAM_ARMOR_MAX_LIST_LENGTH of the ``engram ros`` under test."""


@dataclass
class Launched:
    """The two nodes under test, each on its own master, started together (each takes seconds
    to import Engram): ``engram ros`` and ``engram serve --ros`` (whose master a test restarts)."""

    ros_master: Master
    ros: Engram
    serve_master: Master
    serve: Engram
    http_port: int


@pytest.fixture(scope="session")
def launched(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Launched]:
    ros_home = tmp_path_factory.mktemp("engram-ros")
    serve_home = tmp_path_factory.mktemp("serve-ros")
    ros_master = Master(free_port(), ros_home).start()
    serve_master = Master(free_port(), serve_home).start()
    pose = ros_home / "pose.txt"
    np.savetxt(pose, Camera().world_from_camera)
    arguments = ["ros", "--init", "--data", str(ros_home / "data"), "--cloud-topic", CLOUD_TOPIC]
    arguments += ["--result-topic", RESULT_TOPIC, "--pose", str(pose)]
    arguments += ["--scene-frames", "2", "--min-hits", "2"]
    # ARMOR's file commands reach the data directory and the directories allowed (docs/security.md)
    files = {"ENGRAM_ARMOR_FILE_DIRS": ARMOR_FILE_DIRS}
    limit = {"ENGRAM_ARMOR_MAX_LIST_LENGTH": str(MAX_LIST_LENGTH), **files}
    port = free_port()
    serve_arguments = ["serve", "--ros", "--init", "--data", str(serve_home / "data")]
    serve_arguments += ["--port", str(port)]
    nodes = [
        Engram(arguments, ros_master, ros_home, limit),
        Engram(serve_arguments, serve_master, serve_home, files),
    ]
    try:
        for node in nodes:
            node.wait()
        yield Launched(ros_master, nodes[0], serve_master, nodes[1], port)
        for node in nodes:
            node.interrupt()  # both stop at once
        codes = [node.stop() for node in nodes]
        assert codes == [0, 0], "a node did not stop cleanly on SIGINT: " + "".join(
            node.log_path.read_text() for node in nodes
        )
    finally:
        for node in nodes:
            node.stop()
        ros_master.stop()
        serve_master.stop()


@pytest.fixture(scope="session")
def ros_master(launched: Launched) -> Master:
    """The master of ``engram ros``."""
    return launched.ros_master


@pytest.fixture(scope="session")
def engram_ros(launched: Launched) -> Path:
    """``engram ros`` on a fresh data directory, perceiving ``CLOUD_TOPIC`` from the synthetic
    tabletop camera's pose, lists limited to ``MAX_LIST_LENGTH``; its home directory."""
    return launched.ros.home


@pytest.fixture
def ros_armor(engram_ros: Path, ros_master: Master) -> RosArmor:
    return RosArmor(ros_master.uri)
