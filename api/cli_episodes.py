"""``engram episodes ...``: the autobiographical memory from the command line.

Each command opens the on-disk store (stop ``engram serve`` first, or use the HTTP API), does
one thing and prints JSON. Bad input exits with status 2 and a message naming the field, the
value and what was expected; something not found exits with status 1.
"""

import json
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any

import typer

from api.config import Settings
from episodes import (
    ArgumentSpec,
    Cue,
    EpisodeError,
    EpisodeMemory,
    InvalidInputError,
    NotFoundError,
    to_jsonable,
)
from episodes.times import parse_time
from kg import EngramError, Store, ensure_ontology

__all__ = ["app"]

app = typer.Typer(
    help="Autobiographical memory: episodes, queries by cue, augmentation runs, ratings.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
)

DataOption = Annotated[
    Path | None, typer.Option("--data", help="Data directory (default: $ENGRAM_DATA_DIR).")
]
AgentOption = Annotated[str | None, typer.Option(help="Who is in the role 'agent' (name or IRI).")]
ObjectOption = Annotated[
    str | None, typer.Option("--object", help="What is in the role 'object' (name or IRI).")
]
RoleOption = Annotated[
    str | None, typer.Option(help="A role (recipient, partner, ...); with --participant, who.")
]
ParticipantOption = Annotated[
    str | None, typer.Option(help="Someone in --role, or in any role without --role.")
]
NowOption = Annotated[
    str | None, typer.Option(help="Reference time for 'one month ago' (ISO 8601, with zone).")
]


def _fail(message: str, code: int) -> typer.Exit:
    typer.echo(f"error: {message}", err=True)
    return typer.Exit(code)


@contextmanager
def _memory(data: Path | None) -> Iterator[EpisodeMemory]:
    try:
        overrides: dict[str, Any] = {"data_dir": data} if data is not None else {}
        settings = Settings(**overrides)
    except ValueError as error:
        raise _fail(f"invalid setting: {error}", 2) from None
    try:
        store = Store(settings.store_dir)
    except EngramError as error:
        raise _fail(str(error), 1) from None
    ensure_ontology(store)
    memory = EpisodeMemory(store, data_dir=settings.data_dir)
    try:
        yield memory
    except InvalidInputError as error:
        raise _fail(str(error), 2) from None
    except NotFoundError as error:
        raise _fail(str(error), 1) from None
    except EpisodeError as error:
        raise _fail(str(error), 1) from None
    finally:
        memory.close()
        store.flush()


def _print(value: Any) -> None:
    typer.echo(json.dumps(to_jsonable(value), indent=2, ensure_ascii=False))


def _arguments(values: list[str] | None) -> list[ArgumentSpec]:
    specs = []
    for i, text in enumerate(values or []):
        role, sep, value = text.partition("=")
        if not sep:
            raise _fail(f"argument[{i}]: got {text!r}, expected ROLE=VALUE", 2)
        specs.append(ArgumentSpec(role.strip(), value.strip()))
    return specs


def _now(now: str | None) -> Any:
    return parse_time(now, "now") if now is not None else None


@app.command()
def begin(
    activity: Annotated[str, typer.Argument(help="Activity name, e.g. babbling.")],
    type: Annotated[str | None, typer.Option(help="Activity type, e.g. action.")] = None,
    argument: Annotated[
        list[str] | None, typer.Option("--argument", "-a", help="ROLE=VALUE, repeatable.")
    ] = None,
    at: Annotated[str | None, typer.Option(help="Begin time (ISO 8601); default now.")] = None,
    id: Annotated[str | None, typer.Option(help="Episode id; default a new one.")] = None,
    data: DataOption = None,
) -> None:
    """Begin an episode."""
    specs = _arguments(argument)
    with _memory(data) as memory:
        _print(memory.begin(activity, activity_type=type, arguments=specs, begin=at, episode_id=id))


@app.command("import")
def import_command(
    bag: Annotated[Path, typer.Argument(help="A ROS 1 .bag file or a ROS 2 bag directory.")],
    activity: str,
    type: Annotated[str | None, typer.Option(help="Activity type.")] = None,
    argument: Annotated[
        list[str] | None, typer.Option("--argument", "-a", help="ROLE=VALUE, repeatable.")
    ] = None,
    id: Annotated[str | None, typer.Option(help="Episode id; default a new one.")] = None,
    data: DataOption = None,
) -> None:
    """Import a ROS bag as a finished episode (channels mapped, times kept); prints the
    episode and the topics skipped (type and count), and warns about them on stderr."""
    from episodes.streams import StreamError

    specs = _arguments(argument)
    with _memory(data) as memory:
        try:
            report = memory.import_bag_report(
                bag, activity, activity_type=type, arguments=specs, episode_id=id
            )
        except StreamError as error:
            raise _fail(str(error), 1) from None
        for topic in report.skipped:
            typer.echo(
                f"skipped {topic.topic}: {topic.count} messages of {topic.message_type}"
                " (no channel kind for this type)",
                err=True,
            )
        _print({**to_jsonable(report.episode), "skipped": report.skipped})


@app.command()
def end(
    episode: str,
    at: Annotated[str | None, typer.Option(help="End time (ISO 8601); default now.")] = None,
    data: DataOption = None,
) -> None:
    """End a running episode."""
    with _memory(data) as memory:
        _print(memory.end(episode, end=at))


@app.command()
def show(episode: str, data: DataOption = None) -> None:
    """Show everything about one episode."""
    with _memory(data) as memory:
        _print(memory.get(episode))


@app.command()
def delete(episode: str, data: DataOption = None) -> None:
    """Delete an episode everywhere (triples, stream and derived files)."""
    with _memory(data) as memory:
        memory.delete(episode)
        typer.echo(f"deleted episode {episode}")


@app.command("export-rdf")
def export_rdf(
    episode: str,
    output: Annotated[Path, typer.Option("-o", "--output", help="TriG file to write.")],
    data: DataOption = None,
) -> None:
    """Write one episode's triples (graph nodes, participants, scene links) as TriG."""
    with _memory(data) as memory:
        body = memory.export_rdf(episode)
    partial = output.with_name(output.name + ".part")
    partial.write_bytes(body)
    partial.replace(output)  # a reader never sees half a file
    typer.echo(f"wrote {len(body)} bytes to {output}")


@app.command("import-rdf")
def import_rdf(
    source: Annotated[Path, typer.Argument(help="A TriG file written by export-rdf.")],
    data: DataOption = None,
) -> None:
    """Load one episode's triples exported by export-rdf."""
    try:
        body = source.read_bytes()
    except OSError as error:
        raise _fail(f"source: cannot read {str(source)!r}: {error.strerror}", 1) from None
    with _memory(data) as memory:
        _print(memory.import_rdf(body))


@app.command()
def annotate(
    episode: str,
    key: str,
    value: str,
    author: Annotated[str | None, typer.Option()] = None,
    confidence: Annotated[float | None, typer.Option()] = None,
    start: Annotated[str | None, typer.Option(help="Range start inside the episode.")] = None,
    stop: Annotated[str | None, typer.Option("--end", help="Range end inside the episode.")] = None,
    data: DataOption = None,
) -> None:
    """Annotate an episode, optionally over a time range inside it."""
    with _memory(data) as memory:
        _print(
            memory.annotate(
                episode,
                key=key,
                value=value,
                author=author,
                confidence=confidence,
                start=start,
                end=stop,
            )
        )


@app.command()
def recall(
    activity: str,
    which: Annotated[str, typer.Option(help="first, last or nth.")] = "last",
    n: Annotated[int, typer.Option(help="With --which nth: 1 is the first time.")] = 1,
    agent: AgentOption = None,
    obj: ObjectOption = None,
    role: RoleOption = None,
    participant: ParticipantOption = None,
    now: NowOption = None,
    data: DataOption = None,
) -> None:
    """The first / last / n-th time <agent> did <activity> (with <object>), and when."""
    with _memory(data) as memory:
        found = memory.recall(
            Cue(activity, agent=agent, obj=obj, role=role, participant=participant),
            which=which,  # type: ignore[arg-type]
            n=n,
            now=_now(now),
        )
        _print(found)


@app.command("list")
def list_command(
    activity: str,
    agent: AgentOption = None,
    obj: ObjectOption = None,
    role: RoleOption = None,
    participant: ParticipantOption = None,
    now: NowOption = None,
    data: DataOption = None,
) -> None:
    """All episodes of an activity, oldest first."""
    cue = Cue(activity, agent=agent, obj=obj, role=role, participant=participant)
    with _memory(data) as memory:
        _print(memory.all(cue, now=_now(now)))


@app.command()
def count(
    activity: str,
    agent: AgentOption = None,
    obj: ObjectOption = None,
    role: RoleOption = None,
    participant: ParticipantOption = None,
    data: DataOption = None,
) -> None:
    """How many times <agent> did <activity> (with <object>, <participant> as <role>)."""
    cue = Cue(activity, agent=agent, obj=obj, role=role, participant=participant)
    with _memory(data) as memory:
        _print({"count": memory.count(cue)})


@app.command("argument")
def argument_command(
    episode: str,
    role: str,
    value: Annotated[
        str | None, typer.Argument(help="Who or what; omit with --remove for the whole role.")
    ] = None,
    author: Annotated[str | None, typer.Option(help="Who asserts (or retracts) it.")] = None,
    confidence: Annotated[float | None, typer.Option(help="0 to 1.")] = None,
    replace: Annotated[bool, typer.Option(help="Replace the arguments in this role.")] = False,
    remove: Annotated[bool, typer.Option(help="Retract instead of adding.")] = False,
    data: DataOption = None,
) -> None:
    """Add, replace (--replace) or remove (--remove) an argument after the fact."""
    with _memory(data) as memory:
        if remove:
            _print(memory.remove_argument(episode, role=role, value=value, author=author))
            return
        if value is None:
            raise _fail("value: got nothing, expected who or what takes the role", 2)
        _print(
            memory.add_argument(
                episode,
                role=role,
                value=value,
                author=author,
                confidence=confidence,
                replace=replace,
            )
        )


@app.command()
def between(start: str, stop: str, now: NowOption = None, data: DataOption = None) -> None:
    """What happened between two times (ISO 8601 with zones)."""
    with _memory(data) as memory:
        _print(memory.between(start, stop, now=_now(now)))


@app.command()
def knowledge(
    activity: Annotated[str | None, typer.Argument(help="One activity; default all.")] = None,
    data: DataOption = None,
) -> None:
    """What the episodes say about each activity: how often, first and last, with whom."""
    with _memory(data) as memory:
        _print(memory.knowledge(activity))


@app.command()
def lacking(
    activity: str,
    augmentation: str,
    versions: Annotated[int, typer.Option(help="Fewer runs than this count as lacking.")] = 1,
    data: DataOption = None,
) -> None:
    """Which episodes of <activity> lack <augmentation>."""
    with _memory(data) as memory:
        found = memory.lacking(activity, augmentation, versions=versions)
        _print([{"episode": summary, "runs": runs} for summary, runs in found])


@app.command()
def runs(episode: str, data: DataOption = None) -> None:
    """The augmentation runs of an episode."""
    with _memory(data) as memory:
        _print(memory.runs(episode))


@app.command()
def rate(
    episode: str,
    run: str,
    person: str,
    value: int,
    question: Annotated[str | None, typer.Option(help="The question answered.")] = None,
    replace: Annotated[bool, typer.Option(help="Revise this person's earlier answer.")] = False,
    session: Annotated[
        str | None, typer.Option(help="The feedback episode it is given in (see `feedback`).")
    ] = None,
    data: DataOption = None,
) -> None:
    """Store a person's 1-10 rating of an augmentation run (one answer per question)."""
    with _memory(data) as memory:
        _print(
            memory.rate(
                episode,
                run,
                person=person,
                value=value,
                question=question,
                replace=replace,
                session=session,
            )
        )


@app.command()
def feedback(
    person: Annotated[str, typer.Argument(help="Who rates (the feedback episode's agent).")],
    rated: Annotated[
        list[str] | None, typer.Option("--rated", help="An episode shown for rating; repeatable.")
    ] = None,
    at: Annotated[str | None, typer.Option(help="Begin time (ISO 8601); default now.")] = None,
    id: Annotated[str | None, typer.Option(help="Episode id; default a new one.")] = None,
    data: DataOption = None,
) -> None:
    """Begin a rating session, recorded as a feedback episode; end it with `end`."""
    with _memory(data) as memory:
        _print(memory.begin_feedback(person, rated=rated or [], begin=at, episode_id=id))


@app.command("session-ratings")
def session_ratings(session: str, data: DataOption = None) -> None:
    """The ratings given in a feedback episode, in the order given."""
    with _memory(data) as memory:
        _print(memory.session_ratings(session))


@app.command()
def rank(
    augmentation: str,
    episode: Annotated[str | None, typer.Option(help="Only this episode's runs.")] = None,
    alpha: Annotated[float, typer.Option(help="Significance level (Wilcoxon).")] = 0.05,
    question: Annotated[str | None, typer.Option(help="Rank by this question.")] = None,
    data: DataOption = None,
) -> None:
    """Rank the rated runs of an augmentation (quartile heuristic, Wilcoxon signed-rank)."""
    with _memory(data) as memory:
        _print(memory.rank(augmentation, episode_id=episode, alpha=alpha, question=question))
