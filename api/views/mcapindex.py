"""One channel's messages of a complete MCAP file, found through the file's own indexes.

A closed recording ends with a summary: its channels and, per chunk, where the chunk lies and
where its message index for each channel is. A message index lists the channel's messages in
the chunk (log time, offset), so a channel's messages are read without walking the other
channels' records: per chunk one decompression and one numpy gather of the message bodies
(all the same length for a provider without a baseline). Files without a summary (cut short
by a crash) give None and are read by a forward scan instead.
"""

import mmap
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from episodes.streams.mcapscan import chunk_records, read_string

__all__ = ["ChannelMessages", "McapIndex", "open_index"]

_MAGIC = b"\x89MCAP0\r\n"
_U16 = struct.Struct("<H")
_U32 = struct.Struct("<I")
_U64 = struct.Struct("<Q")
_MESSAGE_HEADER = 1 + 8 + 2 + 4 + 8 + 8  # opcode, length, channel, sequence, two times
_INDEX_ENTRY = np.dtype([("time", "<u8"), ("offset", "<u8")])


@dataclass(frozen=True)
class _Chunk:
    start: int
    message_indexes: dict[int, int]


@dataclass(frozen=True)
class ChannelMessages:
    """A channel's messages in file order: log times, and bodies as rows of equal length."""

    time_ns: NDArray[np.int64]
    data: NDArray[np.uint8]


class McapIndex:
    """The summary of an MCAP file: its channels by topic and its chunks."""

    def __init__(self, buf: memoryview, channels: dict[str, int], chunks: list[_Chunk]) -> None:
        self._buf = buf
        self.channels = channels
        self._chunks = chunks

    def _records(self, chunk: _Chunk) -> memoryview:
        (length,) = _U64.unpack_from(self._buf, chunk.start + 1)
        return chunk_records(self._buf[chunk.start + 9 : chunk.start + 9 + length])

    def _entries(self, chunk: _Chunk, channel: int) -> NDArray[np.void]:
        at = chunk.message_indexes[channel]
        (length,) = _U32.unpack_from(self._buf, at + 9 + 2)
        start = at + 9 + 2 + 4
        return np.frombuffer(self._buf[start : start + length], dtype=_INDEX_ENTRY)

    def times(self, topic: str) -> NDArray[np.int64]:
        """The log times of the topic's messages, in file order (no chunk is decompressed)."""
        channel = self.channels[topic]
        parts = [
            self._entries(c, channel)["time"] for c in self._chunks if channel in c.message_indexes
        ]
        return np.concatenate(parts).astype(np.int64) if parts else np.zeros(0, np.int64)

    def bodies(self, topic: str) -> list[tuple[int, bytes]]:
        """The topic's messages one by one, as (log time, body): for topics of few messages."""
        channel = self.channels[topic]
        out = []
        for chunk in self._chunks:
            if channel not in chunk.message_indexes:
                continue
            records = self._records(chunk)
            for time_ns, offset in self._entries(chunk, channel).tolist():
                (length,) = _U64.unpack_from(records, offset + 1)
                out.append((int(time_ns), bytes(records[offset + 31 : offset + 9 + length])))
        return out

    def messages(self, topic: str) -> ChannelMessages | None:
        """The topic's messages; None when their bodies differ in length."""
        channel = self.channels[topic]
        times, rows, width = [], [], None
        for chunk in self._chunks:
            if channel not in chunk.message_indexes:
                continue
            entries = self._entries(chunk, channel)
            if not len(entries):
                continue
            records = np.frombuffer(self._records(chunk), dtype=np.uint8)
            offsets = entries["offset"].astype(np.int64)
            lengths = records[offsets[:, None] + np.arange(1, 9)].copy().view("<u8").reshape(-1)
            if np.any(lengths != lengths[0]) or (width is not None and lengths[0] - 22 != width):
                return None
            width = int(lengths[0]) - 22
            if int(offsets.max()) + _MESSAGE_HEADER + width > len(records):
                raise ValueError("a message index points past its chunk")
            rows.append(records[(offsets + _MESSAGE_HEADER)[:, None] + np.arange(width)])
            times.append(entries["time"].astype(np.int64))
        if width is None:
            return ChannelMessages(np.zeros(0, np.int64), np.zeros((0, 0), np.uint8))
        return ChannelMessages(np.concatenate(times), np.concatenate(rows))


def open_index(file: Path) -> McapIndex | None:
    """The file's summary, or None when it has none usable (cut short, or written without
    chunk and message indexes)."""
    with file.open("rb") as stream:
        if stream.read(8) != _MAGIC:
            return None
        buf = memoryview(mmap.mmap(stream.fileno(), 0, access=mmap.ACCESS_READ))
    size = len(buf)
    footer = size - 8 - (1 + 8 + 20)
    if size < 8 + 29 + 8 or bytes(buf[size - 8 :]) != _MAGIC or buf[footer] != 0x02:
        return None
    (summary_start,) = _U64.unpack_from(buf, footer + 9)
    if summary_start == 0:
        return None
    channels: dict[str, int] = {}
    chunks: list[_Chunk] = []
    pos = summary_start
    while pos < footer:
        op = buf[pos]
        (length,) = _U64.unpack_from(buf, pos + 1)
        body = pos + 9
        if op == 0x04:  # channel
            (channel_id,) = _U16.unpack_from(buf, body)
            topic, _ = read_string(buf, body + 4)
            channels[topic] = channel_id
        elif op == 0x08:  # chunk index
            (start,) = _U64.unpack_from(buf, body + 16)
            (map_length,) = _U32.unpack_from(buf, body + 32)
            entries = np.frombuffer(
                buf[body + 36 : body + 36 + map_length], dtype=[("c", "<u2"), ("o", "<u8")]
            )
            indexes = {int(e["c"]): int(e["o"]) for e in entries}
            chunks.append(_Chunk(start, indexes))
        pos = body + length
    if not chunks:
        return None
    chunks.sort(key=lambda c: c.start)
    return McapIndex(buf, channels, chunks)
