"""The perception client and the demo: point clouds in, scenes in the memory, results out."""

import gc
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import open3d as o3d
import pytest
import rdflib
from mcap.reader import make_reader
from typer.testing import CliRunner

from api.cli import app
from api.client import ArmorClient
from api.config import Settings
from api.demo import SCENES
from api.main import create_app
from api.perceive import PerceiveExit, perceive
from api.summary import memory_sizes
from episodes.streams.foxglove import SCENE_TOPIC, SCENE_TYPE, scene_typestore
from kg import Store
from shapes import Frame
from shapes.bags import write_bag
from shapes.sensor import DepthCamera
from shapes.synthetic import TabletopScene, TruthObject
from tests.conftest import LiveServer, free_port, serve

runner = CliRunner()
QUERY_EXAMPLES = Path(__file__).parents[2] / "api" / "web" / "query-examples.json"


def memory_in(data: Path) -> Path:
    """``data`` with an empty memory in it, as ``engram init`` makes one."""
    made = runner.invoke(app, ["init", "--data", str(data)])
    assert made.exit_code == 0, made.output
    return data


def _world_frames(title: str | None, count: int, seed: int = 0) -> list[Frame]:
    """Frames of a demo scene (None: the empty table) with points in the world frame, as a bag
    without tf would hold them."""
    rng = np.random.default_rng(seed)
    scene = SCENES[title] if title else TabletopScene(())
    frames = []
    for index in range(count):
        frame = scene.render(rng).frame
        frames.append(Frame(frame.world_points(), frame.colours, float(index), "world"))
    return frames


def test_perceive_local_stores_each_stable_scene(tmp_path: Path) -> None:
    bag = tmp_path / "breakfast"
    write_bag(bag, _world_frames("breakfast", 8))
    data = tmp_path / "data"
    result = runner.invoke(app, ["perceive", str(bag), "--local", "--data", str(memory_in(data))])
    assert result.exit_code == 0, result.output
    assert "learned Scene-1" in result.output
    assert "1 scene(s) stored" in result.output
    gc.collect()  # the command ran in this process; let its store go
    store = Store(data / "store")
    assert memory_sizes(store)["memory"] > 0


@pytest.mark.parametrize(
    ("arguments", "fragment"),
    [
        (["missing.ply", "--local"], "does not exist"),
        (["notes.txt", "--local"], "expected a point-cloud file"),
    ],
)
def test_perceive_refuses_bad_sources(tmp_path: Path, arguments: list[str], fragment: str) -> None:
    (tmp_path / "notes.txt").write_text("not a cloud")
    arguments = [str(tmp_path / arguments[0]), *arguments[1:], "--data", str(tmp_path / "d")]
    result = runner.invoke(app, ["perceive", *arguments])
    assert result.exit_code == 2
    assert fragment in " ".join(result.output.split())  # rich wraps long lines


def _scan(path: Path, objects: tuple[TruthObject, ...]) -> Path:
    """One 320x240 scan of the simulated depth camera, written as a PLY in the world frame."""
    camera = DepthCamera().scaled(0.5)
    shot = camera.shoot(TabletopScene(objects), np.random.default_rng(3))
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(shot.frame.world_points()))
    assert o3d.io.write_point_cloud(str(path), cloud)
    return path


def test_one_scan_stores_one_scene_with_the_frames_it_averages(tmp_path: Path) -> None:
    objects = (
        TruthObject("Sphere", (-0.1, 0.0, 0.0), radius=0.05, height=0.1),
        TruthObject("Cylinder", (0.12, 0.05, 0.0), radius=0.04, height=0.14),
    )
    scan = _scan(tmp_path / "scan.ply", objects)
    data = tmp_path / "data"
    result = runner.invoke(app, ["perceive", str(scan), "--local", "--data", str(memory_in(data))])
    assert result.exit_code == 0, result.output
    output = " ".join(result.output.split())
    assert "(Cylinder, Sphere on Plane; 1 frame(s) averaged, end of the source): learned" in output
    assert "1 scene(s) stored" in output
    waiting = runner.invoke(
        app,
        [
            "perceive",
            str(scan),
            "--local",
            "--data",
            str(memory_in(tmp_path / "d2")),
            "--wait-stable",
        ],
    )
    assert waiting.exit_code == PerceiveExit.NOTHING_STORED, waiting.output
    output = " ".join(waiting.output.split())
    assert "0 scene(s) stored" in output
    assert "no scene: not stable yet: 1 frame(s) seen" in output


def test_a_scan_of_an_empty_table_says_why_no_scene(tmp_path: Path) -> None:
    scan = _scan(tmp_path / "empty.ply", ())
    data = str(memory_in(tmp_path / "d"))
    result = runner.invoke(app, ["perceive", str(scan), "--local", "--data", data])
    assert result.exit_code == PerceiveExit.NOTHING_STORED, result.output
    output = " ".join(result.output.split())
    assert "0 scene(s) stored" in output
    assert "no scene: no clusters above the support" in output


def test_an_empty_table_over_http_exits_with_nothing_stored(
    tmp_path: Path, live_server: LiveServer
) -> None:
    scan = _scan(tmp_path / "empty.ply", ())
    result = runner.invoke(app, ["perceive", str(scan), "--server", live_server.url])
    assert result.exit_code == PerceiveExit.NOTHING_STORED, result.output
    assert "no scene: no clusters above the support" in " ".join(result.output.split())


REAL_SCANS = Path(__file__).parents[1] / "data" / "real_scans"


def test_a_real_tilted_scan_with_no_pose_stores_a_mug_on_a_table(tmp_path: Path) -> None:
    scan = REAL_SCANS / "mug_stereo.npz"
    data = str(memory_in(tmp_path / "d"))
    result = runner.invoke(app, ["perceive", str(scan), "--local", "--data", data])
    assert result.exit_code == PerceiveExit.STORED, result.output
    output = " ".join(result.output.split())
    assert "(Cylinder on Plane; 1 frame(s) averaged, end of the source): learned" in output
    assert "1 scene(s) stored" in output
    assert "up: gravity from the scene" in output


def test_a_malformed_cloud_file_is_refused_with_its_bracketed_values(tmp_path: Path) -> None:
    bad = tmp_path / "flat.ply"
    bad.write_text(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "end_header\n0 0\n"
    )
    result = runner.invoke(app, ["perceive", str(bad), "--local", "--data", str(tmp_path / "d")])
    assert result.exit_code == 2
    output = " ".join(result.output.split())
    assert "flat.ply" in output
    assert "the vertices have no z property: ['x', 'y']" in output


def test_perceive_over_http_recognises_a_scene_seen_again(live_server: LiveServer) -> None:
    frames = _world_frames("two cans", 8) + _world_frames("two cans", 8, seed=1)
    # a gap of empty tables between the two views makes them two stable scenes
    empty = _world_frames(None, 4)
    with ArmorClient("camera", "engram", base_url=live_server.url, timeout=60) as client:
        first = list(perceive(frames[:8] + empty, client))
        again = list(perceive(frames[8:], client))
    assert [r.learned for r in first] == [True]
    assert [r.learned for r in again] == [False]
    assert again[0].stored_as == first[0].stored_as


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Any]:
    """A data directory the demo filled (``engram demo --no-serve``), and the command's result."""
    data_dir = tmp_path_factory.mktemp("demo")
    return data_dir, runner.invoke(app, ["demo", "--no-serve", "--data", str(data_dir)])


@pytest.mark.slow
def test_demo_learns_recalls_forgets_and_exports(demo_run: tuple[Path, Any]) -> None:
    tmp_path, result = demo_run
    assert result.exit_code == 0, result.output
    output = result.output
    assert "learned" in output and "recognised" in output
    assert "In the trash: Scene-4" in output  # the scene seen once and never recalled
    assert "Restored from the trash on request: Scene-4" in output
    asked = output.split("Asking the memory in words", 1)[1]
    assert "> When did HyungJin last show you tidying?" in asked
    assert "The last time HyungJin did tidying was three days ago" in asked
    assert "> Why did you forget experience-" in asked and "because its level was WEAK" in asked
    assert "> Why did you not recognise the last scene?" in asked
    export = rdflib.Graph().parse(tmp_path / "engram.owl", format="xml")
    assert len(list(export.subjects(rdflib.RDF.type, rdflib.OWL.Ontology))) == 1
    (scenes,) = (tmp_path / "streams").glob("*/*.mcap")  # the demo episode's, for Foxglove
    with scenes.open("rb") as stream:
        read = [m for m in make_reader(stream).iter_messages() if m[1].topic == SCENE_TOPIC]
    assert read and {s.name for s, _, _ in read} == {SCENE_TYPE}
    decoded = [scene_typestore().deserialize_cdr(m.data, SCENE_TYPE) for _, _, m in read]
    entities = [update.entities[0] for update in decoded]  # type: ignore[attr-defined]
    assert all(len(e.spheres) + len(e.cylinders) >= 2 for e in entities)
    again = runner.invoke(app, ["demo", "--no-serve", "--data", str(tmp_path)])
    assert again.exit_code == 0, again.output  # a memory the demo made is replaced
    assert "emptied the memory of" in again.output
    other = tmp_path / "robot"
    assert runner.invoke(app, ["init", "--data", str(other)]).exit_code == 0
    began = runner.invoke(app, ["episodes", "begin", "tidying", "--data", str(other)])
    assert began.exit_code == 0, began.output
    refused = runner.invoke(app, ["demo", "--no-serve", "--data", str(other)])
    assert refused.exit_code == 2  # any other memory is the robot's: only --reset empties it
    assert "--reset" in refused.output


@pytest.fixture
def demo_server(demo_run: tuple[Path, Any]) -> Iterator[httpx.Client]:
    """A server over the demo's memory, and a client bound to it."""
    data_dir, result = demo_run
    assert result.exit_code == 0, result.output
    gc.collect()  # a command run before may still hold the store in a traceback's frames
    settings = Settings(host="127.0.0.1", port=free_port(), data_dir=data_dir)
    with (
        serve(create_app(settings), settings) as running,
        httpx.Client(base_url=running.url, timeout=60) as client,
    ):
        yield client


@pytest.mark.slow
def test_every_query_page_example_returns_rows_on_the_demos_memory(
    demo_server: httpx.Client,
) -> None:
    page = json.loads(QUERY_EXAMPLES.read_text())
    for name, query in page["examples"].items():
        answer = demo_server.post(
            "/sparql",
            data={"query": page["prefixes"] + query},
            headers={"Accept": "application/sparql-results+json"},
        )
        assert answer.status_code == 200, (name, answer.text)
        rows = answer.json()["results"]["bindings"]
        assert rows, name
        if name == "The best classes by score":
            assert {row["level"]["value"] for row in rows} <= {"HIGH", "LOW", "WEAK"}
            assert 0 < float(rows[0]["score"]["value"]) <= 1


@pytest.mark.slow
def test_the_demo_episode_recorded_a_camera_to_replay_and_plot(demo_server: httpx.Client) -> None:
    (episode,) = demo_server.get("/views/episodes").json()["episodes"]
    assert episode["channels"] >= 2
    base = f"/views/episodes/{episode['id']}"
    channels = {c["name"]: c for c in demo_server.get(f"{base}/channels").json()["channels"]}
    assert channels["camera/rgb"]["image"] and channels["camera/depth"]["numeric"]
    assert channels["camera/rgb"]["samples"] == channels["camera/depth"]["samples"] > 100
    plot = demo_server.get(f"{base}/plot", params={"channel": "camera/depth"}).json()
    assert len(plot["t"]) > 100 and all(0 < v <= 1 for v in plot["values"][0])
    frames = demo_server.get(f"{base}/frames", params={"channel": "camera/rgb"}).json()
    assert len(frames["frames"]) == channels["camera/rgb"]["samples"]


@pytest.mark.parametrize("points", [1 << 27, (1 << 32) - 1])
def test_a_pcd_claiming_gigabytes_of_points_is_one_line_not_a_traceback(
    tmp_path: Path, points: int
) -> None:
    claim = tmp_path / "claim.pcd"
    header = (
        "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        f"WIDTH {points}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {points}\nDATA binary\n"
    )
    claim.write_bytes(header.encode() + b"\0" * 120)
    result = runner.invoke(app, ["perceive", str(claim), "--data", str(memory_in(tmp_path / "d"))])
    assert result.exit_code == 2, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert "claim.pcd" in result.output and "Traceback" not in result.output
