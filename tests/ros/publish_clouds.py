"""A test node: publishes the clouds of an .npz file as sensor_msgs/PointCloud2 at a rate, and
prints (one JSON line each) the answers engram publishes on the result topic.

    python publish_clouds.py CLOUDS.npz TOPIC RESULT_TOPIC RATE_HZ WAIT_S

CLOUDS.npz holds ``points_<i>`` (N x 3, the sensor frame) and ``colours_<i>`` (N x 3 in [0, 1]).
"""

import json
import sys
import threading
import time

import numpy as np

from api.ros.system import load_ros

load_ros()

import rospy  # noqa: E402
from sensor_msgs.msg import PointCloud2, PointField  # noqa: E402

from api.ros.convert import response_of  # noqa: E402
from api.ros.messages import armor_msgs  # noqa: E402


def cloud(points: np.ndarray, colours: np.ndarray, stamp: float) -> PointCloud2:
    """An unorganised cloud of x, y, z float32 and packed rgb (float32), 16 bytes a point."""
    data = np.zeros((len(points), 4), dtype="<f4")
    data[:, :3] = points
    rgb = np.round(colours * 255).astype(np.uint32)
    data[:, 3] = ((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2]).view("<f4")
    message = PointCloud2()
    message.header.stamp = rospy.Time.from_sec(stamp)
    message.header.frame_id = "camera"
    message.height, message.width = 1, len(points)
    message.fields = [
        PointField(name, 4 * i, PointField.FLOAT32, 1) for i, name in enumerate("xyz")
    ] + [PointField("rgb", 12, PointField.FLOAT32, 1)]
    message.is_bigendian, message.point_step = False, 16
    message.row_step, message.is_dense = 16 * len(points), True
    message.data = data.tobytes()
    return message


def main() -> None:
    path, topic, result_topic, rate_hz, wait_s = sys.argv[1:6]
    clouds = np.load(path)
    count = len([k for k in clouds.files if k.startswith("points_")])
    rospy.init_node("cloud_publisher", anonymous=True, disable_signals=True)
    answers: list[dict[str, object]] = []
    got = threading.Event()

    def received(message: object) -> None:
        answers.append(response_of(message).model_dump())
        got.set()

    rospy.Subscriber(result_topic, armor_msgs().msg.ArmorDirectiveRes, received)
    publisher = rospy.Publisher(topic, PointCloud2, queue_size=2)
    deadline = time.monotonic() + 20
    while publisher.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    period = 1.0 / float(rate_hz)
    index = 0
    end = time.monotonic() + float(wait_s)
    while not got.is_set() and time.monotonic() < end:
        i = index % count
        publisher.publish(cloud(clouds[f"points_{i}"], clouds[f"colours_{i}"], float(index)))
        index += 1
        time.sleep(period)
    got.wait(max(0.0, end - time.monotonic()))
    for answer in answers:
        print(json.dumps(answer))
    print(json.dumps({"published": index}))
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
