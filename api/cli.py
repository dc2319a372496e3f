"""The ``engram`` command line."""

import copy
import gc
from pathlib import Path
from typing import Annotated, Any

import typer
import uvicorn
from rich.console import Console
from rich.markup import escape

from api.cli_ask import ask_command
from api.cli_episodes import app as episodes_app
from api.cli_perceive import perceive_command
from api.config import Settings
from api.demo import run_demo
from api.header_timeout import with_header_timeout
from api.main import create_app
from api.summary import memory_sizes, print_summary, reset_memories
from kg import DEFAULT_GRAPHS, EngramError, Store, ensure_ontology, export
from kg.export import FORMATS
from ontologies.vocab import GRAPHS
from reasoners.check import check_memory, describe, fix_memory

app = typer.Typer(
    help="Engram: a human-like memory for robots, kept as a knowledge graph.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
)
console = Console()
app.add_typer(episodes_app, name="episodes")
app.command("perceive")(perceive_command)
app.command("ask")(ask_command)

DataOption = Annotated[
    Path | None, typer.Option("--data", help="Data directory (default: $ENGRAM_DATA_DIR).")
]
HostOption = Annotated[str | None, typer.Option(help="Address to listen on.")]
PortOption = Annotated[int | None, typer.Option(help="TCP port to listen on.")]


def _settings(**overrides: Any) -> Settings:
    try:
        return Settings(**{key: value for key, value in overrides.items() if value is not None})
    except ValueError as error:
        console.print(f"[red]invalid setting:[/red] {error}")
        raise typer.Exit(2) from None


def _open(settings: Settings) -> Store:
    try:
        return Store(settings.store_dir)
    except EngramError as error:
        console.print(f"[red]{error}[/red]")
        raise typer.Exit(1) from None


def _refuse_damaged(settings: Settings) -> None:
    """Stop before serving a store whose memory graphs are damaged, naming what and how to fix."""
    if not settings.store_dir.exists():
        return
    store = _open(settings)
    damages = check_memory(store)
    del store
    gc.collect()  # unlock the directory for the server
    if damages:
        console.print(f"[red]{escape(describe(damages))}[/red]", soft_wrap=True)
        raise typer.Exit(1)


def views_url(settings: Settings) -> str:
    """Where the served web views are."""
    return f"http://{settings.host}:{settings.port}/web/"


def _serve(settings: Settings) -> None:
    _refuse_damaged(settings)
    # Engram's own loggers go through uvicorn's handler, at INFO, like the server's.
    log_config = copy.deepcopy(uvicorn.config.LOGGING_CONFIG)
    log_config["root"] = {"handlers": ["default"], "level": "INFO"}
    console.print(
        f"Serving {settings.store_dir} on http://{settings.host}:{settings.port} "
        "(SPARQL at /sparql, OWL export at /export, API docs at /docs); Ctrl-C stops."
    )
    console.print(f"Web views (memory graph, scenes in 3D, episodes, query): {views_url(settings)}")
    uvicorn.run(
        create_app(settings),
        host=settings.host,
        port=settings.port,
        log_level="info",
        log_config=log_config,
        access_log=False,  # a line per request costs more than a directive does
        http=with_header_timeout(settings.header_timeout_s),  # api/header_timeout.py
    )


@app.command()
def demo(
    data: DataOption = None,
    serve: Annotated[bool, typer.Option(help="Serve the store when done.")] = True,
    reset: Annotated[
        bool, typer.Option(help="Empty the memories of the data directory before the demo.")
    ] = False,
    host: HostOption = None,
    port: PortOption = None,
) -> None:
    """The main job: a scripted memory life from point clouds to forgetting, then serve it.

    Synthetic scenes are perceived and stored, cues recalled, nights slept; what was learned,
    recalled and forgotten is printed, the memory exported for Protégé, and the store served.
    """
    settings = _settings(data_dir=data, host=host, port=port)
    store = _open(settings)
    status = ensure_ontology(store)
    held = {name: size for name, size in memory_sizes(store).items() if size}
    if held and not reset:
        console.print(
            f"[red]{settings.data_dir} already holds a memory ({held}); run the demo with "
            "--reset to empty it first, or with --data on another directory[/red]"
        )
        raise typer.Exit(2)
    if held:
        reset_memories(store)
        console.print(f"emptied the memories of {settings.data_dir}: {held}")
    console.print(
        f"[bold]Engram[/bold] store at {store.path}: ontology {status.version.value} "
        f"({status.action})"
    )
    run_demo(store, settings.data_dir, console)
    store.flush()
    del store
    gc.collect()  # the demo's services hold the store in cycles; free them to unlock the directory
    if serve:
        _serve(settings)


@app.command()
def serve(data: DataOption = None, host: HostOption = None, port: PortOption = None) -> None:
    """Serve the store over HTTP: SPARQL, export, the ARMOR directive API, episodes, streams."""
    _serve(_settings(data_dir=data, host=host, port=port))


@app.command()
def check(
    data: DataOption = None,
    fix: Annotated[bool, typer.Option("--fix", help="Repair what can be repaired safely.")] = False,
) -> None:
    """Check the memory graphs for damage that stops the memory loading; --fix repairs."""
    store = _open(_settings(data_dir=data))
    damages = check_memory(store)
    if fix and damages:
        fixed = fix_memory(store, damages)
        console.print(f"repaired {fixed} problem(s)")
        damages = check_memory(store)
    del store
    gc.collect()  # unlock the directory even when the exit below keeps this frame alive
    if damages:
        console.print(escape(describe(damages)), soft_wrap=True)
        raise typer.Exit(1)
    console.print("the memory graphs are sound")


@app.command()
def info(data: DataOption = None) -> None:
    """Show the ontology version, graph sizes, T-Box entities and memory policy."""
    settings = _settings(data_dir=data)
    store = _open(settings)
    print_summary(console, store, ensure_ontology(store))


@app.command("export")
def export_command(
    output: Annotated[Path, typer.Option("-o", "--output", help="File to write.")],
    format: Annotated[str, typer.Option(help="rdfxml or turtle.")] = "rdfxml",
    graphs: Annotated[
        list[str] | None,
        typer.Option(help=f"Graphs to export, repeated or comma-separated: {', '.join(GRAPHS)}."),
    ] = None,
    data: DataOption = None,
) -> None:
    """Export the T-Box and the memory as one OWL ontology for Protégé."""
    names = [n.strip() for g in graphs or [] for n in g.split(",") if n.strip()]
    store = _open(_settings(data_dir=data))
    ensure_ontology(store)
    try:
        body = export(store, names or list(DEFAULT_GRAPHS), format)
    except ValueError as error:
        console.print(f"[red]{error}[/red]")
        raise typer.Exit(2) from None
    tmp = output.with_name(output.name + ".part")
    tmp.write_bytes(body)
    tmp.replace(output)  # atomic: a reader never sees half a file
    console.print(f"wrote {len(body)} bytes of {FORMATS[format][1]} to {output}")


@app.command()
def backup(
    target: Annotated[Path, typer.Argument(help="New directory for the copy.")],
    data: DataOption = None,
) -> None:
    """Copy the store to a new directory (hard links where possible)."""
    store = _open(_settings(data_dir=data))
    try:
        store.backup(target)
    except (EngramError, FileExistsError) as error:
        console.print(f"[red]{error}[/red]")
        raise typer.Exit(1) from None
    console.print(f"backed up {store.path} to {target}")
