"""An MCAP recording in object storage, read in place by ranged reads.

:class:`RangedFile` is a read-only, seekable binary file over ``read(start, length)`` (an S3
ranged GET) with read-ahead: a read that continues forward from the last one, less than
``gap_bytes`` after where it ended (a forward read of chunks, past their message indexes),
fetches at least ``ahead_bytes``, twice as much on each such read up to ``max_ahead_bytes``;
any other read fetches what is asked (a chunk that the summary locates, read exactly).
:class:`episodes.streams.mcapread.McapFile` reads a stored recording through it exactly as it
reads a local file: footer and summary, then only the chunks a replay asks for.

A replayer reads, when it opens, a few bytes from every chunk (the ticks). To open with one read
instead, those messages are saved beside the file when it is stored (:func:`write_messages`,
a small object fetched whole), with the end of the MCAP file from its summary on (the
``tail``, which :class:`RangedFile` then holds from the start, with the magic bytes);
:class:`SavedTopics` answers those topics from them and reads everything else from the file.

>>> import io
>>> data = b"0123456789"
>>> file = RangedFile(lambda start, length: data[start : start + length], len(data))
>>> file.seek(4), file.read(3), file.requests
(4, b'456', 1)
"""

from __future__ import annotations

import io
import struct
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO, cast

from episodes.streams.errors import CorruptRecordingError
from episodes.streams.mcapread import LIMIT_BYTES, MAGIC, McapFile, MessageSource, RawMessage

__all__ = [
    "RangedFile",
    "SavedMessages",
    "SavedTopics",
    "read_messages",
    "write_messages",
]

Read = Callable[[int, int], bytes]
AHEAD_BYTES = 256 * 1024
"""Fetched at least by the first ranged read ahead of a forward reader."""
GAP_BYTES = 32 * 1024
"""A read at most this far past the last one continues a forward read."""
MAX_AHEAD_BYTES = 16 * 1024 * 1024
"""The most fetched by one ranged read ahead of a forward reader."""


class RangedFile(io.RawIOBase):
    """``size`` bytes read by ``read(start, length)``; the ``known`` parts, (offset, bytes)
    each, are held from the start. Counts its ranged reads (:attr:`requests`) and the bytes
    they brought (:attr:`bytes_read`).

    Raises :class:`CorruptRecordingError` when a ranged read returns fewer bytes than asked.
    """

    def __init__(
        self,
        read: Read,
        size: int,
        *,
        name: str = "",
        known: Collection[tuple[int, bytes]] = (),
        ahead_bytes: int = AHEAD_BYTES,
        max_ahead_bytes: int = MAX_AHEAD_BYTES,
        gap_bytes: int = GAP_BYTES,
    ) -> None:
        super().__init__()
        self._read, self._size, self.name = read, size, name
        self._pos = 0
        self._ahead, self._min_ahead, self._max_ahead = 0, ahead_bytes, max_ahead_bytes
        self._gap = gap_bytes
        self._held: tuple[int, bytes] = (0, b"")
        self._known = [part for part in known if part[1] and part[0] + len(part[1]) <= size]
        self.requests = self.bytes_read = 0

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def tell(self) -> int:
        return self._pos

    def seek(self, offset: int, whence: int = io.SEEK_SET) -> int:
        base = {io.SEEK_SET: 0, io.SEEK_CUR: self._pos, io.SEEK_END: self._size}[whence]
        if base + offset < 0:
            raise ValueError(f"offset: got {base + offset}, expected a position >= 0")
        self._pos = base + offset
        return self._pos

    def readinto(self, buffer: memoryview) -> int:  # type: ignore[override]
        wanted = min(len(buffer), max(0, self._size - self._pos))
        done = 0
        while done < wanted:
            chunk = self._bytes_at(self._pos + done, wanted - done)
            buffer[done : done + len(chunk)] = chunk
            done += len(chunk)
        self._pos += done
        return done

    def _bytes_at(self, start: int, length: int) -> bytes:
        """Some of the ``length`` bytes at ``start`` (at least one), from what is held or
        fetched now."""
        for held_at, held in (*self._known, self._held):
            if held_at <= start < held_at + len(held):
                return held[start - held_at : start - held_at + length]
        end = min([self._size, *(at for at, _ in self._known if at > start)])
        last_end = self._held[0] + len(self._held[1])
        if self._held[1] and last_end <= start <= last_end + self._gap:  # reading forward
            self._ahead = min(max(2 * self._ahead, self._min_ahead), self._max_ahead)
        else:
            self._ahead = 0
        fetch = min(max(length, self._ahead), end - start)
        data = self._read(start, fetch)
        self.requests += 1
        self.bytes_read += len(data)
        if len(data) != fetch:
            raise CorruptRecordingError(
                f"{self.name}: read {len(data)} bytes at offset {start}, expected {fetch}"
            )
        self._held = (start, data)
        return data[:length]


class SavedTopics:
    """Messages of ``saved.messages``' topics answered from them, all others read from
    ``recording`` (see the module)."""

    def __init__(self, recording: McapFile, saved: SavedMessages, topics: Collection[str]) -> None:
        self.recording, self.saved, self.topics = recording, saved, frozenset(topics)
        self.path = recording.path

    @property
    def complete(self) -> bool:
        return self.recording.complete

    def messages(
        self, topics: Collection[str] | None = None, start_ns: int | None = None
    ) -> Iterator[RawMessage]:
        """Messages in file order; ``topics`` filters by topic, ``start_ns`` by log time."""
        if topics is None or not set(topics) <= self.topics:
            yield from self.recording.messages(topics, start_ns)
            return
        for message in self.saved.messages:
            if message.topic in topics and (start_ns is None or message.log_time >= start_ns):
                yield message


def open_ranged(
    read: Read,
    size: int,
    *,
    name: str,
    saved: SavedMessages | None = None,
    topics: Collection[str] = (),
    limit_bytes: int = LIMIT_BYTES,
) -> MessageSource:
    """The MCAP file of ``size`` bytes read by ``read``, with the ``saved`` messages of
    ``topics`` when given; ``limit_bytes`` as :class:`McapFile`'s. Raises
    :class:`CorruptRecordingError`."""
    # the saved messages were written from this file, read whole (its magic bytes checked)
    known = [(0, MAGIC), saved.tail] if saved is not None else []

    def opener() -> IO[bytes]:
        return cast(IO[bytes], RangedFile(read, size, name=name, known=known))

    recording = McapFile(opener, name=name, limit_bytes=limit_bytes)
    return SavedTopics(recording, saved, topics) if saved is not None else recording


_MESSAGES_MAGIC = b"ENGRAM-MESSAGES-2\n"
_TAIL = struct.Struct("<QQ")  # where the saved end of the MCAP file starts, its length
_SAVED = struct.Struct("<HHQI")  # topic length, type length, log time, data length


@dataclass(frozen=True)
class SavedMessages:
    """What :func:`write_messages` saved: messages, and the end of the MCAP file (from its
    summary on) as ``(offset, bytes)``."""

    messages: list[RawMessage]
    tail: tuple[int, bytes]


def write_messages(path: Path, topics: Collection[str], target: Path) -> int:
    """Save the messages of ``topics`` of the complete MCAP file at ``path``, and its end from
    the summary on, to the file ``target`` (see the module); returns how many messages.
    :func:`read_messages` reads them back. Raises :class:`CorruptRecordingError`, also for a
    file without a summary."""
    recording = McapFile.open(path)
    if recording.footer is None or not recording.footer.summary_start:
        raise CorruptRecordingError(f"{path}: no summary section")
    start = recording.footer.summary_start
    with path.open("rb") as file:
        file.seek(start)
        tail = file.read()
    count = 0
    with target.open("wb") as out:
        out.write(_MESSAGES_MAGIC)
        out.write(_TAIL.pack(start, len(tail)))
        out.write(tail)
        for message in recording.messages(topics):
            topic, msgtype = message.topic.encode(), message.msgtype.encode()
            out.write(_SAVED.pack(len(topic), len(msgtype), message.log_time, len(message.data)))
            out.write(topic + msgtype)
            out.write(message.data)
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
    try:
        while pos < len(view):
            if pos + _SAVED.size > len(view):
                raise ValueError("the file ends inside a message")
            topic_length, type_length, log_time, data_length = _SAVED.unpack_from(view, pos)
            pos += _SAVED.size
            end = pos + topic_length + type_length + data_length
            if end > len(view):
                raise ValueError("the file ends inside a message")
            topic = bytes(view[pos : pos + topic_length]).decode()
            msgtype = bytes(view[pos + topic_length : pos + topic_length + type_length]).decode()
            found.append(RawMessage(topic, msgtype, log_time, bytes(view[end - data_length : end])))
            pos = end
    except ValueError as error:
        raise CorruptRecordingError(f"saved messages at offset {pos}: {error}") from error
    return SavedMessages(found, (tail_offset, tail))
