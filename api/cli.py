"""The ``engram`` command line."""

import copy
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape

from api.cli_ask import ask_command
from api.cli_common import (
    DataOption,
    InitOption,
    ServerOption,
    TokenOption,
    call,
    fail,
    opened,
    reach,
    settings_for,
    tell,
)
from api.cli_episodes import app as episodes_app
from api.cli_perceive import perceive_command
from api.cli_ros import ros_command, ros_options
from api.config import Settings

app = typer.Typer(
    help="Engram: a human-like memory for robots, kept as a knowledge graph. Every command "
    "works on one memory: the data directory --data (default $ENGRAM_DATA_DIR, else "
    "~/.local/share/engram), or the server that holds it.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
)
console = Console(soft_wrap=True)  # paths and URLs stay on one line
app.add_typer(episodes_app, name="episodes")
app.command("perceive")(perceive_command)
app.command("ask")(ask_command)
app.command("ros")(ros_command)

HostOption = Annotated[str | None, typer.Option(help="Address to listen on.")]
PortOption = Annotated[
    int | None, typer.Option(min=1, max=65535, help="TCP port to listen on (1-65535).")
]

DEMO_MARK = "DEMO"
"""A file in a data directory whose memory the demo made: the next demo may replace it."""


def _refuse_damaged(settings: Settings) -> None:
    """Stop before serving a store whose memory graphs are damaged, naming what and how to fix."""
    from reasoners.check import check_memory, describe

    if settings.store_url is not None or not settings.store_dir.exists():
        return
    with opened(settings) as services:
        damages = check_memory(services.store)
    if damages:
        console.print(f"[red]{escape(describe(damages))}[/red]", soft_wrap=True)
        raise typer.Exit(1)


def views_url(settings: Settings) -> str:
    """Where the served web views are."""
    return f"http://{settings.host}:{settings.port}/web/"


def _serve(settings: Settings, *, ros: bool = False) -> None:
    import uvicorn

    from api.header_timeout import with_header_timeout
    from api.main import create_app

    _refuse_damaged(settings)
    # Engram's own loggers go through uvicorn's handler, at INFO, like the server's.
    log_config = copy.deepcopy(uvicorn.config.LOGGING_CONFIG)
    log_config["root"] = {"handlers": ["default"], "level": "INFO"}
    where = settings.store_url or settings.data_dir
    console.print(
        f"Serving the memory {where} on http://{settings.host}:{settings.port} "
        "(SPARQL at /sparql, OWL export at /export, API docs at /docs); Ctrl-C stops."
    )
    console.print(f"Web views (memory graph, scenes in 3D, episodes, query): {views_url(settings)}")
    app = create_app(settings)
    if ros:  # the ROS node on the app's engine (api/ros/serve.py)
        from api.ros.serve import add_ros

        add_ros(app, ros_options())
    uvicorn.run(
        app,
        host=settings.host,
        port=settings.port,
        log_level="info",
        log_config=log_config,
        access_log=False,  # a line per request costs more than a directive does
        # 408 for stalled headers or bodies (api/header_timeout.py)
        http=with_header_timeout(settings.header_timeout_s, body_timeout_s=settings.body_timeout_s),
    )


@app.command()
def demo(
    data: DataOption = None,
    serve: Annotated[bool, typer.Option(help="Serve the memory when done.")] = True,
    reset: Annotated[
        bool,
        typer.Option(
            help="Empty the data directory's memory first, even one the demo did not make."
        ),
    ] = False,
    host: HostOption = None,
    port: PortOption = None,
) -> None:
    """The main job: a scripted memory life from point clouds to forgetting, then serve it.

    Synthetic scenes are perceived and stored, cues recalled, nights slept; what was learned,
    recalled and forgotten is printed, the memory exported for Protégé, and the store served.
    A memory the demo made before is replaced; any other needs --reset.
    """
    from api.demo import run_demo
    from api.summary import memory_sizes, reset_memories

    settings = settings_for(data, host=host, port=port)
    if settings.store_url is not None:
        fail("the demo runs on an embedded memory; unset ENGRAM_STORE_URL", 2)
    mark = settings.data_dir / DEMO_MARK
    with opened(settings, create=True) as services:
        store = services.store
        held = {name: size for name, size in memory_sizes(store).items() if size}
        if held and not (reset or mark.exists()):
            fail(
                f"{settings.data_dir} holds a memory the demo did not make ({held}); run the "
                "demo with --reset to empty it, or with --data on another directory",
                2,
            )
        if held:
            reset_memories(store)
            console.print(f"emptied the memory of {settings.data_dir}: {held}")
        mark.write_text("This memory was made by `engram demo`; the next demo replaces it.\n")
        status = services.ontology
        console.print(
            f"[bold]Engram[/bold] memory at {settings.data_dir}: ontology "
            f"{status.version.value} ({status.action})"
        )
        run_demo(store, settings.data_dir, console)
    if serve:
        _serve(settings)


@app.command()
def serve(
    data: DataOption = None,
    host: HostOption = None,
    port: PortOption = None,
    init: InitOption = False,
    ros: Annotated[
        bool, typer.Option(help="Also serve ARMOR's ROS services (engram ros).")
    ] = False,
) -> None:
    """Serve the memory over HTTP: SPARQL, export, the ARMOR directive API, episodes, streams;
    with --ros, ARMOR's ROS services on the same memory too."""
    settings = settings_for(data, host=host, port=port)
    if settings.store_url is None and not init and not settings.store_dir.is_dir():
        fail(
            f"no memory in {settings.data_dir}; `engram serve --init` creates an empty one "
            "there, `engram demo` one with a demo's life, or --data names another",
            1,
        )
    _serve(settings, ros=ros)


@app.command()
def init(data: DataOption = None) -> None:
    """Create an empty memory in the data directory (the T-Box and the memory policy), or say
    that one is there already."""
    settings = settings_for(data)
    existed = settings.store_dir.is_dir()
    with opened(settings, create=True) as services:
        status = services.ontology
    state = "holds a memory already" if existed else "now holds an empty memory"
    console.print(f"{settings.data_dir} {state}: ontology {status.version.value}")


@app.command()
def check(
    data: DataOption = None,
    fix: Annotated[bool, typer.Option("--fix", help="Repair what can be repaired safely.")] = False,
) -> None:
    """Check the memory graphs for damage that stops the memory loading; --fix repairs."""
    from api.services import StoreBusyError, open_services
    from kg import EngramError
    from reasoners.check import check_memory, describe, fix_memory

    settings = settings_for(data)
    try:
        services = open_services(settings)
    except StoreBusyError as error:
        if error.server is None:
            fail(str(error), 1)
        fail(
            f"the server at {error.server} holds {settings.data_dir}; it checked the memory "
            "when it started (it refuses a damaged one): stop it to check or fix again",
            1,
        )
    except (EngramError, ValueError) as error:
        fail(str(error), 1)
    tell(f"memory: {services.where}")
    with services:
        damages = check_memory(services.store)
        if fix and damages:
            fixed = fix_memory(services.store, damages)
            console.print(f"repaired {fixed} problem(s)")
            damages = check_memory(services.store)
    if damages:
        console.print(escape(describe(damages)), soft_wrap=True)
        raise typer.Exit(1)
    console.print("the memory graphs are sound")


@app.command()
def info(data: DataOption = None, server: ServerOption = None) -> None:
    """Show the ontology version, graph sizes, T-Box entities and memory policy."""
    from api.services import Services
    from api.summary import print_summary

    with reach(settings_for(data), server) as memory:
        if isinstance(memory, Services):
            print_summary(console, memory.store, memory.ontology)
        else:
            health = call(memory, "GET", "/health")
            console.print_json(data=health)


def _graph_names(graphs: list[str] | None) -> list[str]:
    return [n.strip() for g in graphs or [] for n in g.split(",") if n.strip()]


@app.command("export")
def export_command(
    output: Annotated[Path, typer.Option("-o", "--output", help="File to write.")],
    format: Annotated[str, typer.Option(help="rdfxml or turtle.")] = "rdfxml",
    graphs: Annotated[
        list[str] | None,
        typer.Option(
            help="Graphs to export, repeated or comma-separated: tbox, memory, episodic, "
            "trash, episodes (default tbox and memory)."
        ),
    ] = None,
    data: DataOption = None,
    server: ServerOption = None,
) -> None:
    """Export the T-Box and the memory as one OWL ontology for Protégé."""
    from api.services import Services
    from kg.export import DEFAULT_GRAPHS, FORMATS, export

    names = _graph_names(graphs) or list(DEFAULT_GRAPHS)
    if format not in FORMATS:
        fail(f"format: got {format!r}, expected one of {', '.join(FORMATS)}", 2)
    with reach(settings_for(data), server) as memory:
        if isinstance(memory, Services):
            try:
                body = export(memory.store, names, format)
            except ValueError as error:
                fail(str(error), 2)
        else:
            body = call(memory, "GET", "/export", params={"format": format, "graphs": names})
    tmp = output.with_name(output.name + ".part")
    tmp.write_bytes(body)
    tmp.replace(output)  # atomic: a reader never sees half a file
    console.print(f"wrote {len(body)} bytes of {FORMATS[format][1]} to {output}")


@app.command()
def backup(
    target: Annotated[Path, typer.Argument(help="New directory for the copy.")],
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Copy the store to a new directory (hard links where possible); `engram restore` makes
    a data directory of it again."""
    import shutil

    from api.services import Services
    from kg import EngramError

    settings = settings_for(data)
    with reach(settings, server, token) as memory:
        if isinstance(memory, Services):
            try:
                memory.store.backup(target)
            except (EngramError, FileExistsError) as error:
                fail(str(error), 1)
        else:
            made = Path(str(call(memory, "POST", "/backup")["backup"]))
            if server is not None:  # another machine's server, maybe: its copy stays there
                console.print(f"the server backed up its store to {made}")
                return
            if target.exists():
                fail(f"the backup target {target} already exists", 1)
            shutil.move(settings.backup_dir / made.name, target)
    console.print(f"backed up the memory of {settings.data_dir} to {target}")


@app.command()
def restore(
    backup: Annotated[Path, typer.Argument(help="A copy made by `engram backup` or POST /backup.")],
    data: DataOption = None,
) -> None:
    """Make a backup the data directory's memory again; the store it replaces is kept under
    <data dir>/backups/before-restore-<time>. Stop the server first."""
    from api.services import running_server
    from kg import EngramError
    from kg.restore import restore_backup

    settings = settings_for(data)
    if settings.store_url is not None:
        fail("restore works on an embedded memory; unset ENGRAM_STORE_URL", 2)
    server = running_server(settings.data_dir)
    if server is not None:
        fail(f"the server at {server} holds {settings.data_dir}; stop it, then restore", 1)
    tell(f"memory: {settings.data_dir}")
    try:
        kept = restore_backup(backup, settings.store_dir)
    except (EngramError, FileExistsError) as error:
        fail(str(error), 1)
    console.print(f"restored {backup} as the memory of {settings.data_dir}")
    if kept is not None:
        console.print(f"the memory it replaced is kept in {kept}")
