"""Import of ROS 2 and ROS 1 bags as finished episodes: channels mapped, times kept."""

import datetime as dt
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

from episodes import ArgumentSpec, Cue, EpisodeMemory
from episodes.bag_limits import DamagedBagError
from episodes.streams import Replayer
from tests.conftest import LiveServer

T0 = 1_769_441_400_000_000_000  # 2026-01-26T15:30:00Z


def _joint_messages(store: Any, ros1: bool) -> list[tuple[str, str, int, Any]]:
    types = store.types
    out = []
    for i in range(4):
        t = T0 + i * 50_000_000
        stamp = types["builtin_interfaces/msg/Time"](sec=t // 10**9, nanosec=t % 10**9)
        header = (
            types["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id="base")
            if ros1
            else types["std_msgs/msg/Header"](stamp=stamp, frame_id="base")
        )
        joints = types["sensor_msgs/msg/JointState"](
            header=header,
            name=["neck", "eyes"],
            position=np.array([0.1 * i, -0.1 * i]),
            velocity=np.array([], dtype=np.float64),
            effort=np.array([], dtype=np.float64),
        )
        out.append(("/nao/joint_states", "sensor_msgs/msg/JointState", t, joints))
    return out


def write_ros2_bag(path: Path) -> Path:
    store = get_typestore(Stores.ROS2_HUMBLE)
    with Ros2Writer(path, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        connection = None
        for topic, msgtype, t, msg in _joint_messages(store, ros1=False):
            connection = connection or writer.add_connection(topic, msgtype, typestore=store)
            writer.write(connection, t, store.serialize_cdr(msg, msgtype))
    return path


def write_ros1_bag(path: Path) -> Path:
    store = get_typestore(Stores.ROS1_NOETIC)
    with Ros1Writer(path) as writer:
        connection = None
        for topic, msgtype, t, msg in _joint_messages(store, ros1=True):
            connection = connection or writer.add_connection(topic, msgtype, typestore=store)
            writer.write(connection, t, store.serialize_ros1(msg, msgtype))
    return path


@pytest.mark.parametrize("write", [write_ros2_bag, write_ros1_bag], ids=["ros2", "ros1"])
def test_a_bag_becomes_a_finished_episode_with_its_times_and_streams(
    disk_memory: EpisodeMemory, tmp_path: Path, write: Any
) -> None:
    bag = write(tmp_path / ("nao.bag" if write is write_ros1_bag else "nao"))
    episode = disk_memory.imports.bag(
        bag, "wave", activity_type="action", arguments=[ArgumentSpec("agent", "NAO")]
    )
    assert episode.begin == dt.datetime(2026, 1, 26, 15, 30, tzinfo=dt.UTC)
    assert episode.end == episode.begin + dt.timedelta(milliseconds=150)
    assert [(s.provider, s.count, s.dropped) for s in episode.streams] == [
        ("nao/joint_states", 4, 0)
    ]
    assert episode.state_at_begin is None
    assert episode.annotations[0].key == "imported_from"
    assert disk_memory.recall(Cue("wave", agent="NAO"), which="first").episode.id == episode.id
    frames = list(Replayer(disk_memory.streams.path(episode.id)).frames())
    assert [f.time_ns for f in frames] == [T0 + i * 50_000_000 for i in range(4)]


def test_a_file_that_is_not_a_bag_leaves_nothing_behind(
    disk_memory: EpisodeMemory, tmp_path: Path
) -> None:
    junk = tmp_path / "junk.bag"
    junk.write_bytes(b"not a bag")
    before = len(disk_memory.store)
    with pytest.raises(DamagedBagError, match=r"junk\.bag"):
        disk_memory.imports.bag(junk, "wave", episode_id="j1")
    assert len(disk_memory.store) == before
    assert not disk_memory.streams.path("j1").exists()


def test_import_over_http(live_server: LiveServer, tmp_path: Path) -> None:
    bag = write_ros2_bag(live_server.settings.data_dir / "bags" / "nao")
    answer = live_server.client.post(
        "/episodes/import", json={"path": str(bag), "activity": "wave", "id": "nao1"}
    )
    assert answer.status_code == 201, answer.text
    assert answer.json()["streams"][0]["count"] == 4
    missing = live_server.client.post(
        "/episodes/import", json={"path": "bags/none", "activity": "wave"}
    )
    assert missing.status_code == 404
