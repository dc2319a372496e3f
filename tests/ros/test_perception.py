"""PointCloud2 in, scenes stored, answers published: a test node publishes a synthetic tabletop."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from api.ros._ros import sensor_msgs
from api.ros.perception import frame_of
from shapes import SourceError
from shapes.synthetic import TabletopScene, TruthObject
from tests.api.armor.conftest import request
from tests.ros.conftest import CLOUD_TOPIC, RESULT_TOPIC, RosArmor
from tests.ros.processes import Master, ros_env

PointCloud2, PointField = sensor_msgs.msg.PointCloud2, sensor_msgs.msg.PointField

HERE = Path(__file__).parent
SCENE = TabletopScene(
    (
        TruthObject("Sphere", (-0.15, 0.0, 0.0), radius=0.05, height=0.1, colour=(0.8, 0.1, 0.1)),
        TruthObject("Cylinder", (0.15, 0.05, 0.0), radius=0.04, height=0.15),
    )
)


def test_a_published_tabletop_is_stored_and_its_answer_published(
    engram_ros: Path, ros_master: Master, ros_armor: RosArmor, tmp_path: Path
) -> None:
    rng = np.random.default_rng(7)
    shots = [SCENE.render(rng).frame for _ in range(3)]
    clouds = tmp_path / "clouds.npz"
    np.savez(
        clouds,
        **{f"points_{i}": f.points for i, f in enumerate(shots)},
        **{f"colours_{i}": f.colours for i, f in enumerate(shots)},
    )
    script = str(HERE / "publish_clouds.py")
    done = subprocess.run(
        [sys.executable, script, str(clouds), CLOUD_TOPIC, RESULT_TOPIC, "5", "40"],
        env=ros_env(ros_master.uri, tmp_path),
        capture_output=True,
        text=True,
        timeout=90,
        check=True,
    )
    lines = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    answers = [line for line in lines if "success" in line]
    assert answers, done.stdout + done.stderr + (engram_ros / "engram.log").read_text()
    first = answers[0]
    assert first["success"], first
    stored_as = first["queried_objects"][0]
    details = {item["key"]: item["value"] for item in first["sparql_queried_objects"]}
    assert details["learned"] == "true"
    # the memory holds the scene: its class has a memory level, asked over the ARMOR service
    level = ros_armor.execute(request("QUERY", "MEMORY", "LEVEL", [stored_as], ref="engram"))
    assert level.success, level


def _cloud(fields: list[tuple[str, int, int]], step: int, rows: int, width: int) -> PointCloud2:
    message = PointCloud2()
    message.fields = [PointField(name, offset, kind, 1) for name, offset, kind in fields]
    message.height, message.width, message.point_step = rows, width, step
    message.row_step, message.is_bigendian = step * width + 4, False  # padded rows
    return message


def test_an_organised_padded_float64_cloud_is_an_organised_frame_of_its_finite_points() -> None:
    points = np.arange(2 * 3 * 3, dtype="<f8").reshape(2, 3, 3)
    points[1, 2] = np.nan  # a hole of the organised cloud
    message = _cloud([("x", 0, 8), ("y", 8, 8), ("z", 16, 8)], 24, 2, 3)
    message.data = b"".join(points[r].tobytes() + b"\0" * 4 for r in range(2))
    frame = frame_of(message)
    assert frame is not None
    np.testing.assert_allclose(frame.points, points.reshape(-1, 3)[:5])
    assert frame.colours is None
    assert frame.image_shape == (2, 3)
    assert frame.pixels is not None
    assert frame.pixels.tolist() == [0, 1, 2, 3, 4]


@pytest.mark.parametrize(
    ("fields", "data", "fragment"),
    [
        ([("x", 0, 7), ("y", 4, 7)], b"\0" * 24, "expected x, y and z"),
        ([("x", 0, 7), ("y", 4, 7), ("z", 8, 7)], b"\0" * 5, "PointCloud2.data"),
    ],
)
def test_an_unreadable_cloud_is_refused_with_what_is_wrong(
    fields: list[tuple[str, int, int]], data: bytes, fragment: str
) -> None:
    message = _cloud(fields, 12, 1, 2)
    message.data = data
    with pytest.raises(SourceError, match=fragment):
        frame_of(message)


def test_a_cloud_without_a_finite_point_is_no_frame() -> None:
    message = _cloud([("x", 0, 7), ("y", 4, 7), ("z", 8, 7)], 12, 1, 1)
    message.row_step = 12
    message.data = np.full(3, np.nan, dtype="<f4").tobytes()
    assert frame_of(message) is None
