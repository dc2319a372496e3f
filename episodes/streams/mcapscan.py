"""A forward scan of an MCAP file that also reads files cut short by a crash.

``rosbags`` needs the MCAP footer and summary, which the writer adds only when it closes the
bag. After a crash the file ends inside a chunk; this scan reads every complete record from
the start and stops at the first incomplete one, so everything up to the last flushed chunk is
readable. It yields messages in file order, which for the recorder's files is tick order.

>>> import io
>>> scan_bytes(b"not an mcap file")
Traceback (most recent call last):
...
episodes.streams.errors.CorruptRecordingError: not an MCAP file (bad magic bytes)
"""

from __future__ import annotations

import mmap
import struct
from collections.abc import Collection, Iterator
from dataclasses import dataclass
from pathlib import Path

from episodes.streams.errors import CorruptRecordingError, RecordingNotFoundError

try:
    from compression import zstd  # type: ignore[import-not-found,unused-ignore]
except ImportError:  # Python < 3.14, as rosbags does
    from backports import zstd  # type: ignore[import-not-found,unused-ignore,no-redef]

__all__ = ["McapScan", "RawMessage", "chunk_records", "read_string", "scan_bytes"]

_MAGIC = b"\x89MCAP0\r\n"
_U16 = struct.Struct("<H")
_U32 = struct.Struct("<I")
_U64 = struct.Struct("<Q")
_REC = struct.Struct("<BQ")
_MSG = struct.Struct("<HIQQ")


@dataclass(frozen=True)
class RawMessage:
    """One message: its topic, type name, log time (ns) and CDR bytes."""

    topic: str
    msgtype: str
    log_time: int
    data: memoryview


@dataclass(frozen=True)
class _Channel:
    topic: str
    msgtype: str


def read_string(buf: memoryview | bytes, pos: int) -> tuple[str, int]:
    """The MCAP string (u32 length, UTF-8) at ``pos``, and the position after it."""
    (n,) = _U32.unpack_from(buf, pos)
    return bytes(buf[pos + 4 : pos + 4 + n]).decode(), pos + 4 + n


class McapScan:
    """Scans an MCAP file, complete or truncated.

    Raises:
        RecordingNotFoundError: the file does not exist.
        CorruptRecordingError: it is not an MCAP file.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        if not path.is_file():
            raise RecordingNotFoundError(f"path: no recording file at {str(path)!r}")
        with path.open("rb") as f:
            if f.read(8) != _MAGIC:
                raise CorruptRecordingError("not an MCAP file (bad magic bytes)")
        self.complete = False
        self.truncated_at: int | None = None

    def messages(
        self, topics: Collection[str] | None = None, start_ns: int | None = None
    ) -> Iterator[RawMessage]:
        """Messages in file order; ``topics`` filters by topic, ``start_ns`` by log time."""
        with self.path.open("rb") as f:
            # mapped, not read: a recording can be larger than memory; the map is released
            # when the last message view of it is gone
            data = mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ)
        yield from _scan(self, memoryview(data), topics, start_ns)


def scan_bytes(data: bytes) -> list[RawMessage]:
    """All messages of an MCAP file held in memory (for tests and small files)."""
    if data[:8] != _MAGIC:
        raise CorruptRecordingError("not an MCAP file (bad magic bytes)")
    holder = McapScan.__new__(McapScan)
    holder.complete, holder.truncated_at = False, None
    return list(_scan(holder, memoryview(data), None, None))


def _scan(
    owner: McapScan,
    buf: memoryview,
    topics: Collection[str] | None,
    start_ns: int | None,
) -> Iterator[RawMessage]:
    schemas: dict[int, str] = {}
    channels: dict[int, _Channel] = {}
    wanted = set(topics) if topics is not None else None
    pos, end = 8, len(buf)
    while True:
        if pos + 9 > end:
            owner.truncated_at = pos
            return
        op, length = _REC.unpack_from(buf, pos)
        body_start = pos + 9
        if body_start + length > end:
            owner.truncated_at = pos
            return
        body = buf[body_start : body_start + length]
        pos = body_start + length
        if op == 0x02 or op == 0x0F:  # footer or data end: the rest is the summary
            owner.complete = True
            return
        if op == 0x06:
            yield from _chunk(body, schemas, channels, wanted, start_ns)
        else:
            yield from _record(op, body, schemas, channels, wanted, start_ns)


def chunk_records(body: memoryview) -> memoryview:
    """The records a Chunk record's body holds, decompressed (zstd or lz4) and size-checked."""
    (uncompressed_size,) = _U64.unpack_from(body, 16)
    compression, pos = read_string(body, 28)
    (records_len,) = _U64.unpack_from(body, pos)
    records = body[pos + 8 : pos + 8 + records_len]
    if compression == "zstd":
        records = memoryview(zstd.decompress(bytes(records)))
    elif compression == "lz4":
        from lz4.frame import decompress  # type: ignore[import-untyped,unused-ignore]

        records = memoryview(decompress(bytes(records)))
    elif compression:
        raise CorruptRecordingError(f"unsupported chunk compression {compression!r}")
    if len(records) != uncompressed_size:
        raise CorruptRecordingError("chunk size does not match its header")
    return records


def records(buf: memoryview) -> Iterator[tuple[int, memoryview]]:
    """The (opcode, body) of each record laid end to end in ``buf`` (a chunk's records, a
    summary, a chunk's message index); :class:`CorruptRecordingError` for one that runs past
    the end."""
    pos, end = 0, len(buf)
    while pos + 9 <= end:
        op, length = _REC.unpack_from(buf, pos)
        pos += 9
        if pos + length > end:
            raise CorruptRecordingError("a record runs past the bytes read")
        yield op, buf[pos : pos + length]
        pos += length


def _chunk(
    body: memoryview,
    schemas: dict[int, str],
    channels: dict[int, _Channel],
    wanted: set[str] | None,
    start_ns: int | None,
) -> Iterator[RawMessage]:
    for op, rec in records(chunk_records(body)):
        yield from _record(op, rec, schemas, channels, wanted, start_ns)


def _record(
    op: int,
    body: memoryview,
    schemas: dict[int, str],
    channels: dict[int, _Channel],
    wanted: set[str] | None,
    start_ns: int | None,
) -> Iterator[RawMessage]:
    if op == 0x05:
        channel_id, _seq, log_time, _pub = _MSG.unpack_from(body, 0)
        channel = channels.get(channel_id)
        if channel is None:
            raise CorruptRecordingError(f"message on undeclared channel {channel_id}")
        if (wanted is None or channel.topic in wanted) and (
            start_ns is None or log_time >= start_ns
        ):
            yield RawMessage(channel.topic, channel.msgtype, log_time, body[22:])
    elif op == 0x03:
        (schema_id,) = _U16.unpack_from(body, 0)
        schemas[schema_id], _ = read_string(body, 2)
    elif op == 0x04:
        channel_id, schema_id = struct.unpack_from("<HH", body, 0)
        topic, _ = read_string(body, 4)
        channels[channel_id] = _Channel(topic, schemas.get(schema_id, ""))
