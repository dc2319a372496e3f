"""ARMOR over ROS on loopback: directive round trips, a 1,000-directive list, and PointCloud2
perception at 5 Hz. A real ``rosmaster`` is started on a free port; the node runs in this
process (``engram ros``'s services and perception on a fresh store), and the clients call it
with rospy's ServiceProxy over TCP, as ARMOR's clients do.

Targets (issue 30): round trip median <= 2 ms and p99 <= 10 ms; a 1,000-directive list <= 1 s;
a 640 x 480 cloud at 5 Hz perceived with no growing backlog (the subscriber keeps only the
newest cloud, so the backlog is at most one; the figures say how many were skipped).

    PYTHONPATH=. .venv/bin/python bench/ros.py [--calls 1000] [--seconds 10]
"""

import argparse
import os
import statistics
import sys
import tempfile
import time
import uuid
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from api.config import Settings
from api.protocol import ArmorDirectiveReq
from api.ros._ros import rospy, sensor_msgs
from api.ros.convert import ros_request
from api.ros.messages import armor_msgs
from api.ros.node_options import RosOptions
from api.ros.running import RunningNode
from api.ros.runtime import open_memory
from shapes.sensor import DepthCamera
from shapes.synthetic import TabletopScene, TruthObject
from tests.ros.processes import master

CLOUD_TOPIC = "/bench/points"


def _directive(command: str, first: str, second: str, args: list[str], ref: str) -> object:
    request = ArmorDirectiveReq(
        client_name="bench",
        reference_name=ref,
        command=command,
        primary_command_spec=first,
        secondary_command_spec=second,
        args=args,
    )
    return ros_request(request, armor_msgs().msg)


def _ms(values: list[float]) -> str:
    ordered = sorted(values)
    p99 = ordered[min(len(ordered) - 1, int(0.99 * len(ordered)))]
    return f"median {statistics.median(ordered) * 1e3:.2f} ms, p99 {p99 * 1e3:.2f} ms"


def round_trips(calls: int) -> None:
    srv = armor_msgs().srv
    ref = "ref_" + uuid.uuid4().hex[:8]
    load = ["", f"http://ex.org/{ref}", "false", "PELLET", "true"]
    for persistent in (False, True):
        proxy = rospy.ServiceProxy("/armor_interface_srv", srv.ArmorDirective, persistent)
        proxy(_directive("LOAD", "FILE", "", load, ref))
        proxy(_directive("ADD", "IND", "CLASS", ["ind_1", "Class_1"], ref))
        query = _directive("QUERY", "IND", "CLASS", ["Class_1"], ref)
        times = []
        for _ in range(calls):
            started = time.perf_counter()
            proxy(query)
            times.append(time.perf_counter() - started)
        proxy.close()
        how = "one connection" if persistent else "a connection per call (armor_py_api)"
        print(f"round trip, QUERY IND CLASS, {how}: {_ms(times)} over {calls} calls")


def master_lookups(calls: int) -> None:
    """What a call without a persistent connection asks the master first (rosmaster's time)."""
    master = rospy.core.xmlrpcapi(os.environ["ROS_MASTER_URI"])
    times = []
    for _ in range(calls):
        started = time.perf_counter()
        master.lookupService("/bench", "/armor_interface_srv")
        times.append(time.perf_counter() - started)
    print(f"of which the master's lookupService (rosmaster, rospy's connection): {_ms(times)}")


def long_list(length: int, runs: int = 3) -> None:
    srv = armor_msgs().srv
    proxy = rospy.ServiceProxy("/armor_interface_serialized_srv", srv.ArmorDirectiveList)
    times = []
    for _ in range(runs):
        ref = "ref_" + uuid.uuid4().hex[:8]
        load = ["", f"http://ex.org/{ref}", "false", "PELLET", "true"]
        requests = [_directive("LOAD", "FILE", "", load, ref)] + [
            _directive("ADD", "IND", "CLASS", [f"ind_{i}", f"Class_{i % 10}"], ref)
            for i in range(length - 1)
        ]
        started = time.perf_counter()
        result = proxy(requests)
        times.append(time.perf_counter() - started)
        assert result.success, "the list failed"
    print(
        f"a {length}-directive list (LOAD FILE, ADD IND CLASS...): median "
        f"{statistics.median(times):.3f} s over {runs} runs"
    )


def _cloud(points: np.ndarray, stamp: float) -> object:
    message = sensor_msgs.msg.PointCloud2()
    message.header.stamp = rospy.Time.from_sec(stamp)
    message.header.frame_id = "camera"
    message.height, message.width = 480, 640
    message.fields = [
        sensor_msgs.msg.PointField(name, 4 * i, sensor_msgs.msg.PointField.FLOAT32, 1)
        for i, name in enumerate("xyz")
    ]
    message.is_bigendian, message.point_step, message.row_step = False, 12, 12 * 640
    message.is_dense = False
    message.data = points.astype("<f4").tobytes()
    return message


def perception(node: RunningNode, seconds: float, rate_hz: float) -> None:
    camera = DepthCamera()
    scene = TabletopScene(
        (
            TruthObject("Sphere", (-0.15, 0.0, 0.0), radius=0.05, height=0.1),
            TruthObject("Cylinder", (0.15, 0.05, 0.0), radius=0.04, height=0.15),
        )
    )
    shot = camera.shoot(scene, np.random.default_rng(1))
    # an organised 640 x 480 cloud: NaN where the camera saw nothing
    organised = np.full((480 * 640, 3), np.nan)
    organised[shot.frame.pixels] = shot.frame.points
    publisher = rospy.Publisher(CLOUD_TOPIC, sensor_msgs.msg.PointCloud2, queue_size=1)
    while publisher.get_num_connections() == 0:
        time.sleep(0.05)
    assert node.perception is not None
    counts = node.perception.counts
    period = 1.0 / rate_hz
    started = time.monotonic()
    sent = 0
    while time.monotonic() - started < seconds:
        publisher.publish(_cloud(organised, time.time()))
        sent += 1
        time.sleep(max(0.0, started + sent * period - time.monotonic()))
    time.sleep(1.0)
    durations = list(node.perception.durations_s)
    print(
        f"PointCloud2 640x480 at {rate_hz:g} Hz for {seconds:g} s: {sent} sent, "
        f"{counts.received} received, {counts.perceived} perceived, {counts.skipped} skipped "
        f"(replaced by a newer cloud), {counts.scenes} scene(s) stored; perception "
        f"{_ms(durations)} a cloud; backlog at most 1 cloud"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--calls", type=int, default=1000)
    parser.add_argument("--list-length", type=int, default=1000)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--rate", type=float, default=5.0)
    args = parser.parse_args()
    home = Path(tempfile.mkdtemp(prefix="engram-bench-ros-"))
    os.environ["ROS_HOME"] = str(home)
    with master(home) as running:
        os.environ["ROS_MASTER_URI"] = running.uri
        memory = open_memory(Settings(data_dir=home / "data"), create=True)
        pose = DepthCamera().world_from_camera
        options = RosOptions(
            node_name="engram_bench", cloud_topic=CLOUD_TOPIC, world_from_sensor=pose
        )
        node = RunningNode(memory.engine, options, signals=False)
        rospy.wait_for_service("/armor_interface_srv", 30)
        try:
            round_trips(args.calls)
            master_lookups(args.calls)
            long_list(args.list_length)
            perception(node, args.seconds, args.rate)
        finally:
            node.stop()
            memory.close()


if __name__ == "__main__":
    main()
