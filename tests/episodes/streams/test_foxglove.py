"""Stored scenes written as a foxglove.SceneUpdate channel when their episode ends, read back
with the ``mcap`` library."""

import datetime as dt
import json
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from pyoxigraph import NamedNode

from episodes import EpisodeMemory
from episodes.scene_channel import scene_mcap_path
from episodes.streams.foxglove import SCENE_TOPIC, SCHEMA_NAME, _rotation_from_z
from kg import Store
from reasoners.memory import SceneMemory
from reasoners.primitives import Primitive

START = dt.datetime(2026, 1, 26, 8, 0, tzinfo=dt.UTC)
BALL = Primitive("ball", "Sphere", centre=(-0.2, 0.0, 0.05), radius=0.05, colour=(1, 0.8, 0))
CAN = Primitive(
    "can", "Cylinder", centre=(0.1, 0.0, 0.07), axis=(0, 0, 1), radius=0.04, height=0.14
)
CONE = Primitive("cone", "Cone", centre=(0.0, 0.2, 0.06), axis=(1, 0, 0), radius=0.05, height=0.1)


def _rotate(q: dict[str, float], v: np.ndarray) -> np.ndarray:
    u, w = np.array([q["x"], q["y"], q["z"]]), q["w"]
    return v + 2 * np.cross(u, np.cross(u, v) + w * v)


@pytest.mark.parametrize("axis", [(0, 0, 1), (1, 0, 0), (0, 1, 0), (0.6, 0, 0.8), (0, 0, -1)])
def test_the_orientation_turns_z_onto_the_axis(axis: tuple[float, float, float]) -> None:
    turned = _rotate(_rotation_from_z(axis), np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(turned, np.array(axis) / np.linalg.norm(axis), atol=1e-9)


def test_an_ended_episode_has_its_scenes_as_a_scene_update_channel(tmp_path: Path) -> None:
    now = [START]
    store = Store()
    memory = SceneMemory(store, clock=lambda: now[0])
    episodes = EpisodeMemory(store, data_dir=tmp_path, clock=lambda: now[0])
    episode = episodes.begin("tidying", episode_id="tidy-1")
    memory.store_scene([BALL, CAN], episode=NamedNode(episode.iri))
    now[0] = START + dt.timedelta(minutes=1)
    memory.store_scene([BALL, CAN, CONE], episode=NamedNode(episode.iri))
    episodes.end(episode.id)

    with scene_mcap_path(tmp_path, "tidy-1").open("rb") as stream:
        read = list(make_reader(stream).iter_messages())
    assert [channel.topic for _, channel, _ in read] == [SCENE_TOPIC, SCENE_TOPIC]
    schema, channel, first = read[0]
    assert (schema.name, schema.encoding, channel.message_encoding) == (
        SCHEMA_NAME,
        "jsonschema",
        "json",
    )
    assert json.loads(schema.data)["title"] == "foxglove.SceneUpdate"
    assert first.log_time == int(START.timestamp() * 1e9)
    entity = json.loads(read[1][2].data)["entities"][0]
    assert entity["frame_id"] == "world" and entity["id"] == "experience-2"
    sphere = entity["spheres"][0]
    assert sphere["pose"]["position"] == {"x": -0.2, "y": 0.0, "z": 0.05}
    assert sphere["size"] == {"x": 0.1, "y": 0.1, "z": 0.1}
    assert sphere["color"] == {"r": 1.0, "g": 0.8, "b": 0.0, "a": 1.0}
    can, cone = entity["cylinders"]
    assert can["size"] == {"x": 0.08, "y": 0.08, "z": 0.14} and can["top_scale"] == 1.0
    assert cone["top_scale"] == 0.0
    assert sorted(t["text"] for t in entity["texts"]) == ["ball", "can", "cone"]


def test_an_episode_without_scenes_writes_no_file(tmp_path: Path) -> None:
    episodes = EpisodeMemory(Store(), data_dir=tmp_path, clock=lambda: START)
    episodes.end(episodes.begin("babbling", episode_id="b-1").id)
    assert not scene_mcap_path(tmp_path, "b-1").exists()
