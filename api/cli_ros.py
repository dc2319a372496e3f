"""``engram ros``: ARMOR's ROS services (and PointCloud2 perception) on the local memory."""

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape

from api.cli_common import DataOption, InitOption, settings_for
from api.config import Settings
from api.ros.system import RosUnavailableError, load_ros
from kg import EngramError

if TYPE_CHECKING:  # perception (open3d) is imported when a node starts, not with the CLI
    from api.ros.node_options import RosOptions

__all__ = ["ros_command", "ros_options"]

console = Console()


def ros_options(
    *,
    node_name: str = "engram",
    cloud_topic: str | None = None,
    result_topic: str = "/engram/scenes",
    pose: Path | None = None,
    scene_frames: int = 5,
    min_hits: int = 3,
    seed: int = 0,
) -> "RosOptions":
    """The node's options; raises ValueError for a pose file that is not a rigid 4x4 matrix."""
    from api.ros.node_options import RosOptions
    from shapes import PerceptionParams
    from shapes.frame import as_transform

    world_from_sensor = None
    if pose is not None:
        try:
            world_from_sensor = as_transform(np.loadtxt(pose).reshape(4, 4))
        except (OSError, ValueError) as error:
            raise ValueError(f"--pose {pose}: expected a 4x4 rigid transform ({error})") from None
    return RosOptions(
        node_name=node_name,
        cloud_topic=cloud_topic,
        result_topic=result_topic,
        world_from_sensor=world_from_sensor,
        perception=PerceptionParams(
            stable_frames=scene_frames, min_hits=min_hits, gravity_from_scene=pose is None
        ),
        seed=seed,
    )


def ros_command(
    data: DataOption = None,
    node_name: Annotated[str, typer.Option("--node-name", help="ROS node name.")] = "engram",
    cloud_topic: Annotated[
        str | None,
        typer.Option("--cloud-topic", help="sensor_msgs/PointCloud2 topic to perceive."),
    ] = None,
    result_topic: Annotated[
        str,
        typer.Option(
            "--result-topic",
            help="Where each stored scene's answer is published (ArmorDirectiveRes).",
        ),
    ] = "/engram/scenes",
    pose: Annotated[
        Path | None,
        typer.Option(
            help="Text file with the 4x4 world-from-sensor matrix (world z up); default identity."
        ),
    ] = None,
    scene_frames: Annotated[
        int, typer.Option(min=1, help="Frames a scene must hold still to be stored.")
    ] = 5,
    min_hits: Annotated[
        int, typer.Option(min=1, help="Frames an object must be seen in to join a scene.")
    ] = 3,
    seed: Annotated[int, typer.Option(help="Seed of the RANSAC fits.")] = 0,
    init: InitOption = False,
) -> None:
    """Serve ARMOR's ROS services on the master of $ROS_MASTER_URI; Ctrl-C stops.

    /armor_interface_srv and /armor_interface_serialized_srv, with ARMOR's armor_msgs, answer
    as `engram serve` does over HTTP. With --cloud-topic, stable scenes of that PointCloud2
    topic are stored and their answers published on --result-topic.
    """
    settings = settings_for(data)
    try:
        options = ros_options(
            node_name=node_name,
            cloud_topic=cloud_topic,
            result_topic=result_topic,
            pose=pose,
            scene_frames=scene_frames,
            min_hits=min_hits,
            seed=seed,
        )
        load_ros()
    except (ValueError, RosUnavailableError) as error:
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(2) from None
    _run(settings, options, create=init)


def _run(settings: Settings, options: "RosOptions", *, create: bool) -> None:
    from api.ros.running import RunningNode
    from api.ros.runtime import open_memory

    try:
        memory = open_memory(settings, create=create)
    except (EngramError, ValueError) as error:  # a locked or unreadable store, a bad setting
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(1) from None
    try:
        node = RunningNode(memory.engine, options, signals=True)
        console.print(
            f"Serving {escape(memory.services.where)} to ROS as node /{escape(options.node_name)}"
            "; Ctrl-C stops."
        )
        try:
            node.spin()
        finally:
            node.stop()
    finally:
        memory.close()
