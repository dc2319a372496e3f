"""No dangling link, no silent loss: what the autobiographical memory refuses and reports
(issue 12 item 6, issue 16 item 4)."""

import io
import tarfile
from pathlib import Path
from typing import Any

import pytest
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore
from typer.testing import CliRunner

from api.cli import app as cli
from episodes import DerivedSpec, EpisodeMemory, InvalidInputError
from ontologies.vocab import EPISODIC, HAPPENED_DURING, engram
from tests.conftest import LiveServer
from tests.episodes.conftest import record_frames, store_experienced_scene
from tests.episodes.test_import import write_ros1_bag, write_ros2_bag
from tests.episodes.test_routes import store_scene_over_http


def test_a_scene_not_stored_yet_cannot_be_linked(memory: EpisodeMemory) -> None:
    memory.begin("point", episode_id="ep2")
    before = len(memory.store)
    with pytest.raises(InvalidInputError) as caught:
        memory.link_scene("ep2", engram("scene-99").value)
    assert caught.value.field == "scene" and "stored" in caught.value.expected
    assert len(memory.store) == before
    memory.link_scene("ep2", store_experienced_scene(memory.store, "scene-99"))
    assert list(memory.store.quads(engram("scene-99"), HAPPENED_DURING, None, EPISODIC))


def test_http_scene_link_names_only_stored_scenes(live_server: LiveServer) -> None:
    client = live_server.client
    assert client.post("/episodes", json={"activity": "point", "id": "ep2"}).status_code == 201
    future = "https://w3id.org/engram/ontology#Scene-1-item-1"
    answer = client.post("/episodes/ep2/scenes", json={"scene": future})
    assert answer.status_code == 422, answer.text
    assert answer.json()["field"] == "scene" and answer.json()["value"] == future
    stored = store_scene_over_http(client)
    assert client.get("/episodes/ep2").json()["scenes"] == []  # the next scene is not ep2's
    assert client.post("/episodes/ep2/scenes", json={"scene": stored}).status_code == 204
    assert client.get("/episodes/ep2").json()["scenes"] == [stored]


def test_streams_need_an_existing_running_episode(live_server: LiveServer) -> None:
    client = live_server.client
    answer = client.post("/episodes/nope/streams")
    assert answer.status_code == 404 and "nope" in answer.json()["detail"]
    assert not (live_server.settings.data_dir / "streams" / "nope").exists()
    client.post("/episodes", json={"activity": "wave", "id": "done"})
    client.post("/episodes/done/end", json={})
    assert client.post("/episodes/done/streams").status_code == 409
    client.post("/episodes", json={"activity": "wave", "id": "live"})
    assert client.post("/episodes/live/streams").status_code == 201


@pytest.mark.parametrize(
    ("path", "code"),
    [
        ("", 422),
        ("   ", 422),
        (".", 422),
        ("streams", 422),  # a directory, but not a bag
        ("../outside", 422),
        ("/etc", 422),
        ("no-such-bag", 404),
    ],
)
def test_import_refuses_paths_that_are_not_bags_in_the_data_directory(
    live_server: LiveServer, path: str, code: int
) -> None:
    (live_server.settings.data_dir / "streams").mkdir(parents=True, exist_ok=True)
    answer = live_server.client.post("/episodes/import", json={"path": path, "activity": "wave"})
    assert answer.status_code == code, answer.text
    if code == 422:
        assert answer.json()["field"] == "path" and "data directory" in answer.json()["expected"]
    assert live_server.client.get("/episodes", params={"activity": "wave"}).json() == []


def write_bag_with_an_unsupported_topic(path: Path) -> Path:
    """A ROS 2 bag: three twists (no channel kind for them) and one string."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = store.types
    with Ros2Writer(path, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        said = writer.add_connection("/said", "std_msgs/msg/String", typestore=store)
        moved = writer.add_connection("/cmd_vel", "geometry_msgs/msg/Twist", typestore=store)
        vector = types["geometry_msgs/msg/Vector3"]
        twist = types["geometry_msgs/msg/Twist"](linear=vector(1, 0, 0), angular=vector(0, 0, 0))
        for i in range(3):
            writer.write(moved, 10**18 + i, store.serialize_cdr(twist, "geometry_msgs/msg/Twist"))
        hello = types["std_msgs/msg/String"](data="hello")
        writer.write(said, 10**18 + 5, store.serialize_cdr(hello, "std_msgs/msg/String"))
    return path


SKIPPED = [{"topic": "/cmd_vel", "message_type": "geometry_msgs/msg/Twist", "count": 3}]


def test_import_reports_skipped_topics_over_http(live_server: LiveServer) -> None:
    write_bag_with_an_unsupported_topic(live_server.settings.data_dir / "bags" / "drive")
    answer = live_server.client.post(
        "/episodes/import", json={"path": "bags/drive", "activity": "drive", "id": "d1"}
    )
    assert answer.status_code == 201, answer.text
    assert answer.json()["skipped"] == SKIPPED
    assert [s["provider"] for s in answer.json()["streams"]] == ["said"]
    notes = {a["key"]: a["value"] for a in answer.json()["annotations"]}
    assert notes["skipped_topic"] == "/cmd_vel geometry_msgs/msg/Twist x3"


def test_import_reports_skipped_topics_on_the_command_line(tmp_path: Path) -> None:
    bag = write_bag_with_an_unsupported_topic(tmp_path / "drive")
    data = ["--data", str(tmp_path / "data")]
    assert CliRunner().invoke(cli, ["init", *data]).exit_code == 0
    result = CliRunner().invoke(cli, ["episodes", "import", str(bag), "drive", *data])
    assert result.exit_code == 0, result.output
    assert "skipped /cmd_vel: 3 messages of geometry_msgs/msg/Twist" in result.stderr
    assert '"count": 3' in result.stdout


def _tar_of(directory: Path) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as tar:
        tar.add(directory, arcname=directory.name)
    return buffer.getvalue()


def test_a_bag_can_be_uploaded(live_server: LiveServer, tmp_path: Path) -> None:
    client = live_server.client
    ros1 = write_ros1_bag(tmp_path / "nao.bag").read_bytes()
    ros2 = _tar_of(write_ros2_bag(tmp_path / "nao2"))
    for i, body in enumerate((ros1, ros2)):
        answer = client.post(
            "/episodes/import/upload",
            params={"activity": "wave", "argument": "agent=NAO", "id": f"up{i}"},
            content=body,
        )
        assert answer.status_code == 201, answer.text
        assert answer.json()["streams"][0]["count"] == 4 and answer.json()["skipped"] == []
    assert client.get("/episodes/count", params={"activity": "wave", "agent": "NAO"}).json() == {
        "count": 2
    }
    junk = client.post("/episodes/import/upload", params={"activity": "x"}, content=b"junk")
    assert junk.status_code == 422 and junk.json()["field"] == "body"
    assert not any((live_server.settings.data_dir / "uploads").iterdir())


@pytest.fixture
def recorded(disk_memory: EpisodeMemory) -> tuple[EpisodeMemory, str]:
    """An episode of 100 frames: "left" at every frame, "skin" only at frames 1-10."""
    disk_memory.begin("babbling", episode_id="r1", record=True)
    record_frames(disk_memory, "r1", {"left": range(1, 101), "skin": range(1, 11)})
    disk_memory.end("r1")
    run = disk_memory.runs.start("r1", name="edges", producer="canny")
    return disk_memory, run.id


@pytest.mark.parametrize(
    ("spec", "field", "fragment"),
    [
        (DerivedSpec(999_999, "left", "edges"), "samples[1].frame", "1 to 100"),
        (DerivedSpec(0, "left", "edges"), "samples[1].frame", "1 to 100"),
        (DerivedSpec(50, "skin", "edges"), "samples[1].source_channel", "frame 50"),
        (DerivedSpec(50, "/skin", "edges"), "samples[1].source_channel", "frame 50"),
    ],
)
def test_a_derived_sample_needs_a_recorded_frame_holding_its_source(
    recorded: tuple[EpisodeMemory, str], spec: DerivedSpec, field: str, fragment: str
) -> None:
    memory, run = recorded
    before = len(memory.store)
    with pytest.raises(InvalidInputError) as caught:
        memory.runs.add_derived("r1", run, [DerivedSpec(5, "skin", "edges"), spec])
    assert caught.value.field == field and fragment in caught.value.expected
    assert len(memory.store) == before
    added = memory.runs.add_derived(
        "r1", run, [DerivedSpec(5, "/skin", "e"), DerivedSpec(50, "left", "e")]
    )
    assert [s.frame for s in added] == [5, 50]


def test_an_episode_without_a_recording_takes_no_derived_samples(memory: EpisodeMemory) -> None:
    memory.begin("babbling", episode_id="g1")
    run = memory.runs.start("g1", name="edges", producer="canny")
    with pytest.raises(InvalidInputError) as caught:
        memory.runs.add_derived("g1", run.id, [DerivedSpec(1, "left", "edges")])
    assert "no recording" in caught.value.expected


UNKNOWN_FIELDS: list[tuple[str, str, dict[str, Any]]] = [
    ("post", "/episodes", {"activity": "x", "agent": "HyungJin"}),
    ("post", "/episodes/ep1/end", {"end": None, "at": "now"}),
    ("post", "/episodes/ep1/annotations", {"key": "k", "value": "v", "score": 1}),
    ("post", "/episodes/ep1/scenes", {"scene": "https://x/s", "why": "?"}),
    ("post", "/episodes/ep1/runs", {"name": "e", "producer": "p", "version": 3}),
    ("post", "/episodes/import", {"path": "x", "activity": "y", "force": True}),
    ("post", "/episodes/ep1/streams", {"compression": None, "codec": "lz4"}),
]


@pytest.mark.parametrize(("method", "url", "body"), UNKNOWN_FIELDS)
def test_unknown_fields_are_refused_and_change_nothing(
    live_server: LiveServer, method: str, url: str, body: dict[str, Any]
) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "babbling", "id": "ep1"})
    before = client.get("/episodes/ep1").json()
    answer = client.request(method, url, json=body)
    assert answer.status_code == 422, answer.text
    assert "extra" in answer.text.lower() or "not permitted" in answer.text.lower()
    assert client.get("/episodes/ep1").json() == before


def test_ratings_refuse_unknown_fields_and_keep_the_first_answer(
    recorded: tuple[EpisodeMemory, str], start_server: Any
) -> None:
    memory, run = recorded
    memory.ratings.rate("r1", run, person="Alice", value=8)
    from episodes import EpisodeStateError

    with pytest.raises(EpisodeStateError) as caught:
        memory.ratings.rate("r1", run, person="Alice", value=3)
    assert "already rated" in str(caught.value) and "replace" in str(caught.value)
    assert memory.ratings.rank("edges").candidates[0].ratings == {"Alice": 8}
    memory.ratings.rate("r1", run, person="Alice", value=3, replace=True)
    assert memory.ratings.rank("edges").candidates[0].ratings == {"Alice": 3}


def test_rating_endpoint_refuses_a_second_answer_and_unknown_fields(
    live_server: LiveServer,
) -> None:
    client = live_server.client
    client.post("/episodes", json={"activity": "babbling", "id": "ep1"})
    run = client.post("/episodes/ep1/runs", json={"name": "ks", "producer": "p"}).json()["id"]
    url = f"/episodes/ep1/runs/{run}/ratings"
    typo = client.post(url, json={"person": "A", "value": 7, "questoin": "q1"})
    assert typo.status_code == 422 and "questoin" in typo.text
    assert client.post(url, json={"person": "A", "value": 7}).status_code == 201
    again = client.post(url, json={"person": "A", "value": 2})
    assert again.status_code == 409 and "already rated" in again.json()["detail"]
    ranking = client.get("/augmentations/ks/ranking").json()
    assert ranking["candidates"][0]["ratings"] == {"A": 7}
