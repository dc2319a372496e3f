"""MCAP files read through the official ``mcap`` library, checked and bounded.

Every reader of a recording goes through :class:`McapFile`: replay (of a local file, or of an
object in storage through :class:`episodes.streams.ranged.RangedFile`), the views' channel list
and plots, recovery and export. Records are parsed by the library's record classes
(:mod:`mcap.records`); what this module adds is what the library leaves to its caller:

* **Bounds.** A chunk is decompressed by a streaming zstd or lz4 decompressor that stops at the
  chunk's declared uncompressed size, and that size may not exceed ``limit_bytes``; no record
  larger than ``limit_bytes`` is read into memory. A file claiming more is damaged.
* **Checks.** Each chunk's CRC and the summary's CRC are validated whenever they are read; the
  data section's CRC on every full forward read.
* **One error.** Any damage raises :class:`CorruptRecordingError` naming the file and the byte
  offset of the record at fault, never another exception.
* **Files cut short.** A recording whose writer crashed has no footer: it is read forward up to
  its last complete record (:attr:`McapFile.complete` False, :attr:`McapFile.truncated_at`).

A complete file whose summary lists its chunks and their channels is read through the summary:
only the chunks holding wanted channels at or after the wanted time are read. Any other file is
read forward, record by record.

>>> import io
>>> McapFile(lambda: io.BytesIO(b"not an mcap file"), name="x")
Traceback (most recent call last):
...
episodes.streams.errors.CorruptRecordingError: x: not an MCAP file (bad magic bytes) at offset 0
"""

from __future__ import annotations

import io
import struct
import zlib
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any, Protocol

import lz4.frame  # type: ignore[import-untyped,unused-ignore]
from mcap.data_stream import ReadDataStream
from mcap.exceptions import McapError
from mcap.records import (
    Attachment,
    Channel,
    Chunk,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    McapRecord,
    Message,
    Metadata,
    Schema,
    Statistics,
)
from mcap.summary import Summary

from episodes.streams.errors import CorruptRecordingError, RecordingNotFoundError

try:
    from compression import zstd  # type: ignore[import-not-found,unused-ignore]
except ImportError:  # Python < 3.14
    from backports import zstd  # type: ignore[import-not-found,unused-ignore,no-redef]

__all__ = [
    "LIMIT_BYTES",
    "McapFile",
    "MessageSource",
    "RawMessage",
    "decompress",
]

LIMIT_BYTES = 1024**3
"""Default bound of one record read into memory and of one chunk decompressed (bytes)."""

RUN_BYTES = 8 * 1024 * 1024
"""The most bytes of neighbouring chunks read at once (one ranged read in object storage)."""
GAP_BYTES = 32 * 1024
"""Chunks at most this far apart (their message indexes between them) are read at once."""
MAGIC = b"\x89MCAP0\r\n"
_HEAD = struct.Struct("<BQ")  # a record's opcode and body length
_MESSAGE = struct.Struct("<HIQQ")  # a message's channel, sequence, log and publish times
_FOOTER_RECORD = _HEAD.size + 8 + 8 + 4
_OP_HEADER, _OP_FOOTER, _OP_SCHEMA, _OP_CHANNEL, _OP_MESSAGE, _OP_CHUNK = 1, 2, 3, 4, 5, 6
_OP_MESSAGE_INDEX, _OP_CHUNK_INDEX, _OP_ATTACHMENT, _OP_STATISTICS = 7, 8, 9, 11
_OP_METADATA, _OP_DATA_END = 12, 15

_DAMAGE = (
    McapError,
    ValueError,  # also UnicodeDecodeError, the library's CRCValidationError
    struct.error,
    EOFError,
    IndexError,
    KeyError,
    OverflowError,
    RuntimeError,  # lz4's errors
    zstd.ZstdError,
)
"""What parsing or decompressing damaged bytes can raise."""


@dataclass(frozen=True)
class RawMessage:
    """One message: its topic, type (schema) name, log time (ns) and bytes."""

    topic: str
    msgtype: str
    log_time: int
    data: bytes


class MessageSource(Protocol):
    """What a replayer reads messages from: a :class:`McapFile`, or one answering some
    topics from messages saved beside it."""

    @property
    def complete(self) -> bool:
        """The file ends with its footer (not cut short)."""

    def messages(
        self, topics: Collection[str] | None = None, start_ns: int | None = None
    ) -> Iterator[RawMessage]:
        """Messages in file order; ``topics`` filters by topic, ``start_ns`` by log time."""


class _Exact(io.BytesIO):
    """Bytes whose reads return all that is asked or raise: the library's record readers
    accept short reads, which would turn a length running past its record into garbage."""

    def read(self, size: int | None = -1, /) -> bytes:
        if size is not None and size < 0:
            raise EOFError("a negative length")
        data = super().read(size)
        if size is not None and len(data) < size:
            raise EOFError(f"{size} bytes asked, {len(data)} left in the record")
        return data


def _parse(body: bytes | memoryview) -> ReadDataStream:
    return ReadDataStream(_Exact(body))


def decompress(
    compression: str, data: bytes, size: int, *, limit_bytes: int = LIMIT_BYTES
) -> bytes:
    """``data`` decompressed (``""``, ``"zstd"`` or ``"lz4"``), exactly ``size`` bytes.

    Never holds more than ``size`` bytes of output, so a chunk that expands beyond what it
    declares is stopped there. Raises :class:`ValueError` (a damaged chunk) when ``size`` is
    over ``limit_bytes``, the output is not ``size`` bytes, or the compression is unknown.

    >>> decompress("lz4", lz4.frame.compress(b"x" * 100), 10)
    Traceback (most recent call last):
    ...
    ValueError: the chunk expands to more than the 10 bytes it declares
    """
    if size > limit_bytes:
        raise ValueError(
            f"the chunk declares {size} bytes uncompressed, over the limit {limit_bytes}"
        )
    if compression == "":
        out = data
    elif compression == "zstd":
        out = _bounded(zstd.ZstdDecompressor, data, size)
    elif compression == "lz4":
        out = _bounded(lz4.frame.LZ4FrameDecompressor, data, size)
    else:
        raise ValueError(f"unsupported chunk compression {compression!r}")
    if len(out) != size:
        raise ValueError(f"the chunk holds {len(out)} bytes, its header declares {size}")
    return out


def _bounded(make: Callable[[], object], data: bytes, size: int) -> bytes:
    """Frame after frame of ``data``, stopping once ``size`` bytes are out."""
    parts: list[bytes] = []
    left, rest = size, data
    while rest:
        decompressor: object = make()
        # max_length bounds the output of this call, whatever the frame declares
        out: bytes = decompressor.decompress(rest, max_length=left + 1)  # type: ignore[attr-defined]
        if len(out) > left:
            raise ValueError(f"the chunk expands to more than the {size} bytes it declares")
        if not decompressor.eof:  # type: ignore[attr-defined]
            raise ValueError("the chunk's compressed data ends inside a frame")
        parts.append(out)
        left -= len(out)
        rest = decompressor.unused_data  # type: ignore[attr-defined]
    return b"".join(parts)


class _Channels:
    """The schemas and channels declared so far: type names by schema id, (topic, type name)
    by channel id."""

    def __init__(self, summary: Summary | None = None) -> None:
        self.schemas: dict[int, str] = {}
        self.channels: dict[int, tuple[str, str]] = {}
        if summary is not None:
            self.schemas = {sid: schema.name for sid, schema in summary.schemas.items()}
            for channel in summary.channels.values():
                self.channels[channel.id] = (channel.topic, self.schemas.get(channel.schema_id, ""))


_Where = tuple[int, int | None]
"""Where a record lies: (its offset, None), or (its chunk's offset, its offset in the chunk's
records)."""

_READERS: dict[int, Callable[[ReadDataStream, int], McapRecord]] = {
    _OP_HEADER: lambda stream, _: Header.read(stream),
    _OP_SCHEMA: lambda stream, _: Schema.read(stream),
    _OP_CHANNEL: lambda stream, _: Channel.read(stream),
    _OP_ATTACHMENT: lambda stream, _: Attachment.read(stream),
    _OP_METADATA: lambda stream, _: Metadata.read(stream),
}
"""The library's reader of each record a copy of the data section keeps."""


class McapFile:
    """An MCAP file read by ``opener`` (a new binary, seekable file object each call).

    ``name`` names it in messages; ``limit_bytes`` bounds every record read and every chunk
    decompressed. :meth:`open` opens a local file.

    Raises:
        CorruptRecordingError: not an MCAP file, or its footer or summary is damaged.
    """

    def __init__(
        self, opener: Callable[[], IO[bytes]], *, name: str, limit_bytes: int = LIMIT_BYTES
    ) -> None:
        if limit_bytes <= 0:
            raise ValueError(f"limit_bytes: got {limit_bytes!r}, expected a positive size")
        self.path = Path(name)
        self.name = name
        self.limit_bytes = limit_bytes
        self._opener = opener
        self.truncated_at: int | None = None
        """Where a forward read of a file cut short stopped (the first incomplete record)."""
        with opener() as file:
            self.size = file.seek(0, io.SEEK_END)
            file.seek(0)
            if file.read(len(MAGIC)) != MAGIC:
                raise self._error(0, "not an MCAP file (bad magic bytes)")
            self.footer_at, self.footer = self._read_footer(file)
            self.summary = self._read_summary(file) if self.footer is not None else None
        self.data_end = self.footer_at
        """Where the data section ends: the summary, or the footer."""
        if self.footer is not None and self.footer.summary_start:
            self.data_end = self.footer.summary_start
        self._indexed = self.summary is not None and _usable(self.summary)

    @classmethod
    def open(cls, path: Path, *, limit_bytes: int = LIMIT_BYTES) -> McapFile:
        """The local MCAP file at ``path``; :class:`RecordingNotFoundError` if there is none."""
        if not path.is_file():
            raise RecordingNotFoundError(f"path: no recording file at {str(path)!r}")
        return cls(lambda: path.open("rb"), name=str(path), limit_bytes=limit_bytes)

    @property
    def complete(self) -> bool:
        """The file ends with its footer (not cut short by a crash)."""
        return self.footer is not None

    @property
    def indexed(self) -> bool:
        """The summary locates every chunk and declares the channels they hold."""
        return self._indexed

    def _error(self, offset: int, what: str) -> CorruptRecordingError:
        return CorruptRecordingError(f"{self.name}: {what} at offset {offset}")

    # ---------------------------------------------------------------- footer and summary

    def _read_footer(self, file: IO[bytes]) -> tuple[int, Footer | None]:
        """The footer and its offset; ``(size, None)`` for a file cut short."""
        at = self.size - len(MAGIC) - _FOOTER_RECORD
        if at < len(MAGIC):
            return self.size, None
        file.seek(at)
        tail = file.read(_FOOTER_RECORD + len(MAGIC))
        if tail[-len(MAGIC) :] != MAGIC or tail[0] != _OP_FOOTER:
            return self.size, None
        _, length = _HEAD.unpack_from(tail)
        if length != _FOOTER_RECORD - _HEAD.size:
            raise self._error(at, f"a footer of {length} bytes, expected 20")
        footer = Footer.read(_parse(tail[_HEAD.size : -len(MAGIC)]))
        for field in ("summary_start", "summary_offset_start"):
            value = getattr(footer, field)
            if value and not len(MAGIC) <= value < at:
                raise self._error(at, f"the footer's {field} {value} lies outside the file")
        return at, footer

    def _read_summary(self, file: IO[bytes]) -> Summary | None:
        footer = self.footer
        assert footer is not None
        start = footer.summary_start or self.footer_at
        if self.footer_at - start > self.limit_bytes:
            raise self._error(start, f"a summary of {self.footer_at - start} bytes, over the limit")
        file.seek(start)
        data = file.read(self.footer_at + _HEAD.size + 16 - start)
        if footer.summary_crc and zlib.crc32(data) != footer.summary_crc:
            raise self._error(start, "the summary does not match its CRC")
        if not footer.summary_start:
            return None
        summary = Summary()
        end = self.footer_at - start
        for at, op, body in self._records(
            memoryview(data), 0, end, lambda pos: (start + pos, None)
        ):
            try:
                if op == _OP_SCHEMA:
                    schema = Schema.read(_parse(body))
                    summary.schemas[schema.id] = schema
                elif op == _OP_CHANNEL:
                    channel = Channel.read(_parse(body))
                    summary.channels[channel.id] = channel
                elif op == _OP_CHUNK_INDEX:
                    index = ChunkIndex.read(_parse(body))
                    if index.chunk_start_offset + index.chunk_length > start:
                        raise ValueError("a chunk index points past the data section")
                    summary.chunk_indexes.append(index)
                elif op == _OP_STATISTICS:
                    summary.statistics = Statistics.read(_parse(body))
            except _DAMAGE as error:
                raise self._error(start + at, f"summary record {op:#04x}: {error}") from error
        summary.chunk_indexes.sort(key=lambda index: index.chunk_start_offset)
        return summary

    def _records(
        self, data: memoryview, start: int, end: int, where: Callable[[int], _Where]
    ) -> Iterator[tuple[int, int, memoryview]]:
        """(offset in ``data``, opcode, body) of the records laid end to end in
        ``data[start:end]``; ``where`` places an offset in ``data`` for messages."""
        pos = start
        while pos < end:
            if pos + _HEAD.size > end:
                raise self._damaged(where(pos), "a record header runs past its section")
            op, length = _HEAD.unpack_from(data, pos)
            body_at = pos + _HEAD.size
            if length > end - body_at:
                raise self._damaged(where(pos), f"a record of {length} bytes runs past its section")
            yield pos, op, data[body_at : body_at + length]
            pos = body_at + length

    # ---------------------------------------------------------------- messages

    def messages(
        self, topics: Collection[str] | None = None, start_ns: int | None = None
    ) -> Iterator[RawMessage]:
        """Messages in file order; ``topics`` filters by topic, ``start_ns`` by log time.

        Raises :class:`CorruptRecordingError` at the first damaged record.
        """
        wanted = None if topics is None else frozenset(topics)
        with self._opener() as file:
            if self._indexed:
                yield from self._indexed_messages(file, wanted, start_ns)
            else:
                yield from self._forward_messages(file, wanted, start_ns)

    def _indexed_messages(
        self, file: IO[bytes], wanted: frozenset[str] | None, start_ns: int | None
    ) -> Iterator[RawMessage]:
        assert self.summary is not None
        channels = _Channels(self.summary)
        for run in _runs(self.chunk_indexes(wanted, start_ns), min(RUN_BYTES, self.limit_bytes)):
            start = run[0].chunk_start_offset
            span = self._span(file, start, run[-1].chunk_start_offset + run[-1].chunk_length)
            for index in run:
                records = self.chunk_records(file, index, span=span)
                yield from self._chunk_messages(
                    records, index.chunk_start_offset, channels, wanted, start_ns
                )

    def _span(self, file: IO[bytes], start: int, end: int) -> tuple[int, bytes]:
        """The bytes from ``start`` to ``end`` of the data section, read at once."""
        if not len(MAGIC) <= start < end <= self.data_end:
            raise self._error(start, f"chunks indexed up to offset {end}, outside the data section")
        if end - start > self.limit_bytes:
            raise self._error(
                start, f"a chunk of {end - start} bytes, over the limit {self.limit_bytes}"
            )
        file.seek(start)
        data = file.read(end - start)
        if len(data) != end - start:
            raise self._error(start, "the file ends inside a chunk")
        return start, data

    def chunk_indexes(
        self, topics: Collection[str] | None = None, start_ns: int | None = None
    ) -> list[ChunkIndex]:
        """The summary's chunks (in file order) that may hold messages of ``topics`` at or
        after ``start_ns``; empty without a summary listing chunks."""
        if self.summary is None:
            return []
        found = []
        for index in self.summary.chunk_indexes:
            if start_ns is not None and index.message_end_time < start_ns:
                continue
            if topics is not None and index.message_index_offsets:
                held = [self.summary.channels.get(cid) for cid in index.message_index_offsets]
                if all(held) and not {c.topic for c in held if c} & set(topics):
                    continue
            found.append(index)
        return found

    def read_record(
        self,
        file: IO[bytes],
        at: int,
        opcode: int,
        end: int,
        *,
        span: tuple[int, bytes] | None = None,
    ) -> bytes:
        """The body of the record with ``opcode`` at offset ``at``, which ends by ``end``:
        taken from ``span`` (offset, bytes) when it holds them, else read with one read."""
        if end - at < _HEAD.size:
            raise self._error(at, f"a record indexed up to offset {end}, too short")
        if span is not None and span[0] <= at and end <= span[0] + len(span[1]):
            data = span[1][at - span[0] : end - span[0]]
        else:
            data = self._span(file, at, end)[1]
        op, length = _HEAD.unpack_from(data)
        if op != opcode:
            raise self._error(at, f"record {op:#04x} where the index says {opcode:#04x}")
        if length > len(data) - _HEAD.size:
            raise self._error(at, f"a record of {length} bytes runs past its index")
        return data[_HEAD.size : _HEAD.size + length]

    def chunk_records(
        self, file: IO[bytes], index: ChunkIndex, *, span: tuple[int, bytes] | None = None
    ) -> bytes:
        """The records of the chunk ``index`` locates, decompressed and CRC-checked (taken from
        ``span`` when it holds them)."""
        at = index.chunk_start_offset
        body = self.read_record(file, at, _OP_CHUNK, at + index.chunk_length, span=span)
        return self._decompressed(body, at)

    def _decompressed(self, body: bytes, at: int) -> bytes:
        try:
            chunk = Chunk.read(_parse(body))
            records = decompress(
                chunk.compression, chunk.data, chunk.uncompressed_size, limit_bytes=self.limit_bytes
            )
        except _DAMAGE as error:
            raise self._error(at, f"chunk: {error}") from error
        if chunk.uncompressed_crc and zlib.crc32(records) != chunk.uncompressed_crc:
            raise self._error(at, "chunk: its records do not match their CRC")
        return records

    def _chunk_records(self, records: bytes, at: int) -> Iterator[tuple[_Where, McapRecord]]:
        """(where, record) of the records of the chunk at offset ``at``."""
        view = memoryview(records)
        for pos, op, body in self._records(view, 0, len(view), lambda pos: (at, pos)):
            record = self._parsed(op, body, (at, pos))
            if record is not None:
                yield (at, pos), record

    def _damaged(self, where: _Where, what: str) -> CorruptRecordingError:
        at, pos = where
        if pos is None:
            return self._error(at, what)
        return CorruptRecordingError(
            f"{self.name}: {what} at offset {pos} of the records of the chunk at offset {at}"
        )

    def _parsed(self, op: int, body: memoryview, where: _Where) -> McapRecord | None:
        """The record parsed by the library (None for records no reader here needs); a
        message's data is a view of ``body``."""
        if op == _OP_MESSAGE:
            # one struct unpack, not the library's Message.read (a read call per field): that
            # made a replayer open 1.7 times slower; the conformance suite checks both alike
            if len(body) < _MESSAGE.size:
                raise self._damaged(where, f"a message of {len(body)} bytes")
            channel_id, sequence, log_time, publish_time = _MESSAGE.unpack_from(body)
            data: Any = body[_MESSAGE.size :]
            return Message(channel_id, log_time, data, publish_time, sequence)
        read = _READERS.get(op)
        if read is None:
            return None
        try:
            return read(_parse(bytes(body)), len(body))
        except _DAMAGE as error:
            raise self._damaged(where, f"record {op:#04x}: {error}") from error

    def _chunk_messages(
        self,
        records: bytes,
        at: int,
        channels: _Channels,
        wanted: frozenset[str] | None,
        start_ns: int | None,
    ) -> Iterator[RawMessage]:
        """The wanted messages among the records of the chunk at offset ``at``: the loop of
        :meth:`_chunk_records` and :meth:`_messages_of` in one, without a record object per
        message (half the time of a replayer's opening read went there)."""
        view = memoryview(records)
        pos, end = 0, len(view)
        head, message = _HEAD.unpack_from, _MESSAGE.unpack_from
        while pos < end:
            if pos + _HEAD.size > end:
                raise self._damaged((at, pos), "a record header runs past its section")
            op, length = head(view, pos)
            body_at = pos + _HEAD.size
            if length > end - body_at:
                raise self._damaged((at, pos), f"a record of {length} bytes runs past its section")
            if op == _OP_MESSAGE and length >= _MESSAGE.size:
                channel_id, _, log_time, _ = message(view, body_at)
                found = channels.channels.get(channel_id)
                if found is None:
                    raise self._damaged((at, pos), f"a message on undeclared channel {channel_id}")
                if (wanted is None or found[0] in wanted) and (
                    start_ns is None or log_time >= start_ns
                ):
                    data = bytes(view[body_at + _MESSAGE.size : body_at + length])
                    yield RawMessage(found[0], found[1], log_time, data)
            else:
                record = self._parsed(op, view[body_at : body_at + length], (at, pos))
                if record is not None:
                    self._declare(channels, record, (at, pos))
            pos = body_at + length

    def _declare(self, channels: _Channels, record: McapRecord, where: _Where) -> None:
        """Take in a schema or channel record."""
        if isinstance(record, Schema):
            channels.schemas[record.id] = record.name
        elif isinstance(record, Channel):
            if record.schema_id != 0 and record.schema_id not in channels.schemas:
                raise self._damaged(
                    where, f"channel {record.id} refers to undeclared schema {record.schema_id}"
                )
            channels.channels[record.id] = (
                record.topic,
                channels.schemas.get(record.schema_id, ""),
            )

    def _messages_of(
        self,
        records: Iterator[tuple[_Where, McapRecord | bytes]],
        channels: _Channels,
        wanted: frozenset[str] | None,
        start_ns: int | None,
    ) -> Iterator[RawMessage]:
        for where, record in records:
            if isinstance(record, bytes):  # a chunk's records
                yield from self._chunk_messages(record, where[0], channels, wanted, start_ns)
            elif isinstance(record, Message):
                found = channels.channels.get(record.channel_id)
                if found is None:
                    raise self._damaged(
                        where, f"a message on undeclared channel {record.channel_id}"
                    )
                topic, msgtype = found
                if (wanted is None or topic in wanted) and (
                    start_ns is None or record.log_time >= start_ns
                ):
                    yield RawMessage(topic, msgtype, record.log_time, bytes(record.data))
            else:
                self._declare(channels, record, where)

    def records(self) -> Iterator[McapRecord]:
        """The records of the data section in file order, the records of each chunk in its
        place (Header, Schema, Channel, Message, Metadata, Attachment), read forward and
        checked like :meth:`messages`: for a copy of the whole file."""
        with self._opener() as file:
            for where, record in self._forward_records(file):
                if isinstance(record, bytes):
                    for _, inner in self._chunk_records(record, where[0]):
                        yield inner
                else:
                    yield record

    def _forward_messages(
        self, file: IO[bytes], wanted: frozenset[str] | None, start_ns: int | None
    ) -> Iterator[RawMessage]:
        yield from self._messages_of(self._forward_records(file), _Channels(), wanted, start_ns)

    def _forward_records(self, file: IO[bytes]) -> Iterator[tuple[_Where, McapRecord | bytes]]:
        """(where, record) of the data section read forward; a chunk as its records' bytes,
        decompressed and checked."""
        file.seek(0)
        crc = zlib.crc32(file.read(len(MAGIC)))
        pos, end = len(MAGIC), self.data_end
        while True:
            if pos == end and self.complete:
                return
            head = file.read(_HEAD.size)
            if len(head) < _HEAD.size or pos + _HEAD.size > end:
                if self.complete:
                    raise self._error(pos, "the data section ends inside a record header")
                self.truncated_at = pos
                return
            op, length = _HEAD.unpack_from(head)
            if length > end - pos - _HEAD.size:
                if self.complete:
                    raise self._error(pos, f"a record of {length} bytes runs past the data section")
                self.truncated_at = pos
                return
            if length > self.limit_bytes:
                raise self._error(
                    pos, f"a record of {length} bytes, over the limit {self.limit_bytes}"
                )
            body = file.read(length)
            if len(body) != length:
                raise self._error(pos, "the file ends inside a record")
            if op == _OP_DATA_END:
                try:
                    expected = DataEnd.read(_parse(body)).data_section_crc
                except _DAMAGE as error:
                    raise self._error(pos, f"data end: {error}") from error
                if expected and expected != crc:
                    raise self._error(pos, "the data section does not match its CRC")
                return
            if op == _OP_FOOTER:
                return
            crc = zlib.crc32(body, zlib.crc32(head, crc))
            if op == _OP_CHUNK:
                yield (pos, None), self._decompressed(body, pos)
            else:
                record = self._parsed(op, memoryview(body), (pos, None))
                if record is not None:
                    yield (pos, None), record
            pos += _HEAD.size + length


def _runs(chunks: list[ChunkIndex], run_bytes: int) -> Iterator[list[ChunkIndex]]:
    """Chunks in runs read at once: a chunk joins the run before it when at most
    ``GAP_BYTES`` (its message indexes) lie between them and the run stays within
    ``run_bytes``."""
    run: list[ChunkIndex] = []
    for chunk in chunks:
        if run:
            last_end = run[-1].chunk_start_offset + run[-1].chunk_length
            gap = chunk.chunk_start_offset - last_end
            end = chunk.chunk_start_offset + chunk.chunk_length
            if not 0 <= gap <= GAP_BYTES or end - run[0].chunk_start_offset > run_bytes:
                yield run
                run = []
        run.append(chunk)
    if run:
        yield run


def _usable(summary: Summary) -> bool:
    """The summary locates every chunk and declares every channel (and schema) its chunk
    indexes name: messages can be read chunk by chunk from it alone."""
    if not summary.chunk_indexes or not summary.channels:
        return False
    for index in summary.chunk_indexes:
        if not index.message_index_offsets:
            return False
        for channel_id in index.message_index_offsets:
            channel = summary.channels.get(channel_id)
            if channel is None or (channel.schema_id and channel.schema_id not in summary.schemas):
                return False
    return True
