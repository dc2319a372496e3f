"""``engram perceive``: point clouds or bags in, scenes stored in the memory, results printed."""

import itertools
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import httpx
import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import Progress

from api.cli_common import DataOption, TokenOption, reach, settings_for
from api.client import ArmorClient, ArmorPyException

if TYPE_CHECKING:  # perception (open3d, scipy) is imported when a command perceives
    from api.perceive import PerceivedScene
    from shapes import Frame

__all__ = ["perceive_command"]

console = Console()


def _describe(result: "PerceivedScene") -> str:
    kinds = ", ".join(sorted(p.kind.value for p in result.scene.primitives))
    if result.scene.supports:
        kinds += " on " + ", ".join(p.kind.value for p in result.scene.supports)
    how = "learned" if result.learned else "recognised as"
    confidence = result.answer.details.get("confidence", ["?"])[0]
    frames = result.scene.frames
    held = ", end of the source" if result.scene.partial else ""
    return (
        f"scene {result.scene.scene_index} ({escape(kinds)}; {frames} frame(s) averaged{held}): "
        f"{how} [bold]{escape(result.stored_as.rsplit('#', 1)[-1].rstrip('>'))}[/bold] "
        f"(confidence {escape(confidence)})"
    )


def perceive_command(
    source: Annotated[Path, typer.Argument(help="PLY/PCD/NumPy file, ROS 1 .bag or ROS 2 bag.")],
    server: Annotated[
        str | None,
        typer.Option(
            help="Store through this Engram server (default: the data directory, or the server "
            "that holds it)."
        ),
    ] = None,
    token: TokenOption = None,
    local: Annotated[
        bool, typer.Option(help="Open the data directory here; never talk to a server.")
    ] = False,
    data: DataOption = None,
    topic: Annotated[str | None, typer.Option(help="PointCloud2 topic of a bag.")] = None,
    pose: Annotated[
        Path | None,
        typer.Option(
            help="Text file with the 4x4 world-from-sensor matrix (world z up); by default up "
            "is the normal of the scene's dominant support."
        ),
    ] = None,
    episode: Annotated[str | None, typer.Option(help="Episode IRI the scenes belong to.")] = None,
    client_id: Annotated[str, typer.Option(help="ARMOR client name.")] = "perception",
    seed: Annotated[int, typer.Option(help="Seed of the RANSAC fits.")] = 0,
    scene_frames: Annotated[
        int,
        typer.Option(
            min=1, help="Frames a scene must hold still (no object appearing, moving, vanishing)."
        ),
    ] = 5,
    min_hits: Annotated[
        int, typer.Option(min=1, help="Frames an object must be seen in to join a scene.")
    ] = 3,
    wait_stable: Annotated[
        bool,
        typer.Option(
            help="Store only scenes that held still; by default the end of the source also "
            "stores the scene it has (one scan stores one scene)."
        ),
    ] = False,
) -> None:
    """Perceive SOURCE and store every stable scene; print what the memory recognised or learned."""
    import numpy as np

    try:
        from shapes import ShapesError, open_source, source_length
    except ImportError as error:
        console.print(
            f"[red]perception is not installed ({error}): pip install 'engram-kg[perception]'[/red]"
        )
        raise typer.Exit(1) from None

    try:
        world_from_sensor = np.loadtxt(pose).reshape(4, 4) if pose else None
        total = source_length(source, topic=topic)
        frames = open_source(source, topic=topic, world_from_sensor=world_from_sensor)
        # the first frame is read now, so that a bad source says so before the memory opens
        first = next(frames, None)
        if first is not None:
            frames = itertools.chain([first], frames)
    except (ShapesError, OSError, ValueError) as error:
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(2) from None
    if local and server is not None:
        console.print("[red]--local and --server exclude each other[/red]")
        raise typer.Exit(2)
    with reach(settings_for(data), server, token) as memory:
        if isinstance(memory, httpx.Client):
            if local:
                console.print(
                    f"[red]the server at {memory.base_url} holds the data directory; stop it, "
                    "or leave out --local to store through it[/red]"
                )
                raise typer.Exit(1)
            client = ArmorClient(client_id, "engram", http=memory)
        else:
            from api.client import LocalTransport

            transport = LocalTransport(memory.armor)
            client = ArmorClient(
                client_id, "engram", http=httpx.Client(base_url="http://local", transport=transport)
            )
        _perceive_into(
            client, source, frames, total, scene_frames, min_hits, seed, episode, wait_stable, pose
        )


def _perceive_into(
    client: ArmorClient,
    source: Path,
    frames: Iterator["Frame"],
    total: int,
    scene_frames: int,
    min_hits: int,
    seed: int,
    episode: str | None,
    wait_stable: bool,
    pose: Path | None,
) -> None:
    from api.perceive import PerceiveExit, exit_status, perceive
    from shapes import Frame, Perception, PerceptionParams, ShapesError

    stored = 0
    try:
        with client, Progress(console=console, transient=True) as progress:
            task = progress.add_task(f"perceiving {source.name}", total=total)

            def counted() -> Iterator[Frame]:
                for frame in frames:
                    yield frame
                    progress.advance(task)

            params = PerceptionParams(
                stable_frames=scene_frames, min_hits=min_hits, gravity_from_scene=pose is None
            )
            perception = Perception(params, seed=seed)
            for result in perceive(
                counted(), client, perception=perception, episode=episode, finish=not wait_stable
            ):
                stored += 1
                progress.console.print(_describe(result))
    except ShapesError as error:  # the source is bad: an input error
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(2) from None
    except ArmorPyException as error:  # the memory refused or could not be reached
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(1) from None
    up = f"the pose in {pose}" if pose else perception.gravity
    console.print(f"{stored} scene(s) stored from {escape(str(source))}; up: {escape(up)}")
    if not stored:
        for line in perception.why_no_scene() or ["no frame in the source"]:
            console.print(f"no scene: {escape(line)}")
    if exit_status(stored) is not PerceiveExit.STORED:
        raise typer.Exit(exit_status(stored))
