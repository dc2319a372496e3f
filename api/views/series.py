"""A numeric channel's samples read straight from its MCAP file and sliced out with numpy.

Replaying a channel decodes every tick record and every message one by one in Python (seconds
for a 10-minute 100 Hz channel). For a plot only the channel's own messages and their log
times (the tick times) are needed, and all messages of a provider without a baseline filter
share one byte layout: a float array's elements are the message's last bytes, a joint state's
positions sit at one offset (its names and frame never change). So one forward scan keeps the
channel's raw messages, checks they all have the same length, computes the offset once from
the first message's CDR bytes and slices every value out at once; the first and last messages
are checked against the full decoder. Anything else (a baseline-filtered channel, whose missing
samples only the tick records restore; layouts that differ) is left to the replayer: ``None``.
"""

import json
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from episodes.streams import Kind
from episodes.streams import messages as ros
from episodes.streams.mcapscan import McapScan
from episodes.streams.messages import PROVIDER_TYPE, ProviderSpec
from episodes.streams.recorder import PROVIDERS_TOPIC, TICKS_TOPIC

__all__ = ["ChannelScan", "scan_channel"]

_U32 = struct.Struct("<I")
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


def scan_channel(file: Path, channel: str) -> ChannelScan:
    """One scan of ``file`` for the providers, the first tick time and ``channel``'s samples
    (``time_ns`` and ``values`` stay None when the fast path does not apply)."""
    store = ros.typestore()
    providers: dict[str, ProviderSpec] = {}
    start_ns: int | None = None
    times: list[int] = []
    raw: list[memoryview] = []
    topic = "/" + channel
    for message in McapScan(file).messages({PROVIDERS_TOPIC, TICKS_TOPIC, topic}):
        if message.topic == topic:
            times.append(message.log_time)
            raw.append(message.data)
        elif message.topic == TICKS_TOPIC:
            if start_ns is None or message.log_time < start_ns:
                start_ns = message.log_time
        else:
            p: Any = store.deserialize_cdr(message.data, PROVIDER_TYPE)
            config = json.loads(p.config_json)
            providers[p.name] = ProviderSpec.from_config(config, bytes(p.baseline))
    spec = providers.get(channel)
    found = ChannelScan(providers, start_ns)
    if spec is None or spec.baseline is not None or spec.kind not in _NUMERIC:
        return found
    if not raw:
        return ChannelScan(providers, start_ns, np.zeros(0, np.int64), np.zeros((0, 0)))
    size = len(raw[0])
    if any(len(m) != size for m in raw) or raw[0][1] != 1:  # one layout, little-endian CDR
        return found
    first = bytes(raw[0])
    layout = _layout(spec, first)
    if layout is None:
        return found
    offset, count, dtype = layout
    if offset < 4 or offset + count * np.dtype(dtype).itemsize > size:
        return found
    block = np.frombuffer(b"".join(raw), dtype=np.uint8).reshape(len(raw), size)
    values = (
        np.ascontiguousarray(block[:, offset : offset + count * np.dtype(dtype).itemsize])
        .view(dtype)
        .astype(np.float64)
    )
    for index in (0, len(raw) - 1):  # the slices agree with the decoder
        if not np.array_equal(values[index], _decoded(spec, bytes(raw[index])), equal_nan=True):
            return found
    return ChannelScan(providers, start_ns, np.asarray(times, dtype=np.int64), values)
