"""``/views/...``: the JSON the web views read (memory graph, scenes, episodes, channel plots),
and ``/`` serving the pages themselves (``api/web/``). Read-only; pin and restore go through
the directive API like any other write."""

from pathlib import Path
from typing import Annotated

from fastapi import APIRouter, FastAPI, HTTPException, Query, Request, Response, status
from fastapi.responses import RedirectResponse
from fastapi.staticfiles import StaticFiles
from starlette.concurrency import run_in_threadpool

from api.deps import EpisodesDep, StoreDep
from api.openapi_errors import error_responses
from api.views import channels, graph, scenes, timeline
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
from reasoners.memory import SceneMemory

__all__ = ["WEB_DIR", "install", "router"]

WEB_DIR = Path(__file__).resolve().parent.parent / "web"
"""The static pages, scripts, styles and vendored libraries."""

router = APIRouter(tags=["views"])
_NOT_FOUND = error_responses(404)

Offset = Annotated[int, Query(ge=0, description="Entries to skip.")]


def _memory(request: Request) -> SceneMemory:
    memory: SceneMemory = request.app.state.scene_memory
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
    """For the live 3D view, which polls it; 404 while no scene is stored."""
    found = await run_in_threadpool(scenes.latest_scene, store)
    if found is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, "no scene is stored yet")
    return found


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
) -> EpisodeList:
    return await run_in_threadpool(timeline.episode_list, memory, offset=offset, limit=limit)


@router.get(
    "/views/episodes/{episode_id}/channels",
    summary="An episode's recorded channels",
    responses=_NOT_FOUND,
)
async def channel_list(memory: EpisodesDep, episode_id: str) -> ChannelList:
    path = memory.streams_path(check_id(episode_id, "episode_id"))
    return await run_in_threadpool(channels.channel_list, episode_id, path)


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
    path = memory.streams_path(check_id(episode_id, "episode_id"))
    return await run_in_threadpool(channels.plot_data, path, channel, points=points)


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
    path = memory.streams_path(check_id(episode_id, "episode_id"))
    return await run_in_threadpool(channels.frame_list, path, channel, offset=offset, limit=limit)


def install(app: FastAPI) -> None:
    """Add the view endpoints and serve the pages under ``/web/`` (``/`` leads there)."""
    app.include_router(router)
    app.mount("/web", StaticFiles(directory=WEB_DIR, html=True), name="web")
