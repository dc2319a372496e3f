"""Writing MCAP files: the bytes the official ``mcap`` package's :class:`mcap.writer.Writer`
writes, at a fraction of its cost on large messages.

:class:`McapWriter` writes a chunked file: every chunk carries the CRC of its records, the data
section's CRC is in its end record and the summary's in the footer; the summary repeats schemas
and channels and holds statistics, chunk indexes (each with its message indexes), the metadata
index and summary offsets. Records other than messages and chunks are the library's own record
classes; chunks are assembled here. The library's writer copies each payload twice into fresh
buffers and reads it twice for CRCs, which tripled the recorder's CPU per camera frame; here a
payload is read once for its CRC (``isal``'s CRC-32) and written once from the caller's buffer
(figures: ``bench/README.md``). Tests compare the bytes with the library's on random sequences
and on the contents of the MCAP conformance suite.

Recordings are written through :class:`episodes.streams.bagwrite.BagWriter`, the rosbag2 layer
on top of this one.

>>> import io
>>> out = io.BytesIO()
>>> mcap = McapWriter(out, profile="ros2")
>>> channel = mcap.register_channel("/note", "cdr", mcap.register_schema("T", "ros2msg", b""), {})
>>> mcap.add_message(channel, 1_000, b"hello", 1_000)
>>> mcap.finish()
>>> from mcap.reader import make_reader
>>> read = make_reader(io.BytesIO(out.getvalue()), validate_crcs=True)
>>> [m.data for _, _, m in read.iter_messages()]
[b'hello']
"""

from __future__ import annotations

import struct
from collections.abc import Mapping
from typing import IO, Any

import lz4.frame  # type: ignore[import-untyped,unused-ignore]
import zstandard
from isal.isal_zlib import crc32, crc32_combine
from mcap.data_stream import RecordBuilder
from mcap.opcode import Opcode
from mcap.records import (
    Channel,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    MessageIndex,
    Metadata,
    MetadataIndex,
    Schema,
    Statistics,
    SummaryOffset,
)
from mcap.writer import LIBRARY_IDENTIFIER, MCAP0_MAGIC

from episodes.streams.errors import InvalidSampleError

__all__ = ["CHUNK_BYTES", "COMPRESSIONS", "McapWriter"]

CHUNK_BYTES = 1024 * 1024
"""Chunks close once their records pass this size (the library's and rosbags' default)."""
COMPRESSIONS = (None, "zstd", "lz4")
"""The chunk compressions a file may use, by the name MCAP gives them."""
_MESSAGE_HEAD = struct.Struct("<BQHIQQ")
"""A message record's opcode, length, channel, sequence, log time and publish time."""
_CHUNK_HEAD = struct.Struct("<BQQQQI")
"""A chunk record's opcode, length, start and end times, records size and records CRC."""
_CHUNK_FIELDS = 8 + 8 + 8 + 4 + 4 + 8  # times, size, CRC, compression's length, data's length


class McapWriter:
    """An MCAP file written to ``stream``: the bytes ``mcap.writer.Writer`` writes for the same
    calls (chunked, every index, statistics, summary offsets, chunk, data-section and summary
    CRCs), with each message's payload CRC-checked while it is added and written to the
    stream once, from the caller's buffer. With ``alone_bytes``, messages that large also
    get chunks of their own (the library has no such setting).

    The library's writer copies a payload into its chunk buffer, copies the finished chunk
    into a record buffer (both fresh memory: ~430 page faults a 640x480 frame), and CRCs it
    twice. Here the data section's CRC is combined from the chunk's (isal's ``crc32_combine``)
    for uncompressed chunks. Records other than messages and chunks are the library's own
    record classes.
    """

    def __init__(
        self,
        stream: IO[bytes],
        *,
        compression: str | None = None,
        chunk_bytes: int = CHUNK_BYTES,
        alone_bytes: int | None = None,
        profile: str = "",
        library: str = LIBRARY_IDENTIFIER,
    ) -> None:
        if compression not in COMPRESSIONS:
            raise InvalidSampleError("compression", compression, "None, 'zstd' or 'lz4'")
        self._stream = stream
        self._alone_bytes = alone_bytes
        # one compressor for every chunk: a new one per chunk (``zstandard.compress``) costs
        # megabytes of fresh tables each time; same level, same bytes
        self._zstd = zstandard.ZstdCompressor(level=3)
        self._compression = compression or ""
        self._chunk_bytes = chunk_bytes
        self._schemas: dict[int, Schema] = {}
        self._channels: dict[int, Channel] = {}
        self._chunk_indexes: list[ChunkIndex] = []
        self._metadata_indexes: list[MetadataIndex] = []
        self._counts: dict[int, int] = {}
        self._message_count = 0
        self._start_ns = 0
        self._end_ns = 0
        self._metadata_count = 0
        self._data_crc = 0
        self._offset = 0
        self._parts: list[bytes | memoryview] = []
        self._chunk_size = self._chunk_crc = self._chunk_messages = 0
        self._chunk_start_ns = self._chunk_end_ns = 0
        self._index: dict[int, list[tuple[int, int]]] = {}
        self._write(MCAP0_MAGIC, _record(Header(profile, library)))

    def register_schema(self, name: str, encoding: str, data: bytes) -> int:
        """A new schema; its id."""
        schema = Schema(id=len(self._schemas) + 1, name=name, encoding=encoding, data=data)
        self._schemas[schema.id] = schema
        self._add(_record(schema))
        return schema.id

    def register_channel(
        self, topic: str, message_encoding: str, schema_id: int, metadata: Mapping[str, str]
    ) -> int:
        """A new channel; its id."""
        channel = Channel(
            id=len(self._channels) + 1,
            topic=topic,
            message_encoding=message_encoding,
            schema_id=schema_id,
            metadata=dict(metadata),
        )
        self._channels[channel.id] = channel
        self._add(_record(channel))
        return channel.id

    def add_message(
        self, channel_id: int, log_time: int, data: bytes | memoryview, publish_time: int
    ) -> None:
        """A message (sequence 0) into the chunk in progress; ``data`` is kept, not copied,
        until the chunk is written. A message of at least ``alone_bytes`` closes the chunk
        before it and gets one of its own."""
        size = len(data)
        alone = self._alone_bytes is not None and size >= self._alone_bytes
        if alone:
            self._write_chunk()
        if self._message_count == 0:
            self._start_ns = log_time
        self._start_ns = min(self._start_ns, log_time)
        self._end_ns = max(self._end_ns, log_time)
        self._counts[channel_id] = self._counts.get(channel_id, 0) + 1
        self._message_count += 1
        if self._chunk_messages == 0:
            self._chunk_start_ns = log_time
        self._chunk_start_ns = min(self._chunk_start_ns, log_time)
        self._chunk_end_ns = max(self._chunk_end_ns, log_time)
        self._chunk_messages += 1
        self._index.setdefault(channel_id, []).append((log_time, self._chunk_size))
        head = _MESSAGE_HEAD.pack(Opcode.MESSAGE, 22 + size, channel_id, 0, log_time, publish_time)
        self._chunk_crc = crc32(data, crc32(head, self._chunk_crc))
        self._parts += (head, data)
        self._chunk_size += len(head) + size
        if alone or self._chunk_size > self._chunk_bytes:
            self._write_chunk()

    def add_metadata(self, name: str, data: Mapping[str, str]) -> None:
        """A metadata record, written at once (before the chunk in progress)."""
        record = _record(Metadata(name=name, metadata=dict(data)))
        self._metadata_indexes.append(MetadataIndex(self._offset, len(record), name))
        self._metadata_count += 1
        self._write(record)

    def flush(self) -> None:
        """Write the chunk in progress (if it holds a message) and flush the stream."""
        self._write_chunk()
        self._stream.flush()

    def finish(self) -> None:
        """Write the last chunk, the data section's end, the summary and the footer."""
        self._write_chunk()
        self._write(_record(DataEnd(self._data_crc)))
        summary_start = self._offset
        summary = RecordBuilder()
        offsets: list[SummaryOffset] = []

        def group(opcode: Opcode, records: list[Any]) -> None:
            begin = summary.count
            for record in records:
                record.write(summary)
            offsets.append(SummaryOffset(opcode, summary_start + begin, summary.count - begin))

        group(Opcode.SCHEMA, list(self._schemas.values()))
        group(Opcode.CHANNEL, list(self._channels.values()))
        group(Opcode.STATISTICS, [self._statistics()])
        group(Opcode.CHUNK_INDEX, self._chunk_indexes)
        group(Opcode.ATTACHMENT_INDEX, [])
        group(Opcode.METADATA_INDEX, self._metadata_indexes)
        offset_start = summary_start + summary.count
        for offset in offsets:
            offset.write(summary)
        data: bytes = summary.end()  # type: ignore[no-untyped-call]
        crc = crc32(
            struct.pack("<BQQQ", Opcode.FOOTER, 20, summary_start, offset_start),
            crc32(data),
        )
        self._stream.write(data)
        self._stream.write(_record(Footer(summary_start, offset_start, crc)))
        self._stream.write(MCAP0_MAGIC)

    def _statistics(self) -> Statistics:
        return Statistics(
            message_count=self._message_count,
            schema_count=len(self._schemas),
            channel_count=len(self._channels),
            attachment_count=0,
            metadata_count=self._metadata_count,
            chunk_count=len(self._chunk_indexes),
            message_start_time=self._start_ns,
            message_end_time=self._end_ns,
            channel_message_counts=self._counts,
        )

    def _new_chunk(self) -> None:
        self._parts = []
        self._chunk_size = self._chunk_crc = self._chunk_messages = 0
        self._chunk_start_ns = self._chunk_end_ns = 0
        self._index = {}

    def _add(self, record: bytes) -> None:
        """A schema or channel record into the chunk in progress."""
        self._chunk_crc = crc32(record, self._chunk_crc)
        self._parts.append(record)
        self._chunk_size += len(record)
        if self._chunk_size > self._chunk_bytes:
            self._write_chunk()

    def _write_chunk(self) -> None:
        if self._chunk_messages == 0:
            return  # schemas and channels wait for a message, as in the library
        parts: list[bytes | memoryview] = self._parts
        if self._compression == "zstd":
            parts = [self._zstd.compress(b"".join(parts))]
        elif self._compression == "lz4":
            parts = [lz4.frame.compress(b"".join(parts))]
        stored = sum(len(p) for p in parts)
        name = self._compression.encode()
        head = (
            _CHUNK_HEAD.pack(
                Opcode.CHUNK,
                _CHUNK_FIELDS + len(name) + stored,
                self._chunk_start_ns,
                self._chunk_end_ns,
                self._chunk_size,
                self._chunk_crc,
            )
            + struct.pack("<I", len(name))
            + name
            + struct.pack("<Q", stored)
        )
        start = self._offset
        if self._compression:
            self._write(head, *parts)
        else:  # the records' CRC is known: the data section's follows without reading them again
            self._write(head)
            for part in parts:
                self._stream.write(part)
            self._data_crc = crc32_combine(self._data_crc, self._chunk_crc, self._chunk_size)
            self._offset += self._chunk_size
        end = self._offset
        offsets = {}
        for channel_id, entries in self._index.items():
            offsets[channel_id] = self._offset
            self._write(_record(MessageIndex(channel_id, entries)))
        self._chunk_indexes.append(
            ChunkIndex(
                message_start_time=self._chunk_start_ns,
                message_end_time=self._chunk_end_ns,
                chunk_start_offset=start,
                chunk_length=end - start,
                message_index_offsets=offsets,
                message_index_length=self._offset - end,
                compression=self._compression,
                compressed_size=stored,
                uncompressed_size=self._chunk_size,
            )
        )
        self._new_chunk()

    def _write(self, *parts: bytes | memoryview) -> None:
        """Bytes of the data section, counted into its CRC."""
        for part in parts:
            self._data_crc = crc32(part, self._data_crc)
            self._stream.write(part)
            self._offset += len(part)


def _record(record: Any) -> bytes:
    """One record's bytes, written by the library's record class."""
    builder = RecordBuilder()
    record.write(builder)
    data: bytes = builder.end()  # type: ignore[no-untyped-call]
    return data
