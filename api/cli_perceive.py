"""``engram perceive``: point clouds or bags in, scenes stored in the memory, results printed."""

from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import httpx
import numpy as np
import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import Progress

from api.armor import ArmorEngine
from api.client import ArmorClient, ArmorPyException, LocalTransport
from api.config import Settings
from api.perceive import PerceivedScene, PerceiveExit, exit_status, perceive
from kg import EngramError, Store, ensure_ontology
from shapes import Frame, Perception, PerceptionParams, ShapesError, open_source, source_length

__all__ = ["perceive_command"]

console = Console()


def _describe(result: PerceivedScene) -> str:
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
    server: Annotated[str, typer.Option(help="Engram server URL.")] = "http://127.0.0.1:8000",
    token: Annotated[
        str | None, typer.Option(envvar="ENGRAM_TOKEN", help="Bearer token for writes.")
    ] = None,
    local: Annotated[
        bool, typer.Option(help="Store into the local data directory, with no server.")
    ] = False,
    data: Annotated[Path | None, typer.Option(help="Data directory for --local.")] = None,
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
    try:
        world_from_sensor = np.loadtxt(pose).reshape(4, 4) if pose else None
        total = source_length(source, topic=topic)
        frames = open_source(source, topic=topic, world_from_sensor=world_from_sensor)
    except (ShapesError, OSError, ValueError) as error:
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(PerceiveExit.BAD_INPUT) from None
    if local:
        settings = Settings(data_dir=data) if data else Settings()
        try:
            store = Store(settings.store_dir)
        except EngramError as error:
            console.print(f"[red]{escape(str(error))}[/red]")
            raise typer.Exit(PerceiveExit.MEMORY_ERROR) from None
        ensure_ontology(store)
        http = httpx.Client(base_url="http://local", transport=LocalTransport(ArmorEngine(store)))
        client = ArmorClient(client_id, "engram", http=http)
    else:
        client = ArmorClient(client_id, "engram", base_url=server, token=token, timeout=60)
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
        raise typer.Exit(PerceiveExit.BAD_INPUT) from None
    except ArmorPyException as error:  # the memory refused or could not be reached
        console.print(f"[red]{escape(str(error))}[/red]")
        raise typer.Exit(PerceiveExit.MEMORY_ERROR) from None
    up = f"the pose in {pose}" if pose else perception.gravity
    console.print(f"{stored} scene(s) stored from {escape(str(source))}; up: {escape(up)}")
    if not stored:
        for line in perception.why_no_scene() or ["no frame in the source"]:
            console.print(f"no scene: {escape(line)}")
    if exit_status(stored) is not PerceiveExit.STORED:
        raise typer.Exit(exit_status(stored))
