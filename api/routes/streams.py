"""``/episodes/{episode_id}/streams``: record an episode's sensor streams, replay and export them.

Writes need the bearer token when one is configured. Samples come as a JSON batch of ticks,
as a binary batch (``application/x-engram-batch``, see ``episodes.streams.wire``), or one
sample per request as a raw binary body with ``X-Engram-*`` headers. Replay is streamed as
NDJSON, one frame per line. Bags live under ``<data_dir>/streams/<episode id>``.
"""

from __future__ import annotations

import logging
import shutil
import tarfile
import tempfile
from collections.abc import Iterator
from itertools import chain
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from fastapi import APIRouter, Depends, Header, Query, Request, Response, status
from fastapi.responses import StreamingResponse
from pydantic import BaseModel, ConfigDict, Field
from starlette.background import BackgroundTask
from starlette.concurrency import run_in_threadpool

from api.deps import EpisodesDep, RecordingsDep, SettingsDep, require_token
from episodes.streams import (
    InvalidSampleError,
    Kind,
    Recorder,
    RecordingStateError,
    TickResult,
    UnknownProviderError,
    bag_path,
    check_episode_id,
    export_bag,
)
from episodes.streams.wire import (
    BATCH_MEDIA_TYPE,
    DTYPES,
    TickRequest,
    decode_batch,
    decode_json_batch,
    encode_frame,
)

__all__ = ["router", "streams_root"]

log = logging.getLogger(__name__)


def streams_root(data_dir: Path) -> Path:
    """The directory holding one bag directory per episode."""
    return data_dir / "streams"


router = APIRouter(prefix="/episodes/{episode_id}/streams", tags=["streams"])

WriteGuard = [Depends(require_token)]


def _episode(episode_id: str) -> str:
    return check_episode_id(episode_id)


def _tick_json(result: TickResult) -> dict[str, Any]:
    return {
        "frame": result.frame,
        "time_ns": result.time_ns,
        "queued": list(result.queued),
        "dropped": result.dropped,
    }


class OpenRequest(BaseModel):
    """Options of a new recording."""

    model_config = ConfigDict(extra="forbid")
    max_queue_bytes: int = Field(256 * 1024 * 1024, gt=0, le=16 * 1024**3)
    flush_interval_s: float = Field(0.5, gt=0, le=60)
    compression: Literal["zstd"] | None = None


class ProviderRequest(BaseModel):
    """A provider to register: name, kind and the settings of that kind."""

    model_config = ConfigDict(extra="forbid")
    name: str
    kind: Kind
    dtype: str | None = None
    shape: list[int] | None = None
    encoding: str | None = None
    names: list[str] | None = None
    sample_rate: int | None = None
    channels: int | None = None
    rate_limit_hz: float | None = None
    baseline: float | list[Any] | None = None
    threshold: float | None = Field(
        None,
        description="Skin filter bound θ: an element within θ of its baseline is stored as the "
        "baseline (recorded with the stream); 0 or none is lossless.",
    )


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    dependencies=WriteGuard,
    summary="Start recording an episode's streams",
)
def open_recording(
    episode_id: str,
    registry: RecordingsDep,
    settings: SettingsDep,
    memory: EpisodesDep,
    body: OpenRequest | None = None,
) -> dict[str, Any]:
    path = bag_path(streams_root(settings.data_dir), _episode(episode_id))
    memory.check_recordable(episode_id)  # 404 for no such episode, 409 when it has ended
    options = (body or OpenRequest()).model_dump()
    recorder = registry.open(episode_id, path, **options)
    return {"episode": episode_id, "path": str(recorder.path), "recording": True}


@router.get("", summary="Recording state, or what a finished recording holds")
def recording_status(
    episode_id: str, registry: RecordingsDep, episodes: EpisodesDep
) -> dict[str, Any]:
    if episode_id in registry:
        recorder = registry.get(episode_id)
        return {
            "episode": episode_id,
            "recording": True,
            "queued_bytes": recorder.queued_bytes,
            "channels": [s.as_dict() for s in recorder.stats()],
        }
    replayer = episodes.streams.replayer(_episode(episode_id))
    return {
        "episode": episode_id,
        "recording": False,
        "complete": replayer.complete,
        "frames": replayer.frame_count,
        "start_ns": replayer.start_ns,
        "end_ns": replayer.end_ns,
        "channels": [
            {
                "provider": name,
                "channel": spec.topic,
                "kind": spec.kind.value,
                "message_type": spec.msgtype,
                "count": count,
            }
            for (name, spec), count in zip(
                replayer.providers.items(), replayer.counts().values(), strict=True
            )
        ],
    }


@router.post(
    "/providers",
    status_code=status.HTTP_201_CREATED,
    dependencies=WriteGuard,
    summary="Register a provider (typed channel)",
)
def add_provider(episode_id: str, body: ProviderRequest, registry: RecordingsDep) -> dict[str, Any]:
    settings = body.model_dump(exclude_none=True, exclude={"name", "kind"})
    spec = registry.get(episode_id).add_provider(body.name, body.kind, **settings)
    return spec.config()


@router.delete(
    "/providers/{provider:path}",
    status_code=status.HTTP_204_NO_CONTENT,
    dependencies=WriteGuard,
    summary="Stop accepting a provider's samples",
)
def remove_provider(episode_id: str, provider: str, registry: RecordingsDep) -> Response:
    registry.get(episode_id).remove_provider(provider)
    return Response(status_code=status.HTTP_204_NO_CONTENT)


def _record(recorder: Recorder, ticks: list[TickRequest]) -> list[dict[str, Any]]:
    # check every tick of the batch first, so a bad one refuses the whole batch
    for i, tick in enumerate(ticks):
        unknown = [name for name in tick.samples if name not in recorder.providers]
        if unknown:
            raise UnknownProviderError(f"ticks[{i}].samples: provider {unknown[0]!r} unknown")
    return [
        _tick_json(recorder.tick(t.samples, time_ns=t.time_ns, stamps_ns=t.stamps_ns))
        for t in ticks
    ]


@router.post(
    "/samples",
    dependencies=WriteGuard,
    summary="Record a batch of ticks (JSON, or application/x-engram-batch)",
)
async def post_samples(
    episode_id: str,
    request: Request,
    registry: RecordingsDep,
    content_type: Annotated[str, Header()] = "application/json",
) -> dict[str, Any]:
    recorder = registry.get(episode_id)
    body = await request.body()
    media = content_type.split(";")[0].strip().lower()
    if media == BATCH_MEDIA_TYPE:
        ticks = await run_in_threadpool(decode_batch, body)
    elif media == "application/json":
        ticks = await run_in_threadpool(decode_json_batch, body)
    else:
        raise InvalidSampleError("content-type", media, f"application/json or {BATCH_MEDIA_TYPE}")
    return {"ticks": await run_in_threadpool(_record, recorder, ticks)}


def _header_int(name: str, value: str | None) -> int | None:
    if value is None:
        return None
    try:
        return int(value)
    except ValueError:
        raise InvalidSampleError(name, value, "an integer (ns since the epoch)") from None


@router.post(
    "/providers/{provider:path}/samples",
    dependencies=WriteGuard,
    summary="Record one sample from a raw binary body (its own tick)",
)
async def post_raw_sample(
    episode_id: str,
    provider: str,
    request: Request,
    registry: RecordingsDep,
    x_engram_dtype: Annotated[str | None, Header()] = None,
    x_engram_shape: Annotated[str | None, Header()] = None,
    x_engram_time_ns: Annotated[str | None, Header()] = None,
    x_engram_stamp_ns: Annotated[str | None, Header()] = None,
) -> dict[str, Any]:
    recorder = registry.get(episode_id)
    spec = recorder.providers.get(provider)
    if spec is None:
        raise UnknownProviderError(f"provider: {provider!r} is not registered")
    body = await request.body()
    value: Any
    if spec.kind is Kind.STRING:
        try:
            value = body.decode()
        except UnicodeDecodeError:
            raise InvalidSampleError("body", f"{len(body)} bytes", "UTF-8 text") from None
    else:
        dtype = x_engram_dtype or _default_dtype(spec.kind, spec.dtype, spec.encoding)
        if dtype not in DTYPES:
            raise InvalidSampleError("x-engram-dtype", dtype, f"one of {sorted(DTYPES)}")
        itemsize = np.dtype(dtype).itemsize
        if len(body) % itemsize:
            raise InvalidSampleError("body", f"{len(body)} bytes", f"a multiple of {itemsize}")
        array = np.frombuffer(body, dtype=np.dtype(dtype).newbyteorder("<"))
        if x_engram_shape:
            try:
                shape = [int(n) for n in x_engram_shape.split(",")]
                array = array.reshape(shape)
            except ValueError:
                raise InvalidSampleError(
                    "x-engram-shape", x_engram_shape, f"comma-separated sizes of {array.size} items"
                ) from None
        value = array
    stamp = _header_int("x-engram-stamp-ns", x_engram_stamp_ns)
    result = await run_in_threadpool(
        recorder.tick,
        {provider: value},
        time_ns=_header_int("x-engram-time-ns", x_engram_time_ns),
        stamps_ns={provider: stamp} if stamp is not None else None,
    )
    return _tick_json(result)


def _default_dtype(kind: Kind, dtype: str, encoding: str) -> str:
    if kind is Kind.FLOAT_ARRAY:
        return dtype
    if kind is Kind.IMAGE:
        return {"mono16": "uint16", "16UC1": "uint16", "32FC1": "float32"}.get(encoding, "uint8")
    if kind is Kind.AUDIO:
        return "int16" if encoding == "s16le" else "float32"
    return "float64"


@router.post("/close", dependencies=WriteGuard, summary="Finish the recording")
async def close_recording(episode_id: str, registry: RecordingsDep) -> dict[str, Any]:
    stats = await run_in_threadpool(registry.close, episode_id)
    return {"episode": episode_id, "channels": [s.as_dict() for s in stats]}


@router.get("/replay", summary="Replay as NDJSON, one frame per line")
def replay(
    episode_id: str,
    registry: RecordingsDep,
    episodes: EpisodesDep,
    mode: Annotated[Literal["frames", "realtime"], Query()] = "frames",
    speed: Annotated[float, Query(gt=0, le=1000)] = 1.0,
    channels: Annotated[list[str] | None, Query()] = None,
    start_ns: Annotated[int | None, Query(ge=0)] = None,
    start_frame: Annotated[int | None, Query(ge=0)] = None,
    end_ns: Annotated[int | None, Query(ge=0)] = None,
) -> StreamingResponse:
    if episode_id in registry:
        raise RecordingStateError(f"episode_id: {episode_id!r} is still recording")
    replayer = episodes.streams.replayer(_episode(episode_id))
    if start_ns is not None and start_frame is not None:
        raise InvalidSampleError("start_frame", start_frame, "either start_ns or start_frame")
    if start_ns is not None:
        replayer.seek(time_ns=start_ns)
    elif start_frame is not None:
        replayer.seek(frame=start_frame)
    frames = (
        replayer.play(channels, speed=speed, end_ns=end_ns)
        if mode == "realtime"
        else replayer.frames(channels, end_ns=end_ns)
    )
    first = next(frames, None)  # errors (unknown channel) surface here, before streaming
    lines: Iterator[bytes] = (
        encode_frame(f) for f in (chain([first], frames) if first is not None else ())
    )
    return StreamingResponse(lines, media_type="application/x-ndjson")


@router.get("/export", summary="The episode as a standalone rosbag2 directory (tar)")
def export(
    episode_id: str,
    registry: RecordingsDep,
    memory: EpisodesDep,
    with_runs: Annotated[
        bool,
        Query(
            description="Add every augmentation run's derived channels, each as its own "
            "topic /augmentations/<name>/v<version>/<channel>."
        ),
    ] = False,
) -> Response:
    if episode_id in registry:
        raise RecordingStateError(f"episode_id: {episode_id!r} is still recording")
    source = memory.streams.local(_episode(episode_id))
    work = Path(tempfile.mkdtemp(prefix="engram-export-"))
    try:
        if with_runs:
            memory.runs.files.export(episode_id, work / episode_id, with_runs=True)
        else:
            export_bag(source, work / episode_id, limit_bytes=memory.streams.read_limit_bytes)
        archive = work / f"{episode_id}.tar"
        with tarfile.open(archive, "w") as tar:
            tar.add(work / episode_id, arcname=episode_id)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise

    def chunks() -> Iterator[bytes]:
        with archive.open("rb") as f:
            while block := f.read(1 << 20):
                yield block

    return StreamingResponse(
        chunks(),
        media_type="application/x-tar",
        headers={"Content-Disposition": f'attachment; filename="{episode_id}.tar"'},
        background=BackgroundTask(shutil.rmtree, work, ignore_errors=True),
    )
