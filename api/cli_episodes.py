"""``engram episodes ...``: the autobiographical memory from the command line.

Each command does one thing and prints JSON: on the data directory opened here, or through the
server that holds it (or ``--server``), with the same request the HTTP API takes. Bad input
exits with status 2 and a message naming the field, the value and what was expected; something
not found exits with status 1.
"""

import json
import tarfile
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from api.cli_common import DataOption, ServerOption, TokenOption, call, fail, reach, settings_for

if TYPE_CHECKING:
    from episodes import ArgumentSpec, EpisodeMemory

__all__ = ["app"]

app = typer.Typer(
    help="Autobiographical memory: episodes, queries by cue, augmentation runs, ratings.",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
)

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

Local = Callable[["EpisodeMemory"], Any]


def _run(
    data: Path | None,
    server: str | None,
    token: str | None,
    local: Local,
    method: str,
    path: str,
    **request: Any,
) -> Any:
    """``local`` on the episodes of the data directory, or ``method path`` with ``request``
    on the server that holds it; the answer as JSON values."""
    from api.services import Services
    from episodes import EpisodeError, InvalidInputError, NotFoundError, to_jsonable

    with reach(settings_for(data), server, token) as memory:
        if not isinstance(memory, Services):
            return call(memory, method, path, **request)
        try:
            return to_jsonable(local(memory.episodes))
        except InvalidInputError as error:
            fail(str(error), 2)
        except (NotFoundError, EpisodeError) as error:
            fail(str(error), 1)


def _print(value: Any) -> None:
    typer.echo(json.dumps(value, indent=2, ensure_ascii=False))


def _arguments(values: list[str] | None) -> list["ArgumentSpec"]:
    from episodes import ArgumentSpec

    specs = []
    for i, text in enumerate(values or []):
        role, sep, value = text.partition("=")
        if not sep:
            fail(f"argument[{i}]: got {text!r}, expected ROLE=VALUE", 2)
        specs.append(ArgumentSpec(role.strip(), value.strip()))
    return specs


def _cue(
    activity: str,
    agent: str | None,
    obj: str | None,
    role: str | None,
    participant: str | None,
) -> tuple[Any, dict[str, str]]:
    """The cue, and the same as query parameters."""
    from episodes import Cue

    cue = Cue(activity, agent=agent, obj=obj, role=role, participant=participant)
    given = {"activity": activity, "agent": agent, "object": obj}
    given |= {"role": role, "participant": participant}
    return cue, {key: value for key, value in given.items() if value is not None}


def _now(now: str | None) -> Any:
    from episodes.times import parse_time

    return parse_time(now, "now") if now is not None else None


def _given(**values: Any) -> dict[str, Any]:
    return {key: value for key, value in values.items() if value is not None}


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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Begin an episode."""
    specs = _arguments(argument)
    body = _given(activity=activity, type=type, begin=at, id=id)
    body["arguments"] = [{"role": s.role, "value": s.value} for s in specs]
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.begin(
                activity, activity_type=type, arguments=specs, begin=at, episode_id=id
            ),
            "POST",
            "/episodes",
            json=body,
        )
    )


def _bag_body(bag: Path, chunk_bytes: int = 1 << 20) -> Iterator[bytes]:
    """What the upload takes, read as it is sent (nothing happens unless it is): a ROS 1 bag
    file as it is, a ROS 2 bag directory as a tar (spooled to a temporary file)."""
    with tempfile.TemporaryFile() if bag.is_dir() else bag.open("rb") as source:
        if bag.is_dir():
            with tarfile.open(fileobj=source, mode="w") as tar:
                tar.add(bag, arcname=bag.name)
            source.seek(0)
        while chunk := source.read(chunk_bytes):
            yield chunk


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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Import a ROS bag as a finished episode (channels mapped, times kept); prints the
    episode and the topics skipped (type and count), and warns about them on stderr."""
    from episodes.streams import StreamError

    if not bag.exists():
        fail(f"bag: {str(bag)!r} does not exist", 2)
    specs = _arguments(argument)

    def local(memory: "EpisodeMemory") -> Any:
        from episodes import to_jsonable

        try:
            report = memory.imports.bag_report(
                bag, activity, activity_type=type, arguments=specs, episode_id=id
            )
        except StreamError as error:
            fail(str(error), 1)
        return {**to_jsonable(report.episode), "skipped": to_jsonable(report.skipped)}

    params = _given(activity=activity, type=type, id=id)
    params["argument"] = [f"{s.role}={s.value}" for s in specs]
    found = _run(
        data,
        server,
        token,
        local,
        "POST",
        "/episodes/import/upload",
        params=params,
        content=_bag_body(bag),
        headers={"Content-Type": "application/octet-stream"},
    )
    for topic in found.get("skipped", []):
        typer.echo(
            f"skipped {topic['topic']}: {topic['count']} messages of {topic['message_type']}"
            " (no channel kind for this type)",
            err=True,
        )
    _print(found)


@app.command()
def end(
    episode: str,
    at: Annotated[str | None, typer.Option(help="End time (ISO 8601); default now.")] = None,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """End a running episode."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.end(episode, end=at),
            "POST",
            f"/episodes/{episode}/end",
            json=_given(end=at),
        )
    )


@app.command()
def show(
    episode: str, data: DataOption = None, server: ServerOption = None, token: TokenOption = None
) -> None:
    """Show everything about one episode."""
    _print(_run(data, server, token, lambda m: m.get(episode), "GET", f"/episodes/{episode}"))


@app.command()
def delete(
    episode: str, data: DataOption = None, server: ServerOption = None, token: TokenOption = None
) -> None:
    """Delete an episode everywhere (triples, stream and derived files)."""
    _run(data, server, token, lambda m: m.delete(episode), "DELETE", f"/episodes/{episode}")
    typer.echo(f"deleted episode {episode}")


@app.command("export-rdf")
def export_rdf(
    episode: str,
    output: Annotated[Path, typer.Option("-o", "--output", help="TriG file to write.")],
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Write one episode's triples (graph nodes, participants, scene links) as TriG."""
    body = _run(
        data,
        server,
        token,
        lambda m: m.export_rdf(episode).decode(),
        "GET",
        f"/episodes/{episode}/rdf",
    )
    content = body if isinstance(body, bytes) else body.encode()
    partial = output.with_name(output.name + ".part")
    partial.write_bytes(content)
    partial.replace(output)  # a reader never sees half a file
    typer.echo(f"wrote {len(content)} bytes to {output}")


@app.command("import-rdf")
def import_rdf(
    source: Annotated[Path, typer.Argument(help="A TriG file written by export-rdf.")],
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Load one episode's triples exported by export-rdf."""
    try:
        body = source.read_bytes()
    except OSError as error:
        fail(f"source: cannot read {str(source)!r}: {error.strerror}", 1)
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.import_rdf(body),
            "POST",
            "/episodes/rdf",
            content=body,
            headers={"Content-Type": "application/trig"},
        )
    )


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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Annotate an episode, optionally over a time range inside it."""
    fields = _given(author=author, confidence=confidence, start=start, end=stop)
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.annotate(
                episode,
                key=key,
                value=value,
                author=author,
                confidence=confidence,
                start=start,
                end=stop,
            ),
            "POST",
            f"/episodes/{episode}/annotations",
            json={"key": key, "value": value, **fields},
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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """The first / last / n-th time <agent> did <activity> (with <object>), and when."""
    cue, params = _cue(activity, agent, obj, role, participant)
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.recall(cue, which=which, n=n, now=_now(now)),  # type: ignore[arg-type]
            "GET",
            "/episodes/recall",
            params={**params, "which": which, "n": n, **_given(now=now)},
        )
    )


@app.command("list")
def list_command(
    activity: str,
    agent: AgentOption = None,
    obj: ObjectOption = None,
    role: RoleOption = None,
    participant: ParticipantOption = None,
    now: NowOption = None,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """All episodes of an activity, oldest first."""
    cue, params = _cue(activity, agent, obj, role, participant)
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.all(cue, now=_now(now)),
            "GET",
            "/episodes",
            params={**params, **_given(now=now)},
        )
    )


@app.command()
def count(
    activity: str,
    agent: AgentOption = None,
    obj: ObjectOption = None,
    role: RoleOption = None,
    participant: ParticipantOption = None,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """How many times <agent> did <activity> (with <object>, <participant> as <role>)."""
    cue, params = _cue(activity, agent, obj, role, participant)
    _print(
        _run(
            data,
            server,
            token,
            lambda m: {"count": m.count(cue)},
            "GET",
            "/episodes/count",
            params=params,
        )
    )


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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Add, replace (--replace) or remove (--remove) an argument after the fact."""
    if remove:
        _print(
            _run(
                data,
                server,
                token,
                lambda m: m.remove_argument(episode, role=role, value=value, author=author),
                "DELETE",
                f"/episodes/{episode}/arguments/{role}",
                params=_given(value=value, author=author),
            )
        )
        return
    if value is None:
        fail("value: got nothing, expected who or what takes the role", 2)
    body = _given(role=role, value=value, author=author, confidence=confidence)
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.add_argument(
                episode,
                role=role,
                value=value,
                author=author,
                confidence=confidence,
                replace=replace,
            ),
            "POST",
            f"/episodes/{episode}/arguments",
            json={**body, "replace": replace},
        )
    )


@app.command()
def between(
    start: str,
    stop: str,
    now: NowOption = None,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """What happened between two times (ISO 8601 with zones)."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.between(start, stop, now=_now(now)),
            "GET",
            "/episodes/between",
            params={"start": start, "end": stop, **_given(now=now)},
        )
    )


@app.command()
def knowledge(
    activity: Annotated[str | None, typer.Argument(help="One activity; default all.")] = None,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """What the episodes say about each activity: how often, first and last, with whom."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.knowledge(activity),
            "GET",
            "/episodes/knowledge",
            params=_given(activity=activity),
        )
    )


@app.command()
def lacking(
    activity: str,
    augmentation: str,
    versions: Annotated[int, typer.Option(help="Fewer runs than this count as lacking.")] = 1,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Which episodes of <activity> lack <augmentation>."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: [
                {"episode": summary, "runs": runs}
                for summary, runs in m.runs.lacking(activity, augmentation, versions=versions)
            ],
            "GET",
            "/episodes/lacking",
            params={"activity": activity, "augmentation": augmentation, "versions": versions},
        )
    )


@app.command()
def runs(
    episode: str, data: DataOption = None, server: ServerOption = None, token: TokenOption = None
) -> None:
    """The augmentation runs of an episode."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.runs.of_episode(episode),
            "GET",
            f"/episodes/{episode}/runs",
        )
    )


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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Store a person's 1-10 rating of an augmentation run (one answer per question)."""
    body = {"person": person, "value": value, "replace": replace}
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.ratings.rate(
                episode,
                run,
                person=person,
                value=value,
                question=question,
                replace=replace,
                session=session,
            ),
            "POST",
            f"/episodes/{episode}/runs/{run}/ratings",
            json={**body, **_given(question=question, session=session)},
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
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Begin a rating session, recorded as a feedback episode; end it with `end`."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.ratings.begin_session(person, rated=rated or [], begin=at, episode_id=id),
            "POST",
            "/feedback-sessions",
            json={"person": person, "rated": rated or [], **_given(begin=at, id=id)},
        )
    )


@app.command("session-ratings")
def session_ratings(
    session: str, data: DataOption = None, server: ServerOption = None, token: TokenOption = None
) -> None:
    """The ratings given in a feedback episode, in the order given."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.ratings.of_session(session),
            "GET",
            f"/feedback-sessions/{session}/ratings",
        )
    )


@app.command()
def rank(
    augmentation: str,
    episode: Annotated[str | None, typer.Option(help="Only this episode's runs.")] = None,
    alpha: Annotated[float, typer.Option(help="Significance level (Wilcoxon).")] = 0.05,
    question: Annotated[str | None, typer.Option(help="Rank by this question.")] = None,
    data: DataOption = None,
    server: ServerOption = None,
    token: TokenOption = None,
) -> None:
    """Rank the rated runs of an augmentation (quartile heuristic, Wilcoxon signed-rank)."""
    _print(
        _run(
            data,
            server,
            token,
            lambda m: m.ratings.rank(
                augmentation, episode_id=episode, alpha=alpha, question=question
            ),
            "GET",
            f"/augmentations/{augmentation}/ranking",
            params={"alpha": alpha, **_given(episode=episode, question=question)},
        )
    )
