"""What a recording's two sides share, under one lock: the providers with their counts, the
bytes waiting in the queue, the last tick's time and the writer's failure.

The producer side (:class:`episodes.streams.recorder.Recorder`) registers providers, counts
the samples it receives and drops, and reserves queue bytes for those it queues; the writer
thread (:class:`episodes.streams.tick_writer.TickWriter`) counts the samples it stores,
releases their bytes, and records its failure, after which the producer drops every sample
(reason ``write_error``).
"""

import datetime as dt
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from episodes.streams.messages import ProviderSpec

__all__ = ["ChannelStats", "Ledger", "Provider", "Tick"]

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

    def copy(self) -> "ChannelStats":
        """A copy that later counting leaves unchanged."""
        return ChannelStats(**{**self.__dict__, "dropped": dict(self.dropped)})


@dataclass
class Provider:
    """A registered provider: its settings and counts; ``next_due_ns`` is when its rate limit
    lets the next sample in, ``written`` whether its provider record is in the file."""

    spec: ProviderSpec
    stats: ChannelStats
    next_due_ns: int = -1
    active: bool = True
    written: bool = False


@dataclass
class Tick:
    """One tick on its way to the writer: each queued sample with its provider, sensor stamp,
    checked value and the queue bytes it holds."""

    frame: int
    time_ns: int
    samples: list[tuple[Provider, int, Any, int]]


@dataclass
class Ledger:
    """The shared state of one recording; every field is read and changed under ``lock``."""

    lock: threading.Lock = field(default_factory=threading.Lock)
    providers: dict[str, Provider] = field(default_factory=dict)
    queued_bytes: int = 0
    """Bytes of queued samples the writer has not yet written or dropped."""
    last_tick_ns: int = -1
    """The last queued tick's time; -1 before the first."""
    failure: BaseException | None = None
    """Why the writer stopped writing, once it has."""

    def count_write_errors(self, tick: Tick, *, release: bool) -> None:
        """Count the tick's samples as dropped by a failed writer, and give back their queue
        bytes if ``release``."""
        with self.lock:
            for provider, _stamp, _value, size in tick.samples:
                stats = provider.stats
                stats.dropped["write_error"] = stats.dropped.get("write_error", 0) + 1
                if release:
                    self.queued_bytes -= size
