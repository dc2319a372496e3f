"""The autobiographical memory over HTTP: episodes, annotations, queries by cue, augmentation
runs and feedback. Thin routes over :class:`episodes.EpisodeMemory`; errors are mapped to HTTP
in ``api/errors.py`` (404 unknown, 422 bad value with field/value/expected, 409 wrong state).
Writes need the bearer token when one is configured.

The episode memory shares the app's recording registry with ``api/routes/streams.py``, so an
episode begun here with ``record`` takes samples there, and ending it here closes that
recording and describes its channels in the graph.
"""

import datetime as dt
from collections.abc import Iterator
from itertools import chain
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Body, Depends, Query, Request, Response, status
from fastapi.responses import StreamingResponse
from pydantic import BaseModel, ConfigDict, Field
from starlette.concurrency import run_in_threadpool

from api.deps import EpisodesDep, SettingsDep, require_token
from api.openapi_errors import error_responses
from api.security import saved_body
from episodes import (
    ArgumentSpec,
    Cue,
    DerivedSpec,
    ImportReport,
    InvalidInputError,
    to_jsonable,
)
from episodes.streams.wire import decode_value, encode_frame
from episodes.times import parse_time

__all__ = ["router"]

router = APIRouter(tags=["episodes"])
WRITE = [Depends(require_token)]


def _now(now: str | None) -> dt.datetime | None:
    return parse_time(now, "now") if now is not None else None


NowQuery = Annotated[
    str | None, Query(description="Reference time for phrases like 'one month ago' (ISO 8601).")
]
ActivityQuery = Annotated[str, Query(description="Activity name, e.g. babbling.")]
AgentQuery = Annotated[str | None, Query(description="Who is in the role 'agent' (name or IRI).")]
ObjectQuery = Annotated[str | None, Query(description="What is in the role 'object'.")]
RoleQuery = Annotated[
    str | None,
    Query(description="A role (recipient, partner, ...): with participant, who is in it."),
]
ParticipantQuery = Annotated[
    str | None, Query(description="Someone in `role`, or in any role when `role` is not given.")
]


def _cue(
    activity: ActivityQuery,
    agent: AgentQuery = None,
    object: ObjectQuery = None,
    role: RoleQuery = None,
    participant: ParticipantQuery = None,
) -> Cue:
    """The cue named by a request's query (a dependency of the routes that take one)."""
    return Cue(activity, agent=agent, obj=object, role=role, participant=participant)


CueQuery = Annotated[Cue, Depends(_cue)]


class _Strict(BaseModel):
    """A request body: an unknown field is refused (422 naming it), never silently dropped."""

    model_config = ConfigDict(extra="forbid")


class ArgumentIn(_Strict):
    role: str = Field(description="agent, object, recipient, ...")
    value: str = Field(description="A name or an IRI.")
    kind: Literal["agent", "entity"] | None = None


class BeginIn(_Strict):
    activity: str
    type: str | None = None
    arguments: list[ArgumentIn] = []
    begin: str | None = Field(None, description="ISO 8601 with a time zone; default now.")
    id: str | None = None
    record: bool = Field(False, description="Open a stream recording for the episode.")


class ImportIn(_Strict):
    path: str = Field(
        description="A ROS 1 .bag file or ROS 2 bag directory inside the server's data "
        "directory (absolute, or relative to it)."
    )
    activity: str
    type: str | None = None
    arguments: list[ArgumentIn] = []
    id: str | None = None


class EndIn(_Strict):
    end: str | None = None


class AnnotationIn(_Strict):
    key: str
    value: str
    author: str | None = None
    confidence: float | None = None
    start: str | None = None
    end: str | None = None


class ArgumentAddIn(_Strict):
    role: str = Field(description="agent, object, recipient, ...")
    value: str = Field(description="A name or an IRI.")
    kind: Literal["agent", "entity"] | None = None
    author: str | None = Field(None, description="Who asserts it (a person or a module).")
    confidence: float | None = Field(None, description="How sure the author is, 0 to 1.")
    time: str | None = Field(None, description="When it was asserted (ISO 8601); default now.")
    replace: bool = Field(False, description="Replace the arguments now in this role.")
    replaces: str | None = Field(
        None, description="With replace: only the argument with this value."
    )


class SceneIn(_Strict):
    scene: str = Field(description="IRI of an experienced scene of the scene memory.")


class RunIn(_Strict):
    name: str
    producer: str
    parameters: dict[str, Any] = {}


class SampleIn(_Strict):
    frame: int
    source_channel: str
    derived_channel: str
    value: Any = None


class SamplesIn(_Strict):
    samples: list[SampleIn]
    channels: dict[str, dict[str, Any]] = {}


class RatingIn(_Strict):
    person: str
    value: int
    time: str | None = None
    sample: int | None = None
    question: str | None = Field(
        None, description="The question answered (a name or IRI); one answer per person."
    )
    replace: bool = Field(False, description="Revise this person's earlier answer.")
    session: str | None = Field(
        None, description="The running feedback episode the rating is given in (its agent rates)."
    )


class FeedbackIn(_Strict):
    person: str = Field(description="Who rates: the agent of the feedback episode.")
    rated: list[str] = Field(
        default_factory=list, description="The episodes whose data is shown for rating."
    )
    begin: str | None = Field(None, description="When the session began (ISO 8601); now.")
    id: str | None = Field(None, description="The feedback episode's id; a new one.")


def _answer(value: Any) -> Any:
    return to_jsonable(value)


@router.post("/episodes", status_code=status.HTTP_201_CREATED, dependencies=WRITE)
async def begin(memory: EpisodesDep, body: BeginIn) -> Any:
    """Begin an episode (snapshot of the scene memory; optionally a stream recording)."""
    arguments = [ArgumentSpec(a.role, a.value, a.kind) for a in body.arguments]
    episode = await run_in_threadpool(
        memory.begin,
        body.activity,
        activity_type=body.type,
        arguments=arguments,
        begin=body.begin,
        episode_id=body.id,
        record=body.record,
    )
    return _answer(episode)


def _report(report: ImportReport) -> Any:
    """The imported episode, and the topics skipped with their type and count."""
    return {**_answer(report.episode), "skipped": _answer(report.skipped)}


@router.post(
    "/episodes/import",
    status_code=status.HTTP_201_CREATED,
    dependencies=WRITE,
    responses=error_responses(404),
)
async def import_bag(memory: EpisodesDep, settings: SettingsDep, body: ImportIn) -> Any:
    """Import a ROS 1 or ROS 2 bag inside the server's data directory as a finished episode;
    the answer lists the topics skipped (no channel kind for their type)."""
    arguments = [ArgumentSpec(a.role, a.value, a.kind) for a in body.arguments]
    source = await run_in_threadpool(memory.imports.source, body.path)
    report = await run_in_threadpool(
        memory.imports.bag_report,
        source,
        body.activity,
        activity_type=body.type,
        arguments=arguments,
        episode_id=body.id,
        name=body.path,
        max_decompressed_bytes=settings.max_decompressed_bytes,
    )
    return _report(report)


@router.post("/episodes/import/upload", status_code=status.HTTP_201_CREATED, dependencies=WRITE)
async def import_upload(
    memory: EpisodesDep,
    settings: SettingsDep,
    request: Request,
    activity: ActivityQuery,
    type: Annotated[str | None, Query(description="Activity type.")] = None,
    argument: Annotated[
        list[str] | None, Query(description="ROLE=VALUE, repeatable (kind from the role).")
    ] = None,
    id: Annotated[str | None, Query(description="Episode id; default a new one.")] = None,
) -> Any:
    """Import a bag sent as the body: a ROS 1 ``.bag`` file, or a tar of a ROS 2 bag
    directory; the answer lists the topics skipped."""
    arguments = []
    for i, text in enumerate(argument or []):
        role, sep, value = text.partition("=")
        if not sep:
            raise InvalidInputError(f"argument[{i}]", text, "ROLE=VALUE")
        arguments.append(ArgumentSpec(role, value))
    async with saved_body(request, memory.imports.uploads_dir) as upload:
        report = await run_in_threadpool(
            memory.imports.upload,
            upload,
            activity,
            activity_type=type,
            arguments=arguments,
            episode_id=id,
            max_decompressed_bytes=settings.max_decompressed_bytes,
            max_unpacked_bytes=settings.max_upload_bytes,
        )
    return _report(report)


@router.get("/episodes")
async def all_of_activity(
    memory: EpisodesDep,
    cue: CueQuery,
    now: NowQuery = None,
) -> Any:
    """All episodes of an activity (by an agent, with an object, with someone in a role),
    oldest first."""
    return _answer(await run_in_threadpool(memory.all, cue, now=_now(now)))


@router.get("/episodes/recall")
async def recall(
    memory: EpisodesDep,
    cue: CueQuery,
    which: Annotated[str, Query(description="first, last or nth")] = "last",
    n: Annotated[int, Query(description="With which=nth: 1 is the first time.")] = 1,
    now: NowQuery = None,
) -> Any:
    """The first / last / n-th time <agent> did <activity> (with <object>, with
    <participant> as <role>), and when, in words."""
    found = await run_in_threadpool(memory.recall, cue, which=which, n=n, now=_now(now))  # type: ignore[arg-type]
    return _answer(found)


@router.get("/episodes/count")
async def count(
    memory: EpisodesDep,
    cue: CueQuery,
) -> dict[str, int]:
    """How many times <agent> did <activity> (with <object>, with <participant> as <role>)."""
    return {"count": await run_in_threadpool(memory.count, cue)}


@router.get("/episodes/between")
async def between(
    memory: EpisodesDep,
    start: Annotated[str, Query(description="ISO 8601 with a time zone.")],
    end: Annotated[str, Query(description="ISO 8601 with a time zone.")],
    now: NowQuery = None,
) -> Any:
    """What happened between two times: the episodes that overlap them."""
    return _answer(await run_in_threadpool(memory.between, start, end, now=_now(now)))


@router.get("/episodes/knowledge")
async def knowledge(
    memory: EpisodesDep,
    activity: Annotated[str | None, Query(description="One activity; default all.")] = None,
) -> Any:
    """What the episodes say about each activity: how often, first and last, with whom."""
    return _answer(await run_in_threadpool(memory.knowledge, activity))


@router.post("/episodes/rdf", status_code=status.HTTP_201_CREATED, dependencies=WRITE)
async def import_rdf(memory: EpisodesDep, request: Request) -> Any:
    """Load one episode's triples (TriG, as ``GET /episodes/{id}/rdf`` gives them)."""
    return _answer(await run_in_threadpool(memory.import_rdf, await request.body()))


@router.get("/episodes/lacking")
async def lacking(
    memory: EpisodesDep,
    activity: ActivityQuery,
    augmentation: Annotated[str, Query(description="Augmentation name.")],
    versions: Annotated[int, Query(description="Fewer runs than this count as lacking.")] = 1,
) -> Any:
    """Which episodes of <activity> lack <augmentation> (have fewer than ``versions`` runs)."""
    found = await run_in_threadpool(memory.runs.lacking, activity, augmentation, versions=versions)
    return [{"episode": _answer(summary), "runs": runs} for summary, runs in found]


@router.get("/episodes/{episode_id}")
async def get(memory: EpisodesDep, episode_id: str) -> Any:
    """Everything about one episode."""
    return _answer(await run_in_threadpool(memory.get, episode_id))


@router.get("/episodes/{episode_id}/world")
async def world(memory: EpisodesDep, episode_id: str) -> Any:
    """What was on the table (the scene memory's current scene: primitives, the class it was
    stored as) and who was there at begin and end, and what changed."""
    return _answer(await run_in_threadpool(memory.world, episode_id))


@router.get("/episodes/{episode_id}/rdf")
async def export_rdf(memory: EpisodesDep, episode_id: str) -> Response:
    """The episode's triples as TriG: its graph nodes, participants, roles and scene links."""
    body = await run_in_threadpool(memory.export_rdf, episode_id)
    return Response(body, media_type="application/trig")


@router.post("/episodes/{episode_id}/end", dependencies=WRITE)
async def end(memory: EpisodesDep, episode_id: str, body: EndIn | None = None) -> Any:
    """End a running episode; its recording (if any) closes and its streams are described."""
    episode = await run_in_threadpool(memory.end, episode_id, end=body.end if body else None)
    return _answer(episode)


@router.delete("/episodes/{episode_id}", status_code=status.HTTP_204_NO_CONTENT, dependencies=WRITE)
async def delete(memory: EpisodesDep, episode_id: str) -> Response:
    """Delete an episode everywhere: triples, scene links, stream and derived files."""
    await run_in_threadpool(memory.delete, episode_id)
    return Response(status_code=status.HTTP_204_NO_CONTENT)


@router.post(
    "/episodes/{episode_id}/annotations", status_code=status.HTTP_201_CREATED, dependencies=WRITE
)
async def annotate(memory: EpisodesDep, episode_id: str, body: AnnotationIn) -> Any:
    """Annotate an episode, as a whole or over a time range inside it."""
    annotation = await run_in_threadpool(
        memory.annotate,
        episode_id,
        key=body.key,
        value=body.value,
        author=body.author,
        confidence=body.confidence,
        start=body.start,
        end=body.end,
    )
    return _answer(annotation)


@router.post(
    "/episodes/{episode_id}/arguments", status_code=status.HTTP_201_CREATED, dependencies=WRITE
)
async def add_argument(memory: EpisodesDep, episode_id: str, body: ArgumentAddIn) -> Any:
    """Add an argument after the fact (or replace the ones in its role), with its author,
    time and confidence kept as PROV; cues see it at once."""
    argument = await run_in_threadpool(
        memory.add_argument,
        episode_id,
        role=body.role,
        value=body.value,
        kind=body.kind,
        author=body.author,
        confidence=body.confidence,
        time=body.time,
        replace=body.replace,
        replaces=body.replaces,
    )
    return _answer(argument)


@router.delete("/episodes/{episode_id}/arguments/{role}", dependencies=WRITE)
async def remove_argument(
    memory: EpisodesDep,
    episode_id: str,
    role: str,
    value: Annotated[str | None, Query(description="Only the argument with this value.")] = None,
    author: Annotated[str | None, Query(description="Who retracts it.")] = None,
) -> Any:
    """Retract the arguments in a role (kept in the graph as invalidated); the answer lists
    them."""
    gone = await run_in_threadpool(
        memory.remove_argument, episode_id, role=role, value=value, author=author
    )
    return _answer(gone)


@router.post(
    "/episodes/{episode_id}/scenes", status_code=status.HTTP_204_NO_CONTENT, dependencies=WRITE
)
async def link_scene(memory: EpisodesDep, episode_id: str, body: SceneIn) -> Response:
    """Link an experienced scene of the scene memory to the episode it happened in."""
    await run_in_threadpool(memory.link_scene, episode_id, body.scene)
    return Response(status_code=status.HTTP_204_NO_CONTENT)


@router.post("/episodes/{episode_id}/runs", status_code=status.HTTP_201_CREATED, dependencies=WRITE)
async def start_run(memory: EpisodesDep, episode_id: str, body: RunIn) -> Any:
    """Start a new, versioned augmentation run on an episode."""
    run = await run_in_threadpool(
        memory.runs.start,
        episode_id,
        name=body.name,
        producer=body.producer,
        parameters=body.parameters,
    )
    return _answer(run)


@router.get("/episodes/{episode_id}/runs")
async def runs(memory: EpisodesDep, episode_id: str) -> Any:
    """The augmentation runs of an episode."""
    return _answer(await run_in_threadpool(memory.runs.of_episode, episode_id))


@router.post(
    "/episodes/{episode_id}/runs/{run_id}/samples",
    status_code=status.HTTP_201_CREATED,
    dependencies=WRITE,
)
async def add_samples(memory: EpisodesDep, episode_id: str, run_id: str, body: SamplesIn) -> Any:
    """Post derived samples, each linked to the recorded frame it was computed from; with
    values, their data goes into the run's stream file."""
    specs = [DerivedSpec(s.frame, s.source_channel, s.derived_channel) for s in body.samples]
    with_values = any(s.value is not None for s in body.samples)
    if with_values and any(s.value is None for s in body.samples):
        raise InvalidInputError("samples[].value", None, "a value for every sample, or for none")
    values = (
        [decode_value(f"samples[{i}].value", s.value) for i, s in enumerate(body.samples)]
        if with_values
        else None
    )
    added = await run_in_threadpool(
        memory.runs.add_derived, episode_id, run_id, specs, values=values, channels=body.channels
    )
    return _answer(added)


@router.get("/episodes/{episode_id}/runs/{run_id}/replay")
def replay_run(
    memory: EpisodesDep,
    episode_id: str,
    run_id: str,
    merge: Annotated[
        bool, Query(description="Beside the source frames (merged by frame), or alone.")
    ] = False,
    channels: Annotated[
        list[str] | None, Query(description="With merge: the source channels to include.")
    ] = None,
) -> StreamingResponse:
    """Replay a run's derived samples as NDJSON, one frame per line, numbered by the source
    frames; merged, the derived channels are named ``augmentations/<name>/v<version>/...``."""
    frames = memory.runs.files.replay(episode_id, run_id, merge=merge, channels=channels)
    first = next(frames, None)  # errors (unknown channel) surface before streaming
    lines: Iterator[bytes] = (
        encode_frame(f) for f in (chain([first], frames) if first is not None else ())
    )
    return StreamingResponse(lines, media_type="application/x-ndjson")


@router.post("/episodes/{episode_id}/runs/{run_id}/end", dependencies=WRITE)
async def end_run(memory: EpisodesDep, episode_id: str, run_id: str) -> Any:
    """Close an augmentation run."""
    return _answer(await run_in_threadpool(memory.runs.end, episode_id, run_id))


@router.post(
    "/episodes/{episode_id}/runs/{run_id}/ratings",
    status_code=status.HTTP_201_CREATED,
    dependencies=WRITE,
)
async def rate(
    memory: EpisodesDep, episode_id: str, run_id: str, body: Annotated[RatingIn, Body()]
) -> Any:
    """A person's 1-10 rating of a run (or of one of its derived samples)."""
    rating = await run_in_threadpool(
        memory.ratings.rate,
        episode_id,
        run_id,
        person=body.person,
        value=body.value,
        time=body.time,
        sample=body.sample,
        question=body.question,
        replace=body.replace,
        session=body.session,
    )
    return _answer(rating)


@router.post("/feedback-sessions", status_code=status.HTTP_201_CREATED, dependencies=WRITE)
async def begin_feedback(memory: EpisodesDep, body: FeedbackIn) -> Any:
    """Begin a rating session, recorded as a feedback episode (agent: the person rating;
    ``rated``: the episodes shown). Ratings sent with ``session`` belong to it; end it with
    ``POST /episodes/{id}/end``."""
    episode = await run_in_threadpool(
        memory.ratings.begin_session,
        body.person,
        rated=body.rated,
        begin=body.begin,
        episode_id=body.id,
    )
    return _answer(episode)


@router.get("/feedback-sessions/{session_id}/ratings")
async def session_ratings(memory: EpisodesDep, session_id: str) -> Any:
    """The ratings given in a feedback episode, in the order given."""
    return _answer(await run_in_threadpool(memory.ratings.of_session, session_id))


@router.get("/augmentations/{name}/versions")
async def versions(
    memory: EpisodesDep,
    name: str,
    episode: Annotated[str, Query(description="The episode whose runs to compare.")],
) -> Any:
    """The versions of one augmentation on one episode side by side (for a rating view):
    parameters, derived channels, rating summary, which are best."""
    return _answer(await run_in_threadpool(memory.runs.versions, name, episode))


class ClaimIn(_Strict):
    worker: str = Field(description="Who works on it (becomes the run's producer).")
    activity: str = Field(description="Episodes of this activity.")
    versions: int = Field(1, description="Episodes with fewer runs than this lack it.")
    lease_s: float = Field(60.0, description="Seconds the claim holds without a heartbeat.")
    wait_s: float = Field(0.0, description="Long-poll: wait up to this long for work (max 60).")


class LeaseIn(_Strict):
    lease_s: float = Field(60.0, description="Seconds the claim holds from now.")


@router.post(
    "/augmentations/{name}/claims",
    dependencies=WRITE,
    responses={204: {"description": "No episode lacks this augmentation (after waiting)"}},
)
async def claim(memory: EpisodesDep, name: str, body: ClaimIn) -> Any:
    """Claim an ended episode of the activity that lacks this augmentation: a run is started
    for the worker and the episode leased to it. 204 when there is no work (after waiting)."""
    found = await run_in_threadpool(
        memory.runs.queue.claim,
        name,
        worker=body.worker,
        activity=body.activity,
        versions=body.versions,
        lease_s=body.lease_s,
        wait_s=body.wait_s,
    )
    if found is None:
        return Response(status_code=status.HTTP_204_NO_CONTENT)
    return _answer(found)


@router.post("/augmentations/claims/{token}/heartbeat", dependencies=WRITE)
async def heartbeat(memory: EpisodesDep, token: str, body: LeaseIn | None = None) -> Any:
    """Keep a claim's lease; 404 when it expired (its unfinished run was discarded)."""
    lease = body.lease_s if body is not None else 60.0
    return _answer(await run_in_threadpool(memory.runs.queue.heartbeat, token, lease_s=lease))


@router.post("/augmentations/claims/{token}/complete", dependencies=WRITE)
async def complete(memory: EpisodesDep, token: str) -> Any:
    """End the claimed run and release the lease."""
    return _answer(await run_in_threadpool(memory.runs.queue.complete, token))


@router.get("/augmentations/{name}/ranking")
async def ranking(
    memory: EpisodesDep,
    name: str,
    episode: Annotated[str | None, Query(description="Only the runs of this episode.")] = None,
    alpha: Annotated[float, Query(description="Significance level of the Wilcoxon test.")] = 0.05,
    question: Annotated[
        str | None, Query(description="Rank by the answers to this question.")
    ] = None,
) -> Any:
    """Rank the rated candidates of an augmentation: quartile heuristic, then Wilcoxon."""
    found = await run_in_threadpool(
        memory.ratings.rank, name, episode_id=episode, alpha=alpha, question=question
    )
    return _answer(found)
