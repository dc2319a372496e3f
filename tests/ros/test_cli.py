"""``engram ros``: what it refuses before it registers with a master."""

import gc
import logging
from pathlib import Path

import pytest
from typer.testing import CliRunner

from api.cli import app
from kg import Store


@pytest.mark.parametrize(
    ("pose", "fragment"),
    [("1 0 0\n0 1 0\n", "expected a 4x4 rigid transform"), (None, "expected a 4x4")],
)
def test_engram_ros_refuses_a_bad_pose_before_starting(
    tmp_path: Path, pose: str | None, fragment: str
) -> None:
    path = tmp_path / "pose.txt"
    if pose is not None:
        path.write_text(pose)
    scaled = "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n"  # not rigid
    if pose is None:
        path.write_text(scaled)
    result = CliRunner().invoke(app, ["ros", "--data", str(tmp_path), "--pose", str(path)])
    assert result.exit_code == 2
    assert fragment in " ".join(result.output.split())


def test_engram_ros_refuses_a_store_another_process_holds(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    result = CliRunner().invoke(app, ["ros", "--data", str(tmp_path)])
    assert result.exit_code == 1
    assert "is open in another process" in " ".join(result.output.split())
    del store
    gc.collect()


def test_importing_ros_leaves_the_class_of_new_loggers_alone() -> None:
    from api.ros._ros import rosgraph

    assert logging.getLoggerClass() is not rosgraph.roslogging.RospyLogger
    assert rosgraph.roslogging.RospyLogger is not logging.Logger
