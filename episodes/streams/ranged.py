"""Reading an MCAP recording in object storage by ranged reads, without fetching the whole file.

:class:`RangedMcap` answers what :class:`episodes.streams.replay.Replayer` asks of a scan
(messages of some topics from some time on, in file order) from a complete MCAP file it can
only read by ranges (``read(start, length)``: an S3 ranged GET):

1. The tail of the file: its footer, which locates the summary section; from the summary the
   schemas, channels and chunk indexes (each chunk's offset, time span, channels, compression).
2. For each chunk that holds a wanted channel at or after the wanted time, in file order, read
   ahead ``window`` chunks at a time on a thread pool:

   * when only ``small_topics`` are wanted (the replayer's ticks and provider records, a few
     bytes between camera frames) and the chunk holds other channels too, its message index is
     read first, and then only the wanted messages' byte ranges, ranges closer than ``gap``
     bytes joined into one read (the whole chunk if they would cover a quarter of it);
   * otherwise, and when the chunk is compressed, the chunk is read whole.

Every chunk of a recording holds a few of the replayer's ticks, which it reads whole when it
opens; to open with a handful of reads instead of a few per chunk, the messages of some topics
(the ticks) can be saved beside the file when it is stored (:func:`write_messages`, a small
object fetched whole and given as ``preloaded``): those topics are then answered from it. The
same object holds the end of the file from its summary on (``tail``), so opening reads nothing
of the recording itself.

Ranged reads pay off only where a read's cost does not grow with the object (on S3 it does
not; on moto's test server it does, about 0.8 ms per MB of object: see ``bench/fleet.py``), so
the chunks are read ahead starting with one and doubling up to ``window``.

A file without a summary (a recording cut short by a crash) raises
:class:`CorruptRecordingError`; the caller fetches it whole and scans it instead.

>>> RangedMcap.__name__
'RangedMcap'
"""

from __future__ import annotations

import bisect
import struct
from collections.abc import Callable, Collection, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from episodes.streams.errors import CorruptRecordingError
from episodes.streams.mcapscan import (
    McapScan,
    RawMessage,
    chunk_records,
    read_string,
    records,
)

__all__ = ["RangedMcap", "SavedMessages", "read_messages", "write_messages"]

_MAGIC = b"\x89MCAP0\r\n"
_FOOTER = struct.Struct("<BQQQI")  # opcode, length, summary start, summary offset start, crc
_U16 = struct.Struct("<H")
_U32 = struct.Struct("<I")
_U64 = struct.Struct("<Q")
GROUP_BYTES = 8 * 1024 * 1024
"""The most bytes of adjacent chunks fetched by one ranged read."""
_MSG = struct.Struct("<HIQQ")
_CHUNK_INDEX = struct.Struct("<QQQQ")
TAIL_BYTES = 256 * 1024
"""Read at once from the end of the file: the footer and, usually, the whole summary."""

Read = Callable[[int, int], bytes]


@dataclass(frozen=True)
class _Chunk:
    start_ns: int
    end_ns: int
    offset: int
    length: int
    """Of the whole chunk record, opcode and length included."""
    index_offsets: dict[int, int]
    index_length: int
    compression: str

    @property
    def records_offset(self) -> int:
        """Where the chunk's records start in the file (uncompressed chunks)."""
        return self.offset + 9 + 28 + 4 + len(self.compression.encode()) + 8


class RangedMcap(McapScan):
    """A complete MCAP file of ``size`` bytes read by ``read(start, length)`` (see the module).

    ``name`` names it in messages. Raises :class:`CorruptRecordingError` if the file is not a
    complete MCAP file with a summary.
    """

    def __init__(
        self,
        read: Read,
        size: int,
        *,
        name: str,
        workers: int = 8,
        window: int = 8,
        gap: int = 32 * 1024,
        preloaded: Collection[RawMessage] = (),
        preloaded_topics: Collection[str] = (),
        tail: tuple[int, bytes] | None = None,
        small_topics: Collection[str] = (),
    ) -> None:
        self.path = Path(name)
        self.complete, self.truncated_at = True, None
        self._read, self._size = read, size
        self.workers, self.window, self.gap = workers, window, gap
        self._preloaded, self._preloaded_topics = list(preloaded), set(preloaded_topics)
        self._small_topics = set(small_topics)
        self.requests = self.bytes_read = 0
        """Ranged reads made so far, and the bytes they read."""
        if size < 8 + _FOOTER.size + 8:
            raise CorruptRecordingError(f"{name}: too short for an MCAP file with a summary")
        if tail is not None and tail[0] + len(tail[1]) == size and len(tail[1]) >= 45:
            start, data = tail  # saved beside the file: no read
        else:
            start = max(0, size - TAIL_BYTES)
            data = self._get(start, size - start)
        if data[-8:] != _MAGIC:
            raise CorruptRecordingError(f"{name}: no MCAP footer (a recording cut short?)")
        op, _length, summary_start, _offsets, _crc = _FOOTER.unpack_from(data, len(data) - 37)
        if op != 0x02 or summary_start == 0:
            raise CorruptRecordingError(f"{name}: the MCAP file has no summary section")
        summary_end = size - 37
        if summary_start >= start:
            summary = data[summary_start - start : summary_end - start]
        else:
            summary = self._get(summary_start, summary_end - summary_start)
        self.tail = (
            summary_start,
            data[summary_start - start :]
            if summary_start >= start
            else summary + data[len(data) - 37 :],
        )
        """The end of the file from its summary on, as (offset, bytes)."""
        self._channels: dict[int, tuple[str, str]] = {}
        self._chunks: list[_Chunk] = []
        self._parse_summary(memoryview(summary))

    def _get(self, start: int, length: int) -> bytes:
        data = self._read(start, length)
        self.requests += 1
        self.bytes_read += len(data)
        if len(data) != length:
            raise CorruptRecordingError(
                f"{self.path}: read {len(data)} bytes at {start}, expected {length}"
            )
        return data

    def _parse_summary(self, buf: memoryview) -> None:
        schemas: dict[int, str] = {}
        channels: dict[int, tuple[int, str]] = {}
        for op, body in records(buf):
            if op == 0x03:
                (schema_id,) = _U16.unpack_from(body, 0)
                schemas[schema_id], _ = read_string(body, 2)
            elif op == 0x04:
                channel_id, schema_id = struct.unpack_from("<HH", body, 0)
                topic, _ = read_string(body, 4)
                channels[channel_id] = (schema_id, topic)
            elif op == 0x08:
                self._chunks.append(_chunk_index(body))
        self._channels = {
            cid: (topic, schemas.get(schema_id, "")) for cid, (schema_id, topic) in channels.items()
        }
        self._chunks.sort(key=lambda chunk: chunk.offset)

    def messages(
        self, topics: Collection[str] | None = None, start_ns: int | None = None
    ) -> Iterator[RawMessage]:
        """Messages in file order; ``topics`` filters by topic, ``start_ns`` by log time."""
        if topics is not None and self._preloaded_topics and set(topics) <= self._preloaded_topics:
            chosen = [m for m in self._preloaded if m.topic in topics]
            yield from _after(chosen, start_ns)
            return
        wanted = {
            cid for cid, (topic, _) in self._channels.items() if topics is None or topic in topics
        }
        chunks = [
            chunk
            for chunk in self._chunks
            if wanted & chunk.index_offsets.keys()
            and (start_ns is None or chunk.end_ns >= start_ns)
        ]
        small = {cid for cid, (topic, _) in self._channels.items() if topic in self._small_topics}
        by_index = bool(wanted) and wanted <= small
        groups = [[chunk] for chunk in chunks] if by_index else _adjacent(chunks, self.gap)
        pool = ThreadPoolExecutor(self.workers)
        try:
            ahead: list[Future[list[RawMessage]]] = []
            window = 1  # the first read alone, then more ahead as the reader keeps reading
            for group in groups:
                ahead.append(pool.submit(self._group_messages, group, wanted, by_index))
                if len(ahead) >= window:
                    yield from _after(ahead.pop(0).result(), start_ns)
                    window = min(2 * window, self.window)
            while ahead:
                yield from _after(ahead.pop(0).result(), start_ns)
        finally:  # a reader that stops early does not wait for the reads ahead
            pool.shutdown(wait=False, cancel_futures=True)

    def _group_messages(
        self, group: list[_Chunk], wanted: set[int], by_index: bool
    ) -> list[RawMessage]:
        if len(group) == 1:
            return self._chunk_messages(group[0], wanted, by_index)
        start = group[0].offset
        data = memoryview(self._get(start, group[-1].offset + group[-1].length - start))
        found: list[RawMessage] = []
        for chunk in group:
            at = chunk.offset - start
            found.extend(_scan(data[at : at + chunk.length], self._channels, wanted))
        return found

    def _chunk_messages(self, chunk: _Chunk, wanted: set[int], by_index: bool) -> list[RawMessage]:
        if not by_index or chunk.compression or chunk.index_offsets.keys() <= wanted:
            return self._whole_chunk(chunk, wanted)
        index = memoryview(self._get(chunk.offset + chunk.length, chunk.index_length))
        offsets = _message_offsets(index)
        records_length = chunk.offset + chunk.length - chunk.records_offset
        bounds = sorted({offset for _, offset in offsets} | {records_length})
        ranges = sorted(
            (offset, bounds[bisect.bisect_right(bounds, offset)])
            for cid, offset in offsets
            if cid in wanted
        )
        joined = _joined(ranges, self.gap)
        if sum(end - start for start, end in joined) > records_length // 4:
            return self._whole_chunk(chunk, wanted)
        found: list[RawMessage] = []
        for start, end in joined:
            data = memoryview(self._get(chunk.records_offset + start, end - start))
            found.extend(_scan(data, self._channels, wanted))
        return found

    def _whole_chunk(self, chunk: _Chunk, wanted: set[int]) -> list[RawMessage]:
        data = self._get(chunk.offset, chunk.length)
        return _scan(memoryview(data), self._channels, wanted)


def _chunk_index(body: memoryview) -> _Chunk:
    start_ns, end_ns, offset, length = _CHUNK_INDEX.unpack_from(body, 0)
    (map_length,) = _U32.unpack_from(body, 32)
    offsets = {}
    for pos in range(36, 36 + map_length, 10):
        (channel_id,) = _U16.unpack_from(body, pos)
        (offsets[channel_id],) = _U64.unpack_from(body, pos + 2)
    pos = 36 + map_length
    (index_length,) = _U64.unpack_from(body, pos)
    compression, _ = read_string(body, pos + 8)
    return _Chunk(start_ns, end_ns, offset, length, offsets, index_length, compression)


def _message_offsets(index: memoryview) -> list[tuple[int, int]]:
    """(channel id, offset in the chunk's records) of every message a chunk's index lists."""
    found = []
    for op, body in records(index):
        if op != 0x07:
            continue
        (channel_id,) = _U16.unpack_from(body, 0)
        (entries,) = _U32.unpack_from(body, 2)
        for at in range(6, 6 + entries, 16):
            (offset,) = _U64.unpack_from(body, at + 8)
            found.append((channel_id, offset))
    return found


def _adjacent(chunks: list[_Chunk], gap: int) -> list[list[_Chunk]]:
    """Chunks in runs read by one request each: a chunk joins the run before it when less than
    ``gap`` bytes (its message indexes) lie between them and the run stays under
    ``GROUP_BYTES`` (a recorder writes each image as a chunk of its own)."""
    runs: list[list[_Chunk]] = []
    for chunk in chunks:
        run = runs[-1] if runs else None
        if (
            run is not None
            and chunk.offset - (run[-1].offset + run[-1].length) <= gap
            and chunk.offset + chunk.length - run[0].offset <= GROUP_BYTES
        ):
            run.append(chunk)
        else:
            runs.append([chunk])
    return runs


def _joined(ranges: list[tuple[int, int]], gap: int) -> list[tuple[int, int]]:
    joined: list[tuple[int, int]] = []
    for start, end in ranges:
        if joined and start - joined[-1][1] <= gap:
            joined[-1] = (joined[-1][0], max(end, joined[-1][1]))
        else:
            joined.append((start, end))
    return joined


def _after(messages: list[RawMessage], start_ns: int | None) -> list[RawMessage]:
    return messages if start_ns is None else [m for m in messages if m.log_time >= start_ns]


def _scan(
    buf: memoryview, channels: dict[int, tuple[str, str]], wanted: set[int]
) -> list[RawMessage]:
    """The wanted messages among whole records (a chunk's records are read inside it)."""
    found: list[RawMessage] = []
    for op, body in records(buf):
        if op == 0x05:
            channel_id, _sequence, log_time, _published = _MSG.unpack_from(body, 0)
            if channel_id in wanted:
                topic, msgtype = channels[channel_id]
                found.append(RawMessage(topic, msgtype, log_time, body[22:]))
        elif op == 0x06:
            found.extend(_scan(chunk_records(body), channels, wanted))
    return found


_MESSAGES_MAGIC = b"ENGRAM-MESSAGES-2\n"
_TAIL = struct.Struct("<QQ")  # where the saved end of the MCAP file starts, its length
_SAVED = struct.Struct("<HHQI")  # topic length, type length, log time, data length


@dataclass(frozen=True)
class SavedMessages:
    """What :func:`write_messages` saved: messages, and the end of the MCAP file (from its
    summary on) as ``(offset, bytes)``, the ``tail`` of a :class:`RangedMcap`."""

    messages: list[RawMessage]
    tail: tuple[int, bytes]


def write_messages(
    scan: McapScan, topics: Collection[str], target: Path, tail: tuple[int, bytes]
) -> int:
    """Save ``scan``'s messages of ``topics`` and ``tail`` (the end of the MCAP file, from its
    summary on) to the file ``target`` (see the module); returns how many messages.
    :func:`read_messages` reads them back."""
    count = 0
    with target.open("wb") as file:
        file.write(_MESSAGES_MAGIC)
        file.write(_TAIL.pack(tail[0], len(tail[1])))
        file.write(tail[1])
        for message in scan.messages(topics):
            topic, msgtype = message.topic.encode(), message.msgtype.encode()
            file.write(_SAVED.pack(len(topic), len(msgtype), message.log_time, len(message.data)))
            file.write(topic + msgtype)
            file.write(message.data)
            count += 1
    return count


def read_messages(data: bytes) -> SavedMessages:
    """What :func:`write_messages` saved. Raises :class:`CorruptRecordingError`."""
    if not data.startswith(_MESSAGES_MAGIC) or len(data) < len(_MESSAGES_MAGIC) + _TAIL.size:
        raise CorruptRecordingError("not a file of saved messages (bad magic bytes)")
    view, pos, found = memoryview(data), len(_MESSAGES_MAGIC), []
    tail_offset, tail_length = _TAIL.unpack_from(view, pos)
    pos += _TAIL.size
    tail = bytes(view[pos : pos + tail_length])
    pos += tail_length
    while pos < len(view):
        if pos + _SAVED.size > len(view):
            raise CorruptRecordingError("saved messages: the file ends inside a message")
        topic_length, type_length, log_time, data_length = _SAVED.unpack_from(view, pos)
        pos += _SAVED.size
        end = pos + topic_length + type_length + data_length
        if end > len(view):
            raise CorruptRecordingError("saved messages: the file ends inside a message")
        topic = bytes(view[pos : pos + topic_length]).decode()
        msgtype = bytes(view[pos + topic_length : pos + topic_length + type_length]).decode()
        found.append(RawMessage(topic, msgtype, log_time, view[end - data_length : end]))
        pos = end
    return SavedMessages(found, (tail_offset, tail))
