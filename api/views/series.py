"""A numeric channel's samples read straight from its MCAP file and sliced out with numpy.

Replaying a channel decodes every tick record and every message one by one in Python (seconds
for a 10-minute 100 Hz channel). For a plot only the channel's own messages and their log
times (the tick times) are needed: a closed recording's summary and message indexes locate
them (:class:`_Index`), a recording cut short is read forward once
(:class:`episodes.streams.mcapread.McapFile` reads both, checked and bounded). All messages
of a provider without a baseline filter share one byte layout: a float array's elements are the
message's last bytes, a joint state's positions sit at one offset (its names and frame never
change). So the offset is computed once from the first message's CDR bytes and every value is
sliced out at once; the first and last messages are checked against the full decoder. Anything
else (a baseline-filtered channel, whose missing samples only the tick records restore;
layouts that differ) is left to the replayer.
"""

import json
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np
from mcap.records import ChunkIndex
from numpy.typing import NDArray

from episodes.streams import Kind
from episodes.streams import messages as ros
from episodes.streams.errors import CorruptRecordingError
from episodes.streams.mcapread import LIMIT_BYTES, McapFile
from episodes.streams.messages import PROVIDER_TYPE, ProviderSpec
from episodes.streams.tick_writer import PROVIDERS_TOPIC, TICKS_TOPIC

__all__ = ["ChannelScan", "RecordingTimes", "recording_times", "scan_channel"]

_U32 = struct.Struct("<I")
_MESSAGE_INDEX = 7
_MESSAGE_HEADER = 1 + 8 + 2 + 4 + 8 + 8  # opcode, length, channel, sequence, two times
_INDEX_ENTRY = np.dtype([("time", "<u8"), ("offset", "<u8")])


class _Index:
    """A closed recording's channels read through its summary's chunk indexes and the
    chunks' message indexes. Message indexes are parsed with numpy, not the library's
    ``MessageIndex`` (a Python loop per entry: far over ``bench/views.py``'s target at 60,000
    samples); chunks are read by :meth:`McapFile.chunk_records`, bounded and CRC-checked."""

    def __init__(self, recording: McapFile, file: IO[bytes]) -> None:
        assert recording.summary is not None
        self.recording, self.file = recording, file
        self.summary = recording.summary
        self.channels = {c.topic: c.id for c in self.summary.channels.values()}
        self._last: tuple[int, NDArray[np.uint8]] | None = None  # the chunk read last

    def _chunks(self, channel: int) -> list[ChunkIndex]:
        return [c for c in self.summary.chunk_indexes if channel in c.message_index_offsets]

    def _entries(self, chunk: ChunkIndex, channel: int) -> NDArray[np.void]:
        at = chunk.message_index_offsets[channel]
        end = chunk.chunk_start_offset + chunk.chunk_length + chunk.message_index_length
        body = self.recording.read_record(self.file, at, _MESSAGE_INDEX, end)
        (length,) = _U32.unpack_from(body, 2) if len(body) >= 6 else (-1,)
        if length < 0 or length % _INDEX_ENTRY.itemsize or 6 + length > len(body):
            raise CorruptRecordingError(
                f"{self.recording.name}: a damaged message index at offset {at}"
            )
        return np.frombuffer(
            body, dtype=_INDEX_ENTRY, count=length // _INDEX_ENTRY.itemsize, offset=6
        )

    def times(self, topic: str) -> NDArray[np.int64]:
        """The log times of the topic's messages, in file order (no chunk is decompressed)."""
        channel = self.channels[topic]
        parts = [self._entries(c, channel)["time"] for c in self._chunks(channel)]
        return np.concatenate(parts).astype(np.int64) if parts else np.zeros(0, np.int64)

    def bodies(self, topic: str) -> list[bytes]:
        """The topic's message bodies (of any lengths) in file order, found through the message
        indexes: no record of another topic is parsed."""
        channel, found = self.channels[topic], []
        for chunk in self._chunks(channel):
            _, offsets, records = self._located(chunk, channel)
            lengths = _at(records, offsets + 1, "<u8").astype(np.int64)
            ends = offsets + 9 + lengths
            if np.any(lengths < _MESSAGE_HEADER - 9) or np.any(ends > len(records)):
                raise self._damaged(chunk, "a message runs past its chunk")
            found += [
                records[at + _MESSAGE_HEADER : end].tobytes()
                for at, end in zip(offsets.tolist(), ends.tolist(), strict=True)
            ]
        return found

    def _located(
        self, chunk: ChunkIndex, channel: int
    ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.uint8]]:
        """The log times of the channel's messages in ``chunk``, their offsets in its records,
        and the records (decompressed and checked; kept until another chunk is read); each
        offset is checked to be a message of the channel."""
        entries = self._entries(chunk, channel)
        times, offsets = entries["time"].astype(np.int64), entries["offset"].astype(np.int64)
        if not len(entries):
            return times, offsets, np.zeros(0, np.uint8)
        at = chunk.chunk_start_offset
        if self._last is None or self._last[0] != at:
            body = self.recording.chunk_records(self.file, chunk)
            self._last = at, np.frombuffer(body, dtype=np.uint8)
        records = self._last[1]
        if int(offsets.min()) < 0 or int(offsets.max()) + _MESSAGE_HEADER > len(records):
            raise self._damaged(chunk, "the message index points past its records")
        channels = _at(records, offsets + 9, "<u2")
        if np.any(records[offsets] != 5) or np.any(channels != channel):
            raise self._damaged(chunk, "the message index does not point at its channel's messages")
        return times, offsets, records

    def _damaged(self, chunk: ChunkIndex, what: str) -> CorruptRecordingError:
        return CorruptRecordingError(
            f"{self.recording.name}: {what} (the chunk at offset {chunk.chunk_start_offset})"
        )

    def messages(self, topic: str) -> tuple[NDArray[np.int64], NDArray[np.uint8]] | None:
        """The topic's log times and message bodies (rows of one length); None when their
        bodies differ in length."""
        channel = self.channels[topic]
        times, rows, width = [], [], None
        for chunk in self._chunks(channel):
            found, offsets, records = self._located(chunk, channel)
            if not len(offsets):
                continue
            lengths = _at(records, offsets + 1, "<u8")
            if np.any(lengths != lengths[0]) or (width is not None and lengths[0] - 22 != width):
                return None
            width = int(lengths[0]) - 22
            if width < 0 or int(offsets.max()) + _MESSAGE_HEADER + width > len(records):
                raise self._damaged(chunk, "a message runs past its chunk")
            rows.append(_at(records, offsets + _MESSAGE_HEADER, np.dtype((np.void, width))))
            times.append(found)
        if width is None:
            return np.zeros(0, np.int64), np.zeros((0, 0), np.uint8)
        return np.concatenate(times), np.concatenate(rows).view(np.uint8).reshape(-1, width)


def _at(buffer: NDArray[np.uint8], offsets: NDArray[np.int64], dtype: Any) -> NDArray[Any]:
    """The items of ``dtype`` starting at each byte offset of ``buffer`` (any alignment): one
    gather of whole items, not one of bytes."""
    size = np.dtype(dtype).itemsize
    if len(buffer) < size:
        return np.zeros(len(offsets), dtype)
    windows = np.lib.stride_tricks.as_strided(
        buffer, shape=(len(buffer) - size + 1, size), strides=(1, 1), writeable=False
    )
    items: NDArray[Any] = windows.view(dtype)[:, 0][offsets]
    return items


_NUMERIC = (Kind.FLOAT_ARRAY, Kind.JOINT_STATE)


@dataclass(frozen=True)
class ChannelScan:
    """What one scan found: the providers, the first tick's time and, when the fast path
    applies, the channel's tick times and values (samples by elements, float64)."""

    providers: dict[str, ProviderSpec]
    start_ns: int | None
    time_ns: NDArray[np.int64] | None = None
    values: NDArray[np.float64] | None = None


def _aligned(pos: int, size: int) -> int:
    # CDR aligns relative to the end of the 4-byte encapsulation header
    return 4 + -(-(pos - 4) // size) * size


def _joint_positions(data: bytes) -> tuple[int, int]:
    """Offset and count of a ``sensor_msgs/JointState``'s positions in its CDR bytes."""
    pos = 4 + 8  # header.stamp
    (length,) = _U32.unpack_from(data, pos)
    pos = _aligned(pos + 4 + length, 4)  # header.frame_id
    (names,) = _U32.unpack_from(data, pos)
    pos += 4
    for _ in range(names):
        pos = _aligned(pos, 4)
        (length,) = _U32.unpack_from(data, pos)
        pos += 4 + length
    pos = _aligned(pos, 4)
    (count,) = _U32.unpack_from(data, pos)
    return _aligned(pos + 4, 8), count


def _layout(spec: ProviderSpec, first: bytes) -> tuple[int, int, str] | None:
    """(offset, elements, dtype) of the values in every message of the channel."""
    if spec.kind is Kind.JOINT_STATE:
        offset, count = _joint_positions(first)
        return offset, count, "<f8"
    dtype = "<f4" if spec.dtype == "float32" else "<f8"
    count = int(np.prod(spec.shape)) if spec.shape else 0
    if count <= 0:
        return None
    return len(first) - count * np.dtype(dtype).itemsize, count, dtype


def _decoded(spec: ProviderSpec, data: bytes) -> NDArray[np.float64]:
    value: Any = ros.decode(spec, ros.typestore().deserialize_cdr(data, spec.msgtype))
    if spec.kind is Kind.JOINT_STATE:
        value = value["position"]
    return np.asarray(value, dtype=np.float64).reshape(-1)


def _values(spec: ProviderSpec, rows: NDArray[np.uint8]) -> NDArray[np.float64] | None:
    """The values sliced out of the messages' bodies (rows of one length), or None when the
    layout is not the one expected (also when the messages do not decode: replay, which reads
    them one by one, then says which is damaged)."""
    size = rows.shape[1]
    first = rows[0].tobytes()
    if size < 2 or first[1] != 1:  # little-endian CDR only
        return None
    try:
        layout = _layout(spec, first)
        if layout is None:
            return None
        offset, count, dtype = layout
        width = count * np.dtype(dtype).itemsize
        if offset < 4 or offset + width > size:
            return None
        values = np.ascontiguousarray(rows[:, offset : offset + width]).view(dtype)
        for index in (0, len(rows) - 1):  # the slices agree with the decoder
            decoded = _decoded(spec, rows[index].tobytes())
            if not np.array_equal(values[index], decoded, equal_nan=True):
                return None
    except ros.DECODE_ERRORS:
        return None
    return values.astype(np.float64)


def _providers(file: Path, bodies: list[bytes]) -> dict[str, ProviderSpec]:
    store = ros.typestore()
    providers = {}
    for data in bodies:
        try:
            p: Any = store.deserialize_cdr(data, PROVIDER_TYPE)
            providers[p.name] = ProviderSpec.from_config(
                json.loads(p.config_json), bytes(p.baseline)
            )
        except ros.DECODE_ERRORS as error:
            raise CorruptRecordingError(f"{file}: a provider record is damaged: {error}") from error
    return providers


@dataclass(frozen=True)
class RecordingTimes:
    """A closed recording's providers, its tick times and each provider's sample times."""

    providers: dict[str, ProviderSpec]
    ticks: NDArray[np.int64]
    samples: dict[str, NDArray[np.int64]]


def recording_times(file: Path, *, limit_bytes: int = LIMIT_BYTES) -> RecordingTimes | None:
    """From the file's indexes alone (no chunk of samples decompressed); None for a file
    without them, or with a baseline-filtered provider (whose restored samples only the tick
    records list). Raises :class:`CorruptRecordingError` for a damaged file."""
    recording = McapFile.open(file, limit_bytes=limit_bytes)
    if not recording.indexed:
        return None
    with file.open("rb") as stream:
        index = _Index(recording, stream)
        if PROVIDERS_TOPIC not in index.channels:
            return None
        providers = _providers(file, index.bodies(PROVIDERS_TOPIC))
        if any(spec.baseline is not None for spec in providers.values()):
            return None
        has = index.channels
        ticks = index.times(TICKS_TOPIC) if TICKS_TOPIC in has else np.zeros(0, np.int64)
        samples = {
            name: index.times(spec.topic) if spec.topic in has else np.zeros(0, np.int64)
            for name, spec in providers.items()
        }
    return RecordingTimes(providers, ticks, samples)


def _sliceable(spec: ProviderSpec | None) -> bool:
    return spec is not None and spec.baseline is None and spec.kind in _NUMERIC


def _from_index(recording: McapFile, channel: str) -> ChannelScan | None:
    """Through the file's summary and message indexes (closed recordings)."""
    if not recording.indexed:
        return None
    with recording.path.open("rb") as stream:
        index = _Index(recording, stream)
        if PROVIDERS_TOPIC not in index.channels:
            return None
        providers = _providers(recording.path, index.bodies(PROVIDERS_TOPIC))
        ticks = index.times(TICKS_TOPIC) if TICKS_TOPIC in index.channels else None
        start = int(ticks.min()) if ticks is not None and len(ticks) else None
        spec, topic = providers.get(channel), "/" + channel
        if spec is None or not _sliceable(spec):
            return ChannelScan(providers, start)
        if topic not in index.channels:
            return ChannelScan(providers, start, np.zeros(0, np.int64), np.zeros((0, 0)))
        found = index.messages(topic)
    if found is None:
        return ChannelScan(providers, start)
    time_ns, rows = found
    if not len(time_ns):
        return ChannelScan(providers, start, time_ns, np.zeros((0, 0)))
    values = _values(spec, rows)
    if values is None:
        return ChannelScan(providers, start)
    return ChannelScan(providers, start, time_ns, values)


def scan_channel(file: Path, channel: str, *, limit_bytes: int = LIMIT_BYTES) -> ChannelScan:
    """The providers, the first tick time and ``channel``'s samples (``time_ns`` and
    ``values`` stay None when they cannot be sliced out), through the file's indexes when it
    has them, else by one forward read. Raises :class:`CorruptRecordingError` for a damaged
    file."""
    recording = McapFile.open(file, limit_bytes=limit_bytes)
    indexed = _from_index(recording, channel)
    if indexed is not None:
        return indexed
    start_ns: int | None = None
    times: list[int] = []
    raw: list[bytes] = []
    provider_bodies: list[bytes] = []
    topic = "/" + channel
    for message in recording.messages({PROVIDERS_TOPIC, TICKS_TOPIC, topic}):
        if message.topic == topic:
            times.append(message.log_time)
            raw.append(message.data)
        elif message.topic == TICKS_TOPIC:
            if start_ns is None or message.log_time < start_ns:
                start_ns = message.log_time
        else:
            provider_bodies.append(message.data)
    providers = _providers(file, provider_bodies)
    spec = providers.get(channel)
    found = ChannelScan(providers, start_ns)
    if spec is None or not _sliceable(spec):
        return found
    if not raw:
        return ChannelScan(providers, start_ns, np.zeros(0, np.int64), np.zeros((0, 0)))
    size = len(raw[0])
    if any(len(m) != size for m in raw):  # one layout
        return found
    rows = np.frombuffer(b"".join(raw), dtype=np.uint8).reshape(len(raw), size)
    values = _values(spec, rows)
    if values is None:
        return found
    return ChannelScan(providers, start_ns, np.asarray(times, dtype=np.int64), values)
