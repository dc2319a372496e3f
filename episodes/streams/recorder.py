"""The recorder: one rosbag2 directory (MCAP storage) per episode, written on a background thread.

Producers call :meth:`Recorder.tick` with the samples of one recording tick. The samples are
checked and copied in the producer's thread, given one tick time and one frame number, and put
on a bounded queue; a writer thread serialises them and writes them through
:class:`episodes.streams.bagwrite.BagWriter` (MCAP with chunk, data and summary CRCs). A
producer never waits for the disk: when the queue's byte budget is spent, the sample is dropped
and counted (reason ``queue_full``), never lost silently. The writer closes the current MCAP
chunk and flushes the file every ``flush_interval_s`` (and passes each full chunk to the
operating system as soon as it is written), so a crash leaves a file readable up to the last
flushed chunk
(:class:`episodes.streams.Replayer` reads it, :func:`episodes.streams.recover` completes it).

File layout (all topics in one MCAP file, log time = tick time):

* ``/<provider>``: the samples, one typed channel per provider (see ``messages``);
* ``/engram/ticks`` (``engram_msgs/msg/Tick``): one record per tick, written after its samples:
  frame number, tick time, and for each sample its provider, its sensor's own timestamp and
  whether it is stored or equalled the provider's baseline (then restored on read);
* ``/engram/providers`` (``engram_msgs/msg/Provider``): each provider's settings and baseline;
* ``/engram/recording`` (``std_msgs/msg/String``): JSON with the episode id.

>>> import tempfile, pathlib
>>> with tempfile.TemporaryDirectory() as tmp:
...     rec = Recorder(pathlib.Path(tmp) / "ep", episode_id="ep")
...     _ = rec.add_provider("head", "joint_state", names=["neck", "eyes"])
...     rec.tick({"head": [0.1, 0.2]}).frame
...     [(s.provider, s.count_stored, s.count_received) for s in rec.close()]
1
[('head', 1, 1)]
"""

from __future__ import annotations

import datetime as dt
import json
import logging
import queue
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from episodes.streams import messages
from episodes.streams.bagwrite import COMPRESSIONS, BagWriter, mcap_file
from episodes.streams.errors import (
    InvalidSampleError,
    RecordingStateError,
    UnknownProviderError,
)
from episodes.streams.messages import PROVIDER_TYPE, TICK_TYPE, ProviderSpec

__all__ = ["ChannelStats", "Recorder", "TickResult", "mcap_file"]

log = logging.getLogger(__name__)

TICKS_TOPIC = "/engram/ticks"
PROVIDERS_TOPIC = "/engram/providers"
RECORDING_TOPIC = "/engram/recording"
FORMAT_VERSION = 1
_MAX_NS = 2**63 - 1
_EPOCH = dt.datetime(1970, 1, 1, tzinfo=dt.UTC)


def _iso(ns: int | None) -> str | None:
    if ns is None:
        return None
    moment = _EPOCH + dt.timedelta(microseconds=ns // 1000)
    return moment.isoformat(timespec="microseconds").replace("+00:00", "Z")


@dataclass
class ChannelStats:
    """What happened to one provider's samples (times: ns since the UNIX epoch, UTC)."""

    provider: str
    channel: str
    message_type: str
    count_stored: int
    count_received: int
    dropped: dict[str, int]
    first_time_ns: int | None
    last_time_ns: int | None
    path: Path
    baseline_samples: int = 0
    bytes_written: int = 0
    write_seconds: float = 0.0
    """Time the writer thread spent filtering, encoding and writing this provider's samples."""

    @property
    def count_dropped(self) -> int:
        """All dropped samples, whatever the reason."""
        return sum(self.dropped.values())

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready values, times also as ISO 8601 UTC strings."""
        return {
            "provider": self.provider,
            "channel": self.channel,
            "message_type": self.message_type,
            "count_stored": self.count_stored,
            "count_received": self.count_received,
            "count_dropped": self.count_dropped,
            "dropped": dict(self.dropped),
            "baseline_samples": self.baseline_samples,
            "bytes_written": self.bytes_written,
            "write_seconds": round(self.write_seconds, 6),
            "first_time_ns": self.first_time_ns,
            "last_time_ns": self.last_time_ns,
            "first_time": _iso(self.first_time_ns),
            "last_time": _iso(self.last_time_ns),
            "path": str(self.path),
        }


@dataclass(frozen=True)
class TickResult:
    """The outcome of one tick: its frame number (None if nothing was kept) and time."""

    frame: int | None
    time_ns: int
    queued: tuple[str, ...]
    dropped: dict[str, str] = field(default_factory=dict)


@dataclass
class _Provider:
    spec: ProviderSpec
    stats: ChannelStats
    next_due_ns: int = -1
    active: bool = True
    written: bool = False


@dataclass
class _Tick:
    frame: int
    time_ns: int
    samples: list[tuple[_Provider, int, Any, int]]  # provider, stamp, value, queued bytes


class Recorder:
    """Records the typed streams of one episode into ``path`` (a new rosbag2 directory).

    Args:
        path: the bag directory to create; it must not exist yet.
        episode_id: stored in the file so every replayed sample names its episode.
        max_queue_bytes: memory the queue may hold before samples are dropped (and counted).
        flush_interval_s: the longest time a written sample waits before it is on disk.
        fsync: also ``os.fsync`` the file at each flush (survives power loss, costs I/O).
        compression: ``None``, ``"zstd"`` or ``"lz4"`` (MCAP chunk compression).
        clock: tick times in ns since the UNIX epoch; injectable for tests.

    Raises:
        RecordingStateError: ``path`` exists already.
        InvalidSampleError: a setting is out of range.
    """

    def __init__(
        self,
        path: Path | str,
        *,
        episode_id: str,
        max_queue_bytes: int = 256 * 1024 * 1024,
        flush_interval_s: float = 0.5,
        fsync: bool = False,
        compression: str | None = None,
        clock: Callable[[], int] = time.time_ns,
    ) -> None:
        self.path = Path(path)
        self.episode_id = episode_id
        if max_queue_bytes <= 0:
            raise InvalidSampleError("max_queue_bytes", max_queue_bytes, "a positive size")
        if not flush_interval_s > 0:
            raise InvalidSampleError("flush_interval_s", flush_interval_s, "a positive duration")
        if compression not in COMPRESSIONS:
            raise InvalidSampleError("compression", compression, "None, 'zstd' or 'lz4'")
        if self.path.exists():
            raise RecordingStateError(f"path: {str(self.path)!r} exists already")
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._max_queue_bytes = max_queue_bytes
        self._flush_interval_s = flush_interval_s
        self._fsync = fsync
        self._clock = clock
        self._lock = threading.Lock()
        self._providers: dict[str, _Provider] = {}
        self._queue: queue.SimpleQueue[Any] = queue.SimpleQueue()
        self._queued_bytes = 0
        self._frame = 0
        self._last_tick_ns = -1
        self._closed = False
        self._failure: BaseException | None = None
        self.writer_cpu_s = 0.0

        self._ts = messages.typestore()
        self._writer = BagWriter(
            self.path,
            typestore=self._ts,
            compression=compression,
            custom_data={"engram.episode": episode_id, "engram.format": str(FORMAT_VERSION)},
        )
        self._connections: dict[str, int] = {}
        for topic, msgtype in (
            (RECORDING_TOPIC, "std_msgs/msg/String"),
            (PROVIDERS_TOPIC, PROVIDER_TYPE),
            (TICKS_TOPIC, TICK_TYPE),
        ):
            self._connections[topic] = self._writer.add_connection(topic, msgtype)
        self._started = False
        self._thread = threading.Thread(
            target=self._run, name=f"engram-recorder-{episode_id}", daemon=True
        )
        self._thread.start()
        log.info("recording episode %s into %s", episode_id, self.path)

    # ----------------------------------------------------------------- producer side

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def queued_bytes(self) -> int:
        """Bytes of samples waiting for the writer."""
        return self._queued_bytes

    @property
    def providers(self) -> dict[str, ProviderSpec]:
        """The registered providers, by name."""
        with self._lock:
            return {name: p.spec for name, p in self._providers.items() if p.active}

    def add_provider(self, name: str, kind: str, **settings: Any) -> ProviderSpec:
        """Register a provider (a typed channel); possible at any time while recording.

        ``settings`` are those of :meth:`ProviderSpec.create` (``dtype``, ``shape``,
        ``encoding``, ``names``, ``sample_rate``, ``channels``, ``rate_limit_hz``,
        ``baseline``).

        Raises:
            InvalidSampleError: bad settings, or the name is taken with other settings.
            RecordingStateError: the recording is closed.
        """
        spec = ProviderSpec.create(name, kind, **settings)
        with self._lock:
            self._check_open()
            existing = self._providers.get(name)
            if existing is not None:
                if existing.spec == spec and _same_baseline(existing.spec, spec):
                    existing.active = True
                    return existing.spec
                raise InvalidSampleError(
                    "name", name, "a provider name not yet used with other settings"
                )
            stats = ChannelStats(
                provider=name,
                channel=spec.topic,
                message_type=spec.msgtype,
                count_stored=0,
                count_received=0,
                dropped={},
                first_time_ns=None,
                last_time_ns=None,
                path=mcap_file(self.path),
            )
            self._providers[name] = _Provider(spec, stats)
        log.info("episode %s: provider %s (%s)", self.episode_id, name, spec.kind.value)
        return spec

    def remove_provider(self, name: str) -> None:
        """Stop accepting samples from a provider; what it recorded stays.

        Raises:
            UnknownProviderError: no such provider.
        """
        with self._lock:
            provider = self._providers.get(name)
            if provider is None or not provider.active:
                raise UnknownProviderError(f"provider: {name!r} is not registered")
            provider.active = False

    def tick(
        self,
        samples: Mapping[str, Any],
        *,
        time_ns: int | None = None,
        stamps_ns: Mapping[str, int] | None = None,
    ) -> TickResult:
        """Record the samples of one tick; they share one tick time and one frame number.

        Args:
            samples: provider name -> sample value (see ``messages`` for each kind).
            time_ns: the tick time (ns since the epoch); default: the clock, kept increasing.
            stamps_ns: each sensor's own timestamp; default: the tick time.

        Returns:
            the frame number and time, the providers queued and those dropped (with reason
            ``rate_limit`` or ``queue_full``). Dropped samples are also counted in
            :meth:`stats`.

        Raises:
            InvalidSampleError, UnknownProviderError: bad input; nothing is recorded.
            RecordingStateError: the recording is closed.
        """
        stamps = dict(stamps_ns or {})
        for name in stamps:
            if name not in samples:
                raise InvalidSampleError("stamps_ns", name, "a provider that has a sample")
        for name, stamp in stamps.items():
            if isinstance(stamp, bool) or not isinstance(stamp, int) or not 0 <= stamp < _MAX_NS:
                raise InvalidSampleError(f"stamps_ns[{name}]", stamp, "ns since the epoch (int)")
        if time_ns is not None and (
            isinstance(time_ns, bool) or not isinstance(time_ns, int) or not 0 < time_ns < _MAX_NS
        ):
            raise InvalidSampleError("time_ns", time_ns, "ns since the epoch (positive int)")
        with self._lock:
            self._check_open()
            providers = []
            for name in samples:
                provider = self._providers.get(name)
                if provider is None or not provider.active:
                    raise UnknownProviderError(f"samples: provider {name!r} is not registered")
                providers.append(provider)
        checked = [messages.check(p.spec, samples[p.spec.name]) for p in providers]
        with self._lock:
            self._check_open()
            if time_ns is None:
                now = max(self._clock(), self._last_tick_ns + 1)
            elif time_ns <= self._last_tick_ns:
                raise InvalidSampleError(
                    "time_ns", time_ns, f"a tick time after the previous one ({self._last_tick_ns})"
                )
            else:
                now = time_ns
            queued: list[tuple[_Provider, int, Any, int]] = []
            dropped: dict[str, str] = {}
            for provider, value in zip(providers, checked, strict=True):
                spec, stats = provider.spec, provider.stats
                stamp = stamps.get(spec.name, now)
                stats.count_received += 1
                reason = None
                if self._failure is not None:
                    reason = "write_error"
                elif spec.rate_limit_hz is not None and stamp < provider.next_due_ns:
                    reason = "rate_limit"
                else:
                    size = messages.nbytes(value)
                    if self._queued_bytes + size > self._max_queue_bytes:
                        reason = "queue_full"
                if reason is not None:
                    stats.dropped[reason] = stats.dropped.get(reason, 0) + 1
                    dropped[spec.name] = reason
                    continue
                if spec.rate_limit_hz is not None:
                    period = 1e9 / spec.rate_limit_hz
                    # 5 % slack so jitter of a source at exactly the limit drops nothing
                    provider.next_due_ns = stamp + int(period * 0.95)
                self._queued_bytes += size
                queued.append((provider, stamp, value, size))
            if not queued:
                return TickResult(None, now, (), dropped)
            self._frame += 1
            self._last_tick_ns = now
            self._queue.put(_Tick(self._frame, now, queued))
            return TickResult(self._frame, now, tuple(p.spec.name for p, *_ in queued), dropped)

    def flush(self, timeout_s: float = 60.0) -> None:
        """Wait until everything queued so far is written and flushed to the file.

        Raises:
            RecordingStateError: closed, or the writer failed.
            TimeoutError: the writer did not catch up within ``timeout_s``.
        """
        done = threading.Event()
        with self._lock:
            self._check_open()
            self._queue.put(done)
        if not done.wait(timeout_s):
            raise TimeoutError(f"the writer did not flush within {timeout_s} s")
        if self._failure is not None:
            raise RecordingStateError(f"the writer failed: {self._failure}")

    def stats(self) -> list[ChannelStats]:
        """A snapshot of every provider's counts."""
        with self._lock:
            return [_copy_stats(p.stats) for p in self._providers.values()]

    def close(self, timeout_s: float = 300.0) -> list[ChannelStats]:
        """Write what is queued, complete the file (index, metadata.yaml) and return the counts.

        Raises:
            RecordingStateError: already closed.
        """
        with self._lock:
            self._check_open()
            self._closed = True
            self._queue.put(None)
        self._thread.join(timeout_s)
        if self._thread.is_alive():
            raise TimeoutError(f"the writer did not finish within {timeout_s} s")
        result = self.stats()
        log.info(
            "closed recording of episode %s: %d samples stored, %d dropped",
            self.episode_id,
            sum(s.count_stored for s in result),
            sum(s.count_dropped for s in result),
        )
        if self._failure is not None:
            log.error("episode %s: the writer failed: %s", self.episode_id, self._failure)
        return result

    def _check_open(self) -> None:
        if self._closed:
            raise RecordingStateError(f"the recording of episode {self.episode_id!r} is closed")

    # ----------------------------------------------------------------- writer side

    def _run(self) -> None:
        # chunks are closed and the file flushed here, so a crash loses at most
        # `flush_interval_s` of data
        cpu0 = time.thread_time()
        last_flush = time.monotonic()
        try:
            while True:
                item = self._queue.get()
                if item is None:
                    break
                if isinstance(item, threading.Event):
                    if self._failure is None:
                        self._write_pending_providers(self._record_time())
                        self._writer.flush(fsync=self._fsync)
                    item.set()
                    continue
                if self._failure is not None:
                    self._drop_failed(item, release=True)
                    continue
                try:
                    self._write_tick(item)
                    now = time.monotonic()
                    if now - last_flush >= self._flush_interval_s:
                        self._writer.flush(fsync=self._fsync)
                        last_flush = now
                    else:
                        self._writer.pass_on()  # a chunk the library completed
                except Exception as exc:  # disk full, I/O error: count, never lose silently
                    log.exception("episode %s: writing failed", self.episode_id)
                    self._failure = exc
                    self._drop_failed(item, release=False)
            if self._failure is None:
                self._write_pending_providers(self._record_time())
                self._writer.close()
            else:
                self._writer.abort()
        except Exception as exc:
            log.exception("episode %s: closing the bag failed", self.episode_id)
            self._failure = exc
        finally:
            self.writer_cpu_s = time.thread_time() - cpu0

    def _record_time(self) -> int:
        # provider records written outside a tick: at the last tick, or now if none yet
        return self._last_tick_ns if self._last_tick_ns > 0 else max(self._clock(), 1)

    def _write_pending_providers(self, time_ns: int) -> None:
        with self._lock:
            pending = [p for p in self._providers.values() if not p.written]
        if not pending:
            return
        types = self._ts.types
        if not self._started:
            self._started = True
            record = json.dumps({"episode": self.episode_id, "format": FORMAT_VERSION})
            data = self._ts.serialize_cdr(
                types["std_msgs/msg/String"](data=record), "std_msgs/msg/String"
            )
            self._writer.write(self._connections[RECORDING_TOPIC], time_ns, data)
        for provider in pending:
            spec = provider.spec
            baseline = spec.baseline
            msg = types[PROVIDER_TYPE](
                name=spec.name,
                kind=spec.kind.value,
                topic=spec.topic,
                config_json=messages.config_json(spec),
                baseline=(
                    np.frombuffer(baseline.tobytes(), dtype=np.uint8)
                    if baseline is not None
                    else np.zeros(0, dtype=np.uint8)
                ),
            )
            self._connections[spec.topic] = self._writer.add_connection(spec.topic, spec.msgtype)
            self._writer.write(
                self._connections[PROVIDERS_TOPIC],
                time_ns,
                self._ts.serialize_cdr(msg, PROVIDER_TYPE),
            )
            provider.written = True

    def _write_tick(self, tick: _Tick) -> None:
        self._write_pending_providers(tick.time_ns)
        names: list[str] = []
        stamps: list[int] = []
        stored: list[int] = []
        sizes: list[int] = []
        spent: list[float] = []
        try:
            for provider, stamp, value, _size in tick.samples:
                began = time.perf_counter()
                spec = provider.spec
                names.append(spec.name)
                stamps.append(stamp)
                sparse = None
                if spec.baseline is not None:
                    sparse = messages.sparse_of(spec, value)
                    if sparse is None:
                        stored.append(0)
                        sizes.append(0)
                        spent.append(time.perf_counter() - began)
                        continue
                msg = messages.encode(spec, stamp, value, sparse)
                data = self._ts.serialize_cdr(msg, spec.msgtype)
                self._writer.write(self._connections[spec.topic], tick.time_ns, data)
                stored.append(1)
                sizes.append(len(data))
                spent.append(time.perf_counter() - began)
            record = self._ts.types[TICK_TYPE](
                frame=tick.frame,
                tick_time_ns=tick.time_ns,
                providers=names,
                stamps_ns=np.asarray(stamps, dtype=np.int64),
                stored=np.asarray(stored, dtype=np.uint8),
            )
            self._writer.write(
                self._connections[TICKS_TOPIC],
                tick.time_ns,
                self._ts.serialize_cdr(record, TICK_TYPE),
            )
        finally:
            with self._lock:
                self._queued_bytes -= sum(size for *_, size in tick.samples)
        # counted only once the tick record is written: before it, the samples are unreadable
        with self._lock:
            for (provider, *_), flag, size, seconds in zip(
                tick.samples, stored, sizes, spent, strict=True
            ):
                stats = provider.stats
                stats.count_stored += 1
                stats.bytes_written += size
                stats.write_seconds += seconds
                stats.baseline_samples += 1 - flag
                if stats.first_time_ns is None:
                    stats.first_time_ns = tick.time_ns
                stats.last_time_ns = tick.time_ns

    def _drop_failed(self, tick: _Tick, *, release: bool) -> None:
        # after a write error nothing more is written; every later sample is counted
        with self._lock:
            for provider, _stamp, _value, size in tick.samples:
                stats = provider.stats
                stats.dropped["write_error"] = stats.dropped.get("write_error", 0) + 1
                if release:
                    self._queued_bytes -= size


def _same_baseline(a: ProviderSpec, b: ProviderSpec) -> bool:
    if a.baseline is None or b.baseline is None:
        return a.baseline is None and b.baseline is None
    return a.baseline.tobytes() == b.baseline.tobytes()


def _copy_stats(stats: ChannelStats) -> ChannelStats:
    return ChannelStats(**{**stats.__dict__, "dropped": dict(stats.dropped)})
