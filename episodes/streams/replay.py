"""Replay of a recorded episode: frame by frame, or in real time with late frames skipped.

Every replayed :class:`Sample` carries its provenance: episode, provider and channel, tick
time, frame number and the sensor's own timestamp. Samples a baseline filter left out of the
file come back equal to the baseline, bit for bit.

* :meth:`Replayer.frames` yields every frame in order, nothing skipped (for offline
  processors, as fast as the consumer reads).
* :meth:`Replayer.play` keeps the recording's clock, scaled by ``speed``: it waits until a
  frame is due, and when the consumer falls behind it sends, per channel, only the newest
  due sample and counts the skipped ones (:attr:`Replayer.skipped`).

Both start at the cursor set by :meth:`Replayer.seek` and can be limited to some channels.
The recording may be complete or cut short by a crash (read up to the last flushed chunk).
"""

from __future__ import annotations

import bisect
import json
import logging
import time
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from episodes.streams import messages
from episodes.streams.bagwrite import mcap_file
from episodes.streams.errors import (
    CorruptRecordingError,
    InvalidSampleError,
    RecordingNotFoundError,
    UnknownProviderError,
)
from episodes.streams.mcapread import LIMIT_BYTES, McapFile, MessageSource, RawMessage
from episodes.streams.messages import PROVIDER_TYPE, TICK_TYPE, Kind, ProviderSpec
from episodes.streams.tick_writer import PROVIDERS_TOPIC, RECORDING_TOPIC, TICKS_TOPIC

__all__ = ["Frame", "Replayer", "Sample", "TickInfo"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Sample:
    """One replayed sample and where it comes from."""

    episode: str
    provider: str
    channel: str
    kind: Kind
    time_ns: int
    frame: int
    stamp_ns: int
    value: Any
    from_baseline: bool = False


@dataclass(frozen=True)
class Frame:
    """The samples sent together: in :meth:`Replayer.frames` one recording tick; in
    :meth:`Replayer.play` the newest due sample of each channel (``number``/``time_ns``: the
    newest due tick)."""

    number: int
    time_ns: int
    samples: dict[str, Sample]


@dataclass(frozen=True)
class TickInfo:
    """The tick record of one frame."""

    frame: int
    time_ns: int
    providers: tuple[str, ...]
    stamps_ns: tuple[int, ...]
    stored: tuple[bool, ...]


def _damaged(file: Path, raw: RawMessage, error: Exception) -> CorruptRecordingError:
    return CorruptRecordingError(
        f"{file}: the {raw.topic} message logged at {raw.log_time} ns cannot be decoded: {error}"
    )


class Replayer:
    """Reads one recording (a rosbag2 directory written by the recorder, or its MCAP file).

    Args:
        path: the bag directory or its ``.mcap`` file.
        clock: seconds, monotonic; with ``sleep`` injectable for tests of :meth:`play`.
        scan: read the recording from this source instead (``path`` then only names it): a
            recording in object storage read by ranges (:mod:`episodes.streams.ranged`).
        limit_bytes: the most bytes one record or one decompressed chunk may take
            (:class:`~episodes.streams.mcapread.McapFile`); a file claiming more is corrupt.

    A recording that holds no message (an episode that recorded nothing) has no frames.

    Raises:
        RecordingNotFoundError: nothing at ``path``.
        CorruptRecordingError: not a recording made by the recorder.
    """

    def __init__(
        self,
        path: Path | str,
        *,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
        scan: MessageSource | None = None,
        limit_bytes: int = LIMIT_BYTES,
    ) -> None:
        path = Path(path)
        if scan is not None:
            file = path
        elif path.is_dir():
            file = mcap_file(path)
            if not file.exists():
                found = sorted(path.glob("*.mcap"))
                if len(found) != 1:
                    raise RecordingNotFoundError(f"path: no single .mcap file in {str(path)!r}")
                file = found[0]
        else:
            file = path
        self.path = file
        self._scan = scan if scan is not None else McapFile.open(file, limit_bytes=limit_bytes)
        self._clock, self._sleep = clock, sleep
        self._ts = messages.typestore()
        self.episode_id = ""
        self.providers: dict[str, ProviderSpec] = {}
        self.ticks: list[TickInfo] = []
        for raw in self._scan.messages({RECORDING_TOPIC, PROVIDERS_TOPIC, TICKS_TOPIC}):
            try:
                self._read_opening(raw)
            except messages.DECODE_ERRORS as error:
                raise _damaged(file, raw, error) from error
        if not self.episode_id:
            if self.providers or self.ticks or next(self._scan.messages(), None) is not None:
                raise CorruptRecordingError(f"{str(file)!r} has no /engram/recording record")
            # a recording that holds no message at all (nothing was recorded) replays as
            # empty; the recorder names its file after the episode
            self.episode_id = file.stem
        self.complete = self._scan.complete
        self._times = [t.time_ns for t in self.ticks]
        self._cursor = 0
        self.skipped = 0
        """Samples :meth:`play` did not send because a newer one of their channel was due."""

    def _read_opening(self, raw: RawMessage) -> None:
        """Take in one of the messages read when opening: a tick, a provider, the record."""
        if raw.topic == TICKS_TOPIC:
            t: Any = self._ts.deserialize_cdr(raw.data, TICK_TYPE)
            tick = TickInfo(
                int(t.frame),
                int(t.tick_time_ns),
                tuple(t.providers),
                tuple(int(x) for x in t.stamps_ns),
                tuple(bool(x) for x in t.stored),
            )
            if not len(tick.providers) == len(tick.stamps_ns) == len(tick.stored):
                raise ValueError("a tick lists providers, stamps and flags of unequal lengths")
            unknown = set(tick.providers) - self.providers.keys()
            if unknown:
                raise ValueError(f"a tick names providers never declared: {sorted(unknown)}")
            self.ticks.append(tick)
        elif raw.topic == PROVIDERS_TOPIC:
            p: Any = self._ts.deserialize_cdr(raw.data, PROVIDER_TYPE)
            self.providers[p.name] = ProviderSpec.from_config(
                json.loads(p.config_json), bytes(p.baseline)
            )
        else:
            text: Any = self._ts.deserialize_cdr(raw.data, "std_msgs/msg/String")
            record = json.loads(text.data)
            self.episode_id = str(record.get("episode", ""))

    # ------------------------------------------------------------------ info

    @property
    def frame_count(self) -> int:
        return len(self.ticks)

    @property
    def start_ns(self) -> int | None:
        return self.ticks[0].time_ns if self.ticks else None

    @property
    def end_ns(self) -> int | None:
        return self.ticks[-1].time_ns if self.ticks else None

    def counts(self) -> dict[str, int]:
        """Samples per provider (stored or restored from the baseline)."""
        out = dict.fromkeys(self.providers, 0)
        for tick in self.ticks:
            for name in tick.providers:
                out[name] = out.get(name, 0) + 1
        return out

    # ------------------------------------------------------------------ navigation

    def seek(self, *, time_ns: int | None = None, frame: int | None = None) -> int:
        """Move the cursor to the first frame at or after ``time_ns`` or ``frame``.

        Returns the index of that frame (``frame_count`` if past the end).

        Raises:
            InvalidSampleError: neither or both given, or not an integer.
        """
        if (time_ns is None) == (frame is None):
            raise InvalidSampleError("seek", {"time_ns": time_ns, "frame": frame}, "exactly one")
        target = time_ns if time_ns is not None else frame
        if isinstance(target, bool) or not isinstance(target, int):
            raise InvalidSampleError("time_ns" if frame is None else "frame", target, "an integer")
        if time_ns is not None:
            self._cursor = bisect.bisect_left(self._times, time_ns)
        else:
            self._cursor = bisect.bisect_left([t.frame for t in self.ticks], target)
        return self._cursor

    def _selected(self, channels: Collection[str] | None) -> set[str]:
        if channels is None:
            return set(self.providers)
        if isinstance(channels, str):
            channels = [channels]
        chosen = set()
        for name in channels:
            key = name[1:] if name.startswith("/") else name
            if key not in self.providers:
                raise UnknownProviderError(
                    f"channels: {name!r} is not a channel of this recording "
                    f"(have {sorted(self.providers)})"
                )
            chosen.add(key)
        return chosen

    # ------------------------------------------------------------------ replay

    def frames(
        self,
        channels: Collection[str] | None = None,
        *,
        end_ns: int | None = None,
    ) -> Iterator[Frame]:
        """Every frame from the cursor on (up to ``end_ns`` inclusive), nothing skipped.

        Frames with no sample on the chosen channels are left out.
        """
        chosen = self._selected(channels)
        first = self._cursor
        if first >= len(self.ticks):
            return
        topics = {self.providers[name].topic for name in chosen}
        stream = self._scan.messages(topics, start_ns=self.ticks[first].time_ns)
        pending: RawMessage | None = next(stream, None)
        for tick in self.ticks[first:]:
            if end_ns is not None and tick.time_ns > end_ns:
                return
            stored: dict[str, RawMessage] = {}
            while pending is not None and pending.log_time <= tick.time_ns:
                if pending.log_time == tick.time_ns:
                    stored[pending.topic] = pending
                pending = next(stream, None)
            samples: dict[str, Sample] = {}
            for name, stamp, is_stored in zip(
                tick.providers, tick.stamps_ns, tick.stored, strict=True
            ):
                if name not in chosen:
                    continue
                spec = self.providers[name]
                if is_stored:
                    raw = stored.get(spec.topic)
                    if raw is None:
                        log.warning("frame %d: sample of %s missing", tick.frame, name)
                        continue
                    try:
                        value = messages.decode(
                            spec, self._ts.deserialize_cdr(raw.data, raw.msgtype)
                        )
                    except messages.DECODE_ERRORS as error:
                        raise _damaged(self.path, raw, error) from error
                elif spec.baseline is None:
                    raise CorruptRecordingError(
                        f"{self.path}: frame {tick.frame} leaves out a sample of {name}, "
                        "which has no baseline to restore it from"
                    )
                else:
                    value = spec.baseline.copy()
                samples[name] = Sample(
                    self.episode_id,
                    name,
                    spec.topic,
                    spec.kind,
                    tick.time_ns,
                    tick.frame,
                    stamp,
                    value,
                    from_baseline=not is_stored,
                )
            if samples:
                yield Frame(tick.frame, tick.time_ns, samples)

    def play(
        self,
        channels: Collection[str] | None = None,
        *,
        speed: float = 1.0,
        end_ns: int | None = None,
    ) -> Iterator[Frame]:
        """Replay in real time (scaled by ``speed``), sending only the newest due samples.

        Raises:
            InvalidSampleError: ``speed`` is not a positive number.
        """
        if isinstance(speed, bool) or not isinstance(speed, int | float) or not 0 < speed < 1e6:
            raise InvalidSampleError("speed", speed, "a positive factor (1.0 = real time)")
        self.skipped = 0
        source = self.frames(channels, end_ns=end_ns)
        current = next(source, None)
        if current is None:
            return
        base_ns = current.time_ns
        start = self._clock()

        def due_in(frame: Frame) -> float:
            return (frame.time_ns - base_ns) / 1e9 / speed - (self._clock() - start)

        held: dict[str, Sample] = {}
        while current is not None:
            wait = due_in(current)
            if wait > 0:
                self._sleep(wait)
            for name, sample in current.samples.items():
                self.skipped += name in held
                held[name] = sample
            following = next(source, None)
            if following is not None and due_in(following) <= 0:
                current = following  # late: a newer frame is due already
                continue
            yield Frame(current.number, current.time_ns, held)
            held = {}
            current = following
