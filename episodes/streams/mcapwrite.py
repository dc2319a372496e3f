"""Writing recordings: one rosbag2 directory (``metadata.yaml`` and one MCAP file), written as
the official ``mcap`` package's :class:`mcap.writer.Writer` writes it.

:class:`BagWriter` is the only code that writes an MCAP file: the recorder, bag export, import
and recovery (through the recorder) and the scene channel's rewrite all use it. The file is what
``ros2 bag record`` writes with its MCAP storage: profile ``ros2``, one ``ros2msg`` schema per
message type, CDR messages, each channel's ``offered_qos_profiles`` in its metadata, and a
``rosbag2`` metadata record holding the bag's metadata; ``metadata.yaml`` beside it lists the
topics, counts and times as rosbags' writer does, so ``rosbags``, ``ros2 bag``, the ``mcap``
package's readers and :mod:`episodes.streams.mcapread` open it.

Every chunk carries the CRC of its records, the data section's CRC is in its end record and the
summary's in the footer; the summary repeats schemas and channels and holds statistics, chunk
indexes (each with its message indexes), the metadata index and summary offsets. Messages of
``ALONE_BYTES`` or more (images) get chunks of their own.

:class:`McapWriter` assembles chunks by hand around the library's record classes, and writes
the bytes the library's writer writes (a test compares them): the library's writer copies
each payload twice into fresh buffers and reads it twice for CRCs, which tripled the
recorder's CPU per camera frame; here a payload is read once for its CRC (``isal``'s CRC-32)
and written once from the caller's buffer (figures: ``bench/README.md``).

Messages must be written in log-time order (the caller's contract: the recorder's ticks only
move forward, the scene channel's rewrite merges its updates by log time). :meth:`BagWriter.flush`
ends the chunk in progress and hands the file's buffer to the operating system, so a crash
loses only what came after the last flush; such a file has no summary and is read forward.

>>> import tempfile, pathlib
>>> from episodes.streams.messages import typestore
>>> with tempfile.TemporaryDirectory() as tmp:
...     bag = BagWriter(pathlib.Path(tmp) / "ep", typestore=typestore())
...     topic = bag.add_connection("/note", "std_msgs/msg/String")
...     text = typestore().types["std_msgs/msg/String"](data="hello")
...     bag.write(topic, 1_000, typestore().serialize_cdr(text, "std_msgs/msg/String"))
...     bag.close().name, sorted(p.name for p in (pathlib.Path(tmp) / "ep").iterdir())
('ep.mcap', ['ep.mcap', 'metadata.yaml'])
"""

from __future__ import annotations

import functools
import os
import struct
from collections.abc import Mapping
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from io import StringIO
from pathlib import Path
from typing import IO, Any

import lz4.frame  # type: ignore[import-untyped,unused-ignore]
import zstandard
from isal.isal_zlib import crc32
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
from rosbags.typesys.store import Typestore
from ruamel.yaml import YAML

from episodes.streams.errors import InvalidSampleError, RecordingStateError

__all__ = [
    "COMPRESSIONS",
    "BagWriter",
    "McapWriter",
    "bag_metadata_text",
    "crc32_combine",
    "mcap_file",
]

ROSBAG2_VERSION = 9
CHUNK_BYTES = 1024 * 1024
"""Chunks close once their records pass this size (the library's and rosbags' default)."""
ALONE_BYTES = 64 * 1024
"""A recording's messages at least this large (images) get chunks of their own, so a reader
of other channels (a plot of the joints, replay of some channels from object storage) skips
them without reading them."""
COMPRESSIONS = (None, "zstd", "lz4")
"""The chunk compressions a recording may use, by the name MCAP gives them."""
_NO_QOS = "[]"
"""``offered_qos_profiles`` of a channel with none, as rosbag2 version 9 writes it."""
_MESSAGE_HEAD = struct.Struct("<BQHIQQ")
"""A message record's opcode, length, channel, sequence, log time and publish time."""
_CHUNK_HEAD = struct.Struct("<BQQQQI")
"""A chunk record's opcode, length, start and end times, records size and records CRC."""
_CHUNK_FIELDS = 8 + 8 + 8 + 4 + 4 + 8  # times, size, CRC, compression's length, data's length


def mcap_file(path: Path) -> Path:
    """The MCAP file inside a rosbag2 directory written by :class:`BagWriter`."""
    return path / f"{path.name}.mcap"


def _library() -> str:
    try:
        ours = version("engram-kg")
    except PackageNotFoundError:  # run from a source tree that was never installed
        ours = "0"
    return f"engram-{ours}; {LIBRARY_IDENTIFIER}"


class McapWriter:
    """An MCAP file written to ``stream``: the bytes ``mcap.writer.Writer`` writes for the same
    calls (chunked, every index, statistics, summary offsets, chunk, data-section and summary
    CRCs), with each message's payload CRC-checked while it is added and written to the
    stream once, from the caller's buffer. With ``alone_bytes``, messages that large also
    get chunks of their own (the library has no such setting).

    The library's writer copies a payload into its chunk buffer, copies the finished chunk
    into a record buffer (both fresh memory: ~430 page faults a 640x480 frame), and CRCs it
    twice. Here the data section's CRC is combined from the chunk's (:func:`crc32_combine`)
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
            parts = [zstandard.compress(b"".join(parts))]
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


_CRC32_POLYNOMIAL = 0xEDB88320  # CRC-32 as zlib computes it, bits reflected


def _multiply_mod_p(a: int, b: int) -> int:
    """``a(x) * b(x)`` modulo the CRC-32 polynomial (reflected: x^0 is the top bit)."""
    product = 0
    bit = 1 << 31
    while a:
        if a & bit:
            product ^= b
            a ^= bit
        bit >>= 1
        b = (b >> 1) ^ _CRC32_POLYNOMIAL if b & 1 else b >> 1
    return product


def _powers_of_x() -> list[int]:
    powers = [1 << 30]  # x^1
    for _ in range(63):
        powers.append(_multiply_mod_p(powers[-1], powers[-1]))
    return powers


_X_TO_2_TO_THE = _powers_of_x()
"""``x^(2^k)`` modulo the polynomial, for k = 0..63."""


def crc32_combine(crc_a: int, crc_b: int, length_b: int) -> int:
    """The CRC-32 of ``a + b`` from those of ``a`` and ``b`` and the length of ``b`` (zlib's
    ``crc32_combine``, which Python's ``zlib`` does not expose): ``a``'s CRC times
    ``x^(8 * length_b)``, plus ``b``'s; a few dozen small multiplications, not a pass over ``b``.

    >>> crc32_combine(crc32(b"chunk "), crc32(b"records"), 7) == crc32(
    ...     b"chunk records"
    ... )
    True
    """
    return _multiply_mod_p(_x_to_8_times(length_b), crc_a) ^ crc_b


@functools.lru_cache(maxsize=256)  # a camera's frames, and so its chunks, repeat their sizes
def _x_to_8_times(n: int) -> int:
    """``x^(8 n)`` modulo the polynomial: the product of ``x^(2^(k + 3))`` over the bits k of n."""
    power = 1 << 31  # x^0
    k = 3
    while n:
        if n & 1:
            power = _multiply_mod_p(_X_TO_2_TO_THE[k], power)
        n >>= 1
        k += 1
    return power


def _record(record: Any) -> bytes:
    """One record's bytes, written by the library's record class."""
    builder = RecordBuilder()
    record.write(builder)
    data: bytes = builder.end()  # type: ignore[no-untyped-call]
    return data


@dataclass
class _Topic:
    channel: int
    topic: str
    msgtype: str
    type_hash: str
    count: int = 0


class BagWriter:
    """Writes one new rosbag2 directory ``path`` holding ``<path.name>.mcap`` and
    ``metadata.yaml`` (the latter on :meth:`close`).

    Args:
        path: the bag directory to create; it must not exist yet.
        typestore: where message definitions and type hashes come from.
        compression: ``None``, ``"zstd"`` or ``"lz4"``: how chunks are compressed.
        custom_data: string pairs stored in ``metadata.yaml``'s ``custom_data``.
        chunk_bytes: a chunk closes once its records pass this size.
        alone_bytes: messages at least this large get chunks of their own.

    Raises:
        RecordingStateError: ``path`` exists already.
        InvalidSampleError: an unknown compression.
    """

    def __init__(
        self,
        path: Path | str,
        *,
        typestore: Typestore,
        compression: str | None = None,
        custom_data: Mapping[str, str] | None = None,
        chunk_bytes: int = CHUNK_BYTES,
        alone_bytes: int | None = ALONE_BYTES,
    ) -> None:
        if compression not in COMPRESSIONS:
            raise InvalidSampleError("compression", compression, "None, 'zstd' or 'lz4'")
        self.path = Path(path)
        self.compression = compression
        self._typestore = typestore
        self._custom_data = dict(custom_data or {})
        try:
            self.path.mkdir(parents=True)
        except FileExistsError:
            raise RecordingStateError(f"path: {str(self.path)!r} exists already") from None
        self.file = mcap_file(self.path)
        self._stream = self.file.open("xb")
        self._mcap = McapWriter(
            self._stream,
            compression=compression,
            chunk_bytes=chunk_bytes,
            alone_bytes=alone_bytes,
            profile="ros2",
            library=_library(),
        )
        self._schemas: dict[str, int] = {}
        self._topics: dict[int, _Topic] = {}
        self._start_ns: int | None = None
        self._end_ns = 0
        self._closed = False

    def add_connection(
        self,
        topic: str,
        msgtype: str,
        *,
        definition: tuple[str, str] | None = None,
        type_hash: str | None = None,
    ) -> int:
        """Declare a topic of ROS 2 type ``msgtype``; return the id its messages are written to.

        ``definition`` (schema encoding, text) and ``type_hash`` (RIHS01) default to what the
        type store generates; a copy passes those of the file it copies.

        Raises:
            RecordingStateError: the topic is declared already, or the bag is closed.
        """
        self._check_open()
        if any(t.topic == topic for t in self._topics.values()):
            raise RecordingStateError(f"topic: {topic!r} is declared already")
        schema = self._schemas.get(msgtype)
        if schema is None:
            if definition is None:
                text, _ = self._typestore.generate_msgdef(msgtype, ros_version=2)
                definition = ("ros2msg", text)
            encoding, text = definition
            schema = self._mcap.register_schema(msgtype, encoding, text.encode())
            self._schemas[msgtype] = schema
        channel = self._mcap.register_channel(
            topic, "cdr", schema, {"offered_qos_profiles": _NO_QOS}
        )
        self._topics[channel] = _Topic(
            channel, topic, msgtype, type_hash or self._typestore.hash_rihs01(msgtype)
        )
        return channel

    def write(self, channel: int, time_ns: int, data: bytes | memoryview) -> None:
        """Write one serialised message at log (and publish) time ``time_ns``.

        Raises:
            KeyError: ``channel`` was not returned by :meth:`add_connection`.
        """
        self._topics[channel].count += 1
        if self._start_ns is None:
            self._start_ns = time_ns
        self._start_ns = min(self._start_ns, time_ns)
        self._end_ns = max(self._end_ns, time_ns)
        self._mcap.add_message(channel, time_ns, data, time_ns)

    def add_metadata(self, name: str, values: Mapping[str, str]) -> None:
        """Write a metadata record (a copy keeps those of the file it copies)."""
        self._check_open()
        self._mcap.add_metadata(name, dict(values))

    def flush(self, *, fsync: bool = False) -> None:
        """End the chunk in progress and pass everything written to the operating system
        (with ``fsync``, to the disk)."""
        self._mcap.flush()
        if fsync:
            os.fsync(self._stream.fileno())

    def pass_on(self) -> None:
        """Pass chunks the library has completed to the operating system, leaving the chunk in
        progress open (cheap when there are none: a buffered write that is empty)."""
        self._stream.flush()

    @property
    def message_count(self) -> int:
        """Messages written so far."""
        return sum(t.count for t in self._topics.values())

    def close(self) -> Path:
        """Complete the MCAP file (summary, footer) and write ``metadata.yaml``; return the file.

        Raises:
            RecordingStateError: closed already.
        """
        self._check_open()
        self._closed = True
        info = self._info()
        self._mcap.flush()  # the last chunk before the record
        self._mcap.add_metadata("rosbag2", {"serialized_metadata": bag_metadata_text(info).strip()})
        self._mcap.finish()
        self._stream.flush()
        os.fsync(self._stream.fileno())
        self._stream.close()
        metadata = self.path / "metadata.yaml"
        partial = metadata.with_name("metadata.yaml.part")
        partial.write_text(bag_metadata_text({"rosbag2_bagfile_information": info}), "utf8")
        partial.replace(metadata)
        return self.file

    def abort(self) -> None:
        """Close the file without its summary (a crash's file: read forward, ``recover``)."""
        if not self._closed:
            self._closed = True
            self._stream.close()

    def _check_open(self) -> None:
        if self._closed:
            raise RecordingStateError(f"the bag {str(self.path)!r} is closed")

    def _info(self) -> dict[str, Any]:
        """The bag's metadata, as rosbags' writer (version 9) lays it out."""
        start = self._start_ns if self._start_ns is not None else 2**63 - 1
        duration = max(0, self._end_ns - start)
        count = self.message_count
        return {
            "version": ROSBAG2_VERSION,
            "storage_identifier": "mcap",
            "relative_file_paths": [self.file.name],
            "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start},
            "message_count": count,
            "topics_with_message_count": [
                {
                    "topic_metadata": {
                        "name": t.topic,
                        "type": t.msgtype,
                        "serialization_format": "cdr",
                        "offered_qos_profiles": [],
                        "type_description_hash": t.type_hash,
                    },
                    "message_count": t.count,
                }
                for t in self._topics.values()
            ],
            "compression_format": "",
            "compression_mode": "",
            "files": [
                {
                    "path": self.file.name,
                    "starting_time": {"nanoseconds_since_epoch": start},
                    "duration": {"nanoseconds": duration},
                    "message_count": count,
                }
            ],
            "custom_data": self._custom_data or None,
            "ros_distro": "rosbags",
        }


def bag_metadata_text(document: Mapping[str, Any]) -> str:
    """``document`` as the YAML text of a rosbag2 ``metadata.yaml`` (block style)."""
    yaml = YAML(typ="safe")
    yaml.default_flow_style = False
    text = StringIO()
    yaml.dump(dict(document), text)
    return text.getvalue()
