"""Episode bags in and out: export as a standalone rosbag2, repair after a crash, import bags.

* :func:`export_bag` writes a standalone rosbag2 directory (MCAP) with standard message
  types only on the sensor channels: baseline-filtered arrays come out dense, every sample
  restored. ``rosbags``, ``ros2 bag`` and Foxglove read it; so does :class:`Replayer`.
* :func:`recover` completes a recording cut short by a crash (everything up to the last
  flushed chunk), so that tools needing the MCAP index and ``metadata.yaml`` read it too.
* :func:`import_bag` turns an existing ROS 1 ``.bag`` or ROS 2 bag into an episode recording:
  supported topics become channels (times kept), the others are listed as skipped.
"""

from __future__ import annotations

import logging
import re
import shutil
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.rosbag1 import ReaderError as Ros1ReaderError
from rosbags.rosbag2 import ReaderError as Ros2ReaderError

from episodes.streams.bagwrite import mcap_file
from episodes.streams.errors import (
    CorruptRecordingError,
    RecordingNotFoundError,
    RecordingStateError,
)
from episodes.streams.ledger import ChannelStats
from episodes.streams.mcapread import LIMIT_BYTES
from episodes.streams.messages import IMAGE_ENCODINGS, Kind, ProviderSpec
from episodes.streams.recorder import Recorder
from episodes.streams.replay import Frame, Replayer

__all__ = ["ImportResult", "export_bag", "import_bag", "recover"]

log = logging.getLogger(__name__)

_BACKLOG_BYTES = 64 * 1024 * 1024


def _settings(spec: ProviderSpec, *, keep_baseline: bool) -> dict[str, Any]:
    config = spec.config()
    for key in ("name", "kind", "baseline", "threshold"):
        config.pop(key, None)
    if keep_baseline and spec.baseline is not None:
        config["baseline"] = spec.baseline
        if spec.threshold:
            config["threshold"] = spec.threshold
    return config


def _copy(source: Replayer, dest: Path, *, keep_baseline: bool) -> list[ChannelStats]:
    recorder = Recorder(dest, episode_id=source.episode_id, max_queue_bytes=4 * _BACKLOG_BYTES)
    try:
        for name, spec in source.providers.items():
            recorder.add_provider(name, spec.kind, **_settings(spec, keep_baseline=keep_baseline))
        source.seek(frame=0)
        for frame in source.frames():
            _tick(recorder, frame)
    except BaseException:
        recorder.close()
        raise
    return recorder.close()


def _tick(recorder: Recorder, frame: Frame) -> None:
    if recorder.queued_bytes > _BACKLOG_BYTES:
        recorder.flush()  # the copier may wait for the disk; a live producer never does
    result = recorder.tick(
        {name: s.value for name, s in frame.samples.items()},
        time_ns=frame.time_ns,
        stamps_ns={name: s.stamp_ns for name, s in frame.samples.items()},
    )
    if result.dropped:  # cannot happen with the flush above; never drop silently anyway
        raise RecordingStateError(f"frame {frame.number}: samples dropped {result.dropped}")


def export_bag(
    source: Path | str, dest: Path | str, *, limit_bytes: int = LIMIT_BYTES
) -> list[ChannelStats]:
    """Write the episode at ``source`` as a standalone rosbag2 directory ``dest``; each record
    and decompressed chunk of ``source`` may take at most ``limit_bytes``.

    Raises:
        RecordingNotFoundError, CorruptRecordingError: ``source`` is not a recording.
        RecordingStateError: ``dest`` exists already.
    """
    dest = Path(dest)
    if dest.exists():
        raise RecordingStateError(f"dest: {str(dest)!r} exists already")
    stats = _copy(Replayer(source, limit_bytes=limit_bytes), dest, keep_baseline=False)
    log.info("exported %s to %s", source, dest)
    return stats


def recover(path: Path | str) -> int:
    """Complete a recording a crash cut short, in place; return the number of frames kept.

    A complete recording is left alone. The rebuilt bag is written next to the old one and
    swapped in only when it is complete, so a crash during recovery loses nothing.

    Raises:
        RecordingNotFoundError, CorruptRecordingError: not a recording.
    """
    path = Path(path)
    source = Replayer(path)
    if source.complete and (path / "metadata.yaml").exists():
        return source.frame_count
    rebuilt = path.with_name(path.name + ".recovering")
    if rebuilt.exists():
        shutil.rmtree(rebuilt)
    _copy(source, rebuilt, keep_baseline=True)
    old = path.with_name(path.name + ".crashed")
    path.rename(old)
    # the recorder names the file after its directory
    mcap_file(rebuilt).rename(rebuilt / f"{path.name}.mcap")
    meta = rebuilt / "metadata.yaml"
    meta.write_text(meta.read_text().replace(f"{rebuilt.name}.mcap", f"{path.name}.mcap"))
    rebuilt.rename(path)
    shutil.rmtree(old)
    log.info("recovered %s: %d frames", path, source.frame_count)
    return source.frame_count


@dataclass
class ImportResult:
    """What an import made: the channels written and the topics left out (with counts)."""

    episode_id: str
    path: Path
    channels: list[ChannelStats]
    skipped: dict[str, dict[str, Any]] = field(default_factory=dict)
    start_ns: int | None = None
    end_ns: int | None = None


_SEGMENT = re.compile(r"[^A-Za-z0-9_]")


def _provider_name(topic: str) -> str:
    parts = []
    for part in topic.strip("/").split("/"):
        part = _SEGMENT.sub("_", part)
        if part:
            parts.append(part if part[0].isalpha() else "t" + part)
    name = "/".join(parts) or "topic"
    return "imported/" + name if name == "engram" or name.startswith("engram/") else name


def _stamp_of(msg: Any, log_time: int) -> int:
    header = getattr(msg, "header", None)
    if header is None:
        return log_time
    ns = int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)
    return ns if ns > 0 else log_time


def _sample_of(msgtype: str, msg: Any) -> tuple[dict[str, Any], Any] | None:
    """Provider settings and sample value for a supported message, None otherwise."""
    if msgtype in ("sensor_msgs/msg/JointState", "sensor_msgs/JointState"):
        value: dict[str, Any] = {"position": np.asarray(msg.position, dtype=np.float64)}
        for key in ("velocity", "effort"):
            part = np.asarray(getattr(msg, key), dtype=np.float64)
            if part.size:
                value[key] = part
        return {"kind": Kind.JOINT_STATE, "names": list(msg.name)}, value
    if msgtype.endswith("/Float32MultiArray") or msgtype.endswith("/Float64MultiArray"):
        dtype = "float32" if "Float32" in msgtype else "float64"
        data = np.asarray(msg.data, dtype=dtype)
        dims = [int(d.size) for d in msg.layout.dim]
        if dims and int(np.prod(dims)) == data.size:
            data = data.reshape(dims)
        return {"kind": Kind.FLOAT_ARRAY, "dtype": dtype}, data
    if msgtype.endswith("/Image"):
        encoding = str(msg.encoding)
        if encoding not in IMAGE_ENCODINGS:
            return None
        dtype, nchan = IMAGE_ENCODINGS[encoding]
        height, width = int(msg.height), int(msg.width)
        itemsize = np.dtype(dtype).itemsize
        rows = np.asarray(msg.data, dtype=np.uint8).reshape(height, int(msg.step))
        pixels = np.ascontiguousarray(rows[:, : width * nchan * itemsize])
        stored = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
        arr = pixels.view(stored).astype(dtype)
        arr = arr.reshape((height, width) if nchan == 1 else (height, width, nchan))
        return {"kind": Kind.IMAGE, "encoding": encoding}, arr
    if msgtype in ("std_msgs/msg/String", "std_msgs/String"):
        return {"kind": Kind.STRING}, str(msg.data)
    return None


def import_bag(path: Path | str, *, dest: Path | str, episode_id: str) -> ImportResult:
    """Import a ROS 1 ``.bag`` file or a ROS 2 bag directory as the recording ``dest``.

    Messages with the same timestamp share one tick; the tick time is the bag's log time and
    each sample keeps its header stamp (or the log time if it has no header). Joint states,
    float32/float64 multi-arrays, images (rgb8, bgr8, rgba8, mono8, mono16, 16UC1, 32FC1) and
    strings are imported; other topics are reported in ``skipped``.

    Raises:
        RecordingNotFoundError: nothing at ``path``.
        CorruptRecordingError: ``path`` is not a bag ``rosbags`` can read.
        RecordingStateError: ``dest`` exists already.
    """
    path, dest = Path(path), Path(dest)
    if not path.exists():
        raise RecordingNotFoundError(f"path: no bag at {str(path)!r}")
    if dest.exists():
        raise RecordingStateError(f"dest: {str(dest)!r} exists already")
    try:
        reader = AnyReader([path])
        reader.open()
    except (AnyReaderError, Ros1ReaderError, Ros2ReaderError, OSError, ValueError) as exc:
        # rosbags answers a directory without metadata.yaml with FileNotFoundError
        raise CorruptRecordingError(f"path: {str(path)!r} is not a readable bag: {exc}") from exc
    recorder = Recorder(dest, episode_id=episode_id, max_queue_bytes=4 * _BACKLOG_BYTES)
    skipped: dict[str, dict[str, Any]] = {}
    names: dict[str, str] = {}
    counts: dict[str, int] = defaultdict(int)
    taken: set[str] = set()
    start = end = None
    try:
        pending: dict[str, Any] = {}
        stamps: dict[str, int] = {}
        pending_time = None

        def flush_tick() -> None:
            if pending and pending_time is not None:
                if recorder.queued_bytes > _BACKLOG_BYTES:
                    recorder.flush()
                recorder.tick(dict(pending), time_ns=pending_time, stamps_ns=dict(stamps))
            pending.clear()
            stamps.clear()

        for connection, log_time, raw in reader.messages():
            topic = connection.topic
            if topic in skipped:
                skipped[topic]["count"] += 1
                continue
            msg = reader.deserialize(raw, connection.msgtype)
            converted = _sample_of(connection.msgtype, msg)
            if converted is None:
                skipped[topic] = {"message_type": connection.msgtype, "count": 1}
                continue
            settings, value = converted
            name = names.get(topic)
            if name is None:
                name = _provider_name(topic)
                while name in taken:
                    name += "_"
                kind = settings.pop("kind")
                recorder.add_provider(name, kind, **settings)
                names[topic] = name
                taken.add(name)
            tick_time = max(log_time, 1)
            if pending_time is not None and (tick_time != pending_time or name in pending):
                flush_tick()
                # two messages of one topic at one timestamp: the second gets the next ns
                tick_time = max(tick_time, pending_time + 1)
            pending_time = tick_time
            pending[name] = value
            stamps[name] = _stamp_of(msg, log_time)
            counts[name] += 1
            start = tick_time if start is None else start
            end = tick_time
        flush_tick()
    except BaseException:
        recorder.close()
        reader.close()
        raise
    reader.close()
    channels = recorder.close()
    log.info("imported %s as episode %s: %d channels", path, episode_id, len(channels))
    return ImportResult(episode_id, dest, channels, skipped, start, end)
