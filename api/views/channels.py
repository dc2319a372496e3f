"""An episode's recorded channels for the episode view: coverage, numeric channels decimated
for plotting, and the frames of a channel for a scrubber.

A channel's numbers are read from the stream file once and kept (a few channels, keyed by the
file's size and modification time, so a file that changed is read again); decimation then runs
on numpy arrays: the samples fall into at most ``points / 2`` equal-count buckets and each bucket
gives its first time with its minimum and its last time with its maximum, so spikes survive.

>>> import numpy as np
>>> t = np.arange(10, dtype=float)
>>> x, ys = decimate(t, np.arange(10.0)[None, :] ** 2, points=4)
>>> x.tolist(), ys.tolist()
([0.0, 4.0, 5.0, 9.0], [[0.0, 16.0, 25.0, 81.0]])
"""

import threading
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from api.views import series as series_scan
from api.views.models import ChannelInfo, ChannelList, FrameList, PlotData
from episodes.streams import (
    InvalidSampleError,
    Kind,
    RecordingNotFoundError,
    Replayer,
    UnknownProviderError,
)
from episodes.streams.mcapread import LIMIT_BYTES

__all__ = ["MAX_POINTS", "channel_list", "decimate", "frame_list", "plot_data"]

MAX_POINTS = 2000
"""The most points a plot request may ask for."""
COVERAGE_BINS = 100
MAX_SERIES = 16
"""The most series of one channel a plot carries (the first ones)."""
_NUMERIC = {Kind.FLOAT_ARRAY, Kind.JOINT_STATE}


@dataclass(frozen=True)
class _Series:
    names: list[str]
    time_ns: NDArray[np.int64]
    values: NDArray[np.float64]
    """shape (series, samples)"""


_cache: "OrderedDict[tuple[str, int, int, str], Any]" = OrderedDict()
_cache_lock = threading.Lock()
_CACHE_SIZE = 8


def _cached(path: Path, key: str, compute: Any) -> Any:
    stat = path.stat()
    full = (str(path), stat.st_size, stat.st_mtime_ns, key)
    with _cache_lock:
        if full in _cache:
            _cache.move_to_end(full)
            return _cache[full]
    value = compute()
    with _cache_lock:
        _cache[full] = value
        while len(_cache) > _CACHE_SIZE:
            _cache.popitem(last=False)
    return value


def _replayer(path: Path, limit_bytes: int) -> Replayer:
    if not path.exists():
        raise RecordingNotFoundError(f"episode: nothing was recorded at {path.name!r}")
    replayer: Replayer = _cached(_file(path), "", lambda: Replayer(path, limit_bytes=limit_bytes))
    return replayer


def _file(path: Path) -> Path:
    if path.is_dir():
        found = sorted(path.glob("*.mcap"))
        if found:
            return found[0]
    return path


def channel_list(episode_id: str, path: Path, *, limit_bytes: int = LIMIT_BYTES) -> ChannelList:
    """The channels of the recording at ``path`` with their sample counts and coverage (from
    the file's indexes when it has them, else by replaying its tick records); ``limit_bytes``
    bounds each record and decompressed chunk read (here and in the functions below).

    Raises ``RecordingNotFoundError`` when nothing was recorded."""
    if not path.exists():
        raise RecordingNotFoundError(f"episode: nothing was recorded at {path.name!r}")
    indexed = _cached(
        _file(path),
        "times",
        lambda: series_scan.recording_times(_file(path), limit_bytes=limit_bytes),
    )
    if indexed is not None:
        ticks, providers, samples = indexed.ticks, indexed.providers, indexed.samples
    else:
        replayer = _replayer(path, limit_bytes)
        providers = replayer.providers
        ticks = np.asarray([t.time_ns for t in replayer.ticks], dtype=np.int64)
        times: dict[str, list[int]] = {name: [] for name in providers}
        for tick in replayer.ticks:
            for name in tick.providers:
                times.setdefault(name, []).append(tick.time_ns)
        samples = {name: np.asarray(t, dtype=np.int64) for name, t in times.items()}
    start = int(ticks[0]) if len(ticks) else None
    end = int(ticks[-1]) if len(ticks) else None
    span = (end - start) if start is not None and end is not None and end > start else 0
    channels = []
    for name, spec in sorted(providers.items()):
        stamps = samples.get(name, np.zeros(0, np.int64))
        if len(stamps) and start is not None:
            bins = (
                np.minimum((stamps - start) * COVERAGE_BINS // span, COVERAGE_BINS - 1)
                if span
                else np.zeros(len(stamps), dtype=np.int64)
            )
            coverage = np.bincount(bins, minlength=COVERAGE_BINS).tolist()
            first_s, last_s = (stamps[0] - start) / 1e9, (stamps[-1] - start) / 1e9
        else:
            coverage, first_s, last_s = [0] * COVERAGE_BINS, None, None
        channels.append(
            ChannelInfo(
                name=name,
                kind=spec.kind.value,
                samples=len(stamps),
                first_s=first_s,
                last_s=last_s,
                coverage=coverage,
                numeric=spec.kind in _NUMERIC,
                image=spec.kind is Kind.IMAGE,
            )
        )
    return ChannelList(
        episode=episode_id, start_ns=start, end_ns=end, frames=len(ticks), channels=channels
    )


def _spec(replayer: Replayer, channel: str) -> Any:
    key = channel.removeprefix("/")
    spec = replayer.providers.get(key)
    if spec is None:
        raise UnknownProviderError(
            f"channel: {channel!r} is not a channel of this recording "
            f"(have {sorted(replayer.providers)})"
        )
    return key, spec


def _read_series(replayer: Replayer, channel: str, spec: Any) -> _Series:
    times: list[int] = []
    rows: list[NDArray[np.float64]] = []
    names: list[str] = []
    for frame in replayer.frames([channel]):
        sample = frame.samples[channel]
        value = sample.value
        if spec.kind is Kind.JOINT_STATE:
            row = np.asarray(value["position"], dtype=np.float64).reshape(-1)
        else:
            row = np.asarray(value, dtype=np.float64).reshape(-1)
        times.append(sample.time_ns)
        rows.append(row[:MAX_SERIES])
    width = max((len(r) for r in rows), default=0)
    values = np.full((width, len(rows)), np.nan)
    for i, row in enumerate(rows):
        values[: len(row), i] = row
    if spec.kind is Kind.JOINT_STATE and spec.names:
        names = [f"{n} position" for n in spec.names[:width]]
    names += [f"{channel}[{i}]" for i in range(len(names), width)]
    return _Series(names, np.asarray(times, dtype=np.int64), values)


def decimate(
    t: NDArray[np.float64], values: NDArray[np.float64], *, points: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """At most ``points`` (even, at least 2) of ``values`` (series by samples) over times ``t``:
    all of them when few enough, else each bucket's first time with the minimum and last time
    with the maximum (per series)."""
    n = len(t)
    if n <= points:
        return t, values
    buckets = points // 2
    starts = (np.arange(buckets) * n) // buckets
    ends = np.append(starts[1:], n) - 1
    with np.errstate(all="ignore"):
        low = np.fmin.reduceat(values, starts, axis=1)
        high = np.fmax.reduceat(values, starts, axis=1)
    x = np.empty(2 * buckets)
    x[0::2], x[1::2] = t[starts], t[ends]
    ys = np.empty((values.shape[0], 2 * buckets))
    ys[:, 0::2], ys[:, 1::2] = low, high
    return x, ys


def _names(channel: str, spec: Any, width: int) -> list[str]:
    names = [f"{n} position" for n in spec.names[:width]] if spec.kind is Kind.JOINT_STATE else []
    return names + [f"{channel}[{i}]" for i in range(len(names), width)]


def _scanned_series(
    path: Path, key: str, limit_bytes: int
) -> tuple[Any, int | None, _Series | None]:
    """The channel's spec, the first tick time and its series when one scan of the file gives
    them (:mod:`api.views.series`); the series is None when only replay can read it."""
    scan = series_scan.scan_channel(_file(path), key, limit_bytes=limit_bytes)
    spec = scan.providers.get(key)
    if spec is None or scan.time_ns is None or scan.values is None:
        return spec, scan.start_ns, None
    values = scan.values[:, :MAX_SERIES].T.copy()
    return spec, scan.start_ns, _Series(_names(key, spec, values.shape[0]), scan.time_ns, values)


def plot_data(path: Path, channel: str, *, points: int, limit_bytes: int = LIMIT_BYTES) -> PlotData:
    """The numeric channel ``channel`` decimated to at most ``points`` points.

    Raises ``UnknownProviderError`` for a channel the file lacks and ``InvalidSampleError`` for
    one that holds no numbers (images, audio, text)."""
    if not path.exists():
        raise RecordingNotFoundError(f"episode: nothing was recorded at {path.name!r}")
    key = channel.removeprefix("/")
    spec, start, series = _cached(
        _file(path), "scan:" + key, lambda: _scanned_series(path, key, limit_bytes)
    )
    if series is None:  # baseline-filtered or unusual: replay it (slower, read once and kept)
        replayer = _replayer(path, limit_bytes)
        key, spec = _spec(replayer, channel)
        if spec.kind not in _NUMERIC:
            raise InvalidSampleError(
                "channel",
                channel,
                "a numeric channel (joint_state or float_array), not " + spec.kind,
            )
        series = _cached(_file(path), key, lambda: _read_series(replayer, key, spec))
        start = replayer.start_ns
    start = start or 0
    t = (series.time_ns - start) / 1e9
    x, ys = decimate(t, series.values, points=points)
    return PlotData(
        channel=key,
        series=series.names,
        samples=len(series.time_ns),
        t=x.tolist(),
        values=[[None if v != v else v for v in row] for row in ys.tolist()],
    )


def frame_list(
    path: Path, channel: str, *, offset: int, limit: int, limit_bytes: int = LIMIT_BYTES
) -> FrameList:
    """The frame numbers and times of the ticks holding a sample of ``channel``."""
    replayer = _replayer(path, limit_bytes)
    key, _ = _spec(replayer, channel)
    ticks = [t for t in replayer.ticks if key in t.providers]
    page = ticks[offset : offset + limit]
    return FrameList(
        channel=key,
        total=len(ticks),
        frames=[t.frame for t in page],
        time_ns=[t.time_ns for t in page],
    )
