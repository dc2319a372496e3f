"""Stored scenes written as a Foxglove SceneUpdate channel into the episode's own rosbag2 MCAP
when it ends: the ``mcap`` library reads the channel, ``rosbags`` still reads the bag (and
decodes the scenes from the definitions the file carries), replay is unchanged."""

import datetime as dt
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mcap.reader import make_reader
from pyoxigraph import NamedNode
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from episodes import EpisodeMemory
from episodes.scene_channel import scene_bag_path
from episodes.streams import Recorder, Replayer
from episodes.streams.bagwrite import mcap_file
from episodes.streams.foxglove import (
    SCENE_TOPIC,
    SCENE_TYPE,
    _rotation_from_z,
    add_scene_channel,
    scene_entity,
    scene_message,
)
from episodes.streams.mcapread import McapFile
from kg import Store
from kg.primitive import Primitive
from reasoners.memory import SceneMemory

START = dt.datetime(2026, 1, 26, 8, 0, tzinfo=dt.UTC)
T0 = int(START.timestamp() * 1e9)
BALL = Primitive("ball", "Sphere", centre=(-0.2, 0.0, 0.05), radius=0.05, colour=(1, 0.8, 0))
CAN = Primitive(
    "can", "Cylinder", centre=(0.1, 0.0, 0.07), axis=(0, 0, 1), radius=0.04, height=0.14
)
CONE = Primitive("cone", "Cone", centre=(0.0, 0.2, 0.06), axis=(1, 0, 0), radius=0.05, height=0.1)


def _rotate(q: dict[str, float], v: np.ndarray) -> np.ndarray:
    u, w = np.array([q["x"], q["y"], q["z"]]), q["w"]
    turned: np.ndarray = v + 2 * np.cross(u, np.cross(u, v) + w * v)
    return turned


@pytest.mark.parametrize("axis", [(0, 0, 1), (1, 0, 0), (0, 1, 0), (0.6, 0, 0.8), (0, 0, -1)])
def test_the_orientation_turns_z_onto_the_axis(axis: tuple[float, float, float]) -> None:
    turned = _rotate(_rotation_from_z(axis), np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(turned, np.array(axis) / np.linalg.norm(axis), atol=1e-9)


def _two_scenes(tmp_path: Path, *, record: bool) -> tuple[EpisodeMemory, str]:
    now = [START]
    store = Store()
    memory = SceneMemory(store, clock=lambda: now[0])
    episodes = EpisodeMemory(store, data_dir=tmp_path, clock=lambda: now[0])
    episode = episodes.begin("tidying", episode_id="tidy-1", record=record)
    if record:
        recorder = episodes.streams.recordings.get(episode.id)
        recorder.add_provider("head", "joint_state", names=["neck", "eyes"])
        for i in range(5):
            recorder.tick({"head": [0.1 * i, 0.2]}, time_ns=int(START.timestamp() * 1e9) + i)
    memory.store_scene([BALL, CAN], episode=NamedNode(episode.iri))
    now[0] = START + dt.timedelta(minutes=1)
    memory.store_scene([BALL, CAN, CONE], episode=NamedNode(episode.iri))
    episodes.end(episode.id)
    return episodes, episode.id


def _mcap_scenes(file: Path) -> list[tuple[Any, Any, Any]]:
    with file.open("rb") as stream:
        return [m for m in make_reader(stream).iter_messages() if m[1].topic == SCENE_TOPIC]


def _decode_with_the_file_s_definition(schema: Any, data: bytes) -> Any:
    """Decode as a tool that knows nothing of Foxglove would: from the schema in the file."""
    store = get_typestore(Stores.EMPTY)
    text = schema.data.decode()
    parts = text.split("=" * 80 + "\n")
    types = get_types_from_msg(parts[0], SCENE_TYPE)
    for part in parts[1:]:
        header, _, body = part.partition("\n")
        name = header.removeprefix("MSG: ")
        types.update(get_types_from_msg(body, name.replace("/", "/msg/", 1)))
    store.register(types)
    return store.deserialize_cdr(data, SCENE_TYPE)


@pytest.mark.parametrize("record", [False, True], ids=["no streams", "recorded streams"])
def test_the_episode_mcap_holds_its_scenes_as_a_scene_update_channel(
    tmp_path: Path, record: bool
) -> None:
    _two_scenes(tmp_path, record=record)
    file = mcap_file(scene_bag_path(tmp_path, "tidy-1"))

    read = _mcap_scenes(file)
    assert len(read) == 2
    schema, channel, first = read[0]
    assert (schema.name, schema.encoding, channel.message_encoding) == (
        SCENE_TYPE,
        "ros2msg",
        "cdr",
    )
    assert first.log_time == int(START.timestamp() * 1e9)
    update = _decode_with_the_file_s_definition(schema, read[1][2].data)
    entity = update.entities[0]
    assert (entity.frame_id, entity.id, entity.timestamp.sec) == (
        "world",
        "experience-2",
        int(START.timestamp()) + 60,
    )
    sphere = entity.spheres[0]
    assert (sphere.pose.position.x, sphere.pose.position.z) == (-0.2, 0.05)
    assert (sphere.size.x, sphere.color.r, sphere.color.g) == (0.1, 1.0, 0.8)
    can, cone = entity.cylinders
    assert (can.size.x, can.size.z, can.top_scale, cone.top_scale) == (0.08, 0.14, 1.0, 0.0)
    assert sorted(t.text for t in entity.texts) == ["ball", "can", "cone"]


def test_the_bag_stays_a_rosbag2_recording_that_rosbags_and_replay_read(tmp_path: Path) -> None:
    _two_scenes(tmp_path, record=True)
    bag = scene_bag_path(tmp_path, "tidy-1")

    with AnyReader([bag]) as reader:
        topics = {c.topic: c for c in reader.connections}
        assert topics[SCENE_TOPIC].msgtype == SCENE_TYPE
        assert topics[SCENE_TOPIC].msgcount == 2 and topics["/head"].msgcount == 5
        scenes: list[Any] = [
            reader.deserialize(raw, c.msgtype)
            for c, _, raw in reader.messages(connections=[topics[SCENE_TOPIC]])
        ]
        assert [s.entities[0].id for s in scenes] == ["experience-1", "experience-2"]
        assert reader.message_count == 2 + 5 + 5 + 1 + 1  # scenes, samples, ticks, records

    replayer = Replayer(bag)
    assert replayer.episode_id == "tidy-1" and replayer.complete
    values = [f.samples["head"].value for f in replayer.frames()]
    np.testing.assert_allclose([v["position"][0] for v in values], [0.0, 0.1, 0.2, 0.3, 0.4])


def test_an_episode_without_scenes_gets_no_scene_channel(tmp_path: Path) -> None:
    episodes = EpisodeMemory(Store(), data_dir=tmp_path, clock=lambda: START)
    episodes.end(episodes.begin("babbling", episode_id="b-1").id)
    assert not scene_bag_path(tmp_path, "b-1").exists()


def test_a_zstd_recording_keeps_its_compression_and_gains_the_channel(tmp_path: Path) -> None:
    bag = tmp_path / "ep"
    recorder = Recorder(bag, episode_id="ep", compression="zstd")
    recorder.add_provider("head", "joint_state", names=["neck"])
    for i in range(20):
        recorder.tick({"head": [0.01 * i]}, time_ns=T0 + i * 10_000_000)
    recorder.close()
    ball = Primitive("ball", "Sphere", centre=(0.0, 0.0, 0.05), radius=0.05)
    update = scene_message(scene_entity("experience-1", [ball], time_ns=T0 + 5))
    add_scene_channel(bag, [(T0 + 5, update)], episode_id="ep")

    with mcap_file(bag).open("rb") as stream:
        reader = make_reader(stream)
        summary = reader.get_summary()
        assert summary is not None
        assert {c.compression for c in summary.chunk_indexes} == {"zstd"}
        topics = [c.topic for _, c, _ in reader.iter_messages()]
    assert topics.count(SCENE_TOPIC) == 1 and topics.count("/head") == 20
    with AnyReader([bag]) as rosbag:
        assert {c.topic for c in rosbag.connections} >= {SCENE_TOPIC, "/head"}
    assert Replayer(bag).frame_count == 20


def test_scenes_go_among_the_samples_so_log_times_never_go_backwards(tmp_path: Path) -> None:
    bag = tmp_path / "ep"
    recorder = Recorder(bag, episode_id="ep")
    recorder.add_provider("head", "joint_state", names=["neck"])
    for i in range(20):
        recorder.tick({"head": [0.01 * i]}, time_ns=T0 + i * 10_000_000)
    recorder.close()
    ball = Primitive("ball", "Sphere", centre=(0.0, 0.0, 0.05), radius=0.05)
    times = [T0 + 35_000_000, T0 + 120_000_000, T0 + 500_000_000]  # the last after every tick
    updates = [(t, scene_message(scene_entity("s", [ball], time_ns=t))) for t in times]
    add_scene_channel(bag, updates, episode_id="ep")

    in_file_order = [(m.topic, m.log_time) for m in McapFile.open(mcap_file(bag)).messages()]
    logged = [t for _, t in in_file_order]
    assert logged == sorted(logged)
    assert [t for topic, t in in_file_order if topic == SCENE_TOPIC] == times
    assert Replayer(bag).frame_count == 20
