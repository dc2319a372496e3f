"""A primitive read back from the store is the one the client sent: over the HTTP API (the
scene views) and through an episode's scene channel (``episodes.scene_channel``)."""

from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from pydantic import TypeAdapter

import episodes.scene_channel
from api.armor import ArmorEngine
from api.client import ArmorClient, LocalTransport, Primitive
from episodes import EpisodeMemory
from kg import Store, ensure_ontology
from reasoners.memory import SceneMemory
from tests.conftest import LiveServer

SENT = [
    Primitive("table", "Plane", centre=(0.3, 0.1, 0.1), axis=(0, 0, 1), hessian=-0.1),
    Primitive(
        "ball", "Sphere", centre=(0.3, 0.3, 0.3), radius=0.05, colour=(1, 0.5, 0), tracking_id=7
    ),
    Primitive(
        "can",
        "Cylinder",
        centre=(0.1, 0.3, 0.2),
        axis=(0, 0, 2),
        radius=0.04,
        height=0.12,
        point_on_axis=(0.1, 0.3, 0.14),
    ),
    Primitive(
        "cone", "Cone", centre=(0.5, 0.3, 0.2), axis=(0, 0, -1), radius=0.03, apex=(0.5, 0.3, 0.3)
    ),
]
PRIMITIVES = TypeAdapter(list[Primitive])


def test_a_scene_read_back_over_http_has_the_primitives_the_client_sent(
    live_server: LiveServer,
) -> None:
    with ArmorClient("camera", "engram", base_url=live_server.url) as client:
        answer = client.memory.store_scene(SENT)
    item = answer.detail("scene_item")
    detail = live_server.client.get(f"/views/scenes/{item}")
    assert detail.status_code == 200
    assert PRIMITIVES.validate_python(detail.json()["primitives"]) == SENT


@pytest.fixture
def drawn(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[list[Any]]]:
    """The primitives of each scene the scene channel draws, as it hands them to Foxglove."""
    scenes: list[list[Any]] = []
    draw = episodes.scene_channel.scene_entity

    def spy(scene_id: str, primitives: Iterable[Any], *, time_ns: int) -> dict[str, Any]:
        scenes.append(list(primitives))
        return draw(scene_id, scenes[-1], time_ns=time_ns)

    monkeypatch.setattr(episodes.scene_channel, "scene_entity", spy)
    yield scenes


def test_the_scene_channel_draws_the_primitives_the_client_sent(
    tmp_path: Path, drawn: list[list[Any]]
) -> None:
    store = Store()
    ensure_ontology(store)
    engine = ArmorEngine(store, scene_memory=SceneMemory(store))
    memory = EpisodeMemory(store, data_dir=tmp_path)
    episode = memory.begin("tidying", episode_id="tidy-1")
    http = httpx.Client(base_url="http://engram.local", transport=LocalTransport(engine))
    with ArmorClient("camera", "engram", http=http) as client:
        client.memory.store_scene(SENT, episode=episode.iri)
    memory.end(episode.id)
    assert drawn == [SENT]
    assert episodes.scene_channel.scene_bag_path(tmp_path, "tidy-1").exists()
