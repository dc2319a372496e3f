"""Large messages written straight to the MCAP file, each in a chunk of its own.

rosbags' MCAP writer (pinned in ``pyproject.toml``) copies every message about seven times on
its way to the disk: into a record buffer, into the chunk buffer (which grows by reallocation),
out of it, into the chunk record, out of that, and into the file: for large images, most of the
writer thread's work, holding the interpreter lock. :func:`write_alone` closes the pending
chunk (so records stay in log-time order and each channel's definition precedes its messages)
and writes the message as a one-message uncompressed chunk: its headers packed in one call and
the payload written once, from the serialised buffer, to the file. The MCAP file is the same
format: the message index and chunk index records are what rosbags would write, so its
summary, rosbags' and the ``mcap`` package's readers (and :mod:`episodes.streams.mcapread`)
read it unchanged.
"""

import struct
from io import BytesIO
from typing import Any

__all__ = ["DIRECT_BYTES", "can_write_alone", "write_alone"]

DIRECT_BYTES = 64 * 1024
"""Messages at least this large are written alone; smaller ones share rosbags' chunks."""

_CHUNK_AND_MESSAGE_HEAD = struct.Struct("<BQQQQIIQ" + "BQHIQQ")
"""Chunk record (op 0x06, length, start, end, uncompressed size, crc, empty compression name,
records length), then its one message record (op 0x05, length, channel, sequence, log time,
publish time)."""
_MESSAGE_INDEX = struct.Struct("<BQHIQQ")
"""Message index record (op 0x07, length, channel, entries length, log time, offset)."""
_CHUNK_INDEX = struct.Struct("<QQQQIHQQIQQ")
"""Chunk index body: start, end, chunk offset, chunk length, offsets length, (channel, message
index offset), message index length, empty compression name, compressed and uncompressed
size."""
_MESSAGE_FIELDS = 2 + 4 + 8 + 8
_RECORD_HEAD = 1 + 8
_CHUNK_FIELDS = 8 + 8 + 8 + 4 + 4 + 8


def can_write_alone(writer: Any) -> bool:
    """Whether ``writer`` (an open ``rosbags.rosbag2.Writer`` with MCAP storage) writes
    uncompressed chunks and messages, the only case :func:`write_alone` handles."""
    storage = writer.storage
    return (
        storage is not None
        and getattr(storage, "compression", None) == ""
        and str(getattr(writer.compression_mode, "name", "")) != "MESSAGE"
    )


def write_alone(writer: Any, connection: Any, timestamp: int, data: bytes | memoryview) -> None:
    """Write one message as a chunk of its own (see the module's docstring); the bookkeeping
    of ``writer.write`` (counts, times, statistics, the chunk index) is kept."""
    storage = writer.storage
    if storage.chunk.bio.tell():
        storage.close_chunk()
    size = len(data)
    message_length = _MESSAGE_FIELDS + size
    records_length = _RECORD_HEAD + message_length
    cid = connection.id
    bio = storage.bio
    chunk_start = bio.tell()
    bio.write(
        _CHUNK_AND_MESSAGE_HEAD.pack(
            0x06,
            _CHUNK_FIELDS + records_length,
            timestamp,
            timestamp,
            records_length,
            0,
            0,
            records_length,
            0x05,
            message_length,
            cid,
            0,
            timestamp,
            timestamp,
        )
    )
    bio.write(data)
    chunk_end = bio.tell()
    bio.write(_MESSAGE_INDEX.pack(0x07, 2 + 4 + 16, cid, 16, timestamp, 0))
    index = BytesIO()
    index.write(
        _CHUNK_INDEX.pack(
            timestamp,
            timestamp,
            chunk_start,
            chunk_end - chunk_start,
            10,
            cid,
            chunk_end,
            bio.tell() - chunk_end,
            0,
            records_length,
            records_length,
        )
    )
    storage.chunks.append(index)
    storage.message_start_time = min(timestamp, storage.message_start_time)
    storage.message_end_time = max(timestamp, storage.message_end_time)
    storage.channel_stats[cid] += 1
    writer.counts[cid] += 1
    writer.min_timestamp = min(timestamp, writer.min_timestamp)
    writer.max_timestamp = max(timestamp, writer.max_timestamp)
