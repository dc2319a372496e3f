"""``/views/...``: the JSON the web views read (memory graph, scenes, episodes, channel plots),
and ``/`` serving the pages themselves (``api/web/``). Read-only; pin and restore go through
the directive API like any other write."""

import asyncio
import logging
import time
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Annotated

from fastapi import APIRouter, FastAPI, HTTPException, Query, Request, Response, status
from fastapi.responses import RedirectResponse, StreamingResponse
from fastapi.staticfiles import StaticFiles
from starlette.concurrency import run_in_threadpool

from api.deps import EpisodesDep, StoreDep
from api.openapi_errors import error_responses
from api.routes import api_docs
from api.views import channels, graph, scenes, timeline
from api.views.live import LatestScene
from api.views.models import (
    ChannelList,
    ClassDetail,
    ClassList,
    EpisodeList,
    FrameList,
    PlotData,
    SceneDetail,
    SceneList,
)
from episodes.terms import check_id
from kg import Store
from reasoners.memory import SceneMemory

__all__ = ["WEB_DIR", "install", "router", "warm_up"]

log = logging.getLogger(__name__)

WEB_DIR = Path(__file__).resolve().parent.parent / "web"
"""The static pages, scripts, styles and vendored libraries."""

router = APIRouter(tags=["views"])
_NOT_FOUND = error_responses(404)

Offset = Annotated[int, Query(ge=0, description="Entries to skip.")]

LIVE_CHECK_S = 0.2
"""How often a live stream looks at the store's write counter (an integer read)."""
LIVE_STREAM_S = 15.0
"""A live stream ends after this long and the browser's EventSource reconnects by itself (and
is sent the latest scene again). A stopping server waits for open responses to finish, so an
open live view delays a stop by at most this."""
LIVE_DISCONNECT_CHECK_S = 1.0
"""How often a live stream with nothing to send checks that its client is still there."""
LIVE_RETRY_MS = 500
"""How long the browser waits before it reconnects."""


def _memory(request: Request) -> SceneMemory:
    memory: SceneMemory = request.app.state.services.scene_memory
    return memory


def _not_found(error: LookupError) -> HTTPException:
    return HTTPException(status.HTTP_404_NOT_FOUND, str(error))


def _json(model: SceneList) -> Response:
    # Serialised by pydantic in one pass: the graph of 10,000 classes is read in one request.
    return Response(model.model_dump_json(), media_type="application/json")


@router.get("/", include_in_schema=False)
async def index() -> RedirectResponse:
    return RedirectResponse("/web/")


@router.get("/views/classes", response_model=ClassList, summary="The memory graph's classes")
async def classes(
    request: Request,
    trash: Annotated[bool, Query(description="Include the forgotten classes.")] = False,
    q: Annotated[
        str | None,
        Query(max_length=200, description='A part of a name or of a relation ("isAboveOf").'),
    ] = None,
    offset: Offset = 0,
    limit: Annotated[int, Query(ge=1, le=50_000)] = 20_000,
    relations: Annotated[bool, Query(description="Include each class's relations.")] = True,
) -> Response:
    """Learned scene classes, simplest first, with normalised score, level, pinned and forgotten
    marks, direct superclasses and the signature in words."""
    body = await run_in_threadpool(
        graph.class_list_json,
        _memory(request),
        trash=trash,
        query=q,
        offset=offset,
        limit=limit,
        relations=relations,
    )
    return Response(body, media_type="application/json")


@router.get("/views/classes/{name}", summary="One class in detail", responses=_NOT_FOUND)
async def class_detail(request: Request, name: str) -> ClassDetail:
    """Its definition in words, counters, score and level (over time when the memory keeps a
    history), its children and its most recent stored scenes."""
    try:
        return await run_in_threadpool(graph.class_detail, _memory(request), name)
    except graph.UnknownClassError as error:
        raise _not_found(error) from None


@router.get("/views/scenes", response_model=SceneList, summary="Stored scenes, newest first")
async def scene_list(
    store: StoreDep,
    cls: Annotated[str | None, Query(alias="class", max_length=200)] = None,
    episode: Annotated[str | None, Query(max_length=200)] = None,
    offset: Offset = 0,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
) -> Response:
    page = await run_in_threadpool(
        scenes.scene_list, store, cls=cls, episode=episode, offset=offset, limit=limit
    )
    return _json(page)


@router.get("/views/scenes/latest", summary="The scene stored last", responses=_NOT_FOUND)
async def latest_scene(store: StoreDep) -> SceneDetail:
    """The scene stored last; 404 while no scene is stored (the live view follows
    ``/views/scenes/live``)."""
    found = await run_in_threadpool(scenes.latest_scene, store)
    if found is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, "no scene is stored yet")
    return found


def _live(request: Request, store: Store) -> LatestScene:
    """The app's one producer of the latest scene, made on first use."""
    state = request.app.state
    live: LatestScene | None = getattr(state, "live_scene", None)
    if live is None or live.store is not store:
        live = state.live_scene = LatestScene(store, check_s=LIVE_CHECK_S)
    return live


def _event(detail: SceneDetail, version: int) -> str:
    return f"event: scene\nid: {version}\ndata: {detail.model_dump_json()}\n\n"


async def _live_events(request: Request, store: Store, *, follow: bool) -> AsyncIterator[str]:
    """``scene`` events carrying the latest stored scene: one on connecting (when a scene is
    stored) and, when ``follow``, one each time a write stores a newer one (read once for all
    streams, by the app's :class:`~api.views.live.LatestScene`)."""
    yield f"retry: {LIVE_RETRY_MS}\n\n"
    if not follow:
        found = await run_in_threadpool(scenes.latest_scene, store)
        if found is not None:
            yield _event(found, store.generation)
        return
    began = time.monotonic()
    async with _live(request, store).watching() as live:
        seen, shown = live.version, None
        while True:
            detail = live.scene
            if detail is not None and detail.scene.iri != shown:
                shown = detail.scene.iri
                yield _event(detail, live.version)
            remaining = LIVE_STREAM_S - (time.monotonic() - began)
            if remaining <= 0:
                return
            seen = await live.newer(seen, timeout_s=min(LIVE_DISCONNECT_CHECK_S, remaining))
            if await request.is_disconnected():
                return


@router.get(
    "/views/scenes/live",
    summary="The latest stored scene, pushed as server-sent events",
    response_class=StreamingResponse,
    responses={200: {"content": {"text/event-stream": {}}}},
)
async def live_scenes(request: Request, store: StoreDep) -> StreamingResponse:
    """A ``text/event-stream`` for the live 3D view (``engram perceive --server`` and any other
    writer): each ``scene`` event's data is the scene as ``GET /views/scenes/{name}`` gives it.
    Writes are noticed within ``LIVE_CHECK_S``; the stream ends after ``LIVE_STREAM_S`` (15 s)
    and the browser reconnects. A client whose ``Accept`` header does not ask for
    ``text/event-stream`` (as every EventSource does) gets the current scene and the end."""
    follow = "text/event-stream" in request.headers.get("accept", "")
    return StreamingResponse(
        _live_events(request, store, follow=follow),
        media_type="text/event-stream",
        headers={"Cache-Control": "no-cache", "X-Accel-Buffering": "no"},
    )


@router.get(
    "/views/scenes/{name}", summary="A stored scene with its primitives", responses=_NOT_FOUND
)
async def scene_detail(store: StoreDep, name: str) -> SceneDetail:
    try:
        return await run_in_threadpool(scenes.scene_detail, store, name)
    except scenes.UnknownSceneError as error:
        raise _not_found(error) from None


@router.get("/views/episodes", summary="The episode timeline, oldest first")
async def episode_list(
    memory: EpisodesDep,
    offset: Offset = 0,
    limit: Annotated[int, Query(ge=1, le=500)] = 200,
    newest: Annotated[
        bool, Query(description="The newest `limit` episodes (`offset` is ignored).")
    ] = False,
) -> EpisodeList:
    return await run_in_threadpool(
        timeline.episode_list, memory, offset=offset, limit=limit, newest=newest
    )


@router.get(
    "/views/episodes/{episode_id}/channels",
    summary="An episode's recorded channels",
    responses=_NOT_FOUND,
)
async def channel_list(memory: EpisodesDep, episode_id: str) -> ChannelList:
    path = memory.streams.path(check_id(episode_id, "episode_id"))
    return await run_in_threadpool(
        channels.channel_list, episode_id, path, limit_bytes=memory.streams.read_limit_bytes
    )


@router.get(
    "/views/episodes/{episode_id}/plot",
    summary="A numeric channel, decimated",
    responses=_NOT_FOUND,
)
async def plot(
    memory: EpisodesDep,
    episode_id: str,
    channel: Annotated[str, Query(max_length=200)],
    points: Annotated[int, Query(ge=2, le=channels.MAX_POINTS)] = channels.MAX_POINTS,
) -> PlotData:
    """Per bucket of samples its minimum and maximum, at most ``points`` points in all."""
    path = memory.streams.path(check_id(episode_id, "episode_id"))
    return await run_in_threadpool(
        channels.plot_data,
        path,
        channel,
        points=points,
        limit_bytes=memory.streams.read_limit_bytes,
    )


@router.get(
    "/views/episodes/{episode_id}/frames",
    summary="The frames holding a channel",
    responses=_NOT_FOUND,
)
async def frames(
    memory: EpisodesDep,
    episode_id: str,
    channel: Annotated[str, Query(max_length=200)],
    offset: Offset = 0,
    limit: Annotated[int, Query(ge=1, le=100_000)] = 10_000,
) -> FrameList:
    path = memory.streams.path(check_id(episode_id, "episode_id"))
    return await run_in_threadpool(
        channels.frame_list,
        path,
        channel,
        offset=offset,
        limit=limit,
        limit_bytes=memory.streams.read_limit_bytes,
    )


async def warm_up(memory: SceneMemory, *, poll_s: float = 0.5) -> None:
    """Once the memory has loaded, derive the class list the graph page reads first (seconds for
    10,000 classes), in a worker thread, so the first page load finds it ready. Run as a task by
    the app's lifespan and cancelled with it."""
    while not memory.loaded.wait_ready(timeout_s=0):
        await asyncio.sleep(poll_s)
    try:
        await run_in_threadpool(graph.warm, memory)
    except Exception:  # only the first page load is slower then
        log.warning("the class list was not prepared ahead", exc_info=True)


def install(app: FastAPI) -> None:
    """Add the view endpoints and serve the pages under ``/web/`` (``/`` leads there), and the
    API reference at ``/docs`` from the same vendored files (api/routes/api_docs.py)."""
    app.include_router(router)
    api_docs.install(app, WEB_DIR / "docs.html")
    app.mount("/web", StaticFiles(directory=WEB_DIR, html=True), name="web")
