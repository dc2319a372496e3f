"""Bags in and out: standalone export read back by rosbags, import of ROS 1 and ROS 2 bags."""

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

from episodes.streams import (
    CorruptRecordingError,
    RecordingStateError,
    Replayer,
    export_bag,
    import_bag,
)

Recorded = tuple[Path, list[dict[str, Any]], list[int]]
T0 = 1_600_000_000_000_000_000


def test_export_is_a_standalone_bag_with_standard_types(
    recorded: Recorded, tmp_path: Path, same: Callable[..., None]
) -> None:
    path, sent, times = recorded
    out = tmp_path / "exported"
    export_bag(path, out)
    with AnyReader([out]) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        skin = [
            (t, reader.deserialize(raw, c.msgtype))
            for c, t, raw in reader.messages()
            if c.topic == "/icub/skin/torso"
        ]
        total = sum(1 for _ in reader.messages())
    assert types["/icub/skin/torso"] == "std_msgs/msg/Float64MultiArray"  # dense again
    assert types["/icub/cam/left"] == "sensor_msgs/msg/Image"
    assert types["/icub/head"] == "sensor_msgs/msg/JointState"
    assert [t for t, _ in skin] == times  # every sample, also those at the baseline
    for (_, msg), samples in zip(skin, sent, strict=True):
        assert np.asarray(msg.data).tobytes() == samples["icub/skin/torso"].tobytes()
    assert total == 30 * 7 + 30 + 7 + 1  # samples, ticks, providers, recording record
    for frame, samples in zip(Replayer(out).frames(), sent, strict=True):
        for name, value in samples.items():
            same(name, frame.samples[name].value, value)
    with pytest.raises(RecordingStateError, match="exists already"):
        export_bag(path, out)


def _ros_messages(typestore: Any, ros1: bool) -> list[tuple[str, str, int, Any]]:
    types = typestore.types
    time_cls = types["builtin_interfaces/msg/Time"]

    def header(ns: int) -> Any:
        stamp = time_cls(sec=ns // 10**9, nanosec=ns % 10**9)
        if ros1:
            return types["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id="base")
        return types["std_msgs/msg/Header"](stamp=stamp, frame_id="base")

    out = []
    for i in range(5):
        t = T0 + i * 20_000_000
        joints = types["sensor_msgs/msg/JointState"](
            header=header(t - 1_000),
            name=["j1", "j2"],
            position=np.array([i, -i], dtype=np.float64),
            velocity=np.array([], dtype=np.float64),
            effort=np.array([], dtype=np.float64),
        )
        out.append(("/robot/joint_states", "sensor_msgs/msg/JointState", t, joints))
        img = np.full((2, 3, 3), i, dtype=np.uint8)
        image = types["sensor_msgs/msg/Image"](
            header=header(t - 2_000),
            height=2,
            width=3,
            encoding="rgb8",
            is_bigendian=0,
            step=9,
            data=img.reshape(-1),
        )
        out.append(("/cameras/head_camera/image", "sensor_msgs/msg/Image", t, image))
        if i % 2 == 0:
            text = types["std_msgs/msg/String"](data=f"said {i}")
            out.append(("/speech", "std_msgs/msg/String", t + 5_000_000, text))
        pose = types["geometry_msgs/msg/Point"](x=1.0, y=2.0, z=float(i))
        out.append(("/tf_like", "geometry_msgs/msg/Point", t + 7_000_000, pose))
    return out


def _check_imported(result: Any, dest: Path) -> None:
    assert result.skipped == {"/tf_like": {"message_type": "geometry_msgs/msg/Point", "count": 5}}
    counts = {s.provider: s.count_stored for s in result.channels}
    assert counts == {"robot/joint_states": 5, "cameras/head_camera/image": 5, "speech": 3}
    frames = list(Replayer(dest).frames())
    joints = [f.samples["robot/joint_states"] for f in frames if "robot/joint_states" in f.samples]
    assert [j.time_ns for j in joints] == [T0 + i * 20_000_000 for i in range(5)]  # times kept
    assert [j.stamp_ns for j in joints] == [T0 + i * 20_000_000 - 1_000 for i in range(5)]
    assert [j.value["position"].tolist() for j in joints] == [[i, -i] for i in range(5)]
    first = frames[0].samples
    assert set(first) == {"robot/joint_states", "cameras/head_camera/image"}  # same time, tick
    assert first["cameras/head_camera/image"].value.tobytes() == bytes(18)
    speech = [f.samples["speech"].value for f in frames if "speech" in f.samples]
    assert speech == ["said 0", "said 2", "said 4"]
    assert result.start_ns == T0


def test_import_of_a_ros2_bag_keeps_channels_and_times(tmp_path: Path) -> None:
    store = get_typestore(Stores.ROS2_HUMBLE)
    src = tmp_path / "ros2bag"
    with Ros2Writer(src, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        conns: dict[str, Any] = {}
        for topic, msgtype, t, msg in _ros_messages(store, ros1=False):
            if topic not in conns:
                conns[topic] = writer.add_connection(topic, msgtype, typestore=store)
            writer.write(conns[topic], t, store.serialize_cdr(msg, msgtype))
    result = import_bag(src, dest=tmp_path / "ep-2", episode_id="ep-2")
    _check_imported(result, tmp_path / "ep-2")


def test_import_of_a_ros1_bag_keeps_channels_and_times(tmp_path: Path) -> None:
    store = get_typestore(Stores.ROS1_NOETIC)
    src = tmp_path / "old.bag"
    with Ros1Writer(src) as writer:
        conns: dict[str, Any] = {}
        for topic, msgtype, t, msg in _ros_messages(store, ros1=True):
            if topic not in conns:
                conns[topic] = writer.add_connection(topic, msgtype, typestore=store)
            writer.write(conns[topic], t, store.serialize_ros1(msg, msgtype))
    result = import_bag(src, dest=tmp_path / "ep-1", episode_id="ep-1")
    _check_imported(result, tmp_path / "ep-1")
    assert Replayer(tmp_path / "ep-1").episode_id == "ep-1"


def test_import_refuses_what_is_not_a_bag(tmp_path: Path) -> None:
    junk = tmp_path / "junk.bag"
    junk.write_bytes(b"this is no bag")
    with pytest.raises(CorruptRecordingError, match="not a readable bag"):
        import_bag(junk, dest=tmp_path / "ep", episode_id="ep")
    assert not (tmp_path / "ep").exists()
