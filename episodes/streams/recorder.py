"""The recorder: one rosbag2 directory (MCAP storage) per episode, written on a background thread.

This is the producer side. Producers call :meth:`Recorder.tick` with the samples of one
recording tick. The samples are checked and copied in the producer's thread, given one tick time
and one frame number, and put on a bounded queue, which the writer thread
(:class:`episodes.streams.tick_writer.TickWriter`, where the file's layout is described) drains
into the file. A producer never waits for the disk: when the queue's byte budget is spent, the
sample is dropped and counted (reason ``queue_full``), never lost silently; so are samples over
a provider's rate limit (``rate_limit``) and, once the writer has failed, every sample
(``write_error``). The counts are kept in the recording's
:class:`~episodes.streams.ledger.Ledger`, shared with the writer. A crash leaves a file readable
up to the last flushed chunk (:class:`episodes.streams.Replayer` reads it,
:func:`episodes.streams.recover` completes it).

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

import logging
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from episodes.streams import messages
from episodes.streams.bagwrite import mcap_file
from episodes.streams.errors import (
    InvalidSampleError,
    RecordingStateError,
    UnknownProviderError,
)
from episodes.streams.ledger import ChannelStats, Ledger, Provider, Tick
from episodes.streams.mcapwrite import COMPRESSIONS
from episodes.streams.messages import ProviderSpec
from episodes.streams.tick_writer import TickWriter

__all__ = [
    "Recorder",
    "TickResult",
]

log = logging.getLogger(__name__)

_MAX_NS = 2**63 - 1


@dataclass(frozen=True)
class TickResult:
    """The outcome of one tick: its frame number (None if nothing was kept) and time."""

    frame: int | None
    time_ns: int
    queued: tuple[str, ...]
    dropped: dict[str, str] = field(default_factory=dict)


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
        self._clock = clock
        self._ledger = Ledger()
        self._lock = self._ledger.lock
        self._providers = self._ledger.providers
        self._frame = 0
        self._closed = False
        self.writer = TickWriter(
            self.path,
            episode_id=episode_id,
            ledger=self._ledger,
            compression=compression,
            flush_interval_s=flush_interval_s,
            fsync=fsync,
            clock=clock,
        )
        """The writer thread, started here (its CPU time is ``writer.cpu_s`` once closed)."""
        log.info("recording episode %s into %s", episode_id, self.path)

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def queued_bytes(self) -> int:
        """Bytes of samples waiting for the writer."""
        return self._ledger.queued_bytes

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
            self._providers[name] = Provider(spec, stats)
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
        ledger = self._ledger
        with self._lock:
            self._check_open()
            if time_ns is None:
                now = max(self._clock(), ledger.last_tick_ns + 1)
            elif time_ns <= ledger.last_tick_ns:
                raise InvalidSampleError(
                    "time_ns",
                    time_ns,
                    f"a tick time after the previous one ({ledger.last_tick_ns})",
                )
            else:
                now = time_ns
            queued: list[tuple[Provider, int, Any, int]] = []
            dropped: dict[str, str] = {}
            for provider, value in zip(providers, checked, strict=True):
                spec, stats = provider.spec, provider.stats
                stamp = stamps.get(spec.name, now)
                stats.count_received += 1
                reason = None
                if ledger.failure is not None:
                    reason = "write_error"
                elif spec.rate_limit_hz is not None and stamp < provider.next_due_ns:
                    reason = "rate_limit"
                else:
                    size = messages.nbytes(value)
                    if ledger.queued_bytes + size > self._max_queue_bytes:
                        reason = "queue_full"
                if reason is not None:
                    stats.dropped[reason] = stats.dropped.get(reason, 0) + 1
                    dropped[spec.name] = reason
                    continue
                if spec.rate_limit_hz is not None:
                    period = 1e9 / spec.rate_limit_hz
                    # 5 % slack so jitter of a source at exactly the limit drops nothing
                    provider.next_due_ns = stamp + int(period * 0.95)
                ledger.queued_bytes += size
                queued.append((provider, stamp, value, size))
            if not queued:
                return TickResult(None, now, (), dropped)
            self._frame += 1
            ledger.last_tick_ns = now
            self.writer.put(Tick(self._frame, now, queued))
            return TickResult(self._frame, now, tuple(p.spec.name for p, *_ in queued), dropped)

    def flush(self, timeout_s: float = 60.0) -> None:
        """Wait until everything queued so far is written and flushed to the file.

        Raises:
            RecordingStateError: closed, or the writer failed.
            TimeoutError: the writer did not catch up within ``timeout_s``.
        """
        with self._lock:
            self._check_open()
            done = self.writer.request_flush()
        if not done.wait(timeout_s):
            raise TimeoutError(f"the writer did not flush within {timeout_s} s")
        if self._ledger.failure is not None:
            raise RecordingStateError(f"the writer failed: {self._ledger.failure}")

    def stats(self) -> list[ChannelStats]:
        """A snapshot of every provider's counts."""
        with self._lock:
            return [p.stats.copy() for p in self._providers.values()]

    def close(self, timeout_s: float = 300.0) -> list[ChannelStats]:
        """Write what is queued, complete the file (index, metadata.yaml) and return the counts.

        Raises:
            RecordingStateError: already closed.
        """
        with self._lock:
            self._check_open()
            self._closed = True
        self.writer.finish(timeout_s)
        result = self.stats()
        log.info(
            "closed recording of episode %s: %d samples stored, %d dropped",
            self.episode_id,
            sum(s.count_stored for s in result),
            sum(s.count_dropped for s in result),
        )
        if self._ledger.failure is not None:
            log.error("episode %s: the writer failed: %s", self.episode_id, self._ledger.failure)
        return result

    def _check_open(self) -> None:
        if self._closed:
            raise RecordingStateError(f"the recording of episode {self.episode_id!r} is closed")


def _same_baseline(a: ProviderSpec, b: ProviderSpec) -> bool:
    if a.baseline is None or b.baseline is None:
        return a.baseline is None and b.baseline is None
    return a.baseline.tobytes() == b.baseline.tobytes()
